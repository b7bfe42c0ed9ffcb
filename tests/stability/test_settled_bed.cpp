// A settled bed of 10^4 frictional particles held at rest for 10^5 steps: the maximum
// speed stays under a stated bound, no particle leaves the box, every value stays
// finite, and the kinetic energy does not grow. The bed is the benchmark's settle
// problem (bench/scenes/settle_1e4.toml: 10,000 spheres poured from a lattice with
// random velocities) run until it has come to rest.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

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
  const cdm::SceneSpec spec = cdm::load_scene(std::string(CDM_SOURCE_DIR) + "/bench/scenes/settle_1e4.toml",
                                              {{"integrator.end_time", "1.0"},
                                               {"contacts[0].en", "0.5"},
                                               {"contacts[1].en", "0.5"}});
  cdm::Simulation sim(spec);
  // Pour and settle: 150,000 steps (0.24 s).
  for (int k = 0; k < 100000; ++k) sim.step();
  const BedState start = measure(sim);
  std::printf("settled after %llu steps: KE = %.3e J, max speed = %.3e m/s\n",
              static_cast<unsigned long long>(sim.steps()), start.ke, start.vmax);
  ASSERT_TRUE(start.finite && start.inside);
  // "At rest": the speed a particle would gain falling 1 % of its diameter,
  // sqrt(2 g 0.01 d) = 14 mm/s, bounds every particle's speed.
  const double v_bound = std::sqrt(2.0 * 9.81 * 0.01 * 1e-3);
  EXPECT_LT(start.vmax, v_bound) << "the bed has not come to rest";
  double ke_prev = start.ke;
  int ke_rises = 0;
  for (int block = 0; block < 100; ++block) {  // 10^5 steps, checked every 1000
    for (int k = 0; k < 1000; ++k) sim.step();
    const BedState s = measure(sim);
    std::printf("block %d KE %.4e vmax %.4e\n", block, s.ke, s.vmax);
    ASSERT_TRUE(s.finite) << "non-finite state at step " << sim.steps();
    ASSERT_TRUE(s.inside) << "a particle left the box at step " << sim.steps();
    EXPECT_LT(s.vmax, v_bound) << "step " << sim.steps();
    // Kinetic energy may not grow: it stays below its value when holding began, and
    // rises between checks only at round-off level (at most 10 of 100 blocks).
    EXPECT_LE(s.ke, start.ke) << "step " << sim.steps();
    if (s.ke > ke_prev * (1.0 + 1e-9)) ++ke_rises;
    ke_prev = s.ke;
  }
  const BedState end = measure(sim);
  std::printf("after holding 1e5 steps: KE = %.3e J, max speed = %.3e m/s, KE rose in %d of 100 blocks\n", end.ke,
              end.vmax, ke_rises);
  EXPECT_LE(ke_rises, 10);
}

}  // namespace
