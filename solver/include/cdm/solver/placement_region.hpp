#pragma once
/// @file placement_region.hpp
/// @brief Where [[random_particles]] and [[insertions]] draw their centres: a box between
/// two corners, or a finite cylinder (the centre of its start face, a unit axis, a radius
/// and a length: a silo's or a pipe's inside). Each draws a point uniformly in its volume
/// from three uniform numbers in [0, 1), so one stream of numbers places a block.
#include "cdm/solver/vec3.hpp"

namespace cdm {

struct PlacementRegion {
  bool cylinder = false;
  Vec3 lower, upper;  ///< the box; for a cylinder its bounding box [m]
  Vec3 point, axis;   ///< cylinder: centre of the start face [m], unit axis
  double radius = 0.0, length = 0.0;  ///< cylinder [m]
  Vec3 e1, e2;        ///< cylinder: unit vectors across the axis, a right-handed triple with it

  static PlacementRegion box(Vec3 lower, Vec3 upper);
  /// @p axis must be a unit vector; @p radius and @p length > 0.
  static PlacementRegion make_cylinder(Vec3 point, Vec3 axis, double radius, double length);

  /// The point of the region that (@p a, @p b, @p c) in [0, 1)^3 maps to; uniform in
  /// volume for uniform numbers. Box: lower + (a, b, c) (upper − lower). Cylinder: a along
  /// the axis, b the squared distance from it over radius², c the angle over 2π.
  Vec3 draw(double a, double b, double c) const;
  /// Whether @p x lies in the region (its boundary included; for a cylinder within 1e-12
  /// of its size, the round-off of draw()).
  bool contains(Vec3 x) const;
};

}  // namespace cdm
