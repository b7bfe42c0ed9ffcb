// The Verlet list shared among processes (SearchShare): each holds its slabs' pairs and
// its shadow slab's, and the contacts are gathered only for those who read them whole.
#include "cdm/solver/contact/verlet_list.hpp"

#include <algorithm>
#include <stdexcept>

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

std::vector<std::uint32_t> VerletList::deal_slabs(const std::vector<std::uint64_t>& cost,
                                                   const std::vector<std::uint64_t>& work, std::size_t size,
                                                   bool wrap) {
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

void VerletList::divide(std::vector<std::vector<ContactPair>>& chunks, const SlabOf& slab_of, std::size_t n,
                        std::vector<PairContact>& carry, bool whole) {
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
    for (const ContactPair& c : chunk) ++work[slab(c.i, c.j)];
  if (history_ && (!whole || me == 0))
    for (const PairContact& c : carry) work[slab(c.i, c.j)] += kTouchCost;
  share.sum(work);
  std::vector<std::uint64_t> cost(nslab + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++cost[slab_of(static_cast<std::uint32_t>(i)) + 1];
  for (std::size_t s = 0; s < nslab; ++s) cost[s + 1] += cost[s] + work[s];
  rank_slab_first_ = deal_slabs(cost, work, size, slab_of.wrap);
  std::vector<std::uint32_t> owner(nslab, 0);
  for (std::size_t r = 0; r < size; ++r)
    for (std::size_t s = rank_slab_first_[r]; s < rank_slab_first_[r + 1]; ++s) owner[s] = static_cast<std::uint32_t>(r);
  // A pair of slab s goes to its owner and, when s is the shadow slab of the process
  // above (whose first slab is the next, slab 0 after the last where they wrap), to that
  // process too.
  auto each_process = [&](std::uint32_t s, auto&& to) {
    to(owner[s]);
    const std::size_t next = s + 1 < nslab ? s + 1 : slab_of.wrap ? 0 : nslab;
    if (next < nslab && owner[next] != owner[s]) to(owner[next]);
  };
  {
    std::vector<std::vector<std::uint32_t>> out(size);
    for (auto& chunk : chunks) {
      for (const ContactPair& c : chunk)
        each_process(slab(c.i, c.j), [&](std::uint32_t r) { out[r].insert(out[r].end(), {c.i, c.j}); });
      std::vector<ContactPair>().swap(chunk);
    }
    // From each process its rows' pairs in row order, the processes in row order: the
    // one-process order of the candidates.
    const std::vector<std::uint32_t> in = share.swap_values(out);
    chunks.assign(1, {});
    chunks[0].reserve(in.size() / 2);
    for (std::size_t k = 0; k + 1 < in.size(); k += 2) chunks[0].push_back({in[k], in[k + 1], 0.0});
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

}  // namespace cdm
