/// @file stacked.cpp
/// @brief Two stacked particles between two walls (Garg et al. 2012 §3.2, App. C):
/// both heights over the run against CVODE on the two-body equations.
#include <stdexcept>

#include "cdm/oracles/stacked.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

RunOutput stacked(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  const SceneSpec spec = scene_for(v, rc);
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
                {series_title("stacked particles", v, rc, r.dt)});
  for (std::size_t k = 0; k < t.size(); ++k) {
    e1 = std::max(e1, rel_pct(o.y1[k], y1[k]));
    e2 = std::max(e2, rel_pct(o.y2[k], y2[k]));
    w.row({t[k], y1[k], o.y1[k], y2[k], o.y2[k]});
  }
  r.measurements.push_back({"y1", "max_rel_pct", e1});
  r.measurements.push_back({"y2", "max_rel_pct", e2});
  return r;
}

}  // namespace cdm::verification::runners
