#include "cdm/solver/contact/verlet_list.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "cdm/solver/parallel.hpp"

namespace cdm {

VerletList::VerletList(std::vector<Wall> walls, bool with_history, double skin)
    : walls_(std::move(walls)), posed_(walls_), history_(with_history), skin_(skin) {
  for (const Wall& w : walls_) {
    walls_move_ = walls_move_ || w.motion.moving();
    still_planes_ = still_planes_ && w.shape == WallShape::plane && !w.motion.moving();
  }
}

void VerletList::set_time(double t) {
  time_ = t;
  if (!walls_move_) return;
  for (std::size_t w = 0; w < walls_.size(); ++w)
    if (walls_[w].motion.moving()) posed_[w] = walls_[w].at(t);
}

bool VerletList::walls_moved_away() const {
  if (!walls_move_) return false;
  for (const Wall& w : walls_)
    if (!(w.shift_bound(listed_time_, time_) <= 0.5 * skin_)) return true;
  return false;
}

VerletList::Update VerletList::update(const ParticleStore& p) {
  Update u;
  if (pairs_pending_ && built_ && x0_.size() == p.size()) {
    // A loaded list: its pairs as its build listed them, from the build positions.
    list_pairs(p, {x0_.data(), y0_.data(), z0_.data(), p.radius.data(), x0_.size()}, false);
    u.rebuilt = u.walls_listed = true;
  }
  if (!built_ || needs_rebuild(p)) {
    rebuild(p);
    u.rebuilt = u.walls_listed = true;
  } else if (wall_candidates_stale_ || walls_moved_away()) {
    list_wall_candidates(p);
    u.walls_listed = true;
  }
  displacement_ = -1.0;  // measured for these positions only
  return u;
}

void VerletList::save_state(OutArchive& a) const {
  // The contacts only: a listed pair or wall entry out of contact carries nothing (a
  // contact starts afresh), and the pairs are listed again from x0_. A list shared
  // among processes holds its own part only: its whole contacts are held for this.
  // Written as three arrays, field by field, without a copy of the contacts.
  if (rank_split_ && share_ && !holding_ && !pairs_pending_)
    throw std::logic_error("VerletList: a shared list saved without its whole contacts");
  const std::vector<PairContact>* whole = holding_ ? &held_ : pairs_pending_ ? &pair_carry_ : nullptr;
  auto put_field = [&](auto field) {
    if (whole) {
      a.put(static_cast<std::uint64_t>(whole->size()));
      for (const PairContact& c : *whole) a.put(field(c));
      return;
    }
    std::uint64_t n = 0;
    if (history_)
      for (std::size_t k = 0; k < pi_.size(); ++k) n += touch_[k];
    a.put(n);
    if (history_)
      for (std::size_t k = 0; k < pi_.size(); ++k)
        if (touch_[k]) a.put(field(PairContact{pi_[k], pj_[k], hist_[k]}));
  };
  put_field([](const PairContact& c) { return c.i; });
  put_field([](const PairContact& c) { return c.j; });
  put_field([](const PairContact& c) { return c.h; });
  const std::vector<WallContact> wc = wall_contacts();
  std::vector<std::uint32_t> wi(wc.size()), ww(wc.size());
  std::vector<Vec3> wh(wc.size());
  for (std::size_t k = 0; k < wc.size(); ++k) {
    wi[k] = wc[k].i; ww[k] = wc[k].w; wh[k] = wc[k].h;
  }
  a.put(wi); a.put(ww); a.put(wh);
  a.put(x0_); a.put(y0_); a.put(z0_);
}

void VerletList::load_state(InArchive& a, bool built, std::uint64_t builds) {
  // The pair contacts' three arrays are read field by field into the contacts (a
  // large run's would otherwise be held twice); the three must be as long, and fit.
  std::uint64_t nc = 0, again = 0;
  a.get(nc);
  if (nc > a.remaining() / (2 * sizeof(std::uint32_t) + sizeof(Vec3)))
    throw ArchiveError("an array's length (" + std::to_string(nc) + ") does not fit the data that follows");
  pair_carry_.resize(nc);
  for (PairContact& c : pair_carry_) a.get(c.i);
  a.get(again);
  bool ok = again == nc;
  for (std::size_t k = 0; ok && k < nc; ++k) a.get(pair_carry_[k].j);
  if (ok) a.get(again);
  ok = ok && again == nc;
  for (std::size_t k = 0; ok && k < nc; ++k) a.get(pair_carry_[k].h);
  if (!ok) throw ArchiveError("the contact list is inconsistent");
  std::vector<std::uint32_t> wi, ww;
  std::vector<Vec3> wh;
  a.get(wi); a.get(ww); a.get(wh);
  a.get(x0_); a.get(y0_); a.get(z0_);
  const std::size_t n = x0_.size();
  ok = y0_.size() == n && z0_.size() == n;
  // Contacts of particles listed, each pair once (in list order), and the wall
  // contacts in strictly increasing (i, w) order.
  ok = ok && (history_ || nc == 0);
  for (std::size_t k = 0; ok && k < nc; ++k) ok = pair_carry_[k].i < pair_carry_[k].j && pair_carry_[k].j < n;
  ok = ok && ww.size() == wi.size() && wh.size() == wi.size() && (history_ || wi.empty());
  for (std::size_t k = 0; ok && k < wi.size(); ++k)
    ok = wi[k] < n && ww[k] < walls_.size() && (k == 0 || wall_key(wi[k - 1], ww[k - 1]) < wall_key(wi[k], ww[k]));
  if (!ok) throw ArchiveError("the contact list is inconsistent");
  // Kept in (i, j) order: the build that lists the pairs again finds each particle's
  // contacts by their row, without a copy.
  std::sort(pair_carry_.begin(), pair_carry_.end(), PairContact::by_key);
  for (std::size_t k = 1; k < pair_carry_.size(); ++k)
    if (pair_carry_[k - 1].key() == pair_carry_[k].key()) throw ArchiveError("the contact list is inconsistent");
  carry_sorted_ = true;
  pairs_pending_ = true;
  for (auto* v : {&pi_, &pj_, &slab_start_}) v->clear();
  hist_.clear();
  touch_.clear();
  wall_carry_.resize(wi.size());
  for (std::size_t k = 0; k < wi.size(); ++k) wall_carry_[k] = {wi[k], ww[k], wh[k]};
  drop_wall_entries();
  built_ = built;
  builds_ = builds;
  displacement_ = -1.0;
  drift_bound_ = std::numeric_limits<double>::infinity();  // the moves since the build are unknown
  wall_candidates_stale_ = true;  // listed from the build's positions at the next update
}

void VerletList::renumber_pair_carry(const std::vector<std::uint32_t>& to) {
  // As permute and remap renumber listed pairs: i < j kept, the history seen from i.
  std::erase_if(pair_carry_, [&](const PairContact& c) {
    return c.j >= to.size() || to[c.i] == new_particle || to[c.j] == new_particle;
  });
  for (PairContact& c : pair_carry_) {
    c.i = to[c.i];
    c.j = to[c.j];
    if (c.i > c.j) {
      std::swap(c.i, c.j);
      c.h = -c.h;
    }
  }
  std::sort(pair_carry_.begin(), pair_carry_.end(), PairContact::by_key);
  carry_sorted_ = true;
}

bool VerletList::needs_rebuild(const ParticleStore& p) const {
  if (skin_ <= 0.0 || p.size() != x0_.size()) return true;
  const double lim2 = 0.25 * skin_ * skin_;
  const std::size_t n = p.size();
  if (displacement_ >= 0.0) return displacement_ > lim2;  // the integrator measured it
  return parallel_max(n, [&](std::size_t i) { return displacement(p, i); }) > lim2;
}

VerletList::Slabs VerletList::slabs(const double* x, const double* y, const double* z,
                                    const std::vector<double>& radius, std::size_t n) const {
  // Slabs along the longest side of the particles' bounding box (below), each at least one
  // interaction range (2 r_max + skin) wide, so listed partners are in the same or the
  // neighbouring slab. The slab count depends on the geometry only, never on threads.
  // A periodic axis is never cut (partners across its faces would sit in the first and
  // the last slab); with all three periodic, one slab.
  const double* axis_data[3] = {x, y, z};
  Slabs g;
  double rmax = 0.0;
  if (n) {
    for (int a = 0; a < 3; ++a) g.lo[a] = g.hi[a] = axis_data[a][0];
    for (std::size_t i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        g.lo[a] = std::min(g.lo[a], axis_data[a][i]);
        g.hi[a] = std::max(g.hi[a], axis_data[a][i]);
      }
      rmax = std::max(rmax, radius[i]);
    }
  }
  // Of sides within a tenth of the longest, the first (x, y, z): a bed about as wide as it
  // is deep keeps its axis as its sides trade places by a grain, and with it the
  // particles' order and, among MPI ranks, their owners.
  double longest = 0.0;
  for (int a = 0; a < 3; ++a)
    if (!box_.on[a]) longest = std::max(longest, g.hi[a] - g.lo[a]);
  int axis = -1;
  for (int a = 0; a < 3 && axis < 0; ++a)
    if (!box_.on[a] && g.hi[a] - g.lo[a] >= 0.9 * longest) axis = a;
  const bool cut = axis >= 0;
  g.axis = cut ? axis : 0;
  g.range = 2.0 * rmax + skin_;
  const double extent = cut ? g.hi[g.axis] - g.lo[g.axis] : 0.0;
  g.count = g.range > 0.0
                ? std::max<std::size_t>(1, std::min<std::size_t>(4096, static_cast<std::size_t>(extent / g.range)))
                : 1;
  g.width = g.count > 1 ? extent / static_cast<double>(g.count) : 1.0;
  return g;
}

