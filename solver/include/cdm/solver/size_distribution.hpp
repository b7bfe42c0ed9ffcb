#pragma once
/// @file size_distribution.hpp
/// @brief The particle radii of one placement or insertion block: one radius, or a
/// discrete, uniform, normal or log-normal distribution, given by number or by mass,
/// cut off at a smallest and a largest radius. Sampled from a 64-bit Mersenne twister
/// through a fixed mapping to doubles (no std:: distribution, whose algorithms differ
/// between standard libraries), so a scene gives the same radii everywhere.
///
/// By mass: the distribution says which fraction of the *mass* lies at each radius;
/// the number density is then that density divided by r³ (equal density). Discrete
/// fractions are converted exactly; a log-normal by mass is a log-normal by number with
/// the median divided by exp(3σ²) (Hatch–Choate), cut off at the same radii; the uniform
/// and the normal by mass draw by number and keep a radius r with probability
/// (r_min/r)³ (rejection, exact).
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "cdm/solver/keywords.hpp"

namespace cdm {

enum class SizeKind { fixed, discrete, uniform, normal, lognormal };
inline constexpr Keywords<SizeKind, 4> size_kind_keywords{{{"discrete", SizeKind::discrete},
                                                           {"uniform", SizeKind::uniform},
                                                           {"normal", SizeKind::normal},
                                                           {"lognormal", SizeKind::lognormal}}};
enum class SizeBasis { number, mass };
inline constexpr Keywords<SizeBasis, 2> size_basis_keywords{{{"number", SizeBasis::number}, {"mass", SizeBasis::mass}}};

/// Uniform in [0, 1) from a 64-bit Mersenne twister with a fixed mapping to doubles, so a
/// scene gives the same particles on every platform.
inline double uniform01(std::mt19937_64& rng) { return static_cast<double>(rng() >> 11) * 0x1.0p-53; }

struct SizeDistribution {
  SizeKind kind = SizeKind::fixed;
  SizeBasis basis = SizeBasis::number;
  double radius = 0.0;               ///< fixed: the one radius [m]
  std::vector<double> radii;         ///< discrete: the radii [m] (set_discrete)
  std::vector<double> fractions;     ///< discrete: their fractions (of the basis), summing to 1
  std::vector<double> cumulative;    ///< discrete: the running sums of the count weights
  double mean = 0.0, std_dev = 0.0;  ///< normal: mean and standard deviation of the radius [m]
  double median = 0.0, sigma = 0.0;  ///< log-normal: median radius [m], standard deviation of ln r [-]
  double min = 0.0;                  ///< smallest radius drawn [m] (uniform: the lower end)
  double max = std::numeric_limits<double>::infinity();  ///< largest radius drawn [m]

  /// A discrete distribution of @p r with @p f (of the basis set before): the radii,
  /// the fractions and the cumulative count weights a draw searches.
  void set_discrete(std::vector<double> r, std::vector<double> f);
  /// One radius [m].
  double sample(std::mt19937_64& rng) const;
  /// The largest radius that can be drawn [m] (finite for every accepted distribution).
  double largest() const;
  /// The smallest radius that can be drawn [m] (> 0 for every accepted distribution).
  double smallest() const;
  /// The fraction of draws sample() keeps: of the untruncated distribution, the share
  /// inside [min, max], times (by mass, uniform and normal) the mean of (min/r)³ there.
  /// 1 for fixed and discrete.
  double kept_fraction() const;
  /// The number-weighted distribution's median radius [m] (log-normal: by number).
  double number_median() const;
};

/// Φ, the standard normal distribution function.
double standard_normal_cdf(double z);

}  // namespace cdm
