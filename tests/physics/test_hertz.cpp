// Hertz–Mindlin and rolling resistance: the force laws (and the kernel the solver calls) against hand-computed
// values and the published equations (the oracles, for what needs an ODE), and
// physical laws of whole runs: restitution from the velocity ratio, conservation of
// momentum, energy and angular momentum. And: the linear model's results do not depend
// on which other laws a scene defines (its kernel is the same in every variant).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "cdm/oracles/hertz_impact.hpp"
#include "cdm/solver/contact/hertz_mindlin.hpp"
#include "cdm/solver/contact/rolling_resistance.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"

namespace {

using cdm::Vec3;
namespace contact = cdm::contact;

TEST(HertzLaw, EffectiveModuliAndForces) {
  // Glass on glass: E* = E/(2(1 - nu^2)) = 70e9/1.875, G = E/2.5 = 28e9, G* = G/(2(2 - nu)) = 8e9.
  EXPECT_DOUBLE_EQ(contact::effective_youngs_modulus(70e9, 0.25, 70e9, 0.25), 70e9 / 1.875);
  EXPECT_DOUBLE_EQ(contact::shear_modulus(70e9, 0.25), 28e9);
  EXPECT_NEAR(contact::effective_shear_modulus(70e9, 0.25, 70e9, 0.25), 8e9, 1e-6);
  // Alumina on glass (MFIX DEM05): 1/E* = 0.9471/380e9 + 0.9375/70e9.
  EXPECT_NEAR(contact::effective_youngs_modulus(380e9, 0.23, 70e9, 0.25), 1.0 / (0.9471 / 380e9 + 0.9375 / 70e9), 1.0);
  // K = 4/3 E* sqrt(R*); F = K d^(3/2); k_t = 8 G* sqrt(R* d).
  const double k = contact::hertz_constant(3.0e10, 4.0e-3);
  EXPECT_DOUBLE_EQ(k, 4.0 / 3.0 * 3.0e10 * std::sqrt(4.0e-3));
  EXPECT_NEAR(contact::hertz_elastic_force(k, 1.0e-6), k * 1.0e-9, 1e-12 * k * 1e-9);
  EXPECT_NEAR(contact::mindlin_stiffness(8.0e9, 4.0e-3, 1.0e-6), 8.0 * 8.0e9 * std::sqrt(4.0e-9), 1e-3);
  // Dashpot eta_n = alpha sqrt(m* K) d^(1/4).
  EXPECT_NEAR(contact::hertz_normal_damping(0.5, 2.0e-3, k, 1.0e-8), 0.5 * std::sqrt(2.0e-3 * k) * 1.0e-2, 1e-12);
}

TEST(HertzLaw, KernelAssemblesTheLaw) {
  // The kernel the contact module calls per contact, from the functions above:
  // F_n = -K d^(3/2) eta - eta_n V_n, k_t = 8 G* sqrt(R* d), eta_t = etat_factor eta_n.
  namespace hm = contact::hertz_mindlin;
  const hm::Params pp{3.0e10, 8.0e9, 0.5, 0.8, 0.4};
  const double m = 2.0e-3, r = 4.0e-3, d = 1.0e-8, dt = 1e-8;
  const contact::ContactGeometry g{d, {0.0, 0.0, 1.0}, {0.0, 0.01, 0.2}, {0.0, 0.01, 0.2}};
  const double k = contact::hertz_constant(pp.e_star, r);
  const double eta_n = contact::hertz_normal_damping(pp.alpha, m, k, d);
  const double fn = contact::hertz_elastic_force(k, d) + eta_n * 0.2;
  const contact::ContactForce n = hm::force<false>(pp, m, r, g, dt, {});
  EXPECT_DOUBLE_EQ(n.total.z, -fn);
  EXPECT_EQ(n.total.y, 0.0);
  EXPECT_DOUBLE_EQ(n.normal_magnitude, fn);
  // A new contact sticking: delta_t = V_t min(d/V_n, dt) = 0.01 dt along y.
  Vec3 hist{};
  std::uint8_t touching = 0;
  const contact::ContactForce f = hm::force<true>(pp, m, r, g, dt, {&hist, &touching});
  const double kt = contact::mindlin_stiffness(pp.g_star, r, d);
  EXPECT_EQ(touching, 1);
  EXPECT_DOUBLE_EQ(hist.y, 0.01 * dt);
  EXPECT_DOUBLE_EQ(f.tangential.y, -kt * 0.01 * dt - pp.etat_factor * eta_n * 0.01);
  EXPECT_LT(std::abs(f.tangential.y), pp.mu * fn);
  EXPECT_DOUBLE_EQ(f.total.z, n.total.z);
}

TEST(HertzLaw, DampingFormsAndRestitution) {
  // No damping for an elastic contact; exact alpha = sqrt(5)|ln e|/sqrt(pi^2 + ln^2 e).
  EXPECT_EQ(contact::hertz_alpha_exact(1.0), 0.0);
  const double l = std::log(0.5);
  EXPECT_DOUBLE_EQ(contact::hertz_alpha_exact(0.5), std::sqrt(5.0) * -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l));
  for (double e : {0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99}) {
    // The closed form reproduces e when the damped Hertz equation is integrated by CVODE
    // (rtol 1e-12): Antypov & Elliott's result, checked independently.
    EXPECT_NEAR(cdm::oracles::hertz_restitution(contact::hertz_alpha_exact(e)), e, 1e-8 * e) << "e = " << e;
    // Marshall's fit of Tsuji's curve is an approximation: within 0.6 % over 0.1 ... 1.
    if (e >= 0.1) {
      EXPECT_NEAR(cdm::oracles::hertz_restitution(contact::hertz_alpha_tsuji(e)), e, 6e-3 * e) << "e = " << e;
    }
  }
}

