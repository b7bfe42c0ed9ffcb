#include "cdm/solver/io/output_fields.hpp"

#include <array>
#include <cmath>

#include "cdm/solver/io/counted_sums.hpp"
#include "cdm/solver/simulation.hpp"

namespace cdm {

namespace {
/// A copy of the run's contacts that evaluates every contact on this process, so that
/// the run itself is not changed. Where the processes share the list, each holding its
/// slabs' pairs, the copy lists them all again, carrying the whole list's contacts held
/// for the output (Simulation::hold_contacts), unless @p pairs is false: the copy's pairs
/// are then this process's only, and only its wall contacts may be read.
ContactModule probe_of(const Simulation& sim, bool pairs = true) {
  ContactModule probe = *sim.contact();
  if (pairs && sim.shares_list()) probe.list().list_held_again();
  probe.set_ranks(nullptr);
  return probe;
}

/// The forces and torques (fx fy fz tx ty tz) @p probe's contacts give the run's own
/// particles. They are evaluated on the run's store with its force and torque arrays
/// set aside meanwhile (zeroed ones in their place) and put back before this returns or
/// throws: a copy of the store would cost its whole size (about 150 B a particle) at
/// every output. The observers hold the simulation const; its store is not, and only
/// these six arrays change hands.
std::array<std::vector<double>, 6> probe_forces(const ParticleStore& held, ContactModule& probe) {
  ParticleStore& p = const_cast<ParticleStore&>(held);
  const std::array<std::vector<double>*, 6> run = {&p.fx, &p.fy, &p.fz, &p.tx, &p.ty, &p.tz};
  std::array<std::vector<double>, 6> out;
  for (std::size_t a = 0; a < 6; ++a) out[a].assign(run[a]->size(), 0.0);
  auto trade = [&] {
    for (std::size_t a = 0; a < 6; ++a) run[a]->swap(out[a]);
  };
  trade();
  try {
    probe.add_forces(p, 0.0);
  } catch (...) {
    trade();
    throw;
  }
  trade();
  return out;
}
}  // namespace

std::vector<double> contact_forces(const Simulation& sim) {
  if (!sim.contact()) return {};
  const ParticleStore& p = sim.written_particles();
  ContactModule probe = probe_of(sim);
  const std::array<std::vector<double>, 6> fc = probe_forces(p, probe);
  std::vector<double> f(3 * p.size());
  for (std::size_t k = 0; k < p.size(); ++k) {
    const std::size_t s = p.slot_of(k);
    f[3 * k] = fc[0][s]; f[3 * k + 1] = fc[1][s]; f[3 * k + 2] = fc[2][s];
  }
  return f;
}

ContactNetwork contact_network(const Simulation& sim) {
  ContactNetwork net;
  if (!sim.contact()) return net;
  const ParticleStore& p = sim.written_particles();
  ContactModule probe = probe_of(sim);
  probe.set_recording(true);
  probe_forces(p, probe);
  const VerletList& list = probe.list();
  const std::vector<double>& fn = probe.pair_normal_force();
  const std::vector<double>& fv = probe.pair_force();
  for (std::size_t k = 0; k < list.size(); ++k) {
    if (fn[k] < 0.0) continue;
    const std::size_t i = list.pair_i()[k], j = list.pair_j()[k];
    net.pairs.push_back(static_cast<std::int64_t>(p.id_of(i)));
    net.pairs.push_back(static_cast<std::int64_t>(p.id_of(j)));
    for (int a = 0; a < 3; ++a) {
      net.normal.push_back(fv[6 * k + a] - fv[6 * k + 3 + a]);
      net.tangential.push_back(fv[6 * k + 3 + a]);
    }
    const Vec3 d = list.periodic_box().min_image(p.position(j) - p.position(i));
    net.overlap.push_back(p.radius[i] + p.radius[j] - norm(d));
  }
  return net;
}

std::vector<double> wall_forces(const Simulation& sim) {
  if (!sim.contact()) return {};
  // Each process evaluates the wall contacts on the state it holds and sums its own
  // particles' forces (Simulation::counted_runs); the sums are added up.
  const ParticleStore& p = sim.local_particles();
  ContactModule probe = probe_of(sim, false);
  probe.set_recording(true);
  probe_forces(p, probe);
  const VerletList& list = probe.list();
  const std::vector<double>& fn = probe.wall_normal_force();
  const std::vector<double>& fv = probe.wall_force();
  // A particle's entries name each wall once: one term per particle in each sum.
  return counted_sums(sim, 3 * probe.walls().size(), [&](std::size_t i, auto&& add) {
    const auto [q0, q1] = list.wall_entries(static_cast<std::uint32_t>(i));
    for (std::uint32_t q = q0; q < q1; ++q) {
      if (fn[q] < 0.0) continue;
      const std::size_t w = list.wall_ids()[q];
      for (std::size_t a = 0; a < 3; ++a) add(3 * w + a, fv[3 * q + a]);
    }
  });
}

std::vector<double> solids_velocity(const Simulation& sim) {
  const fluid::StaggeredGrid& g = sim.gas()->grid();
  const ParticleStore& p = sim.written_particles();
  const int n[3] = {g.n(0), g.n(1), g.n(2)};
  const std::size_t nc = g.cell_count();
  std::vector<double> mv(3 * nc, 0.0), vol(nc, 0.0);
  for (std::size_t s = 0; s < p.size(); ++s) {
    const Vec3 x = sim.gas()->wrap(p.position(s));
    const double c[3] = {x.x, x.y, x.z};
    std::size_t cell = 0, stride = 1;
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      // A 2D grid has one layer of cells whatever z is.
      const double q = a == 2 && g.two_d() ? 0.0 : std::floor((c[a] - g.lo(a)) / g.h(a));
      inside = inside && q >= 0.0 && q < n[a];  // false for NaN too
      cell += stride * (inside ? static_cast<std::size_t>(q) : 0);
      stride *= static_cast<std::size_t>(n[a]);
    }
    if (!inside) continue;
    // Weights r³: the volume up to a factor common to all particles.
    const double w = p.radius[s] * p.radius[s] * p.radius[s];
    vol[cell] += w;
    mv[3 * cell] += w * p.vx[s]; mv[3 * cell + 1] += w * p.vy[s]; mv[3 * cell + 2] += w * p.vz[s];
  }
  for (std::size_t c = 0; c < nc; ++c)
    if (vol[c] > 0.0)
      for (int a = 0; a < 3; ++a) mv[3 * c + a] /= vol[c];
  return mv;
}

}  // namespace cdm
