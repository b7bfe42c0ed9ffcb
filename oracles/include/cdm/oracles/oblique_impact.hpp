#pragma once
/// @file oblique_impact.hpp
/// @brief Oblique elastic impact of a sphere on a flat wall with Hertz–Mindlin contact
/// and Coulomb friction: the setup of Kharaz, Gorham & Salman (2001, Powder Technol.
/// 120, 281) as MFIX's DEM05 and Lethe model it (d = 5 mm, ρ = 4000 kg/m³, 3.9 m/s,
/// μ = 0.092, alumina E = 380 GPa, ν = 0.23 on glass E = 70 GPa, ν = 0.25, e_n = 1).
///
/// The contact model, restated (Hertz; Mindlin's stiffness in the no-slip form of
/// Di Renzo & Di Maio 2004, 2005, with the tangential displacement ξ accumulated over
/// the contact; LIGGGHTS' `tangential history` Coulomb rule):
///   normal:   m δ'' = −K δ^{3/2},  K = (4/3) E* √R,  δ(0) = 0, δ'(0) = v cos θ;
///   tangent:  F_t = −k_t ξ, k_t = 8 G* √(R δ), |F_t| ≤ μ K δ^{3/2};
///   slip velocity of the contact point u = v_t + L ω, lever arm L = R − δ (centre to
///   contact point); m v_t' = F_t, I ω' = L F_t, I = (2/5) m R².
///   stick:    ξ' = u;
///   slip:     F_t = −s μ K δ^{3/2} (s = ±1, the sign of the slip), ξ held on the limit,
///             ξ = s μ K δ^{3/2}/k_t = s c δ with c = μ E*/(6 G*).
/// The contact slides from the start when |u(0)| > c δ'(0) (the spring ξ = u t would
/// exceed the limit c δ = c δ' t at once); it goes from stick to slip when |ξ| reaches
/// c δ, and from slip back to stick when s u falls below s c δ' (ξ can no longer keep up
/// with the moving limit). These switches, and the end of contact (δ = 0), are roots of
/// SUNDIALS CVODE's root finding; between them CVODE (Adams, dense Newton) integrates
/// at rtol 1e-12.
///
/// Closed forms where the contact slides throughout ("gross sliding", Maw, Barnes &
/// Fawcett 1976; Thornton & Yin 1991; Di Renzo & Di Maio 2004): the friction impulse is
/// μ times the normal impulse 2 m v_n, so the tangential restitution of the centre is
///   e_t = v_t'/v_t = 1 − 2μ v_n / v_t = 1 − 2μ / tan θ,
/// and the rebound spin is ω' = μ ∫F_n L dt / I. With L = R (rigid sphere) that is
/// ω' = 5 μ v_n / R; with the model's lever arm L = R − δ, ∫F_n δ dt = J_n δ̄ where
/// δ̄ = δ_max B(7/5, 1/2)/2 (Hertz's phase-plane integral), so ω' = 5 μ v_n (R − δ̄)/R².
#include "cdm/oracles/tolerance.hpp"

namespace cdm::oracles {

struct ObliqueParams {
  double radius;           // R [m]
  double density;          // [kg/m^3]
  double e_particle, nu_particle;  // Young's modulus [Pa], Poisson ratio
  double e_wall, nu_wall;
  double mu;               // Coulomb friction coefficient
  double speed;            // impact speed [m/s]
  double angle_deg;        // incidence angle from the wall normal [deg]
};

struct ObliqueResult {
  double omega;            // rebound angular velocity, in the sense that rolls the sphere forward [rad/s]
  double vt_after;         // tangential velocity of the centre after the impact [m/s]
  double vn_after;         // normal rebound speed [m/s]
  double et;               // tangential restitution of the centre v_t'/v_t [-]
  double contact_time;     // [s]
  bool slid_throughout;    // the contact never stuck
  int switches;            // number of stick/slip switches
  OracleAccuracy accuracy;
};

/// CVODE solution of the Mindlin contact ODE above.
ObliqueResult oblique_impact_cvode(const ObliqueParams& p, double rtol = 1e-12);

struct ObliqueSliding {
  double et;               // 1 − 2μ/tan θ
  double omega_rigid;      // 5 μ v_n / R
  double omega_lever;      // 5 μ v_n (R − δ̄)/R²
};

/// Gross-sliding closed forms (valid where oblique_impact_cvode reports slid_throughout).
ObliqueSliding oblique_sliding_closed_form(const ObliqueParams& p);

}  // namespace cdm::oracles