TEST(HertzLaw, CollisionTimeAgreesWithJohnson) {
  // The solver's t_H = 2.868 (...)^(1/5) (for dt = auto) against the oracle's exact
  // constant 2 (15/16)^(2/5) (2/5) B(2/5, 1/2) = 2.8682.
  cdm::oracles::HertzImpactParams p{1.3e-3, 5e-3, 3.7e10, 1.0, 0.0};
  EXPECT_NEAR(contact::hertz_collision_time(p.m_eff, p.r_eff, p.e_star, p.v),
              cdm::oracles::hertz_closed_form(p).contact_time, 1e-4 * cdm::oracles::hertz_closed_form(p).contact_time);
  // Rayleigh time of glass, R = 5 mm: pi R sqrt(rho/G)/(0.1631 nu + 0.8766).
  EXPECT_NEAR(contact::rayleigh_time(5e-3, 2500.0, 70e9, 0.25), std::numbers::pi * 5e-3 * std::sqrt(2500.0 / 28e9) / 0.917375,
              1e-18);
}

TEST(HertzLaw, MindlinCoulombLimitRescalesHistory) {
  // Spring 1000 N/m x 1 mm = 1 N > mu Fn = 0.5 N: slides; force -0.5 N along the
  // history, history rescaled to hold exactly mu Fn / kt; no dashpot.
  Vec3 hist{1e-3, 0.0, 0.0};
  bool sliding = false;
  const Vec3 f = contact::mindlin_tangential_force(1000.0, 3.0, 0.5, 1.0, hist, {0.2, 0.0, 0.0}, &sliding);
  EXPECT_TRUE(sliding);
  EXPECT_DOUBLE_EQ(f.x, -0.5);
  EXPECT_DOUBLE_EQ(hist.x, 5e-4);
  // Below the limit: spring plus dashpot, history untouched.
  Vec3 h2{1e-4, 0.0, -1e-4};
  const Vec3 g = contact::mindlin_tangential_force(1000.0, 3.0, 0.5, 1.0, h2, {0.01, 0.0, 0.0}, &sliding);
  EXPECT_FALSE(sliding);
  EXPECT_DOUBLE_EQ(g.x, -0.1 - 0.03);
  EXPECT_DOUBLE_EQ(g.z, 0.1);
  EXPECT_DOUBLE_EQ(h2.x, 1e-4);
  // No normal force: no friction, history emptied.
  Vec3 h3{2e-4, 0.0, 0.0};
  const Vec3 z = contact::mindlin_tangential_force(1000.0, 0.0, 0.5, 0.0, h3, {}, &sliding);
  EXPECT_TRUE(sliding);
  EXPECT_EQ(z.x, 0.0);
  EXPECT_EQ(h3.x, 0.0);
}

