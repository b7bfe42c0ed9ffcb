/// @file free_fall.cpp
/// @brief Free fall onto a wall (Garg et al. 2012 §3.1, App. B).
/// y: centre height over the whole run against the three-stage analytic solution.
/// With options.apex_bounces = K: the maximum height of each of the first K rebounds
/// against the exact soft-sphere apex (App. B) and the hard-sphere h_max,k (Fig 5).
#include <cmath>
#include <limits>

#include "cdm/oracles/free_fall.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

namespace {

/// The highest sample of each flight that follows a contact (contact: y below the radius).
std::vector<double> dem_apexes(const std::vector<double>& t, const std::vector<double>& y,
                               const std::vector<double>& vy, double radius) {
  std::vector<double> apex;
  bool was_contact = false, in_flight = false;
  double best = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    const bool contact = y[k] < radius;
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
  return apex;
}

/// The first K rebounds against the soft-sphere and hard-sphere apexes.
void compare_apexes(const oracles::FreeFall& oracle, const oracles::FreeFallParams& p, int K,
                    const std::vector<double>& apex, const RunConfig& rc, RunOutput& r) {
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
  if (rc.series_path.empty()) return;
  TableWriter w(series_beside(rc.series_path, "_apex"),
                {"bounce[-]", "apex[m]", "apex_soft_oracle[m]", "apex_hard_sphere[m]"},
                {"maximum centre height after each bounce: cdm, exact soft-sphere (App. B), hard sphere (Fig 5)"});
  for (const auto& row : rows) w.row(row);
}

}  // namespace

RunOutput free_fall(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const SceneSpec spec = scene_for(v, rc);
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
                  {series_title("free fall", v, rc, r.dt)});
    for (std::size_t k = 0; k < t.size(); ++k) w.row({t[k], y[k], ya[k], vy[k], va[k]});
  }

  auto it = c.options.find("apex_bounces");
  if (it != c.options.end()) compare_apexes(oracle, p, std::stoi(it->second), dem_apexes(t, y, vy, p.radius), rc, r);
  return r;
}

}  // namespace cdm::verification::runners