std::size_t VerletList::thread_first_slab(std::size_t t, std::size_t nt) const {
  const std::size_t nslab = slab_cost_.empty() ? 0 : slab_cost_.size() - 1;
  const auto [first, last] = rank_split_ ? rank_slabs_ : std::pair<std::size_t, std::size_t>{0, nslab};
  if (t >= nt || first >= last) return last;
  // The first slab that starts at or after thread t's share of the estimated cost (of
  // this rank's slabs).
  const std::uint64_t c0 = slab_cost_[first], at = c0 + (slab_cost_[last] - c0) * t / nt;
  return static_cast<std::size_t>(std::lower_bound(slab_cost_.begin() + static_cast<std::ptrdiff_t>(first),
                                                   slab_cost_.begin() + static_cast<std::ptrdiff_t>(last), at) -
                                  slab_cost_.begin());
}

std::vector<std::uint32_t> VerletList::particle_slabs(const ParticleStore& p) const {
  // As rebuild() cut them, from the same positions (x0_ is the build's p.x).
  const std::size_t n = x0_.size();
  const Slabs g = slabs(x0_.data(), y0_.data(), z0_.data(), p.radius, n);
  const std::vector<double>& c = g.axis == 0 ? x0_ : g.axis == 1 ? y0_ : z0_;
  std::vector<std::uint32_t> out(n, 0);
  if (g.count == 1) return out;
  const double lo_axis = g.lo[g.axis];
  for (std::size_t i = 0; i < n; ++i)
    out[i] = static_cast<std::uint32_t>(std::min(g.count - 1, static_cast<std::size_t>((c[i] - lo_axis) / g.width)));
  return out;
}

