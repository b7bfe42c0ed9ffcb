#pragma once
/// @file suspension.hpp
/// @brief Homogeneous gas–particle suspension in a periodic box: the two-way coupled
/// mean-velocity equations of MFIX model A (pressure gradient shared by volume fraction),
/// 1D along z (up), gravity g > 0 toward −z, with an imposed mean pressure gradient
/// G = −dP/dz [Pa/m] (default: the mixture weight G = (ε_g ρ_g + ε_s ρ_p) g):
///   ε_g ρ_g dU/dt = ε_g G − ε_g ρ_g g + β (V − U)
///   ε_s ρ_p dV/dt = ε_s G − ε_s ρ_p g + β (U − V)
/// U interstitial gas velocity, V particle (mean) velocity, ε_g constant, β = β(law, ε_g,
/// |U − V|) from drag.hpp (β = K ε_s/V_p, Garg et al. 2012 eq 30/35). These are the gas
/// momentum equation of Garg eqs 2 and 35 and the sum over the particles of eq 30 for a
/// spatially uniform state (no convection, no viscous stress, I_gm = ε_s ∇P − β(U − V)).
///
/// Consequences used as checks:
///  - mixture momentum M = ε_g ρ_g U + ε_s ρ_p V obeys dM/dt = G − (ε_g ρ_g + ε_s ρ_p) g,
///    so it is conserved when G carries the mixture's weight;
///  - the slip w = U − V obeys dw/dt = G (1/ρ_g − 1/ρ_p) − β w (1/(ε_g ρ_g) + 1/(ε_s ρ_p)),
///    so it relaxes to the steady slip
///      β(w) w = G ε_g ε_s (ρ_p − ρ_g) / (ε_g ρ_g + ε_s ρ_p),
///    which for the weight-carrying G is β(w) w = ε_s ε_g (ρ_p − ρ_g) g (the particles'
///    buoyant weight per unit volume, reduced by ε_g because model A gives the particles
///    their share ε_s of the pressure gradient); found by GSL Brent root finding.
///  - with M conserved, U → (M + ε_s ρ_p w)/(ε_g ρ_g + ε_s ρ_p), V → U − w.
#include <limits>
#include <vector>

#include "cdm/oracles/drag.hpp"
#include "cdm/oracles/tolerance.hpp"

namespace cdm::oracles {

struct SuspensionParams {
  DragLaw law = DragLaw::WenYu;  // drag law for β
  double d = 1e-4;               // particle diameter [m]
  double rho_p = 2500.0;         // particle density [kg/m^3]
  double rho_g = 1.2;            // gas density [kg/m^3]
  double mu_g = 1.8e-5;          // gas viscosity [Pa s]
  double eps_g = 0.9;            // gas volume fraction, in (0, 1) [-]
  double g = 9.80665;            // gravity magnitude, toward −z [m/s^2]
  double G = std::numeric_limits<double>::quiet_NaN();  // −dP/dz [Pa/m]; NaN = mixture weight
  double U0 = 0.0;               // initial gas velocity [m/s]
  double V0 = 0.0;               // initial particle velocity [m/s]
};

struct SuspensionSeries {
  std::vector<double> t;  // [s]
  std::vector<double> U;  // gas interstitial velocity [m/s]
  std::vector<double> V;  // particle velocity [m/s]
  OracleAccuracy accuracy;
};

struct SuspensionSteady {
  double slip;  // steady w = U − V [m/s]
  double beta;  // β at the steady slip [kg/(m^3 s)]
  double U;     // final gas velocity if G carries the weight (momentum conserved), else NaN [m/s]
  double V;     // final particle velocity, same condition [m/s]
  OracleAccuracy accuracy;
};

/// @brief G actually used: p.G, or (ε_g ρ_g + ε_s ρ_p) g when p.G is NaN [Pa/m].
double suspension_pressure_gradient(const SuspensionParams& p);
/// @brief Mixture momentum per unit volume ε_g ρ_g U + ε_s ρ_p V [kg/(m^2 s)].
double suspension_momentum(const SuspensionParams& p, double U, double V);
/// @brief CVODE (BDF) solution at the requested increasing times (t = 0 is the start).
SuspensionSeries suspension_cvode(const SuspensionParams& p, const std::vector<double>& times, double rtol = 1e-12);
/// @brief Steady slip by GSL Brent root finding (relative tolerance 1e-14).
SuspensionSteady suspension_steady(const SuspensionParams& p);

}  // namespace cdm::oracles
