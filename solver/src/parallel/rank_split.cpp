#include "cdm/solver/rank_split.hpp"

#include <algorithm>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <stdexcept>
#include <type_traits>

#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/contact/mesh_contacts.hpp"
#include "cdm/solver/contact/verlet_list.hpp"
#include "cdm/solver/mpi_session.hpp"
#include "cdm/solver/slot_pages.hpp"

#ifdef CDM_WITH_MPI
#include <mpi.h>
#endif

namespace cdm {

RankSplit::~RankSplit() = default;

// A particle's radius, mass, 1/m and (with rotation) 1/I: they travel with it, and go to a ghost once, when it
// becomes one.
static std::vector<std::vector<double>*> mass_arrays(ParticleStore& p) {
  if (p.has_rotation()) return {&p.radius, &p.mass, &p.inv_mass, &p.inv_inertia};
  return {&p.radius, &p.mass, &p.inv_mass};
}

std::vector<std::vector<double>*> RankSplit::dynamic_arrays(ParticleStore& p, bool with_carried) const {
  std::vector<std::vector<double>*> a = {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz};
  if (p.has_rotation()) a.insert(a.end(), {&p.wx, &p.wy, &p.wz, &p.tx, &p.ty, &p.tz});
  for (auto* m : mass_arrays(p)) a.push_back(m);
  // The drag's per-particle state (relaxed drag: K and u_g; two-way: F_d and the impulse J).
  for (auto* d : {&p.drag_k, &p.ugx, &p.ugy, &p.ugz, &p.dfx, &p.dfy, &p.dfz, &p.jx, &p.jy, &p.jz})
    if (d->size() == p.size()) a.push_back(d);
  for (auto* e : extra_)
    if (e->size() == p.size()) a.push_back(e);
  if (with_carried)
    for (auto* c : carried_)
      if (c->size() == p.size()) a.push_back(c);
  return a;
}

std::vector<std::vector<double>*> RankSplit::ghost_arrays(ParticleStore& p) const {
  std::vector<std::vector<double>*> a = {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz};
  if (p.has_rotation()) a.insert(a.end(), {&p.wx, &p.wy, &p.wz});
  for (auto* e : extra_)
    if (e->size() == p.size() &&
        (!ghost_extras_set_ || std::find(ghost_extras_.begin(), ghost_extras_.end(), e) != ghost_extras_.end()))
      a.push_back(e);
  return a;
}

RankSplit::WallRows RankSplit::wall_rows(VerletList& list, std::size_t n) {
  const std::size_t nw = list.walls().size();
  if (!list.keeps_history() || nw == 0 || !list.listed(n)) return {};
  // At a build each rank lists the candidates of the particles it owned and of those its
  // new slabs hold (of every particle before the slabs were first dealt out), from the
  // build's positions, so a migrating particle's row names its listed walls' entries on
  // either side; the others travel as zeros. While the entries are set aside (share_contact_records) none
  // travel; listed again between builds, a rank's are its own particles' only, and a
  // gather of the whole state sets them aside first (share_whole_state).
  if (!list.wall_entries_current()) return {};
  VerletList* const l = &list;
  return {4 * nw,
          [=](std::uint32_t i, double* out) {
            std::fill(out, out + 4 * nw, 0.0);
            const auto [q0, q1] = l->wall_entries(i);
            for (std::uint32_t q = q0; q < q1; ++q) {
              double* const o = out + 4 * l->wall_ids()[q];
              const Vec3 h = l->wall_history()[q];
              o[0] = h.x; o[1] = h.y; o[2] = h.z; o[3] = l->wall_touch()[q];
            }
          },
          [=](std::uint32_t i, const double* in) {
            const auto [q0, q1] = l->wall_entries(i);
            for (std::uint32_t q = q0; q < q1; ++q) {
              const double* const o = in + 4 * l->wall_ids()[q];
              l->wall_history()[q] = {o[0], o[1], o[2]};
              l->wall_touch()[q] = static_cast<std::uint8_t>(o[3]);
            }
          }};
}

#ifdef CDM_WITH_MPI

std::unique_ptr<RankSplit> RankSplit::create() {
  const WorldPlace w = mpi_world();
  if (w.size <= 1) return nullptr;
  if (w.size > std::numeric_limits<Owner>::max() + 1)
    throw std::runtime_error("cdm runs on at most " + std::to_string(std::numeric_limits<Owner>::max() + 1) +
                             " MPI processes, not " + std::to_string(w.size));
  return std::unique_ptr<RankSplit>(new RankSplit(w.rank, w.size));
}

namespace {
/// One message of an exchange: the values at @p idx, to or from @p rank, going @p up (to
/// the rank above the sender, where the slabs are dealt out) or not. Two ranks may be
/// each other's neighbours both ways (slabs that wrap): the direction tells the messages
/// apart.
struct Leg {
  const std::vector<std::uint32_t>* idx;
  int rank;
  bool up = false;
};

/// Sends each of @p sends and receives each of @p recvs, the values of @p arrays at the
/// legs' slots, particle by particle.
void exchange(const std::vector<std::vector<double>*>& arrays, const std::vector<Leg>& sends,
              const std::vector<Leg>& recvs, int tag, RankSplit::LegBuffers& buffers,
              const RankSplit::WallRows& rows) {
  const std::size_t k = arrays.size() + rows.count;
  // Buffers kept between calls: fresh ones cost an allocation and a zero fill per step.
  std::vector<std::vector<double>>& out = buffers.out;
  std::vector<std::vector<double>>& in = buffers.in;
  if (out.size() < sends.size()) out.resize(sends.size());
  if (in.size() < recvs.size()) in.resize(recvs.size());
  std::vector<MPI_Request> req;
  for (std::size_t m = 0; m < recvs.size(); ++m) {
    in[m].resize(recvs[m].idx->size() * k);
    req.emplace_back();
    mpi_check(MPI_Irecv(in[m].data(), static_cast<int>(in[m].size()), MPI_DOUBLE, recvs[m].rank,
                        2 * tag + recvs[m].up, MPI_COMM_WORLD, &req.back()),
              "MPI_Irecv");
  }
  for (std::size_t m = 0; m < sends.size(); ++m) {
    std::vector<double>& b = out[m];
    b.resize(sends[m].idx->size() * k);
    std::size_t at = 0;
    for (std::uint32_t i : *sends[m].idx) {
      for (const auto* a : arrays) b[at++] = (*a)[i];
      if (rows.count) rows.put(i, &b[at]);
      at += rows.count;
    }
    req.emplace_back();
    mpi_check(MPI_Isend(b.data(), static_cast<int>(b.size()), MPI_DOUBLE, sends[m].rank, 2 * tag + sends[m].up,
                        MPI_COMM_WORLD, &req.back()),
              "MPI_Isend");
  }
  mpi_check(MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE), "MPI_Waitall");
  for (std::size_t m = 0; m < recvs.size(); ++m) {
    std::size_t at = 0;
    for (std::uint32_t i : *recvs[m].idx) {
      for (auto* a : arrays) (*a)[i] = in[m][at++];
      if (rows.count) rows.get(i, &in[m][at]);
      at += rows.count;
    }
  }
}
}  // namespace

