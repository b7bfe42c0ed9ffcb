// Checks of the Hertz and oblique-impact oracles themselves: the CVODE solutions
// against Hertz's closed forms, energy conservation of the elastic impact, the
// gross-sliding closed forms of the oblique impact, and agreement with themselves at a
// looser tolerance (an estimate of their own error, >= 100x below every tolerance).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "cdm/oracles/hertz_impact.hpp"
#include "cdm/oracles/oblique_impact.hpp"
#include "cdm/oracles/rolling_resistance.hpp"

namespace {

using namespace cdm::oracles;

TEST(HertzOracle, CvodeAgreesWithClosedForms) {
  const double m = 2500.0 * 4.0 / 3.0 * std::numbers::pi * 1.25e-7;
  const HertzImpactParams p{m, 5e-3, hertz_effective_modulus(7e10, 0.25, 7e10, 0.25), 1.0, 0.0};
  const HertzClosedForm c = hertz_closed_form(p);
  // Johnson's t_c = 2.868 (m*^2/(R* E*^2 v))^(1/5) to its printed digits.
  EXPECT_NEAR(c.contact_time, 2.868 * std::pow(m * m / (5e-3 * p.e_star * p.e_star), 0.2), 1e-4 * c.contact_time);
  std::vector<double> t;
  for (int k = -10; k <= 1000; ++k) t.push_back(1.2 * c.contact_time * k / 1000.0);
  const HertzSeries s = hertz_impact_cvode(p, t);
  EXPECT_NEAR(s.contact_time, c.contact_time, 1e-10 * c.contact_time);
  EXPECT_NEAR(s.max_overlap, c.max_overlap, 1e-10 * c.max_overlap);
  EXPECT_NEAR(s.exit_speed, 1.0, 1e-9);  // elastic: energy conserved
  double fmax = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    fmax = std::max(fmax, s.force[k]);
    if (t[k] <= 0.0 || t[k] >= c.contact_time) {
      EXPECT_EQ(s.force[k], 0.0) << "force outside the contact";
    }
  }
  EXPECT_NEAR(fmax, c.max_force, 1e-4 * c.max_force);  // sampled at 1/1000 of t_c
  // A looser tolerance changes the series by far less than any case tolerance (1e-5 of F_max).
  const HertzSeries loose = hertz_impact_cvode(p, t, 1e-10);
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_NEAR(loose.force[k], s.force[k], 1e-8 * c.max_force);
}

TEST(HertzOracle, RestitutionFallsWithDamping) {
  EXPECT_NEAR(hertz_restitution(0.0), 1.0, 1e-9);
  double last = 1.0;
  for (double a : {0.05, 0.2, 0.5, 1.0, 1.5}) {
    const double e = hertz_restitution(a);
    EXPECT_LT(e, last);
    EXPECT_GT(e, 0.0);
    last = e;
  }
  // Self-consistency: at rtol 1e-11 the result moves by ~1e-9 (the dashpot's d^(1/4)
  // at first touch and release keeps the global error above rtol), so the rtol-1e-12
  // solution the cases use is good to ~1e-9: 1e4 below the tightest restitution
  // tolerance (1e-5 % = 1e-7 relative).
  EXPECT_NEAR(hertz_restitution(0.7, nullptr, 1e-11), hertz_restitution(0.7), 2e-9);
}

ObliqueParams dem05(double angle) { return {2.5e-3, 4000.0, 380e9, 0.23, 70e9, 0.25, 0.092, 3.9, angle}; }

TEST(ObliqueOracle, GrossSlidingMatchesClosedForms) {
  int sliding = 0;
  for (double a = 30.0; a <= 85.0; a += 5.0) {
    const ObliqueResult r = oblique_impact_cvode(dem05(a));
    const ObliqueSliding c = oblique_sliding_closed_form(dem05(a));
    ASSERT_TRUE(r.slid_throughout) << a;
    ++sliding;
    EXPECT_NEAR(r.et, c.et, 1e-9) << a;
    EXPECT_NEAR(r.omega, c.omega_lever, 1e-8 * c.omega_lever) << a;
    EXPECT_NEAR(r.vn_after, 3.9 * std::cos(a * std::numbers::pi / 180.0), 1e-9) << a;
  }
  EXPECT_EQ(sliding, 12);
}

TEST(ObliqueOracle, StickingRegimeSwitchesAndIsSelfConsistent) {
  for (double a : {5.0, 10.0, 20.0, 25.0}) {
    const ObliqueResult r = oblique_impact_cvode(dem05(a));
    EXPECT_FALSE(r.slid_throughout) << a;
    EXPECT_GE(r.switches, 2) << a;
    // Friction only removes energy (the normal impact is elastic): the kinetic energy
    // after, translation and rotation (I = 2/5 m R^2), is below the energy before.
    const double th = a * std::numbers::pi / 180.0, vt = 3.9 * std::sin(th);
    EXPECT_LT(r.et, 1.0);
    EXPECT_LT(r.vt_after * r.vt_after + 0.4 * std::pow(r.omega * 2.5e-3, 2), vt * vt) << a;
    const ObliqueResult loose = oblique_impact_cvode(dem05(a), 1e-10);
    EXPECT_NEAR(loose.omega, r.omega, 1e-7 * 620.0) << a;  // 1e-5 % of the peak spin
    EXPECT_NEAR(loose.et, r.et, 1e-8) << a;  // the tightest e_t tolerance is 4e-5 (t_H/400)
  }
}

TEST(RollingOracle, ClosedForms) {
  const RollingParams p{5e-4, 0.1, 9.81};
  EXPECT_DOUBLE_EQ(rolling_deceleration(p, p.radius), 5.0 / 7.0 * 0.1 * 9.81);
  EXPECT_NEAR(rolling_velocity(p, 0.05, rolling_stop_time(p, 0.05)), 0.0, 1e-18);
  EXPECT_EQ(rolling_velocity(p, 0.05, 1.0), 0.0);
  EXPECT_NEAR(spinning_angular_velocity(p, 100.0, spinning_stop_time(p, 100.0)), 0.0, 1e-12);
}

}  // namespace
