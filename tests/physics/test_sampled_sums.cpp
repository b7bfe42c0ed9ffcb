// The run log's sums over the particles (counted_sums.hpp): within n 2^-61 of each sum's
// Σ|term|, each sum on its own scale, however skewed the terms.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cdm/solver/io/thermo_log.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"
#include "scene_text.hpp"

namespace {

// 20 x 20 x 25 = 10,000 spheres apart from each other, with friction (so with spins).
const std::string scene = cdm_test::scene_head({.mu = 0.5}) + cdm_test::floor_wall() + R"(
[[lattices]]
material = "glass"
radius = 0.0005
origin = [0.001, 0.001, 0.001]
spacing = [0.0015, 0.0015, 0.0015]
count = [20, 20, 25]
[integrator]
scheme = "velocity_verlet"
dt = "auto"
end_time = 0.001
)";

struct Exact {
  long double trans = 0.0L, rot = 0.0L;
};

Exact exact_energies(const cdm::ParticleStore& p) {
  Exact e;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const long double v2 = static_cast<long double>(p.vx[i]) * p.vx[i] + static_cast<long double>(p.vy[i]) * p.vy[i] +
                           static_cast<long double>(p.vz[i]) * p.vz[i];
    const long double w2 = static_cast<long double>(p.wx[i]) * p.wx[i] + static_cast<long double>(p.wy[i]) * p.wy[i] +
                           static_cast<long double>(p.wz[i]) * p.wz[i];
    e.trans += 0.5L * p.mass[i] * v2;
    e.rot += 0.5L / p.inv_inertia[i] * w2;
  }
  return e;
}

// One fast sphere among slow ones, and spins a trillion times weaker than the motion:
// each energy within n 2^-61 of itself (its terms are positive, so Σ|term| is the sum).
TEST(SampledSums, EachEnergyWithinItsOwnBoundHoweverSkewed) {
  cdm::Simulation sim(cdm::load_scene_from_string(scene, "sums.toml"));
  {
    cdm::ParticleStore& p = sim.particles();
    ASSERT_TRUE(p.has_rotation());
    for (std::size_t i = 0; i < p.size(); ++i) {
      const double s = 1.0 + 0.37 * std::sin(1.3 * static_cast<double>(i));
      p.vx[i] = 1e-4 * s; p.vy[i] = -2e-4 * s; p.vz[i] = 3e-4 * s;
      p.wx[i] = 1e-6 * s; p.wy[i] = 2e-6 * s; p.wz[i] = -1e-6 * s;
    }
    p.vz[4321] = 25.0;  // about 10^8 times the others' energy each
  }
  const cdm::ThermoSample s = cdm::thermo_sample(sim);
  const Exact e = exact_energies(sim.particles());
  const double n = static_cast<double>(sim.particles().size());
  const double tol = n * std::ldexp(1.0, -61);
  EXPECT_LE(std::abs(s.kinetic_translational - static_cast<double>(e.trans)), tol * static_cast<double>(e.trans));
  EXPECT_LE(std::abs(s.kinetic_rotational - static_cast<double>(e.rot)), tol * static_cast<double>(e.rot));
  // The test means something: the spins' energy is far below the motion's.
  EXPECT_LT(e.rot, 1e-12L * e.trans);
}

}  // namespace