void RankSplit::exchange_ghosts(ParticleStore& p, bool with_masses) {
  if (!assigned_) return;
  std::vector<Leg> sends, recvs;
  if (below_ >= 0) {
    sends.push_back({&lower_, below_, false});
    recvs.push_back({&under_, below_, true});
  }
  if (above_ >= 0) {
    sends.push_back({&top_, above_, true});
    recvs.push_back({&upper_, above_, false});
  }
  std::vector<std::vector<double>*> arrays = ghost_arrays(p);
  if (with_masses)
    for (auto* m : mass_arrays(p)) arrays.push_back(m);
  exchange(arrays, sends, recvs, 11, legs_, {});
}

void RankSplit::exchange_ghost_torques(ParticleStore& p) {
  if (!assigned_) return;
  std::vector<Leg> sends, recvs;
  if (below_ >= 0) sends.push_back({&lower_, below_, false});
  if (above_ >= 0) recvs.push_back({&upper_, above_, false});
  exchange({&p.tx, &p.ty, &p.tz}, sends, recvs, 14, legs_, {});
}

void RankSplit::boundary_torques(ParticleStore& p, int pass) {
  if (!assigned_) return;
  std::vector<std::vector<double>*> f = {&p.tx, &p.ty, &p.tz};
  // A boundary slab's particles take their contributions from the pairs of the slab
  // below (the lower rank's) and of their own slab (the upper rank's): of the even one
  // of the two first. An odd boundary slab: the lower rank adds in the even phase, then
  // hands the torques up. An even one: the upper rank adds in the even phase, hands them
  // down, the lower one adds in the odd phase and hands them back.
  std::vector<Leg> sends, recvs;
  if (below_ >= 0) {
    if (pass == 0 && lower_odd_) recvs.push_back({&lower_, below_, true});
    if (pass == 0 && !lower_odd_) sends.push_back({&lower_, below_, false});
    if (pass == 1 && !lower_odd_) recvs.push_back({&lower_, below_, true});
  }
  if (above_ >= 0) {
    if (pass == 0 && upper_odd_) sends.push_back({&upper_, above_, true});
    if (pass == 0 && !upper_odd_) recvs.push_back({&upper_, above_, false});
    if (pass == 1 && !upper_odd_) sends.push_back({&upper_, above_, true});
  }
  exchange(f, sends, recvs, 15 + pass, legs_, {});
}

