#include "cdm/solver/contact/mesh_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace cdm {

namespace {

/// A vertex's cell in the welding grid.
struct CellKey {
  std::int64_t c[3];
  bool operator==(const CellKey& o) const { return c[0] == o.c[0] && c[1] == o.c[1] && c[2] == o.c[2]; }
};
struct CellHash {
  std::size_t operator()(const CellKey& k) const {
    std::uint64_t h = 14695981039346656037ull;
    for (std::int64_t v : k.c) h = (h ^ static_cast<std::uint64_t>(v)) * 1099511628211ull;
    return static_cast<std::size_t>(h);
  }
};

}  // namespace

TriangleMesh build_triangle_mesh(const std::vector<std::array<Vec3, 3>>& corners) {
  TriangleMesh m;
  // Weld tolerance: 1e-10 of the mesh's extent (a mesh generated with cos(2 pi) != cos(0)
  // leaves cracks of 1e-17 m at its seam; STL's float32 coordinates are 6e-8 apart).
  double big = 0.0;
  for (const auto& tri : corners)
    for (const Vec3& v : tri) big = std::max({big, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  const double eps = big > 0.0 ? 1e-10 * big : 1.0;
  std::unordered_map<CellKey, std::vector<std::uint32_t>, CellHash> grid;
  grid.reserve(corners.size());
  auto cell = [&](Vec3 v) {
    return CellKey{{static_cast<std::int64_t>(std::floor(v.x / eps)), static_cast<std::int64_t>(std::floor(v.y / eps)),
                    static_cast<std::int64_t>(std::floor(v.z / eps))}};
  };
  auto vertex_id = [&](Vec3 v) {
    const CellKey k = cell(v);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid.find(CellKey{{k.c[0] + dx, k.c[1] + dy, k.c[2] + dz}});
          if (it == grid.end()) continue;
          for (std::uint32_t id : it->second) {
            const Vec3 d = m.vertices[id] - v;
            if (std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)}) <= eps) return id;
          }
        }
    const auto id = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back(v);
    grid[k].push_back(id);
    return id;
  };
  std::unordered_map<std::uint64_t, std::uint32_t> edge_id;
  edge_id.reserve(2 * corners.size());
  for (const auto& tri : corners) {
    const std::array<std::uint32_t, 3> v{vertex_id(tri[0]), vertex_id(tri[1]), vertex_id(tri[2])};
    // A sliver whose two corners welded has no surface left: nothing can touch it.
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
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
    const Vec3 p0 = m.vertices[v[0]], p1 = m.vertices[v[1]], p2 = m.vertices[v[2]];
    const Vec3 n = cross(p1 - p0, p2 - p0);
    const double len = norm(n);
    m.normals.push_back({n.x / len, n.y / len, n.z / len});
  }
  return m;
}

}  // namespace cdm
