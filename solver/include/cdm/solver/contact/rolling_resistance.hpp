#pragma once
/// @file rolling_resistance.hpp
/// @brief Constant-torque rolling resistance as a small pure function.
///
/// Constant directional torque (Zhou, Wright, Yang, Xu & Yu 1999, Physica A 269, 536;
/// "model A" of Ai, Chen, Rotter & Ooi 2011, Powder Technol. 206, 269; LIGGGHTS'
/// `rolling_friction cdt`): on particle i of a contact,
///   M_r = −μ_r R* |F_n| ω̂_r,   ω_r = ω_rel − (ω_rel·η)η,   ω_rel = ω_i − ω_j (wall: ω_i),
/// and −M_r on j. Only the part of the relative rotation in the tangent plane (rolling)
/// is resisted, not the part about the normal (twisting). R* = R_i R_j/(R_i+R_j)
/// (wall: R_i); |F_n| is the magnitude of the contact's normal force (spring + dashpot).
///
/// Switching off at rest: a constant torque would overshoot ω_r = 0 in the step that
/// reaches it and then chatter about zero with amplitude μ_r R*|F_n| Δt/I. The torque
/// is therefore capped at the torque that stops the relative rotation in one step,
///   |M_r| = min(μ_r R* |F_n|,  I* |ω_r| / (Δt n)),   I* = I_i I_j/(I_i+I_j) (wall: I_i),
/// where n ≥ 1 is the larger number of contacts of i or j (each may be stopped by all of
/// its contacts at once, so each takes its share). With the first-order scheme a lone
/// contact stops ω_r exactly in one step; velocity Verlet (which evaluates the torque at
/// a predicted ω) halves ω_r every step from there, without changing its sign. The cap
/// acts only when |ω_r| < n μ_r R*|F_n| Δt/I*, so it changes nothing else.
#include <algorithm>
#include <cmath>

#include "cdm/solver/vec3.hpp"

namespace cdm::contact {

/// Rolling-resistance torque on i [N m] (j receives its negative).
/// @p w_rel = ω_i − ω_j [rad/s], @p eta the contact normal from i to j,
/// @p inertia_eff I* [kg m²], @p dt the step [s], @p n_share ≥ 1 (see the file comment).
inline Vec3 rolling_torque(double mu_r, double r_star, double fn_mag, Vec3 w_rel, Vec3 eta, double inertia_eff,
                           double dt, double n_share) {
  const Vec3 wr = w_rel - dot(w_rel, eta) * eta;
  const double w = norm(wr);
  if (!(w > 0.0)) return Vec3{};
  const double m = std::min(mu_r * r_star * fn_mag, inertia_eff * w / (dt * n_share));
  return (-m / w) * wr;
}

}  // namespace cdm::contact