std::pair<std::size_t, std::size_t> VerletList::thread_slabs() const {
  const auto [t, nt] = thread_id();
  return {thread_first_slab(t, nt), thread_first_slab(t + 1, nt)};
}

std::vector<std::uint32_t> VerletList::spatial_order(const ParticleStore& p) const {
  const std::size_t n = p.size();
  const Slabs g = slabs(p);
  // The slab first (12 bits: at most 4096 slabs), so that each slab's particles, and so
  // each thread's and each rank's, are one run of slots; then cell coordinates (edge =
  // one interaction range, 17 bits per axis: a wider box only coarsens the order), the
  // slab axis most significant, then the other two.
  const std::vector<double>* data[3] = {&p.x, &p.y, &p.z};
  const int ax[3] = {g.axis, (g.axis + 1) % 3, (g.axis + 2) % 3};
  const double h = g.range > 0.0 ? g.range : 1.0;
  constexpr double cmax = double((1 << 17) - 1);
  const double lo_axis = g.lo[g.axis];
  std::vector<std::pair<std::uint64_t, std::uint32_t>> key(n);
  parallel_for(n, [&](std::size_t i) {
    // The slab as rebuild() will cut it from these positions.
    std::uint64_t k =
        g.count == 1 ? 0 : std::min<std::size_t>(g.count - 1, static_cast<std::size_t>(((*data[g.axis])[i] - lo_axis) / g.width));
    for (int a : ax) {
      const double c = std::clamp(std::floor(((*data[a])[i] - g.lo[a]) / h), 0.0, cmax);
      k = (k << 17) | static_cast<std::uint64_t>(c);
    }
    key[i] = {k, static_cast<std::uint32_t>(i)};
  });
  std::sort(key.begin(), key.end());
  std::vector<std::uint32_t> from(n);
  for (std::size_t i = 0; i < n; ++i) from[i] = key[i].second;
  return from;
}

