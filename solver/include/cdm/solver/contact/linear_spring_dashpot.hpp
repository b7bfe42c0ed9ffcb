#pragma once
/// @file linear_spring_dashpot.hpp
/// @brief Linear spring–dashpot contact laws as small pure functions.
/// Garg et al. (2012), Powder Technology 220, §2.2, eqs 8–26:
///   normal force on i:      F_n = -k_n δ_n η - η_n V_n                       (eq 10)
///   tangential spring:      F_t = -k_t δ_t - η_t V_t                         (eq 11)
///   contact start:          δ_t = V_t min(|δ_n| / |V_ij·η|, Δt)              (eq 14)
///   afterwards:             δ_t(t+Δt) = δ_t(t) + V_t Δt, then projected onto
///                           the current tangent plane δ_t ← δ_t - (δ_t·η)η    (eqs 15–16)
///   Coulomb limit:          |F_t| > μ|F_n| → F_t = -μ|F_n| t, t = V_t/|V_t|,
///                           or -μ|F_n| δ_t/|δ_t| when V_t = 0                  (eqs 17–19)
/// η is the unit normal from i to j; V_ij the relative velocity of i's contact point
/// with respect to j's. The normal force is not clipped when the dashpot makes it
/// attractive near separation: the paper's analytic solution (App. B) keeps it too.
#include <algorithm>
#include <cmath>
#include <limits>

#include "cdm/solver/vec3.hpp"

namespace cdm::contact {

/// Normal spring–dashpot force on i [N] (eq 10).
inline Vec3 normal_force(double kn, double eta_n, double overlap, Vec3 eta, Vec3 vn) {
  return -(kn * overlap) * eta - eta_n * vn;
}

/// Tangential displacement after this step (eqs 14–16). @p is_new marks contact start.
inline Vec3 update_tangential_displacement(Vec3 delta_t, bool is_new, Vec3 vt, double vn_mag, double overlap,
                                           double dt, Vec3 eta) {
  if (is_new) {
    const double dur = vn_mag > 0.0 ? std::min(std::abs(overlap) / vn_mag, dt) : dt;
    delta_t = dur * vt;
  } else {
    delta_t += dt * vt;
  }
  return delta_t - dot(delta_t, eta) * eta;
}

/// Tangential force on i [N] with the Coulomb limit (eqs 11, 17–19).
inline Vec3 tangential_force(double kt, double eta_t, double mu, double fn_mag, Vec3 delta_t, Vec3 vt,
                             bool* sliding = nullptr) {
  Vec3 ft = -kt * delta_t - eta_t * vt;
  const double limit = mu * fn_mag;
  const bool slide = dot(ft, ft) > limit * limit;
  if (slide) {
    const double vt_mag = norm(vt);
    const double dt_mag = norm(delta_t);
    if (vt_mag > 0.0) ft = (-limit / vt_mag) * vt;
    else if (dt_mag > 0.0) ft = (-limit / dt_mag) * delta_t;
    else ft = Vec3{};
  }
  if (sliding) *sliding = slide;
  return ft;
}

}  // namespace cdm::contact
