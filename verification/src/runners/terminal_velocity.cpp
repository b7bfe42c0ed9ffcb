/// @file terminal_velocity.cpp
/// @brief A particle falling through an upward gas stream (Garg et al. 2012 §3.6, eq 48,
/// Fig 15), through a frozen gas (kind terminal_velocity) or a solved gas that receives
/// the drag reaction (terminal_velocity_coupled). Both compare v(t) with CVODE on eq 48
/// and the final velocity with the terminal velocity from the force balance (GSL root).
#include <algorithm>
#include <cmath>

#include "cdm/oracles/terminal_velocity.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

namespace {

/// The fall's velocity record and its oracles: the ODE at the recorded times and the
/// terminal state.
struct Fall {
  std::vector<double> t, vy;
  oracles::TerminalSeries ode;
  oracles::TerminalState terminal;
};

/// Records the particle's vertical velocity after every step; @p also sees every step.
template <class F>
RunOutput record_fall(Simulation& sim, Fall& fall, F&& also) {
  return run_timed(sim, [&](const Simulation& s) {
    fall.t.push_back(s.time());
    fall.vy.push_back(s.particles().vy[0]);
    also(s);
  });
}

/// Solves the oracles for the variant and adds the velocity error over the run, the final
/// velocity against the ODE (with @p vs_ode) and against the terminal velocity.
void compare_fall(const Variant& v, Fall& fall, bool vs_ode, RunOutput& r) {
  oracles::TerminalParams p;
  set_particle_gas(p, v);
  p.u_g = v.param("u_g");
  p.g = v.param("g");
  fall.ode = oracles::terminal_velocity_cvode(p, fall.t);
  fall.terminal = oracles::terminal_velocity(p);
  r.oracle_accuracy = accuracy_text(fall.ode.accuracy);
  const double vt = std::abs(fall.terminal.velocity);
  double e = 0.0;
  for (std::size_t k = 0; k < fall.t.size(); ++k) e = std::max(e, std::abs(fall.vy[k] - fall.ode.v[k]));
  r.measurements.push_back({"v", "max_abs_pct_of_terminal", 100.0 * e / vt});
  if (vs_ode) r.measurements.push_back({"v_end", "rel_pct_vs_ode", rel_pct(fall.ode.v.back(), fall.vy.back())});
  r.measurements.push_back({"v_end", "rel_pct_vs_terminal", rel_pct(fall.terminal.velocity, fall.vy.back())});
}

void write_fall(const std::string& path, const Fall& fall, const std::string& title) {
  if (path.empty()) return;
  TableWriter w(path, {"t[s]", "vy[m/s]", "vy_oracle[m/s]", "v_terminal[m/s]"}, {title});
  for (std::size_t k = 0; k < fall.t.size(); ++k) w.row({fall.t[k], fall.vy[k], fall.ode.v[k], fall.terminal.velocity});
}

}  // namespace

/// Frozen gas: dt = time_scale/N.
RunOutput terminal_velocity(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  const SceneSpec spec = scene_with_dt(v, rc, v.param("time_scale") / rc.dt_divisor);
  Simulation sim(spec);
  Fall fall;
  RunOutput r = record_fall(sim, fall, [](const Simulation&) {});
  if (rc.timing_only) return r;  // a repeat for timing: no oracle, no tables
  compare_fall(v, fall, true, r);
  write_fall(rc.series_path, fall,
             series_title("terminal velocity", v, rc, r.dt) + "; oracle: CVODE on Garg et al. eq 48; terminal from the force balance (slip " +
                 std::to_string(fall.terminal.slip) + " m/s)");
  return r;
}

/// Two-way coupled: dt = gas dt/N. The decoupled ODE stays the oracle (the self-induced gas
/// disturbance is a numerical artefact the coupling must keep small); the momentum balance
/// of every gas step compares what the gas received with what drag gave the particles.
RunOutput terminal_velocity_coupled(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  const SceneSpec spec = scene_with_dt(v, rc, variant_scene(v).gas_dt / rc.dt_divisor);
  Simulation sim(spec);
  Fall fall;
  double imbalance = 0.0, imbalance_cells = 0.0;
  RunOutput r = record_fall(sim, fall, [&](const Simulation& s) {
    if (s.steps() > 0 && s.steps() % s.substeps() == 0) {
      const auto& b = s.coupling_balance();
      const double mag = norm(b.particles);
      imbalance = std::max(imbalance, norm(b.particles + b.gas_faces) / mag);
      imbalance_cells = std::max(imbalance_cells, norm(b.particles + b.gas_cells) / mag);
    }
  });
  if (rc.timing_only) return r;
  compare_fall(v, fall, false, r);
  r.measurements.push_back({"momentum_exchange", "max_rel_imbalance_faces", imbalance});
  r.measurements.push_back({"momentum_exchange", "max_rel_imbalance_cells", imbalance_cells});
  write_fall(rc.series_path, fall,
             "terminal velocity, two-way coupled, " + v.name + ", " + rc.integrator + ", particle dt = " +
                 std::to_string(r.dt) + " s, gas dt = " + std::to_string(spec.gas_dt) +
                 " s; oracle: CVODE on Garg et al. eq 48 (uncoupled)");
  return r;
}

}  // namespace cdm::verification::runners
