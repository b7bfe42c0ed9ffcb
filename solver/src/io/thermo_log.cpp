#include "cdm/solver/io/thermo_log.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/io/counted_sums.hpp"
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
  // Each process its own particles and pairs (where they share them), added up.
  const ParticleStore& p = sim.local_particles();
  s.time = sim.time();
  s.step = sim.steps();
  s.particles = p.size();
  const std::vector<double> ke = counted_sums(sim, 2, [&](std::size_t i, auto&& add) {
    if (p.inv_mass[i] > 0.0) add(0, 0.5 * p.mass[i] * dot(p.velocity(i), p.velocity(i)));
    if (p.has_rotation() && p.inv_inertia[i] > 0.0)
      add(1, 0.5 / p.inv_inertia[i] * dot(p.angular_velocity(i), p.angular_velocity(i)));
  });
  s.kinetic_translational = ke[0];
  s.kinetic_rotational = ke[1];
  if (const ContactModule* c = sim.contact()) {
    const VerletList& list = c->list();
    const PeriodicBox& box = list.periodic_box();
    const auto [k0, k1] = list.own_pairs();
    std::uint64_t contacts = 0;
    double worst = 0.0;
    auto touch = [&](double overlap, double r) {
      if (overlap <= 0.0) return;
      ++contacts;
      worst = std::max(worst, overlap / r);
    };
    for (std::size_t n = k0; n < k1; ++n) {
      const std::size_t i = list.pair_i()[n], j = list.pair_j()[n];
      const Vec3 d = box.min_image(p.position(j) - p.position(i));
      touch(p.radius[i] + p.radius[j] - norm(d), std::min(p.radius[i], p.radius[j]));
    }
    const auto runs = sim.counted_runs();
    const std::vector<Wall>& walls = c->walls();
    auto wall_touch = [&](std::size_t i, std::size_t w) {
      touch(p.radius[i] - walls[w].gap(p.position(i), p.radius[i]).gap, p.radius[i]);
    };
    if (list.listed(p.size()) && list.wall_entries_current()) {
      // Only the list's wall candidates can touch a wall before the next build.
      const std::vector<std::uint32_t>& cand = list.wall_candidates();
      for (const auto& run : runs)
        for (auto k = static_cast<std::size_t>(std::lower_bound(cand.begin(), cand.end(), run.first) - cand.begin());
             k < cand.size() && cand[k] < run.second; ++k)
          for (std::uint32_t q = list.wall_begin()[k]; q < list.wall_begin()[k + 1]; ++q)
            wall_touch(cand[k], list.wall_ids()[q]);
    } else {
      for (const auto& run : runs)
        for (std::size_t i = run.first; i < run.second; ++i)
          for (std::size_t w = 0; w < walls.size(); ++w) wall_touch(i, w);
    }
    // Mesh contacts as the last force evaluation found them (one per touching region),
    // of the counted particles: a process's list may hold others' since the last gather.
    if (const MeshContacts* m = c->meshes()) {
      std::vector<std::uint8_t> counted(p.size(), 0);
      for (const auto& run : runs) std::fill(counted.begin() + run.first, counted.begin() + run.second, 1);
      for (const MeshContacts::Contact& mc : m->contacts())
        if (counted[mc.particle]) touch(mc.overlap, p.radius[mc.particle]);
    }
    s.contacts = sim.rank_sum(contacts);
    s.max_overlap_ratio = sim.rank_max(worst);
  }
  if (const fluid::GasField* gas = sim.gas(); gas && gas->has_pressure()) {
    s.has_gas = true;
    const int a = flow_axis(sim);
    const fluid::StaggeredGrid& g = gas->grid();
    const fluid::PlaneShare& share = sim.gas_planes();
    s.pressure_drop = layer_mean(g, share, gas->p, a, 0) - layer_mean(g, share, gas->p, a, g.n(a) - 1);
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
