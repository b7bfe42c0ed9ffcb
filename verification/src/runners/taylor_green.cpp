/// @file taylor_green.cpp
/// @brief Particles with Wen–Yu drag in a steady Taylor–Green vortex, periodic (Garg et
/// al. 2012 §3.5, eq 44, Fig 14). Kind taylor_green: trajectories against CVODE in the
/// exact field. Kind taylor_green_clustering: the clustering the vortex causes and the
/// cell-crossing threshold St_c = 1/4 (Maxey 1987). dt = T_g/N.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "cdm/oracles/clustering.hpp"
#include "cdm/oracles/taylor_green.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

namespace {

/// Runs @p sim, calling @p record(step, x, y) with positions unwrapped across periodic
/// boundaries of period @p L (both axes), after every step and at t = 0; unwrapped
/// positions can be compared with the oracle's trajectories in the exact field.
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
  set_particle_gas(tp, v);
  tp.eps_g = v.param("eps_g");
  return tp;
}

}  // namespace

RunOutput taylor_green(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  const double L = v.param("L"), U = v.param("U");
  const SceneSpec spec = scene_with_dt(v, rc, v.param("T_g") / rc.dt_divisor);
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
                  {series_title("Taylor-Green particles", v, rc, r.dt) + "; positions unwrapped across the periodic boundaries"});
    const std::size_t every = std::max<std::size_t>(1, t.size() / 100);
    for (std::size_t k = 0; k < t.size(); k += every)
      for (std::size_t i = 0; i < n; ++i) w.row({t[k], static_cast<double>(i), xs[k][i], ys[k][i], o.particles[i].x[k], o.particles[i].y[k]});
  }
  return r;
}

/// Clustering (Fig 14, quantified): D = s²/n̄ − 1 over boxes × boxes boxes (clustering.hpp)
/// every T_g/10, against the same index for uniformly random points; the fraction of
/// particles that ever left the vortex cell they started in (cells bounded by the
/// separatrices k x, k y = π/2 + nπ).
RunOutput taylor_green_clustering(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  const double L = v.param("L"), k = v.param("k"), Tg = v.param("T_g");
  const int M = static_cast<int>(v.param("boxes"));
  const SceneSpec spec = scene_with_dt(v, rc, Tg / rc.dt_divisor);
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
                  {series_title("Taylor-Green clustering", v, rc, r.dt) + ": box-counting index D = s^2/mean - 1 over " + std::to_string(M) + "x" + std::to_string(M) +
                   " boxes, and D for uniformly random points (Monte Carlo)"});
    for (std::size_t j = 0; j < ts.size(); ++j) w.row({ts[j], ds[j], base.mean, base.stddev});
    TableWriter f(series_beside(rc.series_path, "_final"), {"id[-]", "x[m]", "y[m]", "vx[m/s]", "vy[m/s]", "crossed[-]"},
                  {"particles at the end (wrapped into the box), and whether each left its starting vortex cell"});
    for (std::size_t i = 0; i < n; ++i) f.row({static_cast<double>(i), p.x[i], p.y[i], p.vx[i], p.vy[i], static_cast<double>(crossed[i])});
  }
  return r;
}

}  // namespace cdm::verification::runners
