#include "cdm/solver/io/output_fields.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "cdm/solver/io/counted_sums.hpp"
#include "cdm/solver/simulation.hpp"
#include "cdm/solver/slot_pages.hpp"

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
/// set aside meanwhile (zeroed ones in their place, whose pages are committed only where
/// a contact writes) and put back before this returns or throws: a copy of the store
/// would cost its whole size (about 150 B a particle) at every output. The observers
/// hold the simulation const; its store is not, and only these six arrays change hands.
/// @p listed: the list as it stands (ContactModule::add_listed_forces), else updated.
std::array<std::vector<double>, 6> probe_forces(const ParticleStore& held, ContactModule& probe, bool listed = false) {
  ParticleStore& p = const_cast<ParticleStore&>(held);
  const std::array<std::vector<double>*, 6> run = {&p.fx, &p.fy, &p.fz, &p.tx, &p.ty, &p.tz};
  std::array<std::vector<double>, 6> out;
  for (std::size_t a = 0; a < 6; ++a) resize_zeroed(out[a], run[a]->size());
  auto trade = [&] {
    for (std::size_t a = 0; a < 6; ++a) run[a]->swap(out[a]);
  };
  trade();
  try {
    if (listed) probe.add_listed_forces(p);
    else probe.add_forces(p, 0.0);
  } catch (...) {
    trade();
    throw;
  }
  trade();
  return out;
}
}  // namespace

