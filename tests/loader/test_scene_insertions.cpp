// [[insertions]], [[outlets]] and size distributions at load: good input is converted
// to SI, bad input refused with the file, the key, the value and what was expected.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cdm/solver/scene_loader.hpp"
#include "scene_text.hpp"
#include "support.hpp"

namespace {

const std::string base = cdm_test::scene_head() + cdm_test::floor_wall() + R"(
[[insertions]]
material = "glass"
lower = [0.0, 0.0, 0.05]
upper = [0.02, 0.02, 0.06]
count_rate = 1000.0
count = 50
radius = 0.001

[[outlets]]
name = "drain"
type = "plane"
point = [0.0, 0.0, -0.01]
normal = [0.0, 0.0, -1.0]

[integrator]
scheme = "velocity_verlet"
dt = "auto"
end_time = 0.1
)";

using cdm::test::replace;

using cdm::test::expect_refused;

const std::string size_line = "radius = 0.001";

TEST(SceneInsertions, SceneWithoutParticlesLoads) {
  const cdm::SceneSpec s = cdm::load_scene_from_string(base, "good.toml");
  EXPECT_TRUE(s.particles.empty());
  ASSERT_EQ(s.insertions.size(), 1u);
  EXPECT_EQ(s.insertions[0].rate, 1000.0);
  EXPECT_EQ(s.insertions[0].total, 50.0);
  EXPECT_FALSE(s.insertions[0].rate_by_mass);
  EXPECT_NEAR(s.verlet_skin, 0.1 * 0.002, 1e-15);  // from the inserted diameter
  EXPECT_GT(s.t_col_min, 0.0);                     // dt from the inserted particles' pairs
  ASSERT_EQ(s.outlets.size(), 1u);
  EXPECT_EQ(s.outlets[0].normal.z, -1.0);
  EXPECT_TRUE(s.outlets[0].removes({0.0, 0.0, -0.02}));
  EXPECT_FALSE(s.outlets[0].removes({0.0, 0.0, 0.0}));
}

TEST(SceneInsertions, CgsMassRateAndTotalInSi) {
  std::string t = replace(base, "units = \"SI\"", "units = \"cgs\"");
  t = replace(t, "count_rate = 1000.0\ncount = 50", "mass_rate = 20.0\nmass = 5.0");
  const cdm::SceneSpec s = cdm::load_scene_from_string(t, "good.toml");
  EXPECT_TRUE(s.insertions[0].rate_by_mass);
  EXPECT_NEAR(s.insertions[0].rate, 0.02, 1e-15);   // g/s → kg/s
  EXPECT_NEAR(s.insertions[0].total, 0.005, 1e-15);  // g → kg
}

TEST(SceneInsertions, BadRatesAndTotals) {
  expect_refused(replace(base, "count_rate = 1000.0", "count_rate = 0.0"), {"insertions[0].count_rate", "> 0"});
  expect_refused(replace(base, "count_rate = 1000.0", "count_rate = -5.0"), {"insertions[0].count_rate", "> 0"});
  expect_refused(replace(base, "count_rate = 1000.0", ""), {"insertions[0].count_rate", "missing", "mass_rate"});
  expect_refused(replace(base, "count_rate = 1000.0", "count_rate = 1000.0\nmass_rate = 0.1"),
                 {"insertions[0].mass_rate", "not both"});
  expect_refused(replace(base, "count = 50", "count = 50\nmass = 0.1"), {"insertions[0].mass", "not both"});
  expect_refused(replace(base, "count = 50", "count = 0"), {"insertions[0].count", "integer >= 1"});
  expect_refused(replace(base, "count = 50", "count_rate2 = 1"), {"insertions[0].count_rate2", "not a known key"});
  expect_refused(replace(base, "count = 50", "end = 0.0"), {"insertions[0].end"});
  expect_refused(replace(base, "count = 50", "start = 0.2"), {"insertions[0].start", "before integrator.end_time"});
  expect_refused(replace(base, "count = 50", "start = 0.05\nend = 0.04"), {"insertions[0].end", "after"});
  expect_refused(replace(base, "count = 50", "interval = -1.0"), {"insertions[0].interval", ">= 0"});
  // No total: inserting until the end of the run.
  EXPECT_TRUE(std::isinf(cdm::load_scene_from_string(replace(base, "count = 50", ""), "good.toml").insertions[0].total));
}