void VerletList::permute(const std::vector<std::uint32_t>& from) {
  const std::size_t n = from.size();
  if (x0_.size() != n) return;  // nothing listed yet: the next evaluation builds
  std::vector<std::uint32_t> to(n);
  for (std::size_t i = 0; i < n; ++i) to[from[i]] = static_cast<std::uint32_t>(i);
  // Pairs keep i < j: a pair whose order flips has its history seen from the other
  // particle, the tangential displacement of j relative to i (the negative).
  for (std::size_t k = 0; k < pi_.size(); ++k) {
    std::uint32_t i = to[pi_[k]], j = to[pj_[k]];
    if (i > j) {
      std::swap(i, j);
      if (history_) hist_[k] = -hist_[k];
    }
    pi_[k] = i;
    pj_[k] = j;
  }
  if (pairs_pending_) renumber_pair_carry(to);
  set_aside_wall_history(&to);
  std::vector<double> tmp;
  for (auto* v : {&x0_, &y0_, &z0_}) permute_array(*v, from, tmp);
  wall_candidates_stale_ = true;  // listed again, in the new order, from x0_
}

void VerletList::remap(const std::vector<std::uint32_t>& from, const ParticleStore& p) {
  const std::size_t n_old = x0_.size(), n = from.size();
  std::vector<std::uint32_t> to(n_old, new_particle);
  for (std::size_t i = 0; i < n; ++i)
    if (from[i] != new_particle && from[i] < n_old) to[from[i]] = static_cast<std::uint32_t>(i);
  // Pairs of two particles left keep their slab (each particle stays where it was) and
  // their history, seen from the lower slot (as permute keeps them); the slab starts
  // count the pairs kept.
  std::size_t kept = 0;
  for (std::size_t s = 0; s + 1 < slab_start_.size(); ++s) {
    const std::size_t begin = slab_start_[s], end = slab_start_[s + 1];
    slab_start_[s] = static_cast<std::uint32_t>(kept);
    for (std::size_t k = begin; k < end; ++k) {
      std::uint32_t i = pi_[k] < n_old ? to[pi_[k]] : new_particle, j = pj_[k] < n_old ? to[pj_[k]] : new_particle;
      if (i == new_particle || j == new_particle) continue;
      Vec3 h = history_ ? hist_[k] : Vec3{};
      if (i > j) {
        std::swap(i, j);
        h = -h;
      }
      pi_[kept] = i;
      pj_[kept] = j;
      if (history_) {
        hist_[kept] = h;
        touch_[kept] = touch_[k];
      }
      ++kept;
    }
  }
  if (!slab_start_.empty()) slab_start_.back() = static_cast<std::uint32_t>(kept);
  pi_.resize(kept);
  pj_.resize(kept);
  if (history_) {
    hist_.resize(kept);
    touch_.resize(kept);
  }
  // The contacts of the particles left follow them; new particles have none.
  if (pairs_pending_) renumber_pair_carry(to);
  set_aside_wall_history(&to);
  // Build positions: the particles' own (a new particle's is where it appeared); the
  // list is built again at the next update, so the new particles find their partners.
  for (auto* v : {&x0_, &y0_, &z0_}) v->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    x0_[i] = p.x[i]; y0_[i] = p.y[i]; z0_[i] = p.z[i];
  }
  built_ = false;
  wall_candidates_stale_ = true;
}

