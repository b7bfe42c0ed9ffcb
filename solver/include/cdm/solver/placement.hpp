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
#include <unordered_map>
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

  double cell_;
  std::vector<Wall> walls_;  // at the placement time
  double time_;              // the placement time [s]
  std::unique_ptr<MeshContacts> meshes_;  // the meshes' search, when the scene has any
  PeriodicBox box_;
  std::unordered_map<std::uint64_t, std::vector<Sphere>> cells_;
};

}  // namespace cdm
