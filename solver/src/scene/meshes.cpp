/// @file meshes.cpp
/// @brief Triangle-mesh walls ([[meshes]]): an STL file placed by scale, rotation and
/// offset, with a material.
#include "sections.hpp"

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include "cdm/solver/io/stl_reader.hpp"

namespace cdm::scene {

namespace {

/// Rotation by @p deg (degrees) about x, then y, then z (fixed axes): R = Rz Ry Rx.
struct Rotation {
  double m[3][3];
  explicit Rotation(Vec3 deg) {
    const double k = std::numbers::pi / 180.0;
    const double cx = std::cos(k * deg.x), sx = std::sin(k * deg.x);
    const double cy = std::cos(k * deg.y), sy = std::sin(k * deg.y);
    const double cz = std::cos(k * deg.z), sz = std::sin(k * deg.z);
    const double r[3][3] = {{cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx},
                            {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx},
                            {-sy, cy * sx, cy * cx}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] = r[i][j];
  }
  Vec3 operator()(Vec3 v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
};

}  // namespace

void read_meshes(const Reader& rd, SceneSpec& spec) {
  const toml::array* ms = rd.array_of_tables(rd.root(), "meshes");
  if (!ms) return;
  if (!spec.normal_contact)
    throw SceneError(rd.file() + ": [[meshes]] is not used: modules.normal_contact is \"none\", so nothing touches a mesh");
  // STL paths are relative to the scene file's folder.
  const std::filesystem::path base = std::filesystem::path(rd.file()).parent_path();
  for (std::size_t i = 0; i < ms->size(); ++i) {
    const toml::table& t = *ms->get(i)->as_table();
    const std::string path = "meshes[" + std::to_string(i) + "]";
    rd.check_keys(t, "meshes[]", path);
    const auto file = rd.string(t, "file", path);
    if (!file) rd.fail_missing(path + ".file", "the path of an STL file (relative to the scene file)");
    const std::string stl = std::filesystem::path(*file).is_absolute() ? *file : (base / *file).string();
    const double scale = rd.positive(t, "scale", path, Dim::none, false, 1.0);
    const Vec3 offset = rd.vec3(t, "offset", path, Dim::length).value_or(Vec3{});
    const Vec3 rotation = rd.vec3(t, "rotation", path, Dim::none).value_or(Vec3{});
    for (double a : {rotation.x, rotation.y, rotation.z})
      if (!(std::abs(a) <= 360.0)) rd.fail_value(path + ".rotation", *t.get("rotation"), "3 angles in [-360, 360] degrees");
    const int material = rd.material_index(spec, t, "material", path);
    std::vector<std::array<Vec3, 3>> corners;
    try {
      corners = read_stl(stl);
    } catch (const StlError& e) {
      throw SceneError(rd.file() + ": key '" + path + ".file' = \"" + *file + "\": " + e.what());
    }
    // File units are the scene's length unit, times scale; rotated, then offset.
    const Rotation rot(rotation);
    const double f = scale * rd.factor(Dim::length);
    for (auto& c : corners)
      for (Vec3& v : c) v = offset + rot(f * v);
    // Placement can make a sliver of a valid triangle degenerate only through overflow or
    // underflow of extreme scales: checked again in SI.
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const auto& c = corners[k];
      const Vec3 n = cross(c[1] - c[0], c[2] - c[0]);
      if (!is_finite(c[0]) || !is_finite(c[1]) || !is_finite(c[2]) || !(norm(n) > 0.0))
        rd.fail_value(path + ".scale", *t.get("scale"),
                      "a scale that keeps triangle " + std::to_string(k + 1) + " of '" + *file + "' finite and of non-zero area");
    }
    TriangleMesh mesh = build_triangle_mesh(corners);
    mesh.name = rd.string(t, "name", path).value_or("mesh" + std::to_string(i));
    mesh.file = *file;
    mesh.material = material;
    mesh.motion = read_motion(rd, t, "motion", path, "meshes[].motion");
    spec.meshes.push_back(std::move(mesh));
  }
}

}  // namespace cdm::scene
