#pragma once
/// @file mesh_geometry.hpp
/// @brief Triangle meshes as walls: the triangles with their shared vertices and edges
/// (welded where an STL file repeats the same coordinates), and the closest point of a
/// triangle to a point, with the feature (face, edge or vertex) it lies on.
///
/// Closest point: Ericson, Real-Time Collision Detection (2005), §5.1.5: the Voronoi
/// regions of the triangle's vertices and edges are tested in turn with the barycentric
/// dot products, and a point in none of them projects onto the face.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cdm/solver/vec3.hpp"
#include "cdm/solver/walls/wall_motion.hpp"

namespace cdm {

/// A triangle mesh placed in the scene [m]. Triangle t has vertices triangles[t] (in the
/// file's order) and edges edges[t] (edge k joins vertex k and vertex k+1 mod 3); vertex
/// and edge ids are shared by every triangle that has that vertex or edge.
struct TriangleMesh {
  std::string name;
  std::string file;  // the STL file, as the scene named it (messages)
  int material = 0;
  std::vector<Vec3> vertices;                              // [m]
  std::vector<std::array<std::uint32_t, 3>> triangles;     // vertex ids
  std::vector<std::array<std::uint32_t, 3>> edges;         // edge ids
  std::vector<Vec3> normals;                               // unit, right-handed in the vertex order [-]
  std::uint32_t edge_count = 0;
  /// Rigid motion of the whole mesh (walls/wall_motion.hpp); the vertices above are its
  /// place at rest (the scene's), its body frame.
  WallMotion motion;

  std::size_t size() const { return triangles.size(); }
  Vec3 vertex(std::size_t t, int k) const { return vertices[triangles[t][static_cast<std::size_t>(k)]]; }
};

/// The mesh of @p corners (three corners per triangle, [m]): vertices welded where their
/// coordinates differ by at most 1e-10 of the mesh's extent (each coordinate; the first
/// one read is kept), edges shared by the triangles that have both their ends. A triangle
/// two of whose corners weld (a sliver that thin) is left out. The corners must be finite
/// and each triangle of non-zero area (io/stl_reader.hpp checks both).
TriangleMesh build_triangle_mesh(const std::vector<std::array<Vec3, 3>>& corners);

/// Where the closest point of a triangle lies.
enum class MeshFeature : std::uint8_t { face, edge, vertex };

struct TrianglePoint {
  Vec3 point;           // closest point of the triangle [m]
  MeshFeature feature;  // what it lies on
  int index;            // the edge (0: v0-v1, 1: v1-v2, 2: v2-v0) or vertex (0..2); 0 for the face
};

/// The point of triangle (a, b, c) closest to @p p (Ericson §5.1.5).
inline TrianglePoint closest_point_on_triangle(Vec3 p, Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, MeshFeature::vertex, 0};
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, MeshFeature::vertex, 1};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return {a + (d1 / (d1 - d3)) * ab, MeshFeature::edge, 0};
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, MeshFeature::vertex, 2};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return {a + (d2 / (d2 - d6)) * ac, MeshFeature::edge, 2};
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return {b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b), MeshFeature::edge, 1};
  const double denom = 1.0 / (va + vb + vc);
  return {a + (vb * denom) * ab + (vc * denom) * ac, MeshFeature::face, 0};
}

}  // namespace cdm
