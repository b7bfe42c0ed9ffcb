#pragma once
/// @file slipping_ball.hpp
/// @brief A ball slipping on a rough surface: Garg et al. (2012) §3.3, eqs 38–42.
/// While slipping, dv/dt = −μg and dω/dt = μ m g R / I = 5μg/(2R) (I = 2/5 m R²);
/// slip ends at t_s = 2v₀/(7μg), after which the ball rolls with v = ωR = 5/7 v₀.
/// Non-dimensional: t' = μ g t_s / v₀ = 2/7, v' = ω'R/v₀ = 5/7.
namespace cdm::oracles {

struct SlippingParams {
  double radius;  // R [m]
  double v0;      // initial velocity [m/s], omega0 = 0
  double mu;      // friction coefficient [-]
  double g;       // gravity magnitude [m/s^2]
};

inline double slip_end_time(const SlippingParams& p) { return 2.0 * p.v0 / (7.0 * p.mu * p.g); }

inline double slipping_velocity(const SlippingParams& p, double t) {
  const double ts = slip_end_time(p);
  return t < ts ? p.v0 - p.mu * p.g * t : 5.0 / 7.0 * p.v0;
}

/// Angular velocity in the sense that rolls the ball forward [rad/s].
inline double slipping_angular_velocity(const SlippingParams& p, double t) {
  const double ts = slip_end_time(p);
  return t < ts ? 2.5 * p.mu * p.g * t / p.radius : 5.0 / 7.0 * p.v0 / p.radius;
}

}  // namespace cdm::oracles
