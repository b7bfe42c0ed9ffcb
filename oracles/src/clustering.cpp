#include "cdm/oracles/clustering.hpp"

#include <cmath>
#include <random>
#include <vector>

namespace cdm::oracles {

ClusteringBaseline random_points_clustering(int points, int boxes, int draws, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> box(0, boxes * boxes - 1);
  const double B = static_cast<double>(boxes) * boxes, mean_n = points / B;
  double sum = 0.0, sum2 = 0.0;
  std::vector<int> n(static_cast<std::size_t>(boxes * boxes));
  for (int k = 0; k < draws; ++k) {
    std::fill(n.begin(), n.end(), 0);
    // A uniform point falls in each box with probability 1/B.
    for (int p = 0; p < points; ++p) ++n[static_cast<std::size_t>(box(rng))];
    double s2 = 0.0;
    for (int c : n) s2 += (c - mean_n) * (c - mean_n);
    const double d = s2 / B / mean_n - 1.0;
    sum += d;
    sum2 += d * d;
  }
  const double m = sum / draws;
  return {m, std::sqrt(std::max(0.0, sum2 / draws - m * m)), -1.0 / B, draws};
}

}  // namespace cdm::oracles
