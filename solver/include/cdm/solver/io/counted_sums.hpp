#pragma once
/// @file counted_sums.hpp
/// @brief Sums over the particles for what is sampled (the run log, monitors, the
/// population table), each process adding its own part (Simulation::counted_runs) and
/// the parts added up, with the same result on any number of processes.
///
/// Each sum is an exact sum (exact_sums.hpp) on a unit of 2⁻⁶² of its own Σ|term|
/// rounded up to a power of two: a first pass finds each sum's largest term, a second
/// adds up Σ|term| exactly on the unit that largest term allows (an upper bound, the
/// same on any number of processes), a third the terms on the unit of that bound. A
/// term's rounding then costs at most 2⁻⁶¹ Σ|term|, so n terms lose at most n 2⁻⁶¹ Σ|term|
/// (10⁶ terms: 4e-13 of Σ|term|), near what a double's running sum loses.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

/// @p sums sums over the particles: @p terms(i, add) calls add(k, v) for each term v
/// that particle slot i gives sum k (k < sums; at most one term per particle and sum).
/// A collective call when several processes share the particles.
template <class Terms>
std::vector<double> counted_sums(const Simulation& sim, std::size_t sums, Terms&& terms) {
  const auto runs = sim.counted_runs();
  auto each = [&](auto&& add) {
    for (const auto& run : runs)
      for (std::size_t i = run.first; i < run.second; ++i) terms(i, add);
  };
  const double n = static_cast<double>(std::max<std::size_t>(1, sim.particle_count()));
  // Sum k in integers of unit[k], added up over the processes.
  std::vector<double> unit(sums), scale(sums);
  ExactSums acc;
  auto add_up = [&](auto&& term) {
    acc.reset(sums, 1.0, 1.0);  // its own unit is not used
    for (std::size_t k = 0; k < sums; ++k) scale[k] = 1.0 / unit[k];
    each([&](std::size_t k, double v) { acc.add_scaled(k, term(v) * scale[k]); });
    sim.add_up(acc);
  };
  std::vector<double> largest(sums, 0.0);
  each([&](std::size_t k, double v) { largest[k] = std::max(largest[k], std::abs(v)); });
  sim.rank_max(largest);
  for (std::size_t k = 0; k < sums; ++k) unit[k] = ExactSums::unit_for(largest[k], n * largest[k]);
  add_up([](double v) { return std::abs(v); });
  std::vector<double> bound(sums);
  // Each term, rounded toward zero, lost less than one unit.
  for (std::size_t k = 0; k < sums; ++k) {
    bound[k] = static_cast<double>(acc.data()[k]) * unit[k] + n * unit[k];
    unit[k] = ExactSums::unit_for(largest[k], bound[k]);
  }
  add_up([](double v) { return v; });
  std::vector<double> out(sums);
  for (std::size_t k = 0; k < sums; ++k) out[k] = static_cast<double>(acc.data()[k]) * unit[k];
  return out;
}

}  // namespace cdm
