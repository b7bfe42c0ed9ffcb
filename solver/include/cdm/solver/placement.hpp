#pragma once
/// @file placement.hpp
/// @brief Random sequential addition: spheres accepted one at a time where they overlap
/// no sphere accepted before, no wall and no triangle mesh, found on a grid of cells at least one largest
/// contact distance wide. Along a periodic axis a sphere is tested against the images
/// across the faces too, so that blocks (and insertions) never place a pair of
/// particles that overlap through the period. Used by [[random_particles]] and by the
/// insertions (population.hpp).
#include <cstdint>
#include <memory>
#include <vector>

#include "cdm/solver/contact/mesh_contacts.hpp"
#include "cdm/solver/periodic_box.hpp"
#include "cdm/solver/vec3.hpp"
#include "cdm/solver/walls.hpp"

namespace cdm {

class SequentialPlacement {
 public:
  /// @p r_max: the largest radius any sphere tested or added will have [m]; the walls
  /// and meshes where they stand at time @p t [s].
  SequentialPlacement(double r_max, const std::vector<Wall>& walls, const std::vector<TriangleMesh>& meshes,
                      double t, const PeriodicBox& box);
  /// Whether a sphere of radius @p r at @p x clears every sphere added, every wall (its
  /// centre at least r inside each) and every mesh (no triangle nearer than r); touching
  /// is clear.
  bool clear(Vec3 x, double r) const;
  void add(Vec3 x, double r);

 private:
  struct Sphere {
    Vec3 x;
    double r;
  };
  std::int64_t cell(double v) const;  // the cell index of a coordinate
  bool clear_of_spheres(Vec3 x, double r) const;
  /// The slot of packed cell @p key in table_: its own, or the empty one where it would go.
  std::size_t slot_of(std::uint64_t key) const;

  double cell_;
  std::vector<Wall> walls_;  // at the placement time
  double time_;              // the placement time [s]
  std::unique_ptr<MeshContacts> meshes_;  // the meshes' search, when the scene has any
  PeriodicBox box_;
  // The spheres by cell: an open-addressed table (linear probing, at most half full) of
  // the occupied cells, each with its spheres as a chain through next_ (1-based; 0 ends).
  struct Cell {
    std::uint64_t key = 0;
    std::uint32_t head = 0;  // 0: an empty slot
  };
  std::vector<Cell> table_ = std::vector<Cell>(64);
  std::size_t occupied_ = 0;
  std::vector<Sphere> spheres_;
  std::vector<std::uint32_t> next_;
};

}  // namespace cdm
