// Stiff drag: a 20 µm particle falling through an upward gas stream (Garg et al. case 6
// physics with Schiller–Naumann drag and buoyancy) at steps from τ_p to 10⁴ τ_p. The
// explicit update must blow up past dt ≈ 2τ_p (τ_p with velocity Verlet) and be stopped by the solver's guard with
// a message naming τ_p/dt; the implicit and exponential updates must stay bounded and
// settle on the terminal velocity of the oracle (GSL root of the force balance).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "cdm/oracles/terminal_velocity.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"
#include "scene_text.hpp"

namespace {

// τ_p = ρ_p d²/(18 μ_g) = 2000 (2e-5)²/(18·1.8e-5) = 2.469e-3 s (Stokes; Re_p ≈ 0.04).
constexpr double tau_stokes = 2000.0 * 2e-5 * 2e-5 / (18.0 * 1.8e-5);

std::string scene(const std::string& update, const std::string& scheme, double dt) {
  return R"(
units = "SI"
[modules]
gravity = true
gas = "prescribed"
drag = "schiller_naumann"
pressure_gradient = true
[gravity]
g = [0.0, -9.80665, 0.0]
[gas]
lower = [0.0, 0.0, 0.0]
upper = [0.01, 0.01, 0.01]
cells = [4, 4, 4]
density = 1.2
viscosity = 1.8e-5
)" + cdm_test::periodic_gas_boundaries + R"([gas.field]
type = "uniform"
velocity = [0.0, 0.4, 0.0]
[drag]
update = ")" + update + R"("
[[materials]]
name = "p"
density = 2000.0
[[particles]]
material = "p"
radius = 1.0e-5
position = [0.005, 0.005, 0.005]
[integrator]
scheme = ")" + scheme + R"("
dt = )" + std::to_string(dt) + R"(
end_time = )" + std::to_string(200 * dt) + "\n";
}

TEST(Stability, StiffDragExplicitDivergesImplicitAndExponentialDoNot) {
  cdm::oracles::TerminalParams tp;
  tp.d = 2e-5; tp.rho_p = 2000.0; tp.rho_g = 1.2; tp.mu_g = 1.8e-5; tp.u_g = 0.4; tp.g = 9.80665;
  const double v_term = cdm::oracles::terminal_velocity(tp).velocity;
  for (const char* scheme : {"paper_euler", "velocity_verlet"})
    for (double ratio : {3.0, 1e-1, 1e-2, 1e-3, 1e-4}) {  // τ_p / dt
      const double dt = tau_stokes / ratio;
      for (const char* update : {"explicit", "implicit", "exponential"}) {
        cdm::Simulation sim(cdm::load_scene_from_string(scene(update, scheme, dt), "stiff_drag.toml"));
        const std::string what = std::string(scheme) + " " + update + " tau_p/dt = " + std::to_string(ratio);
        bool stopped = false;
        std::string message;
        double worst = 0.0;
        try {
          sim.run([&](const cdm::Simulation& s) {
            worst = std::max(worst, std::abs(s.particles().vy[0] - v_term));
          });
        } catch (const cdm::SimulationError& e) {
          stopped = true;
          message = e.what();
        }
        // Explicit limits: dt < 2τ_p (paper_euler), dt < τ_p (velocity_verlet's predictor).
        const bool explicit_unstable = std::string(update) == "explicit" && ratio < 0.5;
        if (explicit_unstable) {
          // |1 − dt/τ| > 1: the velocity error grows by ~dt/τ per step until it overflows.
          EXPECT_TRUE(stopped) << what << ": the explicit update should have diverged";
          EXPECT_NE(message.find("tau_p/dt"), std::string::npos) << what << ": " << message;
          EXPECT_NE(message.find("exponential"), std::string::npos) << what << ": the message must name the remedy";
          continue;
        }
        ASSERT_FALSE(stopped) << what << ": " << message;
        // Bounded: never further from the terminal velocity than at rest (|v_term| + 0).
        EXPECT_LE(worst, std::abs(v_term) * (1.0 + 1e-12)) << what;
        // Settled: after 200 steps of at least τ_p the velocity is the terminal one.
        EXPECT_LT(std::abs(sim.particles().vy[0] - v_term), 1e-6 * std::abs(v_term)) << what;
        EXPECT_TRUE(std::isfinite(sim.particles().y[0])) << what;
      }
    }
}

}  // namespace
