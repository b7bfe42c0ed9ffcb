/// @file region.cpp
/// @brief The region a placement or insertion block draws its centres in: `lower` and
/// `upper` (a box) or a `cylinder` table, exactly one of the two.
#include "sections.hpp"

namespace cdm::scene {

PlacementRegion read_region(const Reader& rd, const toml::table& t, const std::string& path,
                            const std::string& schema_path) {
  const toml::node* cn = t.get("cylinder");
  if (!cn) {
    if (!t.get("lower") && !t.get("upper"))
      rd.fail_missing(path + ".lower", "a region: lower and upper (a box) or a cylinder table");
    const Vec3 lo = rd.vec3_required(t, "lower", path, Dim::length), hi = rd.vec3_required(t, "upper", path, Dim::length);
    if (!(hi.x >= lo.x && hi.y >= lo.y && hi.z >= lo.z))
      rd.fail_value(path + ".upper", *t.get("upper"), "a corner at or above " + path + ".lower along every axis");
    return PlacementRegion::box(lo, hi);
  }
  const std::string why = "the region is the cylinder (" + path + ".cylinder); a box has lower and upper instead";
  rd.reject_unused(t, "lower", path, why);
  rd.reject_unused(t, "upper", path, why);
  const std::string cp = path + ".cylinder";
  const toml::table* c = rd.table(t, "cylinder", path, true);
  rd.check_keys(*c, schema_path + ".cylinder", cp);
  const Vec3 point = rd.vec3_required(*c, "point", cp, Dim::length);
  const Vec3 axis = unit_vector(rd, *c, "axis", cp, "a direction (3 numbers, not all 0)");
  const double radius = rd.positive(*c, "radius", cp, Dim::length, true);
  const double length = rd.positive(*c, "length", cp, Dim::length, true);
  return PlacementRegion::make_cylinder(point, axis, radius, length);
}

}  // namespace cdm::scene
