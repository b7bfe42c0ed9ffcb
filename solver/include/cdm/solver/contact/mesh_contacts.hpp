#pragma once
/// @file mesh_contacts.hpp
/// @brief Contacts of spheres with triangle-mesh walls (mesh_geometry.hpp): which
/// triangles a sphere touches, one contact per touching region however many triangles
/// meet there, and each contact's tangential history carried as it moves from triangle
/// to triangle.
///
/// One contact per local minimum of the distance. A sphere of centre X touches triangle
/// t when the closest point q_t of t is nearer than its radius. Several triangles touch
/// where a face meets its neighbours: on a flat mesh every triangle within the radius
/// does, each at its own closest point, and across an edge or a vertex two or more report
/// that same point. The contact is the point of the mesh nearest X locally: q_t is kept
/// when it is a local minimum of |X - q| over the mesh. A face point always is (the
/// distance grows in every direction within the face). An edge or vertex point f is not
/// when another triangle that contains f is nearer: the distance over a triangle is
/// convex, so from f it decreases into that triangle. Triangles reporting the same point
/// (to 1e-7 of the radius: rounding) count once, whichever mesh they belong to. Both tests defer only to a
/// better-ranked triangle (faces first, then the nearer, then the lower index), a strict
/// order, so two candidates never remove each other and every touching region keeps its
/// best. So a flat mesh, however finely tessellated, gives exactly the
/// plane's single contact, on a face, an edge or a vertex; a convex edge or corner gives
/// one contact at its closest point; a concave corner gives one contact per face. (LIGGGHTS
/// marks edges and corners between coplanar triangles inactive beforehand instead; the
/// rule here needs no angle threshold, so it also holds on finely curved meshes.)
///
/// Contact geometry. On a face the normal is the face's, the distance that of the plane
/// (dot(X - v0, n), the expression of a plane wall), so a face contact is a plane wall's
/// contact; on an edge or a vertex the normal is the direction from X to q. Meshes are
/// two-sided: a particle touches a triangle from either side. Vertices are welded within
/// a mesh (mesh_geometry.hpp), not between meshes: where two meshes meet edge to edge, a
/// sphere within reach of the seam feels the other mesh's border edge as an edge, so a
/// surface that must be smooth across a seam belongs in one STL file.
///
/// Moving meshes. A mesh moves as a rigid body (walls/wall_motion.hpp). Each particle is
/// taken into the mesh's body frame (the inverse motion), where the grid, the candidates
/// and the closest points are those of the mesh at rest; the normal is turned back into
/// the world, and the surface's velocity at the contact point enters the contact's
/// relative velocity, as for a moving wall.
///
/// History. The contacts of a particle are matched with those of the last evaluation on
/// the same mesh: each takes the history of the nearest unused previous contact point
/// within the particle's radius (a rolling contact moves by |v| Δt per step; distinct
/// contacts of one particle lie far apart). A contact that moves from one triangle to its
/// neighbour keeps its history; the force law projects it onto the new tangent plane.
///
/// Search. A uniform grid of cells over the meshes' bounding box lists, per cell, the
/// triangles that come within the reach (the largest radius and the Verlet skin) of any
/// point of the cell. When the Verlet list is built, each particle lists, from the cell
/// holding its centre, the triangles within its radius + skin; until the next build it
/// tests only those (most particles none). The grid is built once (again only if a
/// larger particle appears). Chosen over a bounding-volume tree (such
/// as CGAL's AABB tree): a particle's query is one cell lookup and a short list, without
/// a tree descent per particle and step, and the static grid is read-only, so threads
/// share it; large triangles are listed only in the cells they come near.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/contact/mesh_geometry.hpp"
#include "cdm/solver/particle_store.hpp"

namespace cdm {

class MeshContacts {
 public:
  explicit MeshContacts(std::vector<TriangleMesh> meshes);

  /// One contact of a particle with a mesh.
  struct Contact {
    std::uint32_t particle = 0;
    std::uint32_t triangle = 0;  // over all meshes in order (mesh_of)
    Vec3 point;                  // contact point on the mesh, in the mesh's body frame [m]
    Vec3 eta;                    // unit normal from the particle's centre towards the mesh
    Vec3 wall_velocity;          // velocity of the mesh's surface at the contact point [m/s]
    double overlap = 0.0;        // radius - distance [m]
    double lever = 0.0;          // centre to the contact point [m]
    Vec3 delta_t;                // tangential history [m]
    std::uint8_t touching = 0;   // 0: the contact starts now
    /// The list's order: by particle (a particle's contacts in the order found).
    static bool by_particle(const Contact& a, const Contact& b) { return a.particle < b.particle; }
  };

