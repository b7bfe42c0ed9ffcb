/// @file rank_collectives.cpp
/// @brief RankSplit's collectives but the state's gathers and exchanges: the reductions every step
/// takes (the largest drift, a stop signal, the contacts' count and worst overlap, the
/// deposited sums), the shared list's rows, sums and exchanges at a build, its contacts
/// gathered whole, the contacts kept per particle joined at a gather, the records of
/// what each rank finds among its own particles, and what the writer streams: a
/// checkpoint's per-particle arrays and the particle table's rows.
#include "cdm/solver/rank_split.hpp"

#include <algorithm>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <type_traits>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/contact/mesh_contacts.hpp"
#include "cdm/solver/mpi_session.hpp"

#ifdef CDM_WITH_MPI
#include <mpi.h>
#endif

namespace cdm {

#ifdef CDM_WITH_MPI

namespace {
template <class T>
MPI_Datatype mpi_type();
template <>
MPI_Datatype mpi_type<std::uint32_t>() { return MPI_UINT32_T; }
template <>
MPI_Datatype mpi_type<double>() { return MPI_DOUBLE; }
template <>
MPI_Datatype mpi_type<std::uint8_t>() { return MPI_BYTE; }

/// @p n as an MPI count; a count past int's range (more than 2^31 values in one
/// message or on one receiver) is refused rather than wrapped.
int mpi_count(std::size_t n, const char* what) {
  if (n > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::runtime_error(std::string("cdm: ") + what + ": " + std::to_string(n) +
                             " values exceed one MPI message's count (2^31 - 1); run on more processes");
  return static_cast<int>(n);
}

/// Sends out[r] to rank r (released) and returns what each rank sent, in rank order.
template <class T>
std::vector<T> all_to_all(std::vector<std::vector<T>>& out, std::size_t size) {
  std::vector<int> sc(size), sd(size), rc(size), rd(size);
  std::vector<T> send;
  std::size_t total = 0;
  for (std::size_t r = 0; r < size; ++r) total += out[r].size();
  send.reserve(total);
  for (std::size_t r = 0; r < size; ++r) {
    sd[r] = mpi_count(send.size(), "the contact list's exchange at a build");
    sc[r] = mpi_count(out[r].size(), "the contact list's exchange at a build");
    send.insert(send.end(), out[r].begin(), out[r].end());
    std::vector<T>().swap(out[r]);
  }
  mpi_check(MPI_Alltoall(sc.data(), 1, MPI_INT, rc.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Alltoall");
  std::size_t got = 0;
  for (std::size_t r = 0; r < size; ++r) {
    rd[r] = mpi_count(got, "the contact list's exchange at a build");
    got += static_cast<std::size_t>(rc[r]);
  }
  std::vector<T> in(got);
  mpi_check(MPI_Alltoallv(send.data(), sc.data(), sd.data(), mpi_type<T>(), in.data(), rc.data(), rd.data(),
                          mpi_type<T>(), MPI_COMM_WORLD),
            "MPI_Alltoallv");
  return in;
}
}  // namespace

void RankSplit::sum(std::vector<std::uint64_t>& v) {
  mpi_check(MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_UINT64_T, MPI_SUM, MPI_COMM_WORLD),
            "MPI_Allreduce");
}

std::vector<std::uint32_t> RankSplit::swap_values(std::vector<std::vector<std::uint32_t>>& out) {
  return all_to_all(out, static_cast<std::size_t>(size_));
}

std::vector<std::uint8_t> RankSplit::swap_bytes(std::vector<std::vector<std::uint8_t>>& out) {
  return all_to_all(out, static_cast<std::size_t>(size_));
}

std::vector<double> RankSplit::swap_values(std::vector<std::vector<double>>& out) {
  return all_to_all(out, static_cast<std::size_t>(size_));
}

std::vector<VerletList::PairContact> RankSplit::gather_contacts(const VerletList& list) {
  // A loaded list not listed again holds every contact on every rank, or each rank its
  // share, which rank 0 puts in (i, j) order, as the whole would be.
  if (!list.pairs_listed() && !list.carry_partial())
    return rank_ == 0 ? list.own_contacts() : std::vector<VerletList::PairContact>();
  // Each rank's own pairs' contacts, in list order; the ranks' slabs follow one another,
  // so rank 0 receives them in the one-rank list's order.
  using Contact = VerletList::PairContact;
  static_assert(std::is_trivially_copyable_v<Contact>);
  const std::vector<Contact> mine = list.own_contacts();
  const auto size = static_cast<std::size_t>(size_);
  // In bytes (records of 32 B): up to 2^31 bytes in all, 67 million contacts, on rank 0.
  const int bytes = mpi_count(mine.size() * sizeof(Contact), "the contacts gathered for the output");
  std::vector<int> counts(size), displs(size);
  mpi_check(MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
  std::size_t total = 0;
  for (std::size_t r = 0; r < size; ++r) {
    displs[r] = mpi_count(total, "the contacts gathered for the output");  // a rank's error stops the run (abort_world)
    total += static_cast<std::size_t>(counts[r]);
  }
  std::vector<Contact> all(rank_ == 0 ? total / sizeof(Contact) : 0);
  mpi_check(MPI_Gatherv(mine.data(), bytes, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE, 0,
                        MPI_COMM_WORLD),
            "MPI_Gatherv");
  if (list.carry_partial()) std::sort(all.begin(), all.end(), Contact::by_key);
  return all;
}

template <class Record, class ParticleOf, class Less>
void RankSplit::join_own(std::vector<Record>& list, ParticleOf&& particle_of, Less&& less, bool to_writer) {
  // Each rank's own particles' records, in order (the list holds all of them where none
  // changed since the last gather, so the others' are dropped first); joined and put in
  // order (each particle's, from one rank, keep theirs).
  static_assert(std::is_trivially_copyable_v<Record>);
  list.erase(std::remove_if(list.begin(), list.end(), [&](const Record& c) { return !owned_[particle_of(c)]; }),
             list.end());
  const auto size = static_cast<std::size_t>(size_);
  const int bytes = mpi_count(list.size() * sizeof(Record), "the contacts gathered");
  std::vector<int> counts(size), displs(size);
  if (to_writer)
    mpi_check(MPI_Gather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
  else
    mpi_check(MPI_Allgather(&bytes, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
  std::size_t total = 0;
  for (std::size_t r = 0; r < size; ++r) {
    displs[r] = mpi_count(total, "the contacts gathered");
    total += static_cast<std::size_t>(counts[r]);
  }
  std::vector<Record> all(total / sizeof(Record));
  if (to_writer) {
    mpi_check(MPI_Gatherv(list.data(), bytes, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE, 0,
                          MPI_COMM_WORLD),
              "MPI_Gatherv");
    if (rank_ != 0) return;  // the others keep their own particles' records
  } else {
    mpi_check(MPI_Allgatherv(list.data(), bytes, MPI_BYTE, all.data(), counts.data(), displs.data(), MPI_BYTE,
                             MPI_COMM_WORLD),
              "MPI_Allgatherv");
  }
  std::stable_sort(all.begin(), all.end(), less);
  list.swap(all);
}

void RankSplit::records_to_writer(VerletList& list) {
  if (writer_holds_all()) return;
  share_contact_records(list, true);
  // The wall contacts listed: each rank's own particles', joined on rank 0 for the writer.
  if (!list.wall_entries_current() || !list.keeps_history() || list.walls().empty()) return;
  std::vector<VerletList::WallContact> walls = list.wall_contacts();
  join_own(walls, [](const VerletList::WallContact& c) { return c.i; }, VerletList::WallContact::by_key, true);
  if (rank_ == 0) list.hold_wall_contacts(std::move(walls));
}

void RankSplit::gather_round(const std::vector<int>& counts, std::vector<std::size_t>& next) {
  std::vector<int> displs(counts.size());
  std::size_t total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    displs[r] = static_cast<int>(total);
    next[r] = total;
    total += static_cast<std::size_t>(counts[r]);
  }
  if (rank_ == 0) recv_.resize(total);
  mpi_check(MPI_Gatherv(send_.data(), counts[static_cast<std::size_t>(rank_)], MPI_DOUBLE, recv_.data(),
                        counts.data(), displs.data(), MPI_DOUBLE, 0, MPI_COMM_WORLD),
            "MPI_Gatherv");
}

void RankSplit::put_gathered(OutArchive& a, const std::vector<double>& v) {
  const std::size_t n = v.size();
  if (n != owner_.size()) return a.put(v);  // not one value per particle (an empty array)
  a.put(static_cast<std::uint64_t>(n));
  const auto size = static_cast<std::size_t>(size_), me = static_cast<std::size_t>(rank_);
  // Each round of slots [s0, s1): each rank sends its own particles' values in slot order.
  std::vector<int> counts(size);
  std::vector<std::size_t> next(size);
  std::vector<double> round;
  for (std::size_t s0 = 0; s0 < n; s0 += round_values()) {
    const std::size_t s1 = std::min(n, s0 + round_values());
    std::fill(counts.begin(), counts.end(), 0);
    send_.clear();
    for (std::size_t i = s0; i < s1; ++i) {
      ++counts[owner_[i]];
      if (owner_[i] == me) send_.push_back(v[i]);
    }
    gather_round(counts, next);
    if (rank_ == 0) {
      round.resize(s1 - s0);
      for (std::size_t i = s0; i < s1; ++i) round[i - s0] = recv_[next[owner_[i]]++];
      a.put_values(round.data(), round.size());
    }
  }
}

void RankSplit::rows_to_writer(const std::vector<const std::vector<double>*>& arrays, std::size_t n,
                               const std::function<std::size_t(std::size_t)>& slot_of,
                               const std::function<void(std::size_t, const double*)>& row) {
  const std::size_t per = std::max<std::size_t>(1, arrays.size()), size = static_cast<std::size_t>(size_);
  const std::size_t batch = std::max<std::size_t>(1, round_values() / per);
  std::vector<int> counts(size);
  std::vector<std::size_t> next(size);
  for (std::size_t k0 = 0; k0 < n; k0 += batch) {
    const std::size_t k1 = std::min(n, k0 + batch);
    // Each rank's rows of the round, in k order.
    std::fill(counts.begin(), counts.end(), 0);
    send_.clear();
    for (std::size_t k = k0; k < k1; ++k) {
      const std::size_t s = slot_of(k);
      const auto r = static_cast<std::size_t>(owner_[s]);
      counts[r] += static_cast<int>(arrays.size());
      if (static_cast<int>(r) == rank_)
        for (const auto* a : arrays) send_.push_back((*a)[s]);
    }
    gather_round(counts, next);
    if (rank_ != 0) continue;
    for (std::size_t k = k0; k < k1; ++k) {
      const auto r = static_cast<std::size_t>(owner_[slot_of(k)]);
      row(k, recv_.data() + next[r]);
      next[r] += arrays.size();
    }
  }
}

void RankSplit::ordered_to_writer(const void* data, std::size_t count, std::size_t bytes,
                                  const std::function<void(const void*, std::size_t)>& push) {
  const auto size = static_cast<std::size_t>(size_);
  std::uint64_t mine = count;
  std::vector<std::uint64_t> counts(size);
  mpi_check(MPI_Gather(&mine, 1, MPI_UINT64_T, counts.data(), 1, MPI_UINT64_T, 0, MPI_COMM_WORLD), "MPI_Gather");
  const std::size_t per = std::max<std::size_t>(1, round_values() * sizeof(double) / bytes);
  constexpr int tag = 21;
  if (rank_ != 0) {
    const auto* b = static_cast<const char*>(data);
    for (std::size_t k = 0; k < count; k += per) {
      const std::size_t m = std::min(per, count - k);
      mpi_check(MPI_Send(b + k * bytes, mpi_count(m * bytes, "the records sent to the writer"), MPI_BYTE, 0, tag,
                         MPI_COMM_WORLD),
                "MPI_Send");
    }
    return;
  }
  if (count) push(data, count);
  std::vector<char> piece;
  for (std::size_t r = 1; r < size; ++r)
    for (std::uint64_t k = 0; k < counts[r]; k += per) {
      const auto m = static_cast<std::size_t>(std::min<std::uint64_t>(per, counts[r] - k));
      piece.resize(m * bytes);
      mpi_check(MPI_Recv(piece.data(), mpi_count(piece.size(), "the records sent to the writer"), MPI_BYTE,
                         static_cast<int>(r), tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
                "MPI_Recv");
      push(piece.data(), m);
    }
}

void RankSplit::share_contact_records(VerletList& list, bool to_writer) {
  if (meshes_)
    join_own(meshes_->contacts(), [](const MeshContacts::Contact& c) { return c.particle; },
             MeshContacts::Contact::by_particle, to_writer);
  // Between a population change and the next listing the wall contacts are set aside,
  // each rank's own particles' current (wall_rows() has no entries to read).
  if (!list.wall_entries_current())
    join_own(list.pending_wall_contacts(), [](const VerletList::WallContact& c) { return c.i; },
             VerletList::WallContact::by_key, to_writer);
}

double RankSplit::max(double x) const {
  double out = x;
  mpi_check(MPI_Allreduce(&x, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
  return out;
}

void RankSplit::max(std::vector<double>& v) const {
  mpi_check(MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD),
            "MPI_Allreduce");
}

void RankSplit::add_up(ExactSums& s) const {
  mpi_check(MPI_Allreduce(MPI_IN_PLACE, s.data(), static_cast<int>(s.size()), MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD),
            "MPI_Allreduce");
}

void RankSplit::add_up(ExactSums& a, ExactSums& b) const {
  std::vector<std::int64_t> both(a.data(), a.data() + a.size());
  both.insert(both.end(), b.data(), b.data() + b.size());
  add_up(both);
  std::copy_n(both.begin(), a.size(), a.data());
  std::copy_n(both.begin() + static_cast<std::ptrdiff_t>(a.size()), b.size(), b.data());
}

void RankSplit::add_up(std::vector<std::int64_t>& v) const {
  mpi_check(MPI_Allreduce(MPI_IN_PLACE, v.data(), mpi_count(v.size(), "the sums added up"), MPI_INT64_T, MPI_SUM,
                          MPI_COMM_WORLD),
            "MPI_Allreduce");
}

void RankSplit::share_records(std::vector<std::uint64_t>& keys, std::vector<double>& values, std::size_t per) const {
  const auto size = static_cast<std::size_t>(size_);
  const int mine = mpi_count(keys.size(), "the records shared");
  std::vector<int> counts(size), displs(size), vcounts(size), vdispls(size);
  mpi_check(MPI_Allgather(&mine, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
  std::size_t total = 0;
  for (std::size_t r = 0; r < size; ++r) {
    displs[r] = mpi_count(total, "the records shared");
    vdispls[r] = mpi_count(total * per, "the records shared");
    vcounts[r] = mpi_count(static_cast<std::size_t>(counts[r]) * per, "the records shared");
    total += static_cast<std::size_t>(counts[r]);
  }
  std::vector<std::uint64_t> all(total);
  std::vector<double> all_values(total * per);
  mpi_check(MPI_Allgatherv(keys.data(), mine, MPI_UINT64_T, all.data(), counts.data(), displs.data(), MPI_UINT64_T,
                           MPI_COMM_WORLD),
            "MPI_Allgatherv");
  mpi_check(MPI_Allgatherv(values.data(), mpi_count(values.size(), "the records shared"), MPI_DOUBLE,
                           all_values.data(), vcounts.data(), vdispls.data(), MPI_DOUBLE, MPI_COMM_WORLD),
            "MPI_Allgatherv");
  std::vector<std::size_t> order(total);
  for (std::size_t k = 0; k < total; ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return all[a] < all[b]; });
  keys.resize(total);
  values.resize(total * per);
  for (std::size_t k = 0; k < total; ++k) {
    keys[k] = all[order[k]];
    std::copy_n(all_values.begin() + static_cast<std::ptrdiff_t>(order[k] * per), per,
                values.begin() + static_cast<std::ptrdiff_t>(k * per));
  }
}

bool RankSplit::any(bool flag) const {
  int in = flag ? 1 : 0, out = 0;
  mpi_check(MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
  return out != 0;
}

void RankSplit::reduce_contacts(OverlapRecord& worst, std::size_t& active) const {
  const double mine[4] = {worst.ratio, static_cast<double>(worst.particle), static_cast<double>(worst.partner),
                          static_cast<double>(active)};
  std::vector<double> all(4 * static_cast<std::size_t>(size_));
  mpi_check(MPI_Allgather(mine, 4, MPI_DOUBLE, all.data(), 4, MPI_DOUBLE, MPI_COMM_WORLD), "MPI_Allgather");
  OverlapRecord w;
  std::size_t sum = 0;
  for (std::size_t r = 0; r < static_cast<std::size_t>(size_); ++r) {
    const OverlapRecord rec{all[4 * r], static_cast<std::uint32_t>(all[4 * r + 1]), static_cast<long>(all[4 * r + 2])};
    if (contact::worse_overlap(rec, w)) w = rec;
    sum += static_cast<std::size_t>(all[4 * r + 3]);
  }
  worst = w;
  active = sum;
}

#else  // a build without MPI has one rank: create() gives none, so nothing below runs

void RankSplit::sum(std::vector<std::uint64_t>&) {}
std::vector<std::uint32_t> RankSplit::swap_values(std::vector<std::vector<std::uint32_t>>& out) { return out.at(0); }
std::vector<double> RankSplit::swap_values(std::vector<std::vector<double>>& out) { return out.at(0); }
std::vector<std::uint8_t> RankSplit::swap_bytes(std::vector<std::vector<std::uint8_t>>& out) { return out.at(0); }
std::vector<VerletList::PairContact> RankSplit::gather_contacts(const VerletList& list) { return list.own_contacts(); }
void RankSplit::records_to_writer(VerletList&) {}
void RankSplit::put_gathered(OutArchive& a, const std::vector<double>& v) { a.put(v); }
void RankSplit::rows_to_writer(const std::vector<const std::vector<double>*>&, std::size_t,
                               const std::function<std::size_t(std::size_t)>&,
                               const std::function<void(std::size_t, const double*)>&) {
  throw std::logic_error("RankSplit without MPI");
}
void RankSplit::ordered_to_writer(const void*, std::size_t, std::size_t,
                                  const std::function<void(const void*, std::size_t)>&) {
  throw std::logic_error("RankSplit without MPI");
}
double RankSplit::max(double x) const { return x; }
void RankSplit::max(std::vector<double>&) const {}
bool RankSplit::any(bool flag) const { return flag; }
void RankSplit::reduce_contacts(OverlapRecord&, std::size_t&) const {}
void RankSplit::add_up(ExactSums&) const {}
void RankSplit::add_up(std::vector<std::int64_t>&) const {}
void RankSplit::add_up(ExactSums&, ExactSums&) const {}
void RankSplit::share_records(std::vector<std::uint64_t>&, std::vector<double>&, std::size_t) const {}

#endif

}  // namespace cdm
