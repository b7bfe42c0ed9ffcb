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
/// Switching off at rest. Applied as it stands, a constant torque overshoots ω_r = 0 in
/// the step that reaches it and then chatters about zero (with velocity Verlet, which
/// uses each torque for a whole step, it can settle into a period-2 cycle that creeps).
/// The torque is therefore chosen implicitly, as Coulomb friction is: let ω_free be the
/// relative rotation the contact would have after the next kick of the integrator
/// without rolling resistance (the spins that kick starts from, plus Δt times the other
/// torques already on both particles divided by their inertia). If the resistance can
/// stop it within the step, |ω_free,r| I*/Δt ≤ μ_r R*|F_n| (I* = I_i I_j/(I_i+I_j),
/// wall: I_i), the torque is exactly the one that stops it, −I* ω_free,r/Δt; otherwise
/// it is the full μ_r R*|F_n| against ω_free,r. A rolling contact therefore decelerates
/// at the constant torque, stops in the step where it reaches rest, and then stays at
/// rest (a torque below μ_r R*|F_n| does not start it rolling), with no chatter.
#include <algorithm>
#include <cmath>

#include "cdm/solver/vec3.hpp"

namespace cdm::contact {

/// Rolling-resistance torque on i [N m] (j receives its negative).
/// @p w_free: ω_i − ω_j after the next kick without rolling resistance [rad/s] (see the
/// file comment); @p eta: the contact normal from i to j; @p inertia_eff: I* [kg m²];
/// @p dt: the step [s].
inline Vec3 rolling_torque(double mu_r, double r_star, double fn_mag, Vec3 w_free, Vec3 eta, double inertia_eff,
                           double dt) {
  const Vec3 wr = w_free - dot(w_free, eta) * eta;
  const double w = norm(wr);
  if (!(w > 0.0)) return Vec3{};
  const double m = std::min(mu_r * r_star * fn_mag, inertia_eff * w / dt);
  return (-m / w) * wr;
}

}  // namespace cdm::contact
