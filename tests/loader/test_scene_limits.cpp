// Edge values a careless user types: each is refused by the loader with a message naming
// the key and value at fault, and cheaply (before reading or placing anything large);
// the values that are merely extreme but meaningful load.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

#include "cdm/solver/scene_loader.hpp"

namespace {

const std::string free_fall = std::string(CDM_SOURCE_DIR) + "/verification/cases/free_fall/scene.toml";

// Expects @p load to throw a SceneError whose message contains every fragment.
void expect_error(const std::function<void()>& load, const std::vector<std::string>& fragments) {
  try {
    load();
    FAIL() << "accepted; expected an error with '" << fragments.front() << "'";
  } catch (const cdm::SceneError& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "message lacks '" << f << "': " << msg;
  }
}

// The free-fall case with @p overrides.
void expect_refused(const std::vector<cdm::SceneOverride>& overrides, const std::vector<std::string>& fragments) {
  expect_error([&] { cdm::load_scene(free_fall, overrides); }, fragments);
}

// The free-fall case with a ball-ball contact and @p extra appended (more particles).
std::string free_fall_with(const std::string& extra) {
  return cdm::read_scene_file(free_fall) + "\n[[contacts]]\npair = [\"ball\", \"ball\"]\nkn = 5.0e7\nen = 0.9\n" + extra;
}

void expect_text_refused(const std::string& extra, const std::vector<std::string>& fragments) {
  expect_error([&] { cdm::load_scene_from_string(free_fall_with(extra), "bad.toml"); }, fragments);
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

TEST(SceneLimits, StepCountAboveTheCeilingIsRefusedWithTheCount) {
  expect_refused({{"integrator.end_time", "1e17"}}, {"integrator.end_time", "1e+12 steps", "1.07778e+20 steps"});
  expect_refused({{"contacts[0].kn", "1e30"}}, {"integrator.end_time", "\"auto\"", "7.62105e+13 steps"});
}

TEST(SceneLimits, ParticleMassThatUnderflowsOrOverflowsIsRefused) {
  expect_refused({{"particles[0].radius", "1e-300"}}, {"particles[0].radius", "density", "underflows"});
  expect_refused({{"particles[0].radius", "1e300"}}, {"particles[0].radius", "density", "overflows"});
}

TEST(SceneLimits, SubnormalTimeStepIsRefused) {
  expect_refused({{"integrator.dt", "1e-320"}}, {"integrator.dt", "normal floating-point"});
}

TEST(SceneLimits, AbsurdDensityIsNamedNotTheEndTime) {
  // The automatic step then exceeds the run: the message says where dt came from.
  expect_refused({{"materials[0].density", "1e300"}}, {"integrator.dt", "collision time", "densities"});
}

TEST(SceneLimits, DateIsShownAsADate) {
  expect_refused({{"particles[0].position", "1979-05-27"}}, {"particles[0].position", "1979-05-27", "expected an array"});
}

TEST(SceneLimits, WallNormalsOfExtremeLengthAreNormalised) {
  for (const char* n : {"[0, 1e200, 0]", "[0, 1e-320, 0]", "[0, 1.7e308, 1.7e308]"}) {
    const cdm::SceneSpec spec = cdm::load_scene(free_fall, {{"walls[0].normal", n}});
    const cdm::Vec3 w = spec.walls.at(0).normal;
    EXPECT_EQ(w.x, 0.0) << n;
    EXPECT_NEAR(std::hypot(w.y, w.z), 1.0, 1e-15) << n;
  }
  expect_refused({{"walls[0].normal", "[0, 0, 0]"}}, {"walls[0].normal", "non-zero vector"});
}

TEST(SceneLimits, ScenePathMustBeASmallRegularFile) {
  for (const auto& [path, fragment] : std::vector<std::pair<std::string, std::string>>{
           {CDM_SOURCE_DIR, "a directory"}, {"/dev/zero", "not a regular file"}}) {
    const auto t0 = std::chrono::steady_clock::now();
    expect_error([&] { cdm::load_scene(path); }, {path + ": is ", fragment, "expected a scene file"});
    EXPECT_LT(seconds_since(t0), 1.0) << path;
  }
  // A file above the limit is refused by its size, before it is read (a sparse file).
  const std::string big = (std::filesystem::temp_directory_path() / "cdm_test_big_scene.toml").string();
  { std::ofstream(big).put('\n'); }
  std::filesystem::resize_file(big, cdm::max_scene_file_bytes + 1);
  expect_error([&] { cdm::read_scene_file(big); }, {std::to_string(cdm::max_scene_file_bytes + 1) + " bytes", "at most"});
  std::filesystem::remove(big);
}

const std::string big_lattice = R"(
[[lattices]]
material = "ball"
radius = 1.0
origin = [-1000.0, 100.0, -1000.0]
spacing = [3.0, 3.0, 3.0]
count = [500, 500, 101]
)";

TEST(SceneLimits, ScalarsAndTheParticleTotalAreCheckedBeforePlacing) {
  // 2.5e7 particles would take seconds and gigabytes to place: refused at once.
  auto t0 = std::chrono::steady_clock::now();
  std::string text = free_fall_with(big_lattice);
  text.replace(text.find("end_time = 0.5"), 14, "end_time = -1.0");
  expect_error([&] { cdm::load_scene_from_string(text, "bad.toml"); }, {"integrator.end_time", "-1"});
  EXPECT_LT(seconds_since(t0), 2.0);
  t0 = std::chrono::steady_clock::now();
  expect_text_refused(big_lattice + big_lattice, {"lattices[1].count", "50000000", "50500001"});
  EXPECT_LT(seconds_since(t0), 2.0);
}

TEST(SceneLimits, ShellOverlapNamesTheParticles) {
  expect_text_refused(R"(
[[shells]]
material = "ball"
radius = 1.0
center = [0.0, 100.0, 0.0]
shell_radius = 2.0
count = 20
dimension = 2
)",
                      {"shells[0] (particle ", " of 20).position", "overlaps"});
}

