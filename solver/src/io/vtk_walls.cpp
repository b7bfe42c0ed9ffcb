#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "cdm/solver/io/vtk_writer.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

namespace {

/// The polygons of the scene's walls and meshes at one time, as VTK wants them.
struct Polygons {
  std::vector<double> points;          // x y z per point
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::int32_t> wall, material;  // per polygon

  std::int64_t point(Vec3 x) {
    points.insert(points.end(), {x.x, x.y, x.z});
    return static_cast<std::int64_t>(points.size() / 3 - 1);
  }
  void polygon(std::initializer_list<std::int64_t> ids, int w, int m) { polygon(std::vector<std::int64_t>(ids), w, m); }
  void polygon(const std::vector<std::int64_t>& ids, int w, int m) {
    connectivity.insert(connectivity.end(), ids.begin(), ids.end());
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    wall.push_back(w);
    material.push_back(m);
  }
};

/// Two unit vectors completing the unit @p n to a right-handed frame.
void frame(Vec3 n, Vec3& u, Vec3& v) {
  const Vec3 a = std::abs(n.x) < 0.9 ? Vec3{1.0, 0.0, 0.0} : Vec3{0.0, 1.0, 0.0};
  u = cross(n, a);
  u = (1.0 / norm(u)) * u;
  v = cross(n, u);
}

/// A box holding what the run shows (particles, gas domain, meshes, the finite walls),
/// where an infinite plane is drawn; lo > hi when there is nothing.
void extent(const Simulation& sim, double t, Vec3& lo, Vec3& hi) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  lo = {inf, inf, inf};
  hi = {-inf, -inf, -inf};
  auto take = [&](Vec3 x) {
    lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
    hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
  };
  // The particles' bounds: each process its own (Simulation::counted_runs), the largest
  // over the processes (exact: the same on any number of them).
  const ParticleStore& p = sim.local_particles();
  Vec3 plo = lo, phi = hi;
  for (const auto& [i0, i1] : sim.counted_runs())
    for (std::size_t i = i0; i < i1; ++i) {
      const Vec3 x = p.position(i);
      plo = {std::min(plo.x, x.x), std::min(plo.y, x.y), std::min(plo.z, x.z)};
      phi = {std::max(phi.x, x.x), std::max(phi.y, x.y), std::max(phi.z, x.z)};
    }
  std::vector<double> bounds = {-plo.x, -plo.y, -plo.z, phi.x, phi.y, phi.z};
  sim.rank_max(bounds);
  lo = {-bounds[0], -bounds[1], -bounds[2]};
  hi = {bounds[3], bounds[4], bounds[5]};
  if (sim.gas()) {
    const fluid::StaggeredGrid& g = sim.gas()->grid();
    take({g.lo(0), g.lo(1), g.lo(2)});
    take({g.lo(0) + g.length(0), g.lo(1) + g.length(1), g.lo(2) + g.length(2)});
  }
  for (const TriangleMesh& m : sim.spec().meshes)
    for (const Vec3& x : m.vertices) take(m.motion.point(x, t));
  for (const Wall& w0 : sim.spec().walls) {
    if (w0.shape == WallShape::plane) continue;
    const Wall w = w0.at(t);
    const double r = std::max(w.radius_start, w.radius_end);
    for (const Vec3& c : {w.point, w.point + w.length * w.normal}) {
      take(c - Vec3{r, r, r});
      take(c + Vec3{r, r, r});
    }
  }
  for (const InsertionSpec& in : sim.spec().insertions) {
    take(in.region.lower);
    take(in.region.upper);
  }
}

}  // namespace

void write_walls_vtp(const std::string& path, const Simulation& sim, vtk::Encoding encoding) {
  const double t = sim.time();
  const SceneSpec& s = sim.spec();
  Polygons g;
  Vec3 lo, hi;
  extent(sim, t, lo, hi);  // every process takes part
  if (path.empty()) return;
  const bool any = lo.x <= hi.x;
  const Vec3 centre = any ? 0.5 * (lo + hi) : Vec3{};
  const double half = any ? std::max(0.55 * norm(hi - lo), 1e-3) : 1.0;
  constexpr int segments = 64;
  for (std::size_t k = 0; k < s.walls.size(); ++k) {
    const Wall w = s.walls[k].at(t);
    const int id = static_cast<int>(k);
    if (w.shape == WallShape::plane) {
      // A square across the extent, centred where the extent's centre projects on it.
      Vec3 u, v;
      frame(w.normal, u, v);
      const Vec3 c = centre - w.distance(centre) * w.normal;
      g.polygon({g.point(c - half * u - half * v), g.point(c + half * u - half * v), g.point(c + half * u + half * v),
                 g.point(c - half * u + half * v)},
                id, w.material);
      continue;
    }
    // A surface of revolution (quads between the rings at its ends), or one of its end
    // caps (the ring of that end, as one polygon).
    const Vec3 a = w.normal, u = w.across, v = cross(a, u);
    std::vector<std::int64_t> ring0(segments), ring1(segments);
    for (int j = 0; j < segments; ++j) {
      const double phi = 2.0 * std::numbers::pi * j / segments;
      const Vec3 d = std::cos(phi) * u + std::sin(phi) * v;
      ring0[static_cast<std::size_t>(j)] = g.point(w.point + w.radius_start * d);
      ring1[static_cast<std::size_t>(j)] = g.point(w.point + w.length * a + w.radius_end * d);
    }
    if (w.shape == WallShape::cap_start) {
      g.polygon(ring0, id, w.material);
    } else if (w.shape == WallShape::cap_end) {
      g.polygon(ring1, id, w.material);
    } else {
      for (int j = 0; j < segments; ++j) {
        const std::size_t j0 = static_cast<std::size_t>(j), j1 = static_cast<std::size_t>((j + 1) % segments);
        g.polygon({ring0[j0], ring0[j1], ring1[j1], ring1[j0]}, id, w.material);
      }
    }
  }
  for (std::size_t k = 0; k < s.meshes.size(); ++k) {
    const TriangleMesh& m = s.meshes[k];
    const std::int64_t first = static_cast<std::int64_t>(g.points.size() / 3);
    for (const Vec3& x : m.vertices) g.point(m.motion.point(x, t));
    for (const auto& tri : m.triangles)
      g.polygon({first + tri[0], first + tri[1], first + tri[2]}, static_cast<int>(s.walls.size() + k), m.material);
  }
  vtk::XmlFile f(path, encoding, "PolyData");
  f.open("<FieldData>");
  f.array("TIME", 1, std::vector<double>{t});
  std::vector<std::string> names, materials;
  for (const Wall& w : s.walls) names.push_back(w.name);
  for (const TriangleMesh& m : s.meshes) names.push_back(m.name);
  for (const Material& m : s.materials) materials.push_back(m.name);
  if (!names.empty()) f.strings("wall_names", names);
  if (!materials.empty()) f.strings("material_names", materials);
  f.close("</FieldData>");
  const std::size_t np = g.points.size() / 3, nc = g.offsets.size();
  f.open("<Piece NumberOfPoints=\"" + std::to_string(np) + "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" +
         std::to_string(nc) + "\">");
  f.open("<Points>");
  f.array("position", 3, g.points);
  f.close("</Points>");
  f.open("<Polys>");
  f.array("connectivity", 1, g.connectivity);
  f.array("offsets", 1, g.offsets);
  f.close("</Polys>");
  f.open("<CellData Scalars=\"wall\">");
  f.array("wall", 1, g.wall);
  f.array("material", 1, g.material);
  f.close("</CellData>");
  f.close("</Piece>");
  f.write();
}

}  // namespace cdm
