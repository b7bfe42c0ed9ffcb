#pragma once
/// @file linear_spring_dashpot.hpp
/// @brief The linear spring–dashpot contact law: small pure functions and the kernel
/// the contact module calls per contact (linear_spring_dashpot::force).
/// Garg et al. (2012), Powder Technology 220, §2.2, eqs 8–26:
///   normal force on i:      F_n = -k_n δ_n η - η_n V_n                       (eq 10)
///   tangential spring:      F_t = -k_t δ_t - η_t V_t                         (eq 11)
///   history:                δ_t as in contact_geometry.hpp                   (eqs 14–16)
///   Coulomb limit:          |F_t| > μ|F_n| → F_t = -μ|F_n| t, t = V_t/|V_t|,
///                           or -μ|F_n| δ_t/|δ_t| when V_t = 0                  (eqs 17–19)
/// with k_t = kt_factor k_n and η_t = etat_factor η_n; η_n follows from the restitution
/// and m* (materials.hpp, eq 29). The normal force is not clipped when the dashpot makes
/// it attractive near separation: the paper's analytic solution (App. B) keeps it too.
#include <cmath>

#include "cdm/solver/contact/contact_geometry.hpp"
#include "cdm/solver/vec3.hpp"

namespace cdm::contact {

/// The normal force's component along η (eq 10): F_n = f η, f = −(k_n δ + η_n V_ij·η),
/// so |F_n| = |f| with no square root.
inline double normal_force_along(double kn, double eta_n, double overlap, double vn_along) {
  return -(kn * overlap + eta_n * vn_along);
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

namespace linear_spring_dashpot {

/// A pair of materials' parameters for this law.
struct Params {
  double kn;           // normal stiffness [N/m]
  double kt_factor;    // k_t / k_n [-]
  double etat_factor;  // η_t / η_n [-]
  double mu;           // Coulomb friction coefficient [-]
};

/// The force on i of one contact with normal damping @p eta_n [kg/s]; with @p Friction
/// the tangential spring, whose history @p slot advances by @p dt.
template <bool Friction>
[[gnu::always_inline]] inline ContactForce force(const Params& pp, double eta_n, const ContactGeometry& g,
                                                 [[maybe_unused]] double dt,
                                                 [[maybe_unused]] TangentialSlot slot) {
  const double vn_mag = dot(g.vrel, g.eta);
  const Vec3 vn = vn_mag * g.eta;
  const double fn_along = normal_force_along(pp.kn, eta_n, g.overlap, vn_mag);
  ContactForce out{fn_along * g.eta, Vec3{}, std::abs(fn_along)};
  if constexpr (Friction) {
    const Vec3 vt = g.vrel - vn;
    // Held in a local: read back through the slot after the byte store to `touching`
    // (a char may alias anything), it would be stored and loaded again.
    const Vec3 h = advanced_history(g, slot, dt);
    *slot.delta_t = h;
    *slot.touching = 1;
    const double kt = pp.kt_factor * pp.kn;
    const double eta_t = pp.etat_factor * eta_n;
    out.tangential = tangential_force(kt, eta_t, pp.mu, out.normal_magnitude, h, vt);
    out.total += out.tangential;
  }
  return out;
}

}  // namespace linear_spring_dashpot
}  // namespace cdm::contact
