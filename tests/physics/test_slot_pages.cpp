// Per-particle arrays that cost memory only where a process holds particles
// (slot_pages.hpp): zeroing slots returns their whole pages to the system, and a
// permutation gives the same bits as a plain gather while committing no page whose
// slots are all zero; a range read once (the scene's particles) gives its pages back;
// an array read through a slot window (a restart's share) commits the window's only.
#include <gtest/gtest.h>
#include <malloc.h>

#include <bit>
#include <cstdio>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <random>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/slot_pages.hpp"
#include "resident.hpp"

namespace {

constexpr std::size_t kSlots = std::size_t{1} << 20;  // 8 MiB of doubles

// Whether the page holding v[i] is resident.
bool resident(const std::vector<double>& v, std::size_t i) { return cdm_test::resident(v.data() + i); }

std::uint64_t bits(double a) { return std::bit_cast<std::uint64_t>(a); }

// The process's resident memory in pages (/proc/self/statm).
long resident_pages() {
  long size = 0, resident = 0;
  std::FILE* f = std::fopen("/proc/self/statm", "r");
  EXPECT_NE(f, nullptr);
  if (!f) return 0;
  EXPECT_EQ(std::fscanf(f, "%ld %ld", &size, &resident), 2);
  std::fclose(f);
  return resident;
}

std::vector<double> filled(std::size_t n, std::uint32_t seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> v(n);
  for (double& a : v) a = u(gen);
  return v;
}

}  // namespace

