/// @file support.cpp
/// @brief What every case runner needs (support.hpp).
#include "support.hpp"

#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <stdexcept>

namespace cdm::verification::runners {

std::string accuracy_text(const oracles::OracleAccuracy& a) {
  char b[160];
  std::snprintf(b, sizeof b, "%s(rtol=%.0e,atol=%.0e)", a.method.c_str(), a.rtol, a.atol);
  std::string s = b;
  for (auto& ch : s)
    if (ch == ' ') ch = '_';
  return s;
}

double rel_pct(double ref, double val) { return 100.0 * std::abs(ref - val) / std::abs(ref); }

std::string num(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string vec(double x, double y, double z) {
  char b[128];
  std::snprintf(b, sizeof b, "[%.17g, %.17g, %.17g]", x, y, z);
  return b;
}

SceneSpec variant_scene(const Variant& v, const std::vector<SceneOverride>& extra) {
  std::vector<SceneOverride> ov = v.set;
  ov.insert(ov.end(), extra.begin(), extra.end());
  SceneSpec s = load_scene(v.scene, ov);
  s.output_particles = false;
  return s;
}

namespace {
/// @p extra, then the sweep point's integrator.
std::vector<SceneOverride> with_integrator(const RunConfig& rc, std::vector<SceneOverride> extra) {
  extra.push_back({"integrator.scheme", "\"" + rc.integrator + "\""});
  return extra;
}
}  // namespace

SceneSpec scene_for(const Variant& v, const RunConfig& rc, const std::vector<SceneOverride>& extra) {
  std::vector<SceneOverride> ov = with_integrator(rc, extra);
  ov.push_back({"integrator.dt", "\"auto\""});
  ov.push_back({"integrator.dt_divisor", num(rc.dt_divisor)});
  return variant_scene(v, ov);
}

SceneSpec scene_with_dt(const Variant& v, const RunConfig& rc, double dt, const std::vector<SceneOverride>& extra) {
  std::vector<SceneOverride> ov = with_integrator(rc, extra);
  ov.push_back({"integrator.dt", num(dt)});
  return variant_scene(v, ov);
}

RunOutput run_output(const Simulation& sim, double wall_seconds) {
  RunOutput r;
  r.wall_seconds = wall_seconds;
  r.steps = sim.steps();
  r.particles = sim.particles().size();
  r.dt = sim.dt();
  return r;
}

void run_impact(const CaseDef& c, Simulation& sim, const std::string& what, RunOutput& r) {
  const Stopwatch clock;
  sim.run();
  r.wall_seconds += clock.seconds();
  r.steps += sim.steps();
  r.dt = sim.dt();
  if (sim.contact()->active_contacts() != 0)
    throw std::runtime_error(c.name + ": the sphere is still in contact at the end (" + what + ")");
}

bool option_is(const CaseDef& c, const std::string& key, const std::string& value) {
  auto it = c.options.find(key);
  return it != c.options.end() && it->second == value;
}

std::vector<double> numbers_in(const CaseDef& c, const std::string& key) {
  auto it = c.options.find(key);
  if (it == c.options.end()) throw std::runtime_error(c.name + ": case.toml needs options." + key);
  std::istringstream is(it->second);
  std::vector<double> out;
  for (double x; is >> x;) out.push_back(x);
  if (out.empty()) throw std::runtime_error(c.name + ": options." + key + " lists no numbers");
  return out;
}

std::string series_title(const std::string& what, const Variant& v, const RunConfig& rc, double dt) {
  return what + " " + v.name + ", " + rc.integrator + ", dt = " + std::to_string(dt) + " s";
}

std::string series_beside(const std::string& series_path, const std::string& suffix) {
  std::string p = series_path;
  p.insert(p.size() - 4, suffix);
  return p;
}

namespace {
double sphere_volume(double r) { return std::numbers::pi * std::pow(2.0 * r, 3) / 6.0; }
}  // namespace

double solids_volume(const ParticleStore& p) {
  double vol = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) vol += sphere_volume(p.radius[i]);
  return vol;
}

double gas_force_y(const ParticleStore& p, const fluid::GasField& gas, const coupling::Deposition* kernel) {
  double f = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i)
    f += p.dfy[i] - sphere_volume(p.radius[i]) * coupling::particle_pressure_gradient(gas, kernel, p.position(i)).y;
  return f;
}

double momentum_y(const ParticleStore& p) {
  double m = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) m += p.mass[i] * p.vy[i];
  return m;
}

FaceSums y_face_sums(const fluid::GasField& gas) {
  const fluid::StaggeredGrid& g = gas.grid();
  FaceSums s;
  for (int k = 0; k < g.n(2); ++k)
    for (int j = 0; j < g.n(1); ++j)
      for (int i = 0; i < g.n(0); ++i) {
        const double ef = 0.5 * (gas.eps_g[g.at(i, j - 1, k)] + gas.eps_g[g.at(i, j, k)]);
        s.flux += ef * gas.v[g.at(i, j, k)];
        s.eps += ef;
      }
  return s;
}

}  // namespace cdm::verification::runners
