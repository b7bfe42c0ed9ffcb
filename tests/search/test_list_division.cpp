// The Verlet list divided among processes (VerletList::divide through a SearchShare):
// each holds exactly the one-process list's pairs of its slabs and of its shadow slab, in
// the same order, and a later build carries each contact's history to every process that
// lists the pair. The processes are threads here, exchanging through shared memory, so
// that the division runs without MPI (and under the sanitizers).
#include <gtest/gtest.h>

#include <barrier>
#include <cmath>
#include <random>
#include <thread>

#include "cdm/solver/contact/verlet_list.hpp"

namespace {

/// @p size processes as threads: sums and exchanges meet at a barrier.
class ThreadShare {
 public:
  explicit ThreadShare(int size)
      : size_(size), sums_(static_cast<std::size_t>(size)), u32_(static_cast<std::size_t>(size * size)),
        f64_(static_cast<std::size_t>(size * size)), meet_(size) {}

  class Member final : public cdm::SearchShare {
   public:
    Member(ThreadShare& s, int rank) : s_(s), rank_(rank) {}
    int share_rank() const override { return rank_; }
    int share_size() const override { return s_.size_; }
    void sum(std::vector<std::uint64_t>& v) override {
      s_.sums_[static_cast<std::size_t>(rank_)] = v;
      s_.meet_.arrive_and_wait();
      for (std::size_t k = 0; k < v.size(); ++k) {
        v[k] = 0;
        for (const auto& other : s_.sums_) v[k] += other[k];
      }
      s_.meet_.arrive_and_wait();
    }
    std::vector<std::uint32_t> swap_values(std::vector<std::vector<std::uint32_t>>& out) override {
      return s_.swap(s_.u32_, out, rank_);
    }
    std::vector<double> swap_values(std::vector<std::vector<double>>& out) override {
      return s_.swap(s_.f64_, out, rank_);
    }
    const std::uint8_t* own_slots() const override { return own; }
    const std::uint8_t* own = nullptr;  // this process's particles, once it owns some

   private:
    ThreadShare& s_;
    int rank_;
  };

 private:
  template <class T>
  std::vector<T> swap(std::vector<std::vector<T>>& box, std::vector<std::vector<T>>& out, int rank) {
    const auto n = static_cast<std::size_t>(size_), me = static_cast<std::size_t>(rank);
    for (std::size_t r = 0; r < n; ++r) box[me * n + r] = std::move(out[r]);
    meet_.arrive_and_wait();
    std::vector<T> in;
    for (std::size_t s = 0; s < n; ++s) in.insert(in.end(), box[s * n + me].begin(), box[s * n + me].end());
    meet_.arrive_and_wait();
    return in;
  }
  int size_;
  std::vector<std::vector<std::uint64_t>> sums_;
  std::vector<std::vector<std::uint32_t>> u32_;
  std::vector<std::vector<double>> f64_;
  std::barrier<> meet_;
};

cdm::ParticleStore bed(std::size_t n, std::uint64_t seed) {
  // A box longer along x than its other sides, so that it is cut into many slabs.
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  cdm::ParticleStore p;
  for (std::size_t i = 0; i < n; ++i)
    p.add({0.08 * u(rng), 0.01 * u(rng), 0.01 * u(rng)}, {}, 0.4e-3 + 0.2e-3 * u(rng), 2500.0, 0);
  return p;
}

/// The bed's box periodic along x, [0, 0.08) m: the slabs then wrap, the last slab's pairs
/// reaching into the first.
cdm::PeriodicBox periodic_x() {
  cdm::PeriodicBox box;
  box.on[0] = true;
  box.len[0] = 0.08;
  return box;
}

/// Positions back into the box after a move.
void wrap(cdm::ParticleStore& p, const cdm::PeriodicBox& box) {
  for (std::size_t i = 0; i < p.size(); ++i) p.x[i] = box.wrap(p.x[i], 0);
}

/// A tangential history as a function of the pair alone, so that any list can set it.
cdm::Vec3 history_of(std::uint32_t i, std::uint32_t j) { return {1e-7 * i, -1e-7 * j, 1e-9 * (i + j)}; }

/// Builds @p p's list on @p size threads sharing it, after @p prepare(list, rank) on each.
template <class Prepare>
std::vector<cdm::VerletList> build_shared(int size, std::vector<cdm::ParticleStore>& stores, Prepare&& prepare,
                                          std::vector<cdm::VerletList>* lists_in = nullptr) {
  ThreadShare share(size);
  std::vector<ThreadShare::Member> members;
  for (int r = 0; r < size; ++r) members.emplace_back(share, r);
  std::vector<cdm::VerletList> lists;
  if (lists_in) lists = std::move(*lists_in);
  else
    for (int r = 0; r < size; ++r) lists.emplace_back(std::vector<cdm::Wall>{}, true, 0.1e-3);
  std::vector<std::thread> threads;
  for (int r = 0; r < size; ++r)
    threads.emplace_back([&, r] {
      const auto k = static_cast<std::size_t>(r);
      lists[k].set_search_share(&members[k]);
      prepare(lists[k], r);
      lists[k].update(stores[k]);
    });
  for (auto& t : threads) t.join();
  return lists;
}

/// Each process's list holds the one-process list's pairs of its slabs and shadow slab,
/// in order, with the same history, and nothing else.
void expect_divided(cdm::VerletList& whole, std::vector<cdm::VerletList>& parts) {
  const auto& start = whole.slab_start();
  const std::size_t nslab = whole.slab_count();
  ASSERT_GT(nslab, 8u);
  std::size_t owned = 0;
  for (std::size_t r = 0; r < parts.size(); ++r) {
    cdm::VerletList& part = parts[r];
    ASSERT_EQ(part.slab_count(), nslab);
    const auto [s0, s1] = part.rank_slabs();
    EXPECT_EQ(s0, part.rank_slab_first()[r]);
    EXPECT_EQ(s1, part.rank_slab_first()[r + 1]);
    const std::size_t shadow = part.shadow_slab();
    for (std::size_t s = 0; s < nslab; ++s) {
      const bool held = (s >= s0 && s < s1) || s == shadow;
      const std::size_t n = part.slab_start()[s + 1] - part.slab_start()[s];
      ASSERT_EQ(n, held ? start[s + 1] - start[s] : 0u) << "process " << r << ", slab " << s;
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t a = start[s] + k, b = part.slab_start()[s] + k;
        ASSERT_EQ(part.pair_i()[b], whole.pair_i()[a]);
        ASSERT_EQ(part.pair_j()[b], whole.pair_j()[a]);
        ASSERT_EQ(part.pair_touch()[b], whole.pair_touch()[a]);
        const cdm::Vec3 h = part.pair_history()[b], w = whole.pair_history()[a];
        ASSERT_TRUE(h.x == w.x && h.y == w.y && h.z == w.z);
      }
    }
    owned += start[s1] - start[s0];
  }
  EXPECT_EQ(owned, whole.size());  // the processes' own slabs are every slab once
}

