/// @file population_balance.cpp
/// @brief Particles inserted and removed over a run (solver population.hpp).
///
/// population_balance: at every step, what is in the domain against what the run started
/// with, plus what every insertion added, less what every outlet removed: the counts
/// exactly, the masses to the rounding of their sums. Each insertion's tally against its
/// schedule, restated here from the scene (population.hpp's contract): at the first step
/// whose time reaches start + k·interval, a count rate has inserted exactly
/// ⌊rate·(min(t, end) − start)⌋ particles, a mass rate at least rate·(min(t, end) − start)
/// and less than that plus the heaviest particle it can draw, neither beyond its total.
/// And after every step no centre is left in an outlet.
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "cdm/solver/output.hpp"
#include "cdm/solver/population.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

RunOutput population_balance(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  Simulation sim(scene_for(v, rc));
  const SceneSpec& spec = sim.spec();
  if (spec.insertions.empty() || spec.outlets.empty())
    throw std::runtime_error(c.name + ": population_balance needs [[insertions]] and [[outlets]]");
  const ParticleStore& p = sim.particles();
  const double n0 = static_cast<double>(p.size());
  double m0 = 0.0;
  for (double m : p.mass) m0 += m;

  struct Schedule {
    long long k = -1;         // the last event seen
    double heaviest = 0.0;    // [kg]
  };
  std::vector<Schedule> sched(spec.insertions.size());
  for (std::size_t q = 0; q < sched.size(); ++q) {
    const InsertionSpec& in = spec.insertions[q];
    const double r = in.size.kind == SizeKind::fixed ? in.size.radius : in.size.largest();
    sched[q].heaviest = spec.materials[static_cast<std::size_t>(in.material)].density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  }

  double count_err = 0.0, mass_err = 0.0, count_sched = 0.0, mass_deficit = 0.0, mass_lead = 0.0, left = 0.0;
  double peak_in_domain = 0.0;
  struct Row {
    double t, n, m, n_in, m_in, n_out, m_out;
  };
  std::vector<Row> rows;  // every 100th step, for the series
  Row last{};
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    const Population& pop = *s.population();
    double n_in = 0.0, m_in = 0.0, n_out = 0.0, m_out = 0.0;
    for (const auto& t : pop.inserted()) { n_in += static_cast<double>(t.count); m_in += t.mass; }
    for (const auto& t : pop.removed()) { n_out += static_cast<double>(t.count); m_out += t.mass; }
    double m = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      m += p.mass[i];
      for (const OutletSpec& o : spec.outlets) left += o.removes(p.position(i)) ? 1.0 : 0.0;
    }
    const double n = static_cast<double>(p.size());
    count_err = std::max(count_err, std::abs(n - (n0 + n_in - n_out)));
    mass_err = std::max(mass_err, std::abs(m - (m0 + m_in - m_out)) / (m0 + m_in));
    peak_in_domain = std::max(peak_in_domain, n - n0);
    const double t = s.time();
    for (std::size_t q = 0; q < sched.size(); ++q) {
      const InsertionSpec& in = spec.insertions[q];
      if (t < in.start) continue;
      const long long k = in.interval > 0.0 ? static_cast<long long>(std::floor((t - in.start) / in.interval + 1e-9))
                                            : static_cast<long long>(s.steps());
      if (k == sched[q].k) continue;
      sched[q].k = k;
      const double owed = in.rate * (std::min(t, in.end) - in.start);
      const Population::Tally& got = pop.inserted()[q];
      if (!in.rate_by_mass) {
        const double target = std::min(std::floor(owed), in.total_by_mass ? std::numeric_limits<double>::infinity() : in.total);
        count_sched = std::max(count_sched, std::abs(static_cast<double>(got.count) - target));
      } else {
        const double target = std::min(owed, in.total_by_mass ? in.total : std::numeric_limits<double>::infinity());
        mass_deficit = std::max(mass_deficit, (target - got.mass) / sched[q].heaviest);
        mass_lead = std::max(mass_lead, (got.mass - target) / sched[q].heaviest);
      }
    }
    last = {t, n, m, n_in, m_in, n_out, m_out};
    if (!rc.series_path.empty() && s.steps() % 100 == 0) rows.push_back(last);
  });
  if (rc.timing_only) return r;
  const Population& pop = *sim.population();
  double removed = 0.0;
  for (const auto& t : pop.removed()) removed += static_cast<double>(t.count);
  r.oracle_accuracy = "exact(balance and schedule restated from the scene)";
  r.measurements.push_back({"count_balance", "max_abs", count_err});
  r.measurements.push_back({"mass_balance", "max_rel", mass_err});
  r.measurements.push_back({"count_schedule", "max_abs", count_sched});
  r.measurements.push_back({"mass_schedule_deficit", "max_of_heaviest", mass_deficit});
  r.measurements.push_back({"mass_schedule_lead", "max_of_heaviest", mass_lead});
  r.measurements.push_back({"centres_left_in_outlets", "count", left});
  r.measurements.push_back({"jammed_events", "count", static_cast<double>(pop.jammed_events())});
  r.measurements.push_back({"removed", "count", removed});
  r.measurements.push_back({"peak_inserted_in_domain", "count", peak_in_domain});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path,
                  {"t[s]", "in_domain[-]", "mass_in_domain[kg]", "inserted[-]", "mass_inserted[kg]", "removed[-]",
                   "mass_removed[kg]"},
                  {series_title("population balance", v, rc, r.dt)});
    w.set_integer_columns({false, true, false, true, false, true, false});
    // Every 100th step and the last: the balance holds at each, the series is for plots.
    if (rows.empty() || rows.back().t != last.t) rows.push_back(last);
    for (const Row& x : rows) w.row({x.t, x.n, x.m, x.n_in, x.m_in, x.n_out, x.m_out});
  }
  return r;
}

}  // namespace cdm::verification::runners
