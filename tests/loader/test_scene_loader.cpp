// Bad scene input gets a clear error — the file, the key, the value and what was
// expected — and is refused before anything is built (SceneError; `cdm run` exits 2).
// Good input is converted to SI once, at load.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "cdm/solver/fluid/plane_share.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "support.hpp"
#include "cdm/solver/simulation.hpp"

namespace {

const std::string base = R"(
units = "cgs"

[modules]
gravity = true
normal_contact = "linear_spring_dashpot"

[gravity]
g = [0.0, -980.0, 0.0]

[[materials]]
name = "ball"
density = 2.6

[[materials]]
name = "floor"

[[contacts]]
pair = ["ball", "floor"]
kn = 5.0e7
en = 0.9

[[walls]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "floor"

[[particles]]
material = "ball"
radius = 10.0
position = [0.0, 50.0, 0.0]

[integrator]
scheme = "paper_euler"
dt = "auto"
end_time = 0.5
)";

using cdm::test::replace;

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

using cdm::test::expect_refused;

TEST(SceneLoader, BaseSceneLoads) { EXPECT_NO_THROW(cdm::load_scene_from_string(base, "good.toml")); }

TEST(SceneLoader, DoesNotParse) {
  expect_refused(replace(base, "kn = 5.0e7", "kn = = 5.0e7"), {"does not parse", "bad.toml:"});
}

TEST(SceneLoader, UnknownKeyTopLevel) {
  expect_refused("colour = \"red\"\n" + base, {"'colour'", "not a known key", "expected one of"});
}

TEST(SceneLoader, UnknownKeyInTable) {
  expect_refused(replace(base, "en = 0.9", "en = 0.9\nrestitution = 0.9"),
                 {"contacts[0].restitution", "not a known key", "expected one of"});
}

TEST(SceneLoader, WrongTypeStringForNumber) {
  expect_refused(replace(base, "kn = 5.0e7", "kn = \"stiff\""), {"contacts[0].kn", "\"stiff\"", "expected a number"});
}

TEST(SceneLoader, WrongTypeNumberForArray) {
  expect_refused(replace(base, "position = [0.0, 50.0, 0.0]", "position = 50.0"),
                 {"particles[0].position", "50", "expected an array of 3 numbers"});
}

TEST(SceneLoader, MissingValues) {
  expect_refused(replace(base, "units = \"cgs\"", ""), {"'units'", "missing", "expected"});
  expect_refused(replace(base, "kn = 5.0e7", ""), {"contacts[0].kn", "missing", "expected a number > 0"});
  expect_refused(replace(base, "radius = 10.0", ""), {"particles[0].radius", "missing", "expected"});
  expect_refused(replace(base, "end_time = 0.5", ""), {"integrator.end_time", "missing", "expected"});
}

TEST(SceneLoader, OutOfRange) {
  expect_refused(replace(base, "radius = 10.0", "radius = 0.0"), {"particles[0].radius", "= 0", "expected a number > 0"});
  expect_refused(replace(base, "radius = 10.0", "radius = -1.0"), {"particles[0].radius", "-1", "expected a number > 0"});
  expect_refused(replace(base, "density = 2.6", "density = -2.6"), {"materials[0].density", "-2.6", "expected a number > 0"});
  expect_refused(replace(base, "kn = 5.0e7", "kn = 0"), {"contacts[0].kn", "= 0", "expected a number > 0"});
  expect_refused(replace(base, "en = 0.9", "en = 0.0"), {"contacts[0].en", "= 0", "expected a number in (0, 1]"});
  expect_refused(replace(base, "en = 0.9", "en = 1.5"), {"contacts[0].en", "1.5", "expected a number in (0, 1]"});
  const std::string friction = replace(base, "normal_contact = \"linear_spring_dashpot\"",
                                       "normal_contact = \"linear_spring_dashpot\"\ntangential = \"spring_coulomb\"");
  expect_refused(replace(friction, "en = 0.9", "en = 0.9\nmu = -0.1"), {"contacts[0].mu", "-0.1", "expected a number >= 0"});
}

TEST(SceneLoader, ExplicitDtAboveTenthOfCollisionTimeIsExplained) {
  // t_col at kn = 5e7 dyn/cm, m = 10.9 kg, en = 0.9 is 46 ms; 10 ms > t_col/10.
  expect_refused(replace(base, "dt = \"auto\"", "dt = 0.01"),
                 {"integrator.dt", "0.01", "expected a time step <= t_col/10", "t_col ="});
}

TEST(SceneLoader, ParticlesOverlappingAtStart) {
  expect_refused(base + R"(
[[contacts]]
pair = ["ball", "ball"]
kn = 5.0e7
en = 0.9

[[particles]]
material = "ball"
radius = 10.0
position = [15.0, 50.0, 0.0]
)",
                 {"particles[1].position", "overlaps 'particles[0]'", "expected particles that do not overlap"});
}

