// Physical-law checks of the contact model, independent of any stored number:
// restitution from the velocity ratio of a head-on collision, energy conservation at
// en = 1, momentum conservation, the Coulomb limit and the tangent-plane projection.
#include <gtest/gtest.h>

#include <cmath>

#include "cdm/solver/contact/linear_spring_dashpot.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"

namespace {

std::string pair_scene(double en, const std::string& scheme, double r2, double v) {
  return R"(
units = "SI"
[modules]
normal_contact = "linear_spring_dashpot"
[[materials]]
name = "a"
density = 2500.0
[[contacts]]
pair = ["a", "a"]
kn = 1000.0
en = )" + std::to_string(en) + R"(
[[particles]]
material = "a"
radius = 1e-3
position = [0.0, 0.0, 0.0]
velocity = [)" + std::to_string(v) + R"(, 0.0, 0.0]
[[particles]]
material = "a"
radius = )" + std::to_string(r2) + R"(
position = [3.5e-3, 0.0, 0.0]
velocity = [0.0, 0.0, 0.0]
[integrator]
scheme = ")" + scheme + R"("
dt = "auto"
dt_divisor = 400
end_time = 0.02
)";
}

struct Outcome { double e_measured, momentum_change, energy_ratio; };

Outcome collide(double en, const std::string& scheme, double r2) {
  const cdm::SceneSpec spec = cdm::load_scene_from_string(pair_scene(en, scheme, r2, 0.5), "pair.toml");
  cdm::Simulation sim(spec);
  const auto& p = sim.particles();
  const double m0 = p.mass[0], m1 = p.mass[1];
  const double p_before = m0 * p.vx[0] + m1 * p.vx[1];
  const double ke_before = 0.5 * (m0 * p.vx[0] * p.vx[0] + m1 * p.vx[1] * p.vx[1]);
  const double rel_before = p.vx[0] - p.vx[1];
  sim.run();
  EXPECT_EQ(sim.contact()->active_contacts(), 0u) << "particles still in contact at the end";
  const double rel_after = p.vx[0] - p.vx[1];
  const double ke_after = 0.5 * (m0 * p.vx[0] * p.vx[0] + m1 * p.vx[1] * p.vx[1]);
  return {-rel_after / rel_before, (m0 * p.vx[0] + m1 * p.vx[1]) - p_before, ke_after / ke_before};
}

TEST(ContactLaw, RestitutionFromVelocityRatio) {
  // eq 29 makes the linear spring-dashpot's rebound/impact speed ratio exactly en for
  // the pair's effective mass; the measured ratio converges to it with dt (t_col/400 here).
  for (const char* scheme : {"paper_euler", "velocity_verlet"})
    for (double r2 : {1e-3, 0.5e-3})  // equal and unequal masses (m_eff matters)
      for (double en : {0.1, 0.5, 0.9, 1.0}) {
        const Outcome o = collide(en, scheme, r2);
        // First-order Euler carries an O(dt eta_n/m) error that grows with damping
        // (1.6 % at en = 0.1 and t_col/400); the second-order scheme is 4x tighter.
        const double tol = std::string(scheme) == "paper_euler" ? 2e-2 : 5e-3;
        EXPECT_NEAR(o.e_measured, en, tol * en) << scheme << " r2=" << r2 << " en=" << en;
        EXPECT_NEAR(o.momentum_change, 0.0, 1e-15) << "momentum must be conserved to round-off";
      }
}

TEST(ContactLaw, ElasticCollisionConservesEnergy) {
  const Outcome o = collide(1.0, "velocity_verlet", 0.7e-3);
  EXPECT_NEAR(o.energy_ratio, 1.0, 1e-5);
}