  /// The contacts at the particles' current positions, history carried from the last
  /// call (see the file's comment); in particle order, each particle's in triangle order.
  /// Threads split the particles as the integrator's pass does when @p threads. Each
  /// particle tests its candidates: the triangles within its radius + @p margin [m] when
  /// they were listed, listed again when @p builds (the Verlet list's build count)
  /// changes; the Verlet list is built before any particle moves @p margin / 2.
  /// @p time [s]: the time of the positions, where moving meshes stand (their candidates
  /// are listed again too once a mesh has moved margin / 2 since they were listed).
  /// @p runs: the particles whose contacts are wanted, as runs of slots [first, last) in
  /// order (an MPI rank's own, rank_split.hpp); all of them when nullptr.
  void update(const ParticleStore& p, bool threads, std::size_t builds, double margin, double time = 0.0,
              const std::vector<std::pair<std::uint32_t, std::uint32_t>>* runs = nullptr);
  std::vector<Contact>& contacts() { return contacts_; }
  const std::vector<Contact>& contacts() const { return contacts_; }
  /// The contacts [k0, k1) of particles [i0, i1) (contacts() is in particle order): a
  /// thread's share when threads split the particles as the integrator's pass does.
  std::pair<std::size_t, std::size_t> contacts_of(std::size_t i0, std::size_t i1) const;

  const std::vector<TriangleMesh>& meshes() const { return meshes_; }
  std::size_t mesh_of(std::uint32_t triangle) const { return tri_mesh_[triangle]; }
  int material_of(std::uint32_t triangle) const { return meshes_[tri_mesh_[triangle]].material; }

  void save_state(OutArchive& a) const;
  void load_state(InArchive& a);
  /// The particles were reordered: new index k holds old particle from[k].
  void permute(const std::vector<std::uint32_t>& from);
  /// Particles were removed or added: new index k holds old particle from[k], or is new
  /// (new_particle). The contacts of removed particles are dropped, the others renumbered.
  void remap(const std::vector<std::uint32_t>& from);

  /// The contacts of one particle at @p x with radius @p r, geometry only (no history).
  /// The grid must reach r (build_grid).
  void find(Vec3 x, double r, std::uint32_t particle, std::vector<Contact>& out, double time = 0.0) const;
  /// Lists the triangles within @p reach of every point of each cell (reach: the largest
  /// particle radius). Called by update when a particle exceeds the current reach.
  void build_grid(double reach);

 private:
  struct Touch {
    std::uint32_t triangle;
    MeshFeature feature;
    std::uint32_t feature_id;  // triangle, edge or vertex id (over all meshes)
    double distance;
    Vec3 point, eta;  // in the mesh's body frame
    Vec3 world;       // the point where the mesh stands now
  };
  /// find() among the triangles [t0, t1) (in increasing order).
  void find_among(Vec3 x, double r, std::uint32_t particle, const std::uint32_t* t0, const std::uint32_t* t1,
                  std::vector<Contact>& out, double time) const;
  /// Appends the triangles within @p reach of @p x at @p time to @p out, in increasing order.
  void gather(Vec3 x, double reach, double time, std::vector<std::uint32_t>& out) const;
  /// Where the point @p x at @p time is in mesh @p m's body frame.
  Vec3 to_body(std::size_t m, Vec3 x, double time) const {
    return moves_[m] ? inverse_[m].point(x, time) : x;
  }
  /// The triangles the cell holding @p x lists (none outside the grid).
  std::pair<const std::uint32_t*, const std::uint32_t*> cell_triangles(Vec3 x) const;
  double distance(Vec3 x, std::uint32_t t) const;  // from x to triangle t [m]
  void list_candidates(const ParticleStore& p, double margin, bool threads, double time,
                       const std::vector<std::pair<std::uint32_t, std::uint32_t>>* runs);
  bool contains(std::uint32_t t, MeshFeature f, std::uint32_t id) const;
  std::uint64_t fingerprint() const;

  std::vector<TriangleMesh> meshes_;
  // All meshes' triangles in one numbering, vertex and edge ids offset per mesh.
  std::vector<std::array<Vec3, 3>> corner_;
  std::vector<Vec3> normal_;
  std::vector<std::array<std::uint32_t, 3>> tri_v_, tri_e_;
  std::vector<std::uint32_t> tri_mesh_;
  // The grid: cell (ix, iy, iz) of edge h_ from lo_ lists cell_tris_[cell_start_[c] ..).
  Vec3 lo_;
  double h_ = 0.0, reach_ = -1.0;
  long nx_ = 0, ny_ = 0, nz_ = 0;
  std::vector<std::uint32_t> cell_start_, cell_tris_;

  // Per particle i, the triangles cand_[cand_start_[i] .. cand_start_[i + 1]) it may touch.
  std::vector<std::uint32_t> cand_start_, cand_;
  bool listed_ = false;
  std::size_t builds_ = 0;
  // The runs of particles listed (update()'s runs; empty with listed_all_: every one).
  std::vector<std::pair<std::uint32_t, std::uint32_t>> listed_runs_;
  bool listed_all_ = true;
  double listed_time_ = 0.0, listed_reach_ = 0.0;  // when the candidates were listed, and rmax + margin
  // Per mesh: whether it moves, the inverse of its motion (world → body frame), and the
  // largest distance of its vertices from its rotation axis [m].
  std::vector<char> moves_;
  std::vector<WallMotion> inverse_;
  std::vector<double> axis_reach_;
  bool any_moves_ = false;

  std::vector<Contact> contacts_, prev_;  // this evaluation's and the last's
};

}  // namespace cdm