TEST(SceneLoader, ParticleOutsideWall) {
  expect_refused(replace(base, "position = [0.0, 50.0, 0.0]", "position = [0.0, -5.0, 0.0]"),
                 {"particles[0].position", "outside wall 'floor'", "expected a particle inside the domain"});
  expect_refused(replace(base, "position = [0.0, 50.0, 0.0]", "position = [0.0, 5.0, 0.0]"),
                 {"particles[0].position", "across wall 'floor'", "expected"});
}

TEST(SceneLoader, UnusedKeysAreErrors) {
  expect_refused(replace(base, "en = 0.9", "en = 0.9\nmu = 0.3"), {"contacts[0].mu", "0.3", "not used", "tangential"});
  expect_refused(replace(base, "gravity = true", "gravity = false"), {"[gravity]", "not used"});
}

TEST(SceneLoader, MissingContactPair) {
  expect_refused(replace(base, "pair = [\"ball\", \"floor\"]", "pair = [\"ball\", \"ball\"]"),
                 {"\"ball\", \"floor\"", "expected a [[contacts]] entry"});
}

TEST(SceneLoader, AtMost256Materials) {
  // A particle's material is held in one byte: 256 materials load, the last one's index
  // kept whole in the store; a 257th is refused, naming the key and the limit.
  std::string many = base;
  for (int m = 2; m < 256; ++m) many += "\n[[materials]]\nname = \"m" + std::to_string(m) + "\"\ndensity = 1.0\n";
  const cdm::SceneSpec s = cdm::load_scene_from_string(many, "good.toml");
  ASSERT_EQ(s.materials.size(), 256u);
  cdm::ParticleStore p;
  p.add({0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}, 0.1, s.materials[255].density, 255);
  EXPECT_EQ(p.material[0], 255);
  expect_refused(many + "\n[[materials]]\nname = \"m256\"\ndensity = 1.0\n", {"'materials'", "257", "at most 256"});
}

TEST(SceneLoader, CgsIsConvertedToSiOnce) {
  const cdm::SceneSpec s = cdm::load_scene_from_string(base, "good.toml");
  EXPECT_DOUBLE_EQ(s.particles[0].radius, 0.1);
  EXPECT_DOUBLE_EQ(s.particles[0].position.y, 0.5);
  EXPECT_DOUBLE_EQ(s.materials[0].density, 2600.0);
  EXPECT_DOUBLE_EQ(s.pairs.get(0, 1).kn, 50000.0);
  EXPECT_DOUBLE_EQ(s.g.y, -9.8);
}

TEST(SceneLoader, AutoDtIsCollisionTimeOver50) {
  const cdm::SceneSpec s = cdm::load_scene_from_string(base, "good.toml");
  const double m = 2600.0 * std::numbers::pi * 0.2 * 0.2 * 0.2 / 6.0, kn = 5e4, pi = std::numbers::pi;
  const double l = std::log(0.9), eta = 2.0 * std::sqrt(m * kn) * std::abs(l) / std::sqrt(pi * pi + l * l);
  const double t_col = pi / std::sqrt(kn / m - eta * eta / (4.0 * m * m));  // eq 28
  EXPECT_NEAR(s.t_col_min, t_col, 1e-14 * t_col);
  EXPECT_NEAR(s.dt, t_col / 50.0, 1e-14 * t_col);
}

