#include "cdm/solver/size_distribution.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

namespace cdm {

double standard_normal_cdf(double z) { return 0.5 * std::erfc(-z / std::numbers::sqrt2); }

namespace {

/// A standard normal deviate (Box–Muller; the second deviate of the pair is not kept, so
/// each call draws two uniforms).
double standard_normal(std::mt19937_64& rng) {
  const double u1 = uniform01(rng), u2 = uniform01(rng);
  return std::sqrt(-2.0 * std::log1p(-u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

}  // namespace

double SizeDistribution::number_median() const {
  // Hatch–Choate: a log-normal by mass is one by number with ln-median shifted by −3σ².
  return basis == SizeBasis::mass ? median * std::exp(-3.0 * sigma * sigma) : median;
}

void SizeDistribution::set_discrete(std::vector<double> r, std::vector<double> f) {
  kind = SizeKind::discrete;
  radii = std::move(r);
  fractions = std::move(f);
  cumulative.resize(radii.size());
  double sum = 0.0;
  for (std::size_t i = 0; i < radii.size(); ++i) {
    // By mass the count weight is the mass fraction over r³.
    sum += basis == SizeBasis::mass ? fractions[i] / (radii[i] * radii[i] * radii[i]) : fractions[i];
    cumulative[i] = sum;
  }
}

double SizeDistribution::sample(std::mt19937_64& rng) const {
  // By mass, a radius drawn by number is kept with probability (min/r)³: the number
  // density becomes the given one divided by r³ (uniform and normal only).
  const bool reject_by_mass = basis == SizeBasis::mass && (kind == SizeKind::uniform || kind == SizeKind::normal);
  for (;;) {
    double r = 0.0;
    switch (kind) {
      case SizeKind::fixed:
        return radius;
      case SizeKind::discrete: {
        // The first radius whose running weight exceeds u (the last one if rounding
        // leaves u at the total).
        const double u = uniform01(rng) * cumulative.back();
        const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), u);
        return radii[std::min<std::size_t>(static_cast<std::size_t>(it - cumulative.begin()), radii.size() - 1)];
      }
      case SizeKind::uniform:
        r = min + uniform01(rng) * (max - min);
        break;
      case SizeKind::normal:
        r = mean + std_dev * standard_normal(rng);
        if (!(r >= min && r <= max && r > 0.0)) continue;
        break;
      case SizeKind::lognormal:
        r = number_median() * std::exp(sigma * standard_normal(rng));
        if (!(r >= min && r <= max)) continue;
        break;
    }
    if (reject_by_mass) {
      const double q = min / r;
      if (!(uniform01(rng) < q * q * q)) continue;
    }
    return r;
  }
}

double SizeDistribution::largest() const {
  switch (kind) {
    case SizeKind::fixed: return radius;
    case SizeKind::discrete: {
      double m = 0.0;
      for (double r : radii) m = std::fmax(m, r);
      return m;
    }
    default: return max;
  }
}

double SizeDistribution::smallest() const {
  switch (kind) {
    case SizeKind::fixed: return radius;
    case SizeKind::discrete: {
      double m = radii.empty() ? 0.0 : radii[0];
      for (double r : radii) m = std::fmin(m, r);
      return m;
    }
    default: return min;
  }
}

double SizeDistribution::kept_fraction() const {
  // By mass, the mean of (min/r)³ over the density on [min, max]: Simpson's rule in
  // ln r (1000 intervals), accurate where the range spans decades.
  auto by_mass = [&](auto density) {
    if (basis != SizeBasis::mass) return 1.0;
    const int n = 1000;
    const double a = std::log(min), h = (std::log(max) - a) / n;
    double num = 0.0, den = 0.0;
    for (int i = 0; i <= n; ++i) {
      const double r = std::exp(a + i * h), q = min / r;
      const double w = ((i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0)) * r * density(r);  // dr = r d(ln r)
      num += w * q * q * q;
      den += w;
    }
    return den > 0.0 ? num / den : 0.0;
  };
  if (kind == SizeKind::uniform) return by_mass([](double) { return 1.0; });
  if (kind == SizeKind::normal) {
    const double lo = std::fmax(min, 0.0);
    const double kept = standard_normal_cdf((max - mean) / std_dev) - standard_normal_cdf((lo - mean) / std_dev);
    return kept * by_mass([&](double r) { const double z = (r - mean) / std_dev; return std::exp(-0.5 * z * z); });
  }
  if (kind == SizeKind::lognormal) {
    const double m = number_median();
    const double lo = min > 0.0 ? standard_normal_cdf(std::log(min / m) / sigma) : 0.0;
    return standard_normal_cdf(std::log(max / m) / sigma) - lo;
  }
  return 1.0;
}

}  // namespace cdm
