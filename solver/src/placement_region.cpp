/// @file placement_region.cpp
/// @brief The regions particles are placed and inserted in (placement_region.hpp).
#include "cdm/solver/placement_region.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace cdm {

PlacementRegion PlacementRegion::box(Vec3 lower, Vec3 upper) {
  PlacementRegion r;
  r.lower = lower;
  r.upper = upper;
  return r;
}

PlacementRegion PlacementRegion::make_cylinder(Vec3 point, Vec3 axis, double radius, double length) {
  PlacementRegion r;
  r.cylinder = true;
  r.point = point;
  r.axis = axis;
  r.radius = radius;
  r.length = length;
  // Across the axis: the coordinate direction least aligned with it, made orthogonal.
  const Vec3 least = least_aligned_axis(axis);
  const Vec3 u = least - dot(least, axis) * axis;
  r.e1 = (1.0 / norm(u)) * u;
  r.e2 = cross(axis, r.e1);
  // The bounding box: the two end discs, each reaching radius·sqrt(1 − a_k²) along axis k.
  const Vec3 end = point + length * axis;
  const double a[3] = {axis.x, axis.y, axis.z}, p[3] = {point.x, point.y, point.z}, q[3] = {end.x, end.y, end.z};
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    const double reach = radius * std::sqrt(std::max(0.0, 1.0 - a[k] * a[k]));
    lo[k] = std::min(p[k], q[k]) - reach;
    hi[k] = std::max(p[k], q[k]) + reach;
  }
  r.lower = {lo[0], lo[1], lo[2]};
  r.upper = {hi[0], hi[1], hi[2]};
  return r;
}

Vec3 PlacementRegion::draw(double a, double b, double c) const {
  if (!cylinder)
    return {lower.x + a * (upper.x - lower.x), lower.y + b * (upper.y - lower.y), lower.z + c * (upper.z - lower.z)};
  const double rho = radius * std::sqrt(b), phi = 2.0 * std::numbers::pi * c;
  return point + (length * a) * axis + (rho * std::cos(phi)) * e1 + (rho * std::sin(phi)) * e2;
}

bool PlacementRegion::contains(Vec3 x) const {
  if (!cylinder)
    return x.x >= lower.x && x.x <= upper.x && x.y >= lower.y && x.y <= upper.y && x.z >= lower.z && x.z <= upper.z;
  const Vec3 d = x - point;
  const double s = dot(d, axis);
  const Vec3 across = d - s * axis;
  const double tol = 1e-12 * std::max(length, radius);  // the round-off of draw()
  const double rho = radius + tol;
  return s >= -tol && s <= length + tol && dot(across, across) <= rho * rho;
}

}  // namespace cdm
