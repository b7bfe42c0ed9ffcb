#pragma once
/// @file packed_bed.hpp
/// @brief Fixed-bed pressure gradient and minimum fluidisation from the drag laws.
///
/// Ergun (1952), Chem. Eng. Prog. 48:89, for superficial gas velocity U [m/s]:
///   ΔP/L = 150 μ_g ε_s² U/(ε_g³ d²) + 1.75 ρ_g ε_s U²/(ε_g³ d)            (frictional)
/// The gradient a drag law implies for a fixed bed (particles at rest, uniform, steady),
/// from the model-A gas momentum balance (Garg et al. 2012 eqs 2, 35):
///   0 = −ε_g dP/dz − ε_g ρ_g g − β (u_g − 0),  u_g = U/ε_g interstitial
///   ⇒ −dP/dz − ρ_g g = β(ε_g, w = U/ε_g) U / ε_g²                          (frictional)
/// (z up, gravity g toward −z). For Gidaspow's Ergun branch (ε_g < 0.8) this is Ergun's
/// equation exactly: β U/ε_g² = 150 ε_s² μ U/(ε_g³ d²) + 1.75 ε_s ρ_g U²/(ε_g³ d).
///
/// Minimum fluidisation: the U at which the frictional gradient carries the bed's buoyant
/// weight ε_s (ρ_p − ρ_g) g (the particle balance of model A, 0 = −ε_s dP/dz − ε_s ρ_p g +
/// β w, gives the same condition), found by GSL Brent root finding (relative 1e-14).
/// For comparison: Ergun's U_mf in closed form (the positive root of the quadratic
/// 1.75 Re²/ε³ + 150 ε_s Re/ε³ = Ar, Re = ρ_g U d/μ_g, Ar = d³ ρ_g (ρ_p − ρ_g) g/μ_g²), and
/// Wen & Yu's (1966) estimate Re_mf = √(33.7² + 0.0408 Ar) − 33.7, which is the same
/// quadratic with their fitted 1/(φ_s ε_mf³) ≈ 14 and (1 − ε_mf)/(φ_s² ε_mf³) ≈ 11.
#include "cdm/oracles/drag.hpp"
#include "cdm/oracles/tolerance.hpp"

namespace cdm::oracles {

struct BedParams {
  DragLaw law = DragLaw::Gidaspow;  // drag law for the fixed-bed gradient and U_mf
  double d = 5e-4;                  // particle diameter [m]
  double rho_p = 2500.0;            // particle density [kg/m^3]
  double rho_g = 1.2;               // gas density [kg/m^3]
  double mu_g = 1.8e-5;             // gas viscosity [Pa s]
  double eps_g = 0.4;               // bed voidage [-], (0, 1)
  double g = 9.80665;               // gravity magnitude [m/s^2]
};

/// @brief Ergun's frictional pressure gradient [Pa/m] at superficial velocity U >= 0.
double ergun_pressure_gradient(const BedParams& p, double U);
/// @brief Frictional gradient −dP/dz − ρ_g g = β(ε_g, U/ε_g) U/ε_g² of p.law [Pa/m].
double drag_law_pressure_gradient(const BedParams& p, double U);
/// @brief The bed's buoyant weight per unit volume ε_s (ρ_p − ρ_g) g [Pa/m].
double bed_buoyant_weight(const BedParams& p);

struct MinFluidisation {
  double U;         // superficial minimum-fluidisation velocity [m/s]
  double reynolds;  // ρ_g U d / μ_g [-]
  OracleAccuracy accuracy;
};

/// @brief U_mf of p.law by GSL Brent root finding.
MinFluidisation minimum_fluidisation(const BedParams& p);
/// @brief Ergun's U_mf at voidage p.eps_g, closed form (stable quadratic root) [m/s].
double ergun_minimum_fluidisation_velocity(const BedParams& p);
/// @brief Wen & Yu (1966) estimate of U_mf (independent of p.eps_g and p.law) [m/s].
double wen_yu_minimum_fluidisation_estimate(const BedParams& p);
/// @brief Archimedes number d³ ρ_g (ρ_p − ρ_g) g / μ_g² [-].
double archimedes_number(const BedParams& p);

}  // namespace cdm::oracles
