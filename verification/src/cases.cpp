/// @file cases.cpp
/// @brief Case runners: run the solver for one sweep point, evaluate the oracle at the
/// same times, and measure the errors. The registry at the bottom maps each case kind
/// (case.toml `kind`) to its runner.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <sstream>
#include <stdexcept>

#include "cdm/oracles/clustering.hpp"
#include "cdm/oracles/free_fall.hpp"
#include "cdm/oracles/gas_mms.hpp"
#include "cdm/oracles/packed_bed.hpp"
#include "cdm/oracles/slipping_ball.hpp"
#include "cdm/oracles/stacked.hpp"
#include "cdm/oracles/suspension.hpp"
#include "cdm/oracles/taylor_green.hpp"
#include "cdm/oracles/terminal_velocity.hpp"
#include "cdm/oracles/vortex_advection.hpp"
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
SceneSpec scene_for(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  std::vector<SceneOverride> ov = v.set;
  ov.push_back({"integrator.scheme", "\"" + rc.integrator + "\""});
  ov.push_back({"integrator.dt", "\"auto\""});
  char d[32];
  std::snprintf(d, sizeof d, "%.17g", rc.dt_divisor);
  ov.push_back({"integrator.dt_divisor", d});
  SceneSpec s = load_scene(v.scene, ov);
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
  if (rc.timing_only) return r;  // a repeat for timing: no oracle, no tables

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
  if (sim.particles().size() != 2) throw std::runtime_error(v.scene + ": the stacked case needs exactly 2 particles");
  std::vector<double> t, y1, y2;
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    t.push_back(s.time());
    y1.push_back(s.particles().y[0]);
    y2.push_back(s.particles().y[1]);
  });
  if (rc.timing_only) return r;  // a repeat for timing: no oracle, no tables
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
  if (rc.timing_only) return r;  // a repeat for timing: no oracle, no tables
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


// ------------------------------------------------------------------------------------
// Case 4: tracers in the oscillating vortex (§3.4): the circle (eq 43, 2D) and LeVeque's
// sphere (3D). The field sampled on the grid is separable in time like the closed form,
// so every tracer returns to its start at t = nT up to the time integration error: the
// return distance measures the integrator. The distance from the exact-field path
// (CVODE oracle) at sample times within the first period measures the interpolation.
// ------------------------------------------------------------------------------------
/// The scene with the variant's overrides, the sweep point's integrator and dt = T/N.
SceneSpec scene_with_dt(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc, double dt) {
  std::vector<SceneOverride> ov = v.set;
  ov.push_back({"integrator.scheme", "\"" + rc.integrator + "\""});
  char d[32];
  std::snprintf(d, sizeof d, "%.17g", dt);
  ov.push_back({"integrator.dt", d});
  SceneSpec s = load_scene(v.scene, ov);
  s.output_particles = false;
  return s;
}

RunOutput run_vortex_advection(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const double T = v.param("period"), L = v.param("length");
  const auto steps_per_period = static_cast<std::uint64_t>(std::llround(rc.dt_divisor));
  const SceneSpec spec = scene_with_dt(c, v, rc, T / rc.dt_divisor);
  Simulation sim(spec);
  const ParticleStore& p = sim.particles();
  const std::size_t n = p.size();
  const std::vector<double> x0 = p.x, y0 = p.y, z0 = p.z;
  // Samples within the first period: every tenth of T.
  const std::uint64_t sample_every = steps_per_period % 10 == 0 ? steps_per_period / 10 : steps_per_period;
  std::vector<double> ts;
  std::vector<std::vector<double>> sx, sy, sz;
  std::vector<double> cycle_err;
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    const std::uint64_t k = s.steps();
    if (k > 0 && k <= steps_per_period && k % sample_every == 0) {
      ts.push_back(s.time());
      sx.push_back(p.x); sy.push_back(p.y); sz.push_back(p.z);
    }
    if (k > 0 && k % steps_per_period == 0) {
      double e = 0.0;
      for (std::size_t i = 0; i < n; ++i)
        e = std::max(e, std::max({std::abs(p.x[i] - x0[i]), std::abs(p.y[i] - y0[i]), std::abs(p.z[i] - z0[i])}));
      cycle_err.push_back(e);
    }
  });
  if (rc.timing_only) return r;  // a repeat for timing: no oracle, no tables
  const oracles::VortexParams op{v.param("three_d") != 0.0, L, v.param("amplitude"), T};
  const oracles::TracerPaths o = oracles::vortex_tracers(op, x0, y0, z0, ts);
  r.oracle_accuracy = accuracy_text(o.accuracy);
  double path = 0.0, path_half = 0.0;
  for (std::size_t k = 0; k < ts.size(); ++k) {
    double e = 0.0;
    for (std::size_t i = 0; i < n; ++i)
      e = std::max(e, std::max({std::abs(sx[k][i] - o.x[k][i]), std::abs(sy[k][i] - o.y[k][i]),
                                std::abs(sz[k][i] - o.z[k][i])}));
    path = std::max(path, e);
    if (2 * (k + 1) == ts.size()) path_half = e;
  }
  double ret = 0.0;
  for (double e : cycle_err) ret = std::max(ret, e);
  const double R = v.param("shell_radius");
  r.measurements.push_back({"return", "max_abs_over_cycles", ret});
  r.measurements.push_back({"return", "max_pct_of_shell_radius", 100.0 * ret / R});
  r.measurements.push_back({"return_last_cycle", "abs", cycle_err.empty() ? INFINITY : cycle_err.back()});
  r.measurements.push_back({"path", "max_abs_first_period", path});
  r.measurements.push_back({"path", "max_pct_of_shell_radius", 100.0 * path / R});
  r.measurements.push_back({"path_half_period", "abs", path_half});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path, {"cycle[-]", "t[s]", "return_Linf[m]"},
                  {"vortex advection " + v.name + ", " + rc.integrator + ", dt = " + std::to_string(r.dt) +
                   " s: L-infinity distance of the tracers from their start at t = kT (exact: 0)"});
    for (std::size_t k = 0; k < cycle_err.size(); ++k)
      w.row({static_cast<double>(k + 1), static_cast<double>(k + 1) * T, cycle_err[k]});
    std::string spath = rc.series_path;
    spath.insert(spath.size() - 4, "_half_period");
    const std::size_t kh = ts.size() / 2 - 1;
    TableWriter ws(spath, {"id[-]", "x[m]", "y[m]", "z[m]", "x_oracle[m]", "y_oracle[m]", "z_oracle[m]"},
                   {"tracer positions at t = T/2 (largest deformation), cdm and the exact-field oracle"});
    if (ts.size() >= 2)
      for (std::size_t i = 0; i < n; ++i)
        ws.row({static_cast<double>(i), sx[kh][i], sy[kh][i], sz[kh][i], o.x[kh][i], o.y[kh][i], o.z[kh][i]});
  }
  return r;
}

