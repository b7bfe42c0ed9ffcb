// Velocity Verlet leaves each step's final half kick pending where no gas reads the
// velocities, and does it in the same pass as the next step's first half, or when the
// particles are read (Simulation::step). These tests hold that to its promise: reading
// the state changes nothing, and a state that is not finite is still reported, at the
// step where it arose.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"
#include "support.hpp"

namespace {

using cdm_test::box_scene;
using cdm_test::same;

cdm::SceneSpec scene() { return cdm::load_scene_from_string(box_scene, "box.toml", {}); }

}  // namespace

TEST(VelocityVerlet, ReadingTheStateBetweenStepsChangesNothing) {
  cdm::Simulation read_each(scene()), read_last(scene());
  const std::uint64_t steps = 5000;
  double checksum = 0.0;
  std::size_t most_contacts = 0;
  for (std::uint64_t k = 0; k < steps; ++k) {
    read_each.step();
    const cdm::ParticleStore& p = read_each.particles();  // completes every step
    checksum += p.vz[0] + p.wx[0];
    read_last.step();  // completed only by the next step's pass
    most_contacts = std::max(most_contacts, read_last.contact()->active_contacts());
  }
  EXPECT_TRUE(std::isfinite(checksum));
  ASSERT_GT(most_contacts, 50u) << "the test should cover contacts";
  const cdm::ParticleStore& a = read_each.particles();
  const cdm::ParticleStore& b = read_last.particles();
  EXPECT_TRUE(cdm_test::same_motion(a, b));
}

TEST(VelocityVerlet, StateReadIsTheStateAtItsTime) {
  // Between steps the particles hold v(t) and ω(t), not the predicted velocities the
  // forces were evaluated with: a free particle's velocity is v0 + g t exactly as
  // velocity Verlet gives it.
  cdm::Simulation sim(scene());
  const double v0 = sim.particles().vz[0];
  for (int k = 0; k < 10; ++k) sim.step();  // the lowest particle is still in free fall
  double v = v0;
  for (int k = 0; k < 10; ++k) v = (v + 0.5 * sim.dt() * -9.81) + 0.5 * sim.dt() * -9.81;
  EXPECT_NEAR(sim.particles().vz[0], v, 1e-15);
  EXPECT_NE(sim.particles().vz[0], v + sim.dt() * -9.81) << "the predicted velocity is not the state";
}

/// Runs @p action, which must throw cdm::SimulationError naming step @p step and the
/// particle @p particle (@p what_failed says what went unreported otherwise).
template <class Action>
void expect_reported(Action action, const std::string& step, const std::string& particle, const char* what_failed) {
  try {
    action();
    FAIL() << what_failed;
  } catch (const cdm::SimulationError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("(step " + step + ")"), std::string::npos) << what;
    EXPECT_NE(what.find(" " + particle + " "), std::string::npos) << what;
  }
}

TEST(VelocityVerlet, NonFiniteStateIsReportedAtItsStep) {
  {
    // A velocity made NaN between steps: the next step's pass finds it before moving on.
    cdm::Simulation sim(scene());
    for (int k = 0; k < 5; ++k) sim.step();
    sim.particles().vx[cdm::IdentityOrder(sim.particles()).slot_of(17)] = std::numeric_limits<double>::quiet_NaN();
    expect_reported([&] { sim.step(); }, "5", "17", "a NaN velocity went unreported");
  }
  {
    // A force made NaN: the step that uses it completes with a NaN velocity, and reading
    // the state reports it at that step instead of returning it.
    cdm::Simulation sim(scene());
    for (int k = 0; k < 5; ++k) sim.step();
    sim.particles().fz[cdm::IdentityOrder(sim.particles()).slot_of(3)] = std::numeric_limits<double>::quiet_NaN();
    sim.step();
    expect_reported([&] { (void)sim.particles(); }, "6", "3", "a NaN state was returned");
  }
  {
    // A torque made NaN, and the state not read: the step that uses it leaves its final
    // kick pending with a NaN spin, which the next step's pass (the spin's own loop,
    // its final kick done there) finds before moving on, and reports at its step.
    cdm::Simulation sim(scene());
    for (int k = 0; k < 5; ++k) sim.step();
    sim.particles().tz[cdm::IdentityOrder(sim.particles()).slot_of(3)] = std::numeric_limits<double>::quiet_NaN();
    sim.step();
    expect_reported([&] { sim.step(); }, "6", "3", "a NaN spin went unreported");
  }
}