TEST(SceneLimits, CoincidentCentresAreRefusedEvenWhenOverlapIsAllowed) {
  expect_text_refused(R"(
[[particles]]
material = "ball"
radius = 10.0
position = [0.0, 50.0, 0.0]

[checks]
allow_initial_overlap = true
)",
                      {"particles[1].position", "particles[0]", "distinct centres"});
}

TEST(SceneLimits, AParticlePileIsRefusedWithoutListingItsPairs) {
  // A lattice whose spacing is a twentieth of the diameter: ~1.4e6 overlapping pairs.
  // Allowed overlaps are listed only up to 32 per particle on average, then refused.
  expect_text_refused(R"(
[[lattices]]
material = "ball"
radius = 1.0
origin = [0.0, 50.0, 0.0]
spacing = [0.1, 0.1, 0.1]
count = [20, 20, 20]

[checks]
allow_initial_overlap = true
)",
                      {"8001 particles overlap in more than 256032 pairs", "expected a packing", "lattice spacing"});
}

TEST(SceneLimits, RandomBlocksClearEveryEarlierParticle) {
  // Two blocks in one box, the second of larger particles, beside a listed particle:
  // each new centre clears every earlier particle, so nothing overlaps.
  std::string blocks;
  for (const char* r : {"2.0", "3.0"})
    blocks += std::string("\n[[random_particles]]\nmaterial = \"ball\"\nradius = ") + r +
              "\nlower = [-50.0, 20.0, -50.0]\nupper = [50.0, 120.0, 50.0]\ncount = 300\n";
  const cdm::SceneSpec spec = cdm::load_scene_from_string(free_fall_with(blocks), "good.toml");
  ASSERT_EQ(spec.particles.size(), 601u);
  for (std::size_t i = 0; i < spec.particles.size(); ++i)
    for (std::size_t j = 0; j < i; ++j) {
      const cdm::Vec3 d = spec.particles[i].position - spec.particles[j].position;
      const double rr = spec.particles[i].radius + spec.particles[j].radius;
      ASSERT_GE(dot(d, d), rr * rr) << i << " overlaps " << j;
    }
}

}  // namespace