TEST(SceneLoader, OverridesApplyBeforeValidation) {
  const cdm::SceneSpec s = cdm::load_scene_from_string(
      base, "good.toml", {cdm::parse_override("contacts[0].kn=1e7"), cdm::parse_override("integrator.scheme=\"velocity_verlet\"")});
  EXPECT_DOUBLE_EQ(s.pairs.get(0, 1).kn, 1e4);
  EXPECT_EQ(s.integrator, cdm::IntegratorScheme::velocity_verlet);
  EXPECT_THROW(cdm::load_scene_from_string(base, "good.toml", {cdm::parse_override("contacts[0].en=2")}), cdm::SceneError);
  EXPECT_THROW(cdm::parse_override("no-equals-sign"), cdm::SceneError);
}

// A lattice of 4 x 3 x 2 balls of radius 1 cm, the particles' contacts.
const std::string lattice = R"([[lattices]]
material = "ball"
radius = 1.0
origin = [0.0, 10.0, 0.0]
spacing = [2.5, 3.0, 2.5]
count = [4, 3, 2]

[[contacts]]
pair = ["ball", "ball"]
kn = 5.0e7
en = 0.9
)";

TEST(SceneLoader, LatticeExpands) {
  const std::string lat = replace(base, R"([[particles]]
material = "ball"
radius = 10.0
position = [0.0, 50.0, 0.0]
)", lattice);
  const cdm::SceneSpec s = cdm::load_scene_from_string(lat, "good.toml");
  ASSERT_EQ(s.particles.size(), 24u);
  EXPECT_DOUBLE_EQ(s.particles[23].position.x, 0.075);
  EXPECT_DOUBLE_EQ(s.particles[23].position.y, 0.16);
  EXPECT_DOUBLE_EQ(s.particles[23].position.z, 0.025);
}

// A lattice's radii (drawn by the loader) and its velocities' jitter (drawn again by the
// run, InitialMotion) come from its one stream, site by site: the radius, then three
// numbers in [-1, 1) that scale the jitter, one per component. A listed particle keeps
// its own velocity. Restated here with the stream's generator, seeded as the scene says.
TEST(SceneLoader, LatticeRadiiAndJitterShareOneStream) {
  const std::string jittered = replace(lattice, "radius = 1.0\n", R"(size = { distribution = "normal", mean = 0.8, std = 0.1 }
velocity = [0.0, -10.0, 0.0]
velocity_jitter = 5.0
seed = 42
)");
  const std::string lat =
      replace(base, "position = [0.0, 50.0, 0.0]\n", "position = [0.0, 50.0, 0.0]\nvelocity = [1.0, 2.0, 3.0]\n\n" + jittered);
  const cdm::SceneSpec s = cdm::load_scene_from_string(lat, "good.toml");
  ASSERT_EQ(s.particles.size(), 25u);
  ASSERT_EQ(s.groups.size(), 2u);
  const cdm::SizeDistribution size = s.groups[1].size;
  const std::vector<cdm::ParticleSpec> placed = s.particles;
  const cdm::Simulation sim(s);
  const cdm::ParticleStore& p = sim.particles();
  ASSERT_EQ(p.size(), 25u);
  const cdm::Vec3 listed = s.groups[0].velocity, v = s.groups[1].velocity;
  const double jitter = s.groups[1].jitter, density = s.materials[0].density;
  EXPECT_DOUBLE_EQ(listed.y, 0.02);  // cm/s in the file
  EXPECT_DOUBLE_EQ(jitter, 0.05);
  EXPECT_EQ(p.velocity(0).x, listed.x);
  EXPECT_EQ(p.velocity(0).y, listed.y);
  EXPECT_EQ(p.velocity(0).z, listed.z);
  std::mt19937_64 rng(42);
  const auto uniform = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53 * 2.0 - 1.0; };
  bool varied = false;
  for (std::size_t k = 1; k < 25; ++k) {
    EXPECT_EQ(placed[k].radius, size.sample(rng)) << "site " << k - 1;
    varied = varied || placed[k].radius != placed[1].radius;
    const double a = uniform(), b = uniform(), c = uniform();
    EXPECT_EQ(p.velocity(k).x, v.x + jitter * a) << "site " << k - 1;
    EXPECT_EQ(p.velocity(k).y, v.y + jitter * b) << "site " << k - 1;
    EXPECT_EQ(p.velocity(k).z, v.z + jitter * c) << "site " << k - 1;
    const double d = 2.0 * placed[k].radius;
    EXPECT_EQ(p.mass[k], density * std::numbers::pi * d * d * d / 6.0) << "site " << k - 1;
  }
  EXPECT_TRUE(varied);
}

