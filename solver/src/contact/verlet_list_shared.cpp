// The Verlet list shared among processes (SearchShare): each holds its slabs' pairs and
// its shadow slab's, and the contacts are gathered only for those who read them whole.
#include "cdm/solver/contact/verlet_list.hpp"

#include <algorithm>
#include <stdexcept>

#include "cdm/solver/parallel.hpp"
#include "cdm/solver/slot_pages.hpp"

namespace cdm {

std::pair<std::size_t, std::size_t> VerletList::own_pairs() const {
  if (!rank_split_ || slab_start_.empty()) return {0, pi_.size()};
  return {slab_start_[std::min(rank_slabs_.first, slab_count())], slab_start_[std::min(rank_slabs_.second, slab_count())]};
}

std::vector<VerletList::PairContact> VerletList::collect_contacts(bool own) const {
  std::vector<PairContact> out;
  if (!history_ || pairs_pending_) return out;
  const auto [k0, k1] = own ? own_pairs() : std::pair<std::size_t, std::size_t>{0, pi_.size()};
  for (std::size_t k = k0; k < k1; ++k)
    if (touch_[k]) out.push_back({pi_[k], pj_[k], hist_[k]});
  return out;
}

std::vector<VerletList::PairContact> VerletList::own_contacts() const {
  return pairs_pending_ ? pair_carry_ : collect_contacts(true);
}

void VerletList::list_held_again() {
  if (!holding_) throw std::logic_error("VerletList: the whole list's contacts are not held");
  pair_carry_.swap(held_);
  release_contacts();
  pairs_pending_ = true;
  carry_sorted_ = false;  // in list order
  carry_partial_ = false;
  for (auto* v : {&pi_, &pj_, &slab_start_}) v->clear();
  hist_.clear();
  touch_.clear();
}

std::vector<std::uint32_t> deal_slabs(const std::vector<std::uint64_t>& cost, const std::vector<std::uint64_t>& work,
                                      std::size_t size, bool wrap) {
  // Runs of slabs, one per process in turn, each as long as its load stays within a bound
  // L: a process's load is its slabs' cost (cost holds the running sums) and its shadow
  // slab's work, which it evaluates as the process below does. The smallest L for which
  // the runs cover every slab is found by bisection, so the largest load over the
  // processes is as small as runs of whole slabs can make it.
  const std::size_t nslab = work.size();
  std::vector<std::uint32_t> first(size + 1, static_cast<std::uint32_t>(nslab));
  auto cover = [&](std::uint64_t bound) {
    std::size_t b = 0;
    for (std::size_t r = 0; r < size; ++r) {
      first[r] = static_cast<std::uint32_t>(b);
      if (b >= nslab) continue;
      if (b == 0 && cost[nslab] <= bound) {  // every slab: no shadow slab
        b = nslab;
        continue;
      }
      const std::uint64_t shadow = b > 0 ? work[b - 1] : wrap ? work[nslab - 1] : 0;
      if (shadow > bound) continue;
      // The last slab boundary e with cost[e] - cost[b] + shadow <= bound.
      b = static_cast<std::size_t>(std::upper_bound(cost.begin() + static_cast<std::ptrdiff_t>(b), cost.end(),
                                                    cost[b] + (bound - shadow)) - cost.begin()) - 1;
    }
    return b >= nslab;
  };
  std::uint64_t lo = 0, hi = cost.back() + (nslab ? *std::max_element(work.begin(), work.end()) : 0);
  while (lo < hi) {  // cover(hi) holds: the smallest bound that covers
    const std::uint64_t mid = lo + (hi - lo) / 2;
    if (cover(mid)) hi = mid;
    else lo = mid + 1;
  }
  cover(hi);
  first[size] = static_cast<std::uint32_t>(nslab);
  return first;
}

void VerletList::divide(std::vector<std::vector<ListedPair>>& chunks, const SlabOf& slab_of,
                        const std::vector<std::uint32_t>& count, std::vector<PairContact>& carry, bool whole,
                        std::vector<std::uint32_t>& pair_slab) {
  const std::size_t nslab = slab_of.count;
  SearchShare& share = *share_;
  const auto size = static_cast<std::size_t>(share.share_size());
  const auto me = static_cast<std::size_t>(share.share_rank());
  auto slab = [&](std::uint32_t i, std::uint32_t j) { return slab_of.of_pair(i, j); };
  // Each slab's work: its listed pairs (the pair loop), those in contact at the last
  // evaluation kTouchCost times more (a contact's geometry and force law), summed over the
  // processes; with its particles (the integrator's pass; every process holds every
  // position), its cost.
  std::vector<std::uint64_t> work(nslab, 0);
  for (const auto& chunk : chunks)
    for (const ListedPair& c : chunk) ++work[slab(c.i, c.j)];
  if (history_ && (!whole || me == 0))
    for (const PairContact& c : carry) work[slab(c.i, c.j)] += kTouchCost;
  share.sum(work);
  std::vector<std::uint64_t> cost(nslab + 1, 0);
  for (std::size_t s = 0; s < nslab; ++s) cost[s + 1] = cost[s] + (count[s + 1] - count[s]) + work[s];
  rank_slab_first_ = deal_slabs(cost, work, size, slab_of.wrap);
  const std::vector<std::uint32_t> owner = slab_owners();
  // A pair of slab s goes to its owner and, when s is the shadow slab of the process
  // above (whose first slab is the next, slab 0 after the last where they wrap), to that
  // process too.
  auto each_process = [&](std::uint32_t s, auto&& to) {
    to(owner[s]);
    const std::size_t next = s + 1 < nslab ? s + 1 : slab_of.wrap ? 0 : nslab;
    if (next < nslab && owner[next] != owner[s]) to(owner[next]);
  };
  {
    // Each pair with its slab, which the process that found it has the positions to tell.
    std::vector<std::vector<std::uint32_t>> out(size);
    for (auto& chunk : chunks) {
      for (const ListedPair& c : chunk) {
        const std::uint32_t s = slab(c.i, c.j);
        each_process(s, [&](std::uint32_t r) { out[r].insert(out[r].end(), {c.i, c.j, s}); });
      }
      std::vector<ListedPair>().swap(chunk);
    }
    // From each process its rows' pairs in row order, the processes in row order: the
    // one-process order of the candidates.
    const std::vector<std::uint32_t> in = share.swap_values(out);
    chunks.assign(1, {});
    chunks[0].reserve(in.size() / 3);
    pair_slab.clear();
    pair_slab.reserve(in.size() / 3);
    for (std::size_t k = 0; k + 2 < in.size(); k += 3) {
      chunks[0].push_back({in[k], in[k + 1]});
      pair_slab.push_back(in[k + 2]);
    }
  }
  if (!history_) return;
  if (whole) {  // every process holds them all: each keeps its pairs'
    std::erase_if(carry, [&](const PairContact& c) {
      bool mine = false;
      each_process(slab(c.i, c.j), [&](std::uint32_t r) { mine = mine || r == me; });
      return !mine;
    });
    return;
  }
  std::vector<std::vector<double>> out(size);
  for (const PairContact& c : carry)
    each_process(slab(c.i, c.j), [&](std::uint32_t r) {
      out[r].insert(out[r].end(), {static_cast<double>(c.i), static_cast<double>(c.j), c.h.x, c.h.y, c.h.z});
    });
  std::vector<PairContact>().swap(carry);
  const std::vector<double> in = share.swap_values(out);
  carry.resize(in.size() / 5);
  for (std::size_t k = 0; k < carry.size(); ++k) {
    const double* v = &in[5 * k];
    carry[k] = {static_cast<std::uint32_t>(v[0]), static_cast<std::uint32_t>(v[1]), {v[2], v[3], v[4]}};
  }
}

std::vector<std::uint32_t> VerletList::slab_owners() const {
  const std::size_t size = rank_slab_first_.size() - 1;
  std::vector<std::uint32_t> owner(rank_slab_first_[size], 0);
  for (std::size_t r = 0; r < size; ++r)
    for (std::size_t s = rank_slab_first_[r]; s < rank_slab_first_[r + 1]; ++s) owner[s] = static_cast<std::uint32_t>(r);
  return owner;
}

VerletList::Slabs VerletList::held_cut(const SearchPoints& at) const {
  // Every process's own particles' extent, joined alike on every process: the same bits
  // as one process's extent of all of them.
  SearchShare& share = *share_;
  const SlabExtent e = extent(at.x, at.y, at.z, at.r, at.n, share.own_slots());
  std::vector<std::vector<double>> out(static_cast<std::size_t>(share.share_size()),
                                       std::vector<double>{e.lo[0], e.lo[1], e.lo[2], e.hi[0], e.hi[1], e.hi[2], e.rmax});
  const std::vector<double> in = share.swap_values(out);
  SlabExtent all;
  for (std::size_t k = 0; k + 7 <= in.size(); k += 7) all.join({{in[k], in[k + 1], in[k + 2]}, {in[k + 3], in[k + 4], in[k + 5]}, in[k + 6]});
  return cut_of(all);
}

std::vector<std::uint32_t> VerletList::held_counts(const SlabOf& slab_of, std::size_t n) const {
  const std::uint8_t* const own = share_->own_slots();
  std::vector<std::uint64_t> per_slab(slab_of.count, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (own[i]) ++per_slab[slab_of(static_cast<std::uint32_t>(i))];
  share_->sum(per_slab);
  std::vector<std::uint32_t> count(slab_of.count + 1, 0);
  for (std::size_t s = 0; s < slab_of.count; ++s) count[s + 1] = count[s] + static_cast<std::uint32_t>(per_slab[s]);
  return count;
}

std::vector<std::uint32_t> VerletList::held_spatial_order(const ParticleStore& p) const {
  // spatial_order()'s order, found where each process holds its own particles' positions
  // only: each slab's particles are ordered by the process whose run of rows it is in
  // (SearchSlabs), which the others send their particles' keys in it to; every process
  // then gets every run.
  SearchShare& share = *share_;
  const std::uint8_t* const own = share.own_slots();
  const std::size_t n = p.size(), size = static_cast<std::size_t>(share.share_size());
  const auto me = static_cast<std::size_t>(share.share_rank());
  const Slabs g = held_cut(SearchPoints::of(p));
  const std::size_t nslab = g.count;
  const SlabOf slab_of = slab_map(g, SearchPoints::of(p));
  const std::vector<std::uint32_t> start = held_counts(slab_of, n);
  std::vector<std::uint32_t> sorter(nslab, 0);
  for (std::size_t q = 0; q < size; ++q) {
    const SearchSlabs r = SearchSlabs::of(start, q, size, g.wrap);
    for (std::size_t s = r.s0; s < r.s1; ++s) sorter[s] = static_cast<std::uint32_t>(q);
  }
  const SearchSlabs mine = SearchSlabs::of(start, me, size, g.wrap);
  const double* const at[3] = {p.x.data(), p.y.data(), p.z.data()};
  auto id_of = [&](std::size_t i) { return p.id.empty() ? static_cast<std::uint32_t>(i) : p.id[i]; };
  // This process's run: each of its slabs' own particles first, by slab; the others'
  // particles in them come as keys (slab, slot, identity, cells high, cells low).
  const std::uint32_t base = start[mine.s0];
  std::vector<std::uint32_t> run(start[mine.s1] - base);
  std::vector<std::uint32_t> fill(start.begin() + static_cast<std::ptrdiff_t>(mine.s0),
                                  start.begin() + static_cast<std::ptrdiff_t>(mine.s1));
  std::vector<std::vector<std::uint32_t>> out(size);
  for (std::size_t i = 0; i < n; ++i) {
    if (!own[i]) continue;
    const std::uint32_t s = slab_of(static_cast<std::uint32_t>(i));
    if (sorter[s] == me) {
      run[fill[s - mine.s0]++ - base] = static_cast<std::uint32_t>(i);
      continue;
    }
    const std::uint64_t c = SlabKey::cells_of(g, at, i);
    out[sorter[s]].insert(out[sorter[s]].end(), {s, static_cast<std::uint32_t>(i), id_of(i),
                                                 static_cast<std::uint32_t>(c >> 32), static_cast<std::uint32_t>(c & 0xffffffffu)});
  }
  std::vector<std::uint32_t> in = share.swap_values(out);
  std::vector<std::uint32_t> by_slab(in.size() / 5);  // the keys received, by slab
  for (std::size_t k = 0; k < by_slab.size(); ++k) by_slab[k] = static_cast<std::uint32_t>(k);
  std::stable_sort(by_slab.begin(), by_slab.end(), [&](std::uint32_t a, std::uint32_t b) { return in[5 * a] < in[5 * b]; });
  std::size_t next = 0;
  for (std::size_t s = mine.s0; s < mine.s1; ++s) {
    const std::size_t k0 = start[s] - base, mine_end = fill[s - mine.s0] - base;
    std::vector<SlabKey> keys;
    keys.reserve(start[s + 1] - start[s]);
    for (std::size_t k = k0; k < mine_end; ++k) keys.push_back({SlabKey::cells_of(g, at, run[k]), id_of(run[k]), run[k]});
    for (; next < by_slab.size() && in[5 * by_slab[next]] == s; ++next) {
      const std::uint32_t* const r = &in[5 * by_slab[next]];
      keys.push_back({(std::uint64_t{r[3]} << 32) | r[4], r[2], r[1]});
    }
    if (keys.size() != start[s + 1] - start[s]) throw std::logic_error("VerletList: a slab's keys do not add up");
    std::sort(keys.begin(), keys.end(), SlabKey::less);
    for (std::size_t k = 0; k < keys.size(); ++k) run[k0 + k] = keys[k].slot;
  }
  std::vector<std::uint32_t>().swap(in);
  // Every process gets every run, in process order: slab 0's first.
  std::vector<std::vector<std::uint32_t>> runs(size);
  for (std::size_t q = 0; q < size; ++q)
    if (q != me) runs[q] = run;
  const std::vector<std::uint32_t> others = share.swap_values(runs);
  std::vector<std::uint32_t> from;
  from.reserve(n);
  from.insert(from.end(), others.begin(), others.begin() + base);
  from.insert(from.end(), run.begin(), run.end());
  from.insert(from.end(), others.begin() + base, others.end());
  return from;
}

void VerletList::prepare_held_build(ParticleStore& p) {
  SearchShare& share = *share_;
  const std::uint8_t* const own = share.own_slots();
  const std::size_t n = p.size(), size = static_cast<std::size_t>(share.share_size());
  const auto me = static_cast<std::size_t>(share.share_rank());
  if (!own) throw std::logic_error("VerletList: a held build without owners");
  if (pairs_pending_ && !carry_partial_ && history_)
    throw std::logic_error("VerletList: a held build with every process's loaded contacts");
  HeldBuild h;
  // A loaded list whose build is not due lists its pairs again from its build positions
  // (update()), which each process holds for its own rows: those are the positions sent.
  h.relist = relist_due(p);
  std::vector<double>* const pos[3] = {h.relist ? &x0_ : &p.x, h.relist ? &y0_ : &p.y, h.relist ? &z0_ : &p.z};
  const SearchPoints at{pos[0]->data(), pos[1]->data(), pos[2]->data(), p.radius.data(), n};
  h.cut = h.relist && cut_known_ ? cut_ : held_cut(at);
  const std::size_t nslab = h.cut.count;
  const SlabOf slab_of = slab_map(h.cut, at);
  h.count = held_counts(slab_of, n);
  // Each own particle's position and radius to the processes that search its slab.
  std::vector<std::vector<std::uint32_t>> readers(nslab);
  for (std::size_t q = 0; q < size; ++q) {
    if (q == me) continue;
    const SearchSlabs r = SearchSlabs::of(h.count, q, size, h.cut.wrap);
    for (std::size_t s = 0; s < nslab; ++s)
      if (r.reads(s, nslab)) readers[s].push_back(static_cast<std::uint32_t>(q));
  }
  std::vector<std::vector<double>> out(size);
  h.held.assign(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!own[i]) continue;
    h.held[i] = 1;
    for (const std::uint32_t q : readers[slab_of(static_cast<std::uint32_t>(i))])
      out[q].insert(out[q].end(), {static_cast<double>(i), at.x[i], at.y[i], at.z[i], p.radius[i]});
  }
  const std::vector<double> in = share.swap_values(out);
  for (std::size_t k = 0; k + 5 <= in.size(); k += 5) {
    const auto i = static_cast<std::size_t>(in[k]);
    for (int a = 0; a < 3; ++a) (*pos[a])[i] = in[k + 1 + a];
    p.radius[i] = in[k + 4];
    h.held[i] = 1;
  }
  h.ready = true;
  held_build_ = std::move(h);
  if (pairs_pending_ && history_) route_loaded_contacts(slab_of);
}

void VerletList::route_loaded_contacts(const SlabOf& slab_of) {
  // Each process read the contacts of its rows' particles i, whose partners j may be any
  // process's. Each goes to the process that lists the rows of i's slab, which holds the
  // positions of the slabs either side (where the slabs wrap, a pair of the last slab
  // and slab 0 to slab 0's too, which holds both): the build finds its pair's slab there.
  SearchShare& share = *share_;
  const std::size_t size = static_cast<std::size_t>(share.share_size()), nslab = slab_of.count;
  const auto me = static_cast<std::uint32_t>(share.share_rank());
  const HeldBuild& h = held_build_;
  std::vector<std::uint32_t> lister(nslab, 0);
  std::vector<SearchSlabs> runs(size);
  for (std::size_t q = 0; q < size; ++q) {
    runs[q] = SearchSlabs::of(h.count, q, size, h.cut.wrap);
    for (std::size_t s = runs[q].s0; s < runs[q].s1; ++s) lister[s] = static_cast<std::uint32_t>(q);
  }
  std::vector<std::vector<double>> out(size);
  for (const PairContact& c : pair_carry_) {
    const std::uint32_t s = slab_of(c.i);
    auto send = [&](std::uint32_t q) {
      out[q].insert(out[q].end(), {static_cast<double>(c.i), static_cast<double>(c.j), c.h.x, c.h.y, c.h.z});
    };
    send(lister[s]);
    if (slab_of.wrap && s + 1 == nslab && lister[0] != lister[s]) send(lister[0]);
  }
  std::vector<std::uint64_t> tally{pair_carry_.size(), 0};
  std::vector<PairContact>().swap(pair_carry_);
  const std::vector<double> in = share.swap_values(out);
  for (std::size_t k = 0; k + 5 <= in.size(); k += 5) {
    const auto i = static_cast<std::uint32_t>(in[k]), j = static_cast<std::uint32_t>(in[k + 1]);
    // Slab 0's lister keeps a pair of the last slab only where the last slab's lister
    // does not hold its j.
    const std::uint32_t q = lister[slab_of(i)];
    if (!h.held[i] || !h.held[j] || (q != me && (slab_of(j) != 0 || runs[q].reads(0, nslab)))) continue;
    pair_carry_.push_back({i, j, {in[k + 2], in[k + 3], in[k + 4]}});
  }
  tally[1] = pair_carry_.size();
  share.sum(tally);
  if (tally[0] != tally[1]) throw std::logic_error("VerletList: a loaded contact whose pair no process holds");
  std::sort(pair_carry_.begin(), pair_carry_.end(), PairContact::by_key);
}

void VerletList::keep_own_build_positions(const SearchPoints& at, const SlabOf& slab_of) {
  // A process reads the build positions of its own particles only (their displacement,
  // their wall candidates between builds); the others' slots stay zero, uncommitted.
  const std::size_t n = at.n, r = static_cast<std::size_t>(share_->share_rank());
  const std::uint32_t s0 = rank_slab_first_[r], s1 = rank_slab_first_[r + 1];
  const double* const from[3] = {at.x, at.y, at.z};
  std::vector<double>* const to[3] = {&x0_, &y0_, &z0_};
  std::uint8_t* const held = held_build_.ready ? held_build_.held.data() : nullptr;
  auto own = [&](std::size_t i) {
    if (held && !(held[i] & 1)) return false;
    const std::uint32_t s = slab_of(static_cast<std::uint32_t>(i));
    return s >= s0 && s < s1;
  };
  // At a held build the particles of this process's new slabs that it does not hold
  // come from their owners, each of which sends those of its own that change process.
  std::vector<double> entering;
  if (held) {
    const std::uint8_t* const owned = share_->own_slots();
    const std::size_t size = static_cast<std::size_t>(share_->share_size());
    const std::vector<std::uint32_t> owner = slab_owners();
    std::vector<std::vector<double>> out(size);
    for (std::size_t i = 0; i < n; ++i) {
      if (!owned[i]) continue;
      const std::uint32_t q = owner[slab_of(static_cast<std::uint32_t>(i))];
      if (q != r) out[q].insert(out[q].end(), {static_cast<double>(i), at.x[i], at.y[i], at.z[i], at.r[i]});
    }
    entering = share_->swap_values(out);
    for (std::size_t i = 0; i < n; ++i)
      if (own(i)) held[i] |= 2;
    std::vector<std::pair<std::uint32_t, double>>& radius = held_build_.entering_radius;
    radius.clear();
    for (std::size_t k = 0; k + 5 <= entering.size(); k += 5) {
      const auto i = static_cast<std::uint32_t>(entering[k]);
      held[i] |= 2;
      if (!(held[i] & 1)) radius.push_back({i, entering[k + 4]});
    }
    std::sort(radius.begin(), radius.end());
  }
  // A held listing of loaded pairs keeps the build positions of the process's rows too,
  // from which the ranks find their particles' new owners (RankSplit::assign).
  const std::uint8_t* const rows = held_build_.relist ? share_->own_slots() : nullptr;
  auto mine = [&](std::size_t i) { return held ? (held[i] & 2) != 0 || (rows && rows[i]) : own(i); };
  const SlotRuns others = runs_not_held(n, mine);
  for (int a = 0; a < 3; ++a) {
    resize_zeroed(*to[a], n);
    zero_slots(*to[a], others);
  }
  parallel_for(n, [&](std::size_t i) {
    if (own(i))
      for (int a = 0; a < 3; ++a) (*to[a])[i] = from[a][i];
  });
  for (std::size_t k = 0; k + 5 <= entering.size(); k += 5)
    for (int a = 0; a < 3; ++a) (*to[a])[static_cast<std::size_t>(entering[k])] = entering[k + 1 + a];
  own_only_ = !rows;
}

double VerletList::HeldBuild::radius(const ParticleStore& p, std::size_t i) const {
  if (held[i] & 1) return p.radius[i];
  const auto at = std::lower_bound(entering_radius.begin(), entering_radius.end(), static_cast<std::uint32_t>(i),
                                   [](const std::pair<std::uint32_t, double>& e, std::uint32_t k) { return e.first < k; });
  if (at == entering_radius.end() || at->first != i) throw std::logic_error("VerletList: a radius this process does not hold");
  return at->second;
}

}  // namespace cdm
