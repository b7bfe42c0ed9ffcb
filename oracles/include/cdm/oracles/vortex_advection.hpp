#pragma once
/// @file vortex_advection.hpp
/// @brief Tracers in the closed-form oscillating vortex fields of Garg et al. (2012)
/// §3.4, integrated in the exact field (no grid) — the reference for how far
/// interpolation from a grid moves a tracer.
///
/// With ξ = x/L, η = y/L, ζ = z/L on the cube [0, L]³ and c(t) = cos(πt/T):
///  - circle (2D, eq 43 as printed): u = 2U sin²(πξ) sin(2πη) c, v = −U sin(2πξ) sin²(πη) c;
///  - sphere (3D, LeVeque 1996): u = 2U sin²(πξ) sin(2πη) sin(2πζ) c,
///      v = −U sin(2πξ) sin²(πη) sin(2πζ) c,  w = −U sin(2πξ) sin(2πη) sin²(πζ) c.
/// Because u = f(x) c(t) with ∫₀ᵀ c dt = 0, every tracer returns exactly to its start at
/// t = nT; trajectories in between are integrated with SUNDIALS CVODE (Adams, functional
/// iteration) at rtol = atol/L = 1e-13.
#include <vector>

#include "cdm/oracles/tolerance.hpp"

namespace cdm::oracles {

struct VortexParams {
  bool three_d = false;   // false: eq 43 (circle); true: LeVeque's 3D field (sphere)
  double length = 1.0;    // L, side of the square/cube [m]
  double amplitude = 1.0; // U [m/s]
  double period = 0.25;   // T [s]
};

struct TracerPaths {
  /// x[k][i], y[k][i], z[k][i]: tracer i at times[k].
  std::vector<std::vector<double>> x, y, z;
  OracleAccuracy accuracy;
};

/// Trajectories of tracers starting at (x0[i], y0[i], z0[i]), sampled at increasing
/// @p times (starting at or after 0).
TracerPaths vortex_tracers(const VortexParams& p, const std::vector<double>& x0, const std::vector<double>& y0,
                           const std::vector<double>& z0, const std::vector<double>& times, double rtol = 1e-13);

}  // namespace cdm::oracles
