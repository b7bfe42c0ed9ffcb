// The contact module's partner prefetch (ContactModule::Prefetch) touches how the pair
// loop fetches memory, never what it computes: forced on or off, a run is the same to
// the bit, on one thread or two. Run in the sanitizer build, the forced prefetch also
// checks that it never reads past a slab's or the list's end. The policy's inputs (the
// particles' bytes, the machine's largest cache) are tested here too.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <vector>

#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/platform.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"
#include "support.hpp"

namespace {

// 16 x 16 x 20 = 5120 of the box scene's spheres (above the parallel threshold), thrown
// about at up to 0.5 m/s between a floor and two walls: hundreds of contacts within 300
// steps.
cdm::SceneSpec bed() {
  return cdm::load_scene_from_string(cdm_test::box_scene, "box.toml",
                                     {cdm::parse_override("lattices[0].count=[16, 16, 20]"),
                                      cdm::parse_override("walls[2].point=[0.0176, 0.0, 0.0]")});
}

struct State {
  cdm::ParticleStore particles;
  std::size_t contacts = 0, builds = 0;
  bool prefetched = false;
  std::size_t largest_slab = 0;  // listed pairs of the slab with the most
};

State run(cdm::ContactModule::Prefetch mode, int threads, int steps) {
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  cdm::Simulation sim(bed());
  sim.contact()->set_prefetch(mode);
  State s;
  for (int k = 0; k < steps; ++k) {
    sim.step();
    s.contacts = std::max(s.contacts, sim.contact()->active_contacts());
  }
  s.particles = sim.particles();
  s.builds = sim.contact()->list().builds();
  s.prefetched = sim.contact()->prefetched();
  const std::vector<std::uint32_t>& start = sim.contact()->list().slab_start();
  for (std::size_t q = 0; q + 1 < start.size(); ++q)
    s.largest_slab = std::max<std::size_t>(s.largest_slab, start[q + 1] - start[q]);
  omp_set_num_threads(before);
  return s;
}

}  // namespace

TEST(ContactPrefetch, ChangesNothingOnOneThreadOrTwo) {
  using Prefetch = cdm::ContactModule::Prefetch;
  for (int threads : {1, 2}) {
    const State off = run(Prefetch::off, threads, 300);
    const State on = run(Prefetch::on, threads, 300);
    EXPECT_FALSE(off.prefetched);
    EXPECT_TRUE(on.prefetched);
    // The prefetch runs 128 pairs ahead within a slab: the test needs slabs longer than
    // that, contacts (their loads and stores between the prefetches) and rebuilds.
    EXPECT_GT(on.largest_slab, 512u);
    EXPECT_GT(on.contacts, 300u);
    EXPECT_GE(on.builds, 3u);
    EXPECT_EQ(on.builds, off.builds);
    EXPECT_TRUE(cdm_test::same_motion(on.particles, off.particles)) << threads << " thread(s)";
  }
}

TEST(ContactPrefetch, AutomaticPrefetchesOnlyBeyondTheLargestCache) {
  // 5120 particles hold ~0.9 MB: beyond no cache cdm's prefetch is meant for, unless the
  // machine's largest cache is smaller than that.
  cdm::Simulation sim(bed());
  sim.step();
  EXPECT_EQ(sim.contact()->prefetched(), sim.particles().bytes() > cdm::last_level_cache_bytes());
  sim.contact()->set_prefetch(cdm::ContactModule::Prefetch::on);
  sim.step();
  EXPECT_TRUE(sim.contact()->prefetched());
  sim.contact()->set_prefetch(cdm::ContactModule::Prefetch::automatic);
  sim.step();
  EXPECT_EQ(sim.contact()->prefetched(), sim.particles().bytes() > cdm::last_level_cache_bytes());
}

TEST(Platform, ParsesCacheSizesAsSysfsWritesThem) {
  EXPECT_EQ(cdm::parse_cache_size("32768K"), std::size_t{32} << 20);
  EXPECT_EQ(cdm::parse_cache_size("48K\n"), std::size_t{48} << 10);
  EXPECT_EQ(cdm::parse_cache_size("1M"), std::size_t{1} << 20);
  EXPECT_EQ(cdm::parse_cache_size("2G"), std::size_t{2} << 30);
  EXPECT_EQ(cdm::parse_cache_size("512"), 512u);
  for (const char* bad : {"", "K", "32768KB", "12Q", " 1M", "1.5M"}) EXPECT_EQ(cdm::parse_cache_size(bad), 0u) << bad;
}

TEST(Platform, LargestCacheIsAtLeastACacheLine) {
  // Read from sysfs where there is one, else the fallback: either way a size, and the
  // same on every call (read once).
  const std::size_t llc = cdm::last_level_cache_bytes();
  EXPECT_GE(llc, 64u);
  EXPECT_EQ(cdm::last_level_cache_bytes(), llc);
}

TEST(ParticleStore, BytesCountEveryArrayTheSceneCarries) {
  cdm::ParticleStore p;
  const std::size_t n = 10;
  for (std::size_t i = 0; i < n; ++i) p.add({0.001 * double(i), 0.0, 0.0}, {}, 0.5e-3, 2500.0, 0);
  // x, v, f (9), radius, mass, 1/m, and the material index.
  EXPECT_EQ(p.bytes(), n * (12 * sizeof(double) + sizeof(std::uint8_t)));
  p.enable_rotation();  // ω, torque, 1/I
  EXPECT_EQ(p.bytes(), n * (19 * sizeof(double) + sizeof(std::uint8_t)));
  p.enable_drag_relaxation();  // K and the gas velocity
  EXPECT_EQ(p.bytes(), n * (23 * sizeof(double) + sizeof(std::uint8_t)));
  p.enable_two_way();  // drag force and impulse
  EXPECT_EQ(p.bytes(), n * (29 * sizeof(double) + sizeof(std::uint8_t)));
  std::vector<std::uint32_t> from(n);
  for (std::size_t i = 0; i < n; ++i) from[i] = static_cast<std::uint32_t>(n - 1 - i);
  p.permute(from);  // the identities
  EXPECT_EQ(p.bytes(), n * (29 * sizeof(double) + sizeof(std::uint8_t) + sizeof(std::uint32_t)));
}
