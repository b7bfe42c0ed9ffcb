#pragma once
/// @file layers.hpp
/// @brief Layers of gas cells normal to an axis, for the log's and the monitors' plane
/// averages (a uniform grid: every cell of a layer has the same area), and the pressure
/// of one cell, read where the processes divide the gas by planes.
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/fluid/plane_share.hpp"
#include "cdm/solver/fluid/staggered_grid.hpp"

namespace cdm {

/// The mean of the cell-centred array @p cells over layer @p index along @p axis, among
/// the processes sharing the gas's planes (@p share): each adds the layer's cells on its
/// own planes along z (PlaneShare::mine), which it keeps current, in exact sums added up
/// over the processes (exact_mean): the same bits on any number of processes, and no
/// plane sent to any. NaN where a cell of the layer is not finite. Collective.
inline double layer_mean(const fluid::StaggeredGrid& g, const fluid::PlaneShare& share,
                         const std::vector<double>& cells, int axis, int index) {
  const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
  const auto [k0, k1] = share.mine(g.n(2));
  auto visit = [&](auto&& f) {
    int ijk[3];
    ijk[axis] = index;
    for (int b = 0; b < g.n(o2); ++b)
      for (int a = 0; a < g.n(o1); ++a) {
        ijk[o1] = a;
        ijk[o2] = b;
        if (ijk[2] >= k0 && ijk[2] < k1) f(cells[g.at(ijk[0], ijk[1], ijk[2])]);
      }
  };
  const double count = static_cast<double>(g.n(o1)) * g.n(o2);
  const std::optional<double> mean =
      exact_mean(count, visit, [&](double m) { return share.max(m); }, [&](ExactSums& s) { share.sum(s.data(), 1); });
  return mean ? *mean : std::numeric_limits<double>::quiet_NaN();
}

/// The value of the cell-centred array @p cells in cell (@p i, @p j, @p k), among the
/// processes sharing the gas's planes (@p share): its plane's owner's. Collective.
inline double cell_value(const fluid::StaggeredGrid& g, const fluid::PlaneShare& share,
                         const std::vector<double>& cells, int i, int j, int k) {
  const auto [k0, k1] = share.mine(g.n(2));
  return share.max(k >= k0 && k < k1 ? cells[g.at(i, j, k)] : -HUGE_VAL);
}

/// The layer along @p axis holding coordinate @p x (the end layers beyond the domain).
inline int layer_of(const fluid::StaggeredGrid& g, int axis, double x) {
  return std::clamp(static_cast<int>(std::floor((x - g.lo(axis)) / g.h(axis))), 0, g.n(axis) - 1);
}

}  // namespace cdm