// ------------------------------------------------------------------------------------
// Case 6, decoupled (§3.6, eq 48, Fig 15): a particle falling through a frozen upward
// gas stream. v(t) over the run against CVODE on eq 48; the final velocity against the
// terminal velocity from the force balance (GSL root).
// ------------------------------------------------------------------------------------
RunOutput run_terminal_velocity(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const SceneSpec spec = scene_with_dt(c, v, rc, v.param("time_scale") / rc.dt_divisor);
  Simulation sim(spec);
  std::vector<double> t, vy;
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    t.push_back(s.time());
    vy.push_back(s.particles().vy[0]);
  });
  if (rc.timing_only) return r;  // a repeat for timing: no oracle, no tables
  oracles::TerminalParams p;
  p.d = v.param("d");
  p.rho_p = v.param("rho_p");
  p.rho_g = v.param("rho_g");
  p.mu_g = v.param("mu_g");
  p.u_g = v.param("u_g");
  p.g = v.param("g");
  const oracles::TerminalSeries o = oracles::terminal_velocity_cvode(p, t);
  const oracles::TerminalState term = oracles::terminal_velocity(p);
  r.oracle_accuracy = accuracy_text(o.accuracy);
  const double vt = std::abs(term.velocity);
  double e = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) e = std::max(e, std::abs(vy[k] - o.v[k]));
  r.measurements.push_back({"v", "max_abs_pct_of_terminal", 100.0 * e / vt});
  r.measurements.push_back({"v_end", "rel_pct_vs_ode", rel_pct(o.v.back(), vy.back())});
  r.measurements.push_back({"v_end", "rel_pct_vs_terminal", rel_pct(term.velocity, vy.back())});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path, {"t[s]", "vy[m/s]", "vy_oracle[m/s]", "v_terminal[m/s]"},
                  {"terminal velocity " + v.name + ", " + rc.integrator + ", dt = " + std::to_string(r.dt) +
                   " s; oracle: CVODE on Garg et al. eq 48; terminal from the force balance (slip " +
                   std::to_string(term.slip) + " m/s)"});
    for (std::size_t k = 0; k < t.size(); ++k) w.row({t[k], vy[k], o.v[k], term.velocity});
  }
  return r;
}

// ------------------------------------------------------------------------------------
// Case 5 (§3.5, eq 44, Fig 14): particles with Wen–Yu drag in a steady Taylor–Green
// vortex, periodic. Positions are unwrapped across the periodic boundaries so that they
// can be compared with the oracle's (unwrapped) trajectories in the exact field.
// ------------------------------------------------------------------------------------
/// Runs @p sim, calling @p record(step, x, y) with positions unwrapped across periodic
/// boundaries of period @p L (both axes), after every step and at t = 0.
template <class F>
RunOutput run_unwrapped(Simulation& sim, double L, F&& record) {
  const ParticleStore& p = sim.particles();
  const std::size_t n = p.size();
  std::vector<double> ux = p.x, uy = p.y, px = p.x, py = p.y;
  return run_timed(sim, [&](const Simulation& s) {
    for (std::size_t i = 0; i < n; ++i) {
      const double dx = p.x[i] - px[i], dy = p.y[i] - py[i];
      ux[i] += dx - L * std::round(dx / L);
      uy[i] += dy - L * std::round(dy / L);
      px[i] = p.x[i];
      py[i] = p.y[i];
    }
    record(s, ux, uy);
  });
}

oracles::TaylorGreenParams taylor_green_params(const Variant& v) {
  oracles::TaylorGreenParams tp;
  tp.U = v.param("U");
  tp.kx = tp.ky = v.param("k");
  tp.d = v.param("d");
  tp.rho_p = v.param("rho_p");
  tp.rho_g = v.param("rho_g");
  tp.mu_g = v.param("mu_g");
  tp.eps_g = v.param("eps_g");
  return tp;
}