TEST(RollingTorque, OpposesRollingAndStopsWithoutOvershoot) {
  const Vec3 eta{0.0, -1.0, 0.0};  // contact below the particle (a floor)
  // Fast rolling about z: the full mu_r R* Fn against it.
  const Vec3 t = contact::rolling_torque(0.1, 1e-3, 2.0, {0.0, 0.0, 50.0}, eta, 1e-9, 1e-6);
  EXPECT_DOUBLE_EQ(t.z, -0.1 * 1e-3 * 2.0);
  EXPECT_EQ(t.x, 0.0);
  // Twisting (about the normal) is not resisted; only the tangent-plane part counts.
  EXPECT_EQ(norm(contact::rolling_torque(0.1, 1e-3, 2.0, {0.0, 7.0, 0.0}, eta, 1e-9, 1e-6)), 0.0);
  const Vec3 mixed = contact::rolling_torque(0.1, 1e-3, 2.0, {3.0, 7.0, 4.0}, eta, 1e-9, 1e-6);
  EXPECT_NEAR(mixed.x, -2e-4 * 0.6, 1e-18);
  EXPECT_NEAR(mixed.z, -2e-4 * 0.8, 1e-18);
  EXPECT_EQ(mixed.y, 0.0);
  // Slow enough to stop within the step: exactly the torque that stops it, w + dt T/I = 0.
  const double inertia = 1e-9, dt = 1e-6, w = 0.05;  // I w/dt = 5e-5 < 2e-4
  const Vec3 s = contact::rolling_torque(0.1, 1e-3, 2.0, {w, 0.0, 0.0}, eta, inertia, dt);
  EXPECT_NEAR(w + dt * s.x / inertia, 0.0, 1e-15 * w);
  EXPECT_LT(std::abs(s.x), 0.1 * 1e-3 * 2.0);
  // At rest: nothing.
  EXPECT_EQ(norm(contact::rolling_torque(0.1, 1e-3, 2.0, {}, eta, inertia, dt)), 0.0);
}

// Two spheres head on; returns (restitution, momentum change, kinetic energy ratio).
struct Outcome {
  double e, dp, energy;
};

std::string hertz_pair_scene(double en, const std::string& damping, double r2, const std::string& scheme) {
  return R"(
units = "SI"
[modules]
normal_contact = "hertz_mindlin"
[[materials]]
name = "a"
density = 2500.0
youngs_modulus = 7.0e10
poisson_ratio = 0.25
[[contacts]]
pair = ["a", "a"]
en = )" + std::to_string(en) + R"(
damping = ")" + damping + R"("
[[particles]]
material = "a"
radius = 1e-3
position = [0.0, 0.0, 0.0]
velocity = [0.5, 0.0, 0.0]
[[particles]]
material = "a"
radius = )" + std::to_string(r2) + R"(
position = [)" + std::to_string(1e-3 + r2 + 1e-6) + R"(, 0.0, 0.0]
velocity = [-0.5, 0.0, 0.0]
[integrator]
scheme = ")" + scheme + R"("
dt = "auto"
impact_velocity = 1.0
dt_divisor = 400
end_time = 3.0e-5
)";
}

