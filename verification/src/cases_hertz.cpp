/// @file cases_hertz.cpp
/// @brief Case runners for the Hertz–Mindlin contact and rolling resistance (issue 8):
/// normal elastic impact, restitution against the requested e_n, oblique impact, and
/// a sphere rolling or spinning against rolling resistance. Registered in cases.cpp.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <mutex>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "cdm/oracles/hertz_impact.hpp"
#include "cdm/oracles/oblique_impact.hpp"
#include "cdm/oracles/rolling_resistance.hpp"
#include "cdm/solver/output.hpp"
#include "cdm/solver/simulation.hpp"
#include "cdm/verification/harness.hpp"

namespace cdm::verification {

namespace {

std::string accuracy_str(const oracles::OracleAccuracy& a) {
  char b[160];
  std::snprintf(b, sizeof b, "%s(rtol=%.0e,atol=%.0e)", a.method.c_str(), a.rtol, a.atol);
  std::string s = b;
  for (auto& ch : s)
    if (ch == ' ') ch = '_';
  return s;
}

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string vec(double x, double y, double z) {
  char b[128];
  std::snprintf(b, sizeof b, "[%.17g, %.17g, %.17g]", x, y, z);
  return b;
}

/// The scene with the variant's overrides, @p extra, the sweep point's integrator and
/// dt = t_col/divisor.
SceneSpec scene_with(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc, const std::vector<SceneOverride>& extra) {
  std::vector<SceneOverride> ov = v.set;
  ov.insert(ov.end(), extra.begin(), extra.end());
  ov.push_back({"integrator.scheme", "\"" + rc.integrator + "\""});
  ov.push_back({"integrator.dt", "\"auto\""});
  ov.push_back({"integrator.dt_divisor", num(rc.dt_divisor)});
  SceneSpec s = load_scene(v.scene, ov);
  s.output_particles = false;
  return s;
}

/// Run to end_time, calling @p record after every step (and at t = 0); time the solver.
template <class F>
double run_and_time(Simulation& sim, F&& record) {
  const auto t0 = std::chrono::steady_clock::now();
  sim.run([&](const Simulation& s) { record(s); });
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

double rel_pct(double ref, double val) { return 100.0 * std::abs(ref - val) / std::abs(ref); }

std::vector<double> numbers_in(const CaseDef& c, const std::string& key) {
  auto it = c.options.find(key);
  if (it == c.options.end()) throw std::runtime_error(c.name + ": case.toml needs options." + key);
  std::istringstream is(it->second);
  std::vector<double> out;
  for (double x; is >> x;) out.push_back(x);
  if (out.empty()) throw std::runtime_error(c.name + ": options." + key + " lists no numbers");
  return out;
}

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

// -----------------------------------------------------------------------------------
// Normal elastic Hertz impact: a sphere on a wall (options.geometry = "wall") or two
// equal spheres head on ("pair"). The overlap and the force on particle 0 are recorded
// every step; the solver's force (what it applies) is compared with the CVODE solution
// of the Hertz equation over the whole contact, and contact time, maximum overlap and
// maximum force with Johnson's closed forms.
// -----------------------------------------------------------------------------------
RunOutput run_hertz_impact(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const bool pair = c.options.count("geometry") && c.options.at("geometry") == "pair";
  const SceneSpec spec = scene_with(c, v, rc, {});
  Simulation sim(spec);
  if (sim.particles().size() != (pair ? 2u : 1u)) throw std::runtime_error(v.scene + ": wrong number of particles");
  const double R = v.param("radius");
  std::vector<double> t, overlap, force, vel;
  RunOutput r;
  r.wall_seconds = run_and_time(sim, [&](const Simulation& s) {
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
  r.steps = sim.steps();
  r.particles = sim.particles().size();
  r.dt = sim.dt();

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
  r.oracle_accuracy = accuracy_str(ode.accuracy);

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

// -----------------------------------------------------------------------------------
// Restitution: for each e_n in options.en, a sphere hits a wall at options speed with
// no gravity; the rebound/incident speed ratio is compared with the e_n asked for, and
// with the restitution CVODE finds for the α the solver chose (the damping formula's own
// departure from e_n is reported beside it).
// -----------------------------------------------------------------------------------
namespace {
double cached_restitution(double alpha, oracles::OracleAccuracy& acc) {
  static std::mutex mu;
  static std::map<double, std::pair<double, oracles::OracleAccuracy>> cache;
  std::lock_guard<std::mutex> lock(mu);
  auto it = cache.find(alpha);
  if (it == cache.end()) {
    oracles::OracleAccuracy a;
    const double e = oracles::hertz_restitution(alpha, &a);
    it = cache.emplace(alpha, std::make_pair(e, a)).first;
  }
  acc = it->second.second;
  return it->second.first;
}
/// The oblique-impact ODE for one angle, solved once per parameter set (the harness
/// calls a runner repeatedly to time it; the oracle does not change).
oracles::ObliqueResult cached_oblique(const oracles::ObliqueParams& op) {
  static std::mutex mu;
  static std::map<std::vector<double>, oracles::ObliqueResult> cache;
  const std::vector<double> key{op.radius, op.density, op.e_particle, op.nu_particle, op.e_wall,
                                op.nu_wall,  op.mu,      op.speed,      op.angle_deg};
  std::lock_guard<std::mutex> lock(mu);
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, oracles::oblique_impact_cvode(op)).first;
  return it->second;
}
}  // namespace

RunOutput run_hertz_restitution(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const std::vector<double> ens = numbers_in(c, "en");
  const double speed = v.param("speed");
  RunOutput r;
  double e_req = 0.0, e_ode = 0.0, e_model = 0.0;
  std::vector<std::vector<double>> rows;
  oracles::OracleAccuracy acc;
  for (double en : ens) {
    const SceneSpec spec = scene_with(c, v, rc, {{"contacts[0].en", num(en)}});
    Simulation sim(spec);
    r.wall_seconds += run_and_time(sim, [](const Simulation&) {});
    r.steps += sim.steps();
    r.dt = sim.dt();
    if (sim.contact()->active_contacts() != 0)
      throw std::runtime_error(c.name + ": the sphere is still in contact at the end (en = " + num(en) + ")");
    const double e_dem = sim.particles().vy[0] / speed;  // moving up again, incident speed `speed`
    const PairParams& pp = spec.pairs.get(sim.particles().material[0], spec.walls.at(0).material);
    const double e_alpha = cached_restitution(pp.hertz_alpha, acc);
    e_req = std::max(e_req, rel_pct(en, e_dem));
    e_ode = std::max(e_ode, rel_pct(e_alpha, e_dem));
    e_model = std::max(e_model, rel_pct(en, e_alpha));
    rows.push_back({en, pp.hertz_alpha, e_dem, e_alpha});
  }
  r.particles = 1;
  r.oracle_accuracy = accuracy_str(acc);
  r.measurements.push_back({"e_vs_requested", "max_rel_pct", e_req});
  r.measurements.push_back({"e_vs_ode", "max_rel_pct", e_ode});
  r.measurements.push_back({"damping_formula_e_vs_requested", "max_rel_pct", e_model});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path, {"en_requested[-]", "alpha[-]", "e_measured[-]", "e_oracle_for_alpha[-]"},
                  {"restitution " + v.name + ", " + rc.integrator + ", dt = " + num(r.dt) +
                   " s; e_oracle_for_alpha: CVODE of xi'' = -xi^(3/2) - alpha xi^(1/4) xi' with the solver's alpha"});
    for (const auto& row : rows) w.row(row);
  }
  return r;
}

// -----------------------------------------------------------------------------------
// Oblique impact (Kharaz et al. 2001 / MFIX DEM05): for each incidence angle in
// options.angles the sphere hits the wall (normal +y) at options speed, moving along
// +x; rebound spin (sense that rolls it along +x: -w_z) and tangential restitution
// v_x'/v_x against the CVODE Mindlin ODE at every angle, and against the gross-sliding
// closed forms where that ODE slides throughout.
// -----------------------------------------------------------------------------------
RunOutput run_oblique_impact(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const std::vector<double> angles = numbers_in(c, "angles");
  const double R = v.param("radius"), speed = v.param("speed"), gap = v.param("gap");
  RunOutput r;
  double e_w = 0, e_et = 0, e_ws = 0, e_ets = 0, e_wr = 0, e_vn = 0, w_max = 0;
  int sliding = 0;
  std::vector<std::vector<double>> rows;
  oracles::OracleAccuracy acc;
  for (double ang : angles) {
    oracles::ObliqueParams op{R, v.param("density"), v.param("youngs_modulus"), v.param("poisson_ratio"),
                              v.param("youngs_modulus_wall"), v.param("poisson_ratio_wall"), v.param("mu"), speed, ang};
    const oracles::ObliqueResult o = cached_oblique(op);
    acc = o.accuracy;
    const double th = ang * std::numbers::pi / 180.0;
    const double vx = speed * std::sin(th), vy = -speed * std::cos(th);
    // Run until a fifth of the contact time after it ends (constant speed until touch).
    const double t_end = gap / -vy + 1.2 * o.contact_time;
    const SceneSpec spec = scene_with(c, v, rc,
                                      {{"particles[0].velocity", vec(vx, vy, 0.0)},
                                       {"particles[0].position", vec(0.0, R + gap, 0.0)},
                                       {"integrator.end_time", num(t_end)}});
    Simulation sim(spec);
    r.wall_seconds += run_and_time(sim, [](const Simulation&) {});
    r.steps += sim.steps();
    r.dt = sim.dt();
    if (sim.contact()->active_contacts() != 0)
      throw std::runtime_error(c.name + ": still in contact at the end (angle " + num(ang) + ")");
    const ParticleStore& p = sim.particles();
    const double omega = -p.wz[0], et = p.vx[0] / vx;
    w_max = std::max(w_max, std::abs(o.omega));
    e_w = std::max(e_w, std::abs(omega - o.omega));
    e_et = std::max(e_et, std::abs(et - o.et));
    e_vn = std::max(e_vn, rel_pct(o.vn_after, p.vy[0]));
    const oracles::ObliqueSliding cf = oracles::oblique_sliding_closed_form(op);
    double w_cf = std::numeric_limits<double>::quiet_NaN(), et_cf = w_cf;
    if (o.slid_throughout) {
      ++sliding;
      w_cf = cf.omega_lever;
      et_cf = cf.et;
      e_ws = std::max(e_ws, rel_pct(cf.omega_lever, omega));
      e_ets = std::max(e_ets, rel_pct(cf.et, et));
      e_wr = std::max(e_wr, rel_pct(cf.omega_rigid, omega));
    }
    rows.push_back({ang, omega, o.omega, w_cf, cf.omega_rigid, et, o.et, et_cf, o.slid_throughout ? 1.0 : 0.0,
                    180.0 / std::numbers::pi * std::atan2(p.vx[0], p.vy[0])});
  }
  r.particles = 1;
  r.oracle_accuracy = accuracy_str(acc);
  // Spin error relative to the largest rebound spin over the angles (at 5° the spin is
  // 20 rad/s against 620 at 30°, so a relative error there would not measure accuracy).
  r.measurements.push_back({"omega", "max_abs_pct_of_peak", 100.0 * e_w / w_max});
  r.measurements.push_back({"et", "max_abs_pct", 100.0 * e_et});
  r.measurements.push_back({"omega_sliding", "max_rel_pct", e_ws});
  r.measurements.push_back({"et_sliding", "max_rel_pct", e_ets});
  r.measurements.push_back({"omega_sliding_rigid_sphere", "max_rel_pct", e_wr});
  r.measurements.push_back({"normal_rebound_speed", "max_rel_pct", e_vn});
  r.measurements.push_back({"angles_sliding_throughout", "count", static_cast<double>(sliding)});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path,
                  {"angle[deg]", "omega[rad/s]", "omega_ode[rad/s]", "omega_sliding_closed_form[rad/s]",
                   "omega_sliding_rigid[rad/s]", "et[-]", "et_ode[-]", "et_sliding_closed_form[-]",
                   "ode_slid_throughout[-]", "rebound_angle[deg]"},
                  {"oblique impact " + v.name + ", " + rc.integrator + ", dt = " + num(r.dt) +
                   " s; omega: rebound spin in the sense that rolls the sphere forward; closed forms only where the "
                   "ODE slides throughout (NaN elsewhere); rebound angle from the wall normal"});
    for (const auto& row : rows) w.row(row);
  }
  return r;
}

// -----------------------------------------------------------------------------------
// Rolling resistance: a sphere on a floor (normal +y) rolling along +x without slip
// (options.mode = "roll"), or spinning about +x on a frictionless floor ("spin"),
// decelerated by the constant rolling torque until it stops, and after the stop.
// -----------------------------------------------------------------------------------
RunOutput run_rolling_resistance(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const bool spin = c.options.count("mode") && c.options.at("mode") == "spin";
  const SceneSpec spec = scene_with(c, v, rc, {});
  Simulation sim(spec);
  std::vector<double> t, q;  // q: the centre's speed v_x (roll) or the spin w_x (spin)
  const double R = v.param("radius");
  RunOutput r;
  r.wall_seconds = run_and_time(sim, [&](const Simulation& s) {
    const ParticleStore& p = s.particles();
    t.push_back(s.time());
    q.push_back(spin ? p.wx[0] : p.vx[0]);
  });
  r.steps = sim.steps();
  r.particles = 1;
  r.dt = sim.dt();
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

}  // namespace cdm::verification
