/// @file cases.cpp
/// @brief Case runners: run the solver for one sweep point, evaluate the oracle at the
/// same times, and measure the errors. The registry at the bottom maps each case kind
/// (case.toml `kind`) to its runner.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "cdm/oracles/free_fall.hpp"
#include "cdm/oracles/slipping_ball.hpp"
#include "cdm/oracles/stacked.hpp"
#include "cdm/solver/output.hpp"
#include "cdm/solver/simulation.hpp"
#include "cdm/verification/harness.hpp"

namespace cdm::verification {

namespace {

std::string accuracy_text(const oracles::OracleAccuracy& a) {
  char b[160];
  std::snprintf(b, sizeof b, "%s(rtol=%.0e,atol=%.0e)", a.method.c_str(), a.rtol, a.atol);
  std::string s = b;
  for (auto& ch : s)
    if (ch == ' ') ch = '_';
  return s;
}

/// The scene with the variant's overrides, the sweep point's integrator and dt = t_col/divisor.
SceneSpec scene_for(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  std::vector<SceneOverride> ov = v.set;
  ov.push_back({"integrator.scheme", "\"" + rc.integrator + "\""});
  ov.push_back({"integrator.dt", "\"auto\""});
  char d[32];
  std::snprintf(d, sizeof d, "%.17g", rc.dt_divisor);
  ov.push_back({"integrator.dt_divisor", d});
  SceneSpec s = load_scene(c.scene, ov);
  s.output_particles = false;
  return s;
}

/// Run to end_time, calling @p record after every step (and at t = 0); time the solver.
template <class F>
RunOutput run_timed(Simulation& sim, F&& record) {
  RunOutput r;
  const auto t0 = std::chrono::steady_clock::now();
  sim.run([&](const Simulation& s) { record(s); });
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.steps = sim.steps();
  r.particles = sim.particles().size();
  r.dt = sim.dt();
  return r;
}

double rel_pct(double ref, double val) { return 100.0 * std::abs(ref - val) / std::abs(ref); }

// ------------------------------------------------------------------------------------
// Case 1: free fall onto a wall (Garg et al. 2012 §3.1, App. B).
// y: centre height over the whole run against the three-stage analytic solution.
// With options.apex_bounces = K: the maximum height of each of the first K rebounds
// against the exact soft-sphere apex (App. B) and the hard-sphere h_max,k (Fig 5).
// ------------------------------------------------------------------------------------
RunOutput run_free_fall(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const SceneSpec spec = scene_for(c, v, rc);
  Simulation sim(spec);
  std::vector<double> t, y, vy;
  t.reserve(sim.total_steps() + 1); y.reserve(t.capacity()); vy.reserve(t.capacity());
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    t.push_back(s.time());
    y.push_back(s.particles().y[0]);
    vy.push_back(s.particles().vy[0]);
  });

  const oracles::FreeFallParams p{v.param("radius"), v.param("density"), v.param("h0"), v.param("g"), v.param("kn"),
                                  v.param("en")};
  const oracles::FreeFall oracle(p, spec.end_time);
  r.oracle_accuracy = accuracy_text(oracle.accuracy());

