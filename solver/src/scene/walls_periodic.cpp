/// @file walls_periodic.cpp
/// @brief Walls ([[walls]]: planes, finite cylinders and cones) and periodic axes ([periodic], or the gas's).
#include "sections.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace cdm::scene {

Vec3 unit_vector(const Reader& rd, const toml::table& t, const std::string& key, const std::string& path,
                 const std::string& expected) {
  Vec3 n = rd.vec3_required(t, key, path, Dim::none);
  const double big = std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)});
  if (!(big > 0.0)) rd.fail_value(join(path, key), *t.get(key), expected);
  double len = norm(n);
  if (!(len >= 1e-150 && len <= 1e150)) {
    // Its squared length would underflow or overflow: scale by the largest component first.
    n = Vec3{n.x / big, n.y / big, n.z / big};  // divided: 1/big overflows for a subnormal big
    len = norm(n);
  }
  return (1.0 / len) * n;
}

namespace {
/// Refuse the keys of @p t that a wall of type @p type does not take.
void refuse_other_keys(const Reader& rd, const toml::table& t, const std::string& path, WallType type) {
  static const std::vector<std::string> common = {"name", "type", "point", "material", "motion"};
  std::vector<std::string> own;
  switch (type) {
    case WallType::plane: own = {"normal"}; break;
    case WallType::cylinder: own = {"axis", "radius", "length", "caps", "side"}; break;
    case WallType::cone: own = {"axis", "radius_start", "radius_end", "length", "caps", "side"}; break;
  }
  for (auto&& [k, v] : t) {
    const std::string name(k.str());
    if (std::find(common.begin(), common.end(), name) != common.end() ||
        std::find(own.begin(), own.end(), name) != own.end())
      continue;
    std::string list;
    for (const auto& o : own) list += ", " + o;
    rd.fail_value(path + "." + name, v,
                  std::string("no such key in a wall of type \"") + keyword_of(wall_type_keywords, type) +
                      "\" (it takes name, type, point, material, motion" + list + ")");
  }
}

/// A finite cylinder or cone as its surfaces: the lateral surface and each closed end.
void read_revolution(const Reader& rd, const toml::table& t, const std::string& path, WallType type, Wall w,
                     SceneSpec& spec) {
  // The geometry first, then what the wall is made of and how it moves (as a plane).
  w.point = rd.vec3_required(t, "point", path, Dim::length);
  w.normal = unit_vector(rd, t, "axis", path, "a non-zero vector (the axis, from point towards the far end)");
  w.length = rd.positive(t, "length", path, Dim::length, true);
  if (type == WallType::cylinder) {
    w.radius_start = w.radius_end = rd.positive(t, "radius", path, Dim::length, true);
  } else {
    constexpr double inf = std::numeric_limits<double>::infinity();
    w.radius_start = rd.number_in(t, "radius_start", path, Dim::length, true, 0.0, 0.0, false, inf, false, ">= 0");
    w.radius_end = rd.number_in(t, "radius_end", path, Dim::length, true, 0.0, 0.0, false, inf, false, ">= 0");
    if (w.radius_start == w.radius_end)
      rd.fail_value(path + ".radius_end", *t.get("radius_end"),
                    "a radius other than radius_start (equal radii make a cylinder: type = \"cylinder\", radius = ...)");
  }
  const WallCaps caps = rd.keyword(t, "caps", path, wall_caps_keywords, WallCaps::none);
  w.capped_start = caps == WallCaps::start || caps == WallCaps::both;
  w.capped_end = caps == WallCaps::end || caps == WallCaps::both;
  if ((w.capped_start && w.radius_start == 0.0) || (w.capped_end && w.radius_end == 0.0))
    rd.fail_value(path + ".caps", *t.get("caps"), "caps only at an end of radius > 0 (an apex has no cap)");
  w.inside = rd.keyword(t, "side", path, wall_side_keywords, true);
  // Any unit vector perpendicular to the axis: the axis crossed with the coordinate axis
  // it is least aligned with.
  const Vec3 across = cross(w.normal, least_aligned_axis(w.normal));
  w.across = (1.0 / norm(across)) * across;
  w.material = rd.material_index(spec, t, "material", path);
  w.motion = read_motion(rd, t, "motion", path, "walls[].motion");
  const std::string name = w.name;
  w.shape = WallShape::lateral;
  spec.walls.push_back(w);
  if (w.capped_start) {
    w.shape = WallShape::cap_start;
    w.name = name + ".start_cap";
    spec.walls.push_back(w);
  }
  if (w.capped_end) {
    w.shape = WallShape::cap_end;
    w.name = name + ".end_cap";
    spec.walls.push_back(w);
  }
}
}  // namespace

