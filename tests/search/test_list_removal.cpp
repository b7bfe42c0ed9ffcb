// Particles removed from a built Verlet list (an outlet): the list is kept, not built
// again, and it is the list that listing the pairs again from the build positions gives
// (as a restart does), in the same order, although the removals moved the bounding box
// that a build would cut the slabs from.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <utility>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/contact/verlet_list.hpp"

namespace {

// A bed four times longer along x than across, so the slabs are cut along x.
cdm::ParticleStore long_bed(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  cdm::ParticleStore p;
  for (std::size_t i = 0; i < n; ++i)
    p.add({0.04 * u(rng), 0.01 * u(rng), 0.01 * u(rng)}, {}, 4e-4 + 2e-4 * u(rng), 2500.0, 0);
  return p;
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs_of(const cdm::VerletList& l) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  for (std::size_t k = 0; k < l.size(); ++k) out.emplace_back(l.pair_i()[k], l.pair_j()[k]);
  return out;
}

std::vector<char> saved(const cdm::VerletList& l) {
  char* buf = nullptr;
  std::size_t size = 0;
  std::FILE* f = open_memstream(&buf, &size);
  cdm::OutArchive a(f);
  l.save_state(a);
  std::fclose(f);
  std::vector<char> out(buf, buf + size);
  std::free(buf);
  return out;
}

}  // namespace

TEST(ListAfterRemoval, KeptAndEqualToTheListListedAgainFromTheBuildPositions) {
  const double skin = 2e-4;
  cdm::ParticleStore p = long_bed(4000, 3);
  cdm::VerletList list({}, false, skin);
  list.update(p);
  ASSERT_TRUE(list.built());
  ASSERT_GT(list.slab_count(), 8u);
  const std::uint64_t builds = list.builds();
  // The particles move a little (less than half the skin), then the three farthest along
  // x and every 37th leave, in slot order.
  for (std::size_t i = 0; i < p.size(); ++i) p.x[i] += 1e-5 * static_cast<double>(i % 7);
  std::vector<std::uint32_t> by_x(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) by_x[i] = static_cast<std::uint32_t>(i);
  std::sort(by_x.begin(), by_x.end(), [&](std::uint32_t a, std::uint32_t b) { return p.x[a] > p.x[b]; });
  std::vector<bool> gone(p.size(), false);
  for (int k = 0; k < 3; ++k) gone[by_x[k]] = true;
  for (std::size_t i = 0; i < p.size(); i += 37) gone[i] = true;
  std::vector<std::uint32_t> from;
  for (std::size_t i = 0; i < p.size(); ++i)
    if (!gone[i]) from.push_back(static_cast<std::uint32_t>(i));
  p.keep(from);
  list.remap(from, p);

  // Kept: no build at the next update.
  EXPECT_TRUE(list.built());
  EXPECT_FALSE(list.rebuild_due(p));
  list.update(p);
  EXPECT_EQ(list.builds(), builds);
  const auto kept = pairs_of(list);
  const std::vector<std::uint32_t> kept_slabs = list.slab_start();

  // A restart lists the pairs again from the build positions: the same pairs in the
  // same slabs and order.
  const std::vector<char> bytes = saved(list);
  cdm::InArchive in(bytes.data(), bytes.size());
  cdm::VerletList loaded({}, false, skin);
  loaded.load_state(in, true, builds);
  loaded.update(p);
  EXPECT_EQ(loaded.builds(), builds);
  EXPECT_EQ(pairs_of(loaded), kept);
  EXPECT_EQ(loaded.slab_start(), kept_slabs);

  // A build at the same positions finds the same pairs, but cuts the slabs from the
  // bounding box the removals shrank: another order (and, the cells being cut from it
  // too, some pairs listed the other way round). So the kept cut is what makes the two
  // lists above agree.
  cdm::ParticleStore at_build = p;
  at_build.x.assign(list.build_positions(0), list.build_positions(0) + p.size());
  at_build.y.assign(list.build_positions(1), list.build_positions(1) + p.size());
  at_build.z.assign(list.build_positions(2), list.build_positions(2) + p.size());
  cdm::VerletList fresh({}, false, skin);
  fresh.update(at_build);
  auto a = pairs_of(fresh), b = kept;
  EXPECT_NE(a, b);
  for (auto* v : {&a, &b})
    for (auto& [i, j] : *v)
      if (i > j) std::swap(i, j);
  std::sort(a.begin(), a.end());
  std::sort(b.begin(), b.end());
  EXPECT_EQ(a, b);
}

TEST(ListAfterRemoval, BuiltAgainWhenParticlesAreAdded) {
  cdm::ParticleStore p = long_bed(500, 5);
  cdm::VerletList list({}, false, 2e-4);
  list.update(p);
  const std::uint64_t builds = list.builds();
  std::vector<std::uint32_t> from;
  for (std::size_t i = 1; i < p.size(); ++i) from.push_back(static_cast<std::uint32_t>(i));
  p.keep(from);
  p.add({0.02, 0.005, 0.005}, {}, 5e-4, 2500.0, 0);
  from.assign(p.size(), cdm::new_particle);
  for (std::size_t i = 0; i + 1 < p.size(); ++i) from[i] = static_cast<std::uint32_t>(i);
  list.remap(from, p);
  EXPECT_FALSE(list.built());
  list.update(p);
  EXPECT_EQ(list.builds(), builds + 1);
}