namespace {
/// Calls @p evaluate(p, run, true) with the run's own contact module evaluating its list
/// as it stands at @p p (Simulation::own_contacts_current), which it leaves as it was
/// (ContactModule::probe_listed, recording the force vectors with @p vectors).
template <class Evaluate>
void on_run_list(const Simulation& sim, const ParticleStore& p, bool vectors, Evaluate&& evaluate) {
  auto& run = const_cast<ContactModule&>(*sim.contact());  // put back as it was
  run.probe_listed(vectors, [&](ContactModule& probe) { evaluate(p, probe, true); });
}

/// Calls @p evaluate(p, probe, listed) with the state and the contact module a frame's
/// contacts are evaluated with, recording their forces (with @p vectors the force
/// vectors), and returns whether each process evaluated its own. It does where the
/// list stands as the step left it (Simulation::own_contacts_current): each process
/// evaluates its part of the run's own list, its ghosts brought to the frame's state,
/// leaving the run as it was (ContactModule::probe_listed; the same sums as one
/// process's). Otherwise the whole state and the whole list's contacts go to process 0,
/// where a copy of the module lists every pair again and evaluates them. A collective
/// call.
template <class Evaluate>
bool with_probe(const Simulation& sim, bool vectors, Evaluate&& evaluate) {
  if (sim.own_contacts_current()) {
    on_run_list(sim, sim.own_with_ghosts(), vectors, evaluate);
    return true;
  }
  const auto held = sim.hold_contacts();  // for the copy's list, from every process
  const ParticleStore& p = sim.written_particles();
  if (!sim.writes_rows()) return false;
  ContactModule probe = probe_of(sim);
  probe.set_recording(vectors);
  evaluate(p, probe, false);
  return false;
}

/// The contacts of @p probe's pairs at @p p (evaluated as probe_forces(@p listed) does,
/// recording the force vectors), in list order, but those of the shadow slab, which the
/// rank below writes.
ContactNetwork network_of(const ParticleStore& p, ContactModule& probe, bool listed) {
  ContactNetwork net;
  probe_forces(p, probe, listed);
  const VerletList& list = probe.list();
  const std::size_t shadow = list.shadow_slab();
  const std::size_t k0 = shadow == VerletList::no_slab ? 0 : list.slab_start()[shadow],
                    k1 = shadow == VerletList::no_slab ? 0 : list.slab_start()[shadow + 1];
  const std::vector<double>& fn = probe.pair_normal_force();
  const std::vector<double>& fv = probe.pair_force();
  for (std::size_t k = 0; k < list.size(); ++k) {
    if (fn[k] < 0.0 || (k >= k0 && k < k1)) continue;
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
}  // namespace

ContactForces contact_forces(const Simulation& sim) {
  ContactForces out;
  if (!sim.contact()) return out;
  out.from_owners = with_probe(sim, false, [&](const ParticleStore& p, ContactModule& probe, bool listed) {
    std::array<std::vector<double>, 6> fc = probe_forces(p, probe, listed);
    for (std::size_t a = 0; a < 3; ++a) out.f[a].swap(fc[a]);
  });
  return out;
}

ContactNetwork contact_network(const Simulation& sim) {
  ContactNetwork net;
  if (!sim.contact()) return net;
  const bool own = with_probe(sim, true, [&](const ParticleStore& p, ContactModule& probe, bool listed) {
    net = network_of(p, probe, listed);
  });
  net.from_owners = own;
  return net;
}

std::vector<double> wall_forces(const Simulation& sim) {
  if (!sim.contact()) return {};
  // Each process evaluates the wall contacts on the state it holds and sums its own
  // particles' forces (Simulation::counted_runs); the sums are added up. The run's module
  // does, as a frame's contacts (with_probe), where its list is current.
  const ParticleStore& p = sim.local_particles();
  std::vector<double> sums;
  auto sum_walls = [&](const ParticleStore&, ContactModule& probe, bool listed) {
    probe_forces(p, probe, listed);
    const VerletList& list = probe.list();
    const std::vector<double>& fn = probe.wall_normal_force();
    const std::vector<double>& fv = probe.wall_force();
    // A particle's entries name each wall once: one term per particle in each sum.
    sums = counted_sums(sim, 3 * probe.walls().size(), [&](std::size_t i, auto&& add) {
      const auto [q0, q1] = list.wall_entries(static_cast<std::uint32_t>(i));
      for (std::uint32_t q = q0; q < q1; ++q) {
        if (fn[q] < 0.0) continue;
        const std::size_t w = list.wall_ids()[q];
        for (std::size_t a = 0; a < 3; ++a) add(3 * w + a, fv[3 * q + a]);
      }
    });
  };
  if (sim.own_contacts_current()) {
    on_run_list(sim, p, true, sum_walls);
    return sums;
  }
  ContactModule probe = probe_of(sim, false);
  probe.set_recording(true);
  sum_walls(p, probe, false);
  return sums;
}

CellPlanes solids_velocity(const Simulation& sim, std::pair<int, int> planes) {
  const fluid::StaggeredGrid& g = sim.gas()->grid();
  const ParticleStore& p = sim.local_particles();
  const int n[3] = {g.n(0), g.n(1), g.n(2)};
  const auto plane = static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]);
  // Each process deposits its own particles (Simulation::counted_runs) into exact sums
  // (exact_sums.hpp) of one unit per quantity, from its largest term over the processes,
  // and the sums are added up: the same cells on any number of processes, without the
  // particles gathered.
  const auto runs = sim.counted_runs();
  auto each = [&](auto&& deposit) {
    for (const auto& [i0, i1] : runs)
      for (std::size_t s = i0; s < i1; ++s) {
        const Vec3 x = sim.gas()->wrap(p.position(s));
        const double c[3] = {x.x, x.y, x.z};
        int q[3] = {};
        bool inside = true;
        for (int a = 0; a < 3; ++a) {
          // A 2D grid has one layer of cells whatever z is.
          const double at = a == 2 && g.two_d() ? 0.0 : std::floor((c[a] - g.lo(a)) / g.h(a));
          inside = inside && at >= 0.0 && at < n[a];  // false for NaN too
          q[a] = inside ? static_cast<int>(at) : 0;
        }
        // Weights r³: the volume up to a factor common to all particles.
        if (inside) deposit(s, q, p.radius[s] * p.radius[s] * p.radius[s]);
      }
  };
  // The largest weight, weight times a velocity component, and whether some process's
  // particles lie beyond its reach of the gas's planes.
  const fluid::PlaneShare& share = sim.gas_planes();
  int k_lo = n[2], k_hi = -1;
  std::vector<double> largest(3, 0.0);
  each([&](std::size_t s, const int* q, double w) {
    largest[0] = std::max(largest[0], w);
    largest[1] = std::max(largest[1], w * std::max({std::abs(p.vx[s]), std::abs(p.vy[s]), std::abs(p.vz[s])}));
    k_lo = std::min(k_lo, q[2]);
    k_hi = std::max(k_hi, q[2]);
  });
  const bool by_planes = share.processes() > 1 && !share.reach_whole(n[2]);
  if (by_planes) largest[2] = share.within_reach(k_lo, k_hi, n[2]) ? 0.0 : 1.0;
  sim.rank_max(largest);
  // The planes of sums this process holds: its reach (every plane at a periodic end), or
  // every plane where some process's particles lie beyond its reach.
  const bool reach_only = by_planes && largest[2] == 0.0;
  const auto [base, end] = reach_only ? share.reach_of(share.rank(), n[2]) : std::pair{0, n[2]};
  const std::size_t nc = plane * static_cast<std::size_t>(end - base);
  const double count = static_cast<double>(std::max<std::size_t>(1, sim.particle_count()));
  // Sums by blocks of nc: the volume, then the momentum's x, y and z.
  ExactSums vol, mom;
  vol.reset(nc, largest[0], count * largest[0]);
  mom.reset(3 * nc, largest[1], count * largest[1]);
  each([&](std::size_t s, const int* q, double w) {
    const auto at = [](int x) { return static_cast<std::size_t>(x); };
    const std::size_t cell = at(q[0]) + at(n[0]) * at(q[1]) + plane * at(q[2] - base);
    vol.add(cell, w);
    mom.add(cell, w * p.vx[s]); mom.add(nc + cell, w * p.vy[s]); mom.add(2 * nc + cell, w * p.vz[s]);
  });
  if (reach_only) {
    share.add_up({vol.data(), mom.data(), mom.data() + nc, mom.data() + 2 * nc}, 0, plane, n[2], base);
  } else {
    sim.add_up(vol);
    sim.add_up(mom);
  }
  CellPlanes out{planes.first, {}};
  if (planes.first >= planes.second) return out;
  const std::size_t first = plane * static_cast<std::size_t>(planes.first - base);
  out.values.assign(3 * plane * static_cast<std::size_t>(planes.second - planes.first), 0.0);
  for (std::size_t c = 0; 3 * c < out.values.size(); ++c) {
    const double v = vol.value(first + c);
    if (v > 0.0)
      for (std::size_t a = 0; a < 3; ++a) out.values[3 * c + a] = mom.value(a * nc + first + c) / v;
  }
  return out;
}

}  // namespace cdm