void divided_and_carried(bool periodic) {
  const cdm::ParticleStore p0 = bed(3000, 3);
  const cdm::PeriodicBox box = periodic ? periodic_x() : cdm::PeriodicBox{};
  for (int size : {2, 3, 4}) {
    SCOPED_TRACE(size);
    cdm::ParticleStore p = p0;
    cdm::VerletList whole(std::vector<cdm::Wall>{}, true, 0.1e-3);
    whole.set_periodic_box(box);
    whole.update(p);
    ASSERT_EQ(whole.slabs_wrap(), periodic);
    std::vector<cdm::ParticleStore> stores(static_cast<std::size_t>(size), p);
    auto prepare = [&box](cdm::VerletList& l, int) { l.set_periodic_box(box); };
    std::vector<cdm::VerletList> parts = build_shared(size, stores, prepare);
    expect_divided(whole, parts);
    if (periodic) {  // the first process's shadow slab is the last
      EXPECT_EQ(parts[0].shadow_slab(), whole.slab_count() - 1);
      std::size_t across = 0;  // pairs across the periodic faces, in the last slab
      const std::size_t last = whole.slab_count() - 1;
      for (std::size_t k = whole.slab_start()[last]; k < whole.slab_start()[last + 1]; ++k)
        across += std::abs(p.x[whole.pair_i()[k]] - p.x[whole.pair_j()[k]]) > 0.04;
      EXPECT_GE(across, 5u);
    }

    // Every third listed pair in contact, with a history of its own, on each list that
    // holds it; then the particles move past half the skin, and the lists are built again.
    auto touch = [](cdm::VerletList& l) {
      for (std::size_t k = 0; k < l.size(); ++k)
        if ((l.pair_i()[k] + l.pair_j()[k]) % 3 == 0) {
          l.pair_touch()[k] = 1;
          l.pair_history()[k] = history_of(l.pair_i()[k], l.pair_j()[k]);
        }
    };
    touch(whole);
    for (auto& l : parts) touch(l);
    auto move = [](cdm::ParticleStore& s) {
      for (std::size_t i = 0; i < s.size(); ++i) s.x[i] += (i % 2 ? 0.06e-3 : -0.06e-3);
    };
    move(p);
    wrap(p, box);
    for (auto& s : stores) {
      move(s);
      wrap(s, box);
    }
    whole.update(p);
    ASSERT_EQ(whole.builds(), 2u);
    parts = build_shared(size, stores, prepare, &parts);
    std::size_t carried = 0;
    for (std::size_t k = 0; k < whole.size(); ++k) carried += whole.pair_touch()[k];
    EXPECT_GT(carried, 100u);  // contacts were carried, and compared below
    expect_divided(whole, parts);
  }
}

