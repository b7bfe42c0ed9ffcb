#include "cdm/oracles/free_fall.hpp"

#include <gsl/gsl_errno.h>
#include <gsl/gsl_roots.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace cdm::oracles {

namespace {
constexpr double pi = std::numbers::pi;
constexpr double inf = std::numeric_limits<double>::infinity();
}  // namespace

FreeFall::FreeFall(const FreeFallParams& p, double t_end) : p_(p) {
  if (!(p.en > 0.0 && p.en <= 1.0) || !(p.kn > 0.0) || !(p.g > 0.0) || !(p.h0 > p.radius))
    throw std::invalid_argument("FreeFall: parameters out of range");
  const double d = 2.0 * p.radius;
  m_ = p.density * pi * d * d * d / 6.0;
  const double le = std::log(p.en);
  eta_n_ = 2.0 * std::sqrt(m_ * p.kn) * std::abs(le) / std::sqrt(pi * pi + le * le);
  w0_ = std::sqrt(p.kn / m_);
  beta_ = eta_n_ / (2.0 * std::sqrt(p.kn * m_));
  wd_ = w0_ * std::sqrt(1.0 - beta_ * beta_);

  gsl_set_error_handler_off();
  gsl_root_fsolver* solver = gsl_root_fsolver_alloc(gsl_root_fsolver_brent);
  double t = 0.0, y = p.h0, v = 0.0;
  const double g = p.g, r = p.radius;
  while (t < t_end) {
    // Flight from (y, v) until y = r on the way down.
    const double tau_c = (v + std::sqrt(v * v + 2.0 * g * (y - r))) / g;
    stages_.push_back({t, t + tau_c, false, y, v});
    t += tau_c;
    const double vc = v - g * tau_c;
    if (t >= t_end) break;
    // Contact: u = y - (r - g/w0^2) = e^(-b w0 tau) [A cos + B sin], f = u - A = y - r.
    Stage c{t, inf, true, r, vc};
    const double A = g / (w0_ * w0_);
    const double B = (vc + beta_ * w0_ * A) / wd_;
    const double s = beta_ * w0_;
    // u' = e^(-s tau)[C cos + D sin]; critical points where C cos + D sin = 0.
    const double C = wd_ * B - s * A, D = -(s * B + wd_ * A);
    double th1 = std::fmod(std::atan2(D, C) + pi / 2.0, pi);
    if (th1 <= 0.0) th1 += pi;
    const double tau_trough = th1 / wd_, tau_crest = (th1 + pi) / wd_;
    auto f = [&](double tau) { return std::exp(-s * tau) * (A * std::cos(wd_ * tau) + B * std::sin(wd_ * tau)) - A; };
    if (f(tau_crest) <= 0.0) {  // the ball never leaves: it settles on the spring
      stages_.push_back(c);
      break;
    }
    struct Ctx { decltype(f)* fn; } ctx{&f};
    gsl_function F;
    F.function = [](double x, void* pp) { return (*static_cast<Ctx*>(pp)->fn)(x); };
    F.params = &ctx;
    gsl_root_fsolver_set(solver, &F, tau_trough, tau_crest);
    double lo = tau_trough, hi = tau_crest, root = 0.5 * (lo + hi);
    // Absolute tolerance in time: 1e-14 of the contact duration scale (round-off level).
    const double tol = 1e-14 * (pi / wd_);
    root_tol_ = std::max(root_tol_, tol);
    for (int it = 0; it < 200; ++it) {
      gsl_root_fsolver_iterate(solver);
      root = gsl_root_fsolver_root(solver);
      lo = gsl_root_fsolver_x_lower(solver);
      hi = gsl_root_fsolver_x_upper(solver);
      if (gsl_root_test_interval(lo, hi, tol, 0.0) == GSL_SUCCESS) break;
    }
    c.t_end = t + root;
    stages_.push_back(c);
    double yr, vr;
    contact_state(c, root, yr, vr);
    t = c.t_end;
    y = r;   // exactly at the contact boundary by construction
    v = vr;
  }
  gsl_root_fsolver_free(solver);
}

void FreeFall::contact_state(const Stage& s, double tau, double& y, double& v) const {
  const double g = p_.g, r = p_.radius;
  const double A = g / (w0_ * w0_);
  const double B = (s.v0 + beta_ * w0_ * A) / wd_;
  const double sd = beta_ * w0_;
  const double e = std::exp(-sd * tau), cs = std::cos(wd_ * tau), sn = std::sin(wd_ * tau);
  y = e * (A * cs + B * sn) + r - A;
  v = e * ((wd_ * B - sd * A) * cs - (sd * B + wd_ * A) * sn);
}

const FreeFall::Stage& FreeFall::stage_at(double t) const {
  auto it = std::upper_bound(stages_.begin(), stages_.end(), t,
                             [](double x, const Stage& s) { return x < s.t_start; });
  if (it == stages_.begin()) return stages_.front();
  return *(it - 1);
}

double FreeFall::position(double t) const {
  const Stage& s = stage_at(t);
  const double tau = t - s.t_start;
  if (!s.contact) return s.y0 + s.v0 * tau - 0.5 * p_.g * tau * tau;
  double y, v;
  contact_state(s, tau, y, v);
  return y;
}

double FreeFall::velocity(double t) const {
  const Stage& s = stage_at(t);
  const double tau = t - s.t_start;
  if (!s.contact) return s.v0 - p_.g * tau;
  double y, v;
  contact_state(s, tau, y, v);
  return v;
}

std::vector<double> FreeFall::apex_heights() const {
  std::vector<double> h;
  for (std::size_t k = 1; k < stages_.size(); ++k)
    if (!stages_[k].contact) h.push_back(p_.radius + stages_[k].v0 * stages_[k].v0 / (2.0 * p_.g));
  return h;
}

double FreeFall::hard_sphere_apex(const FreeFallParams& p, int k) {
  return (p.h0 - p.radius) * std::pow(p.en, 2 * k) + p.radius;
}

double FreeFall::collision_time() const {
  return pi / std::sqrt(p_.kn / m_ - eta_n_ * eta_n_ / (4.0 * m_ * m_));
}

}  // namespace cdm::oracles