RunOutput run_taylor_green(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const double L = v.param("L"), U = v.param("U");
  const SceneSpec spec = scene_with_dt(c, v, rc, v.param("T_g") / rc.dt_divisor);
  Simulation sim(spec);
  const ParticleStore& p = sim.particles();
  const std::size_t n = p.size();
  std::vector<oracles::ParticleState2D> init(n);
  for (std::size_t i = 0; i < n; ++i) init[i] = {p.x[i], p.y[i], p.vx[i], p.vy[i]};
  std::vector<double> t;
  std::vector<std::vector<double>> xs, ys, vxs, vys;
  RunOutput r = run_unwrapped(sim, L, [&](const Simulation& s, const std::vector<double>& ux, const std::vector<double>& uy) {
    t.push_back(s.time());
    xs.push_back(ux);
    ys.push_back(uy);
    vxs.push_back(p.vx);
    vys.push_back(p.vy);
  });
  if (rc.timing_only) return r;  // a repeat for timing: no oracle, no tables
  const oracles::TaylorGreenSeries o = oracles::taylor_green_cvode(taylor_green_params(v), init, t);
  r.oracle_accuracy = accuracy_text(o.accuracy);
  double ex = 0.0, ev = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k)
    for (std::size_t i = 0; i < n; ++i) {
      const auto& op = o.particles[i];
      ex = std::max({ex, std::abs(xs[k][i] - op.x[k]), std::abs(ys[k][i] - op.y[k])});
      ev = std::max({ev, std::abs(vxs[k][i] - op.vx[k]), std::abs(vys[k][i] - op.vy[k])});
    }
  r.measurements.push_back({"position", "max_abs_pct_of_L", 100.0 * ex / L});
  r.measurements.push_back({"velocity", "max_abs_pct_of_U", 100.0 * ev / U});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path, {"t[s]", "id[-]", "x[m]", "y[m]", "x_oracle[m]", "y_oracle[m]"},
                  {"Taylor-Green particles " + v.name + ", " + rc.integrator + ", dt = " + std::to_string(r.dt) +
                   " s; positions unwrapped across the periodic boundaries"});
    const std::size_t every = std::max<std::size_t>(1, t.size() / 100);
    for (std::size_t k = 0; k < t.size(); k += every)
      for (std::size_t i = 0; i < n; ++i) w.row({t[k], static_cast<double>(i), xs[k][i], ys[k][i], o.particles[i].x[k], o.particles[i].y[k]});
  }
  return r;
}

// Clustering (Fig 14, quantified) and the cell-crossing threshold St_c = 1/4 (Maxey 1987).
// D = s²/n̄ − 1 over boxes × boxes boxes (clustering.hpp) every T_g/10, against the same
// index for uniformly random points; the fraction of particles that ever left the vortex
// cell they started in (cells bounded by the separatrices k x, k y = π/2 + nπ).
RunOutput run_taylor_green_clustering(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const double L = v.param("L"), k = v.param("k"), Tg = v.param("T_g");
  const int M = static_cast<int>(v.param("boxes"));
  const SceneSpec spec = scene_with_dt(c, v, rc, Tg / rc.dt_divisor);
  Simulation sim(spec);
  const ParticleStore& p = sim.particles();
  const std::size_t n = p.size();
  const auto every = static_cast<std::uint64_t>(std::max(1.0, std::round(rc.dt_divisor / 10.0)));
  auto cell = [&](double x) { return static_cast<long>(std::floor((k * x - 0.5 * std::numbers::pi) / std::numbers::pi)); };
  std::vector<long> cx0(n), cy0(n);
  for (std::size_t i = 0; i < n; ++i) { cx0[i] = cell(p.x[i]); cy0[i] = cell(p.y[i]); }
  std::vector<std::uint8_t> crossed(n, 0);
  std::vector<double> ts, ds;
  std::vector<int> counts(static_cast<std::size_t>(M * M));
  auto index = [&]() {
    std::fill(counts.begin(), counts.end(), 0);
    for (std::size_t i = 0; i < n; ++i) {
      const int bx = std::min(M - 1, static_cast<int>(p.x[i] / L * M)), by = std::min(M - 1, static_cast<int>(p.y[i] / L * M));
      ++counts[static_cast<std::size_t>(by * M + bx)];
    }
    const double mean = static_cast<double>(n) / (M * M);
    double s2 = 0.0;
    for (int cnt : counts) s2 += (cnt - mean) * (cnt - mean);
    return s2 / (M * M) / mean - 1.0;
  };
  RunOutput r = run_unwrapped(sim, L, [&](const Simulation& s, const std::vector<double>& ux, const std::vector<double>& uy) {
    for (std::size_t i = 0; i < n; ++i)
      if (cell(ux[i]) != cx0[i] || cell(uy[i]) != cy0[i]) crossed[i] = 1;
    if (s.steps() % every == 0) {
      ts.push_back(s.time());
      ds.push_back(index());
    }
  });
  if (rc.timing_only) return r;
  const oracles::ClusteringBaseline base = oracles::random_points_clustering(static_cast<int>(n), M);
  char acc[96];
  std::snprintf(acc, sizeof acc, "monte-carlo(%d_draws,mean=%.4f,sd=%.4f)", base.draws, base.mean, base.stddev);
  r.oracle_accuracy = acc;
  double dmax = -INFINITY;
  for (double d : ds) dmax = std::max(dmax, d);
  std::size_t nc = 0;
  for (auto b : crossed) nc += b;
  r.measurements.push_back({"clustering_final", "index_D", ds.back()});
  r.measurements.push_back({"clustering_final", "z_vs_random", (ds.back() - base.mean) / base.stddev});
  r.measurements.push_back({"clustering_max", "z_vs_random", (dmax - base.mean) / base.stddev});
  r.measurements.push_back({"crossed_cells", "fraction_pct", 100.0 * static_cast<double>(nc) / static_cast<double>(n)});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path, {"t[s]", "D[-]", "D_random_mean[-]", "D_random_sd[-]"},
                  {"Taylor-Green clustering " + v.name + ", " + rc.integrator + ", dt = " + std::to_string(r.dt) +
                   " s: box-counting index D = s^2/mean - 1 over " + std::to_string(M) + "x" + std::to_string(M) +
                   " boxes, and D for uniformly random points (Monte Carlo)"});
    for (std::size_t j = 0; j < ts.size(); ++j) w.row({ts[j], ds[j], base.mean, base.stddev});
    std::string fpath = rc.series_path;
    fpath.insert(fpath.size() - 4, "_final");
    TableWriter f(fpath, {"id[-]", "x[m]", "y[m]", "vx[m/s]", "vy[m/s]", "crossed[-]"},
                  {"particles at the end (wrapped into the box), and whether each left its starting vortex cell"});
    for (std::size_t i = 0; i < n; ++i) f.row({static_cast<double>(i), p.x[i], p.y[i], p.vx[i], p.vy[i], static_cast<double>(crossed[i])});
  }
  return r;
}

