// Triangle-mesh contacts (solver contact/mesh_contacts.hpp): one contact per touching
// region, wherever the sphere sits relative to the triangles' faces, edges and vertices,
// at the mesh's closest point; the tangential history carried as the contact moves from
// triangle to triangle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "cdm/solver/contact/mesh_contacts.hpp"

namespace {

using cdm::Vec3;
using Corners = std::vector<std::array<Vec3, 3>>;

/// An n x n grid of squares over [0, 1]^2 at z = 0, inner points moved in the plane by up to
/// @p jitter of a square, diagonals alternating.
Corners flat_grid(int n, double jitter, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  const double h = 1.0 / n;
  std::vector<Vec3> pts((n + 1) * (n + 1));
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j) {
      const bool inner = i > 0 && i < n && j > 0 && j < n;
      pts[i * (n + 1) + j] = {i * h + (inner ? u(rng) * h : 0.0), j * h + (inner ? u(rng) * h : 0.0), 0.0};
    }
  Corners c;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const Vec3 a = pts[i * (n + 1) + j], b = pts[(i + 1) * (n + 1) + j], cc = pts[(i + 1) * (n + 1) + j + 1],
                 d = pts[i * (n + 1) + j + 1];
      if ((i + j) % 2) c.push_back({a, b, cc}), c.push_back({a, cc, d});
      else c.push_back({a, b, d}), c.push_back({b, cc, d});
    }
  return c;
}

/// The closest point of every triangle to @p x, brute force: the mesh's nearest point.
Vec3 nearest(const Corners& c, Vec3 x) {
  Vec3 best;
  double d2 = INFINITY;
  for (const auto& t : c) {
    const Vec3 q = cdm::closest_point_on_triangle(x, t[0], t[1], t[2]).point;
    if (dot(q - x, q - x) < d2) d2 = dot(q - x, q - x), best = q;
  }
  return best;
}

cdm::MeshContacts contacts_of(const Corners& c, double reach) {
  cdm::MeshContacts m({cdm::build_triangle_mesh(c)});
  m.build_grid(reach);
  return m;
}

TEST(MeshContacts, FlatJitteredMeshGivesThePlaneContactEverywhere) {
  const Corners c = flat_grid(24, 0.3, 1);
  const double r = 0.05;  // the sphere's footprint covers up to ~20 triangles
  const cdm::MeshContacts m = contacts_of(c, r);
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> xy(0.1, 0.9), z(0.05 * r, 0.999 * r);
  std::vector<Vec3> at;
  for (int k = 0; k < 3000; ++k) at.push_back({xy(rng), xy(rng), z(rng)});
  // Exactly over vertices and edges of the regular border region too.
  for (int k = 0; k <= 4; ++k) at.push_back({0.5, k / 24.0 + 0.3, 0.6 * r});
  const auto& mesh = m.meshes()[0];
  for (std::size_t v = 0; v < mesh.vertices.size(); v += 7) at.push_back(mesh.vertices[v] + Vec3{0, 0, 0.7 * r});
  for (const Vec3& x : at) {
    if (x.x < r || x.x > 1 - r || x.y < r || x.y > 1 - r) continue;  // away from the mesh's border
    std::vector<cdm::MeshContacts::Contact> out;
    m.find(x, r, 0, out);
    ASSERT_EQ(out.size(), 1u) << "at " << x.x << " " << x.y << " " << x.z;
    EXPECT_NEAR(out[0].overlap, r - x.z, 1e-15);
    EXPECT_NEAR(out[0].eta.z, -1.0, 1e-15);
  }
}