// "Only what a scene names is built": a frictionless scene keeps no rotation and no
// tangential history; the same scene with friction does, while in contact.
TEST(SceneLoader, FrictionlessSceneKeepsNoTangentialHistory) {
  const std::string touching = replace(base, "position = [0.0, 50.0, 0.0]", "position = [0.0, 9.9, 0.0]\nvelocity = [10.0, 0.0, 0.0]") +
                               "\n[checks]\nallow_initial_overlap = true\n";
  {
    cdm::Simulation sim(cdm::load_scene_from_string(touching, "good.toml"));
    for (int k = 0; k < 20; ++k) sim.step();
    EXPECT_FALSE(sim.particles().has_rotation());
    EXPECT_TRUE(sim.particles().wx.empty());
    EXPECT_EQ(sim.contact()->history_size(), 0u);
    EXPECT_EQ(sim.contact()->active_contacts(), 1u);
  }
  {
    std::string fr = replace(touching, "normal_contact = \"linear_spring_dashpot\"",
                             "normal_contact = \"linear_spring_dashpot\"\ntangential = \"spring_coulomb\"");
    fr = replace(fr, "en = 0.9", "en = 0.9\nmu = 0.3");
    cdm::Simulation sim(cdm::load_scene_from_string(fr, "good.toml"));
    for (int k = 0; k < 20; ++k) sim.step();
    EXPECT_TRUE(sim.particles().has_rotation());
    EXPECT_EQ(sim.contact()->history_size(), 1u);
  }
  // No gravity and no contact named: no modules at all.
  const cdm::SceneSpec bare = cdm::load_scene_from_string(R"(
units = "SI"
[modules]
[[materials]]
name = "a"
density = 1000.0
[[particles]]
material = "a"
radius = 0.01
position = [0.0, 0.0, 0.0]
velocity = [1.0, 0.0, 0.0]
[integrator]
scheme = "velocity_verlet"
dt = 0.001
end_time = 0.1
)", "good.toml");
  cdm::Simulation sim(bare);
  EXPECT_TRUE(sim.module_names().empty());
  EXPECT_EQ(sim.contact(), nullptr);
  sim.run();
  EXPECT_NEAR(sim.particles().x[0], 0.1, 1e-12);
}

}  // namespace

// coupling.gas_velocity: "interstitial" (default) or "superficial", only where the drag
// interpolates a solved gas's velocity to each particle.
TEST(SceneLoader, CouplingGasVelocity) {
  const std::string scene = read_text(std::string(CDM_SOURCE_DIR) + "/verification/cases/fluidization/scene.toml");
  ASSERT_NE(scene.find("gas_velocity = \"superficial\""), std::string::npos);
  EXPECT_EQ(cdm::load_scene_from_string(scene, "f.toml").gas_velocity, cdm::coupling::SlipVelocity::superficial);
  EXPECT_EQ(cdm::load_scene_from_string(replace(scene, "gas_velocity = \"superficial\"\n", ""), "f.toml").gas_velocity,
            cdm::coupling::SlipVelocity::interstitial);
  expect_refused(replace(scene, "gas_velocity = \"superficial\"", "gas_velocity = \"bulk\""),
                 {"coupling.gas_velocity", "bulk", "\"interstitial\" or \"superficial\""});
  expect_refused(replace(replace(scene, "method = \"interpolate\"", "method = \"cell_average\""), "kernel = \"trilinear\"\n", ""),
                 {"coupling.gas_velocity", "superficial", "not used", "cell_average"});
}

TEST(SceneLoader, GasDivision) {
  const std::string scene = read_text(std::string(CDM_SOURCE_DIR) + "/verification/cases/fluidization/scene.toml");
  const std::string gas = "[gas]\n";
  ASSERT_NE(scene.find(gas), std::string::npos);
  auto with = [&](const std::string& keys) { return replace(scene, gas, gas + keys); };
  EXPECT_EQ(cdm::load_scene_from_string(scene, "f.toml").gas_division, cdm::fluid::GasDivision::automatic);
  EXPECT_EQ(cdm::load_scene_from_string(with("division = \"planes\"\n"), "f.toml").gas_division,
            cdm::fluid::GasDivision::planes);
  EXPECT_EQ(cdm::load_scene_from_string(with("division = \"whole\"\n"), "f.toml").gas_division,
            cdm::fluid::GasDivision::whole);
  expect_refused(with("division = \"slabs\"\n"), {"bad.toml", "gas.division", "slabs", "\"auto\", \"planes\" or \"whole\""});
}