void VerletList::rebuild(const ParticleStore& p) { list_pairs(p, SearchPoints::of(p), true); }

void VerletList::list_pairs(const ParticleStore& p, const SearchPoints& at, bool build) {
  const std::size_t n = p.size();
  const bool divided = share_ && share_->share_size() > 1;
  // The slab cut first: a list shared among processes sends each pair, and each contact,
  // to the process of its slab.
  const Slabs g = slabs(at.x, at.y, at.z, p.radius, n);
  const std::size_t nslab = g.count;
  const double* const axis_data[3] = {at.x, at.y, at.z};
  const SlabOf slab_of{axis_data[g.axis], g.lo[g.axis], g.width, nslab};
  // The rebuild sets the run's peak memory, so what it keeps alive at once is kept
  // small. First the history to carry over: only the pairs in contact have any (a pair
  // not in contact starts afresh), so their partner and history are set apart, by
  // particle i (a counting sort, stable: row i is [carry_first[i], carry_first[i+1])),
  // and the old list is released before the new one is built. (A list that is not
  // built holds pairs only after ParticleStore::keep or add, remapped: their history is
  // carried over too; a loaded one carries the checkpoint's contacts, pair_carry_.) A
  // shared list sets its own pairs' contacts apart, to be sent on once the slabs are
  // dealt out.
  std::vector<std::uint32_t> carry_first;
  std::vector<PairContact> carry;  // by particle i once indexed (a shared list's: until dealt out)
  const std::size_t rows = std::max(n, x0_.size());
  // Row i of the carried contacts is carry[carry_first[i] .. carry_first[i + 1]).
  auto count_rows = [&](auto&& each_contact) {
    carry_first.assign(rows + 1, 0);
    each_contact([&](const PairContact& c) { ++carry_first[c.i + 1]; });
    for (std::size_t r = 0; r < rows; ++r) carry_first[r + 1] += carry_first[r];
  };
  auto sort_rows = [&](auto&& each_contact) {  // carry from each contact, by particle i
    count_rows(each_contact);
    std::vector<PairContact> sorted(carry_first[rows]);
    std::vector<std::uint32_t> fill(carry_first.begin(), carry_first.end() - 1);
    each_contact([&](const PairContact& c) { sorted[fill[c.i]++] = c; });
    carry.swap(sorted);
  };
  const bool carry_whole = pairs_pending_;  // every process holds every contact
  auto index_carry = [&] {                  // the carried vector's rows (loaded ones are in (i, j) order)
    auto each = [&](auto&& f) {
      for (const PairContact& c : carry) f(c);
    };
    if (carry_whole && carry_sorted_) count_rows(each);
    else sort_rows(each);
  };
  if (history_) {
    if (pairs_pending_) carry.swap(pair_carry_);
    else if (divided) carry = collect_contacts(true);
    else if (!pi_.empty())
      sort_rows([&](auto&& f) {
        for (std::size_t k = 0; k < pi_.size(); ++k)
          if (touch_[k]) f(PairContact{pi_[k], pj_[k], hist_[k]});
      });
    if (carry_whole && !divided) index_carry();
  }
  std::vector<PairContact>().swap(pair_carry_);
  pairs_pending_ = false;
  const std::size_t last_size = pi_.size();
  std::vector<std::uint32_t>().swap(pi_);
  std::vector<std::uint32_t>().swap(pj_);
  std::vector<Vec3>().swap(hist_);
  std::vector<std::uint8_t>().swap(touch_);
  // The candidates live only while the list is built, and are released before the
  // history is carried over. Reserved at the last list's size plus a margin, so that
  // they rarely grow by doubling. One chunk per thread (each lists its own particles'
  // pairs), in (i, j) order chunk after chunk.
  std::vector<std::vector<ContactPair>> candidates;
  if (share_) {
    const auto [first, last] = share_->rows(n);
    search_.set_rows(first, last);
  }
  search_.find_contacts(at, skin_, candidates, box_, last_size + last_size / 8 + 64);
  // Two fixed particles never move: their contact does nothing, so it is not listed.
  for (auto& chunk : candidates)
    chunk.erase(std::remove_if(chunk.begin(), chunk.end(),
                               [&](const ContactPair& c) { return p.inv_mass[c.i] == 0.0 && p.inv_mass[c.j] == 0.0; }),
                chunk.end());
  if (divided) {
    divide(candidates, slab_of, n, carry, carry_whole);
    if (history_) index_carry();
  } else {
    rank_slab_first_.clear();
  }
  std::size_t listed = 0;
  for (const auto& chunk : candidates) listed += chunk.size();

  // Counting sort of the pairs by owner slab (the lower of the two), keeping (i, j) order.
  std::vector<std::uint32_t> start(nslab + 1, 0), owner(listed);
  {
    std::size_t k = 0;
    for (const auto& chunk : candidates)
      for (const ContactPair& cp : chunk) {
        owner[k] = std::min(slab_of(cp.i), slab_of(cp.j));
        ++start[owner[k++] + 1];
      }
  }
  for (std::size_t s = 0; s < nslab; ++s) start[s + 1] += start[s];
  std::vector<std::uint32_t> pi(listed), pj(listed);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    std::size_t k = 0;
    for (auto& chunk : candidates) {
      for (const ContactPair& cp : chunk) {
        const std::uint32_t at = fill[owner[k++]]++;
        pi[at] = cp.i;
        pj[at] = cp.j;
      }
      std::vector<ContactPair>().swap(chunk);
    }
  }
  std::vector<std::vector<ContactPair>>().swap(candidates);
  std::vector<std::uint32_t>().swap(owner);
  if (history_) {
    // Carry the history of every pair in contact at the last evaluation (each is in
    // both lists): a new pair looks for its j among the few carried pairs of its i.
    std::vector<Vec3> hist(pi.size());
    std::vector<std::uint8_t> touch(pi.size(), 0);
    if (!carry.empty()) {
      for (std::size_t k = 0; k < pi.size(); ++k) {
        const std::uint32_t i = pi[k], j = pj[k];
        for (std::uint32_t q = carry_first[i]; q < carry_first[i + 1]; ++q) {
          if (carry[q].j != j) continue;
          hist[k] = carry[q].h;
          touch[k] = 1;
          break;
        }
      }
    }
    hist_.swap(hist);
    touch_.swap(touch);
  }
  pi_.swap(pi);
  pj_.swap(pj);
  slab_start_.swap(start);
  slab_active_.assign(nslab, 0);  // the new slabs' contacts are not known yet
  if (divided) set_rank_slabs(rank_slab_first_[static_cast<std::size_t>(share_->share_rank())],
                              rank_slab_first_[static_cast<std::size_t>(share_->share_rank()) + 1]);
  if (build) {
    x0_ = p.x; y0_ = p.y; z0_ = p.z;
    built_ = true;
    ++builds_;
    drift_bound_ = 0.0;
  }
  list_wall_candidates(p);
}

void VerletList::weigh_slabs() {
  const std::size_t nslab = slab_count();
  if (slab_active_.size() != nslab) slab_active_.assign(nslab, 0);
  slab_cost_.resize(nslab + 1);
  slab_cost_[0] = 0;
  for (std::size_t s = 0; s < nslab; ++s)
    slab_cost_[s + 1] = slab_cost_[s] + (slab_start_[s + 1] - slab_start_[s]) + kTouchCost * slab_active_[s];
}

}  // namespace cdm