void RankSplit::share_whole_state(ParticleStore& p, VerletList* list, bool to_writer) {
  std::vector<std::vector<double>*> arrays = dynamic_arrays(p, true);
  if (!list) {  // particles without contacts: their arrays are the whole state
    share_particles(arrays, {}, to_writer);
    return;
  }
  const bool own_x0 = list->listed(p.size()) && list->build_positions_own_only();
  if (own_x0)
    for (auto* a : list->build_position_arrays()) arrays.push_back(a);
  // Wall entries listed for the own particles only cannot take the others' rows: the
  // contacts are set aside and joined as records (share_contact_records).
  if (list->wall_entries_own_only() && list->wall_entries_current()) list->set_aside_walls();
  share_particles(arrays, wall_rows(*list, p.size()), to_writer);
  share_contact_records(*list, to_writer);
  if (own_x0 && (!to_writer || rank_ == 0)) list->build_positions_whole();
}

void RankSplit::synchronise(ParticleStore& p, VerletList* list, bool for_build) {
  if (!stale_ || (moving_ && for_build)) return;
  // A build reads the positions; the rest of the state (the mesh contacts too) moves with
  // the particles that change owner (assign). The mesh contacts are joined only here.
  const bool positions_only = for_build;
  if (positions_only) {
    share_particles({&p.x, &p.y, &p.z, &p.radius}, {});
  } else {
    share_whole_state(p, list, false);
    gathered_ = true;
  }
  stale_ = moving_ = positions_only;
}

void RankSplit::gather_to_writer(ParticleStore& p, VerletList* list) {
  if (!stale_ || written_) return;
  share_whole_state(p, list, true);
  written_ = true;
  gathered_ = gathered_ || rank_ == 0;
}