Outcome collide(const std::string& text) {
  cdm::Simulation sim(cdm::load_scene_from_string(text, "pair.toml"));
  const auto& p = sim.particles();
  const double m0 = p.mass[0], m1 = p.mass[1];
  const double p0 = m0 * p.vx[0] + m1 * p.vx[1];
  const double ke0 = 0.5 * (m0 * p.vx[0] * p.vx[0] + m1 * p.vx[1] * p.vx[1]);
  const double rel0 = p.vx[0] - p.vx[1];
  sim.run();
  EXPECT_EQ(sim.contact()->active_contacts(), 0u) << "still in contact at the end";
  const double ke1 = 0.5 * (m0 * p.vx[0] * p.vx[0] + m1 * p.vx[1] * p.vx[1]);
  return {-(p.vx[0] - p.vx[1]) / rel0, m0 * p.vx[0] + m1 * p.vx[1] - p0, ke1 / ke0};
}

TEST(HertzPhysics, RestitutionFromVelocityRatio) {
  // The exact dashpot gives the asked-for restitution for any pair of masses (m* enters
  // alpha sqrt(m* K)); the rebound/impact speed ratio converges to it with dt.
  for (const char* scheme : {"paper_euler", "velocity_verlet"})
    for (double r2 : {1e-3, 0.6e-3})
      for (double en : {0.3, 0.7, 0.95}) {
        const Outcome o = collide(hertz_pair_scene(en, "exact_restitution", r2, scheme));
        // t_H/400: the first-order scheme's explicit dashpot is within 0.6 %, velocity Verlet 0.2 %.
        const double tol = std::string(scheme) == "paper_euler" ? 6e-3 : 2e-3;
        EXPECT_NEAR(o.e, en, tol * en) << scheme << " r2 = " << r2 << " en = " << en;
        EXPECT_NEAR(o.dp, 0.0, 1e-17) << "momentum must be conserved to round-off";
      }
}

TEST(HertzPhysics, ElasticCollisionConservesEnergy) {
  for (const char* scheme : {"paper_euler", "velocity_verlet"}) {
    const Outcome o = collide(hertz_pair_scene(1.0, "exact_restitution", 0.7e-3, scheme));
    EXPECT_NEAR(o.energy, 1.0, 1e-6) << scheme;
    EXPECT_NEAR(o.e, 1.0, 1e-6) << scheme;
  }
}

// An oblique frictional collision of two linear spring-dashpot spheres (history,
// Coulomb limit and torque all in play). @p extra adds materials and contacts that no
// particle uses, e.g. a Hertz–Mindlin pair, which switches the kernel to its mixed form.
std::string linear_oblique_scene(const std::string& scheme, const std::string& extra) {
  return R"(
units = "SI"
[modules]
normal_contact = "linear_spring_dashpot"
tangential = "spring_coulomb"
[[materials]]
name = "a"
density = 2500.0
)" + extra + R"(
[[contacts]]
pair = ["a", "a"]
kn = 1000.0
en = 0.8
mu = 0.3
[[particles]]
material = "a"
radius = 1e-3
position = [0.0, 0.0, 0.0]
velocity = [0.5, 0.2, 0.0]
angular_velocity = [0.0, 30.0, 10.0]
[[particles]]
material = "a"
radius = 0.8e-3
position = [2.0e-3, 1.0e-3, 0.0]
velocity = [-0.3, 0.0, 0.1]
[integrator]
scheme = ")" + scheme + R"("
dt = "auto"
dt_divisor = 100
end_time = 0.01
)";
}

