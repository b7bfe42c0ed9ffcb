#include "cdm/solver/io/thermo_log.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/io/layers.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

int flow_axis(const Simulation& sim) {
  const fluid::StaggeredGrid& g = sim.gas()->grid();
  for (int a = 0; a < g.dims(); ++a)
    for (int side = 0; side < 2; ++side) {
      const fluid::BoundaryKind k = g.spec().faces[2 * a + side].kind;
      if (k == fluid::BoundaryKind::velocity_inlet || k == fluid::BoundaryKind::pressure_outlet) return a;
    }
  const Vec3 gv = sim.spec().gravity ? sim.spec().g : Vec3{};
  const double c[3] = {std::abs(gv.x), std::abs(gv.y), std::abs(gv.z)};
  if (c[0] == 0.0 && c[1] == 0.0 && c[2] == 0.0) return 1;
  return static_cast<int>(std::max_element(c, c + 3) - c);
}

ThermoSample thermo_sample(const Simulation& sim) {
  ThermoSample s;
  const ParticleStore& p = sim.particles();
  s.time = sim.time();
  s.step = sim.steps();
  s.particles = p.size();
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.inv_mass[i] > 0.0) s.kinetic_translational += 0.5 * p.mass[i] * dot(p.velocity(i), p.velocity(i));
    if (p.has_rotation() && p.inv_inertia[i] > 0.0)
      s.kinetic_rotational += 0.5 / p.inv_inertia[i] * dot(p.angular_velocity(i), p.angular_velocity(i));
  }
  if (const ContactModule* c = sim.contact()) {
    // Each process its own pairs (where they share the list), added up.
    const VerletList& list = c->list();
    const PeriodicBox& box = list.periodic_box();
    const auto [k0, k1] = list.own_pairs();
    std::uint64_t pairs = 0;
    double worst = 0.0;
    for (std::size_t n = k0; n < k1; ++n) {
      const std::size_t i = list.pair_i()[n], j = list.pair_j()[n];
      const Vec3 d = box.min_image(p.position(j) - p.position(i));
      const double overlap = p.radius[i] + p.radius[j] - norm(d);
      if (overlap <= 0.0) continue;
      ++pairs;
      worst = std::max(worst, overlap / std::min(p.radius[i], p.radius[j]));
    }
    s.contacts += sim.rank_sum(pairs);
    s.max_overlap_ratio = std::max(s.max_overlap_ratio, sim.rank_max(worst));
    for (const Wall& w : c->walls())
      for (std::size_t i = 0; i < p.size(); ++i) {
        const double overlap = p.radius[i] - w.gap(p.position(i), p.radius[i]).gap;
        if (overlap <= 0.0) continue;
        ++s.contacts;
        s.max_overlap_ratio = std::max(s.max_overlap_ratio, overlap / p.radius[i]);
      }
    // Mesh contacts as the last force evaluation found them (one per touching region).
    if (const MeshContacts* m = c->meshes())
      for (const MeshContacts::Contact& mc : m->contacts()) {
        ++s.contacts;
        s.max_overlap_ratio = std::max(s.max_overlap_ratio, mc.overlap / p.radius[mc.particle]);
      }
  }
  if (const fluid::GasField* gas = sim.gas(); gas && gas->has_pressure()) {
    s.has_gas = true;
    const int a = flow_axis(sim);
    const fluid::StaggeredGrid& g = gas->grid();
    s.pressure_drop = layer_mean(g, gas->p, a, 0) - layer_mean(g, gas->p, a, g.n(a) - 1);
    if (const fluid::GasSolver* solver = sim.gas_solver()) s.max_courant = solver->max_cfl(sim.spec().gas_dt);
  }
  return s;
}

namespace {

std::vector<std::string> thermo_columns(bool gas) {
  std::vector<std::string> c = {"t[s]", "step[-]", "ke_trans[J]", "ke_rot[J]", "contacts[-]", "max_overlap/r[-]",
                                "particles[-]"};
  if (gas) c.insert(c.end(), {"pressure_drop[Pa]", "max_courant[-]"});
  return c;
}

}  // namespace

ThermoLogObserver::ThermoLogObserver(const std::string& path, const Simulation& sim,
                                     std::optional<std::uint64_t> resume_at)
    : SampledTable(path, sim, sim.spec().log_interval, thermo_columns(sim.gas() && sim.gas()->has_pressure()),
                   {"cdm run log: scene " + sim.spec().file + "; pressure_drop: mean pressure of the first cell layer "
                    "minus the last along axis " + std::string(1, "xyz"[sim.gas() ? flow_axis(sim) : 1])},
                   resume_at) {}

std::string thermo_line(const ThermoSample& s) {
  char b[320];
  int n = std::snprintf(b, sizeof b, "t %-11.5g step %-10llu KE %-11.4g KE_rot %-11.4g contacts %-8llu overlap/r %-9.3g",
                        s.time, static_cast<unsigned long long>(s.step), s.kinetic_translational,
                        s.kinetic_rotational, static_cast<unsigned long long>(s.contacts), s.max_overlap_ratio);
  if (s.has_gas && n > 0 && n < static_cast<int>(sizeof b))
    std::snprintf(b + n, sizeof b - static_cast<std::size_t>(n), " dp %-11.5g Co %.3g", s.pressure_drop, s.max_courant);
  return b;
}

std::optional<ThermoSample> ThermoLogObserver::operator()(const Simulation& sim) {
  if (!schedule_.due(sim)) return std::nullopt;
  const ThermoSample s = thermo_sample(sim);
  std::vector<double> r = {s.time, static_cast<double>(s.step), s.kinetic_translational, s.kinetic_rotational,
                           static_cast<double>(s.contacts), s.max_overlap_ratio, static_cast<double>(s.particles)};
  if (s.has_gas) r.insert(r.end(), {s.pressure_drop, s.max_courant});
  table_.row(r);
  return s;
}

}  // namespace cdm
