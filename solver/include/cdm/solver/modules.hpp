#pragma once
/// @file modules.hpp
/// @brief Physics modules. A scene builds only the modules it names; each adds its
/// contribution to the particles' forces (and torques) once per force evaluation.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/materials.hpp"
#include "cdm/solver/neighbour_search.hpp"
#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/walls.hpp"

namespace cdm {

class ForceModule {
 public:
  virtual ~ForceModule() = default;
  virtual std::string name() const = 0;
  /// Add this module's forces for the particles' current positions and velocities.
  /// @p dt is the step the contact history advances by.
  virtual void add_forces(ParticleStore& p, double dt) = 0;
  /// State carried from step to step (contact history...), for checkpoints.
  virtual void save_state(OutArchive&) const {}
  virtual void load_state(InArchive&) {}
};

/// Uniform gravity: F = m g.
class GravityModule final : public ForceModule {
 public:
  explicit GravityModule(Vec3 g) : g_(g) {}
  std::string name() const override { return "gravity"; }
  void add_forces(ParticleStore& p, double dt) override;

 private:
  Vec3 g_;  // [m/s^2]
};

/// Largest overlap relative to a radius seen in the last force evaluation.
struct OverlapRecord {
  double ratio = 0.0;         // overlap / radius of the smaller partner [-]
  std::uint32_t particle = 0; // particle whose radius that is
  long partner = -1;          // other particle, or -1 - wall index for a wall
};

/// Linear spring–dashpot normal contact, with the tangential spring, history and
/// Coulomb friction when @p with_friction (only then is tangential history kept).
///
/// Contacts are found through a Verlet list: the cell-list search collects every pair
/// closer than r_i + r_j + skin, and the list is rebuilt only once some particle has
/// moved more than skin/2 since the last build — until then no pair outside the list
/// can touch. Tangential history lives beside each listed pair (and per particle and
/// wall), and is carried across rebuilds, so the hot loop does no hashing.
///
/// Threads: at each build the domain is cut into slabs along its longest side, at least
/// one interaction range wide, and each pair belongs to the lower of its particles'
/// slabs, so it adds forces only to particles of that slab and the next. Even slabs run
/// in parallel, then odd ones; each slab is one thread's, in a fixed order. Every
/// particle therefore receives its contributions in the same order whatever the number
/// of threads: trajectories are bit-identical for 1, 2, … threads.
class LinearContactModule final : public ForceModule {
 public:
  /// @p skin [m]: Verlet-list margin; 0 rebuilds every evaluation.
  LinearContactModule(PairTable pairs, std::vector<PlaneWall> walls, bool with_friction, double skin = 0.0);
  std::string name() const override;
  void add_forces(ParticleStore& p, double dt) override;

  const OverlapRecord& worst_overlap() const { return worst_; }
  std::size_t active_contacts() const { return n_active_; }
  /// Contacts carrying tangential history (zero when frictionless).
  std::size_t history_size() const { return friction_ ? n_active_ : 0; }
  std::size_t list_builds() const { return builds_; }
  std::size_t listed_pairs() const { return pi_.size(); }
  const std::vector<PlaneWall>& walls() const { return walls_; }
  void save_state(OutArchive& a) const override;
  void load_state(InArchive& a) override;

 private:
  template <bool Friction>
  void add_forces_impl(ParticleStore& p, double dt);
  bool needs_rebuild(const ParticleStore& p) const;
  void rebuild(const ParticleStore& p);

  PairTable pairs_;
  std::vector<PlaneWall> walls_;
  bool friction_;
  double skin_;
  CellListSearch search_;
  std::vector<ContactPair> candidates_;
  // Listed pairs (i < j) in processing order: slab by slab, pairs of slab s in
  // [slab_start_[s], slab_start_[s+1]).
  std::vector<std::uint32_t> pi_, pj_, slab_start_;
  std::vector<Vec3> hist_;              // tangential displacement per listed pair [m]
  std::vector<std::uint8_t> touch_;     // in contact at the previous evaluation
  std::vector<Vec3> wall_hist_;         // per particle and wall (i * walls + w)
  std::vector<std::uint8_t> wall_touch_;
  std::vector<double> x0_, y0_, z0_;    // positions at the last build
  bool built_ = false;
  std::size_t builds_ = 0;
  OverlapRecord worst_;
  std::size_t n_active_ = 0;
};

}  // namespace cdm