TEST(MeshContacts, ConvexCurvedMeshOneContactAtTheNearestPoint) {
  // The outside of a cylinder of radius 0.1 tessellated with 256 segments and 16 rings. The
  // last segment ends at the angle 2 pi, whose sine is -2.4e-17, not the first segment's
  // 0: a crack of 2.4e-17 m at the seam, as generated meshes have, welded when read.
  Corners c;
  const int segs = 256, rings = 16;
  auto p = [&](int k, int j) {
    const double a = 2 * std::numbers::pi * k / segs;
    return Vec3{0.1 * std::cos(a), 0.1 * std::sin(a), 0.4 * j / rings};
  };
  for (int j = 0; j < rings; ++j)
    for (int k = 0; k < segs; ++k) {
      c.push_back({p(k, j), p(k + 1, j), p(k + 1, j + 1)});
      c.push_back({p(k, j), p(k + 1, j + 1), p(k, j + 1)});
    }
  const double r = 0.01;
  const cdm::MeshContacts m = contacts_of(c, r);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> ang(0, 2 * std::numbers::pi), z(0.05, 0.35), gap(-0.99 * r, -0.01 * r);
  for (int k = 0; k < 2000; ++k) {
    const double a = ang(rng), rho = 0.1 + r + gap(rng);
    const Vec3 x{rho * std::cos(a), rho * std::sin(a), z(rng)};
    std::vector<cdm::MeshContacts::Contact> out;
    m.find(x, r, 0, out);
    ASSERT_EQ(out.size(), 1u) << "at angle " << a;
    const Vec3 q = nearest(c, x);
    EXPECT_LT(norm(out[0].point - q), 1e-12);
    EXPECT_NEAR(out[0].overlap, r - norm(q - x), 1e-15);
  }
}

TEST(MeshContacts, ConvexCornerOneContactConcaveCornerOnePerFace) {
  // The cube [0, 1]^3, 4 x 4 squares per face.
  Corners c;
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side)
      for (const auto& t : flat_grid(4, 0.0, 0)) {
        std::array<Vec3, 3> f;
        for (int k = 0; k < 3; ++k) {
          double v[3];
          v[axis] = side;
          v[(axis + 1) % 3] = t[k].x;
          v[(axis + 2) % 3] = t[k].y;
          f[k] = {v[0], v[1], v[2]};
        }
        c.push_back(f);
      }
  const double r = 0.1;
  const cdm::MeshContacts m = contacts_of(c, r);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> off(0.0, 0.09);
  for (int k = 0; k < 500; ++k) {
    // Outside, near the vertex (1, 1, 1) or along the edge x = y = 1: one contact.
    const Vec3 x{1.0 + off(rng) * 0.8, 1.0 + off(rng) * 0.8, k % 2 ? 1.0 + off(rng) * 0.8 : 0.3 + off(rng)};
    std::vector<cdm::MeshContacts::Contact> out;
    m.find(x, r, 0, out);
    const Vec3 q{std::clamp(x.x, 0.0, 1.0), std::clamp(x.y, 0.0, 1.0), std::clamp(x.z, 0.0, 1.0)};
    if (norm(x - q) >= r) continue;
    ASSERT_EQ(out.size(), 1u);
    EXPECT_LT(norm(out[0].point - q), 1e-15);
    // Inside, in the corner (0, 0, 0) within r of all three faces: three contacts.
    const Vec3 y{0.01 + off(rng), 0.01 + off(rng), 0.01 + off(rng)};
    out.clear();
    m.find(y, r, 0, out);
    ASSERT_EQ(out.size(), 3u);
  }
}

TEST(MeshContacts, HistoryCarriedAcrossTriangles) {
  const Corners c = flat_grid(8, 0.2, 5);
  cdm::MeshContacts m({cdm::build_triangle_mesh(c)});
  cdm::ParticleStore p;
  p.add({0.05, 0.07, 0.0099}, {}, 0.01, 2500.0, 0, false);
  std::uint32_t first_triangle = 0;
  bool moved_on = false;
  for (int step = 0; step < 900; ++step) {
    p.x[0] = 0.05 + 0.001 * step;  // across about 7 squares and their diagonals
    p.y[0] = 0.07 + 0.0008 * step;
    m.update(p, false, static_cast<std::size_t>(step), 0.0);  // candidates listed anew at every step
    ASSERT_EQ(m.contacts().size(), 1u) << "step " << step;
    auto& ct = m.contacts()[0];
    if (step == 0) {
      EXPECT_EQ(ct.touching, 0);
      first_triangle = ct.triangle;
    } else {
      ASSERT_EQ(ct.touching, 1) << "history lost at step " << step;
      EXPECT_EQ(ct.delta_t.x, 1e-6 * step) << "step " << step;
    }
    moved_on |= ct.triangle != first_triangle;
    ct.delta_t = {1e-6 * (step + 1), 0.0, 0.0};  // as a force law would advance it
    ct.touching = 1;
  }
  EXPECT_TRUE(moved_on);
}

}  // namespace
