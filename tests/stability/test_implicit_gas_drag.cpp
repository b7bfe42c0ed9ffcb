// A dense homogeneous suspension whose gas relaxes to the particles far faster than its
// flow asks for a step: 100 µm glass (2500 kg/m³) on a lattice of 9 × 9 × 9 per gas cell
// (ε_g = 0.618) in a gas of 1.2 kg/m³ and 1.8e-4 Pa·s, a 3 mm periodic box of 3³ cells,
// Wen–Yu drag, two-way coupling, the mixture's weight carried by a mean pressure
// gradient. The explicit drag on the gas is stable only for a gas step below
// 2 ε_g ρ_g/β (≈ 3.7 µs); treated implicitly (coupling.gas_drag = "implicit") it must
// stay bounded at gas steps 10–100 times that, reach the drag law's steady slip, and
// keep the momentum exchanged equal and opposite to round-off every gas step.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cdm/oracles/suspension.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"
#include "scene_text.hpp"

namespace {

constexpr double eps_s = 729.0 * 3.14159265358979323846 / 6.0 * 1e-12 / 1e-9;  // 9³ spheres of 100 µm per mm³

cdm::oracles::SuspensionParams params() {
  cdm::oracles::SuspensionParams p;
  p.d = 1e-4; p.rho_p = 2500.0; p.rho_g = 1.2; p.mu_g = 1.8e-4; p.eps_g = 1.0 - eps_s; p.g = 9.80665;
  return p;
}

std::string scene(const std::string& gas_drag, double dtg, double end) {
  const double G = cdm::oracles::suspension_pressure_gradient(params());
  char buf[64];
  auto num = [&](double x) { std::snprintf(buf, sizeof buf, "%.17g", x); return std::string(buf); };
  return R"(
units = "SI"
[modules]
gravity = true
gas = "solved"
drag = "wen_yu"
pressure_gradient = true
[gravity]
g = [0.0, -9.80665, 0.0]
[gas]
lower = [0.0, 0.0, 0.0]
upper = [0.003, 0.003, 0.003]
cells = [3, 3, 3]
density = 1.2
viscosity = 1.8e-4
dt = )" + num(dtg) + R"(
advection = "upwind"
mean_pressure_gradient = [0.0, )" + num(-G) + R"(, 0.0]
interpolation = "trilinear"
)" + cdm_test::periodic_gas_boundaries + R"([coupling]
mode = "two_way"
kernel = "trilinear"
gas_drag = ")" + gas_drag + R"("
[drag]
update = "exponential"
[[materials]]
name = "particle"
density = 2500.0
[[lattices]]
material = "particle"
radius = 5.0e-5
origin = [5.5555555555555556e-5, 5.5555555555555556e-5, 5.5555555555555556e-5]
spacing = [1.1111111111111111e-4, 1.1111111111111111e-4, 1.1111111111111111e-4]
count = [27, 27, 27]
[integrator]
scheme = "velocity_verlet"
dt = )" + num(dtg) + R"(
end_time = )" + num(end) + "\n";
}

struct Means {
  double U = 0.0, V = 0.0;
};

Means means(const cdm::Simulation& sim) {
  const cdm::fluid::GasField& g = *sim.gas();
  const cdm::fluid::StaggeredGrid& gr = g.grid();
  Means m;
  int n = 0;
  for (int k = 0; k < gr.n(2); ++k)
    for (int j = 0; j < gr.n(1); ++j)
      for (int i = 0; i < gr.n(0); ++i) { m.U += g.v[gr.at(i, j, k)]; ++n; }
  m.U /= n;
  const cdm::ParticleStore& p = sim.particles();
  for (std::size_t i = 0; i < p.size(); ++i) m.V += p.vy[i];
  m.V /= static_cast<double>(p.size());
  return m;
}

}  // namespace

TEST(Stability, DenseSuspensionImplicitGasDragBoundedFarAboveTheExplicitLimit) {
  const cdm::oracles::SuspensionSteady st = cdm::oracles::suspension_steady(params());
  const double limit = 2.0 * (1.0 - eps_s) * 1.2 / st.beta;  // the explicit drag's gas-step limit
  for (double factor : {10.0, 30.0, 100.0}) {
    const double dtg = factor * limit;
    SCOPED_TRACE("gas dt = " + std::to_string(factor) + " x the explicit limit");
    cdm::Simulation sim(cdm::load_scene_from_string(scene("implicit", dtg, 150 * dtg), "dense_suspension"));
    double worst_balance = 0.0, scale = 0.0;
    while (sim.steps() < sim.total_steps()) {
      sim.step();
      const Means m = means(sim);
      ASSERT_TRUE(std::isfinite(m.U) && std::isfinite(m.V));
      // Never further from the steady slip than at rest.
      ASSERT_LE(std::abs(m.U - m.V - st.slip), st.slip * (1.0 + 1e-9));
      const auto& b = sim.coupling_balance();
      worst_balance = std::max(worst_balance, std::abs(b.particles.y + b.gas_faces.y));
      scale = std::max(scale, std::abs(b.particles.y));
    }
    const Means m = means(sim);
    std::printf("gas dt %.3g s (%.0f x limit %.3g s): slip %.9g m/s, steady %.9g (rel %.2e), balance %.2e of %.2e N s\n",
                dtg, factor, limit, m.U - m.V, st.slip, (m.U - m.V - st.slip) / st.slip, worst_balance, scale);
    EXPECT_NEAR(m.U - m.V, st.slip, 1e-6 * st.slip);
    EXPECT_LE(worst_balance, 1e-12 * scale);
  }
}

TEST(Stability, DenseSuspensionExplicitGasDragStoppedAboveItsLimit) {
  // The same suspension at 10 times the explicit limit with the explicit treatment: the
  // guard stops it, naming the limit and the key that lifts it.
  const cdm::oracles::SuspensionSteady st = cdm::oracles::suspension_steady(params());
  const double dtg = 10.0 * 2.0 * (1.0 - eps_s) * 1.2 / st.beta;
  cdm::Simulation sim(cdm::load_scene_from_string(scene("explicit", dtg, 150 * dtg), "dense_suspension"));
  try {
    while (sim.steps() < sim.total_steps()) sim.step();
    FAIL() << "the explicit drag ran stable at 10 times its limit";
  } catch (const cdm::SimulationError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("2 eps_g rho_g / beta"), std::string::npos) << m;
    EXPECT_NE(m.find("coupling.gas_drag"), std::string::npos) << m;
  }
}