TEST(ParticleStore, SameMassIsBitForBit) {
  // Velocity Verlet's pass reads one m, 1/m and 1/I for all particles when they agree
  // to the bit (a bed of one kind of particle); one particle apart (a radius one part in
  // 1e15 larger, or fixed) keeps the per-particle arrays.
  auto store = [](double r_last, bool fixed_last) {
    cdm::ParticleStore p;
    p.enable_rotation();
    for (int i = 0; i < 3; ++i) p.add({0.01 * i, 0.0, 0.0}, {}, 0.5e-3, 2500.0, 0);
    p.add({0.05, 0.0, 0.0}, {}, r_last, 2500.0, 0, fixed_last);
    return p;
  };
  EXPECT_TRUE(store(0.5e-3, false).same_mass());
  EXPECT_FALSE(store(0.5e-3 * (1.0 + 1e-15), false).same_mass());
  EXPECT_FALSE(store(0.5e-3, true).same_mass());
  EXPECT_TRUE(cdm::ParticleStore().same_mass());
  // Over runs of slots (an MPI process's own particles): the odd one outside them does
  // not count, one inside does; slots outside hold zero masses, as another's do.
  cdm::ParticleStore q = store(0.6e-3, false);
  EXPECT_TRUE(q.same_mass({{0, 3}}));
  EXPECT_TRUE(q.same_mass({{0, 1}, {2, 3}}));
  EXPECT_FALSE(q.same_mass({{1, 2}, {3, 4}}));
  q.mass[0] = q.inv_mass[0] = q.inv_inertia[0] = 0.0;
  EXPECT_TRUE(q.same_mass({{1, 3}}));
  EXPECT_TRUE(q.same_mass({{2, 2}}));  // none
}

TEST(ParticleStore, FixedFlagsFollowTheParticles) {
  // Whether a particle is fixed is kept apart from its 1/m, which among MPI processes
  // only its owner holds: a build drops the pairs of two fixed particles by it.
  cdm::ParticleStore p;
  for (int i = 0; i < 3; ++i) p.add({0.01 * i, 0.0, 0.0}, {}, 0.5e-3, 2500.0, 0);
  EXPECT_TRUE(p.fixed_flag.empty());
  EXPECT_FALSE(p.is_fixed(1));
  p.add({0.03, 0.0, 0.0}, {}, 0.5e-3, 2500.0, 0, true);
  p.add({0.04, 0.0, 0.0}, {}, 0.5e-3, 2500.0, 0);
  ASSERT_EQ(p.fixed_flag.size(), 5u);
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(p.is_fixed(i), i == 3) << i;
  p.permute({3, 0, 1, 2, 4});
  for (std::size_t i = 0; i < 5; ++i) EXPECT_EQ(p.is_fixed(i), i == 0) << i;
  p.keep({1, 0, 4});  // compacted
  ASSERT_EQ(p.fixed_flag.size(), 3u);
  EXPECT_FALSE(p.is_fixed(0));
  EXPECT_TRUE(p.is_fixed(1));
  EXPECT_FALSE(p.is_fixed(2));
  // Read back from the masses (a checkpoint's), whole on every process.
  p.fixed_flag.clear();
  p.flag_fixed_from_masses();
  ASSERT_EQ(p.fixed_flag.size(), 3u);
  EXPECT_TRUE(p.is_fixed(1));
  EXPECT_FALSE(p.is_fixed(0) || p.is_fixed(2));
  cdm::ParticleStore first;
  first.add({}, {}, 0.5e-3, 2500.0, 0, true);  // the first particle fixed
  EXPECT_TRUE(first.is_fixed(0));
}

