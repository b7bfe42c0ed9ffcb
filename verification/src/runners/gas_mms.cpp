/// @file gas_mms.cpp
/// @brief The gas solver against manufactured solutions (gas_mms.hpp): the exact fields
/// at t = 0, the oracle's sources added every step, the error at the end on four grids.
/// dt = C h²/N keeps the first-order time error below the second-order space error.
#include <algorithm>
#include <cmath>

#include "cdm/oracles/gas_mms.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

RunOutput gas_mms(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  oracles::GasMmsParams q;
  q.u0 = v.param("u0");
  q.v0 = v.param("v0");
  q.p0 = v.param("p0");
  q.a = v.param("a");
  q.b = v.param("b");
  q.rho = v.param("rho");
  q.mu = v.param("mu");
  const double h = v.h, dt = v.param("dt_per_h2") * h * h / rc.dt_divisor;
  const SceneSpec spec = variant_scene(v, {{"gas.dt", num(dt)}, {"integrator.dt", num(dt)}});
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

}  // namespace cdm::verification::runners
