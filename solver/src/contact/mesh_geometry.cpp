#include "cdm/solver/contact/mesh_geometry.hpp"

#include <algorithm>
#include <cstring>
#include <unordered_map>

namespace cdm {

namespace {

struct CoordKey {
  std::uint64_t b[3];
  bool operator==(const CoordKey& o) const { return b[0] == o.b[0] && b[1] == o.b[1] && b[2] == o.b[2]; }
};
struct CoordHash {
  std::size_t operator()(const CoordKey& k) const {
    std::uint64_t h = 14695981039346656037ull;
    for (std::uint64_t v : k.b) h = (h ^ v) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};
CoordKey key_of(Vec3 v) {
  // + 0.0 turns -0 into +0: the two are the same point.
  const double c[3] = {v.x + 0.0, v.y + 0.0, v.z + 0.0};
  CoordKey k;
  std::memcpy(k.b, c, sizeof c);
  return k;
}

}  // namespace

TriangleMesh build_triangle_mesh(const std::vector<std::array<Vec3, 3>>& corners) {
  TriangleMesh m;
  m.triangles.reserve(corners.size());
  m.edges.reserve(corners.size());
  m.normals.reserve(corners.size());
  std::unordered_map<CoordKey, std::uint32_t, CoordHash> vertex_id;
  std::unordered_map<std::uint64_t, std::uint32_t> edge_id;
  vertex_id.reserve(corners.size());
  edge_id.reserve(2 * corners.size());
  for (const auto& tri : corners) {
    std::array<std::uint32_t, 3> v{};
    for (int k = 0; k < 3; ++k) {
      const auto [it, added] = vertex_id.try_emplace(key_of(tri[static_cast<std::size_t>(k)]),
                                                     static_cast<std::uint32_t>(m.vertices.size()));
      if (added) m.vertices.push_back(tri[static_cast<std::size_t>(k)]);
      v[static_cast<std::size_t>(k)] = it->second;
    }
    std::array<std::uint32_t, 3> e{};
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t a = v[static_cast<std::size_t>(k)], b = v[static_cast<std::size_t>((k + 1) % 3)];
      const std::uint64_t key = (static_cast<std::uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
      const auto [it, added] = edge_id.try_emplace(key, m.edge_count);
      if (added) ++m.edge_count;
      e[static_cast<std::size_t>(k)] = it->second;
    }
    m.triangles.push_back(v);
    m.edges.push_back(e);
    // Divided component by component: an axis-aligned triangle's normal is then exactly
    // the unit axis, as a plane wall's is.
    const Vec3 n = cross(tri[1] - tri[0], tri[2] - tri[0]);
    const double len = norm(n);
    m.normals.push_back({n.x / len, n.y / len, n.z / len});
  }
  return m;
}

}  // namespace cdm
