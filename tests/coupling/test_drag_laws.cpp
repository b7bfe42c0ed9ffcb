// The solver's drag laws (solver/.../coupling/drag_laws.hpp) against the formulas restated
// independently in oracles/ (drag.hpp), over Reynolds numbers from the Stokes limit to the
// Newton regime and gas fractions from a packed bed to a single particle — including the
// switch points: Re_p = 1000 (Wen–Yu / Schiller–Naumann's C_d), ε_g = 0.8 (Gidaspow's
// Ergun/Wen–Yu switch) and w = 0.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cdm/oracles/drag.hpp"
#include "cdm/solver/coupling/drag_laws.hpp"

namespace {

using cdm::coupling::DragLaw;
namespace ora = cdm::oracles;

struct LawPair {
  DragLaw solver;
  ora::DragLaw oracle;
};
const LawPair laws[] = {{DragLaw::schiller_naumann, ora::DragLaw::SchillerNaumann},
                        {DragLaw::wen_yu, ora::DragLaw::WenYu},
                        {DragLaw::gidaspow, ora::DragLaw::Gidaspow},
                        {DragLaw::di_felice, ora::DragLaw::DiFelice},
                        {DragLaw::beetstra, ora::DragLaw::Beetstra}};

double rel(double a, double b) { return std::abs(a - b) / std::abs(b); }

// Slip speeds that put the suspension Reynolds number Re_p = ε ρ w d / μ at @p re.
double slip_for(double re, double rho, double mu, double d, double eps) { return re * mu / (eps * rho * d); }

TEST(DragLaws, AgreeWithOracleOverReynoldsAndVoidage) {
  const double rho = 1.2, mu = 1.8e-5;
  int checked = 0;
  for (double d : {1e-4, 1e-3, 5e-3})
    for (double eps : {0.36, 0.5, 0.7, std::nextafter(0.8, 0.0), 0.8, std::nextafter(0.8, 1.0), 0.9, 0.95, 0.999, 1.0})
      for (double re : {0.0, 1e-6, 1e-3, 0.1, 1.0, 10.0, 100.0, 999.0, 1000.0, 1000.5, 1e4}) {
        const double w = slip_for(re, rho, mu, d, eps);
        for (const auto& l : laws) {
          const double ks = cdm::coupling::drag_coefficient(l.solver, rho, mu, d, eps, w);
          const double ko = ora::drag_k(l.oracle, {d, rho, mu, eps, w});
          // Double-precision closed forms written two ways: agreement to a few ulps.
          EXPECT_LT(rel(ks, ko), 1e-12) << cdm::coupling::to_string(l.solver) << " d=" << d << " eps=" << eps
                                        << " Re_p=" << re << ": solver " << ks << ", oracle " << ko;
          ++checked;
        }
      }
  EXPECT_EQ(checked, 3 * 10 * 11 * 5);
}

TEST(DragLaws, SchillerNaumannSwitchesAtItsOwnReynoldsNumber) {
  // The single-particle law uses Re = ρ w d/μ (no ε): its C_d switch sits at w = 1000 μ/(ρ d).
  const double rho = 1.2, mu = 1.8e-5, d = 1e-3, w = 1000.0 * mu / (rho * d);
  for (double ww : {w, std::nextafter(w, 0.0), std::nextafter(w, 1e9)}) {
    const double ks = cdm::coupling::drag_coefficient(DragLaw::schiller_naumann, rho, mu, d, 0.7, ww);
    EXPECT_LT(rel(ks, ora::drag_k(ora::DragLaw::SchillerNaumann, {d, rho, mu, 0.7, ww})), 1e-12);
  }
}

TEST(DragLaws, GidaspowJumpsAtPointEightAsMfix) {
  // MFIX's DRAG_GIDASPOW: ε_g <= 0.8 is Ergun, above is Wen–Yu; the law is not blended.
  const double rho = 1.2, mu = 1.8e-5, d = 5e-4, w = 1.0;
  const double at = cdm::coupling::drag_coefficient(DragLaw::gidaspow, rho, mu, d, 0.8, w);
  const double above = cdm::coupling::drag_coefficient(DragLaw::gidaspow, rho, mu, d, std::nextafter(0.8, 1.0), w);
  const double ergun = M_PI * d * d * d / 6.0 * (150.0 * 0.2 * mu / (0.8 * d * d) + 1.75 * rho * w / d);
  EXPECT_LT(rel(at, ergun), 1e-14);
  EXPECT_LT(rel(above, cdm::coupling::drag_coefficient(DragLaw::wen_yu, rho, mu, d, std::nextafter(0.8, 1.0), w)), 1e-15);
  EXPECT_GT(at / above, 1.2);  // beta 1380 -> 1138 kg/(m^3 s): a 21 % drop
}

TEST(DragLaws, StokesLimitOfEverySingleParticleLaw) {
  const double rho = 1.2, mu = 1.8e-5, d = 1e-4, stokes = 3.0 * M_PI * mu * d;
  for (DragLaw l : {DragLaw::schiller_naumann, DragLaw::wen_yu, DragLaw::gidaspow, DragLaw::beetstra})
    EXPECT_LT(rel(cdm::coupling::drag_coefficient(l, rho, mu, d, 1.0, 0.0), stokes), 1e-15) << cdm::coupling::to_string(l);
  // The Dallavalle C_d of Di Felice's law is 23.04/Re at small Re: 0.96 of Stokes drag.
  EXPECT_LT(rel(cdm::coupling::drag_coefficient(DragLaw::di_felice, rho, mu, d, 1.0, 0.0), 0.96 * stokes), 1e-15);
}

TEST(DragLaws, BetaFromCoefficient) {
  const double d = 2e-4, eps = 0.6, k = 3.0e-6;
  EXPECT_LT(rel(cdm::coupling::beta_from_coefficient(k, d, eps), k * 0.4 / (M_PI * d * d * d / 6.0)), 1e-15);
}

}  // namespace