// Case 6, two-way coupled (§3.6, Fig 15): the same fall through a solved gas that
// receives the drag reaction. v(t) against the decoupled ODE oracle (the self-induced
// gas disturbance is a numerical artefact the coupling must keep small), and the momentum
// balance of every gas step: what the gas received against what drag gave the particles.
RunOutput run_terminal_velocity_coupled(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  SceneSpec spec0 = load_scene(v.scene, v.set);
  const SceneSpec spec = scene_with_dt(c, v, rc, spec0.gas_dt / rc.dt_divisor);
  Simulation sim(spec);
  std::vector<double> t, vy;
  double imbalance = 0.0, imbalance_cells = 0.0, exchanged = 0.0;
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    t.push_back(s.time());
    vy.push_back(s.particles().vy[0]);
    if (s.steps() > 0 && s.steps() % s.substeps() == 0) {
      const auto& b = s.coupling_balance();
      const double mag = norm(b.particles);
      exchanged = std::max(exchanged, mag);
      imbalance = std::max(imbalance, norm(b.particles + b.gas_faces) / mag);
      imbalance_cells = std::max(imbalance_cells, norm(b.particles + b.gas_cells) / mag);
    }
  });
  if (rc.timing_only) return r;
  oracles::TerminalParams p;
  p.d = v.param("d");
  p.rho_p = v.param("rho_p");
  p.rho_g = v.param("rho_g");
  p.mu_g = v.param("mu_g");
  p.u_g = v.param("u_g");
  p.g = v.param("g");
  const oracles::TerminalSeries o = oracles::terminal_velocity_cvode(p, t);
  const oracles::TerminalState term = oracles::terminal_velocity(p);
  r.oracle_accuracy = accuracy_text(o.accuracy);
  const double vt = std::abs(term.velocity);
  double e = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) e = std::max(e, std::abs(vy[k] - o.v[k]));
  r.measurements.push_back({"v", "max_abs_pct_of_terminal", 100.0 * e / vt});
  r.measurements.push_back({"v_end", "rel_pct_vs_terminal", rel_pct(term.velocity, vy.back())});
  r.measurements.push_back({"momentum_exchange", "max_rel_imbalance_faces", imbalance});
  r.measurements.push_back({"momentum_exchange", "max_rel_imbalance_cells", imbalance_cells});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path, {"t[s]", "vy[m/s]", "vy_oracle[m/s]", "v_terminal[m/s]"},
                  {"terminal velocity, two-way coupled, " + v.name + ", " + rc.integrator + ", particle dt = " +
                   std::to_string(r.dt) + " s, gas dt = " + std::to_string(spec.gas_dt) +
                   " s; oracle: CVODE on Garg et al. eq 48 (uncoupled)"});
    for (std::size_t k = 0; k < t.size(); ++k) w.row({t[k], vy[k], o.v[k], term.velocity});
  }
  return r;
}

