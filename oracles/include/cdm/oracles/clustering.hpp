#pragma once
/// @file clustering.hpp
/// @brief Baseline of a box-counting clustering index for points that are uniformly and
/// independently random: the reference a clustering measure is judged against.
///
/// Index: with the domain cut into B equal boxes holding n_b points (N in all, mean
/// n̄ = N/B), D = s²/n̄ − 1, s² = (1/B) Σ_b (n_b − n̄)². D = 0 for a Poisson process,
/// D < 0 for points more even than random (a lattice: −1), D > 0 for clustered points.
/// For N independent uniform points the counts are multinomial, E[s²] = n̄(1 − 1/B), so
/// E[D] = −1/B exactly; its spread is estimated by Monte Carlo (mt19937_64, fixed seed).
#include <cstdint>

namespace cdm::oracles {

struct ClusteringBaseline {
  double mean;        // Monte Carlo mean of D [-]
  double stddev;      // Monte Carlo standard deviation of D [-]
  double exact_mean;  // −1/B [-]
  int draws;
};

/// @p points independent uniform points in a square cut into @p boxes × @p boxes.
ClusteringBaseline random_points_clustering(int points, int boxes, int draws = 4000, std::uint64_t seed = 20121);

}  // namespace cdm::oracles
