// Checks of the drag-law and packed-bed oracles: values against an independent 40-digit
// evaluation (gas_reference_values.py, written in MFIX's β form rather than the K form
// of oracles/src/drag.cpp), the limits and switch points each law documents, and the
// fixed-bed identities (Gidaspow's Ergun branch is Ergun; U_mf by root finding equals
// Ergun's closed form).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "cdm/oracles/drag.hpp"
#include "cdm/oracles/packed_bed.hpp"

namespace {

using namespace cdm::oracles;
constexpr double pi = std::numbers::pi;

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

struct RefPoint {
  double d, rho_g, mu_g, eps_g, w;
  double beta_wen_yu, beta_gidaspow, beta_di_felice, beta_bvk, k_sn;
};

// /usr/bin/python3 tests/oracles/gas_reference_values.py (mpmath, 40 digits). Re_p of the
// rows: 1.90, 20.0, 567, 3000 (above the Wen–Yu Newton switch), 4.5 (water, Ergun
// branch), 0.35 (Ergun branch, Re < 1).
const RefPoint kRef[] = {
    {1e-4, 1.2, 1.8e-5, 0.95, 0.3, 2.2885253250205709e+3, 2.2885253250205709e+3, 2.4518913947339039e+3,
     2.9330541006016665e+3, 2.1061378970414172e-8},
    {5e-4, 1.2, 1.8e-5, 0.6, 1.0, 4.3646392508557549e+3, 4.56e+3, 3.5949160750229813e+3, 4.886695145952516e+3,
     2.2634455732470945e-7},
    {2e-3, 1.2, 1.8e-5, 0.85, 5.0, 2.3708569572856713e+2, 2.3708569572856713e+2, 2.9323489665896407e+2,
     3.7753316785616481e+2, 4.7722150536254743e-6},
    {5e-3, 1.2, 1.8e-5, 0.9, 10.0, 9.4237778766054821e+1, 9.4237778766054821e+1, 1.0981347855895363e+2,
     1.4453662463329435e+2, 5.1836278784231588e-5},
    {1e-3, 1000, 1e-3, 0.45, 0.01, 1.1678415544815743e+5, 1.1045833333333333e+5, 9.3343752900876602e+4,
     1.2561042625344427e+5, 1.6301197829009838e-5},
    {3e-4, 1.2, 1.8e-5, 0.7, 0.05, 3.1054403810574125e+3, 3.9621428571428571e+3, 3.1537488863809395e+3,
     5.3201846329923983e+3, 5.8527871136377848e-8},
};

TEST(DragOracle, MatchesIndependentHighPrecisionValues) {
  for (const auto& r : kRef) {
    const DragState s{r.d, r.rho_g, r.mu_g, r.eps_g, r.w};
    EXPECT_LT(rel(drag_beta(DragLaw::WenYu, s), r.beta_wen_yu), 1e-14) << "Re_p " << particle_reynolds(s);
    EXPECT_LT(rel(drag_beta(DragLaw::Gidaspow, s), r.beta_gidaspow), 1e-14) << "Re_p " << particle_reynolds(s);
    EXPECT_LT(rel(drag_beta(DragLaw::DiFelice, s), r.beta_di_felice), 1e-14) << "Re_p " << particle_reynolds(s);
    EXPECT_LT(rel(drag_beta(DragLaw::Beetstra, s), r.beta_bvk), 1e-14) << "Re_p " << particle_reynolds(s);
    EXPECT_LT(rel(drag_k(DragLaw::SchillerNaumann, s), r.k_sn), 1e-14) << "Re " << single_particle_reynolds(s);
    // β and K are the same law: β = K ε_s / V_p.
    for (DragLaw law : {DragLaw::SchillerNaumann, DragLaw::WenYu, DragLaw::Gidaspow, DragLaw::DiFelice,
                        DragLaw::Beetstra}) {
      EXPECT_LT(rel(drag_beta(law, s), drag_k(law, s) * (1 - r.eps_g) / (pi * r.d * r.d * r.d / 6)), 1e-15);
    }
  }
}

TEST(DragOracle, StokesLimitOfEverySingleParticleLaw) {
  const double d = 2e-4, mu = 1.8e-5, stokes = 3 * pi * mu * d;
  const DragState s{d, 1.2, mu, 1.0, 0.0};
  // ε_g = 1, w = 0: Schiller–Naumann, Wen–Yu, Gidaspow (ε_g >= 0.8 → Wen–Yu) and BVK are
  // exactly Stokes drag; Di Felice's Dallavalle C_d gives 4.8²/24 = 0.96 of it.
  EXPECT_LT(rel(drag_k(DragLaw::SchillerNaumann, s), stokes), 1e-15);
  EXPECT_LT(rel(drag_k(DragLaw::WenYu, s), stokes), 1e-15);
  EXPECT_LT(rel(drag_k(DragLaw::Gidaspow, s), stokes), 1e-15);
  EXPECT_LT(rel(drag_k(DragLaw::Beetstra, s), stokes), 1e-15);
  EXPECT_LT(rel(drag_k(DragLaw::DiFelice, s), 0.96 * stokes), 1e-15);
  // w → 0 approaches the w = 0 value continuously (no 0·∞ at small slip).
  for (DragLaw law : {DragLaw::SchillerNaumann, DragLaw::WenYu, DragLaw::DiFelice, DragLaw::Beetstra}) {
    const double k0 = drag_k(law, s);
    const double k1 = drag_k(law, {d, 1.2, mu, 1.0, 1e-12});
    EXPECT_LT(rel(k1, k0), 1e-6) << drag_law_name(law);
    EXPECT_GT(k1, k0) << drag_law_name(law);  // inertia only adds drag
  }
  // With particles around, w = 0: Wen–Yu 3πμd ε^−2.65, Di Felice 2.88πμd ε^−2.7,
  // BVK 3πμd ε F0(φ), F0 = 10φ/ε² + ε²(1 + 1.5√φ).
  const double e = 0.7, phi = 0.3;
  const DragState sd{d, 1.2, mu, e, 0.0};
  EXPECT_LT(rel(drag_k(DragLaw::WenYu, sd), stokes * std::pow(e, -2.65)), 1e-15);
  EXPECT_LT(rel(drag_k(DragLaw::DiFelice, sd), 0.96 * stokes * std::pow(e, -2.7)), 1e-15);
  const double f0 = 10 * phi / (e * e) + e * e * (1 + 1.5 * std::sqrt(phi));
  EXPECT_LT(rel(drag_k(DragLaw::Beetstra, sd), stokes * e * f0), 1e-15);
}

TEST(DragOracle, GidaspowSwitchAtEpsilonPointEight) {
  // ε_g <= 0.8 is Ergun (MFIX), just above 0.8 is Wen–Yu. The jump at d = 0.5 mm, air,
  // w = 1 m/s: 1380 (Ergun at 0.8) → 1138.376005937727 (Wen–Yu at 0.8⁺), from the
  // reference script.
  const double below = 0.8, above = std::nextafter(0.8, 1.0);
  const DragState lo{5e-4, 1.2, 1.8e-5, below, 1.0}, at{5e-4, 1.2, 1.8e-5, above, 1.0};
  const double es = 1 - below;
  const double ergun = (150 * es * 1.8e-5 / (below * 25e-8) + 1.75 * 1.2 * 1.0 / 5e-4) * es;
  EXPECT_LT(rel(drag_beta(DragLaw::Gidaspow, lo), ergun), 1e-14);
  EXPECT_LT(rel(drag_beta(DragLaw::Gidaspow, lo), 1.38e3), 1e-13);
  EXPECT_EQ(drag_beta(DragLaw::Gidaspow, at), drag_beta(DragLaw::WenYu, at));
  EXPECT_LT(rel(drag_beta(DragLaw::Gidaspow, at), 1.138376005937727e3), 1e-13);
}

TEST(DragOracle, WenYuNewtonSwitchAtReynoldsThousand) {
  // C_d(1000) = 0.43828814001999688 (correlation, Re = 1000 inclusive), 0.44 just above.
  EXPECT_LT(rel(schiller_naumann_cd(1000.0), 0.43828814001999688), 1e-15);
  EXPECT_EQ(schiller_naumann_cd(std::nextafter(1000.0, 2000.0)), 0.44);
  EXPECT_LT(rel(schiller_naumann_cd(999.0), 24.0 / 999.0 * (1 + 0.15 * std::pow(999.0, 0.687))), 1e-15);
  EXPECT_EQ(schiller_naumann_cd(5000.0), 0.44);
  // The same switch inside the Wen–Yu law, with Re_p = ε ρ w d/μ: K jumps by 0.44/0.43829.
  const double d = 1e-3, mu = 1.8e-5, rho = 1.2, e = 0.9;
  // The largest slip with Re_p <= 1000 and the next representable one (Re_p > 1000).
  double w_at = 1000.0 * mu / (rho * e * d);
  while (particle_reynolds({d, rho, mu, e, w_at}) > 1000.0) w_at = std::nextafter(w_at, 0.0);
  while (particle_reynolds({d, rho, mu, e, std::nextafter(w_at, 1e9)}) <= 1000.0) w_at = std::nextafter(w_at, 1e9);
  const double k_at = drag_k(DragLaw::WenYu, {d, rho, mu, e, w_at});
  const double k_above = drag_k(DragLaw::WenYu, {d, rho, mu, e, std::nextafter(w_at, 1e9)});
  EXPECT_NEAR(k_above / k_at, 0.44 / 0.43828814001999688, 1e-12);
}

TEST(DragOracle, BeetstraKnownLimits) {
  EXPECT_EQ(beetstra_f(0.0, 0.0), 1.0);
  // Isolated sphere: F(0, Re) = 1 + 0.413 Re/24 (1 + 8.4 Re^−0.343)/(1 + Re^−1/2).
  for (double re : {0.1, 1.0, 10.0, 100.0, 1000.0}) {
    const double f = 1 + 0.413 * re / 24 * (1 + 8.4 * std::pow(re, -0.343)) / (1 + std::pow(re, -0.5));
    EXPECT_LT(rel(beetstra_f(0.0, re), f), 1e-14) << re;
  }
  // Dense, Re → 0: the fixed-bed gradient is Carman–Kozeny 180 μ φ² U/(ε³ d²) plus the
  // dilute term 18 μ φ ε (1 + 1.5√φ) U / d² (β = 18 μ ε φ F/d², gradient β U/ε²).
  BedParams p;
  p.law = DragLaw::Beetstra;
  for (double e : {0.4, 0.5, 0.64}) {
    p.eps_g = e;
    const double phi = 1 - e, U = 1e-12;
    const double ck = 180 * p.mu_g * phi * phi * U / (e * e * e * p.d * p.d);
    const double dilute = 18 * p.mu_g * phi * e * (1 + 1.5 * std::sqrt(phi)) * U / (p.d * p.d);
    EXPECT_LT(rel(drag_law_pressure_gradient(p, U), ck + dilute), 1e-9) << e;
  }
}

TEST(DragOracle, DragForceGrowsWithSlipForEveryLaw) {
  // K(w)·w strictly increasing in w: the root finders of the steady states rely on it.
  for (DragLaw law : {DragLaw::SchillerNaumann, DragLaw::WenYu, DragLaw::Gidaspow, DragLaw::DiFelice,
                      DragLaw::Beetstra}) {
    for (double e : {0.4, 0.75, 0.9, 1.0}) {
      double last = 0.0;
      for (double w = 1e-6; w < 1e3; w *= 1.1) {
        const double f = drag_k(law, {1e-3, 1.2, 1.8e-5, e, w}) * w;
        EXPECT_GT(f, last) << drag_law_name(law) << " eps " << e << " w " << w;
        last = f;
      }
    }
  }
}

TEST(DragOracle, SolidsFractionZeroGivesZeroBetaAndFiniteK) {
  const DragState s{1e-4, 1.2, 1.8e-5, 1.0, 0.5};
  for (DragLaw law : {DragLaw::WenYu, DragLaw::DiFelice, DragLaw::Beetstra, DragLaw::Gidaspow}) {
    EXPECT_EQ(drag_beta(law, s), 0.0);
    EXPECT_TRUE(std::isfinite(drag_k(law, s)));
    EXPECT_GT(drag_k(law, s), 0.0);
  }
}

TEST(DragOracle, PressureGradientForce) {
  const double d = 1e-3;
  EXPECT_LT(rel(pressure_gradient_force(d, 1.2e4), -pi * 1e-9 / 6 * 1.2e4), 1e-15);
  EXPECT_EQ(pressure_gradient_force(d, 0.0), 0.0);
}

TEST(DragOracle, BadInputIsRefusedWithTheParameterName) {
  const auto msg = [](DragState s) {
    try {
      drag_k(DragLaw::WenYu, s);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(msg({1e-4, 1.2, 1.8e-5, 0.0, 1.0}).find("eps_g"), std::string::npos);
  EXPECT_NE(msg({1e-4, 1.2, 1.8e-5, 1.1, 1.0}).find("eps_g"), std::string::npos);
  EXPECT_NE(msg({1e-4, 1.2, 1.8e-5, std::nan(""), 1.0}).find("eps_g"), std::string::npos);
  EXPECT_NE(msg({-1e-4, 1.2, 1.8e-5, 0.5, 1.0}).find("d ="), std::string::npos);
  EXPECT_NE(msg({1e-4, 1.2, 0.0, 0.5, 1.0}).find("mu_g"), std::string::npos);
  EXPECT_NE(msg({1e-4, 1.2, 1.8e-5, 0.5, -1.0}).find("slip"), std::string::npos);
}

// ---- packed bed ---------------------------------------------------------------------

TEST(PackedBedOracle, GidaspowErgunBranchIsErgunExactly) {
  BedParams p;  // Gidaspow
  for (double e : {0.35, 0.4, 0.5, 0.6, 0.79}) {
    p.eps_g = e;
    for (double U : {1e-4, 1e-2, 0.1, 1.0, 5.0}) {
      EXPECT_LT(rel(drag_law_pressure_gradient(p, U), ergun_pressure_gradient(p, U)), 1e-14) << e << " " << U;
    }
  }
  // Above the switch the Gidaspow bed is Wen–Yu, and no longer Ergun.
  p.eps_g = 0.85;
  EXPECT_GT(rel(drag_law_pressure_gradient(p, 0.5), ergun_pressure_gradient(p, 0.5)), 1e-2);
}

TEST(PackedBedOracle, MinimumFluidisationAgreesWithClosedFormsAndReference) {
  BedParams p;  // d = 0.5 mm, ρ_p = 2500, air, ε = 0.4
  const MinFluidisation mf = minimum_fluidisation(p);
  // Root finding on the Gidaspow (Ergun) gradient vs Ergun's quadratic, closed form.
  EXPECT_LT(rel(mf.U, ergun_minimum_fluidisation_velocity(p)), 1e-13);
  EXPECT_LT(rel(mf.U, 2.1270017313841519e-1), 1e-13);  // gas_reference_values.py
  EXPECT_LT(rel(drag_law_pressure_gradient(p, mf.U), bed_buoyant_weight(p)), 1e-13);
  EXPECT_LT(rel(archimedes_number(p), 1.1344841212962963e+4), 1e-14);
  EXPECT_LT(rel(wen_yu_minimum_fluidisation_estimate(p), 1.8845969892281083e-1), 1e-13);
  // The other laws on the same bed (their fixed-bed gradient β(ε, U/ε) U/ε² = weight).
  const struct {
    DragLaw law;
    double umf;
  } other[] = {{DragLaw::Beetstra, 1.9252620772443771e-1},
               {DragLaw::DiFelice, 2.3334077742650167e-1},
               {DragLaw::WenYu, 1.769728340527135e-1}};
  for (const auto& o : other) {
    p.law = o.law;
    EXPECT_LT(rel(minimum_fluidisation(p).U, o.umf), 1e-13) << drag_law_name(o.law);
  }
}

}  // namespace
