/// @file rolling_resistance.cpp
/// @brief Rolling resistance: a sphere on a floor (normal +y) rolling along +x without
/// slip (options.mode = "roll"), or spinning about +x on a frictionless floor ("spin"),
/// decelerated by the constant rolling torque until it stops, and after the stop; against
/// the closed form.
#include <algorithm>
#include <cmath>

#include "cdm/oracles/rolling_resistance.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

RunOutput rolling_resistance(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const bool spin = option_is(c, "mode", "spin");
  const SceneSpec spec = scene_for(v, rc);
  Simulation sim(spec);
  std::vector<double> t, q;  // q: the centre's speed v_x (roll) or the spin w_x (spin)
  const double R = v.param("radius");
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    const ParticleStore& p = s.particles();
    t.push_back(s.time());
    q.push_back(spin ? p.wx[0] : p.vx[0]);
  });
  if (rc.timing_only) return r;  // a repeat for timing: no oracle, no tables
  r.oracle_accuracy = "closed_form";
  const oracles::RollingParams op{R, v.param("mu_r"), v.param("g")};
  const double q0 = spin ? v.param("omega0") : v.param("v0");
  // Spin: the resisting torque is mu_r R m g and nothing else acts, so the closed form
  // is the model's. Roll: the friction acts at the centre-to-contact distance R - delta
  // (delta the static overlap, from the case), which the closed form takes into account;
  // the rigid-sphere (5/7) mu_r g is reported beside it.
  const double rate = spin ? 2.5 * op.mu_r * op.g / R : oracles::rolling_deceleration(op, R - v.param("static_overlap"));
  const double rate_rigid = spin ? rate : 5.0 / 7.0 * op.mu_r * op.g;
  const double t_stop = q0 / rate;
  auto oracle = [&](double time) { return std::max(0.0, q0 - rate * time); };
  double e_series = 0.0, e_all = 0.0, rest = 0.0;
  // Deceleration: least-squares slope over the middle of the decelerating phase.
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
  std::vector<double> qa(t.size());
  const double t_end = t.empty() ? 0.0 : t.back();
  for (std::size_t k = 0; k < t.size(); ++k) {
    qa[k] = oracle(t[k]);
    const double e = std::abs(q[k] - qa[k]);
    e_all = std::max(e_all, e);
    // Roll: the elastic tangential spring must first take up the friction force (and
    // gives it back at the stop): those transients are the model's, measured apart.
    if (spin || (t[k] > 0.1 * t_stop && t[k] < 0.99 * t_stop)) e_series = std::max(e_series, e);
    if (t[k] > 0.1 * t_stop && t[k] < 0.9 * t_stop) {
      sx += t[k]; sy += q[k]; sxx += t[k] * t[k]; sxy += t[k] * q[k]; n += 1;
    }
    // At rest for good: the last tenth of the run (the stop is at 0.7 of it or earlier).
    if (t[k] > 0.9 * t_end) rest = std::max(rest, std::abs(q[k]));
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  const std::string name = spin ? "omega" : "v";
  r.measurements.push_back({name, "max_abs_pct_of_initial", 100.0 * e_series / q0});
  r.measurements.push_back({"deceleration", "rel_pct", rel_pct(rate, -slope)});
  if (!spin) {
    r.measurements.push_back({"deceleration_rigid_sphere", "rel_pct", rel_pct(rate_rigid, -slope)});
    r.measurements.push_back({"v_with_spring_transients", "max_abs_pct_of_initial", 100.0 * e_all / q0});
  }
  r.measurements.push_back({"at_rest", "max_abs_pct_of_initial", 100.0 * rest / q0});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path,
                  {"t[s]", spin ? "omega[rad/s]" : "v[m/s]", spin ? "omega_oracle[rad/s]" : "v_oracle[m/s]"},
                  {std::string(spin ? "spinning" : "rolling") + " against rolling resistance " + v.name + ", " +
                   rc.integrator + ", dt = " + num(r.dt) + " s"});
    for (std::size_t k = 0; k < t.size(); ++k) w.row({t[k], q[k], qa[k]});
  }
  return r;
}

}  // namespace cdm::verification::runners
