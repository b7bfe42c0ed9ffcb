#pragma once
/// @file hertz_mindlin.hpp
/// @brief The Hertz–Mindlin contact law: small pure functions and the kernel the
/// contact module calls per contact (hertz_mindlin::force).
///
/// Normal force (Hertz 1882; Johnson, Contact Mechanics, 1985, §4.2) with a dashpot
/// of the Tsuji, Tanaka & Ishida (1992, Powder Technol. 71, 239) form:
///   F_n = −K δ^{3/2} η − η_n V_n,   K = (4/3) E* √R*,   η_n = α √(m* K) δ^{1/4},
///   1/E* = (1−ν_i²)/E_i + (1−ν_j²)/E_j,   1/R* = 1/R_i + 1/R_j   (wall: R* = R_i,
///   the wall material's E and ν),   m* = m_i m_j/(m_i+m_j)   (wall: m_i).
/// The restitution coefficient of this contact does not depend on the impact speed;
/// it is a function of α alone. Two published maps from e_n to α:
///  - exact:  α = √5 |ln e| / √(π² + ln² e). Antypov & Elliott (2011, EPL 94, 50004)
///    solved the damped Hertz equation m* δ'' = −K δ^{3/2} − α √(m*K) δ^{1/4} δ' in
///    closed form and showed this α gives exactly e. It is the form of LIGGGHTS'
///    `model hertz` (γ_n = 2√(5/6) β √(S_n m*), S_n = 2E*√(R*δ), β = ln e/√(ln²e+π²):
///    2√(5/6)√(3/2) = √5) and LAMMPS' `damping coeff_restitution`.
///  - tsuji:  α = √2 (1.2728 − 4.2783 e + 11.087 e² − 22.348 e³ + 27.467 e⁴ − 18.022 e⁵
///    + 4.8218 e⁶): Marshall's (2009, J. Comput. Phys. 228, 1541, eq 53) fit to
///    Tsuji's α(e) curve, times √2 for the effective-mass convention, as LAMMPS'
///    `damping tsuji`. A fit: it misses e by up to ~0.5 % (cases/hertz_restitution).
/// The normal force is not clipped when the dashpot makes it attractive just before
/// separation (as LIGGGHTS' default, limitForce off, and as cdm's linear model).
///
/// Tangential force: Mindlin's stiffness in the "no-slip" simplification (Mindlin 1949;
/// Di Renzo & Di Maio 2004, Chem. Eng. Sci. 59, 525; 2005, 60, 1303), with history:
///   k_t = 8 G* √(R* δ),   1/G* = (2−ν_i)/G_i + (2−ν_j)/G_j,   G = E/(2(1+ν)),
///   F_t = −k_t δ_t − η_t V_t,   η_t = η_n √(S_t/S_n) = 2 η_n √(G*/E*),
/// (S_t = 8G*√(R*δ): LIGGGHTS' γ_t = 2√(5/6) β √(S_t m*) has this ratio to γ_n). δ_t is
/// updated and projected onto the tangent plane exactly as the linear model's
/// (contact_geometry.hpp, eqs 14–16). Coulomb limit as LIGGGHTS' `tangential
/// history`: if the spring force |k_t δ_t| exceeds μ|F_n| the contact slides, the
/// history is rescaled so that |k_t δ_t| = μ|F_n| and F_t = −k_t δ_t (no dashpot);
/// otherwise F_t = −k_t δ_t − η_t V_t.
#include <cmath>
#include <numbers>

#include "cdm/solver/contact/contact_geometry.hpp"
#include "cdm/solver/vec3.hpp"