TEST(SlotPages, ZeroingRunsReturnsTheirWholePagesAndKeepsTheRest) {
  std::vector<double> v = filled(kSlots, 1);
  const std::vector<double> before = v;
  // Two runs, neither page-aligned: the pages wholly inside go back, the edges are written.
  const cdm::SlotRuns runs = {{1000, 300'001}, {600'003, 900'000}};
  cdm::zero_slots(v, runs);
  // (Checked before the values are read: a page read maps the shared zero page.)
  EXPECT_FALSE(resident(v, 150'000));
  EXPECT_FALSE(resident(v, 750'000));
  EXPECT_TRUE(resident(v, 500'000));
  EXPECT_TRUE(resident(v, 1000));  // the page also holds slots kept
  std::size_t run = 0;
  for (std::size_t i = 0; i < kSlots; ++i) {
    while (run < runs.size() && i >= runs[run].second) ++run;
    const bool zeroed = run < runs.size() && i >= runs[run].first;
    ASSERT_EQ(bits(v[i]), zeroed ? 0u : bits(before[i])) << "slot " << i;
  }
}

TEST(SlotPages, APermutationGivesTheGathersBitsAndCommitsNoPageOfZeros) {
  // The second half holds no particle of this process: zero, its pages returned.
  std::vector<double> v = filled(kSlots, 2);
  v[7] = -0.0;  // not zero as bits: kept
  v[8] = std::numeric_limits<double>::quiet_NaN();
  v[9] = 0.0;
  cdm::zero_slots(v, {{kSlots / 2, kSlots}});
  const std::vector<double> before = v;
  // A permutation that keeps each half in place but reverses its order.
  std::vector<std::uint32_t> from(kSlots);
  for (std::size_t i = 0; i < kSlots / 2; ++i) {
    from[i] = static_cast<std::uint32_t>(kSlots / 2 - 1 - i);
    from[kSlots / 2 + i] = static_cast<std::uint32_t>(kSlots - 1 - i);
  }
  std::vector<double> tmp = filled(kSlots, 3);  // scratch holding other values
  cdm::permute_array(v, from, tmp);
  EXPECT_TRUE(resident(v, kSlots / 4));
  EXPECT_FALSE(resident(v, kSlots / 2 + kSlots / 4));
  EXPECT_FALSE(resident(v, kSlots - 1000));
  for (std::size_t i = 0; i < kSlots; ++i) ASSERT_EQ(bits(v[i]), bits(before[from[i]])) << "slot " << i;
}

TEST(SlotPages, GrownSlotsAreZeroAndUncommitted) {
  std::vector<double> v = filled(1000, 4);
  const std::vector<double> before = v;
  cdm::resize_zeroed(v, kSlots);
  EXPECT_FALSE(resident(v, kSlots / 2));
  for (std::size_t i = 0; i < 1000; ++i) ASSERT_EQ(bits(v[i]), bits(before[i]));
  for (std::size_t i = 1000; i < kSlots; ++i) ASSERT_EQ(bits(v[i]), 0u) << "slot " << i;
  std::vector<double> f = filled(kSlots, 5);
  f[3] = -0.0;
  cdm::clear_nonzero(f);
  for (double a : f) ASSERT_EQ(bits(a), 0u);
}

TEST(SlotPages, ACopyOfWhatChangedGivesTheBitsAndCommitsNoPageOfZeros) {
  // The list's build positions taken from the particles' after an insertion among
  // processes: a middle half that neither holds, grown by the new particles' slots.
  std::vector<double> from = filled(kSlots + 10000, 10);
  from[5] = -0.0;
  cdm::zero_slots(from, {{kSlots / 4, 3 * kSlots / 4}});
  std::vector<double> v = filled(kSlots, 11);
  cdm::zero_slots(v, {{kSlots / 4, 3 * kSlots / 4}});
  // The copy reads every slot, which maps the zero page (resident to mincore, not in
  // the process's resident memory): the new array's committed pages are measured as
  // the growth of the latter, against a plain copy's: about the two outer quarters'
  // 4 MiB against 8.
  // The heap's free memory is given back first (malloc_trim): the tests before this one in
  // the same process leave freed arrays resident, which glibc would hand out again (its
  // mmap threshold rises with each large free), and their pages would not count.
  malloc_trim(0);
  long before = resident_pages();
  const std::vector<double> plain(from);
  const long grew_plain = resident_pages() - before;
  std::vector<double> fresh;
  malloc_trim(0);
  before = resident_pages();
  cdm::copy_changed(fresh, from);
  const long grew = resident_pages() - before;
  EXPECT_LT(static_cast<double>(grew), 0.75 * static_cast<double>(grew_plain)) << grew << " pages against " << grew_plain;
  for (auto* to : {&v, &fresh}) {
    if (to == &v) cdm::copy_changed(v, from);
    ASSERT_EQ(to->size(), from.size());
    for (std::size_t i = 0; i < from.size(); ++i) ASSERT_EQ(bits((*to)[i]), bits(from[i])) << "slot " << i;
  }
  std::vector<double> shorter = filled(1000, 12);
  cdm::copy_changed(v, shorter);
  ASSERT_EQ(v.size(), shorter.size());
  for (std::size_t i = 0; i < shorter.size(); ++i) ASSERT_EQ(bits(v[i]), bits(shorter[i]));
}

TEST(SlotPages, ReleasedPagesGoBackWhole) {
  std::vector<double> v = filled(kSlots, 6);
  const std::vector<double> before = v;
  // Not page-aligned at either end: the pages partly outside the range stay.
  cdm::release_pages(v.data() + 100, v.data() + kSlots / 2 + 3);
  EXPECT_FALSE(resident(v, kSlots / 4));
  EXPECT_TRUE(resident(v, 99));
  EXPECT_TRUE(resident(v, kSlots / 2 + 3));
  EXPECT_EQ(bits(v[99]), bits(before[99]));
  EXPECT_EQ(bits(v[kSlots / 2 + 3]), bits(before[kSlots / 2 + 3]));
}

TEST(SlotPages, GrowingBeyondTheCapacityCommitsNoPageOfZeros) {
  // An array whose middle half a process let go, grown past its capacity: by
  // reserve_zeroed, through resize_zeroed, and through the store's add (an insertion).
  std::vector<double> v = filled(kSlots, 7);
  v[10] = -0.0;
  cdm::zero_slots(v, {{kSlots / 4, 3 * kSlots / 4}});
  const std::vector<double> before = v;
  std::vector<double> grown = v;
  cdm::resize_zeroed(grown, kSlots + 10000);
  EXPECT_FALSE(resident(grown, kSlots / 2));
  EXPECT_FALSE(resident(grown, kSlots + 5000));
  EXPECT_TRUE(resident(grown, kSlots / 8));
  for (std::size_t i = 0; i < kSlots; ++i) ASSERT_EQ(bits(grown[i]), bits(before[i])) << "slot " << i;
  for (std::size_t i = kSlots; i < kSlots + 10000; ++i) ASSERT_EQ(bits(grown[i]), 0u);

  cdm::ParticleStore p;
  for (std::size_t i = 0; i < kSlots; ++i) p.add({0.0, 0.0, 0.0}, {before[i], 1.0, 1.0}, 1e-3, 2500.0, 0);
  ASSERT_EQ(p.vx.capacity(), p.vx.size());  // the next add reallocates
  cdm::zero_slots(p.vx, {{kSlots / 4, 3 * kSlots / 4}});
  p.add({0.0, 0.0, 0.0}, {2.0, 1.0, 1.0}, 1e-3, 2500.0, 0);
  EXPECT_GT(p.vx.capacity(), kSlots);
  EXPECT_FALSE(resident(p.vx, kSlots / 2));
  EXPECT_TRUE(resident(p.vy, kSlots / 2));
  for (std::size_t i = 0; i < kSlots; ++i) ASSERT_EQ(bits(p.vx[i]), bits(before[i])) << "slot " << i;
  EXPECT_EQ(p.vx[kSlots], 2.0);
}

TEST(SlotPages, RunsThatTouchAreJoined) {
  // A migration's particles sent, slot by slot from each destination in turn: only runs
  // joined give whole pages back.
  const cdm::SlotRuns runs = cdm::merged({{7, 8}, {0, 2}, {2, 3}, {5, 6}, {6, 7}, {1, 2}, {20, 30}, {25, 26}});
  EXPECT_EQ(runs, (cdm::SlotRuns{{0, 3}, {5, 8}, {20, 30}}));
  EXPECT_TRUE(cdm::merged({}).empty());
  std::vector<double> v = filled(kSlots, 8);
  cdm::SlotRuns single;
  for (std::size_t i = kSlots / 2; i > kSlots / 4; --i) single.push_back({i - 1, i});
  cdm::zero_slots(v, cdm::merged(single));
  EXPECT_FALSE(resident(v, 3 * kSlots / 8));
  EXPECT_EQ(v[kSlots / 4], 0.0);
  EXPECT_NE(v[kSlots / 2], 0.0);
}

TEST(SlotPages, TheStoresPagesOfZerosAreReturned) {
  // A bed at rest read into the store: its velocities (and forces) are zero, and their
  // pages go back as the scene is read; the positions' and masses' stay.
  cdm::ParticleStore p;
  for (std::size_t i = 0; i < kSlots; ++i)
    p.add({1e-3 * static_cast<double>(i), 0.0, 0.0}, {i >= kSlots / 2 ? 0.0 : 1.0, 0.0, 0.0}, 1e-3, 2500.0, 0);
  p.release_zero_pages(0, kSlots);
  EXPECT_TRUE(resident(p.x, kSlots / 2));
  EXPECT_TRUE(resident(p.mass, kSlots / 2));
  EXPECT_TRUE(resident(p.vx, kSlots / 4));     // not zero throughout [0, kSlots)
  EXPECT_FALSE(resident(p.vy, kSlots / 2));
  EXPECT_FALSE(resident(p.fx, kSlots / 2));
  p.release_zero_pages(kSlots / 2, kSlots);  // vx is zero there
  EXPECT_FALSE(resident(p.vx, 3 * kSlots / 4));
  EXPECT_TRUE(resident(p.vx, kSlots / 4));
  for (std::size_t i = 0; i < kSlots; ++i) ASSERT_EQ(p.vx[i], i >= kSlots / 2 ? 0.0 : 1.0);
  EXPECT_EQ(p.vy[kSlots / 2], 0.0);
}

TEST(SlotPages, AnArrayReadThroughASlotWindowKeepsTheWindowAndCommitsNoOtherPage) {
  // A checkpoint's per-particle array, and one of another length, read by a process
  // that keeps slots [first, last) of kSlots (a restart among MPI processes).
  const std::vector<double> saved = filled(kSlots, 3), other = filled(1000, 4);
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  cdm::OutArchive out(f);
  out.put(saved);
  out.put(other);
  ASSERT_EQ(std::fflush(f), 0);
  ASSERT_FALSE(out.failed());
  const std::size_t first = 300'001, last = 650'000;
  const cdm::BlockSums blocks{0, out.size(), out.block_sums()};
  // Read from the file, as a restart streams it.
  auto reader = [&] {
    auto in = std::make_unique<cdm::InArchive>(f, blocks, 0, out.size());
    in->keep_slots(kSlots, first, last);
    return in;
  };
  // Into an array that held values everywhere (the scene's), and into an empty one.
  std::vector<double> held = filled(kSlots, 5), fresh;
  cdm::get_slots(*reader(), held);
  const auto in = reader();
  cdm::get_slots(*in, fresh);
  for (const std::vector<double>* v : {&held, &fresh}) {
    ASSERT_EQ(v->size(), kSlots);
    EXPECT_FALSE(resident(*v, 100'000));
    EXPECT_FALSE(resident(*v, 900'000));
    EXPECT_TRUE(resident(*v, 400'000));
    for (std::size_t i = 0; i < kSlots; ++i)
      ASSERT_EQ(bits((*v)[i]), i >= first && i < last ? bits(saved[i]) : 0u) << "slot " << i;
  }
  // An array of another length is read whole, and the archive ends where it should.
  std::vector<double> rest;
  cdm::get_slots(*in, rest);
  EXPECT_EQ(rest, other);
  EXPECT_TRUE(in->done());
  std::fclose(f);
}
