#pragma once
/// @file support.hpp
/// @brief What every case runner needs: the scene of a sweep point, a timed run, the
/// relative error, the text that names an oracle's accuracy, number formats for scene
/// overrides and table headers, the case's options, and the names of companion series.
#include <chrono>
#include <string>
#include <vector>

#include "cdm/oracles/tolerance.hpp"
#include "cdm/solver/simulation.hpp"
#include "cdm/verification/harness.hpp"

namespace cdm::verification::runners {

/// The oracle's method and tolerances as one word for the tables, e.g. "cvode(rtol=1e-10,atol=1e-14)".
std::string accuracy_text(const oracles::OracleAccuracy& a);

/// 100 |ref - val| / |ref|: the relative error in per cent.
double rel_pct(double ref, double val);

/// @p v in "%.17g": a number exact enough for a scene override or a header.
std::string num(double v);
/// A vector as a TOML array in "%.17g", for a scene override.
std::string vec(double x, double y, double z);

/// The variant's scene with its overrides and @p extra, without particle output.
SceneSpec variant_scene(const Variant& v, const std::vector<SceneOverride>& extra = {});
/// The variant's scene with @p extra, the sweep point's integrator and dt = t_col/divisor.
SceneSpec scene_for(const Variant& v, const RunConfig& rc, const std::vector<SceneOverride>& extra = {});
/// The variant's scene with @p extra, the sweep point's integrator and the step @p dt.
SceneSpec scene_with_dt(const Variant& v, const RunConfig& rc, double dt, const std::vector<SceneOverride>& extra = {});

/// Solver wall time on the steady clock, from construction.
class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

/// The run's counts (steps, particles, dt) and its wall time.
RunOutput run_output(const Simulation& sim, double wall_seconds);

/// Run to end_time, calling @p record after every step (and at t = 0); time the solver.
template <class F>
RunOutput run_timed(Simulation& sim, F&& record) {
  const Stopwatch clock;
  sim.run([&](const Simulation& s) { record(s); });
  return run_output(sim, clock.seconds());
}

/// Runs one impact of a runner that sweeps a parameter over several runs: adds its wall
/// time and steps to @p r and keeps its dt. Throws, naming the case and @p what (the swept
/// value), if a contact is still open at the end.
void run_impact(const CaseDef& c, Simulation& sim, const std::string& what, RunOutput& r);

/// Whether case.toml sets options.@p key to @p value.
bool option_is(const CaseDef& c, const std::string& key, const std::string& value);
/// The numbers listed in options.@p key (a string such as "0.3 0.5 0.9"); throws naming
/// the case and key if the option is missing or lists none.
std::vector<double> numbers_in(const CaseDef& c, const std::string& key);

/// The first line of a series' header: "<what> <variant>, <integrator>, dt = <dt> s".
std::string series_title(const std::string& what, const Variant& v, const RunConfig& rc, double dt);
/// A companion series beside @p series_path: "<stem>@p suffix.dat".
std::string series_beside(const std::string& series_path, const std::string& suffix);

/// Sets the particle and gas properties that the drag oracles' parameters share (d, rho_p,
/// rho_g, mu_g) from the variant's parameters of the same names.
template <class P>
void set_particle_gas(P& p, const Variant& v) {
  p.d = v.param("d");
  p.rho_p = v.param("rho_p");
  p.rho_g = v.param("rho_g");
  p.mu_g = v.param("mu_g");
}

/// Volume of the particles' spheres [m³].
double solids_volume(const ParticleStore& p);
/// The particles' momentum along y, Σ m v_y [kg m/s].
double momentum_y(const ParticleStore& p);
/// The gas's force on the particles along y [N]: the drag the solver last gave them
/// (two-way coupling, explicit update: dfy) and the pressure-gradient force −V_p ∂p/∂y,
/// with ∂p/∂y as the particles take it (@p kernel: the two-way deposition,
/// coupling::particle_pressure_gradient).
double gas_force_y(const ParticleStore& p, const fluid::GasField& gas, const coupling::Deposition* kernel);

/// Sums over the gas's y faces of the face gas fraction times v (@c flux) and of the face
/// gas fraction (@c eps); the face fraction is the mean of the two cells beside the face.
struct FaceSums {
  double flux = 0.0, eps = 0.0;
};
FaceSums y_face_sums(const fluid::GasField& gas);

}  // namespace cdm::verification::runners
