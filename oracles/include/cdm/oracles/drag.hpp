#pragma once
/// @file drag.hpp
/// @brief Gas–particle drag laws restated from the published correlations, as reference
/// values for the solver's own (independently written) drag laws.
///
/// Conventions, fixed for every law here (the solver must match them exactly):
///  - ε_g gas volume fraction, ε_s = 1 − ε_g, d particle diameter, ρ_g, μ_g gas density
///    and dynamic viscosity, w = |u_g − v_p| ≥ 0 the slip: interstitial gas velocity minus
///    particle velocity, magnitude. V_p = π d³/6.
///  - Every law gives the per-particle coefficient K [kg/s]: the drag force on one particle
///    is F = K (u_g − v_p). The interphase momentum-exchange coefficient of Garg et al.
///    (2012) eq 30 (F = −V_p ∇P + β V_p/ε_s (u_g − v_p), MFIX "model A": the pressure
///    gradient is shared by volume fraction and NOT part of K) is β = K ε_s / V_p
///    [kg/(m³ s)]. K stays finite as ε_s → 0 (β → 0 there).
///  - Re_p = ρ_g ε_g w d / μ_g (superficial-slip particle Reynolds number; MFIX's
///    RE = D·VREL·ROP_g/Mu with ROP_g = ε_g ρ_g) for Wen–Yu, Gidaspow, Di Felice, BVK.
///    Schiller–Naumann (single particle) uses Re = ρ_g w d / μ_g (no ε_g).
///  - Every K is written through C_d·Re, which is finite at w = 0, so K(w = 0) is the
///    Re → 0 limit (no 0·∞).
///
/// The laws (K form used here; β form of the source in brackets):
///  - Schiller & Naumann (1933), as in Garg et al. (2012) eq 49 (case 6):
///      C_d = 24/Re (1 + 0.15 Re^0.687) for Re ≤ 1000, C_d = 0.44 for Re > 1000;
///      K = (π d²/8) ρ_g C_d w.  Garg eq 49 gives no upper limit (case 6 has Re ≈ 3);
///      the 0.44 Newton plateau above Re = 1000 is the usual extension (Schiller–Naumann
///      is fitted up to Re ≈ 800, Clift, Grace & Weber 1978) and the one the Wen–Yu law
///      below uses. C_d is discontinuous at Re = 1000: 0.438288 → 0.44 (+0.39 %).
///  - Wen & Yu (1966), in the form of Gidaspow (1994) and MFIX `DRAG_WEN_YU`
///    (model/drag_gs.f):  [β = (3/4) C_d ε_s ε_g ρ_g w / d · ε_g^−2.65]
///      C_d(Re_p) as Schiller–Naumann above with Re_p (≤ 1000 → correlation, > 1000 →
///      0.44; MFIX, OpenFOAM's lagrangian ErgunWenYu and PhasicFlow put Re_p = 1000 itself
///      on the correlation). Note some codes differ: OpenFOAM's older multiphaseEulerFoam
///      WenYu uses the interstitial Re = ρ_g w d/μ_g (no ε_g) — not the form here;
///      K = (π d²/8) C_d ρ_g ε_g^−1.65 w.  Re → 0: K → 3π μ_g d ε_g^−2.65.
///  - Gidaspow (1994) / Ding & Gidaspow (1990) (MFIX `DRAG_GIDASPOW`):
///      ε_g ≤ 0.8: Ergun   [β = 150 ε_s² μ_g/(ε_g d²) + 1.75 ε_s ρ_g w/d]
///                  K = V_p (150 ε_s μ_g/(ε_g d²) + 1.75 ρ_g w/d);
///      ε_g > 0.8: Wen–Yu as above.
///    The switch ε_g = 0.8 belongs to Ergun here, as in MFIX's DRAG_GIDASPOW (`EPg <= 0.8`),
///    the code of the paper cdm starts from; OpenFOAM GidaspowErgunWenYu and PhasicFlow
///    ErgunWenYu put ε_g = 0.8 on Wen–Yu instead. The law is discontinuous there: at d = 0.5 mm, air,
///    w = 1 m/s, β jumps from 1380 (Ergun, ε_g → 0.8⁻) to 1138.4 (Wen–Yu) kg/(m³ s).
///  - Di Felice (1994), Int. J. Multiphase Flow 20:153, doi:10.1016/0301-9322(94)90011-6,
///    in the CFD–DEM form of Xu & Yu (1997) / Zhou et al. (2010) and CFDEMcoupling's
///    DiFeliceDrag (model A):
///      C_d = (0.63 + 4.8/√Re_p)² (Dallavalle), χ = 3.7 − 0.65 exp(−(1.5 − log10 Re_p)²/2),
///      F = (1/2) C_d ρ_g (π d²/4) ε_g² w (u_g − v_p) ε_g^−χ, i.e. K = (π d²/8) C_d ρ_g ε_g^(2−χ) w.
///    The ε_g² makes the dynamic pressure superficial (ρ_g (ε_g w)²), as in Di Felice's
///    f₀ based on the superficial velocity. Re → 0: χ → 3.7, C_d Re_p → 4.8² = 23.04, so
///    K → 2.88 π μ_g d ε_g^−2.7: the Dallavalle C_d is NOT exact Stokes drag (0.96 of it).
///  - Beetstra, van der Hoef & Kuipers (2007), AIChE J. 53:489, with φ = ε_s:
///      F(φ, Re_p) = 10φ/ε_g² + ε_g² (1 + 1.5√φ)
///                 + 0.413 Re_p/(24 ε_g²) · (1/ε_g + 3 ε_g φ + 8.4 Re_p^−0.343)
///                                        / (1 + 10^(3φ) Re_p^−(1+4φ)/2),
///      [β = 18 μ_g ε_g ε_s F / d²  (MFIX DRAG_BVK: F_STOKES = 18 μ ε_g/d², times ε_s;
///       OpenFOAM Beetstra.C: CdRe = 24 ε_g F, and its dispersedDragModel exchange
///       coefficient 0.75 CdRe ε_s μ/d², the same β)]
///      K = 3π μ_g d ε_g F, i.e. F is normalised by the Stokes drag at the SUPERFICIAL slip
///      ε_g w, and excludes the mean-pressure-gradient force. Consistency check: in the
///      dense, Re → 0 limit the 10φ/ε_g² term alone gives the fixed-bed gradient
///      β U/ε_g² = 180 μ φ² U/(ε_g³ d²), exactly Carman–Kozeny. (With β = 18 μ ε_g² ε_s F/d²,
///      the Koch–Hill normalisation of the TOTAL force, BVK's F would miss Carman–Kozeny
///      by a factor ε_g — do not mix the two.) Limits: φ → 0, Re → 0: F → 1, K → 3π μ d.
///
/// The pressure-gradient force of eq 30, F_p = −V_p ∇P, is pressure_gradient_force().
#include <string_view>

