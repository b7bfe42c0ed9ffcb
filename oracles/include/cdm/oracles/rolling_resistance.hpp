#pragma once
/// @file rolling_resistance.hpp
/// @brief A sphere on a flat floor under constant-torque rolling resistance
/// M_r = μ_r R F_n (Zhou et al. 1999; Ai et al. 2011, model A), F_n = m g, I = (2/5) m R².
///
/// Rolling without slip (friction holds the contact point): m a = F_t, I ω' = −R F_t −
/// μ_r R m g (taking ω > 0 in the sense that rolls the sphere forward, v = ω R), so
///   a = −μ_r R m g / (m R + I/R) = −(5/7) μ_r g   until v = 0 at t_s = 7 v₀/(5 μ_r g),
/// with the friction force F_t = m a = −(5/7) μ_r m g holding the contact. If the friction
/// acts at a lever arm L (a soft sphere: the centre-to-contact distance R − δ) while the
/// resisting torque stays μ_r R m g, the rolling constraint is v = ω L and
///   a = −μ_r g R L / (0.4 R² + L²)   (= −(5/7) μ_r g at L = R).
/// Spinning in place on a frictionless floor (no tangential force; the spin axis in
/// the floor's plane): I ω' = −μ_r R m g, so
///   ω' = −5 μ_r g/(2R)   until ω = 0 at t_s = 2 R ω₀/(5 μ_r g).
/// Both stop for good: at rest the torque vanishes (it only opposes rotation).
#include <algorithm>

namespace cdm::oracles {

struct RollingParams {
  double radius;  // R [m]
  double mu_r;    // rolling resistance coefficient [-]
  double g;       // gravity magnitude [m/s^2]
};

/// Rolling without slip: speed of the centre [m/s] at time t from v0.
inline double rolling_velocity(const RollingParams& p, double v0, double t) {
  return std::max(0.0, v0 - 5.0 / 7.0 * p.mu_r * p.g * t);
}
inline double rolling_stop_time(const RollingParams& p, double v0) { return 7.0 * v0 / (5.0 * p.mu_r * p.g); }

/// Deceleration of rolling with the friction's lever arm @p lever [m/s^2] (> 0).
inline double rolling_deceleration(const RollingParams& p, double lever) {
  return p.mu_r * p.g * p.radius * lever / (0.4 * p.radius * p.radius + lever * lever);
}

/// Spinning in place: angular speed [rad/s] at time t from w0.
inline double spinning_angular_velocity(const RollingParams& p, double w0, double t) {
  return std::max(0.0, w0 - 2.5 * p.mu_r * p.g / p.radius * t);
}
inline double spinning_stop_time(const RollingParams& p, double w0) {
  return 2.0 * p.radius * w0 / (5.0 * p.mu_r * p.g);
}

}  // namespace cdm::oracles