TEST(VelocityVerlet, ListsAreRebuiltAtTheStepADisplacementPassesHalfTheSkin) {
  // The pass measures the displacement since the list's build only when a bound on it
  // (each step's largest drift, added to the last measure or to zero at the build) nears
  // half the skin. The list must still be rebuilt at exactly the steps where some
  // particle first lies more than half the skin from where it was at the build: never
  // later (a bound that fell short: contacts missed), never earlier. 216 spheres thrown
  // at up to 0.5 m/s bounce off each other and the walls, so the summed drifts run far
  // ahead of the displacements and the bound restarts from many measures.
  cdm::Simulation sim(scene());
  const double skin = sim.contact()->list().skin();
  ASSERT_GT(skin, 0.0);
  const double lim2 = 0.25 * skin * skin;
  auto positions = [&] {
    const cdm::ParticleStore& p = sim.particles();
    std::vector<double> x(3 * p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::size_t k = p.id_of(i);
      x[3 * k] = p.x[i]; x[3 * k + 1] = p.y[i]; x[3 * k + 2] = p.z[i];
    }
    return x;
  };
  std::vector<double> built = positions();  // the first build is at the initial positions
  std::size_t builds = 0;
  int rebuilds = 0;
  for (int k = 1; k <= 4000; ++k) {
    sim.step();
    const std::vector<double> x = positions();
    double worst = 0.0;  // the largest squared displacement, summed as the pass sums it
    for (std::size_t q = 0; q < x.size(); q += 3) {
      const double dx = x[q] - built[q], dy = x[q + 1] - built[q + 1], dz = x[q + 2] - built[q + 2];
      worst = std::max(worst, dx * dx + dy * dy + dz * dz);
    }
    const std::size_t b = sim.contact()->list().builds();
    if (k == 1) {
      ASSERT_EQ(b, 1u) << "the test expects no rebuild at the first step";
    }
    if (k > 1 && b > builds) {
      ASSERT_EQ(b, builds + 1);
      EXPECT_GT(worst, lim2) << "rebuilt at step " << k << " before any particle moved skin/2";
      ++rebuilds;
      built = x;
    } else {
      EXPECT_LE(worst, lim2) << "not rebuilt at step " << k << " though a particle moved "
                             << std::sqrt(worst) / skin << " skin";
    }
    builds = b;
  }
  EXPECT_GE(rebuilds, 10) << "the test needs many rebuilds";
}

TEST(VelocityVerlet, PassCoversEveryBlock) {
  // Velocity Verlet's one pass per step goes through each thread's particles in blocks
  // of 32768 (verlet_pass). 70,000 spheres in free fall make three blocks on one thread
  // and two on each of two. Every block must move its particles, check them and report
  // its drift to the Verlet list: a particle in the last block behaves as one in the first.
  const cdm::SceneSpec spec =
      cdm::load_scene_from_string(box_scene, "box.toml",
                                  {cdm::parse_override("lattices[0].count=[50, 50, 28]"),
                                   cdm::parse_override("lattices[0].origin=[0.00055, 0.00055, 0.002]"),
                                   cdm::parse_override("walls[2].point=[0.0556, 0.0, 0.0]"),
                                   cdm::parse_override("neighbour_list.sort_interval=0")});  // blocks in scene order
  const std::size_t n = 50 * 50 * 28;
  // Free fall: every particle's vertical velocity follows velocity Verlet's two half
  // kicks with its weight, v + (Δt/2)(1/m)(m g) twice a step, to the bit.
  {
    cdm::Simulation sim(spec);
    ASSERT_EQ(sim.particles().size(), n);
    std::vector<double> v = sim.particles().vz;
    const cdm::ParticleStore& p0 = sim.particles();
    for (int k = 0; k < 3; ++k) {
      sim.step();
      for (std::size_t i = 0; i < n; ++i) {
        const double c = 0.5 * sim.dt() * p0.inv_mass[i], f = 0.0 + p0.mass[i] * -9.81;
        v[i] = (v[i] + c * f) + c * f;
      }
    }
    ASSERT_EQ(sim.contact()->active_contacts(), 0u) << "the test needs particles in free fall";
    EXPECT_TRUE(same(sim.particles().vz, v));
  }
  // A particle thrown fast sideways sets off a rebuild at the same step from either end
  // of the particle order (the list is built at step 0; skin/2 = 50 µm is crossed after
  // a few steps at 10 m/s).
  auto rebuild_step = [&](std::size_t fast) {
    cdm::Simulation sim(spec);
    sim.particles().vy[fast] = 10.0;
    for (int k = 1; k <= 20; ++k) {
      sim.step();
      if (sim.contact()->list().builds() > 1) return k;
    }
    return -1;
  };
  const int first = rebuild_step(0);
  EXPECT_GT(first, 1);
  EXPECT_EQ(rebuild_step(n - 1), first);
  EXPECT_EQ(rebuild_step(40000), first);
  // A NaN velocity in the last block is found by the next step's pass.
  cdm::Simulation sim(spec);
  sim.step();
  sim.particles().vx[n - 1] = std::numeric_limits<double>::quiet_NaN();
  expect_reported([&] { sim.step(); }, "1", std::to_string(n - 1), "a NaN velocity in the last block went unreported");
}

