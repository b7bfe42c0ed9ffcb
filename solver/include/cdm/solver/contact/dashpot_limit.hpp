#pragma once
/// @file dashpot_limit.hpp
/// @brief The largest time step at which an explicit spring–dashpot contact stays stable
/// and does not create energy, for cdm's two particle integrators.
///
/// An isolated contact of effective mass m, stiffness k and dashpot η is the oscillator
/// x'' = −ω² x − c x' with ω² = k/m, c = η/m = 2ζω, ζ = η/(2√(mk)). Scaled by the step,
/// p = ω²Δt², q = cΔt = 2ζΩ (Ω = ωΔt), and with V = Δt v, A = Δt² a:
///
/// paper_euler (simulation.cpp: v ← v + Δt a(x, v); x ← x + Δt v; the force of the next
/// step from the new x and v): (x, V) ← M (x, V) with
///   M = [[1 − p, 1 − q], [−p, 1 − q]],   det(λ − M) = λ² − (2 − p − q) λ + (1 − q).
/// Jury (Schur–Cohn) conditions for both roots inside the unit circle: P(1) = p > 0,
/// P(−1) = 4 − p − 2q > 0, |1 − q| < 1. The second, Ω² + 4ζΩ < 4, gives
///   Ω < 2(√(1 + ζ²) − ζ)   (2 for ζ = 0; 1/ζ, i.e. Δt < 2m/η, for ζ ≫ 1),
/// and implies the third (ζΩ < 2ζ/(√(1+ζ²)+ζ) < 1).
///
/// velocity_verlet (simulation.cpp: v½ = v + Δt/2 a; x ← x + Δt v½; the force of the new
/// step from x and the predicted velocity v + Δt a; v ← v½ + Δt/2 a_new): the force is
/// part of the state, (x, V, A) ← M (x, V, A) with
///   M = [[1, 1, 1/2], [−p/2, 1 − p/2 − q/2, 1/2 − p/4 − q/2], [−p, −p − q, −p/2 − q]],
///   det(λ − M) = λ³ + (p + 3q/2 − 2) λ² + (1 − 2q) λ + q/2.
/// Jury conditions for λ³ + a₂λ² + a₁λ + a₀: P(1) = p > 0; −P(−1) = 4 − p − 4q > 0;
/// |a₀| < 1 (q < 2); 1 − a₀² > |a₀a₂ − a₁| (q² + q + pq/2 < 2). The second,
/// Ω² + 8ζΩ < 4, gives
///   Ω < 2(√(1 + 4ζ²) − 2ζ)   (2 for ζ = 0; 1/(2ζ), i.e. Δt < m/η, for ζ ≫ 1),
/// and implies the other two (checked numerically for ζ in [0, 20]; the bound is checked
/// against the growth of the discrete update itself in tests/physics/test_dashpot_limit.cpp).
///
/// Hertz–Mindlin (hertz_mindlin.hpp): linearised at overlap δ the normal force has the
/// stiffness dF/dδ = (3/2) K δ^{1/2} and the dashpot α √(m K) δ^{1/4}, so ζ = α/√6 at every
/// overlap and ω grows with δ. The bound is taken at the largest overlap of an elastic
/// impact at the scene's impact speed v, δ_max = (5 m v²/(4K))^{2/5} (a damped impact
/// compresses less).
///
/// Stability is not enough: a contact is a transient, and near the bound the discrete
/// impact leaves faster than it arrived (under paper_euler t_col/10 is 1.13 bounds for
/// en = 1e-4, and the impact leaves 1.8 times as fast; 2.2 bounds for en = 1e-8: 6 times
/// as fast). A sweep of isolated impacts (tests/physics/
/// test_dashpot_limit.cpp, DashpotLimit.DISABLED_SweepForTheSafetyFactor: en from 1e-8 to
/// 1, linear and Hertz, both schemes, 33 entry phases within a step) at
/// Δt = min(t_col/10, r x bound) finds the exit speed at most 0.043 (paper_euler) and
/// 0.038 (velocity_verlet) above the model's own restitution for every r up to 0.6 and
/// 0.85: the order error that t_col/10 alone already gives at en of 0.5–0.7. Beyond, small
/// en leave faster (paper_euler, r = 0.7: 0.23 above; r = 0.9: faster than they arrived).
/// Hertz pairs stay within 0.02 of their restitution at every r (their t_col/10 is at most
/// 0.45 of the bound under paper_euler, 0.78 under velocity_verlet): the linear pairs set
/// the factor. It is 0.5, below both with a margin for what this one-dimensional analysis
/// leaves out (tangential and rolling forces, several contacts on one particle); it also
/// keeps velocity_verlet Hertz pairs of en below about 0.1 under t_H/10, conservatively.
#include <cmath>
#include <limits>

