// Homogeneous suspension, model A: equations and conventions in suspension.hpp.
#include "cdm/oracles/suspension.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "numerics.hpp"

namespace cdm::oracles {

namespace {

void require(bool ok, const char* name, double value, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("suspension oracle: ") + name + " = " + std::to_string(value) +
                                ", expected " + expected);
  }
}

void validate(const SuspensionParams& p) {
  require(std::isfinite(p.d) && p.d > 0.0, "d", p.d, "> 0 [m]");
  require(std::isfinite(p.rho_p) && p.rho_p > 0.0, "rho_p", p.rho_p, "> 0 [kg/m^3]");
  require(std::isfinite(p.rho_g) && p.rho_g > 0.0, "rho_g", p.rho_g, "> 0 [kg/m^3]");
  require(std::isfinite(p.mu_g) && p.mu_g > 0.0, "mu_g", p.mu_g, "> 0 [Pa s]");
  require(std::isfinite(p.eps_g) && p.eps_g > 0.0 && p.eps_g < 1.0, "eps_g", p.eps_g, "in (0, 1): both phases present");
  require(std::isfinite(p.g) && p.g >= 0.0, "g", p.g, ">= 0 [m/s^2]");
  require(std::isnan(p.G) || std::isfinite(p.G), "G", p.G, "finite, or NaN for the mixture weight [Pa/m]");
  require(std::isfinite(p.U0), "U0", p.U0, "finite [m/s]");
  require(std::isfinite(p.V0), "V0", p.V0, "finite [m/s]");
}

double beta_of(const SuspensionParams& p, double w) { return drag_beta(p.law, {p.d, p.rho_g, p.mu_g, p.eps_g, w}); }

double mixture_weight(const SuspensionParams& p) {
  return (p.eps_g * p.rho_g + (1.0 - p.eps_g) * p.rho_p) * p.g;
}

}  // namespace

double suspension_pressure_gradient(const SuspensionParams& p) { return std::isnan(p.G) ? mixture_weight(p) : p.G; }

double suspension_momentum(const SuspensionParams& p, double U, double V) {
  return p.eps_g * p.rho_g * U + (1.0 - p.eps_g) * p.rho_p * V;
}

SuspensionSteady suspension_steady(const SuspensionParams& p) {
  validate(p);
  const double es = 1.0 - p.eps_g, G = suspension_pressure_gradient(p);
  const double rhs = G * p.eps_g * es * (p.rho_p - p.rho_g) / (p.eps_g * p.rho_g + es * p.rho_p);
  const double rel_tol = 1e-14;
  // β(w) w is 0 at w = 0 and increases with w, so the root has the sign of rhs.
  const double sgn = rhs < 0.0 ? -1.0 : 1.0;
  double w = 0.0;
  if (rhs != 0.0) {
    const auto f = [&](double a) { return beta_of(p, a) * a - sgn * rhs; };
    const double hi = detail::bracket_upward(f, 1e-9, "suspension oracle");
    w = sgn * detail::brent_root(f, 0.0, hi, rel_tol, "suspension oracle");
  }
  SuspensionSteady s{w, beta_of(p, std::abs(w)), std::nan(""), std::nan(""), {rel_tol, 0.0, "gsl-brent"}};
  if (std::abs(G - mixture_weight(p)) <= 1e-14 * mixture_weight(p)) {
    const double m0 = suspension_momentum(p, p.U0, p.V0);
    s.U = (m0 + es * p.rho_p * w) / (p.eps_g * p.rho_g + es * p.rho_p);
    s.V = s.U - w;
  }
  return s;
}

SuspensionSeries suspension_cvode(const SuspensionParams& p, const std::vector<double>& times, double rtol) {
  validate(p);
  require(rtol > 0.0 && rtol <= 1e-6, "rtol", rtol, "in (0, 1e-6]");
  const double es = 1.0 - p.eps_g, G = suspension_pressure_gradient(p);
  const double ag = p.eps_g * p.rho_g, as = es * p.rho_p;  // phase inertia per unit volume
  const SuspensionSteady st = suspension_steady(p);
  const double vscale = std::max({std::abs(st.slip), std::abs(p.U0), std::abs(p.V0), 1e-12});
  const double atol = 1e-3 * rtol * vscale;
  detail::Cvode ode(
      [&](double, const double* y, double* dy) {
        const double w = y[0] - y[1];
        const double b = beta_of(p, std::abs(w));
        dy[0] = (p.eps_g * G - ag * p.g - b * w) / ag;
        dy[1] = (es * G - as * p.g + b * w) / as;
      },
      {p.U0, p.V0}, 0.0, rtol, {atol, atol}, "suspension oracle");
  SuspensionSeries out;
  for (double t : times) {
    require(std::isfinite(t) && t >= 0.0, "time", t, "finite and >= 0 [s]");
    const auto& y = ode.advance(t);
    out.t.push_back(t);
    out.U.push_back(y[0]);
    out.V.push_back(y[1]);
  }
  out.accuracy = {rtol, atol, "cvode-bdf-dense"};
  return out;
}

}  // namespace cdm::oracles
