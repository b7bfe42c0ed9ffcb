#pragma once
/// @file hertz_impact.hpp
/// @brief Normal impact of two elastic spheres (or a sphere and a wall) under Hertz's
/// law, restated from the literature (independently of solver/):
///
///   m* δ'' = −K δ^{3/2} − α √(m* K) δ^{1/4} δ',   δ(0) = 0, δ'(0) = v,
///   K = (4/3) E* √R*,  1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂,  1/R* = 1/R₁ + 1/R₂ (wall: R₁),
///   m* = m₁m₂/(m₁+m₂) (wall: m₁).
/// α = 0 is Hertz's elastic impact; α > 0 adds the dashpot of Tsuji, Tanaka & Ishida
/// (1992), whose restitution coefficient depends on α only.
///
/// Closed forms of the elastic impact (Johnson, Contact Mechanics, 1985, §11.4):
///   δ_max = (15 m* v² / (16 E* √R*))^{2/5},   F_max = K δ_max^{3/2},
///   t_c = 2 (δ_max/v) ∫₀¹ (1 − s^{5/2})^{−1/2} ds = 2 (δ_max/v) (2/5) B(2/5, 1/2)
///       (= 2.8682 (m*²/(R* E*² v))^{1/5}; the Beta function through std::tgamma).
/// Numerical solutions: SUNDIALS CVODE (Adams, dense Newton) at rtol 1e-12, the end of
/// contact (δ = 0 again) located by CVODE's root finding.
#include <vector>

#include "cdm/oracles/tolerance.hpp"

namespace cdm::oracles {

/// Effective Young's modulus E* [Pa] of two bodies.
double hertz_effective_modulus(double e1, double nu1, double e2, double nu2);

struct HertzImpactParams {
  double m_eff;   // m* [kg]
  double r_eff;   // R* [m]
  double e_star;  // E* [Pa]
  double v;       // normal approach speed at first touch [m/s] (> 0)
  double alpha = 0.0;  // dashpot coefficient α [-]; 0 = elastic
};

struct HertzClosedForm {
  double contact_time;  // t_c [s]
  double max_overlap;   // δ_max [m]
  double max_force;     // F_max [N]
};

/// Johnson's closed forms of the elastic impact (α is ignored).
HertzClosedForm hertz_closed_form(const HertzImpactParams& p);

struct HertzSeries {
  std::vector<double> overlap;  // δ at each requested time [m] (0 outside the contact)
  std::vector<double> force;    // repulsive normal force at each time [N] (0 outside)
  double contact_time = 0.0;    // [s] from first touch to δ = 0 again
  double exit_speed = 0.0;      // −δ' at the end of contact [m/s]
  double max_overlap = 0.0;     // largest δ over the integration [m] (at δ' = 0, a root)
  OracleAccuracy accuracy;
};

/// CVODE solution at @p times, measured from first touch (times < 0: before contact).
HertzSeries hertz_impact_cvode(const HertzImpactParams& p, const std::vector<double>& times, double rtol = 1e-12);

/// Restitution coefficient e(α) of the damped Hertz contact, from the nondimensional
/// equation ξ'' = −ξ^{3/2} − α ξ^{1/4} ξ', ξ(0) = 0, ξ'(0) = 1 (δ = δ₀ξ, t = δ₀ξ/v,
/// δ₀ = (m* v²/K)^{2/5}): e = −ξ'(τ_end) at the first return to ξ = 0. CVODE, rtol 1e-12.
double hertz_restitution(double alpha, OracleAccuracy* accuracy = nullptr, double rtol = 1e-12);

}  // namespace cdm::oracles
