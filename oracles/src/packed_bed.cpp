// Fixed bed and minimum fluidisation: equations and conventions in packed_bed.hpp.
#include "cdm/oracles/packed_bed.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "numerics.hpp"

namespace cdm::oracles {

namespace {

void require(bool ok, const char* name, double value, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("packed bed oracle: ") + name + " = " + std::to_string(value) +
                                ", expected " + expected);
  }
}

void validate(const BedParams& p) {
  require(std::isfinite(p.d) && p.d > 0.0, "d", p.d, "> 0 [m]");
  require(std::isfinite(p.rho_p) && p.rho_p > p.rho_g, "rho_p", p.rho_p, "> rho_g [kg/m^3]");
  require(std::isfinite(p.rho_g) && p.rho_g > 0.0, "rho_g", p.rho_g, "> 0 [kg/m^3]");
  require(std::isfinite(p.mu_g) && p.mu_g > 0.0, "mu_g", p.mu_g, "> 0 [Pa s]");
  require(std::isfinite(p.eps_g) && p.eps_g > 0.0 && p.eps_g < 1.0, "eps_g", p.eps_g, "in (0, 1)");
  require(std::isfinite(p.g) && p.g > 0.0, "g", p.g, "> 0 [m/s^2]");
}

}  // namespace

double ergun_pressure_gradient(const BedParams& p, double U) {
  validate(p);
  require(std::isfinite(U) && U >= 0.0, "U", U, ">= 0 [m/s]");
  const double e = p.eps_g, es = 1.0 - e, e3 = e * e * e;
  return 150.0 * p.mu_g * es * es * U / (e3 * p.d * p.d) + 1.75 * p.rho_g * es * U * U / (e3 * p.d);
}

double drag_law_pressure_gradient(const BedParams& p, double U) {
  validate(p);
  require(std::isfinite(U) && U >= 0.0, "U", U, ">= 0 [m/s]");
  const double e = p.eps_g;
  return drag_beta(p.law, {p.d, p.rho_g, p.mu_g, e, U / e}) * U / (e * e);
}

double bed_buoyant_weight(const BedParams& p) {
  validate(p);
  return (1.0 - p.eps_g) * (p.rho_p - p.rho_g) * p.g;
}

double archimedes_number(const BedParams& p) {
  validate(p);
  return p.d * p.d * p.d * p.rho_g * (p.rho_p - p.rho_g) * p.g / (p.mu_g * p.mu_g);
}

MinFluidisation minimum_fluidisation(const BedParams& p) {
  const double w = bed_buoyant_weight(p);
  const auto f = [&](double U) { return drag_law_pressure_gradient(p, U) - w; };
  const double rel_tol = 1e-14;
  const double hi = detail::bracket_upward(f, 1e-9, "packed bed oracle");
  const double U = detail::brent_root(f, 0.0, hi, rel_tol, "packed bed oracle");
  return {U, p.rho_g * U * p.d / p.mu_g, {rel_tol, 0.0, "gsl-brent"}};
}

double ergun_minimum_fluidisation_velocity(const BedParams& p) {
  const double ar = archimedes_number(p);
  const double e = p.eps_g, e3 = e * e * e;
  const double a = 1.75 / e3, b = 150.0 * (1.0 - e) / e3;
  // Positive root of a Re² + b Re − Ar = 0 without cancellation: 2 Ar/(b + √(b² + 4 a Ar)).
  const double re = 2.0 * ar / (b + std::sqrt(b * b + 4.0 * a * ar));
  return re * p.mu_g / (p.rho_g * p.d);
}

double wen_yu_minimum_fluidisation_estimate(const BedParams& p) {
  const double ar = archimedes_number(p);
  const double re = std::sqrt(33.7 * 33.7 + 0.0408 * ar) - 33.7;
  return re * p.mu_g / (p.rho_g * p.d);
}

}  // namespace cdm::oracles
