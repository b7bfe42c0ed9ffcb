/// @file hertz_restitution.cpp
/// @brief Restitution of the Hertz contact: for each e_n in options.en, a sphere hits a
/// wall at the variant's speed with no gravity; the rebound/incident speed ratio is
/// compared with the e_n asked for, and with the restitution CVODE finds for the α the
/// solver chose (the damping formula's own departure from e_n is reported beside it).
#include <map>
#include <mutex>

#include "cdm/oracles/hertz_impact.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

namespace {

/// The restitution of the damping @p alpha, solved once per value (the harness calls a
/// runner repeatedly to time it; the oracle does not change).
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

}  // namespace

RunOutput hertz_restitution(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const std::vector<double> ens = numbers_in(c, "en");
  const double speed = v.param("speed");
  RunOutput r;
  double e_req = 0.0, e_ode = 0.0, e_model = 0.0;
  std::vector<std::vector<double>> rows;
  oracles::OracleAccuracy acc;
  for (double en : ens) {
    const SceneSpec spec = scene_for(v, rc, {{"contacts[0].en", num(en)}});
    Simulation sim(spec);
    run_impact(c, sim, "en = " + num(en), r);
    const double e_dem = sim.particles().vy[0] / speed;  // moving up again, incident speed `speed`
    const PairParams& pp = spec.pairs.get(sim.particles().material[0], spec.walls.at(0).material);
    const double e_alpha = cached_restitution(pp.hertz_alpha, acc);
    e_req = std::max(e_req, rel_pct(en, e_dem));
    e_ode = std::max(e_ode, rel_pct(e_alpha, e_dem));
    e_model = std::max(e_model, rel_pct(en, e_alpha));
    rows.push_back({en, pp.hertz_alpha, e_dem, e_alpha});
  }
  r.particles = 1;
  r.oracle_accuracy = accuracy_text(acc);
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

}  // namespace cdm::verification::runners
