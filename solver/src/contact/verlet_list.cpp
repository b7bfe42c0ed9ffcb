#include "cdm/solver/contact/verlet_list.hpp"

#include <algorithm>
#include <limits>
#include <memory>
#include <stdexcept>

#include "cdm/solver/parallel.hpp"
#include "cdm/solver/slot_pages.hpp"

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
  const bool due = rebuild_due(p);
  if (!due && pairs_pending_ && listed(p.size())) {  // relist_due()
    // A loaded list: its pairs as its build listed them, from the build positions. (A
    // build due carries the loaded contacts over itself.)
    list_pairs(p, {x0_.data(), y0_.data(), z0_.data(), p.radius.data(), x0_.size()}, false);
    u.rebuilt = u.walls_listed = true;
  }
  if (due) {
    rebuild(p);
    u.rebuilt = u.walls_listed = true;
  } else if (wall_candidates_stale_ || walls_moved_away()) {
    list_wall_candidates(p);
    u.walls_listed = true;
  }
  displacement_ = -1.0;  // measured for these positions only
  return u;
}

bool VerletList::relist_due(const ParticleStore& p) const {
  return pairs_pending_ && listed(p.size()) && !rebuild_due(p);
}

bool VerletList::needs_rebuild(const ParticleStore& p) const {
  if (skin_ <= 0.0 || p.size() != x0_.size()) return true;
  const double lim2 = 0.25 * skin_ * skin_;
  const std::size_t n = p.size();
  if (displacement_ >= 0.0) return displacement_ > lim2;  // the integrator measured it
  return parallel_max(n, [&](std::size_t i) { return displacement(p, i); }) > lim2;
}

SlabExtent VerletList::extent(const double* x, const double* y, const double* z, const double* r, std::size_t n,
                              const std::uint8_t* only) {
  const double* axis_data[3] = {x, y, z};
  SlabExtent e;
  for (std::size_t i = 0; i < n; ++i) {
    if (only && !only[i]) continue;
    for (int a = 0; a < 3; ++a) {
      e.lo[a] = std::min(e.lo[a], axis_data[a][i]);
      e.hi[a] = std::max(e.hi[a], axis_data[a][i]);
    }
    e.rmax = std::max(e.rmax, r[i]);
  }
  return e;
}

VerletList::Slabs VerletList::cut_of(const SlabExtent& e) const {
  // Slabs along the longest side of the particles' bounding box (below), each at least one
  // interaction range (2 r_max + skin) wide, so listed partners are in the same or the
  // neighbouring slab. The slab count depends on the geometry only, never on threads.
  // Along a periodic axis the side is the period, which the slabs tile: an even number
  // of them (the last, odd, meets the first, even, so the pair loop's two phases still
  // never touch one particle from two slabs at once), at least four (so the slabs either
  // side of one are two others); an axis too short for four is not cut.
  Slabs g;
  if (!e.empty())
    for (int a = 0; a < 3; ++a) {
      g.lo[a] = e.lo[a];
      g.hi[a] = e.hi[a];
    }
  const double rmax = e.rmax;
  g.range = 2.0 * rmax + skin_;
  auto slabs_along = [&](int a) -> std::size_t {
    if (!(g.range > 0.0)) return box_.on[a] ? 0 : 1;
    if (!box_.on[a]) return std::max<std::size_t>(1, std::min<std::size_t>(4096, static_cast<std::size_t>((g.hi[a] - g.lo[a]) / g.range)));
    const std::size_t k = std::min<std::size_t>(4096, static_cast<std::size_t>(box_.len[a] / g.range)) & ~std::size_t{1};
    return k >= 4 ? k : 0;  // 0: not cut
  };
  auto side = [&](int a) { return box_.on[a] ? box_.len[a] : g.hi[a] - g.lo[a]; };
  // The preferred axis (the gas's planes, so that each MPI process's particles lie over a
  // run of them) where it gives min_preferred_slabs slabs or more (a bed taller than it is
  // deep too); else of sides within a tenth of the longest the first (x, y, z): a bed
  // about as wide as it is deep keeps its axis as its sides trade places by a grain, and
  // with it the particles' order and, among MPI ranks, their owners.
  double longest = 0.0;
  for (int a = 0; a < 3; ++a)
    if (slabs_along(a) > 0) longest = std::max(longest, side(a));
  auto among_longest = [&](int a) { return slabs_along(a) > 0 && side(a) >= 0.9 * longest; };
  const bool preferred =
      preferred_axis_ >= 0 && (among_longest(preferred_axis_) || slabs_along(preferred_axis_) >= min_preferred_slabs);
  int axis = preferred ? preferred_axis_ : -1;
  for (int a = 0; a < 3 && axis < 0; ++a)
    if (among_longest(a)) axis = a;
  const bool cut = axis >= 0;
  g.axis = cut ? axis : 0;
  g.count = cut ? slabs_along(axis) : 1;
  g.wrap = cut && box_.on[axis];
  if (g.wrap) {
    g.lo[axis] = box_.lo[axis];
    g.hi[axis] = box_.lo[axis] + box_.len[axis];
  }
  g.width = g.count > 1 ? (g.hi[g.axis] - g.lo[g.axis]) / static_cast<double>(g.count) : 1.0;
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
  // As the pairs were listed: from x0_, or where it holds the own particles' only (a
  // divided build, which assign() follows at once) from p.x, which is the build's.
  const std::size_t n = x0_.size();
  const SearchPoints at = own_only_ ? SearchPoints::of(p) : SearchPoints{x0_.data(), y0_.data(), z0_.data(), p.radius.data(), n};
  const Slabs g = cut_known_ ? cut_ : slabs(at.x, at.y, at.z, p.radius, n);
  const SlabOf slab = slab_map(g, at);
  std::vector<std::uint32_t> out(n, 0);
  if (g.count == 1) return out;
  for (std::size_t i = 0; i < n; ++i) out[i] = slab(static_cast<std::uint32_t>(i));
  return out;
}

