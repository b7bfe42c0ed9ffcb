#pragma once
/// @file drag_laws.hpp
/// @brief Gas–particle drag correlations as small pure functions.
///
/// Every law returns the per-particle drag coefficient K [kg/s]: the drag force on one
/// particle is F = K (u_g − v_p), with u_g the (interstitial) gas velocity at the
/// particle. In the notation of Garg et al. (2012) eq 30, F = β V_p/ε_s (u_g − v_p), so
/// the interphase momentum-exchange coefficient is β = K ε_s / V_p, V_p = π d³/6. K stays
/// finite as ε_s → 0 (a single particle) and as the slip w = |u_g − v_p| → 0.
///
/// Inputs: ρ_g, μ_g gas density and viscosity, d particle diameter, ε_g gas volume
/// fraction (ε_s = 1 − ε_g), w slip speed. Reynolds numbers:
///   single-particle  Re   = ρ_g w d / μ_g                          (Schiller–Naumann)
///   suspension       Re_p = ε_g ρ_g w d / μ_g (superficial slip)    (all others)
///
///  - Schiller & Naumann (1935), as in Garg et al. eq 48 / Clift, Grace & Weber (1978):
///      C_d = 24/Re (1 + 0.15 Re^0.687) for Re ≤ 1000, 0.44 above; F = ½C_d ρ_g (πd²/4) w²,
///      so K = 3π μ_g d (1 + 0.15 Re^0.687) (Re ≤ 1000), K = (π/8) 0.44 ρ_g d² w above.
///      No voidage correction: a single-particle law.
///  - Wen & Yu (1966) as written in MFIX (Syamlal, Rogers & O'Brien 1993; Gidaspow 1994):
///      β = ¾ C_d ε_s ε_g ρ_g w / d · ε_g^−2.65, C_d(Re_p) as above (0.44 for Re_p > 1000),
///      so K = 3π μ_g d ε_g^−2.65 (1 + 0.15 Re_p^0.687) (Re_p ≤ 1000),
///         K = (π/8) 0.44 ρ_g d² w ε_g^−1.65 above.
///  - Gidaspow (1994): Ergun (1952) for ε_g ≤ 0.8,
///      β = 150 ε_s² μ_g/(ε_g d²) + 1.75 ε_s ρ_g w / d,
///      so K = 25π ε_s μ_g d / ε_g + (1.75π/6) ρ_g d² w; Wen–Yu for ε_g > 0.8.
///      The law jumps at ε_g = 0.8 (it is not blended).
///  - Di Felice (1994): F = f₀ ε_g^−χ with the unhindered drag at the superficial slip,
///      f₀ = ½ C_d ρ_g (πd²/4) (ε_g w)², C_d = (0.63 + 4.8/√Re_p)² (Dallavalle),
///      χ = 3.7 − 0.65 exp(−(1.5 − log₁₀ Re_p)²/2),
///      so K = (π/8) ρ_g d² ε_g^(2−χ) (0.63 √w + 4.8 √(μ_g/(ε_g ρ_g d)))²  (finite at w = 0).
///  - Beetstra, van der Hoef & Kuipers (2007): with φ = ε_s,
///      F = 10φ/ε_g² + ε_g²(1 + 1.5√φ)
///          + 0.413 Re_p/(24 ε_g²) · (1/ε_g + 3ε_g φ + 8.4 Re_p^−0.343)
///                                  / (1 + 10^(3φ) Re_p^(−(1+4φ)/2)),
///      the drag (without the mean pressure-gradient force) normalised by the Stokes drag
///      at the superficial slip, F_d = 3π μ_g d (ε_g w) F: K = 3π μ_g d ε_g F,
///      β = 18 μ_g ε_g ε_s F / d² (as MFIX's current DRAG_BVK and OpenFOAM's Beetstra).
///      Check: the dense low-Re term 10φ/ε_g² gives the fixed-bed gradient β U/ε_g² =
///      180 μ_g φ² U/(ε_g³ d²), Carman–Kozeny. (Older MFIX releases used
///      18 μ_g ε_g² ε_s F/d², which misses Carman–Kozeny by a factor ε_g.)
/// In the limit ε_g → 1, Re → 0 Schiller–Naumann, Wen–Yu, Gidaspow and BVK all give
/// Stokes drag K = 3π μ_g d; Di Felice gives (π/8) 4.8² μ_g d = 0.96 · 3π μ_g d (the
/// Dallavalle C_d is 23.04/Re at small Re).
#include <cmath>
#include <numbers>

#include "cdm/solver/keywords.hpp"