TEST(SceneInsertions, BadRegions) {
  expect_refused(replace(base, "upper = [0.02, 0.02, 0.06]", "upper = [0.02, 0.02, 0.04]"),
                 {"insertions[0].upper", "at or above"});
  expect_refused(replace(base, "lower = [0.0, 0.0, 0.05]\nupper = [0.02, 0.02, 0.06]",
                         "lower = [0.0, 0.0, -0.06]\nupper = [0.02, 0.02, -0.05]"),
                 {"insertions[0].lower", "wall 'floor'", "outside"});
  // With a gas the box lies inside the gas domain.
  const std::string gas = R"(
[gas]
lower = [0.0, 0.0, 0.0]
upper = [0.02, 0.02, 0.055]
cells = [2, 2, 5]
density = 1.2
viscosity = 1.8e-5
[gas.field]
type = "uniform"
velocity = [0.0, 0.0, 0.0]
[gas.boundaries]
x_lower = "no_slip"
x_upper = "no_slip"
y_lower = "no_slip"
y_upper = "no_slip"
z_lower = "no_slip"
z_upper = "no_slip"
)";
  std::string t = replace(base, "normal_contact = \"linear_spring_dashpot\"", "normal_contact = \"linear_spring_dashpot\"\ngas = \"prescribed\"");
  expect_refused(t + gas, {"insertions[0].upper", "inside the gas domain"});
  // A periodic axis: inside the period.
  expect_refused(base + "[periodic]\nx = [0.0, 0.01]\n", {"insertions[0].upper", "periodic"});
}

TEST(SceneInsertions, BadMaterialsAndModules) {
  std::string fixed = replace(base, "name = \"glass\"\ndensity = 2500.0", "name = \"glass\"\ndensity = 2500.0\nfixed = true");
  expect_refused(fixed, {"insertions[0].material", "not fixed"});
}

TEST(SceneInsertions, SizeTables) {
  auto with = [&](const std::string& table) { return replace(base, size_line, "size = " + table); };
  // Accepted, in SI, with the defaults.
  {
    const auto s = cdm::load_scene_from_string(with("{ distribution = \"normal\", mean = 0.001, std = 0.0001 }"), "good.toml");
    const auto& d = s.insertions[0].size;
    EXPECT_EQ(d.kind, cdm::SizeKind::normal);
    EXPECT_NEAR(d.min, 0.0007, 1e-15);
    EXPECT_NEAR(d.max, 0.0013, 1e-15);
    EXPECT_NEAR(s.verlet_skin, 0.1 * 0.0026, 1e-15);
  }
  {
    const auto s = cdm::load_scene_from_string(
        with("{ distribution = \"lognormal\", basis = \"mass\", median = 0.001, sigma = 0.2 }"), "good.toml");
    const auto& d = s.insertions[0].size;
    EXPECT_NEAR(d.min, 0.001 * std::exp(-0.12) * std::exp(-0.6), 1e-15);
  }
  expect_refused(replace(base, "count = 50", "count = 50\nsize = { distribution = \"uniform\", min = 0.001, max = 0.002 }"),
                 {"insertions[0].radius", "no radius"});
  expect_refused(with("{ distribution = \"discrete\", radii = [0.001, 0.002], fractions = [0.5, 0.4] }"),
                 {"insertions[0].size.fractions", "summing to 1", "0.9"});
  expect_refused(with("{ distribution = \"discrete\", radii = [0.001, 0.002], fractions = [1.0] }"),
                 {"insertions[0].size.fractions", "one fraction per radius"});
  expect_refused(with("{ distribution = \"discrete\", radii = [0.001, -0.002], fractions = [0.5, 0.5] }"),
                 {"insertions[0].size.radii", "> 0"});
  expect_refused(with("{ distribution = \"uniform\", min = 0.002, max = 0.001 }"),
                 {"insertions[0].size.max", "above", "min"});
  expect_refused(with("{ distribution = \"uniform\", max = 0.001 }"), {"insertions[0].size.min", "missing"});
  expect_refused(with("{ distribution = \"normal\", mean = 0.001, std = 0.0005 }"),
                 {"insertions[0].size.min", "smallest radius > 0"});
  expect_refused(with("{ distribution = \"normal\", mean = 0.001, std = 0.0001, min = 0.0015, max = 0.002 }"),
                 {"insertions[0].size.min", "0.1 %"});
  // By mass, a uniform from 1 µm to 1 cm keeps one draw in about 20,000: refused.
  expect_refused(with("{ distribution = \"uniform\", basis = \"mass\", min = 0.000001, max = 0.01 }"),
                 {"insertions[0].size.min", "0.1 %"});
  expect_refused(with("{ distribution = \"lognormal\", median = 0.001, sigma = 0.2, mean = 0.001 }"),
                 {"insertions[0].size.mean", "not used"});
  expect_refused(with("{ distribution = \"gamma\" }"), {"insertions[0].size.distribution", "\"lognormal\""});
  expect_refused(with("{ distribution = \"uniform\", min = 0.001, max = 0.002, basis = \"volume\" }"),
                 {"insertions[0].size.basis", "\"mass\""});
  expect_refused(with("{ distribution = \"uniform\", min = 0.001, max = 0.002, shape = 1 }"),
                 {"insertions[0].size.shape", "not a known key"});
  expect_refused(with("{ min = 0.001, max = 0.002 }"), {"insertions[0].size.distribution", "missing"});
}

