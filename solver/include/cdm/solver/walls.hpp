#pragma once
/// @file walls.hpp
/// @brief Infinite plane walls of any orientation. The unit normal points into the
/// domain: a particle centre at X is inside when (X - point)·normal > 0.
#include <string>

#include "cdm/solver/vec3.hpp"

namespace cdm {

struct PlaneWall {
  std::string name;
  Vec3 point;   // any point on the plane [m]
  Vec3 normal;  // unit normal into the domain [-]
  int material = 0;

  /// Signed distance of X from the plane [m], positive inside the domain.
  double distance(Vec3 X) const { return dot(X - point, normal); }
};

}  // namespace cdm
