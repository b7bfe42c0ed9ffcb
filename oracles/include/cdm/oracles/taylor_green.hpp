#pragma once
/// @file taylor_green.hpp
/// @brief Particles in a steady Taylor–Green vortex: Garg et al. (2012) §3.5, eqs 44–47
/// (verification case 5), one-way coupled.
///
/// Gas field (eq 44 with an amplitude U; the paper writes U = 1):
///   u_g = −U cos(k_x x) sin(k_y y),   v_g = U sin(k_x x) cos(k_y y),
/// fixed in time, never affected by the particles (solenoidal only when k_x = k_y).
/// Each particle, independently: dx/dt = v,  m dv/dt = K(ε_g, |u_g(x) − v|) (u_g(x) − v),
/// m = ρ_p π d³/6, K from drag.hpp (default Wen–Yu, as the paper) at a fixed ε_g (default
/// 0.95 = the paper's solids fraction 0.05). No gravity, no pressure-gradient force, no
/// particle–particle interaction. Positions are not wrapped into the periodic cell.
/// Integrated with SUNDIALS CVODE (BDF, dense Newton) per particle at rtol ≤ 1e-12;
/// atol (recorded in OracleAccuracy, for velocities) is 1e-3·rtol·U, and 1e-3·rtol/k for
/// positions.
///
/// Stagnation-point analysis (Maxey 1987, J. Fluid Mech. 174:441): at the cell corners
/// (x, y) = (π/(2k_x), π/(2k_y)) + (ξ, η) the field is u ≈ U k_x ξ, v ≈ −U k_y η. With a
/// linear drag of relaxation time τ (m/K at Re → 0) the compressive direction obeys
///   τ η'' + η' + U k_y η = 0  →  St λ² + λ + 1 = 0,  St = τ U k_y, λ in units of U k_y,
/// overdamped (particles approach the dividing streamline without crossing) for
/// St < St_c = 1/4 and oscillatory (they overshoot into the neighbouring cell) above.
/// Note the relaxation time of the law the oracle integrates: for Wen–Yu at ε_g,
/// K(w → 0) = 3π μ_g d ε_g^−2.65, so τ = τ_p ε_g^2.65 (0.8729 τ_p at ε_g = 0.95), with
/// τ_p = ρ_p d²/(18 μ_g) the Stokes time of eq 46. low_re_relaxation_time() returns it.
/// Garg's St = T_p/T_g with T_g = L/U (eqs 45–47) is a different scale: with L the
/// vortex-cell period 2π/k (MFIX's input: a 1 cm box, k = 200π m⁻¹) St_Maxey = τ U k =
/// 2π St_Garg, so St_c = 1/4 is St_Garg = 1/(8π) ≈ 0.040 — a case must say which it uses.
#include <array>
#include <complex>
#include <vector>

#include "cdm/oracles/drag.hpp"
#include "cdm/oracles/tolerance.hpp"

namespace cdm::oracles {

struct TaylorGreenParams {
  double U = 0.05;                        // gas velocity amplitude [m/s]
  double kx = 628.3185307179586;          // wavenumber k_x [1/m] (200π: MFIX's 1 cm box)
  double ky = 628.3185307179586;          // wavenumber k_y [1/m]
  double d = 1e-4;                        // particle diameter [m]
  double rho_p = 1800.0;                  // particle density [kg/m^3]
  double rho_g = 1.2;                     // gas density [kg/m^3]
  double mu_g = 1.8e-5;                   // gas viscosity [Pa s]
  double eps_g = 0.95;                    // gas volume fraction seen by the drag law [-]
  DragLaw law = DragLaw::WenYu;           // drag law
};

struct ParticleState2D {
  double x, y;    // position [m]
  double vx, vy;  // velocity [m/s]
};

struct TaylorGreenTrajectory {
  std::vector<double> x, y, vx, vy;  // one entry per output time [m], [m/s]
};

struct TaylorGreenSeries {
  std::vector<double> t;                          // output times [s]
  std::vector<TaylorGreenTrajectory> particles;   // in the order of the initial states
  OracleAccuracy accuracy;
};

/// @brief Gas velocity (u_g, v_g) at (x, y) [m/s].
std::array<double, 2> taylor_green_gas_velocity(const TaylorGreenParams& p, double x, double y);

/// @brief CVODE solution for every particle at the requested increasing times (t = 0 is the
/// initial state). Throws std::invalid_argument on bad parameters.
TaylorGreenSeries taylor_green_cvode(const TaylorGreenParams& p, const std::vector<ParticleState2D>& initial,
                                     const std::vector<double>& times, double rtol = 1e-12);

/// @brief Stokes relaxation time τ_p = ρ_p d²/(18 μ_g) [s] (Garg et al. eq 46).
double stokes_relaxation_time(double d, double rho_p, double mu_g);

/// @brief Relaxation time m/K(law, ε_g, w = 0) of the drag the oracle integrates [s].
double low_re_relaxation_time(const TaylorGreenParams& p);

/// @brief Critical Stokes number of the stagnation-point linearisation (Maxey 1987).
inline constexpr double critical_stokes_number = 0.25;

struct StagnationEigenvalues {
  std::complex<double> slow;  // the root closer to 0 (for St < 1/4 the slow decay)
  std::complex<double> fast;  // the other root (complex conjugate of `slow` for St > 1/4)
  bool oscillatory;           // St > 1/4: complex pair, particles overshoot
};

/// @brief Roots of St λ² + λ + 1 = 0 (λ in units of U k), St > 0. Computed without
/// cancellation: slow = −2/(1 + √(1 − 4St)), fast = 1/(St·slow) when real.
StagnationEigenvalues stagnation_point_eigenvalues(double stokes);

}  // namespace cdm::oracles