namespace cdm::coupling {

enum class DragLaw { schiller_naumann, wen_yu, gidaspow, di_felice, beetstra };
inline constexpr Keywords<DragLaw, 5> drag_law_keywords{{{"schiller_naumann", DragLaw::schiller_naumann}, {"wen_yu", DragLaw::wen_yu}, {"gidaspow", DragLaw::gidaspow}, {"di_felice", DragLaw::di_felice}, {"beetstra", DragLaw::beetstra}}};
inline const char* to_string(DragLaw law) { return keyword_of(drag_law_keywords, law); }
/// How the drag enters the velocity update (drag_module.hpp).
enum class DragUpdate { explicit_force, implicit, exponential };
inline constexpr Keywords<DragUpdate, 3> drag_update_keywords{{{"explicit", DragUpdate::explicit_force}, {"implicit", DragUpdate::implicit}, {"exponential", DragUpdate::exponential}}};
inline const char* to_string(DragUpdate u) { return keyword_of(drag_update_keywords, u); }

namespace drag {

inline double schiller_naumann(double rho_g, double mu_g, double d, double /*eps_g*/, double w) {
  constexpr double pi = std::numbers::pi;
  const double re = rho_g * w * d / mu_g;
  if (re <= 1000.0) return 3.0 * pi * mu_g * d * (1.0 + 0.15 * std::pow(re, 0.687));
  return pi / 8.0 * 0.44 * rho_g * d * d * w;
}

inline double wen_yu(double rho_g, double mu_g, double d, double eps_g, double w) {
  constexpr double pi = std::numbers::pi;
  const double re = eps_g * rho_g * w * d / mu_g;
  if (re <= 1000.0) return 3.0 * pi * mu_g * d * std::pow(eps_g, -2.65) * (1.0 + 0.15 * std::pow(re, 0.687));
  return pi / 8.0 * 0.44 * rho_g * d * d * w * std::pow(eps_g, -1.65);
}

inline double gidaspow(double rho_g, double mu_g, double d, double eps_g, double w) {
  constexpr double pi = std::numbers::pi;
  if (eps_g <= 0.8) {
    const double eps_s = 1.0 - eps_g;
    return 25.0 * pi * eps_s * mu_g * d / eps_g + 1.75 * pi / 6.0 * rho_g * d * d * w;
  }
  return wen_yu(rho_g, mu_g, d, eps_g, w);
}

inline double di_felice(double rho_g, double mu_g, double d, double eps_g, double w) {
  constexpr double pi = std::numbers::pi;
  const double re = eps_g * rho_g * w * d / mu_g;
  // χ → 3.7 as Re_p → 0 (the Gaussian in log10 Re_p vanishes).
  const double chi = re > 0.0 ? 3.7 - 0.65 * std::exp(-0.5 * std::pow(1.5 - std::log10(re), 2)) : 3.7;
  const double s = 0.63 * std::sqrt(w) + 4.8 * std::sqrt(mu_g / (eps_g * rho_g * d));
  return pi / 8.0 * rho_g * d * d * std::pow(eps_g, 2.0 - chi) * s * s;
}

inline double beetstra(double rho_g, double mu_g, double d, double eps_g, double w) {
  constexpr double pi = std::numbers::pi;
  const double phi = 1.0 - eps_g;
  const double re = eps_g * rho_g * w * d / mu_g;
  double f = 10.0 * phi / (eps_g * eps_g) + eps_g * eps_g * (1.0 + 1.5 * std::sqrt(phi));
  if (re > 0.0)
    f += 0.413 * re / (24.0 * eps_g * eps_g) * (1.0 / eps_g + 3.0 * eps_g * phi + 8.4 * std::pow(re, -0.343)) /
         (1.0 + std::pow(10.0, 3.0 * phi) * std::pow(re, -0.5 * (1.0 + 4.0 * phi)));
  return 3.0 * pi * mu_g * d * eps_g * f;
}

}  // namespace drag

/// K [kg/s] of @p law (see the file comment for each form).
inline double drag_coefficient(DragLaw law, double rho_g, double mu_g, double d, double eps_g, double w) {
  switch (law) {
    case DragLaw::schiller_naumann: return drag::schiller_naumann(rho_g, mu_g, d, eps_g, w);
    case DragLaw::wen_yu: return drag::wen_yu(rho_g, mu_g, d, eps_g, w);
    case DragLaw::gidaspow: return drag::gidaspow(rho_g, mu_g, d, eps_g, w);
    case DragLaw::di_felice: return drag::di_felice(rho_g, mu_g, d, eps_g, w);
    case DragLaw::beetstra: return drag::beetstra(rho_g, mu_g, d, eps_g, w);
  }
  return 0.0;
}

/// β [kg/(m³ s)] from K: β = K ε_s / V_p.
inline double beta_from_coefficient(double k, double d, double eps_g) {
  return k * (1.0 - eps_g) / (std::numbers::pi * d * d * d / 6.0);
}

}  // namespace cdm::coupling