void RankSplit::migrate(ParticleStore& p, VerletList& list, const std::vector<Owner>& before) {
  const auto size = static_cast<std::size_t>(size_);
  std::vector<std::vector<std::uint32_t>> out(size), in(size);
  for (std::size_t i = 0; i < owner_.size(); ++i) {
    const int was = before[i], is = owner_[i];
    if (was == is) continue;
    if (was == rank_) out[static_cast<std::size_t>(is)].push_back(static_cast<std::uint32_t>(i));
    else if (is == rank_) in[static_cast<std::size_t>(was)].push_back(static_cast<std::uint32_t>(i));
  }
  // After a build: the wall entries are listed, each particle's row goes with it.
  if (!list.wall_entries_current() && list.keeps_history() && !list.walls().empty())
    throw std::logic_error("RankSplit: the wall contacts are not listed");
  // In rounds of at most `batch` particles a leg (both sides cut it alike), each round's
  // particles let go once sent: after a restart most particles move, and no rank then
  // holds its old and its new particles' state at once. Buffers of its own, freed after.
  const std::size_t batch = std::max<std::size_t>(1, round_values() / 64);
  const std::vector<std::vector<double>*> arrays = dynamic_arrays(p, true);
  const WallRows rows = wall_rows(list, p.size());
  LegBuffers buffers;
  std::vector<std::vector<std::uint32_t>> part(2 * size);  // this round's of out, then of in
  for (std::size_t k0 = 0;; k0 += batch) {
    std::vector<Leg> sends, recvs;
    for (std::size_t r = 0; r < 2 * size; ++r) {
      const std::vector<std::uint32_t>& all = r < size ? out[r] : in[r - size];
      part[r].assign(all.begin() + static_cast<std::ptrdiff_t>(std::min(k0, all.size())),
                     all.begin() + static_cast<std::ptrdiff_t>(std::min(k0 + batch, all.size())));
      if (!part[r].empty()) (r < size ? sends : recvs).push_back({&part[r], static_cast<int>(r % size), false});
    }
    if (sends.empty() && recvs.empty()) break;
    exchange(arrays, sends, recvs, 17, buffers, rows);
    SlotRuns sent;
    for (const Leg& leg : sends)
      for (const std::uint32_t i : *leg.idx) sent.push_back({i, i + 1});
    sent = merged(std::move(sent));
    for (auto* a : arrays)
      if (a != &p.x && a != &p.y && a != &p.z) zero_slots(*a, sent);
  }
  if (meshes_) migrate_mesh_contacts(before);
}

void RankSplit::migrate_mesh_contacts(const std::vector<Owner>& before) {
  // Each particle that changed owner takes its mesh contacts (their history) along. The
  // list keeps this rank's own particles' only: it may hold the others' since a gather.
  using Contact = MeshContacts::Contact;
  static_assert(std::is_trivially_copyable_v<Contact>);
  std::vector<Contact>& list = meshes_->contacts();
  std::vector<std::vector<std::uint8_t>> out(static_cast<std::size_t>(size_));
  std::vector<Contact> kept;
  for (const Contact& c : list) {
    if (before[c.particle] != rank_) continue;
    const int is = owner_[c.particle];
    if (is == rank_) {
      kept.push_back(c);
      continue;
    }
    std::vector<std::uint8_t>& o = out[static_cast<std::size_t>(is)];
    const auto* bytes = reinterpret_cast<const std::uint8_t*>(&c);
    o.insert(o.end(), bytes, bytes + sizeof(Contact));
  }
  const std::vector<std::uint8_t> in = swap_bytes(out);
  const std::size_t mine = kept.size(), got = in.size() / sizeof(Contact);
  kept.resize(mine + got);
  if (got) std::memcpy(static_cast<void*>(kept.data() + mine), in.data(), got * sizeof(Contact));
  // In particle order; a particle's contacts, all from one rank, stay in their order.
  std::stable_sort(kept.begin(), kept.end(), Contact::by_particle);
  list.swap(kept);
}

std::size_t RankSplit::round_values() {
  static const std::size_t n = [] {
    const char* v = std::getenv("CDM_MPI_ROUND_VALUES");
    const long k = v ? std::atol(v) : 0;
    return k > 0 ? static_cast<std::size_t>(k) : kRoundValues;
  }();
  return n;
}

