// Drag laws restated from the published correlations; equations, sources and every
// convention are in drag.hpp. Each K is assembled from C_d·Re so that w = 0 gives the
// Re → 0 limit instead of 0·∞.
#include "cdm/oracles/drag.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace cdm::oracles {

namespace {

constexpr double pi = std::numbers::pi;

void require(bool ok, const char* name, double value, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("drag oracle: ") + name + " = " + std::to_string(value) +
                                ", expected " + expected);
  }
}

void validate(const DragState& s) {
  require(std::isfinite(s.d) && s.d > 0.0, "d", s.d, "a finite diameter > 0 [m]");
  require(std::isfinite(s.rho_g) && s.rho_g > 0.0, "rho_g", s.rho_g, "a finite density > 0 [kg/m^3]");
  require(std::isfinite(s.mu_g) && s.mu_g > 0.0, "mu_g", s.mu_g, "a finite viscosity > 0 [Pa s]");
  require(std::isfinite(s.eps_g) && s.eps_g > 0.0 && s.eps_g <= 1.0, "eps_g", s.eps_g, "a gas fraction in (0, 1]");
  require(std::isfinite(s.slip) && s.slip >= 0.0, "slip", s.slip, "a finite slip speed >= 0 [m/s]");
}

// Above Re = 1000 the Newton plateau C_d = 0.44; at and below it the correlation.
constexpr double newton_re = 1000.0;

}  // namespace

std::string_view drag_law_name(DragLaw law) {
  switch (law) {
    case DragLaw::SchillerNaumann: return "schiller_naumann";
    case DragLaw::WenYu: return "wen_yu";
    case DragLaw::Gidaspow: return "gidaspow";
    case DragLaw::DiFelice: return "di_felice";
    case DragLaw::Beetstra: return "beetstra";
  }
  return "unknown";
}

double particle_volume(double d) { return pi * d * d * d / 6.0; }

double particle_reynolds(const DragState& s) { return s.rho_g * s.eps_g * s.slip * s.d / s.mu_g; }

double single_particle_reynolds(const DragState& s) { return s.rho_g * s.slip * s.d / s.mu_g; }

double schiller_naumann_cd_re(double re) {
  return re <= newton_re ? 24.0 * (1.0 + 0.15 * std::pow(re, 0.687)) : 0.44 * re;
}

double schiller_naumann_cd(double re) { return schiller_naumann_cd_re(re) / re; }

double dallavalle_cd(double re) {
  const double a = 0.63 + 4.8 / std::sqrt(re);
  return a * a;
}

double di_felice_chi(double re) {
  if (re <= 0.0) return 3.7;  // log10(Re) → −∞: the Gaussian term vanishes
  const double z = 1.5 - std::log10(re);
  return 3.7 - 0.65 * std::exp(-0.5 * z * z);
}

double beetstra_f(double phi, double re) {
  const double eg = 1.0 - phi;
  const double f0 = 10.0 * phi / (eg * eg) + eg * eg * (1.0 + 1.5 * std::sqrt(phi));
  if (re <= 0.0) return f0;  // the inertial term vanishes like Re^(1.157+2φ)
  const double num = 1.0 / eg + 3.0 * eg * phi + 8.4 * std::pow(re, -0.343);
  const double den = 1.0 + std::pow(10.0, 3.0 * phi) * std::pow(re, -0.5 * (1.0 + 4.0 * phi));
  return f0 + 0.413 * re / (24.0 * eg * eg) * num / den;
}

double schiller_naumann_k(const DragState& s) {
  validate(s);
  // K = (π d²/8) ρ C_d w = (π μ d / 8) C_d Re with Re = ρ w d/μ.
  return pi * s.mu_g * s.d / 8.0 * schiller_naumann_cd_re(single_particle_reynolds(s));
}

double wen_yu_k(const DragState& s) {
  validate(s);
  // K = (π d²/8) C_d ρ ε^−1.65 w = (π μ d/8) (C_d Re_p) ε^−2.65, Re_p = ε ρ w d/μ.
  return pi * s.mu_g * s.d / 8.0 * schiller_naumann_cd_re(particle_reynolds(s)) * std::pow(s.eps_g, -2.65);
}

double gidaspow_k(const DragState& s) {
  validate(s);
  if (s.eps_g <= 0.8) {  // MFIX DRAG_GIDASPOW: EPg <= 0.8 is Ergun
    const double es = 1.0 - s.eps_g;
    return particle_volume(s.d) * (150.0 * es * s.mu_g / (s.eps_g * s.d * s.d) + 1.75 * s.rho_g * s.slip / s.d);
  }
  return wen_yu_k(s);
}

double di_felice_k(const DragState& s) {
  validate(s);
  // K = (π d²/8) C_d ρ ε^(2−χ) w = (π μ d/8) (C_d Re_p) ε^(1−χ); C_d Re_p = (0.63√Re_p + 4.8)².
  const double re = particle_reynolds(s);
  const double a = 0.63 * std::sqrt(re) + 4.8;
  return pi * s.mu_g * s.d / 8.0 * a * a * std::pow(s.eps_g, 1.0 - di_felice_chi(re));
}

double beetstra_k(const DragState& s) {
  validate(s);
  return 3.0 * pi * s.mu_g * s.d * s.eps_g * beetstra_f(1.0 - s.eps_g, particle_reynolds(s));
}

double drag_k(DragLaw law, const DragState& s) {
  switch (law) {
    case DragLaw::SchillerNaumann: return schiller_naumann_k(s);
    case DragLaw::WenYu: return wen_yu_k(s);
    case DragLaw::Gidaspow: return gidaspow_k(s);
    case DragLaw::DiFelice: return di_felice_k(s);
    case DragLaw::Beetstra: return beetstra_k(s);
  }
  throw std::invalid_argument("drag oracle: unknown drag law");
}

double drag_beta(DragLaw law, const DragState& s) {
  return drag_k(law, s) * (1.0 - s.eps_g) / particle_volume(s.d);
}

double pressure_gradient_force(double d, double dpdx) { return -particle_volume(d) * dpdx; }

OracleAccuracy drag_accuracy() { return {1e-14, 0.0, "closed-form"}; }

}  // namespace cdm::oracles
