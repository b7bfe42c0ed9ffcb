// Insertion by mass and removal (population.hpp) through a Simulation: the mass
// inserted follows the mass rate within one particle at every event and stops past the
// total by less than one particle; inserted particles clear every other particle and
// wall; removal compacts the store in order and renumbers identities by rank, sorted
// or not; the contact history of the pairs left follows them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"
#include "scene_text.hpp"

namespace {

const std::string scene = cdm_test::scene_head({.mu = 0.5}) + cdm_test::floor_wall() + R"(
[[insertions]]
material = "glass"
lower = [0.0, 0.0, 0.001]
upper = [0.01, 0.01, 0.02]
mass_rate = 0.01
mass = 0.0004
interval = 0.001
size = { distribution = "lognormal", basis = "mass", median = 0.0005, sigma = 0.3 }
[[outlets]]
name = "low"
type = "box"
lower = [0.0, 0.0, -1.0]
upper = [0.005, 0.01, 0.0015]
[neighbour_list]
sort_interval = 20
[integrator]
scheme = "velocity_verlet"
dt = "auto"
end_time = 0.06
)";

TEST(Population, MassRateAndTotalWithinOneParticle) {
  cdm::Simulation sim(cdm::load_scene_from_string(scene, "population.toml"));
  const auto& in = sim.spec().insertions[0];
  const double r_max = in.size.largest(), m_max = 2500.0 * std::numbers::pi * std::pow(2.0 * r_max, 3) / 6.0;
  double last_mass = 0.0;
  bool removed = false;
  while (sim.steps() < sim.total_steps()) {
    sim.step();
    const auto& t = sim.population()->inserted()[0];
    const double k = std::floor(sim.time() / in.interval + 1e-9);
    const double target = std::min(in.rate * k * in.interval, in.total);
    if (t.mass != last_mass) {  // an event inserted: it reached the target, by less than one particle
      EXPECT_GE(t.mass, target) << "t = " << sim.time();
      EXPECT_LT(t.mass, target + m_max) << "t = " << sim.time();
      last_mass = t.mass;
    }
    // Every particle clears every other at its insertion: no overlap beyond what the
    // contacts allow (the run's guard would stop at the radius).
    removed = removed || sim.population()->removed()[0].count > 0;
    // The identities are 0..n-1, each slot's.
    const cdm::ParticleStore& p = sim.particles();
    if (!p.id.empty()) {
      ASSERT_EQ(p.id.size(), p.size());
      const cdm::IdentityOrder order(p);
      for (std::size_t s = 0; s < p.size(); ++s) ASSERT_EQ(order.slot_of(p.id[s]), s);
    }
  }
  const auto& t = sim.population()->inserted()[0];
  EXPECT_GE(t.mass, in.total);
  EXPECT_LT(t.mass, in.total + m_max);
  EXPECT_TRUE(removed) << "the outlet removed nothing: the test does not test removal";
  // The balance: what is in the domain is what was inserted minus what was removed.
  const cdm::ParticleStore& p = sim.particles();
  double mass = 0.0;
  for (double m : p.mass) mass += m;
  EXPECT_EQ(p.size(), t.count - sim.population()->removed()[0].count);
  EXPECT_NEAR(mass, t.mass - sim.population()->removed()[0].mass, 1e-12 * t.mass);
  // The radii drawn lie within the cut-offs.
  for (double r : p.radius) {
    EXPECT_GE(r, in.size.min);
    EXPECT_LE(r, in.size.max);
  }
}

// An insertion into a cylinder: every particle of the event lies in it, clear of the others.
TEST(Population, InsertsIntoACylinder) {
  std::string text = scene;
  const std::string box = "lower = [0.0, 0.0, 0.001]\nupper = [0.01, 0.01, 0.02]";
  text.replace(text.find(box), box.size(),
               "cylinder = { point = [0.005, 0.005, 0.004], axis = [0.0, 0.0, 1.0], radius = 0.003, length = 0.012 }");
  const std::string rate = "mass_rate = 0.01\nmass = 0.0004";
  text.replace(text.find(rate), rate.size(), "count_rate = 1.0e5\ncount = 60");
  cdm::Simulation sim(cdm::load_scene_from_string(text, "population.toml"));
  while (sim.population()->inserted()[0].count == 0 && sim.steps() < sim.total_steps()) sim.step();
  const cdm::ParticleStore& p = sim.particles();
  ASSERT_EQ(p.size(), 60u);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double dx = p.x[i] - 0.005, dy = p.y[i] - 0.005;
    EXPECT_LE(std::sqrt(dx * dx + dy * dy), 0.003 * (1 + 1e-12));  // inserted at this step's end
    EXPECT_GE(p.z[i], 0.004);
    EXPECT_LE(p.z[i], 0.016);
    for (std::size_t j = i + 1; j < p.size(); ++j)
      EXPECT_GE(cdm::norm(p.position(i) - p.position(j)), (p.radius[i] + p.radius[j]) * (1 - 1e-9));
  }
}