std::pair<std::size_t, std::size_t> VerletList::thread_slabs() const {
  const auto [t, nt] = thread_id();
  return {thread_first_slab(t, nt), thread_first_slab(t + 1, nt)};
}

std::vector<std::uint32_t> VerletList::spatial_order(const ParticleStore& p) const {
  const Slabs g = slabs(p);
  return key_order(SearchPoints::of(p), p.id.empty() ? nullptr : p.id.data(), g, 0, g.count, nullptr, nullptr);
}

std::vector<std::uint32_t> VerletList::key_order(const SearchPoints& at, const std::uint32_t* id, const Slabs& g,
                                                 std::size_t s0, std::size_t s1, std::uint32_t* rank,
                                                 const std::vector<std::uint32_t>* before, const std::uint8_t* held) {
  const std::size_t n = at.n;
  // The slab first, so that each slab's particles, and so each thread's and each rank's,
  // are one run; then each slab's particles in the order of their keys (SlabKey).
  const double* const data[3] = {at.x, at.y, at.z};
  const SlabOf slab = slab_map(g, at);
  auto id_of = [id](std::uint32_t i) { return id ? id[i] : i; };
  // By slab first (a counting sort, stable), then each slab's particles by their cells and
  // identities: a key per particle of one slab at a time, not of all of them at once.
  std::vector<std::uint32_t> start;
  if (before) {
    start = *before;
  } else {
    start.assign(g.count + 1, 0);
    for (std::size_t i = 0; i < n; ++i)
      if (!held || held[i]) ++start[slab(static_cast<std::uint32_t>(i)) + 1];
    for (std::size_t s = 0; s < g.count; ++s) start[s + 1] += start[s];
  }
  const std::uint32_t base = start[s0];
  std::vector<std::uint32_t> from(start[s1] - base);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
      if (held && !held[i]) continue;
      const std::uint32_t s = slab(static_cast<std::uint32_t>(i));
      if (s >= s0 && s < s1) from[fill[s]++ - base] = static_cast<std::uint32_t>(i);
    }
  }
  auto order_slab = [&](std::size_t s) {
    std::vector<SlabKey> key(start[s + 1] - start[s]);
    for (std::size_t k = 0; k < key.size(); ++k) {
      const std::uint32_t i = from[start[s] - base + k];
      key[k] = {SlabKey::cells_of(g, data, i), id_of(i), i};
    }
    std::sort(key.begin(), key.end(), SlabKey::less);
    for (std::size_t k = 0; k < key.size(); ++k) from[start[s] - base + k] = key[k].slot;
  };
  if (from.size() > parallel_threshold) {
#pragma omp parallel for schedule(dynamic)
    for (std::size_t s = s0; s < s1; ++s) order_slab(s);
  } else {
    for (std::size_t s = s0; s < s1; ++s) order_slab(s);
  }
  if (rank)
    for (std::size_t k = 0; k < from.size(); ++k) rank[from[k]] = static_cast<std::uint32_t>(base + k);
  return from;
}