// ------------------------------------------------------------------------------------
// The gas solver against manufactured solutions (gas_mms.hpp): the exact fields at t = 0,
// the oracle's sources added every step, the error at the end on four grids. dt = C h²/N
// keeps the first-order time error below the second-order space error.
// ------------------------------------------------------------------------------------
RunOutput run_gas_mms(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  oracles::GasMmsParams q;
  q.u0 = v.param("u0");
  q.v0 = v.param("v0");
  q.p0 = v.param("p0");
  q.a = v.param("a");
  q.b = v.param("b");
  q.rho = v.param("rho");
  q.mu = v.param("mu");
  const double h = v.h, dt = v.param("dt_per_h2") * h * h / rc.dt_divisor;
  char d[32];
  std::snprintf(d, sizeof d, "%.17g", dt);
  std::vector<SceneOverride> ov = v.set;
  ov.push_back({"gas.dt", d});
  ov.push_back({"integrator.dt", d});
  SceneSpec spec = load_scene(v.scene, ov);
  spec.output_particles = false;
  Simulation sim(spec);
  fluid::GasField& gas = *sim.gas_mutable();
  const fluid::StaggeredGrid& g = gas.grid();
  auto fill = [&](std::vector<double>& a, fluid::Staggering s, auto&& f) {
    for (int k = 0; k < g.samples(s, 2); ++k)
      for (int j = 0; j < g.samples(s, 1); ++j)
        for (int i = 0; i < g.samples(s, 0); ++i) {
          const Vec3 x = g.position(s, i, j, k);
          a[g.at(i, j, k)] = f(x);
        }
  };
  fill(gas.u, fluid::Staggering::u, [&](Vec3 x) { return oracles::gas_mms_state(q, x.x, x.y, 0.0).u; });
  fill(gas.v, fluid::Staggering::v, [&](Vec3 x) { return oracles::gas_mms_state(q, x.x, x.y, 0.0).v; });
  fill(gas.p, fluid::Staggering::centre, [&](Vec3 x) { return oracles::gas_mms_state(q, x.x, x.y, 0.0).p; });
  fill(gas.eps_g, fluid::Staggering::centre, [&](Vec3 x) { return oracles::gas_mms_state(q, x.x, x.y, 0.0).eps; });
  g.fill_scalar_ghosts(gas.eps_g);
  g.fill_velocity_ghosts(gas.u, gas.v, gas.w);
  g.fill_pressure_ghosts(gas.p);
  gas.refresh();
  fluid::GasSolver& solver = *sim.gas_solver();
  solver.momentum_source = [q](Vec3 x, double t, int comp) {
    const oracles::GasMmsSources s = oracles::gas_mms_sources(q, x.x, x.y, t);
    return comp == 0 ? s.momentum_x : comp == 1 ? s.momentum_y : 0.0;
  };
  solver.mass_source = [q](Vec3 x, double t) { return oracles::gas_mms_sources(q, x.x, x.y, t).mass; };
  double resid = 0.0;
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    if (s.steps() > 0) resid = std::max(resid, s.gas_solver()->continuity_residual());
  });
  r.particles = g.cell_count();  // the "particle-steps" column counts cell-steps here
  if (rc.timing_only) return r;
  r.oracle_accuracy = "closed_form(sympy)";
  const double T = sim.time();
  double eu = 0.0, ev = 0.0, ep = 0.0, su = 0.0, sv = 0.0, sp = 0.0, pmean = 0.0, emean = 0.0;
  const int nx = g.n(0), ny = g.n(1);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Vec3 xc = g.position(fluid::Staggering::centre, i, j, 0);
      pmean += gas.p[g.at(i, j, 0)];
      emean += oracles::gas_mms_state(q, xc.x, xc.y, T).p;
    }
  pmean /= nx * ny;
  emean /= nx * ny;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const Vec3 xu = g.position(fluid::Staggering::u, i, j, 0), xv = g.position(fluid::Staggering::v, i, j, 0);
      const Vec3 xc = g.position(fluid::Staggering::centre, i, j, 0);
      const double du = gas.u[g.at(i, j, 0)] - oracles::gas_mms_state(q, xu.x, xu.y, T).u;
      const double dv = gas.v[g.at(i, j, 0)] - oracles::gas_mms_state(q, xv.x, xv.y, T).v;
      const double dp = (gas.p[g.at(i, j, 0)] - pmean) - (oracles::gas_mms_state(q, xc.x, xc.y, T).p - emean);
      eu = std::max(eu, std::abs(du)); ev = std::max(ev, std::abs(dv)); ep = std::max(ep, std::abs(dp));
      su += du * du; sv += dv * dv; sp += dp * dp;
    }
  const double n = static_cast<double>(nx) * ny;
  r.measurements.push_back({"u", "max_abs", eu});
  r.measurements.push_back({"u", "rms", std::sqrt(su / n)});
  r.measurements.push_back({"v", "max_abs", ev});
  r.measurements.push_back({"v", "rms", std::sqrt(sv / n)});
  r.measurements.push_back({"p", "max_abs", ep});
  r.measurements.push_back({"p", "rms", std::sqrt(sp / n)});
  r.measurements.push_back({"continuity", "max_residual", resid});
  return r;
}

// A homogeneous suspension in a periodic box (issue #4): mean gas and particle velocities
// along gravity against the two-way mean-velocity equations (suspension.hpp, CVODE), the
// slip at the end against the drag law's steady slip, and the mixture momentum.
RunOutput run_suspension(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  // Gas step = particle step = T/N: the explicit exchange converges as dt falls below the
  // gas's drag relaxation time.
  const double dt = v.param("time_scale") / rc.dt_divisor;
  char d[32];
  std::snprintf(d, sizeof d, "%.17g", dt);
  Variant vv = v;
  vv.set.push_back({"gas.dt", d});
  const SceneSpec spec = scene_with_dt(c, vv, rc, dt);
  Simulation sim(spec);
  const ParticleStore& p = sim.particles();
  const fluid::GasField& gas = *sim.gas();
  const fluid::StaggeredGrid& g = gas.grid();
  const double rho_g = gas.density();
  double vol_p = 0.0, mass_p = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d = 2.0 * p.radius[i];
    vol_p += std::numbers::pi * d * d * d / 6.0;
    mass_p += p.mass[i];
  }
  const double box = g.length(0) * g.length(1) * g.length(2), eps_s = vol_p / box;
  std::vector<double> t, U, V, M;
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    if (s.steps() % s.substeps() != 0) return;  // the gas state at gas steps
    double vp = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) vp += p.mass[i] * p.vy[i];
    // Gas: mass-weighted mean of the interstitial velocity on the y faces.
    double flux = 0.0, eps = 0.0;
    for (int k = 0; k < g.n(2); ++k)
      for (int j = 0; j < g.n(1); ++j)
        for (int i = 0; i < g.n(0); ++i) {
          const double ef = 0.5 * (gas.eps_g[g.at(i, j - 1, k)] + gas.eps_g[g.at(i, j, k)]);
          flux += ef * gas.v[g.at(i, j, k)];
          eps += ef;
        }
    t.push_back(s.time());
    U.push_back(flux / eps);
    V.push_back(vp / mass_p);
    M.push_back((rho_g * flux * g.cell_volume() + vp) / box);  // mixture momentum per volume
  });
  if (rc.timing_only) return r;
  oracles::SuspensionParams q;
  q.law = oracles::DragLaw::WenYu;
  q.d = v.param("d");
  q.rho_p = v.param("rho_p");
  q.rho_g = v.param("rho_g");
  q.mu_g = v.param("mu_g");
  q.g = v.param("g");
  q.eps_g = 1.0 - eps_s;
  q.G = v.param("G");
  const oracles::SuspensionSeries o = oracles::suspension_cvode(q, t);
  const oracles::SuspensionSteady st = oracles::suspension_steady(q);
  r.oracle_accuracy = accuracy_text(o.accuracy);
  double eu = 0.0, ev = 0.0, em = 0.0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    eu = std::max(eu, std::abs(U[k] - o.U[k]));
    ev = std::max(ev, std::abs(V[k] - o.V[k]));
    em = std::max(em, std::abs(M[k]));
  }
  const double w = st.slip;
  r.measurements.push_back({"gas_velocity", "max_abs_pct_of_slip", 100.0 * eu / w});
  r.measurements.push_back({"particle_velocity", "max_abs_pct_of_slip", 100.0 * ev / w});
  r.measurements.push_back({"slip_end", "rel_pct_vs_steady", rel_pct(w, U.back() - V.back())});
  r.measurements.push_back({"mixture_momentum", "max_abs_rel", em / (eps_s * q.rho_p * w)});
  if (!rc.series_path.empty()) {
    TableWriter tw(rc.series_path, {"t[s]", "U[m/s]", "U_oracle[m/s]", "V[m/s]", "V_oracle[m/s]", "slip_steady[m/s]"},
                   {"suspension " + v.name + ", " + rc.integrator + ": mean gas (interstitial) and particle velocities "
                    "along y; oracle: CVODE on the two-way mean-velocity equations, eps_s = " + std::to_string(eps_s)});
    for (std::size_t k = 0; k < t.size(); ++k) tw.row({t[k], U[k], o.U[k], V[k], o.V[k], w});
  }
  return r;
}

