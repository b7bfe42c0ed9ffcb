#pragma once
/// @file contact_geometry.hpp
/// @brief One contact as the force laws (linear_spring_dashpot.hpp, hertz_mindlin.hpp)
/// see it, the force they return, and the tangential history both laws keep.
///
/// Tangential history (Garg et al. 2012, Powder Technology 220, eqs 14–16):
///   contact start:  δ_t = V_t min(|δ_n| / |V_ij·η|, Δt)                      (eq 14)
///   afterwards:     δ_t(t+Δt) = δ_t(t) + V_t Δt, then projected onto the
///                   current tangent plane δ_t ← δ_t - (δ_t·η)η                 (eqs 15–16)
/// η is the unit normal from i to j; V_ij the relative velocity of i's contact point
/// with respect to j's.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "cdm/solver/vec3.hpp"

namespace cdm::contact {

/// A contact between i and j (or a wall).
struct ContactGeometry {
  double overlap;  // δ > 0 [m]
  Vec3 eta;        // unit normal from i to j
  Vec3 vrel;       // V_ij at the evaluation [m/s]
  Vec3 vrel_step;  // V_ij the positions moved with over the last step [m/s] (see ContactModule::StepVelocities)
};

/// A contact's tangential history: δ_t [m] and whether it was in contact at the
/// previous evaluation (0: the contact starts now). Unused without friction.
struct TangentialSlot {
  Vec3* delta_t = nullptr;
  std::uint8_t* touching = nullptr;
};

/// The force on i [N] (j receives its negative).
struct ContactForce {
  Vec3 total;               // normal + tangential
  Vec3 tangential;          // the tangential part, for the torques
  double normal_magnitude;  // |F_n|
};

/// Tangential displacement after this step (eqs 14–16). @p is_new marks contact start.
inline Vec3 update_tangential_displacement(Vec3 delta_t, bool is_new, Vec3 vt, double vn_mag, double overlap,
                                           double dt, Vec3 eta) {
  if (is_new) {
    const double dur = vn_mag > 0.0 ? std::min(std::abs(overlap) / vn_mag, dt) : dt;
    delta_t = dur * vt;
  } else {
    delta_t += dt * vt;
  }
  return delta_t - dot(delta_t, eta) * eta;
}

/// The history of @p slot advanced over the step @p dt with the displacement the
/// contact points actually made (g.vrel_step), as both laws keep it.
[[gnu::always_inline]] inline Vec3 advanced_history(const ContactGeometry& g, TangentialSlot slot, double dt) {
  const double vs_n = dot(g.vrel_step, g.eta);
  return update_tangential_displacement(*slot.delta_t, *slot.touching == 0, g.vrel_step - vs_n * g.eta,
                                        std::abs(vs_n), g.overlap, dt, g.eta);
}

}  // namespace cdm::contact