/// A held build (VerletList::prepare_held_build): each process holds the current
/// positions of its own particles and of the slabs either side of them only, the others'
/// far off; the build brings what it reads from the owners and lists the same pairs,
/// contacts, build positions and wall candidates as a build from every position, and
/// the sort's order (held_spatial_order) is the same too.
void held_build(bool periodic) {
  const cdm::ParticleStore p0 = bed(3000, 5);
  const cdm::PeriodicBox box = periodic ? periodic_x() : cdm::PeriodicBox{};
  const std::vector<cdm::Wall> walls{cdm::Wall::plane("floor", {0, 0, 0}, {0, 1, 0}, 0)};
  const std::size_t n = p0.size();
  for (int size : {2, 3, 4}) {
    SCOPED_TRACE(size);
    const auto m = static_cast<std::size_t>(size);
    cdm::ParticleStore p = p0;
    cdm::VerletList whole(walls, true, 0.1e-3);
    whole.set_periodic_box(box);
    whole.update(p);
    std::vector<cdm::ParticleStore> stores(m, p);
    std::vector<cdm::VerletList> lists;
    for (std::size_t r = 0; r < m; ++r) lists.emplace_back(walls, true, 0.1e-3);
    ThreadShare share(size);
    std::vector<ThreadShare::Member> members;
    for (int r = 0; r < size; ++r) members.emplace_back(share, r);
    auto on_each = [&](auto&& f) {
      std::vector<std::thread> threads;
      for (std::size_t r = 0; r < m; ++r) threads.emplace_back([&, r] { f(r); });
      for (auto& t : threads) t.join();
    };
    on_each([&](std::size_t r) {
      lists[r].set_search_share(&members[r]);
      lists[r].set_periodic_box(box);
      lists[r].update(stores[r]);
    });
    // Each process's particles: those of its slabs. The pairs in the lower third of the
    // box in contact: those slabs then weigh more, and the build deals them out
    // differently from the runs of rows it searches, so that a process's new slabs hold
    // particles it neither held nor searched.
    const std::vector<std::uint32_t> slab = whole.particle_slabs(p);
    const std::vector<std::uint32_t>& first = lists[0].rank_slab_first();
    const std::size_t nslab = whole.slab_count();
    std::vector<std::vector<std::uint8_t>> own(m, std::vector<std::uint8_t>(n, 0));
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t r = 0; r < m; ++r) own[r][i] = slab[i] >= first[r] && slab[i] < first[r + 1];
    auto touch = [&p](cdm::VerletList& l) {
      for (std::size_t k = 0; k < l.size(); ++k)
        if (p.x[l.pair_i()[k]] < 0.027) {
          l.pair_touch()[k] = 1;
          l.pair_history()[k] = history_of(l.pair_i()[k], l.pair_j()[k]);
        }
    };
    touch(whole);
    for (auto& l : lists) touch(l);
    // Every particle moves past half the skin; a process's store keeps the new positions
    // of its particles and of the slabs either side only (its ghosts).
    auto move = [&](cdm::ParticleStore& s) {
      for (std::size_t i = 0; i < n; ++i) s.x[i] = box.wrap(s.x[i] + (i % 2 ? 0.06e-3 : -0.06e-3), 0);
    };
    move(p);
    whole.update(p);
    ASSERT_EQ(whole.builds(), 2u);
    std::size_t far = 0;
    for (std::size_t r = 0; r < m; ++r) {
      move(stores[r]);
      auto near = [&](std::size_t s) {
        const std::size_t below = s + 1 < nslab ? s + 1 : periodic ? 0 : s, above = s > 0 ? s - 1 : periodic ? nslab - 1 : s;
        for (const std::size_t t : {s, below, above})
          if (t >= first[r] && t < first[r + 1]) return true;
        return false;
      };
      for (std::size_t i = 0; i < n; ++i)
        if (!near(slab[i])) {
          stores[r].x[i] = stores[r].y[i] = stores[r].z[i] = 5.0;  // not current here
          ++far;
        }
    }
    ASSERT_GT(far, n * (m - 1) / 2);
    // The sort's order, from the own particles' positions, is the one from every position.
    const std::vector<std::uint32_t> order = whole.spatial_order(p);
    std::vector<std::vector<std::uint32_t>> orders(m);
    on_each([&](std::size_t r) {
      members[r].own = own[r].data();
      orders[r] = lists[r].held_spatial_order(stores[r]);
      lists[r].prepare_held_build(stores[r]);
      lists[r].update(stores[r]);
    });
    for (std::size_t r = 0; r < m; ++r) ASSERT_EQ(orders[r], order) << "process " << r;
    expect_divided(whole, lists);
    const std::vector<std::uint32_t> slab2 = whole.particle_slabs(p);
    for (std::size_t r = 0; r < m; ++r) {
      const auto [s0, s1] = lists[r].rank_slabs();
      std::size_t wall_entries = 0;
      for (std::size_t i = 0; i < n; ++i) {
        if (slab2[i] < s0 || slab2[i] >= s1) continue;
        ASSERT_EQ(lists[r].build_positions(0)[i], p.x[i]) << "process " << r << ", particle " << i;
        ASSERT_EQ(lists[r].build_positions(1)[i], p.y[i]);
        ASSERT_EQ(lists[r].build_positions(2)[i], p.z[i]);
        const auto [a0, a1] = whole.wall_entries(static_cast<std::uint32_t>(i));
        const auto [b0, b1] = lists[r].wall_entries(static_cast<std::uint32_t>(i));
        ASSERT_EQ(b1 - b0, a1 - a0) << "process " << r << ", particle " << i;
        wall_entries += a1 - a0;
      }
      EXPECT_GT(wall_entries, 10u);
    }
  }
}

