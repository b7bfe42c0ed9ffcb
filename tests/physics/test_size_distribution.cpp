// Size distributions (size_distribution.hpp): the sampled moments ⟨r⟩ and ⟨r³⟩ by count
// against the analytic ones, integrated here from each distribution's density (by mass:
// the given density over r³), for every kind by number and by mass, with cut-offs.
// 200,000 draws: a moment off by more than 5 standard errors fails.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <random>

#include "cdm/solver/size_distribution.hpp"

namespace {

using cdm::SizeBasis;
using cdm::SizeDistribution;
using cdm::SizeKind;

double phi(double z) { return std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi); }

/// ⟨r^k⟩ of the count density @p n on [a, b] (Simpson, 20,000 intervals).
double moment(const std::function<double(double)>& n, double a, double b, int k) {
  const int m = 20000;
  const double h = (b - a) / m;
  double num = 0.0, den = 0.0;
  for (int i = 0; i <= m; ++i) {
    const double r = a + i * h;
    const double w = (i == 0 || i == m) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    num += w * n(r) * std::pow(r, k);
    den += w * n(r);
  }
  return num / den;
}

/// The count density of @p d (unnormalised) from its given density @p given.
std::function<double(double)> count_density(const SizeDistribution& d, std::function<double(double)> given) {
  if (d.basis == SizeBasis::number) return given;
  return [given](double r) { return given(r) / (r * r * r); };
}

void check_moments(const SizeDistribution& d, const std::function<double(double)>& count, const char* what) {
  std::mt19937_64 rng(12345);
  const int n = 200000;
  double s1 = 0.0, s2 = 0.0, s3 = 0.0, s6 = 0.0, lo = 1e300, hi = 0.0;
  for (int i = 0; i < n; ++i) {
    const double r = d.sample(rng);
    s1 += r; s2 += r * r; s3 += r * r * r; s6 += r * r * r * r * r * r;
    lo = std::min(lo, r); hi = std::max(hi, r);
  }
  const double m1 = s1 / n, m3 = s3 / n;
  const double se1 = std::sqrt((s2 / n - m1 * m1) / n), se3 = std::sqrt((s6 / n - m3 * m3) / n);
  const double a1 = moment(count, d.min, d.max, 1), a3 = moment(count, d.min, d.max, 3);
  EXPECT_NEAR(m1, a1, 5.0 * se1) << what << ": <r>";
  EXPECT_NEAR(m3, a3, 5.0 * se3) << what << ": <r^3>";
  EXPECT_GE(lo, d.min) << what;
  EXPECT_LE(hi, d.max) << what;
  EXPECT_GE(lo, d.smallest()) << what;
  EXPECT_LE(hi, d.largest()) << what;
}

TEST(SizeDistribution, UniformByNumberAndByMass) {
  for (SizeBasis b : {SizeBasis::number, SizeBasis::mass}) {
    SizeDistribution d;
    d.kind = SizeKind::uniform;
    d.basis = b;
    d.min = 1e-3;
    d.max = 3e-3;
    check_moments(d, count_density(d, [](double) { return 1.0; }), b == SizeBasis::number ? "uniform by number" : "uniform by mass");
  }
}

TEST(SizeDistribution, NormalByNumberAndByMassWithCutoffs) {
  for (SizeBasis b : {SizeBasis::number, SizeBasis::mass}) {
    SizeDistribution d;
    d.kind = SizeKind::normal;
    d.basis = b;
    d.mean = 1e-3;
    d.std_dev = 2e-4;
    d.min = 0.7e-3;  // asymmetric cut-offs: the truncation shifts the mean
    d.max = 1.6e-3;
    check_moments(d, count_density(d, [&](double r) { return phi((r - d.mean) / d.std_dev); }),
                  b == SizeBasis::number ? "normal by number" : "normal by mass");
  }
}