TEST(ContactLaw, CoulombLimitCapsTangentialForce) {
  const cdm::Vec3 vt{0.2, 0.0, 0.0};
  const cdm::Vec3 delta{1e-3, 0.0, 0.0};
  bool sliding = false;
  // Spring force 1000 N/m * 1e-3 m = 1 N > mu Fn = 0.5 * 1 N: slides, F = -mu Fn vt/|vt|.
  const cdm::Vec3 f = cdm::contact::tangential_force(1000.0, 0.0, 0.5, 1.0, delta, vt, &sliding);
  EXPECT_TRUE(sliding);
  EXPECT_DOUBLE_EQ(f.x, -0.5);
  EXPECT_DOUBLE_EQ(f.y, 0.0);
  // Below the limit the spring-dashpot force stands.
  const cdm::Vec3 g = cdm::contact::tangential_force(1000.0, 0.1, 5.0, 1.0, delta, vt, &sliding);
  EXPECT_FALSE(sliding);
  EXPECT_DOUBLE_EQ(g.x, -1.0 - 0.02);
  // Zero tangential velocity while sliding: the force opposes the displacement.
  const cdm::Vec3 h = cdm::contact::tangential_force(1000.0, 0.0, 0.5, 1.0, {0.0, 0.0, -2e-3}, {}, &sliding);
  EXPECT_TRUE(sliding);
  EXPECT_DOUBLE_EQ(h.z, 0.5);
}

TEST(ContactLaw, TangentialDisplacementStaysInTangentPlane) {
  const cdm::Vec3 eta{0.0, 1.0, 0.0};
  // An old displacement with a normal component is projected out (eqs 15-16).
  const cdm::Vec3 d = cdm::contact::update_tangential_displacement({1e-4, 5e-5, 0.0}, false, {0.1, 0.0, 0.2}, 0.0,
                                                                   1e-6, 1e-3, eta);
  EXPECT_DOUBLE_EQ(d.y, 0.0);
  EXPECT_DOUBLE_EQ(d.x, 1e-4 + 1e-4);
  EXPECT_DOUBLE_EQ(d.z, 2e-4);
  // At contact start: Vt * min(|dn|/|Vn|, dt) (eq 14).
  const cdm::Vec3 s = cdm::contact::update_tangential_displacement({}, true, {1.0, 0.0, 0.0}, 2.0, 1e-6, 1e-3, eta);
  EXPECT_DOUBLE_EQ(s.x, 0.5e-6);
}

TEST(ContactLaw, LinearKernelAssemblesEq10And11) {
  // The kernel the contact module calls per contact. Normal along +x, approaching at
  // 0.1 m/s with 0.3 m/s of sliding along y; kn = 1000 N/m, eta_n = 2 kg/s, delta = 1 um.
  namespace lsd = cdm::contact::linear_spring_dashpot;
  const lsd::Params pp{1000.0, 0.4, 0.5, 0.3};
  const cdm::contact::ContactGeometry g{1e-6, {1.0, 0.0, 0.0}, {0.1, 0.3, 0.0}, {0.1, 0.3, 0.0}};
  // Frictionless: F_n = -(kn delta + eta_n V.eta) eta = -(1e-3 + 0.2) x.
  const cdm::contact::ContactForce n = lsd::force<false>(pp, 2.0, g, 2e-5, {});
  EXPECT_DOUBLE_EQ(n.total.x, -(1e-3 + 0.2));
  EXPECT_EQ(n.total.y, 0.0);
  EXPECT_DOUBLE_EQ(n.normal_magnitude, 1e-3 + 0.2);
  EXPECT_EQ(norm(n.tangential), 0.0);
  // With friction, a new contact: delta_t = V_t min(delta/V_n, dt) = 0.3 * 1e-5 along y (dt = 2e-5),
  // F_t = -kt delta_t - eta_t V_t = -(400 * 3e-6 + 1 * 0.3) = -0.3012 > mu |F_n| = 0.0603:
  // sliding, F_t = -mu |F_n| along V_t.
  cdm::Vec3 hist{};
  std::uint8_t touching = 0;
  const cdm::contact::ContactForce f = lsd::force<true>(pp, 2.0, g, 2e-5, {&hist, &touching});
  EXPECT_EQ(touching, 1);
  EXPECT_DOUBLE_EQ(hist.y, 0.3 * 1e-5);
  EXPECT_DOUBLE_EQ(f.tangential.y, -0.3 * (1e-3 + 0.2));
  EXPECT_DOUBLE_EQ(f.total.x, n.total.x);
  EXPECT_DOUBLE_EQ(f.total.y, f.tangential.y);
}

}  // namespace
