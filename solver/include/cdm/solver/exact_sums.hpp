#pragma once
/// @file exact_sums.hpp
/// @brief Sums of doubles whose result does not depend on the order of the terms, so that
/// a sum split among threads or MPI processes, in any way, gives what one would.
///
/// Each term is rounded to a fixed point, a unit of 2⁻⁶² of the largest a sum can reach
/// (its bound, given by the caller: n terms of at most b reach at most n b), and added
/// exactly in 64-bit integers; a sum's value is the exact sum of the rounded terms,
/// rounded once to a double. Integer addition is associative, so partial sums made
/// anywhere add up to the same integers. A term's rounding costs at most one unit: of
/// a sum of 10⁴ terms, about 2⁻⁴⁸ ≈ 4e-15 of the largest term, near a double's
/// rounding of a running sum of such terms (10⁶ terms: 2⁻⁴² ≈ 2e-13).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "cdm/solver/slot_pages.hpp"

namespace cdm {

class ExactSums {
 public:
  /// Start @p n sums, all zero, of terms of magnitude at most @p bound, the magnitudes of
  /// any one sum's terms adding up to at most @p sum_bound (both finite, ≥ 0). Their
  /// whole pages are returned to the system: a sum costs memory once a term is added
  /// (sums by cells of which a process adds to its planes only).
  void reset(std::size_t n, double bound, double sum_bound) {
    unit_ = unit_for(bound, sum_bound);
    scale_ = 1.0 / unit_;  // a power of two: exact
    assign_zeros(n);
  }
  /// New bounds for sums that are all zero (cleared since their last use), without
  /// touching them.
  void set_bounds(double bound, double sum_bound) {
    unit_ = unit_for(bound, sum_bound);
    scale_ = 1.0 / unit_;
  }
  /// Sums [@p k0, @p k1) back to zero.
  void clear(std::size_t k0, std::size_t k1) { std::fill(acc_.begin() + k0, acc_.begin() + k1, 0); }
  /// The unit of sums of terms of at most @p bound adding up to at most @p sum_bound.
  static double unit_for(double bound, double sum_bound) {
    int e = 0, es = 0;
    std::frexp(bound, &e);  // bound < 2^e
    std::frexp(sum_bound, &es);
    // A unit of 2^-62 of the sums' bound, so that no sum can overflow (each term is
    // rounded toward zero); terms below 2^-960 (far below any physical quantity here)
    // round to zero, the scale staying a finite double.
    return std::ldexp(1.0, std::max({es, e, -960}) - 62);
  }
  /// Add @p v (|v| ≤ the bound) to sum @p k.
  void add(std::size_t k, double v) { add_scaled(k, v * scale_); }
  /// Add a term already multiplied by scale() (w (s v) for a weight w ≤ 1 of a term v
  /// the bound holds: one product per term where several weights share v).
  void add_scaled(std::size_t k, double sv) { acc_[k] += static_cast<std::int64_t>(sv); }
  double scale() const { return scale_; }
  /// Start sums as many, of the same bounds, as @p other's: where these are as many, they
  /// must be zero (cleared since their last use), and are not touched; else new zero
  /// sums, their pages uncommitted (as reset()).
  void reset_like(const ExactSums& other) {
    scale_ = other.scale_;
    unit_ = other.unit_;
    if (acc_.size() != other.acc_.size()) assign_zeros(other.acc_.size());
  }
  /// Add @p other's sums [@p k0, @p k1) (of the same bounds) to these.
  void add(const ExactSums& other, std::size_t k0, std::size_t k1) {
    for (std::size_t k = k0; k < k1; ++k) acc_[k] += other.acc_[k];
  }
  /// Add all of @p other's sums (of the same bounds) to these.
  void add(const ExactSums& other) { add(other, 0, acc_.size()); }
  double value(std::size_t k) const { return static_cast<double>(acc_[k]) * unit_; }
  std::size_t size() const { return acc_.size(); }
  /// The integer sums, for adding up partial sums (RankSplit::add_up).
  std::int64_t* data() { return acc_.data(); }

 private:
  /// @p n zero sums, their whole pages returned to the system.
  void assign_zeros(std::size_t n) {
    acc_.assign(n, 0);
    zero_bytes(acc_.data(), acc_.data() + n);
  }

  double scale_ = 1.0, unit_ = 1.0;
  std::vector<std::int64_t> acc_;
};

/// The mean of @p count values, the same to the bit however they are divided: each part
/// (a process's) visits its terms (@p visit(f) calls f(x) for each), @p largest(m) turns
/// the part's largest |x| into the largest over every part, and @p add_up(sums) adds the
/// parts' ExactSums (one sum) up over them. Empty where a term is not finite (a NaN
/// counts as an infinite magnitude, which a reduction's maximum keeps).
template <class Visit, class Largest, class AddUp>
std::optional<double> exact_mean(double count, Visit&& visit, Largest&& largest, AddUp&& add_up) {
  double m = 0.0;
  visit([&](double x) { m = std::max(m, std::isnan(x) ? HUGE_VAL : std::abs(x)); });
  m = largest(m);
  if (!std::isfinite(m)) return std::nullopt;
  ExactSums sum;
  sum.reset(1, m, count * m);
  visit([&](double x) { sum.add(0, x); });
  add_up(sum);
  return sum.value(0) / count;
}

}  // namespace cdm