TEST(SizeDistribution, LognormalByNumberAndByMassWithCutoffs) {
  for (SizeBasis b : {SizeBasis::number, SizeBasis::mass}) {
    SizeDistribution d;
    d.kind = SizeKind::lognormal;
    d.basis = b;
    d.median = 1e-3;
    d.sigma = 0.35;
    d.min = 0.5e-3;
    d.max = 2.5e-3;
    // The given density of r: log-normal about ln median (of the count or of the mass).
    check_moments(d, count_density(d, [&](double r) { return phi(std::log(r / d.median) / d.sigma) / r; }),
                  b == SizeBasis::number ? "lognormal by number" : "lognormal by mass");
  }
}

TEST(SizeDistribution, DiscreteByNumberAndByMass) {
  for (SizeBasis b : {SizeBasis::number, SizeBasis::mass}) {
    SizeDistribution d;
    d.basis = b;
    d.set_discrete({1e-3, 2e-3, 3e-3}, {0.5, 0.3, 0.2});
    std::mt19937_64 rng(7);
    const int n = 300000;
    double count[3] = {0, 0, 0}, mass[3] = {0, 0, 0};
    for (int i = 0; i < n; ++i) {
      const double r = d.sample(rng);
      int k = 0;
      while (k < 2 && d.radii[k] != r) ++k;
      ASSERT_EQ(d.radii[k], r);
      count[k] += 1.0;
      mass[k] += r * r * r;
    }
    // The count fractions expected: the fractions, or by mass the fractions over r³.
    double expect[3], sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double r = d.radii[k];
      expect[k] = b == SizeBasis::number ? d.fractions[k] : d.fractions[k] / (r * r * r);
      sum += expect[k];
    }
    double mass_total = mass[0] + mass[1] + mass[2];
    for (int k = 0; k < 3; ++k) {
      const double p = expect[k] / sum, se = std::sqrt(p * (1 - p) / n);  // binomial standard error
      EXPECT_NEAR(count[k] / n, p, 5.0 * se) << (b == SizeBasis::number ? "by number" : "by mass") << ", radius "
                                             << d.radii[k];
      if (b == SizeBasis::mass) {
        EXPECT_NEAR(mass[k] / mass_total, d.fractions[k], 0.01) << "mass fraction, radius " << d.radii[k];
      }
    }
  }
}

TEST(SizeDistribution, HatchChoateMedianAndKeptFraction) {
  SizeDistribution d;
  d.kind = SizeKind::lognormal;
  d.basis = SizeBasis::mass;
  d.median = 2e-3;
  d.sigma = 0.5;
  EXPECT_DOUBLE_EQ(d.number_median(), 2e-3 * std::exp(-0.75));
  d.min = d.number_median();
  d.max = 1.0;
  EXPECT_NEAR(d.kept_fraction(), 0.5, 1e-12);  // above the count median: half the count
  SizeDistribution n;
  n.kind = SizeKind::normal;
  n.mean = 1.0;
  n.std_dev = 0.1;
  n.min = 0.9;
  n.max = 1.1;
  EXPECT_NEAR(n.kept_fraction(), 0.682689492137086, 1e-12);
  // By mass, a uniform draw is kept with probability (min/r)³: on [1, 3] its mean is
  // (1/2)(1 − 1/9)/2 = 2/9.
  SizeDistribution u;
  u.kind = SizeKind::uniform;
  u.basis = SizeBasis::mass;
  u.min = 1.0;
  u.max = 3.0;
  EXPECT_NEAR(u.kept_fraction(), 2.0 / 9.0, 1e-9);
}

TEST(SizeDistribution, SameSeedSameRadii) {
  SizeDistribution d;
  d.kind = SizeKind::normal;
  d.mean = 1e-3;
  d.std_dev = 1e-4;
  d.min = 7e-4;
  d.max = 1.3e-3;
  std::mt19937_64 a(3), b(3);
  for (int i = 0; i < 1000; ++i) ASSERT_EQ(d.sample(a), d.sample(b));
}

}  // namespace