// Gas through a fixed packing (issue #4), periodic: a mean pressure gradient G drives the
// gas; the superficial velocity U it reaches is measured and G compared with Ergun's
// gradient at U and the packing's own gas fraction, and with the drag law's own.
RunOutput run_packed_bed(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const double G = v.param("G");
  char gs[48];
  std::snprintf(gs, sizeof gs, "[0.0, %.17g, 0.0]", -G);
  Variant vv = v;
  vv.set.push_back({"gas.mean_pressure_gradient", gs});
  SceneSpec spec0 = load_scene(v.scene, vv.set);
  const SceneSpec spec = scene_with_dt(c, vv, rc, spec0.gas_dt / rc.dt_divisor);
  Simulation sim(spec);
  const fluid::GasField& gas = *sim.gas();
  const fluid::StaggeredGrid& g = gas.grid();
  auto superficial = [&]() {  // mean of eps_f v over the y faces
    double s = 0.0;
    for (int k = 0; k < g.n(2); ++k)
      for (int j = 0; j < g.n(1); ++j)
        for (int i = 0; i < g.n(0); ++i)
          s += 0.5 * (gas.eps_g[g.at(i, j - 1, k)] + gas.eps_g[g.at(i, j, k)]) * gas.v[g.at(i, j, k)];
    return s / static_cast<double>(g.cell_count());
  };
  std::vector<double> t, us;
  RunOutput r = run_timed(sim, [&](const Simulation& s2) {
    t.push_back(s2.time());
    us.push_back(superficial());
  });
  if (rc.timing_only) return r;
  const ParticleStore& p = sim.particles();
  double vol = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) vol += std::numbers::pi * std::pow(2.0 * p.radius[i], 3) / 6.0;
  const double box = g.length(0) * g.length(1) * g.length(2), eps_bed = 1.0 - vol / box;
  const double U = us.back();
  oracles::BedParams bp;
  const double lawcode = v.param("law");  // 0 Gidaspow, 1 Wen-Yu, 2 Di Felice
  bp.law = lawcode == 1 ? oracles::DragLaw::WenYu : lawcode == 2 ? oracles::DragLaw::DiFelice : oracles::DragLaw::Gidaspow;
  bp.d = v.param("d");
  bp.rho_g = v.param("rho_g");
  bp.mu_g = v.param("mu_g");
  bp.eps_g = eps_bed;
  r.oracle_accuracy = "closed_form(ergun)";
  const double steady = std::abs(us.back() - us[us.size() * 3 / 4]) / std::abs(U);
  r.measurements.push_back({"pressure_gradient", "rel_pct_vs_ergun", rel_pct(oracles::ergun_pressure_gradient(bp, U), G)});
  r.measurements.push_back({"pressure_gradient", "rel_pct_vs_own_law", rel_pct(oracles::drag_law_pressure_gradient(bp, U), G)});
  r.measurements.push_back({"superficial_velocity", "last_quarter_change_pct", 100.0 * steady});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path, {"t[s]", "U_superficial[m/s]"},
                  {"packed bed " + v.name + ": superficial gas velocity under the imposed gradient " + std::to_string(G) +
                   " Pa/m; bed gas fraction " + std::to_string(eps_bed) + "; Ergun gradient at the final U " +
                   std::to_string(oracles::ergun_pressure_gradient(bp, U)) + " Pa/m"});
    for (std::size_t k = 0; k < t.size(); ++k) w.row({t[k], us[k]});
  }
  return r;
}

