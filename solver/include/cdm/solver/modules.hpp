#pragma once
/// @file modules.hpp
/// @brief Physics modules. A scene builds only the modules it names; each adds its
/// contribution to the particles' forces (and torques) once per force evaluation.
#include <cstdint>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

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
class LinearContactModule final : public ForceModule {
 public:
  LinearContactModule(PairTable pairs, std::vector<PlaneWall> walls, bool with_friction);
  std::string name() const override;
  void add_forces(ParticleStore& p, double dt) override;

  const OverlapRecord& worst_overlap() const { return worst_; }
  std::size_t active_contacts() const { return n_active_; }
  /// Tangential history entries (zero when frictionless).
  std::size_t history_size() const { return history_.size(); }
  const std::vector<PlaneWall>& walls() const { return walls_; }

 private:
  template <bool Friction>
  void add_forces_impl(ParticleStore& p, double dt);

  PairTable pairs_;
  std::vector<PlaneWall> walls_;
  bool friction_;
  CellListSearch search_;
  std::vector<ContactPair> candidates_;
  // Tangential displacement per contact, keyed (i << 32 | j) for pairs and
  // (i << 32 | (0xFFFFFFFF - wall)) for walls.
  std::unordered_map<std::uint64_t, Vec3> history_, next_history_;
  OverlapRecord worst_;
  std::size_t n_active_ = 0;
};

}  // namespace cdm
