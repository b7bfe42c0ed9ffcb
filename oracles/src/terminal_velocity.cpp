// Garg et al. (2012) eq 48: equations and conventions in terminal_velocity.hpp.
#include "cdm/oracles/terminal_velocity.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "numerics.hpp"

namespace cdm::oracles {

namespace {

void require(bool ok, const char* name, double value, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("terminal velocity oracle: ") + name + " = " + std::to_string(value) +
                                ", expected " + expected);
  }
}

void validate(const TerminalParams& p) {
  require(std::isfinite(p.d) && p.d > 0.0, "d", p.d, "> 0 [m]");
  require(std::isfinite(p.rho_p) && p.rho_p > p.rho_g, "rho_p", p.rho_p, "> rho_g (a particle that sinks)");
  require(std::isfinite(p.rho_g) && p.rho_g > 0.0, "rho_g", p.rho_g, "> 0 [kg/m^3]");
  require(std::isfinite(p.mu_g) && p.mu_g > 0.0, "mu_g", p.mu_g, "> 0 [Pa s]");
  require(std::isfinite(p.u_g), "u_g", p.u_g, "finite [m/s]");
  require(std::isfinite(p.g) && p.g > 0.0, "g", p.g, "> 0 [m/s^2]");
  require(std::isfinite(p.v0), "v0", p.v0, "finite [m/s]");
  require(std::isfinite(p.eps_g) && p.eps_g > 0.0 && p.eps_g <= 1.0, "eps_g", p.eps_g, "in (0, 1]");
}

// Drag acceleration coefficient K(w)/m [1/s].
double k_over_m(const TerminalParams& p, double w) {
  const double m = p.rho_p * particle_volume(p.d);
  return drag_k(p.law, {p.d, p.rho_g, p.mu_g, p.eps_g, w}) / m;
}

double reduced_gravity(const TerminalParams& p) { return p.g * (p.rho_p - p.rho_g) / p.rho_p; }

}  // namespace

TerminalState terminal_velocity(const TerminalParams& p) {
  validate(p);
  const double gr = reduced_gravity(p);
  // f(w) = (K/m) w − g' is −g' at w = 0 and increases with w for every law.
  const auto f = [&](double w) { return k_over_m(p, w) * w - gr; };
  const double rel_tol = 1e-14;
  const double hi = detail::bracket_upward(f, 1e-6, "terminal velocity oracle");
  const double w = detail::brent_root(f, 0.0, hi, rel_tol, "terminal velocity oracle");
  const DragState s{p.d, p.rho_g, p.mu_g, p.eps_g, w};
  const double re = p.law == DragLaw::SchillerNaumann ? single_particle_reynolds(s) : particle_reynolds(s);
  return {w, p.u_g - w, re, {rel_tol, 0.0, "gsl-brent"}};
}

TerminalSeries terminal_velocity_cvode(const TerminalParams& p, const std::vector<double>& times, double rtol) {
  validate(p);
  require(rtol > 0.0 && rtol <= 1e-6, "rtol", rtol, "in (0, 1e-6]");
  const double gr = reduced_gravity(p);
  const TerminalState term = terminal_velocity(p);
  // Absolute tolerances far below the scales of the problem: velocity ~ the largest of
  // |u|, |v0|, w_t; time ~ the relaxation time w_t/g'; length ~ velocity × time.
  const double vscale = std::max({std::abs(p.u_g), std::abs(p.v0), term.slip});
  const double atol_v = 1e-3 * rtol * vscale;
  const double atol_z = atol_v * term.slip / gr;
  detail::Cvode ode(
      [&](double, const double* y, double* dy) {
        const double rel = p.u_g - y[0];  // u − v
        dy[0] = -gr + k_over_m(p, std::abs(rel)) * rel;
        dy[1] = y[0];
      },
      {p.v0, 0.0}, 0.0, rtol, {atol_v, atol_z}, "terminal velocity oracle");
  TerminalSeries out;
  for (double t : times) {
    require(std::isfinite(t) && t >= 0.0, "time", t, "finite and >= 0 [s]");
    const auto& y = ode.advance(t);
    out.t.push_back(t);
    out.v.push_back(y[0]);
    out.z.push_back(y[1]);
  }
  out.accuracy = {rtol, atol_v, "cvode-bdf-dense"};
  return out;
}

}  // namespace cdm::oracles