// "auto" divides where each process's run of planes of the slowest axis holds 2048 cells.
TEST(GasDivision, AutomaticDividesWhereEveryProcessGets2048Cells) {
  using cdm::fluid::GasDivision;
  using cdm::fluid::PlaneShare;
  auto grid = [](int nx, int ny, int nz) {
    cdm::fluid::GridSpec s;
    s.hi = {1.0, 1.0, 1.0};
    s.cells = {nx, ny, nz};
    return cdm::fluid::StaggeredGrid(s);
  };
  const auto mueller = grid(15, 40, 3), cube = grid(16, 16, 16), goldschmidt = grid(2, 30, 90);
  EXPECT_FALSE(PlaneShare::divides(GasDivision::automatic, mueller, 2));  // 600 and 1200 cells
  EXPECT_TRUE(PlaneShare::divides(GasDivision::planes, mueller, 2));
  EXPECT_FALSE(PlaneShare::divides(GasDivision::planes, mueller, 1));
  EXPECT_TRUE(PlaneShare::divides(GasDivision::automatic, cube, 2));   // 2048 each
  EXPECT_FALSE(PlaneShare::divides(GasDivision::automatic, cube, 3));  // 1280, 1280, 1536
  EXPECT_FALSE(PlaneShare::divides(GasDivision::whole, cube, 2));
  EXPECT_TRUE(PlaneShare::divides(GasDivision::automatic, goldschmidt, 2));   // 45 planes of 60 cells each
  EXPECT_FALSE(PlaneShare::divides(GasDivision::automatic, goldschmidt, 3));  // 1800 each
}

TEST(SceneLoader, GasPressureSolver) {
  const std::string scene = read_text(std::string(CDM_SOURCE_DIR) + "/verification/cases/fluidization/scene.toml");
  const std::string gas = "[gas]\n";
  ASSERT_NE(scene.find(gas), std::string::npos);
  auto with = [&](const std::string& keys) { return replace(scene, gas, gas + keys); };
  const cdm::SceneSpec d = cdm::load_scene_from_string(scene, "f.toml");
  if (!cdm::fluid::multigrid_available()) {
    // A build without MPI and hypre: "auto" by default (which resolves to the direct
    // solve), and "multigrid" refused.
    EXPECT_EQ(d.pressure_solver.backend, cdm::fluid::PressureBackend::automatic);
    expect_refused(with("pressure_solver = \"multigrid\"\n"),
                   {"bad.toml", "gas.pressure_solver", "multigrid", "\"direct\"", "without MPI and hypre", "CDM_WITH_MPI"});
    return;
  }
  EXPECT_EQ(d.pressure_solver.backend, cdm::fluid::PressureBackend::automatic);
  EXPECT_EQ(d.pressure_solver.tolerance, 1e-10);
  EXPECT_EQ(cdm::load_scene_from_string(with("pressure_solver = \"multigrid\"\n"), "f.toml").pressure_solver.backend,
            cdm::fluid::PressureBackend::multigrid);
  // The fluidisation case's 8 x 64 x 4 cells: "auto" factorises, so a tolerance has no use there.
  expect_refused(with("pressure_tolerance = 1e-8\n"),
                 {"gas.pressure_tolerance", "1e-08", "\"auto\"", "2048 cells", "direct", "\"multigrid\""});
  const cdm::SceneSpec m =
      cdm::load_scene_from_string(with("pressure_solver = \"multigrid\"\npressure_tolerance = 1e-8\n"), "f.toml");
  EXPECT_EQ(m.pressure_solver.tolerance, 1e-8);
  const cdm::SceneSpec big =
      cdm::load_scene_from_string(with("pressure_tolerance = 1e-8\n"), "f.toml", {cdm::parse_override("gas.cells=[24,96,24]")});
  EXPECT_EQ(big.pressure_solver.backend, cdm::fluid::PressureBackend::automatic);
  EXPECT_EQ(big.pressure_solver.tolerance, 1e-8);
  EXPECT_EQ(cdm::load_scene_from_string(with("pressure_solver = \"direct\"\n"), "f.toml").pressure_solver.backend,
            cdm::fluid::PressureBackend::direct);
  expect_refused(with("pressure_solver = \"cg\"\n"), {"bad.toml", "gas.pressure_solver", "cg", "\"auto\", \"multigrid\" or \"direct\""});
  expect_refused(with("pressure_tolerance = 0.1\n"), {"gas.pressure_tolerance", "0.1", "[1e-14, 0.001]"});
  expect_refused(with("pressure_tolerance = 0.0\n"), {"gas.pressure_tolerance", "relative residual in"});
  expect_refused(with("pressure_tolerance = \"tight\"\n"), {"gas.pressure_tolerance", "tight"});
  expect_refused(with("pressure_solver = \"direct\"\npressure_tolerance = 1e-8\n"),
                 {"gas.pressure_tolerance", "not used", "direct"});
  // A prescribed gas solves no pressure equation.
  const std::string tv = read_text(std::string(CDM_SOURCE_DIR) + "/verification/cases/terminal_velocity/scene.toml");
  if (tv.find(gas) != std::string::npos)
    expect_refused(replace(tv, gas, gas + "pressure_solver = \"direct\"\n"), {"gas.pressure_solver", "not used"});
}