namespace cdm::contact {

/// Effective Young's modulus E* [Pa]: 1/E* = (1−ν_i²)/E_i + (1−ν_j²)/E_j.
inline double effective_youngs_modulus(double e_i, double nu_i, double e_j, double nu_j) {
  return 1.0 / ((1.0 - nu_i * nu_i) / e_i + (1.0 - nu_j * nu_j) / e_j);
}

/// Shear modulus G = E/(2(1+ν)) [Pa].
inline double shear_modulus(double e, double nu) { return e / (2.0 * (1.0 + nu)); }

/// Effective shear modulus G* [Pa]: 1/G* = (2−ν_i)/G_i + (2−ν_j)/G_j.
inline double effective_shear_modulus(double e_i, double nu_i, double e_j, double nu_j) {
  return 1.0 / ((2.0 - nu_i) / shear_modulus(e_i, nu_i) + (2.0 - nu_j) / shear_modulus(e_j, nu_j));
}

/// Hertz constant K = (4/3) E* √R* [N/m^{3/2}]; the elastic force is K δ^{3/2}.
inline double hertz_constant(double e_star, double r_star) { return 4.0 / 3.0 * e_star * std::sqrt(r_star); }

/// Elastic Hertz force magnitude K δ^{3/2} = (K √δ) δ [N].
inline double hertz_elastic_force(double k_hertz, double overlap) { return k_hertz * std::sqrt(overlap) * overlap; }

/// Normal dashpot coefficient η_n = α √(m* K) δ^{1/4} [kg/s] (Tsuji et al. 1992).
inline double hertz_normal_damping(double alpha, double m_eff, double k_hertz, double overlap) {
  return alpha * std::sqrt(m_eff * k_hertz * std::sqrt(overlap));
}

/// α that gives restitution e exactly (Antypov & Elliott 2011): √5 |ln e|/√(π² + ln² e).
inline double hertz_alpha_exact(double en) {
  const double l = std::log(en);
  return std::sqrt(5.0) * std::abs(l) / std::sqrt(std::numbers::pi * std::numbers::pi + l * l);
}

/// α from Marshall's (2009) fit to Tsuji's curve, × √2 for m* (LAMMPS `damping tsuji`).
inline double hertz_alpha_tsuji(double en) {
  const double e = en;
  const double poly = 1.2728 + e * (-4.2783 + e * (11.087 + e * (-22.348 + e * (27.467 + e * (-18.022 + e * 4.8218)))));
  return std::numbers::sqrt2 * poly;
}

/// Mindlin tangential stiffness k_t = 8 G* √R* √δ [N/m] (the square roots those of
/// hertz_constant and hertz_elastic_force, taken once in a kernel that calls all three).
inline double mindlin_stiffness(double g_star, double r_star, double overlap) {
  return 8.0 * g_star * std::sqrt(r_star) * std::sqrt(overlap);
}

/// Tangential force on i [N] with LIGGGHTS' Coulomb rule: when the spring force
/// exceeds μ|F_n| the history @p delta_t is rescaled onto the limit (so it holds
/// μ|F_n|/k_t) and the dashpot is dropped. Returns the force; @p sliding reports the state.
inline Vec3 mindlin_tangential_force(double kt, double eta_t, double mu, double fn_mag, Vec3& delta_t, Vec3 vt,
                                     bool* sliding = nullptr) {
  const Vec3 spring = -kt * delta_t;
  const double s2 = dot(spring, spring);
  const double limit = mu * fn_mag;
  const bool slide = s2 > limit * limit;
  if (sliding) *sliding = slide;
  if (slide) {
    const double scale = limit / std::sqrt(s2);  // s2 > limit^2 >= 0, so s2 > 0
    delta_t = scale * delta_t;
    return scale * spring;
  }
  return spring - eta_t * vt;
}

/// Hertz collision time of an elastic impact at relative normal speed @p v [s]:
/// t_H = 2.868 (m*²/(R* E*² v))^{1/5} (Johnson 1985, §11.4; the constant is
/// 2 (15/16)^{2/5} ∫₀¹ (1 − s^{5/2})^{−1/2} ds = 2.8682).
inline double hertz_collision_time(double m_eff, double r_star, double e_star, double v) {
  return 2.868 * std::pow(m_eff * m_eff / (r_star * e_star * e_star * v), 0.2);
}

/// Rayleigh time T_R = π R √(ρ/G) / (0.1631 ν + 0.8766) [s]: the time a Rayleigh wave
/// takes across the particle (Li, Xu & Thornton 2005, Powder Technol. 160, 219).
inline double rayleigh_time(double radius, double density, double e, double nu) {
  return std::numbers::pi * radius * std::sqrt(density / shear_modulus(e, nu)) / (0.1631 * nu + 0.8766);
}

namespace hertz_mindlin {

/// A pair of materials' parameters for this law (PairTable derives α and η_t/η_n).
struct Params {
  double e_star;       // effective Young's modulus E* [Pa]
  double g_star;       // effective shear modulus G* [Pa]
  double alpha;        // α in η_n = α √(m* K) δ^{1/4} [-]
  double etat_factor;  // η_t / η_n = 2 √(G*/E*) [-]
  double mu;           // Coulomb friction coefficient [-]
};

/// The force on i of one contact of effective mass @p m_eff [kg] and radius @p r_star
/// [m]; with @p Friction the Mindlin spring, whose history @p slot advances by @p dt
/// (and is rescaled onto the Coulomb limit when the contact slides).
template <bool Friction>
[[gnu::always_inline]] inline ContactForce force(const Params& pp, double m_eff, double r_star, const ContactGeometry& g,
                                                 [[maybe_unused]] double dt,
                                                 [[maybe_unused]] TangentialSlot slot) {
  const double k_hertz = hertz_constant(pp.e_star, r_star);
  const double eta_n = hertz_normal_damping(pp.alpha, m_eff, k_hertz, g.overlap);
  const double vn_mag = dot(g.vrel, g.eta);
  const Vec3 vn = vn_mag * g.eta;
  ContactForce out{-hertz_elastic_force(k_hertz, g.overlap) * g.eta - eta_n * vn, Vec3{}, 0.0};
  out.normal_magnitude = norm(out.total);
  if constexpr (Friction) {
    const Vec3 vt = g.vrel - vn;
    Vec3 h = advanced_history(g, slot, dt);
    const double kt = mindlin_stiffness(pp.g_star, r_star, g.overlap);
    const double eta_t = pp.etat_factor * eta_n;
    out.tangential = mindlin_tangential_force(kt, eta_t, pp.mu, out.normal_magnitude, h, vt);
    *slot.delta_t = h;  // after the force, which may rescale the history
    *slot.touching = 1;
    out.total += out.tangential;
  }
  return out;
}

}  // namespace hertz_mindlin
}  // namespace cdm::contact
