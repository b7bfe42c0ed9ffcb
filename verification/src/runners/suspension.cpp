/// @file suspension.cpp
/// @brief A homogeneous suspension in a periodic box: mean gas and particle velocities
/// along gravity against the two-way mean-velocity equations (suspension.hpp, CVODE), the
/// slip at the end against the drag law's steady slip, and the mixture momentum.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "cdm/oracles/suspension.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

RunOutput suspension(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  // Gas step = particle step = T/N: the explicit exchange converges as dt falls below the
  // gas's drag relaxation time.
  const double dt = v.param("time_scale") / rc.dt_divisor;
  const SceneSpec spec = scene_with_dt(v, rc, dt, {{"gas.dt", num(dt)}});
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
    const double vp = momentum_y(p);
    // Gas: mass-weighted mean of the interstitial velocity on the y faces.
    const FaceSums f = y_face_sums(gas);
    t.push_back(s.time());
    U.push_back(f.flux / f.eps);
    V.push_back(vp / mass_p);
    M.push_back((rho_g * f.flux * g.cell_volume() + vp) / box);  // mixture momentum per volume
  });
  if (rc.timing_only) return r;
  oracles::SuspensionParams q;
  q.law = oracles::DragLaw::WenYu;
  set_particle_gas(q, v);
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

}  // namespace cdm::verification::runners
