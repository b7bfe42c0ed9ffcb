/// @file vortex_advection.cpp
/// @brief Tracers in the oscillating vortex (Garg et al. 2012 §3.4): the circle (eq 43,
/// 2D) and LeVeque's sphere (3D). The field sampled on the grid is separable in time like
/// the closed form, so every tracer returns to its start at t = nT up to the time
/// integration error: the return distance measures the integrator. The distance from the
/// exact-field path (CVODE oracle) at sample times within the first period measures the
/// interpolation. dt = T/N, T the period.
#include <algorithm>
#include <cmath>

#include "cdm/oracles/vortex_advection.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

RunOutput vortex_advection(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  const double T = v.param("period"), L = v.param("length");
  const auto steps_per_period = static_cast<std::uint64_t>(std::llround(rc.dt_divisor));
  const SceneSpec spec = scene_with_dt(v, rc, T / rc.dt_divisor);
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
                  {series_title("vortex advection", v, rc, r.dt) + ": L-infinity distance of the tracers from their start at t = kT (exact: 0)"});
    for (std::size_t k = 0; k < cycle_err.size(); ++k)
      w.row({static_cast<double>(k + 1), static_cast<double>(k + 1) * T, cycle_err[k]});
    const std::size_t kh = ts.size() / 2 - 1;
    TableWriter ws(series_beside(rc.series_path, "_half_period"),
                   {"id[-]", "x[m]", "y[m]", "z[m]", "x_oracle[m]", "y_oracle[m]", "z_oracle[m]"},
                   {"tracer positions at t = T/2 (largest deformation), cdm and the exact-field oracle"});
    if (ts.size() >= 2)
      for (std::size_t i = 0; i < n; ++i)
        ws.row({static_cast<double>(i), sx[kh][i], sy[kh][i], sz[kh][i], o.x[kh][i], o.y[kh][i], o.z[kh][i]});
  }
  return r;
}

}  // namespace cdm::verification::runners