  double ey = 0, ey_abs = 0, ev = 0, vmax = 0;
  std::vector<double> ya(t.size()), va(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    ya[k] = oracle.position(t[k]);
    va[k] = oracle.velocity(t[k]);
    ey = std::max(ey, rel_pct(ya[k], y[k]));
    ey_abs = std::max(ey_abs, std::abs(ya[k] - y[k]));
    ev = std::max(ev, std::abs(va[k] - vy[k]));
    vmax = std::max(vmax, std::abs(va[k]));
  }
  r.measurements.push_back({"y", "max_rel_pct", ey});
  r.measurements.push_back({"y", "max_abs_pct_of_r", 100.0 * ey_abs / p.radius});
  r.measurements.push_back({"v", "max_abs_pct_of_peak", 100.0 * ev / vmax});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path, {"t[s]", "y[m]", "y_oracle[m]", "vy[m/s]", "vy_oracle[m/s]"},
                  {"free fall " + v.name + ", " + rc.integrator + ", dt = " + std::to_string(r.dt) + " s"});
    for (std::size_t k = 0; k < t.size(); ++k) w.row({t[k], y[k], ya[k], vy[k], va[k]});
  }

  auto it = c.options.find("apex_bounces");
  if (it != c.options.end()) {
    const int K = std::stoi(it->second);
    // DEM apexes: the highest sample of each flight that follows a contact.
    std::vector<double> apex;
    bool was_contact = false, in_flight = false;
    double best = 0;
    for (std::size_t k = 0; k < t.size(); ++k) {
      const bool contact = y[k] < p.radius;
      if (contact) {
        if (in_flight) apex.push_back(best);
        in_flight = false;
        was_contact = true;
      } else if (was_contact) {
        if (!in_flight) { in_flight = true; best = y[k]; }
        best = std::max(best, y[k]);
      }
    }
    if (in_flight && !t.empty() && vy.back() < 0) apex.push_back(best);  // flight past its apex at the end
    const std::vector<double> soft = oracle.apex_heights();
    // Compare the first K rebounds that rise at least 1e-3 (h0 - r) above the wall
    // contact height; lower ones are lost in the soft contact's static overlap.
    int n = 0;
    double e_soft = 0, e_hard = 0, e_model = 0;
    std::vector<std::vector<double>> rows;
    for (int k = 0; k < K && k < static_cast<int>(soft.size()); ++k) {
      if (soft[k] - p.radius < 1e-3 * (p.h0 - p.radius)) break;
      const double hard = oracles::FreeFall::hard_sphere_apex(p, k + 1);
      const double dem = k < static_cast<int>(apex.size()) ? apex[k] : std::numeric_limits<double>::infinity();
      e_soft = std::max(e_soft, rel_pct(soft[k], dem));
      e_hard = std::max(e_hard, rel_pct(hard, dem));
      e_model = std::max(e_model, rel_pct(hard, soft[k]));
      rows.push_back({static_cast<double>(k + 1), dem, soft[k], hard});
      ++n;
    }
    if (n < K && static_cast<int>(soft.size()) >= K) e_soft = std::numeric_limits<double>::infinity();
    r.measurements.push_back({"apex_soft", "max_rel_pct", e_soft});
    r.measurements.push_back({"apex_hard", "max_rel_pct", e_hard});
    r.measurements.push_back({"apex_model_soft_vs_hard", "max_rel_pct", e_model});
    r.measurements.push_back({"apex_bounces_compared", "count", static_cast<double>(n)});
    if (rc.series_path.empty()) return r;
    std::string apath = rc.series_path;
    apath.insert(apath.size() - 4, "_apex");
    TableWriter w(apath, {"bounce[-]", "apex[m]", "apex_soft_oracle[m]", "apex_hard_sphere[m]"},
                  {"maximum centre height after each bounce: cdm, exact soft-sphere (App. B), hard sphere (Fig 5)"});
    for (const auto& row : rows) w.row(row);
  }
  return r;
}

// ------------------------------------------------------------------------------------
// Case 2: two stacked particles between two walls (§3.2, App. C).
// ------------------------------------------------------------------------------------
RunOutput run_stacked(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const SceneSpec spec = scene_for(c, v, rc);
  Simulation sim(spec);
  if (sim.particles().size() != 2) throw std::runtime_error(c.scene + ": the stacked case needs exactly 2 particles");
  std::vector<double> t, y1, y2;
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    t.push_back(s.time());
    y1.push_back(s.particles().y[0]);
    y2.push_back(s.particles().y[1]);
  });
  const oracles::StackedParams p{v.param("radius"), v.param("rho_lower"), v.param("rho_upper"), v.param("kn"),
                                 v.param("kn_wall"), v.param("en"), v.param("g"), v.param("y_wall_top"),
                                 v.param("y1_0"), v.param("y2_0")};
  const oracles::StackedSeries o = oracles::stacked_cvode(p, t);
  r.oracle_accuracy = accuracy_text(o.accuracy);
  double e1 = 0, e2 = 0;
  TableWriter w(rc.series_path, {"t[s]", "y1[m]", "y1_oracle[m]", "y2[m]", "y2_oracle[m]"},
                {"stacked particles " + v.name + ", " + rc.integrator + ", dt = " + std::to_string(r.dt) + " s"});
  for (std::size_t k = 0; k < t.size(); ++k) {
    e1 = std::max(e1, rel_pct(o.y1[k], y1[k]));
    e2 = std::max(e2, rel_pct(o.y2[k], y2[k]));
    w.row({t[k], y1[k], o.y1[k], y2[k], o.y2[k]});
  }
  r.measurements.push_back({"y1", "max_rel_pct", e1});
  r.measurements.push_back({"y2", "max_rel_pct", e2});
  return r;
}

