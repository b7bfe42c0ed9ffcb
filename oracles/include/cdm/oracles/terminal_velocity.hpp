#pragma once
/// @file terminal_velocity.hpp
/// @brief A particle falling through an upward gas stream to its terminal velocity:
/// Garg et al. (2012), Powder Technology 220:122, §3.6, eqs 48–49 (verification case 6).
///
/// 1D along z (up), gravity g > 0 pointing to −z, gas velocity u frozen (the paper's
/// "decoupled" variant), particle velocity v, z the particle's displacement from its start:
///   dv/dt = −g (ρ_p − ρ_g)/ρ_p − (3/4) ρ_g C_d |v − u| (v − u) / (ρ_p d),   dz/dt = v,
/// C_d Schiller–Naumann with Re = ρ_g |v − u| d/μ_g (eq 49; 0.44 above Re = 1000, see
/// drag.hpp), pressure-gradient force neglected apart from the buoyancy ρ_g g carried by
/// the (ρ_p − ρ_g) factor, exactly as eq 48.
/// Generic version: the drag term is K(ε_g, w)(u − v)/m for any DragLaw at a constant gas
/// fraction ε_g (K from drag.hpp, m = ρ_p V_p); with SchillerNaumann (ε_g ignored) it is
/// eq 48 identically, since K/m = (3/4) ρ_g C_d w/(ρ_p d). The buoyancy term stays
/// −g (ρ_p − ρ_g)/ρ_p (hydrostatic pure-gas pressure).
///
/// Terminal state (dv/dt = 0): K(w) w = m g (ρ_p − ρ_g)/ρ_p with w = u − v > 0, found by
/// GSL Brent root finding. Case 6 values (g = 9.80665, the paper's MFIX gravity):
/// w = 0.4574017 m/s, v = −0.05740169 m/s, Re = 3.049 (the paper: ≈ 0.457, ≈ −0.0574).
/// With g = 9.81 v would be −0.05754.
#include <vector>

#include "cdm/oracles/drag.hpp"
#include "cdm/oracles/tolerance.hpp"

namespace cdm::oracles {

struct TerminalParams {
  double d = 1e-4;        // particle diameter [m]
  double rho_p = 2000.0;  // particle density [kg/m^3]
  double rho_g = 1.2;     // gas density [kg/m^3]
  double mu_g = 1.8e-5;   // gas viscosity [Pa s]
  double u_g = 0.4;       // gas velocity, + up [m/s]
  double g = 9.80665;     // gravity magnitude, acting toward −z [m/s^2]
  double v0 = 0.0;        // initial particle velocity, + up [m/s]
  DragLaw law = DragLaw::SchillerNaumann;  // drag law (generic version)
  double eps_g = 1.0;     // constant gas volume fraction seen by the law [-] (generic version)
};

struct TerminalSeries {
  std::vector<double> t;  // [s]
  std::vector<double> v;  // particle velocity [m/s]
  std::vector<double> z;  // displacement from the start [m]
  OracleAccuracy accuracy;
};

struct TerminalState {
  double slip;      // w = u_g − v [m/s]
  double velocity;  // terminal particle velocity v [m/s]
  double reynolds;  // Reynolds number of the law at the terminal slip [-]
  OracleAccuracy accuracy;
};

/// @brief CVODE (BDF, rtol, atol recorded) solution at the requested increasing times
/// (t = 0 is the start). Throws std::invalid_argument on bad parameters.
TerminalSeries terminal_velocity_cvode(const TerminalParams& p, const std::vector<double>& times, double rtol = 1e-12);

/// @brief Terminal slip and velocity by GSL Brent root finding (relative tolerance 1e-14).
TerminalState terminal_velocity(const TerminalParams& p);

}  // namespace cdm::oracles