void VerletList::rebuild(const ParticleStore& p) { list_pairs(p, SearchPoints::of(p), true); }

void VerletList::list_pairs(const ParticleStore& p, const SearchPoints& at, bool build) {
  const std::size_t n = p.size();
  const bool divided = share_ && share_->share_size() > 1;
  // The slab cut first: a list shared among processes sends each pair, and each contact,
  // to the process of its slab. Listed again without a build, the pairs keep the cut
  // they were listed in (particles removed since may have changed the bounding box).
  // A held build (prepare_held_build) brought its cut and counts, and the positions it
  // reads: the others' are not current here.
  const bool held = held_build_.ready;
  if (held && !(build != held_build_.relist && divided && held_build_.held.size() == n))
    throw std::logic_error("VerletList: a held build prepared for another build");
  const std::uint8_t* const held_slots = held ? held_build_.held.data() : nullptr;
  const Slabs g = held ? held_build_.cut : build || !cut_known_ ? slabs(at.x, at.y, at.z, p.radius, n) : cut_;
  cut_ = g;
  cut_known_ = true;
  const std::size_t nslab = g.count;
  const SlabOf slab_of = slab_map(g, at);
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
  const bool carry_whole = pairs_pending_ && !carry_partial_;  // every process holds every contact
  if (pairs_pending_ && carry_partial_ && !divided)
    throw std::logic_error("VerletList: a share of the contacts loaded for a list that is not divided");
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
  pairs_pending_ = carry_partial_ = false;
  const std::size_t last_size = pi_.size();
  std::vector<std::uint32_t>().swap(pi_);
  std::vector<std::uint32_t>().swap(pj_);
  std::vector<Vec3>().swap(hist_);
  std::vector<std::uint8_t>().swap(touch_);
  // The candidates live only while the list is built, and are released before the
  // history is carried over. Reserved at the last list's size plus a margin, so that
  // they rarely grow by doubling. One chunk per thread (each lists its own particles'
  // pairs), in (i, j) order chunk after chunk.
  std::vector<std::vector<ListedPair>> candidates;
  std::vector<std::uint32_t> count;  // particles before each slab
  std::vector<std::uint32_t> pair_slab;  // divided: each candidate's slab
  {
    // The rows in order of their keys (key_order): the pairs then come in an order that
    // does not depend on the particles' slots, the same on any number of processes. Each
    // process lists the rows of a run of whole slabs, about its share of the particles,
    // the runs in process order, so that their pairs in process order are the one-process
    // order.
    if (held) {
      count.swap(held_build_.count);
    } else {
      count.assign(nslab + 1, 0);
      for (std::size_t i = 0; i < n; ++i) ++count[slab_of(static_cast<std::uint32_t>(i)) + 1];
      for (std::size_t s = 0; s < nslab; ++s) count[s + 1] += count[s];
    }
    SearchSlabs rows_of{0, nslab, 0, nslab, false};
    if (divided)
      rows_of = SearchSlabs::of(count, static_cast<std::size_t>(share_->share_rank()),
                                static_cast<std::size_t>(share_->share_size()), g.wrap);
    // Ranked, and searched: the rows' slabs and the slab either side, where their
    // partners are (of the slab below, none ranks above a row). Only those slots' ranks
    // are written, so the others' pages of the rank array are never committed.
    const std::size_t s0 = rows_of.s0, s1 = rows_of.s1, a = rows_of.a, b = rows_of.b;
    const std::unique_ptr<std::uint32_t[]> rank(new std::uint32_t[n]);
    const std::uint32_t* const id = p.id.empty() ? nullptr : p.id.data();
    std::vector<std::uint32_t> points = key_order(at, id, g, a, b, rank.get(), &count, held_slots);
    // Where the slabs wrap, slab 0's rows meet the last slab's particles: ranked too, as
    // on one process, so that their pairs come in the same order.
    if (rows_of.last) {
      const std::vector<std::uint32_t> last = key_order(at, id, g, nslab - 1, nslab, rank.get(), &count, held_slots);
      points.insert(points.end(), last.begin(), last.end());
    }
    const auto row0 = points.begin() + static_cast<std::ptrdiff_t>(count[s0] - count[a]);
    const std::vector<std::uint32_t> rows(row0, row0 + static_cast<std::ptrdiff_t>(count[s1] - count[s0]));
    // One process searches among every particle; divided, among the ranked ones.
    search_.set_rows({&rows, rank.get(), divided ? &points : nullptr});
    search_.find_contacts(at, skin_, candidates, box_, last_size + last_size / 8 + 64);
    search_.set_rows({});
  }
  // Two fixed particles never move: their contact does nothing, so it is not listed.
  if (!p.fixed_flag.empty())
    for (auto& chunk : candidates)
      chunk.erase(std::remove_if(chunk.begin(), chunk.end(),
                                 [&](const ListedPair& c) { return p.is_fixed(c.i) && p.is_fixed(c.j); }),
                  chunk.end());
  if (divided) {
    divide(candidates, slab_of, count, carry, carry_whole, pair_slab);
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
      for (const ListedPair& cp : chunk) {
        owner[k] = divided ? pair_slab[k] : slab_of.of_pair(cp.i, cp.j);
        ++start[owner[k++] + 1];
      }
  }
  for (std::size_t s = 0; s < nslab; ++s) start[s + 1] += start[s];
  std::vector<std::uint32_t> pi(listed), pj(listed);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    std::size_t k = 0;
    for (auto& chunk : candidates) {
      for (const ListedPair& cp : chunk) {
        const std::uint32_t at = fill[owner[k++]]++;
        pi[at] = cp.i;
        pj[at] = cp.j;
      }
      std::vector<ListedPair>().swap(chunk);
    }
  }
  std::vector<std::vector<ListedPair>>().swap(candidates);
  std::vector<std::uint32_t>().swap(owner);
  std::vector<std::uint32_t>().swap(count);
  std::vector<std::uint32_t>().swap(pair_slab);
  if (history_) {
    // Carry the history of every pair in contact at the last evaluation (each is in
    // both lists): a new pair looks for its j among the few carried pairs of its i, or,
    // listed the other way round before (its particles' keys changed order since), for
    // its i among those of its j, the history then seen from the other particle (the
    // negative).
    std::vector<Vec3> hist(pi.size());
    std::vector<std::uint8_t> touch(pi.size(), 0);
    if (!carry.empty()) {
      auto carried = [&](std::uint32_t a, std::uint32_t b) -> const PairContact* {
        for (std::uint32_t q = carry_first[a]; q < carry_first[a + 1]; ++q)
          if (carry[q].j == b) return &carry[q];
        return nullptr;
      };
      for (std::size_t k = 0; k < pi.size(); ++k) {
        const std::uint32_t i = pi[k], j = pj[k];
        if (const PairContact* c = carried(i, j)) {
          hist[k] = c->h;
          touch[k] = 1;
        } else if (const PairContact* r = carried(j, i)) {
          hist[k] = -r->h;
          touch[k] = 1;
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
  // Divided, a build keeps its own slabs' build positions, and so does a held listing of
  // loaded pairs (with the process's rows' too).
  if (build ? divided : held) keep_own_build_positions(at, slab_of);
  if (build) {
    if (!divided) {
      x0_ = p.x; y0_ = p.y; z0_ = p.z;
      own_only_ = false;
    }
    built_ = true;
    ++builds_;
    drift_bound_ = 0.0;
  }
  list_wall_candidates(p, &at);
  held_build_ = HeldBuild{};
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
