#pragma once
/// @file force_module.hpp
/// @brief The interface of a physics module. A scene builds only the modules it names;
/// each adds its contribution to the particles' forces (and torques) once per force
/// evaluation.
#include <cstdint>
#include <string>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/particle_store.hpp"

namespace cdm {

class RankSplit;

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
  /// The particles were reordered (ParticleStore::permute): slot i now holds what slot
  /// @p from[i] held. Modules that keep per-particle state reorder it alike.
  virtual void permute(const std::vector<std::uint32_t>& /*from*/) {}
  /// Particles were removed or added (population.hpp), @p p is the store after: slot i
  /// holds what slot @p from[i] held, or a new particle where from[i] is new_particle.
  /// Modules that keep per-particle state follow.
  virtual void remap(const std::vector<std::uint32_t>& /*from*/, const ParticleStore& /*p*/) {}
  /// Among MPI ranks (rank_split.hpp): evaluate the forces of @p ranks' own particles
  /// (those of the others are theirs to evaluate) and return the per-particle arrays the
  /// module keeps from one evaluation to the next, which then travel with the particles
  /// whenever the ranks gather the state, and with each particle that changes rank at a
  /// list build (RankSplit::assign). Modules whose forces need no more than each
  /// particle's own state may ignore it.
  virtual std::vector<std::vector<double>*> share_among(RankSplit* /*ranks*/) { return {}; }
};

}  // namespace cdm