// ------------------------------------------------------------------------------------
// Case 3: ball slipping on a rough wall (§3.3). The ball moves along +x on a floor
// with normal +y; it spins about -z, and the slip velocity of its contact point is
// s = v_x + R ω_z. Slip ends at the first zero of s (interpolated between steps).
// ------------------------------------------------------------------------------------
RunOutput run_slipping(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const SceneSpec spec = scene_for(c, v, rc);
  Simulation sim(spec);
  std::vector<double> t, vx, wz;
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    t.push_back(s.time());
    vx.push_back(s.particles().vx[0]);
    wz.push_back(s.particles().wz[0]);
  });
  const oracles::SlippingParams p{v.param("radius"), v.param("v0"), v.param("mu"), v.param("g")};
  const double R = p.radius;
  r.oracle_accuracy = "closed_form";
  // End of slip: the zero of the sliding line. While the contact slides, the friction
  // force is the constant mu m g and the slip s decreases by the same amount every step;
  // the last step that still shows that decrement is extrapolated to s = 0. (Near s = 0
  // the Coulomb force flips with the sign of s, so the first sign change of s depends on
  // the integrator: velocity Verlet's predictor can hold s just above zero.)
  double ts = std::numeric_limits<double>::infinity(), vs = NAN, ws = NAN;
  auto slip = [&](std::size_t k) { return vx[k] + R * wz[k]; };
  if (t.size() > 12) {
    const double ds_ref = slip(9) - slip(10);  // sliding decrement, after the start-up steps
    for (std::size_t k = 11; k < t.size(); ++k) {
      const double ds = slip(k - 1) - slip(k);
      if (std::abs(ds - ds_ref) > 1e-2 * ds_ref || slip(k) <= 0.0) {
        const std::size_t j = k - 1;  // last step on the sliding line
        const double step = t[j] - t[j - 1];
        const double tau = slip(j) / (ds_ref / step);
        ts = t[j] + tau;
        vs = vx[j] - (vx[j - 1] - vx[j]) / step * tau;
        ws = -(wz[j] + (wz[j] - wz[j - 1]) / step * tau);
        break;
      }
    }
  }
  const double g = p.g, mu = p.mu, v0 = p.v0;
  r.measurements.push_back({"t_slip_nondim", "rel_pct", rel_pct(2.0 / 7.0, mu * g * ts / v0)});
  r.measurements.push_back({"v_slip_nondim", "rel_pct", rel_pct(5.0 / 7.0, vs / v0)});
  r.measurements.push_back({"w_slip_nondim", "rel_pct", rel_pct(5.0 / 7.0, ws * R / v0)});
  double ev = 0, ew = 0;
  TableWriter w(rc.series_path, {"t[s]", "vx[m/s]", "vx_oracle[m/s]", "omega[rad/s]", "omega_oracle[rad/s]"},
                {"slipping ball " + v.name + ", " + rc.integrator + ", dt = " + std::to_string(r.dt) +
                 " s; omega = -wz (spin that rolls the ball along +x)"});
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double va = oracles::slipping_velocity(p, t[k]);
    const double wa = oracles::slipping_angular_velocity(p, t[k]);
    ev = std::max(ev, rel_pct(va, vx[k]));
    ew = std::max(ew, 100.0 * std::abs(wa - (-wz[k])) * R / v0);
    w.row({t[k], vx[k], va, -wz[k], wa});
  }
  r.measurements.push_back({"v", "max_rel_pct", ev});
  r.measurements.push_back({"omega", "max_abs_pct_of_v0", ew});
  return r;
}

}  // namespace

// Hertz–Mindlin and rolling resistance (cases_hertz.cpp).
RunOutput run_hertz_impact(const CaseDef&, const Variant&, const RunConfig&);
RunOutput run_hertz_restitution(const CaseDef&, const Variant&, const RunConfig&);
RunOutput run_oblique_impact(const CaseDef&, const Variant&, const RunConfig&);
RunOutput run_rolling_resistance(const CaseDef&, const Variant&, const RunConfig&);

const std::map<std::string, CaseRunner>& case_runners() {
  static const std::map<std::string, CaseRunner> r = {
      {"free_fall", run_free_fall},
      {"stacked", run_stacked},
      {"slipping_ball", run_slipping},
      {"hertz_impact", run_hertz_impact},
      {"hertz_restitution", run_hertz_restitution},
      {"oblique_impact", run_oblique_impact},
      {"rolling_resistance", run_rolling_resistance},
  };
  return r;
}

}  // namespace cdm::verification