TEST(Population, KeepCompactsInOrderAndRanksIdentities) {
  cdm::ParticleStore p;
  p.enable_rotation();
  for (int i = 0; i < 6; ++i) p.add({double(i), 0, 0}, {0, 0, double(i)}, 0.1 + i, 1000.0, 0);
  // A sort: slot s holds particle id[s].
  p.permute({5, 3, 1, 0, 2, 4});
  // Keep slots 0, 2, 3, 5 (particles 5, 1, 0, 4): in that order, ranked 3, 1, 0, 2.
  p.keep({0, 2, 3, 5});
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(p.x, (std::vector<double>{5, 1, 0, 4}));
  EXPECT_EQ(p.vz, (std::vector<double>{5, 1, 0, 4}));
  EXPECT_EQ(p.wx.size(), 4u);
  EXPECT_EQ(p.id, (std::vector<std::uint32_t>{3, 1, 0, 2}));
  const cdm::IdentityOrder order(p);
  for (std::uint32_t k = 0; k < 4; ++k) EXPECT_EQ(order.slot_of(k), (std::vector<std::size_t>{2, 1, 3, 0})[k]);
  // Never sorted: identities are the slots, kept in order.
  cdm::ParticleStore q;
  for (int i = 0; i < 4; ++i) q.add({double(i), 0, 0}, {}, 0.1, 1000.0, 0);
  q.keep({1, 3});
  EXPECT_EQ(q.x, (std::vector<double>{1, 3}));
  EXPECT_TRUE(q.id.empty());
}

// A particle leaving through an outlet takes none of the gas's momentum with it: the drag
// impulse it gathered since its impulses were last deposited (the step, or the gas step
// so far when the drag is evaluated once per gas step) goes to the gas as it leaves. One
// sphere thrown at 1 m/s through still gas (two-way, no gravity, no other force), so the
// impulse the particles give the gas in all equals m (v0 − v) at the step it leaves,
// taken from the same run without the outlet.
std::string leaving_scene(const std::string& evaluation, const std::string& update, bool outlet) {
  return R"(units = "SI"
[modules]
gas = "solved"
drag = "schiller_naumann"
[gas]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
cells = [4, 4, 4]
density = 1.2
viscosity = 1.8e-5
dt = 1.0e-4
)" + cdm_test::periodic_gas_boundaries + R"([coupling]
mode = "two_way"
kernel = "trilinear"
drag_evaluation = ")" + evaluation + R"("
[drag]
update = ")" + update + R"("
[[materials]]
name = "glass"
density = 2500.0
[[particles]]
material = "glass"
radius = 5.0e-4
position = [0.002, 0.005, 0.005]
velocity = [1.0, 0.0, 0.0]
[integrator]
scheme = "velocity_verlet"
dt = 1.0e-5
end_time = 0.01
)" + (outlet ? "[[outlets]]\nname = \"out\"\ntype = \"plane\"\npoint = [0.00835, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n" : "");
}

TEST(Population, ALeavingParticleLeavesItsDragImpulseWithTheGas) {
  for (const std::string evaluation : {"every_step", "gas_step"})
    for (const std::string update : {"explicit", "implicit"}) {
      SCOPED_TRACE(evaluation + ", drag.update = " + update);
      cdm::Simulation a(cdm::load_scene_from_string(leaving_scene(evaluation, update, true), "a.toml", {}));
      const double m = a.particles().mass[0];
      const std::uint64_t sub = a.substeps();
      ASSERT_GT(sub, 1u);
      double given = 0.0;  // the impulse the particles gave, over the gas steps so far [N s]
      std::uint64_t left = 0;
      while (a.steps() < a.total_steps()) {
        a.step();
        if (a.steps() % sub == 0) given += a.coupling_balance().particles.x;
        if (!left && a.particles().size() == 0) left = a.steps();
        if (left && a.steps() >= left + 2 * sub) break;  // its gas step has taken it
      }
      ASSERT_GT(left, 0u) << "the particle never reached the outlet";
      ASSERT_NE(left % sub, 0u) << "the particle left at a gas step: the test does not test a partial one";
      cdm::Simulation b(cdm::load_scene_from_string(leaving_scene(evaluation, update, false), "b.toml", {}));
      while (b.steps() < left) b.step();
      const double lost = m * (b.particles().vx[0] - 1.0);  // < 0: the drag slowed it
      ASSERT_LT(lost, 0.0);
      EXPECT_NEAR(given, lost, 1e-9 * std::abs(lost));
    }
}

}  // namespace
