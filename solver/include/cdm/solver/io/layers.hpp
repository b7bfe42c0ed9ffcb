#pragma once
/// @file layers.hpp
/// @brief Layers of gas cells normal to an axis, for the log's and the monitors' plane
/// averages (a uniform grid: every cell of a layer has the same area).
#include <algorithm>
#include <cmath>
#include <vector>

#include "cdm/solver/fluid/staggered_grid.hpp"

namespace cdm {

/// The mean of the cell-centred array @p cells over layer @p index along @p axis.
inline double layer_mean(const fluid::StaggeredGrid& g, const std::vector<double>& cells, int axis, int index) {
  const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
  double s = 0.0;
  int ijk[3];
  ijk[axis] = index;
  for (int b = 0; b < g.n(o2); ++b)
    for (int a = 0; a < g.n(o1); ++a) {
      ijk[o1] = a;
      ijk[o2] = b;
      s += cells[g.at(ijk[0], ijk[1], ijk[2])];
    }
  return s / (static_cast<double>(g.n(o1)) * g.n(o2));
}

/// The layer along @p axis holding coordinate @p x (the end layers beyond the domain).
inline int layer_of(const fluid::StaggeredGrid& g, int axis, double x) {
  return std::clamp(static_cast<int>(std::floor((x - g.lo(axis)) / g.h(axis))), 0, g.n(axis) - 1);
}

}  // namespace cdm