TEST(SceneInsertions, BadOutlets) {
  expect_refused(replace(base, "type = \"plane\"", "type = \"sphere\""), {"outlets[0].type", "\"box\""});
  expect_refused(replace(base, "normal = [0.0, 0.0, -1.0]", "normal = [0.0, 0.0, 0.0]"), {"outlets[0].normal", "non-zero"});
  expect_refused(replace(base, "name = \"drain\"", "name = \"a b\""), {"outlets[0].name", "letters"});
  expect_refused(replace(base, "normal = [0.0, 0.0, -1.0]", "normal = [0.0, 0.0, -1.0]\nlower = [0.0, 0.0, 0.0]"),
                 {"outlets[0].lower", "not used"});
  expect_refused(base + "[[outlets]]\nname = \"drain\"\ntype = \"box\"\nlower = [0, 0, 0]\nupper = [1, 1, 1]\n",
                 {"outlets[1].name", "no other outlet"});
  expect_refused(base + "[[outlets]]\nname = \"pit\"\ntype = \"box\"\nlower = [0, 0, 0]\nupper = [1, -1, 1]\n",
                 {"outlets[1].upper", "at or above"});
}

// Two [[random_particles]] blocks share a periodic box: each places against the other
// and through the faces (the loader used to miss the images and refuse the overlap).
TEST(SceneInsertions, RandomBlocksShareAPeriodicBox) {
  std::string t = replace(base, "[[insertions]]", "[[random_particles]]\nmaterial = \"glass\"\nlower = [0.0, 0.0, 0.01]\n"
                                                  "upper = [0.0199, 0.0199, 0.02]\ncount = 200\nradius = 0.001\n\n"
                                                  "[[random_particles]]\nmaterial = \"glass\"\nlower = [0.0, 0.0, 0.01]\n"
                                                  "upper = [0.0199, 0.0199, 0.02]\ncount = 100\nseed = 2\n"
                                                  "size = { distribution = \"uniform\", min = 0.0008, max = 0.0012 }\n\n"
                                                  "[[insertions]]");
  t += "[periodic]\nx = [0.0, 0.02]\ny = [0.0, 0.0205]\n";
  const auto s = cdm::load_scene_from_string(t, "good.toml");
  ASSERT_EQ(s.particles.size(), 300u);
  for (std::size_t i = 200; i < 300; ++i) {
    EXPECT_GE(s.particles[i].radius, 0.0008);
    EXPECT_LE(s.particles[i].radius, 0.0012);
  }
}

// A lattice with a size table: radii drawn per site within the cut-offs; sites closer
// than the largest diameter refused.
TEST(SceneInsertions, LatticeWithSizes) {
  const std::string lattice = "[[lattices]]\nmaterial = \"glass\"\norigin = [0.002, 0.002, 0.002]\n"
                              "spacing = [0.003, 0.003, 0.003]\ncount = [4, 4, 2]\n"
                              "size = { distribution = \"uniform\", min = 0.0009, max = 0.0014 }\n\n[[insertions]]";
  const auto s = cdm::load_scene_from_string(replace(base, "[[insertions]]", lattice), "good.toml");
  ASSERT_EQ(s.particles.size(), 32u);
  bool differ = false;
  for (const auto& p : s.particles) {
    EXPECT_GE(p.radius, 0.0009);
    EXPECT_LE(p.radius, 0.0014);
    differ = differ || p.radius != s.particles[0].radius;
  }
  EXPECT_TRUE(differ);
  expect_refused(replace(base, "[[insertions]]", replace(lattice, "spacing = [0.003, 0.003, 0.003]", "spacing = [0.003, 0.0025, 0.003]")),
                 {"lattices[0].spacing", "largest diameter"});
}