TEST(VelocityVerlet, ExactDragRelaxationInThePassIsTheKickToTheBit) {
  // With drag.update = "exponential" the pass does the exact drag relaxation of its
  // kicks itself, from a φ per particle kept while λ = K/m stays the same (between gas
  // steps), and the step's final kick waits for the next pass. Reading the state every
  // step completes each step through Kick instead, e^x and all: the two runs must move
  // every particle the same to the bit, through gas steps (λ new for every particle) and
  // sorts (each slot's φ belongs to another particle afterwards).
  const std::string text = R"(
units = "SI"
[modules]
gravity = true
normal_contact = "linear_spring_dashpot"
gas = "solved"
drag = "gidaspow"
pressure_gradient = true
[gravity]
g = [0.0, -9.81, 0.0]
[gas]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.02, 0.01]
cells = [4, 8, 4]
density = 1.2
viscosity = 1.8e-5
dt = 1.0e-4
initial_velocity = [0.0, 0.3, 0.0]
[gas.boundaries]
x_lower = "no_slip"
x_upper = "no_slip"
y_lower = { type = "velocity_inlet", velocity = 0.3 }
y_upper = { type = "pressure_outlet", pressure = 0.0 }
z_lower = "no_slip"
z_upper = "no_slip"
[coupling]
mode = "two_way"
drag_evaluation = "gas_step"
[drag]
update = "exponential"
[neighbour_list]
sort_interval = 10
[[materials]]
name = "p"
density = 2500.0
[[materials]]
name = "wall"
[[contacts]]
pair = ["p", "p"]
kn = 10.0
en = 0.9
[[contacts]]
pair = ["p", "wall"]
kn = 10.0
en = 0.9
[[walls]]
name = "floor"
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "wall"
[[random_particles]]
material = "p"
radius = 1.5e-4
lower = [0.001, 0.001, 0.001]
upper = [0.009, 0.019, 0.009]
count = 300
[integrator]
scheme = "velocity_verlet"
dt = 1.0e-5
end_time = 1.0
)";
  const cdm::SceneSpec spec = cdm::load_scene_from_string(text, "exact_drag.toml", {});
  cdm::Simulation read_each(spec), read_last(spec);
  for (int k = 0; k < 300; ++k) {
    read_each.step();
    (void)read_each.particles();  // completes the step through Kick
    read_last.step();
  }
  const cdm::ParticleStore& a = read_each.particles();
  const cdm::ParticleStore& b = read_last.particles();
  ASSERT_GT(read_last.contact()->list().builds(), 2u) << "the test needs sorts between gas steps";
  EXPECT_TRUE(cdm_test::same_motion(a, b));
  // The drag moved the particles: not the free fall of their weight alone.
  double lift = 0.0;
  for (std::size_t i = 0; i < b.size(); ++i) lift += b.vy[i] + 9.81 * 300 * 1.0e-5;
  EXPECT_GT(lift / static_cast<double>(b.size()), 1e-4);
}
