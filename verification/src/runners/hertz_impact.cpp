/// @file hertz_impact.cpp
/// @brief Normal elastic Hertz impact: a sphere on a wall (options.geometry = "wall") or
/// two equal spheres head on ("pair"). The overlap and the force on particle 0 are
/// recorded every step; the solver's force (what it applies) is compared with the CVODE
/// solution of the Hertz equation over the whole contact, and contact time, maximum
/// overlap and maximum force with Johnson's closed forms.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "cdm/oracles/hertz_impact.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

namespace {

/// Peak of sampled data by the parabola through the largest sample and its neighbours
/// (the sample maximum alone carries an O(dt²) sampling error of its own).
double sampled_peak(const std::vector<double>& t, const std::vector<double>& y) {
  const std::size_t k = static_cast<std::size_t>(std::max_element(y.begin(), y.end()) - y.begin());
  if (k == 0 || k + 1 >= y.size()) return y[k];
  const double h1 = t[k] - t[k - 1], h2 = t[k + 1] - t[k];
  if (std::abs(h1 - h2) > 1e-9 * h1) return y[k];
  const double a = 0.5 * (y[k + 1] - 2.0 * y[k] + y[k - 1]), b = 0.5 * (y[k + 1] - y[k - 1]);
  return a < 0.0 ? y[k] - b * b / (4.0 * a) : y[k];
}

/// First time after @p from where @p y crosses zero in direction @p sign (+1 rising,
/// -1 falling), by linear interpolation between samples; NaN if it does not.
double zero_crossing(const std::vector<double>& t, const std::vector<double>& y, std::size_t from, int sign,
                     std::size_t* at = nullptr) {
  for (std::size_t k = std::max<std::size_t>(from, 1); k < y.size(); ++k) {
    const bool cross = sign > 0 ? (y[k - 1] <= 0.0 && y[k] > 0.0) : (y[k - 1] > 0.0 && y[k] <= 0.0);
    if (cross) {
      if (at) *at = k;
      return t[k - 1] + (t[k] - t[k - 1]) * y[k - 1] / (y[k - 1] - y[k]);
    }
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

RunOutput hertz_impact(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const bool pair = option_is(c, "geometry", "pair");
  const SceneSpec spec = scene_for(v, rc);
  Simulation sim(spec);
  if (sim.particles().size() != (pair ? 2u : 1u)) throw std::runtime_error(v.scene + ": wrong number of particles");
  const double R = v.param("radius");
  std::vector<double> t, overlap, force, vel;
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    const ParticleStore& p = s.particles();
    t.push_back(s.time());
    if (pair) {
      overlap.push_back(2.0 * R - (p.x[1] - p.x[0]));
      force.push_back(-p.fx[0]);  // repulsion pushes particle 0 towards -x
      vel.push_back(p.vx[0] - p.vx[1]);
    } else {
      overlap.push_back(R - p.y[0]);
      force.push_back(p.fy[0]);   // the wall pushes the sphere up
      vel.push_back(-p.vy[0]);
    }
  });
  if (rc.timing_only) return r;  // a repeat for timing: no oracle, no tables

  // Oracle, from the case's SI parameters alone.
  const double m = v.param("density") * 4.0 / 3.0 * std::numbers::pi * R * R * R;
  oracles::HertzImpactParams op;
  op.m_eff = pair ? 0.5 * m : m;
  op.r_eff = pair ? 0.5 * R : R;
  op.e_star = oracles::hertz_effective_modulus(v.param("youngs_modulus"), v.param("poisson_ratio"),
                                               v.param("youngs_modulus_2"), v.param("poisson_ratio_2"));
  op.v = v.param("speed");
  const double t_touch = v.param("gap") / op.v;  // constant speed until first touch (no gravity)
  std::vector<double> tau(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) tau[k] = t[k] - t_touch;
  const oracles::HertzClosedForm cf = oracles::hertz_closed_form(op);
  const oracles::HertzSeries ode = oracles::hertz_impact_cvode(op, tau);
  r.oracle_accuracy = accuracy_text(ode.accuracy);

  double ef = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) ef = std::max(ef, std::abs(force[k] - ode.force[k]));
  std::size_t k_in = 0;
  const double t_in = zero_crossing(t, overlap, 0, +1, &k_in);
  const double t_out = zero_crossing(t, overlap, k_in, -1);
  r.measurements.push_back({"force", "max_abs_pct_of_peak", 100.0 * ef / cf.max_force});
  r.measurements.push_back({"contact_time", "rel_pct", rel_pct(cf.contact_time, t_out - t_in)});
  r.measurements.push_back({"max_overlap", "rel_pct", rel_pct(cf.max_overlap, sampled_peak(t, overlap))});
  r.measurements.push_back({"max_force", "rel_pct", rel_pct(cf.max_force, sampled_peak(t, force))});
  r.measurements.push_back({"rebound_speed", "rel_pct", rel_pct(op.v, -vel.back())});
  // The two references against each other (no solver involved): how well CVODE and the
  // closed forms agree bounds what the comparisons above can resolve.
  r.measurements.push_back({"oracle_ode_vs_closed_form", "rel_pct",
                            std::max(rel_pct(cf.contact_time, ode.contact_time),
                                     rel_pct(cf.max_overlap, ode.max_overlap))});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path, {"t[s]", "overlap[m]", "overlap_oracle[m]", "force[N]", "force_oracle[N]"},
                  {"Hertz impact " + v.name + " (" + (pair ? "two spheres" : "sphere on a wall") + "), " +
                   rc.integrator + ", dt = " + num(r.dt) + " s; oracle: CVODE of m* d'' = -K d^(3/2); " +
                   "closed forms t_c = " + num(cf.contact_time) + " s, d_max = " + num(cf.max_overlap) +
                   " m, F_max = " + num(cf.max_force) + " N"});
    for (std::size_t k = 0; k < t.size(); ++k) w.row({t[k], overlap[k], ode.overlap[k], force[k], ode.force[k]});
  }
  return r;
}

}  // namespace cdm::verification::runners