TEST(SceneLoader, NeighbourListSortInterval) {
  // The settle benchmark sorts every 1000 steps, as does a scene without [neighbour_list].
  const std::string bench = read_text(std::string(CDM_SOURCE_DIR) + "/bench/scenes/settle_1e4.toml");
  ASSERT_NE(bench.find("[neighbour_list]\nsort_interval = 1000\n"), std::string::npos);
  EXPECT_EQ(cdm::load_scene_from_string(bench, "s.toml").sort_interval, 1000u);
  const std::string settle = replace(bench, "[neighbour_list]\nsort_interval = 1000\n", "");
  EXPECT_EQ(cdm::load_scene_from_string(settle, "s.toml").sort_interval, 1000u);
  EXPECT_EQ(cdm::load_scene_from_string(settle + "\n[neighbour_list]\nsort_interval = 0\n", "s.toml").sort_interval, 0u);
  EXPECT_EQ(cdm::load_scene_from_string(settle + "\n[neighbour_list]\nsort_interval = 500\n", "s.toml").sort_interval, 500u);
  expect_refused(settle + "\n[neighbour_list]\nsort_interval = -1\n", {"neighbour_list.sort_interval", "-1", "integer >= 0"});
  expect_refused(settle + "\n[neighbour_list]\nsort_interval = 2.5\n", {"neighbour_list.sort_interval", "2.5", "integer >= 0"});
  expect_refused(settle + "\n[neighbour_list]\nsort_every = 5\n", {"neighbour_list", "sort_every"});
  // Without contacts there is no neighbour list to sort.
  const std::string fall = read_text(std::string(CDM_SOURCE_DIR) + "/verification/cases/terminal_velocity/scene.toml");
  expect_refused(fall + "\n[neighbour_list]\nsort_interval = 10\n", {"neighbour_list.sort_interval", "not used", "no contacts"});
}

namespace {

// The Verlet skin is a tenth of the largest diameter; contacts reach 2 r_max + skin, and a
// periodic axis must be more than twice that long.
TEST(SceneLoader, VerletSkinSetsThePeriodicReach) {
  const cdm::SceneSpec spec = cdm::load_scene_from_string(base, "base.toml");
  EXPECT_DOUBLE_EQ(spec.verlet_skin, 0.1 * 2.0 * 0.1);  // radius 10 cm
  const std::string periodic = base + "\n[periodic]\nx = [-50.0, 50.0]\n";
  EXPECT_NO_THROW(cdm::load_scene_from_string(replace(periodic, "[-50.0, 50.0]", "[-22.5, 22.5]"), "ok.toml"));
  expect_refused(replace(periodic, "[-50.0, 50.0]", "[-21.5, 21.5]"),
                 {"the period along x (periodic.x)", "4.4 times the largest radius", "Verlet skin"});
}

}  // namespace