// A cylinder region: centres drawn uniformly in its volume (random_particles and
// insertions alike), its bounding box checked like a box; the two region forms exclude
// each other, and a bad cylinder is refused naming its key.
TEST(SceneInsertions, CylinderRegions) {
  const std::string cyl = "cylinder = { point = [0.01, 0.01, 0.01], axis = [0.0, 0.0, 2.0], radius = 0.006, length = 0.03 }";
  const std::string block = "[[random_particles]]\nmaterial = \"glass\"\n" + cyl + "\ncount = 400\nradius = 0.0005\n\n[[insertions]]";
  const auto s = cdm::load_scene_from_string(replace(base, "[[insertions]]", block), "good.toml");
  ASSERT_EQ(s.particles.size(), 400u);
  double rho2 = 0.0, h = 0.0, cx = 0.0, cy = 0.0;
  for (const auto& p : s.particles) {
    const double dx = p.position.x - 0.01, dy = p.position.y - 0.01, dz = p.position.z - 0.01;
    EXPECT_LE(dx * dx + dy * dy, 0.006 * 0.006 * (1 + 1e-12));
    EXPECT_GE(dz, 0.0);
    EXPECT_LE(dz, 0.03);
    rho2 += (dx * dx + dy * dy) / (0.006 * 0.006);
    h += dz / 0.03;
    cx += dx / 0.006;
    cy += dy / 0.006;
  }
  // Uniform in volume: <rho^2>/R^2 = 1/2, <h>/L = 1/2, the centroid on the axis (400
  // draws: each mean's standard deviation is about 0.015, or 0.025 for the centroid).
  EXPECT_NEAR(rho2 / 400, 0.5, 0.06);
  EXPECT_NEAR(h / 400, 0.5, 0.06);
  EXPECT_NEAR(cx / 400, 0.0, 0.1);
  EXPECT_NEAR(cy / 400, 0.0, 0.1);
  for (std::size_t i = 0; i < 400; ++i)
    for (std::size_t j = i + 1; j < 400; ++j)
      ASSERT_GE(cdm::norm(s.particles[i].position - s.particles[j].position), 0.001 * (1 - 1e-12));

  // An insertion into a tilted cylinder: the bounding box is kept as the region's.
  const std::string ins_cyl = "cylinder = { point = [0.01, 0.01, 0.02], axis = [1.0, 0.0, 1.0], radius = 0.002, length = 0.01 }";
  const auto t = cdm::load_scene_from_string(replace(base, "lower = [0.0, 0.0, 0.05]\nupper = [0.02, 0.02, 0.06]", ins_cyl), "good.toml");
  const cdm::PlacementRegion& r = t.insertions[0].region;
  ASSERT_TRUE(r.cylinder);
  const double e = 0.01 / std::sqrt(2.0), reach = 0.002 / std::sqrt(2.0);
  EXPECT_NEAR(r.lower.x, 0.01 - reach, 1e-15);
  EXPECT_NEAR(r.upper.x, 0.01 + e + reach, 1e-15);
  EXPECT_NEAR(r.lower.y, 0.01 - 0.002, 1e-15);
  EXPECT_NEAR(r.upper.z, 0.02 + e + reach, 1e-15);
  for (double a : {0.0, 0.3, 0.999})
    for (double b : {0.0, 0.5, 0.999})
      for (double c : {0.0, 0.25, 0.7}) {
        const cdm::Vec3 x = r.draw(a, b, c);
        EXPECT_TRUE(r.contains(x));
        EXPECT_GE(x.x, r.lower.x); EXPECT_LE(x.x, r.upper.x);
        EXPECT_GE(x.z, r.lower.z); EXPECT_LE(x.z, r.upper.z);
      }
  EXPECT_FALSE(r.contains({0.01, 0.01, 0.019}));  // before the start face

  const std::string both = "lower = [0.0, 0.0, 0.05]\nupper = [0.02, 0.02, 0.06]\n" + ins_cyl;
  expect_refused(replace(base, "lower = [0.0, 0.0, 0.05]\nupper = [0.02, 0.02, 0.06]", both),
                 {"insertions[0].lower", "not used", "cylinder"});
  expect_refused(replace(base, "lower = [0.0, 0.0, 0.05]\nupper = [0.02, 0.02, 0.06]", ""),
                 {"insertions[0].lower", "missing", "cylinder"});
  auto bad = [&](const std::string& from, const std::string& to) {
    return replace(base, "lower = [0.0, 0.0, 0.05]\nupper = [0.02, 0.02, 0.06]", replace(ins_cyl, from, to));
  };
  expect_refused(bad("radius = 0.002", "radius = 0.0"), {"insertions[0].cylinder.radius", "> 0"});
  expect_refused(bad(", length = 0.01", ""), {"insertions[0].cylinder.length", "missing"});
  expect_refused(bad("axis = [1.0, 0.0, 1.0]", "axis = [0.0, 0.0, 0.0]"), {"insertions[0].cylinder.axis", "not all 0"});
  expect_refused(bad("length = 0.01", "length = 0.01, height = 1.0"), {"insertions[0].cylinder.height", "not a known key"});
  // Below the floor: the bounding box lies wholly outside the wall.
  expect_refused(bad("point = [0.01, 0.01, 0.02]", "point = [0.01, 0.01, -0.05]"),
                 {"insertions[0].cylinder", "wall 'floor'", "outside"});
}

}  // namespace