TEST(ListDivision, EachProcessHoldsItsSlabsAndShadowSlabAndTheContactsFollowThePairs) { divided_and_carried(false); }

TEST(ListDivision, AHeldBuildAndSortReadTheOwnersPositionsAndListAsFromEveryPosition) {
  held_build(false);
  held_build(true);
}

TEST(ListDivision, SlabsAlongAPeriodicAxisWrapAndAreDividedAlike) { divided_and_carried(true); }

}  // namespace

TEST(ListDivision, SlabsAreDealtSoTheLargestLoadIsTheLeastRunsCanGive) {
  // A process's load: its run of slabs' cost plus its shadow slab's work (the pairs it
  // evaluates as the process below does): the slab below its run, none below slab 0, or
  // where the slabs wrap the last one unless the run holds them all. Against every way
  // of cutting a few slabs into runs, the deal's largest load is the least.
  std::mt19937 gen(11);
  std::uniform_int_distribution<std::uint64_t> pairs(0, 40), particles(0, 12);
  for (int trial = 0; trial < 600; ++trial) {
    const bool wrap = trial >= 300;
    const std::size_t nslab = 1 + static_cast<std::size_t>(trial % 9), size = 1 + static_cast<std::size_t>(trial % 4);
    std::vector<std::uint64_t> work(nslab), cost(nslab + 1, 0);
    for (std::size_t s = 0; s < nslab; ++s) {
      work[s] = trial % 7 == 0 && s % 3 == 1 ? 0 : pairs(gen);
      cost[s + 1] = cost[s] + work[s] + particles(gen);
    }
    auto largest = [&](const std::vector<std::uint32_t>& first) {
      std::uint64_t most = 0;
      for (std::size_t r = 0; r < size; ++r) {
        const std::size_t b = first[r], e = first[r + 1];
        if (b == e) continue;
        const std::uint64_t shadow = b > 0 ? work[b - 1] : wrap && e < nslab ? work[nslab - 1] : 0;
        most = std::max(most, cost[e] - cost[b] + shadow);
      }
      return most;
    };
    const std::vector<std::uint32_t> dealt = cdm::deal_slabs(cost, work, size, wrap);
    ASSERT_EQ(dealt.size(), size + 1);
    EXPECT_EQ(dealt.front(), 0u);
    EXPECT_EQ(dealt.back(), nslab);
    for (std::size_t r = 0; r < size; ++r) ASSERT_LE(dealt[r], dealt[r + 1]);
    // Every cut: size - 1 boundaries in [0, nslab], in order.
    std::uint64_t best = UINT64_MAX;
    std::vector<std::uint32_t> first(size + 1, 0);
    first[size] = static_cast<std::uint32_t>(nslab);
    auto every = [&](auto&& self, std::size_t r) -> void {
      if (r == size) {
        best = std::min(best, largest(first));
        return;
      }
      for (std::uint32_t b = first[r - 1]; b <= nslab; ++b) {
        first[r] = b;
        self(self, r + 1);
      }
    };
    if (size == 1) best = largest(first);
    else every(every, 1);
    EXPECT_EQ(largest(dealt), best) << "trial " << trial << (wrap ? ", wrapping" : "");
  }
}
