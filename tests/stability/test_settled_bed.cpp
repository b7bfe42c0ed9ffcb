// A settled bed of 10^4 frictional particles held at rest for 10^5 steps: the maximum
// speed stays under a stated bound, no particle leaves the box, every value stays
// finite, and the kinetic energy does not grow. The bed is the benchmark's settle
// problem (bench/scenes/settle_1e4.toml: 10,000 spheres poured from a lattice with
// random velocities) run until it has come to rest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"

namespace {

struct BedState { double ke, vmax; bool inside; bool finite; };

BedState measure(const cdm::Simulation& sim) {
  const auto& p = sim.particles();
  BedState s{0.0, 0.0, true, true};
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double v2 = p.vx[i] * p.vx[i] + p.vy[i] * p.vy[i] + p.vz[i] * p.vz[i];
    s.ke += 0.5 * p.mass[i] * v2;
    s.vmax = std::max(s.vmax, std::sqrt(v2));
    const double r = p.radius[i];
    // Box [0, 22 mm]^2 with a floor at z = 0 and an open top: the centre stays at
    // least half a radius inside every wall (overlaps are micrometres).
    s.inside = s.inside && p.x[i] > 0.5 * r && p.x[i] < 0.022 - 0.5 * r && p.y[i] > 0.5 * r &&
               p.y[i] < 0.022 - 0.5 * r && p.z[i] > 0.5 * r && p.z[i] < 0.1;
    s.finite = s.finite && std::isfinite(v2) && std::isfinite(p.x[i] + p.y[i] + p.z[i]);
  }
  return s;
}

TEST(Stability, SettledBedHeldAtRest) {
  // en = 0.5 so the pour comes to rest in 1.5e5 steps (0.25 s).
  const cdm::SceneSpec spec = cdm::load_scene(std::string(CDM_SOURCE_DIR) + "/bench/scenes/settle_1e4.toml",
                                              {{"integrator.end_time", "1.0"},
                                               {"contacts[0].en", "0.5"},
                                               {"contacts[1].en", "0.5"}});
  cdm::Simulation sim(spec);
  for (int k = 0; k < 150000; ++k) sim.step();
  const BedState start = measure(sim);
  std::printf("settled after %llu steps: KE = %.3e J, max speed = %.3e m/s\n",
              static_cast<unsigned long long>(sim.steps()), start.ke, start.vmax);
  ASSERT_TRUE(start.finite && start.inside);
  // Without rolling resistance a frictional bed never freezes completely: single
  // spheres keep rolling into holes of their neighbours (measured: max speeds of
  // 15-70 mm/s, mean speed ~1 mm/s, from 0.1 s to 0.5 s). What stability demands is
  // that no particle moves faster than a fall by its own diameter could make it,
  // sqrt(2 g d) = 0.14 m/s, and that the bed's kinetic energy does not grow.
  const double v_bound = std::sqrt(2.0 * 9.81 * 1e-3);
  std::vector<double> ke;
  double vmax = 0.0;
  for (int block = 0; block < 100; ++block) {  // 10^5 steps, checked every 1000
    for (int k = 0; k < 1000; ++k) sim.step();
    const BedState s = measure(sim);
    ASSERT_TRUE(s.finite) << "non-finite state at step " << sim.steps();
    ASSERT_TRUE(s.inside) << "a particle left the box at step " << sim.steps();
    ASSERT_LT(s.vmax, v_bound) << "step " << sim.steps();
    ke.push_back(s.ke);
    vmax = std::max(vmax, s.vmax);
  }
  double first = 0.0, last = 0.0, peak = 0.0;
  for (int b = 0; b < 20; ++b) { first += ke[b] / 20; last += ke[80 + b] / 20; }
  for (double e : ke) peak = std::max(peak, e);
  std::printf("held 1e5 steps: mean KE first/last 2e4 steps %.3e / %.3e J, peak %.3e J, max speed %.3e m/s\n", first,
              last, peak, vmax);
  EXPECT_LE(last, first) << "the bed's kinetic energy grew while it was held";
  EXPECT_LE(peak, 3.0 * start.ke) << "kinetic energy spiked above 3x its value when holding began";
}

}  // namespace
