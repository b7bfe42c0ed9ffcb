#include "cdm/solver/neighbour_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cdm {

namespace {
inline bool test_pair(const ParticleStore& p, std::uint32_t i, std::uint32_t j, double margin, double& overlap) {
  const double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i], dz = p.z[j] - p.z[i];
  const double reach = p.radius[i] + p.radius[j] + margin;
  const double d2 = dx * dx + dy * dy + dz * dz;
  if (d2 >= reach * reach) return false;
  overlap = p.radius[i] + p.radius[j] - std::sqrt(d2);
  return true;
}
bool by_pair(const ContactPair& a, const ContactPair& b) { return a.i != b.i ? a.i < b.i : a.j < b.j; }
}  // namespace

void AllPairsSearch::find_contacts(const ParticleStore& p, double margin, std::vector<ContactPair>& out) const {
  out.clear();
  const auto n = static_cast<std::uint32_t>(p.size());
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t j = i + 1; j < n; ++j) {
      double ov;
      if (test_pair(p, i, j, margin, ov)) out.push_back({i, j, ov});
    }
}

void CellListSearch::find_contacts(const ParticleStore& p, double margin, std::vector<ContactPair>& out) {
  out.clear();
  const std::size_t n = p.size();
  if (n < 2) return;
  double lo[3] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                  std::numeric_limits<double>::max()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  double rmax = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const double c[3] = {p.x[i], p.y[i], p.z[i]};
    for (int k = 0; k < 3; ++k) { lo[k] = std::min(lo[k], c[k]); hi[k] = std::max(hi[k], c[k]); }
    rmax = std::max(rmax, p.radius[i]);
  }
  // Cell edge >= the largest possible contact distance, so only the 27 neighbouring
  // cells can hold partners; grown further if the box would need more than ~2N cells.
  double h = 2.0 * rmax + margin;
  long dims[3];
  for (;;) {
    double cells = 1.0;
    for (int k = 0; k < 3; ++k) {
      dims[k] = std::max(1L, static_cast<long>((hi[k] - lo[k]) / h) + 1);
      cells *= static_cast<double>(dims[k]);
    }
    if (cells <= 2.0 * static_cast<double>(n) + 27.0) break;
    h *= 1.5;
  }
  const std::size_t ncell = static_cast<std::size_t>(dims[0] * dims[1] * dims[2]);
  auto coord = [&](double v, int k) {
    return std::min(dims[k] - 1, std::max(0L, static_cast<long>((v - lo[k]) / h)));
  };
  cell_of_.resize(n);
  cell_start_.assign(ncell + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const long c = (coord(p.z[i], 2) * dims[1] + coord(p.y[i], 1)) * dims[0] + coord(p.x[i], 0);
    cell_of_[i] = static_cast<std::uint32_t>(c);
    ++cell_start_[c + 1];
  }
  for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  sorted_.resize(n);
  {
    std::vector<std::uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
    for (std::size_t i = 0; i < n; ++i) sorted_[fill[cell_of_[i]]++] = static_cast<std::uint32_t>(i);
  }
  for (std::size_t i = 0; i < n; ++i) {
    const long cx = coord(p.x[i], 0), cy = coord(p.y[i], 1), cz = coord(p.z[i], 2);
    for (long z = std::max(0L, cz - 1); z <= std::min(dims[2] - 1, cz + 1); ++z)
      for (long y = std::max(0L, cy - 1); y <= std::min(dims[1] - 1, cy + 1); ++y)
        for (long x = std::max(0L, cx - 1); x <= std::min(dims[0] - 1, cx + 1); ++x) {
          const long c = (z * dims[1] + y) * dims[0] + x;
          for (std::uint32_t s = cell_start_[c]; s < cell_start_[c + 1]; ++s) {
            const std::uint32_t j = sorted_[s];
            if (j <= i) continue;
            double ov;
            if (test_pair(p, static_cast<std::uint32_t>(i), j, margin, ov))
              out.push_back({static_cast<std::uint32_t>(i), j, ov});
          }
        }
  }
  std::sort(out.begin(), out.end(), by_pair);
}

}  // namespace cdm