// Fluidisation (issue #4): a settled bed under inflow raised in steps. The frictional
// pressure drop across the bed, against the buoyant weight per area once fluidised (the
// plateau), and the minimum-fluidisation velocity where the packed-bed branch meets it,
// against the same drag law's U_mf at the settled bed's gas fraction.
RunOutput run_fluidization(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  SceneSpec spec0 = load_scene(v.scene, v.set);
  std::vector<SceneOverride> ov = v.set;
  ov.push_back({"integrator.scheme", "\"" + rc.integrator + "\""});
  ov.push_back({"integrator.dt", "\"auto\""});
  char d[32];
  std::snprintf(d, sizeof d, "%.17g", rc.dt_divisor);
  ov.push_back({"integrator.dt_divisor", d});
  SceneSpec spec = load_scene(v.scene, ov);
  spec.output_particles = false;
  // Each inflow is held for t_segment (packed) or t_fluidised (fluidised: the bed's
  // pressure drop fluctuates as it bubbles, so it is averaged longer); the first
  // t_transient of each is discarded and the rest averaged.
  const double t_settle = v.param("t_settle"), t_seg = v.param("t_segment"), t_fl = v.param("t_fluidised"),
               t_tr = v.param("t_transient");
  const std::vector<double> factors = {0.25, 0.5, 0.75, 1.25, 1.5, 2.0};
  auto hold = [&](double f) { return f < 1.0 ? t_seg : t_fl; };
  spec.end_time = t_settle + spec.dt;
  for (double f : factors) spec.end_time += hold(f);
  Simulation sim(spec);
  fluid::GasField& gas = *sim.gas_mutable();
  const fluid::StaggeredGrid& g = gas.grid();
  const ParticleStore& p = sim.particles();
  const double area = g.length(0) * g.length(2), floor_y = v.param("floor");
  double vol = 0.0, mass = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    vol += std::numbers::pi * std::pow(2.0 * p.radius[i], 3) / 6.0;
    mass += p.mass[i];
  }
  const double rho_g = gas.density(), grav = v.param("g");
  const double weight = vol * (v.param("rho_p") - rho_g) * grav / area;  // buoyant weight per area [Pa]
  auto layer_p = [&](int j) {
    double s = 0.0;
    for (int k = 0; k < g.n(2); ++k)
      for (int i = 0; i < g.n(0); ++i) s += gas.p[g.at(i, j, k)];
    return s / (g.n(0) * g.n(2));
  };
  // Frictional pressure drop from the inlet face (pressure extrapolated linearly from the
  // first two cell centres: the bed rests on the inlet, where the gradient is uniform) to
  // the top cell centre, less the gas's own hydrostatic head over that height.
  const int j_hi = g.n(1) - 1;
  const double dy = (j_hi + 0.5) * g.h(1);
  auto frictional = [&] {
    const double p_in = 1.5 * layer_p(0) - 0.5 * layer_p(1);
    return p_in - layer_p(j_hi) - rho_g * grav * dy;
  };
  const auto t0 = std::chrono::steady_clock::now();
  auto advance = [&](double until) {
    while (sim.time() < until - 0.5 * sim.dt()) sim.step();
  };
  advance(t_settle);
  // The settled bed: height from the particles' mean height (uniform bed: H = 2 (ȳ − floor)).
  double ybar = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) ybar += p.y[i];
  ybar /= static_cast<double>(p.size());
  const double H = 2.0 * (ybar - floor_y), eps_bed = 1.0 - vol / (area * H);
  // The bed's bulk gas fraction, away from its ends (the layer against the distributor
  // is looser, the top ragged): the spheres' exact volume in the slab [floor + d, floor +
  // H − d], by spherical caps.
  const double d_p = v.param("d");
  auto cap = [](double r, double h) {  // volume of a sphere of radius r below height h above its bottom
    h = std::clamp(h, 0.0, 2.0 * r);
    return std::numbers::pi * h * h * (3.0 * r - h) / 3.0;
  };
  const double s_lo = floor_y + d_p, s_hi = floor_y + H - d_p;
  double v_slab = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double r = p.radius[i], bottom = p.y[i] - r;
    v_slab += cap(r, s_hi - bottom) - cap(r, s_lo - bottom);
  }
  const double eps_bulk = 1.0 - v_slab / (area * (s_hi - s_lo));
  oracles::BedParams bp;
  bp.law = oracles::DragLaw::Gidaspow;
  bp.d = v.param("d");
  bp.rho_p = v.param("rho_p");
  bp.rho_g = v.param("rho_g");
  bp.mu_g = v.param("mu_g");
  bp.g = grav;
  bp.eps_g = eps_bed;
  const oracles::MinFluidisation mf = oracles::minimum_fluidisation(bp);
  auto bed_momentum = [&] {  // Σ m v_y [kg m/s]
    double m = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) m += p.mass[i] * p.vy[i];
    return m;
  };
  std::vector<double> U, dP, dP_corr, dP_sd, hist_t, hist_u, hist_dp, hist_mv;
  for (double f : factors) {
    const double u = f * mf.U;
    gas.set_inlet_velocity(2, u);
    const double start = sim.time(), end = start + hold(f);
    double s = 0.0, s2 = 0.0, t_a = 0.0, t_b = 0.0, mv_a = 0.0;
    int n = 0;
    while (sim.time() < end - 0.5 * sim.dt()) {
      sim.step();
      if (sim.steps() % sim.substeps() != 0) continue;  // once per gas step
      const double q = frictional();
      if (sim.steps() % (10 * sim.substeps()) == 0) {
        hist_t.push_back(sim.time()); hist_u.push_back(u); hist_dp.push_back(q);
        hist_mv.push_back(bed_momentum() / area);
      }
      if (sim.time() < start + t_tr) continue;
      if (n == 0) { t_a = sim.time(); mv_a = bed_momentum(); }
      s += q; s2 += q * q; ++n;
      t_b = sim.time();
    }
    const double mv_b = bed_momentum();
    U.push_back(u);
    dP.push_back(s / n);
    // The bed's momentum balance over the window: mean gas force on it = weight +
    // Δ(Σ m v_y)/T (+ contact forces from the walls, zero once it is fluidised). A bubbling
    // bed's pressure drop swings by ~15 %, with correlation times of ~30 ms, so a 0.45 s
    // mean of it is uncertain by a few per cent; subtracting the momentum the bed gained
    // over the same window removes that sampling error (a bounded momentum over a finite
    // window), leaving what the time average converges to.
    dP_corr.push_back(s / n - (mv_b - mv_a) / (area * std::max(t_b - t_a, sim.dt())));
    dP_sd.push_back(std::sqrt(std::max(0.0, s2 / n - (s / n) * (s / n))));
  }
  RunOutput r;
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.steps = sim.steps();
  r.particles = p.size();
  r.dt = sim.dt();
  if (rc.timing_only) return r;
  r.oracle_accuracy = accuracy_text(mf.accuracy);
  // Plateau: the fluidised segments (U >= 1.25 U_mf), each also reported on its own.
  double plateau = 0.0, plateau_raw = 0.0;
  int np = 0;
  for (std::size_t k = 0; k < U.size(); ++k)
    if (factors[k] > 1.0) {
      plateau += dP_corr[k];
      plateau_raw += dP[k];
      ++np;
      char q[48];
      std::snprintf(q, sizeof q, "plateau_%.2fUmf", factors[k]);
      r.measurements.push_back({q, "rel_pct_vs_weight", rel_pct(weight, dP_corr[k])});
      r.measurements.push_back({q, "uncorrected_rel_pct_vs_weight", rel_pct(weight, dP[k])});
    }
  plateau /= np;
  plateau_raw /= np;
  r.measurements.push_back({"plateau", "uncorrected_rel_pct_vs_weight", rel_pct(weight, plateau_raw)});
  // The packed branch against Ergun at the bed's mean and at its bulk gas fraction.
  oracles::BedParams bulk = bp;
  bulk.eps_g = eps_bulk;
  double dev_mean = 0.0, dev_bulk = 0.0;
  for (std::size_t k = 0; k < U.size(); ++k)
    if (factors[k] < 1.0) {
      dev_mean = std::max(dev_mean, rel_pct(oracles::ergun_pressure_gradient(bp, U[k]) * H, dP[k]));
      dev_bulk = std::max(dev_bulk, rel_pct(oracles::ergun_pressure_gradient(bulk, U[k]) * H, dP[k]));
    }
  r.measurements.push_back({"packed_dP", "max_rel_pct_vs_ergun_eps_bed", dev_mean});
  r.measurements.push_back({"packed_dP", "max_rel_pct_vs_ergun_eps_bulk", dev_bulk});
  // Packed branch: least-squares dP = a U + b U^2 through the packed segments, met with
  // the measured plateau.
  double s11 = 0, s12 = 0, s22 = 0, r1 = 0, r2 = 0;
  for (std::size_t k = 0; k < U.size(); ++k)
    if (factors[k] < 1.0) {
      const double x1 = U[k], x2 = U[k] * U[k];
      s11 += x1 * x1; s12 += x1 * x2; s22 += x2 * x2; r1 += x1 * dP[k]; r2 += x2 * dP[k];
    }
  const double det = s11 * s22 - s12 * s12, a = (r1 * s22 - r2 * s12) / det, b = (s11 * r2 - s12 * r1) / det;
  const double umf = b != 0.0 ? (-a + std::sqrt(a * a + 4.0 * b * plateau)) / (2.0 * b) : plateau / a;
  r.measurements.push_back({"plateau", "rel_pct_vs_weight", rel_pct(weight, plateau)});
  r.measurements.push_back({"u_mf", "rel_pct_vs_drag_law", rel_pct(mf.U, umf)});
  const oracles::MinFluidisation mf_bulk = oracles::minimum_fluidisation(bulk);
  r.measurements.push_back({"u_mf", "rel_pct_vs_drag_law_eps_bulk", rel_pct(mf_bulk.U, umf)});
  r.measurements.push_back({"u_mf", "rel_pct_vs_wen_yu_1966", rel_pct(oracles::wen_yu_minimum_fluidisation_estimate(bp), umf)});
  if (!rc.series_path.empty()) {
    {
      TableWriter w(rc.series_path,
                    {"U[m/s]", "dP_frictional[Pa]", "dP_momentum_corrected[Pa]", "dP_std_dev[Pa]",
                     "buoyant_weight_per_area[Pa]", "U_mf_oracle[m/s]", "dP_ergun_at_eps_bed[Pa]",
                     "dP_ergun_at_eps_bulk[Pa]"},
                    {"fluidisation " + v.name + ", " + rc.integrator + ": settled bed height " + std::to_string(H) +
                         " m, gas fraction " + std::to_string(eps_bed) + " (bulk, between d and H - d: " +
                         std::to_string(eps_bulk) + "); measured U_mf " + std::to_string(umf) + " m/s",
                     "dP averaged over each inflow after the first " + std::to_string(t_tr) +
                         " s; std_dev = its fluctuation (not an error bar of the mean)"});
      for (std::size_t k = 0; k < U.size(); ++k)
        w.row({U[k], dP[k], dP_corr[k], dP_sd[k], weight, mf.U, oracles::ergun_pressure_gradient(bp, U[k]) * H,
               oracles::ergun_pressure_gradient(bulk, U[k]) * H});
    }
    std::string hp = rc.series_path;
    hp.insert(hp.size() - 4, "_history");
    TableWriter h(hp, {"t[s]", "U[m/s]", "dP_frictional[Pa]", "buoyant_weight_per_area[Pa]", "bed_momentum_per_area[Pa*s]"},
                  {"fluidisation " + v.name + ": frictional pressure drop every 10th gas step while the inflow is raised"});
    for (std::size_t k = 0; k < hist_t.size(); ++k) h.row({hist_t[k], hist_u[k], hist_dp[k], weight, hist_mv[k]});
  }
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
      {"vortex_advection", run_vortex_advection},
      {"terminal_velocity", run_terminal_velocity},
      {"gas_mms", run_gas_mms},
      {"suspension", run_suspension},
      {"packed_bed", run_packed_bed},
      {"fluidization", run_fluidization},
      {"terminal_velocity_coupled", run_terminal_velocity_coupled},
      {"taylor_green", run_taylor_green},
      {"taylor_green_clustering", run_taylor_green_clustering},
      {"hertz_impact", run_hertz_impact},
      {"hertz_restitution", run_hertz_restitution},
      {"oblique_impact", run_oblique_impact},
      {"rolling_resistance", run_rolling_resistance},
  };
  return r;
}

}  // namespace cdm::verification
