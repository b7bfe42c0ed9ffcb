#pragma once
/// @file rolling_resistance_module.hpp
/// @brief Constant-torque rolling resistance (contact/rolling_resistance.hpp) on every
/// contact of a ContactModule (pairs, walls and meshes), with each pair's μ_r.
#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/force_module.hpp"

namespace cdm {

/// Runs after the contact module in the same force evaluation (it must be the last
/// module to add torques: it reads the torques already accumulated, to stop a rolling
/// contact exactly) and reads the contact module's normal forces; it keeps no state of
/// its own. Pairs are visited in the list's slab order, so results stay independent of
/// the thread count; among MPI ranks each visits its own slabs in that order, the
/// boundary slabs' torques passing between the ranks (rank_split.hpp).
class RollingResistanceModule final : public ForceModule {
 public:
  explicit RollingResistanceModule(const ContactModule& contacts) : c_(contacts) {}
  std::string name() const override { return "rolling_resistance(constant_torque)"; }
  void add_forces(ParticleStore& p, double dt) override;

 private:
  /// The torques at the walls' and at the meshes' contacts, after the pairs'.
  template <class FreeSpin>
  void wall_torques(ParticleStore& p, double dt, FreeSpin& free_spin) const;
  template <class FreeSpin>
  void mesh_torques(ParticleStore& p, double dt, FreeSpin& free_spin, bool threads) const;

  const ContactModule& c_;
};

}  // namespace cdm
