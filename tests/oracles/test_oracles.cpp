// Checks of the oracles themselves: the stacked-particle CVODE solution against a second,
// different method (the exact matrix-exponential solution of the same linear system),
// and the free-fall stage solution against its own continuity and limits.
#include <gtest/gtest.h>

#include <cmath>

#include "cdm/oracles/free_fall.hpp"
#include "cdm/oracles/slipping_ball.hpp"
#include "cdm/oracles/stacked.hpp"

namespace {

using namespace cdm::oracles;

const StackedParams case2(double en) { return {5e-4, 2e4, 1e4, 1e3, 1e3, en, 9.80665, 1.8e-3, 4.5e-4, 1.35e-3}; }

TEST(StackedOracle, CvodeAgreesWithExactSolution) {
  for (double en : {1.0, 0.8}) {
    std::vector<double> t;
    for (int k = 0; k <= 2000; ++k) t.push_back(1e-3 * k / 2000.0);
    const StackedSeries a = stacked_cvode(case2(en), t);
    const StackedSeries b = stacked_exact(case2(en), t);
    double worst = 0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      worst = std::max(worst, std::abs(a.y1[k] - b.y1[k]) / std::abs(b.y1[k]));
      worst = std::max(worst, std::abs(a.y2[k] - b.y2[k]) / std::abs(b.y2[k]));
    }
    // The harness's tightest stacked tolerance is 0.2 % (2e-3 relative); the oracle must
    // be >= 100x tighter. The two methods agree far below that.
    EXPECT_LT(worst, 1e-9) << "en = " << en;
    EXPECT_EQ(a.y1.front(), 4.5e-4);
  }
}

TEST(StackedOracle, ElasticSystemConservesEnergy) {
  const StackedParams p = case2(1.0);
  std::vector<double> t;
  for (int k = 0; k <= 200; ++k) t.push_back(1e-3 * k / 200.0);
  const StackedSeries s = stacked_cvode(p, t);
  const double d = 2 * p.radius, m1 = p.rho_lower * M_PI * d * d * d / 6, m2 = p.rho_upper * M_PI * d * d * d / 6;
  auto energy = [&](std::size_t k) {
    const double o1 = p.radius - s.y1[k], o12 = 2 * p.radius - (s.y2[k] - s.y1[k]), o2 = p.radius - (p.y_wall_top - s.y2[k]);
    return 0.5 * m1 * s.v1[k] * s.v1[k] + 0.5 * m2 * s.v2[k] * s.v2[k] + m1 * p.g * s.y1[k] + m2 * p.g * s.y2[k] +
           0.5 * p.kn_wall * (o1 * o1 + o2 * o2) + 0.5 * p.kn * o12 * o12;
  };
  const double e0 = energy(0);
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_NEAR(energy(k), e0, 1e-9 * std::abs(e0));
}

const FreeFallParams case1(double kn, double en) { return {0.1, 2600.0, 0.5, 9.80, kn, en}; }

TEST(FreeFallOracle, StagesAreContinuous) {
  for (double en : {1.0, 0.9, 0.7, 0.5}) {
    const FreeFall f(case1(5e4, en), 5.0);
    const auto& st = f.stages();
    ASSERT_GE(st.size(), 3u);
    for (std::size_t k = 1; k < st.size(); ++k) {
      const double t = st[k].t_start;
      // Position and velocity at the end of stage k-1 equal the start of stage k.
      EXPECT_NEAR(f.position(t - 1e-13), f.position(t), 1e-9);
      EXPECT_NEAR(st[k].y0, 0.1, 1e-12) << "stages change at y = r";
      if (k + 1 < st.size() || std::isfinite(st[k].t_end)) {
        EXPECT_NEAR(f.velocity(t - 1e-13), st[k].v0, 1e-8);
      }
    }
  }
}

TEST(FreeFallOracle, ContactDurationAndRestitution) {
  // Without gravity the linear spring-dashpot contact lasts exactly t_col (eq 28) and
  // returns en times the impact speed; with gravity (g t_col << v_c) both are close.
  const FreeFall f(case1(5e8, 0.7), 1.0);  // g t_col / v_c = 0.2 %
  const auto& c = f.stages()[1];
  ASSERT_TRUE(c.contact);
  EXPECT_NEAR(c.t_end - c.t_start, f.collision_time(), 2e-3 * f.collision_time());
  const double v_in = -c.v0, v_out = f.stages()[2].v0;
  EXPECT_NEAR(v_out / v_in, 0.7, 5e-3);
}

TEST(FreeFallOracle, ElasticApexReturnsToStart) {
  const FreeFall f(case1(5e4, 1.0), 8.0);
  const auto h = f.apex_heights();
  ASSERT_GE(h.size(), 12u);
  for (double x : h) EXPECT_NEAR(x, 0.5, 1e-12);
}

TEST(FreeFallOracle, SoftApexApproachesHardSphereAsKnGrows) {
  const FreeFallParams soft = case1(5e4, 0.9), stiff = case1(5e6, 0.9);
  const auto hs = FreeFall(soft, 5.0).apex_heights(), hh = FreeFall(stiff, 5.0).apex_heights();
  for (int k = 1; k <= 5; ++k) {
    const double hard = FreeFall::hard_sphere_apex(soft, k);
    EXPECT_LT(std::abs(hh[k - 1] - hard), std::abs(hs[k - 1] - hard)) << "bounce " << k;
  }
}

TEST(SlippingOracle, NonDimensionalEndOfSlip) {
  const SlippingParams p{5e-4, 0.1, 0.4, 9.81};
  const double ts = slip_end_time(p);
  EXPECT_DOUBLE_EQ(p.mu * p.g * ts / p.v0, 2.0 / 7.0);
  EXPECT_NEAR(slipping_velocity(p, ts * (1 - 1e-12)), 5.0 / 7.0 * p.v0, 1e-12);
  EXPECT_NEAR(slipping_angular_velocity(p, ts * (1 - 1e-12)) * p.radius, 5.0 / 7.0 * p.v0, 1e-12);
  EXPECT_DOUBLE_EQ(slipping_velocity(p, 2 * ts), 5.0 / 7.0 * p.v0);
}

}  // namespace
