/// @file packed_bed.cpp
/// @brief Gas through a fixed packing, periodic: a mean pressure gradient G drives the
/// gas; the superficial velocity U it reaches is measured and G compared with Ergun's
/// gradient at U and the packing's own gas fraction, and with the drag law's own.
/// dt = gas dt/N.
#include <cmath>

#include "cdm/oracles/packed_bed.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

RunOutput packed_bed(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  const double G = v.param("G");
  const std::vector<SceneOverride> gradient{{"gas.mean_pressure_gradient", "[0.0, " + num(-G) + ", 0.0]"}};
  const SceneSpec spec = scene_with_dt(v, rc, variant_scene(v, gradient).gas_dt / rc.dt_divisor, gradient);
  Simulation sim(spec);
  const fluid::GasField& gas = *sim.gas();
  const fluid::StaggeredGrid& g = gas.grid();
  // Superficial velocity: the mean of eps_f v over the y faces.
  auto superficial = [&]() { return y_face_sums(gas).flux / static_cast<double>(g.cell_count()); };
  std::vector<double> t, us;
  RunOutput r = run_timed(sim, [&](const Simulation& s2) {
    t.push_back(s2.time());
    us.push_back(superficial());
  });
  if (rc.timing_only) return r;
  const double box = g.length(0) * g.length(1) * g.length(2), eps_bed = 1.0 - solids_volume(sim.particles()) / box;
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

}  // namespace cdm::verification::runners