TEST(LinearModel, UnchangedWhenOtherLawsAreDefined) {
  const std::string hertz_pair = R"(
[[materials]]
name = "h"
density = 3000.0
youngs_modulus = 1.0e9
poisson_ratio = 0.3
[[contacts]]
pair = ["h", "h"]
model = "hertz_mindlin"
en = 0.9
mu = 0.3
)";
  for (const char* scheme : {"paper_euler", "velocity_verlet"}) {
    cdm::Simulation a(cdm::load_scene_from_string(linear_oblique_scene(scheme, ""), "a.toml"));
    cdm::Simulation b(cdm::load_scene_from_string(linear_oblique_scene(scheme, hertz_pair), "b.toml"));
    ASSERT_EQ(a.module_names().front(), "linear_spring_dashpot+spring_coulomb");
    ASSERT_EQ(b.module_names().front(), "linear_spring_dashpot,hertz_mindlin+spring_coulomb");
    bool touched = false;
    for (std::uint64_t k = 0; k < a.total_steps(); ++k) {
      a.step();
      b.step();
      touched = touched || a.contact()->active_contacts() > 0;
      for (std::size_t i = 0; i < 2; ++i) {
        const auto& pa = a.particles();
        const auto& pb = b.particles();
        // Bit for bit: the same arithmetic in the linear-only and the mixed kernel.
        ASSERT_EQ(pa.x[i], pb.x[i]) << scheme << " step " << k;
        ASSERT_EQ(pa.vy[i], pb.vy[i]) << scheme << " step " << k;
        ASSERT_EQ(pa.wz[i], pb.wz[i]) << scheme << " step " << k;
      }
    }
    EXPECT_TRUE(touched) << "the spheres never met: the test checks nothing";
  }
}

TEST(RollingPhysics, PairTorquesConserveAngularMomentum) {
  // Two spheres pressed together, spinning about axes in their contact plane, no
  // friction: rolling resistance exerts equal and opposite torques, so the total spin
  // angular momentum is conserved while the relative rotation stops.
  const std::string scene = R"(
units = "SI"
[modules]
normal_contact = "hertz_mindlin"
rolling_resistance = "constant_torque"
[[materials]]
name = "a"
density = 2500.0
youngs_modulus = 1.0e8
poisson_ratio = 0.25
[[contacts]]
pair = ["a", "a"]
en = 0.5
rolling_mu = 0.2
[[particles]]
material = "a"
radius = 1e-3
position = [0.0, 0.0, 0.0]
angular_velocity = [0.0, 40.0, 25.0]
[[particles]]
material = "a"
radius = 0.7e-3
position = [1.69e-3, 0.0, 0.0]
angular_velocity = [0.0, -10.0, 5.0]
[integrator]
scheme = "velocity_verlet"
dt = "auto"
impact_velocity = 0.1
end_time = 0.02
[checks]
allow_initial_overlap = true
)";
  cdm::Simulation sim(cdm::load_scene_from_string(scene, "roll.toml"));
  const auto& p = sim.particles();
  auto spin_momentum = [&](int axis) {
    double s = 0.0;
    for (std::size_t i = 0; i < 2; ++i) {
      const double w = axis == 1 ? p.wy[i] : p.wz[i];
      s += w / p.inv_inertia[i];
    }
    return s;
  };
  const double ly0 = spin_momentum(1), lz0 = spin_momentum(2);
  const double rel0 = std::hypot(p.wy[0] - p.wy[1], p.wz[0] - p.wz[1]);
  sim.run();
  EXPECT_NEAR(spin_momentum(1), ly0, 1e-12 * std::abs(ly0));
  EXPECT_NEAR(spin_momentum(2), lz0, 1e-12 * std::abs(lz0));
  // The pair stays in contact (pressed by the initial overlap, en = 0.5 damps it apart
  // slowly) long enough to stop the relative rolling, and then holds it.
  const double rel = std::hypot(p.wy[0] - p.wy[1], p.wz[0] - p.wz[1]);
  EXPECT_LT(rel, 1e-12 * rel0) << "relative rolling should have stopped";
}

}  // namespace
