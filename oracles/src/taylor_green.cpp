// Garg et al. (2012) §3.5: equations and conventions in taylor_green.hpp.
#include "cdm/oracles/taylor_green.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "numerics.hpp"

namespace cdm::oracles {

namespace {

void require(bool ok, const char* name, double value, const char* expected) {
  if (!ok) {
    throw std::invalid_argument(std::string("Taylor-Green oracle: ") + name + " = " + std::to_string(value) +
                                ", expected " + expected);
  }
}

void validate(const TaylorGreenParams& p) {
  require(std::isfinite(p.U), "U", p.U, "finite [m/s]");
  require(std::isfinite(p.kx) && p.kx > 0.0, "kx", p.kx, "> 0 [1/m]");
  require(std::isfinite(p.ky) && p.ky > 0.0, "ky", p.ky, "> 0 [1/m]");
  require(std::isfinite(p.d) && p.d > 0.0, "d", p.d, "> 0 [m]");
  require(std::isfinite(p.rho_p) && p.rho_p > 0.0, "rho_p", p.rho_p, "> 0 [kg/m^3]");
  require(std::isfinite(p.rho_g) && p.rho_g > 0.0, "rho_g", p.rho_g, "> 0 [kg/m^3]");
  require(std::isfinite(p.mu_g) && p.mu_g > 0.0, "mu_g", p.mu_g, "> 0 [Pa s]");
  require(std::isfinite(p.eps_g) && p.eps_g > 0.0 && p.eps_g <= 1.0, "eps_g", p.eps_g, "in (0, 1]");
}

}  // namespace

std::array<double, 2> taylor_green_gas_velocity(const TaylorGreenParams& p, double x, double y) {
  return {-p.U * std::cos(p.kx * x) * std::sin(p.ky * y), p.U * std::sin(p.kx * x) * std::cos(p.ky * y)};
}

double stokes_relaxation_time(double d, double rho_p, double mu_g) { return rho_p * d * d / (18.0 * mu_g); }

double low_re_relaxation_time(const TaylorGreenParams& p) {
  validate(p);
  return p.rho_p * particle_volume(p.d) / drag_k(p.law, {p.d, p.rho_g, p.mu_g, p.eps_g, 0.0});
}

StagnationEigenvalues stagnation_point_eigenvalues(double st) {
  require(std::isfinite(st) && st > 0.0, "St", st, "finite and > 0");
  const double disc = 1.0 - 4.0 * st;
  if (disc >= 0.0) {
    const double slow = -2.0 / (1.0 + std::sqrt(disc));
    return {slow, 1.0 / (st * slow), false};
  }
  const double re = -1.0 / (2.0 * st), im = std::sqrt(-disc) / (2.0 * st);
  return {{re, im}, {re, -im}, true};
}

TaylorGreenSeries taylor_green_cvode(const TaylorGreenParams& p, const std::vector<ParticleState2D>& initial,
                                     const std::vector<double>& times, double rtol) {
  validate(p);
  require(rtol > 0.0 && rtol <= 1e-6, "rtol", rtol, "in (0, 1e-6]");
  for (double t : times) require(std::isfinite(t) && t >= 0.0, "time", t, "finite and >= 0 [s]");
  for (std::size_t k = 1; k < times.size(); ++k) require(times[k] >= times[k - 1], "time", times[k], "increasing");
  const double m = p.rho_p * particle_volume(p.d);
  double vscale = std::abs(p.U);
  for (const auto& s : initial) vscale = std::max({vscale, std::abs(s.vx), std::abs(s.vy)});
  if (vscale == 0.0) vscale = 1.0;  // nothing moves; any scale will do
  const double atol_v = 1e-3 * rtol * vscale;
  const double atol_x = 1e-3 * rtol / std::max(p.kx, p.ky);
  TaylorGreenSeries out;
  out.t = times;
  out.accuracy = {rtol, atol_v, "cvode-bdf-dense (per particle)"};
  if (initial.empty()) return out;
  const auto rhs = [&](double, const double* y, double* dy) {
    const auto ug = taylor_green_gas_velocity(p, y[0], y[1]);
    const double rx = ug[0] - y[2], ry = ug[1] - y[3];
    const double k = drag_k(p.law, {p.d, p.rho_g, p.mu_g, p.eps_g, std::hypot(rx, ry)}) / m;
    dy[0] = y[2];
    dy[1] = y[3];
    dy[2] = k * rx;
    dy[3] = k * ry;
  };
  const auto state = [](const ParticleState2D& s) { return std::vector<double>{s.x, s.y, s.vx, s.vy}; };
  detail::Cvode ode(rhs, state(initial.front()), 0.0, rtol, {atol_x, atol_x, atol_v, atol_v}, "Taylor-Green oracle");
  for (std::size_t i = 0; i < initial.size(); ++i) {
    const auto& s = initial[i];
    require(std::isfinite(s.x) && std::isfinite(s.y) && std::isfinite(s.vx) && std::isfinite(s.vy), "initial state",
            static_cast<double>(i), "finite position and velocity");
    if (i > 0) ode.reinit(state(s), 0.0);
    TaylorGreenTrajectory tr;
    tr.x.reserve(times.size());
    tr.y.reserve(times.size());
    tr.vx.reserve(times.size());
    tr.vy.reserve(times.size());
    for (double t : times) {
      const auto& y = ode.advance(t);
      tr.x.push_back(y[0]);
      tr.y.push_back(y[1]);
      tr.vx.push_back(y[2]);
      tr.vy.push_back(y[3]);
    }
    out.particles.push_back(std::move(tr));
  }
  return out;
}

}  // namespace cdm::oracles