void read_walls(const Reader& rd, SceneSpec& spec) {
  const toml::array* ws = rd.array_of_tables(rd.root(), "walls");
  if (!ws) return;
  if (!spec.normal_contact)
    throw SceneError(rd.file() + ": [[walls]] is not used: modules.normal_contact is \"none\", so nothing touches a wall");
  for (std::size_t i = 0; i < ws->size(); ++i) {
    const toml::table& t = *ws->get(i)->as_table();
    const std::string path = "walls[" + std::to_string(i) + "]";
    rd.check_keys(t, "walls[]", path);
    const WallType type = rd.keyword(t, "type", path, wall_type_keywords, WallType::plane);
    refuse_other_keys(rd, t, path, type);
    Wall w;
    w.name = rd.string(t, "name", path).value_or("wall" + std::to_string(i));
    if (type != WallType::plane) {
      read_revolution(rd, t, path, type, w, spec);
      continue;
    }
    w.point = rd.vec3_required(t, "point", path, Dim::length);
    w.normal = unit_vector(rd, t, "normal", path, "a non-zero vector (pointing into the domain)");
    w.material = rd.material_index(spec, t, "material", path);
    w.motion = read_motion(rd, t, "motion", path, "walls[].motion");
    spec.walls.push_back(w);
  }
}

void read_periodic(const Reader& rd, SceneSpec& spec) {
  PeriodicBox& box = spec.periodic;
  if (spec.gas != GasModel::none) {
    // The particles share the gas's periodic axes (a 2D gas has no z to wrap).
    if (const toml::node* n = rd.root().get("periodic"))
      rd.fail_value("periodic", *n, "no [periodic] table with a gas: the particles are periodic where gas.boundaries are");
    const fluid::GridSpec& g = spec.gas_spec.grid;
    const double lo[3] = {g.lo.x, g.lo.y, g.lo.z}, hi[3] = {g.hi.x, g.hi.y, g.hi.z};
    for (int a = 0; a < (g.two_d ? 2 : 3); ++a)
      if (g.periodic(a)) {
        box.on[a] = true;
        box.lo[a] = lo[a];
        box.len[a] = hi[a] - lo[a];
      }
    return;
  }
  const toml::node* n = rd.root().get("periodic");
  if (!n) return;
  const toml::table* t = n->as_table();
  if (!t) rd.fail_value("periodic", *n, "a table with x, y and/or z = [lower, upper]");
  rd.check_keys(*t, "periodic", "periodic");
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const toml::node* e = t->get(axes[a]);
    if (!e) continue;
    const std::string key = std::string("periodic.") + axes[a];
    const toml::array* arr = e->as_array();
    double c[2] = {0.0, 0.0};
    if (!arr || arr->size() != 2) rd.fail_value(key, *e, "an array [lower, upper] of 2 numbers");
    for (int i = 0; i < 2; ++i) {
      const toml::node& v = *arr->get(static_cast<std::size_t>(i));
      if (auto iv = v.as_integer()) c[i] = static_cast<double>(iv->get());
      else if (auto fv = v.as_floating_point()) c[i] = fv->get();
      else rd.fail_value(key, *e, "an array [lower, upper] of 2 numbers");
    }
    if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !(c[1] > c[0]))
      rd.fail_value(key, *e, "[lower, upper] with finite lower < upper");
    box.on[a] = true;
    box.lo[a] = c[0] * rd.factor(Dim::length);
    box.len[a] = (c[1] - c[0]) * rd.factor(Dim::length);
  }
  if (!box.any()) rd.fail_value("periodic", *n, "at least one of x, y, z");
}

}  // namespace cdm::scene