#include "cdm/solver/contact/hertz_mindlin.hpp"
#include "cdm/solver/materials.hpp"

namespace cdm::contact {

/// Fraction of the stability bound a time step may take (see the file comment).
inline constexpr double dashpot_safety_factor = 0.5;

/// Largest stable Ω = ωΔt of a linear spring–dashpot contact of damping ratio @p zeta
/// under paper_euler (@p predicted_velocity false) or velocity_verlet (true).
inline double dashpot_stable_omega_dt(double zeta, bool predicted_velocity) {
  // 2(sqrt(1 + b^2) - b) = 2/(sqrt(1 + b^2) + b), b = 2 zeta or zeta: no cancellation.
  const double b = predicted_velocity ? 2.0 * zeta : zeta;
  return 2.0 / (std::sqrt(1.0 + b * b) + b);
}

/// Largest stable time step [s] of a linear contact (mass @p m_eff, stiffness @p k,
/// dashpot @p eta): dashpot_stable_omega_dt(ζ)/ω.
inline double dashpot_stable_dt(double m_eff, double k, double eta, bool predicted_velocity) {
  const double omega = std::sqrt(k / m_eff);
  return dashpot_stable_omega_dt(eta / (2.0 * std::sqrt(m_eff * k)), predicted_velocity) / omega;
}

/// Largest overlap [m] of an elastic Hertz impact at normal speed @p v:
/// (1/2) m v² = (2/5) K δ^{5/2}.
inline double hertz_max_overlap(double m_eff, double k_hertz, double v) {
  return std::pow(1.25 * m_eff * v * v / k_hertz, 0.4);
}

/// Largest stable time step [s] of a Hertz contact (mass @p m_eff, Hertz constant
/// @p k_hertz, dashpot factor @p alpha) met at normal speed @p v: the linear bound with
/// the stiffness and dashpot at the impact's largest overlap.
inline double hertz_stable_dt(double m_eff, double k_hertz, double alpha, double v, bool predicted_velocity) {
  const double d = hertz_max_overlap(m_eff, k_hertz, v);
  return dashpot_stable_dt(m_eff, 1.5 * k_hertz * std::sqrt(d), hertz_normal_damping(alpha, m_eff, k_hertz, d),
                           predicted_velocity);
}

/// The largest time step [s] a pair's normal contact allows (dashpot_safety_factor x its
/// stability bound) for effective mass @p m_eff and radius @p r_star; a Hertz–Mindlin pair
/// at impact speed @p v_impact (no limit when it is 0: the stiffness is then unknown).
inline double dashpot_dt_limit(const PairParams& p, double m_eff, double r_star, double v_impact,
                               bool predicted_velocity) {
  if (p.law == ContactLaw::linear_spring_dashpot)
    return dashpot_safety_factor * dashpot_stable_dt(m_eff, p.kn, normal_damping(p, m_eff), predicted_velocity);
  if (v_impact <= 0.0) return std::numeric_limits<double>::infinity();
  return dashpot_safety_factor *
         hertz_stable_dt(m_eff, hertz_constant(p.e_star, r_star), p.hertz_alpha, v_impact, predicted_velocity);
}

}  // namespace cdm::contact