void RankSplit::share_particles(const std::vector<std::vector<double>*>& arrays, const WallRows& rows,
                                bool to_writer) {
  const std::size_t per = arrays.size() + rows.count, n = owner_.size();
  const auto size = static_cast<std::size_t>(size_), me = static_cast<std::size_t>(rank_);
  // In rounds of slots, each rank sending its own particles of the round in slot order, so
  // that the buffers stay near round_values() whatever the state's size (a million
  // particles' whole state is about 400 MB).
  const std::size_t batch = std::max<std::size_t>(1, round_values() / std::max<std::size_t>(1, per));
  std::vector<int> counts(size), displs(size);
  std::vector<std::size_t> next(size);
  for (std::size_t s0 = 0; s0 < n; s0 += batch) {
    const std::size_t s1 = std::min(n, s0 + batch);
    std::fill(counts.begin(), counts.end(), 0);
    for (std::size_t i = s0; i < s1; ++i) counts[owner_[i]] += static_cast<int>(per);
    send_.resize(static_cast<std::size_t>(counts[me]));
    std::size_t at = 0;
    for (std::size_t i = s0; i < s1; ++i) {
      if (owner_[i] != me) continue;
      for (const auto* a : arrays) send_[at++] = (*a)[i];
      if (rows.count) rows.put(static_cast<std::uint32_t>(i), &send_[at]);
      at += rows.count;
    }
    std::size_t total = 0;
    for (std::size_t r = 0; r < size; ++r) {
      displs[r] = static_cast<int>(total);
      next[r] = total;
      total += static_cast<std::size_t>(counts[r]);
    }
    if (to_writer) {
      if (rank_ == 0) recv_.resize(total);
      mpi_check(MPI_Gatherv(send_.data(), static_cast<int>(send_.size()), MPI_DOUBLE, recv_.data(), counts.data(),
                            displs.data(), MPI_DOUBLE, 0, MPI_COMM_WORLD),
                "MPI_Gatherv");
      if (rank_ != 0) continue;
    } else {
      recv_.resize(total);
      mpi_check(MPI_Allgatherv(send_.data(), static_cast<int>(send_.size()), MPI_DOUBLE, recv_.data(), counts.data(),
                               displs.data(), MPI_DOUBLE, MPI_COMM_WORLD),
                "MPI_Allgatherv");
    }
    for (std::size_t i = s0; i < s1; ++i) {
      const std::size_t r = owner_[i];
      if (r == me) continue;  // this rank's own values, as they are
      const double* in = &recv_[next[r]];
      for (auto* a : arrays) (*a)[i] = *in++;
      if (rows.count) rows.get(static_cast<std::uint32_t>(i), in);
      next[r] += per;
    }
  }
}

void RankSplit::gather(const std::vector<std::vector<double>*>& arrays) {
  if (!stale_) return;  // every rank holds the same state already
  share_particles(arrays, {});
}

#else  // a build without MPI has one rank: create() gives none, so nothing below runs

std::unique_ptr<RankSplit> RankSplit::create() { return nullptr; }
void RankSplit::exchange_ghosts(ParticleStore&, bool) { throw std::logic_error("RankSplit without MPI"); }
void RankSplit::boundary_torques(ParticleStore&, int) { throw std::logic_error("RankSplit without MPI"); }
void RankSplit::exchange_ghost_torques(ParticleStore&) { throw std::logic_error("RankSplit without MPI"); }
void RankSplit::synchronise(ParticleStore&, VerletList*, bool) { throw std::logic_error("RankSplit without MPI"); }
void RankSplit::gather_to_writer(ParticleStore&, VerletList*) { throw std::logic_error("RankSplit without MPI"); }
void RankSplit::gather(const std::vector<std::vector<double>*>&) { throw std::logic_error("RankSplit without MPI"); }
void RankSplit::migrate(ParticleStore&, VerletList&, const std::vector<Owner>&) { throw std::logic_error("RankSplit without MPI"); }

#endif

}  // namespace cdm