#include "cdm/oracles/tolerance.hpp"

namespace cdm::oracles {

enum class DragLaw { SchillerNaumann, WenYu, Gidaspow, DiFelice, Beetstra };

/// @brief Name used in tables and messages: "schiller_naumann", "wen_yu", "gidaspow",
/// "di_felice", "beetstra".
std::string_view drag_law_name(DragLaw law);

/// @brief The local state a drag law sees. All SI.
struct DragState {
  double d;      // particle diameter [m], > 0
  double rho_g;  // gas density [kg/m^3], > 0
  double mu_g;   // gas dynamic viscosity [Pa s], > 0
  double eps_g;  // gas volume fraction [-], (0, 1]
  double slip;   // w = |u_g - v_p| [m/s], >= 0
};

/// @brief Re_p = ρ_g ε_g w d / μ_g (superficial slip).
double particle_reynolds(const DragState& s);
/// @brief Re = ρ_g w d / μ_g (single particle, no ε_g).
double single_particle_reynolds(const DragState& s);

/// @brief Schiller–Naumann C_d(Re) with the 0.44 plateau for Re > 1000 (Re > 0).
double schiller_naumann_cd(double re);
/// @brief C_d·Re of the same law, finite at Re = 0 (= 24).
double schiller_naumann_cd_re(double re);
/// @brief Dallavalle C_d = (0.63 + 4.8/√Re)² (Re > 0).
double dallavalle_cd(double re);
/// @brief Di Felice exponent χ(Re) = 3.7 − 0.65 exp(−(1.5 − log10 Re)²/2); χ(0) = 3.7.
double di_felice_chi(double re);
/// @brief Beetstra et al. dimensionless drag F(φ, Re) (φ = ε_s in [0, 1), Re >= 0).
double beetstra_f(double phi, double re);

/// @brief Per-particle drag coefficient K [kg/s] of `law`: F = K (u_g − v_p).
/// Throws std::invalid_argument naming the parameter for out-of-range input.
double drag_k(DragLaw law, const DragState& s);
/// @brief Interphase coefficient β = K ε_s / V_p [kg/(m^3 s)] (Garg et al. eq 30).
double drag_beta(DragLaw law, const DragState& s);

double schiller_naumann_k(const DragState& s);
double wen_yu_k(const DragState& s);
double gidaspow_k(const DragState& s);
double di_felice_k(const DragState& s);
double beetstra_k(const DragState& s);

/// @brief Pressure-gradient force on one particle along one axis, F_p = −V_p ∂P/∂x [N]
/// (Garg et al. eq 30, first term).
double pressure_gradient_force(double d, double dpdx);

/// @brief Particle volume π d³/6 [m³].
double particle_volume(double d);

/// @brief The laws are closed forms evaluated in double precision; checked against
/// 40-digit evaluations to ~1e-15 relative (tests/oracles/gas_reference_values.py).
OracleAccuracy drag_accuracy();

}  // namespace cdm::oracles
