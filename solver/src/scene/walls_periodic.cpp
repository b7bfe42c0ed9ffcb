/// @file walls_periodic.cpp
/// @brief Plane walls ([[walls]]) and periodic axes ([periodic], or the gas's).
#include "sections.hpp"

#include <algorithm>
#include <cmath>
#include <string>

namespace cdm::scene {

void read_walls(const Reader& rd, SceneSpec& spec) {
  const toml::array* ws = rd.array_of_tables(rd.root(), "walls");
  if (!ws) return;
  if (!spec.normal_contact)
    throw SceneError(rd.file() + ": [[walls]] is not used: modules.normal_contact is \"none\", so nothing touches a wall");
  for (std::size_t i = 0; i < ws->size(); ++i) {
    const toml::table& t = *ws->get(i)->as_table();
    const std::string path = "walls[" + std::to_string(i) + "]";
    rd.check_keys(t, "walls[]", path);
    PlaneWall w;
    w.name = rd.string(t, "name", path).value_or("wall" + std::to_string(i));
    w.point = rd.vec3_required(t, "point", path, Dim::length);
    Vec3 n = rd.vec3_required(t, "normal", path, Dim::none);
    const double big = std::max({std::abs(n.x), std::abs(n.y), std::abs(n.z)});
    if (!(big > 0.0)) rd.fail_value(path + ".normal", *t.get("normal"), "a non-zero vector (pointing into the domain)");
    double len = norm(n);
    if (!(len >= 1e-150 && len <= 1e150)) {
      // Its squared length would underflow or overflow: scale by the largest component first.
      n = Vec3{n.x / big, n.y / big, n.z / big};  // divided: 1/big overflows for a subnormal big
      len = norm(n);
    }
    w.normal = (1.0 / len) * n;
    w.material = rd.material_index(spec, t, "material", path);
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
