#include <algorithm>
#include <cmath>
#include <utility>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/fluid/gas_solver.hpp"
#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/rank_split.hpp"
#include "cdm/solver/simulation.hpp"

// How the particles' state is read: whole on every process (complete_step), whole on
// the writing process (written_particles), streamed to it for a checkpoint
// (hold_for_checkpoint, stream_shared), a table or a VTK frame (written_rows), or each
// process its own part (local_particles, counted_runs), with its ghosts for its
// particles' contacts (own_with_ghosts). The gas likewise: each process the planes under
// its own particles (gas_follows_particles), its own planes streamed to the writing
// process for a checkpoint (stream_shared), or each process its own planes for a
// reduction (gas_planes).

namespace cdm {

VerletList* Simulation::contact_list() const { return contact_ ? &contact_->list() : nullptr; }

void Simulation::synchronise_ranks(bool for_build) const {
  if (ranks_) ranks_->synchronise(const_cast<ParticleStore&>(particles_), contact_list(), for_build);
}

void Simulation::complete_step() const {
  const double bad = integrator_->complete();
  synchronise_ranks();  // the state is read: every rank gets all of it
  if (bad != 0.0) check_state(1.0);
}

void Simulation::complete_for_gas_step() {
  if (!ranks_) return complete_step();
  // The exchange reads the positions and impulses (and the implicit drag the velocities
  // and K): each rank deposits (and kicks) its own particles.
  if (integrator_->complete() != 0.0) fail_not_finite();
}

void Simulation::fail_not_finite() const {
  synchronise_ranks();  // names the particles, whichever rank moved them
  check_state(1.0);
}

const ParticleStore& Simulation::local_particles() const {
  if (!ranks_) return particles();
  // Each process completes its own particles' step; the check is reduced over them all.
  if (integrator_->complete() != 0.0) fail_not_finite();
  return particles_;
}

const ParticleStore& Simulation::written_particles() const {
  if (!ranks_) return particles();
  const double bad = integrator_->complete();
  ranks_->gather_to_writer(const_cast<ParticleStore&>(particles_), contact_list());
  if (bad != 0.0) fail_not_finite();
  return particles_;
}

void Simulation::written_rows(const IdentityOrder& order, const std::vector<const std::vector<double>*>& arrays,
                              const std::function<void(std::size_t, const double*)>& row, bool from_owners) const {
  const ParticleStore& p = local_particles();
  const auto slot_of = [&order](std::size_t k) { return order.slot_of(k); };
  if (ranks_ && (from_owners ? ranks_->partitioned() : !ranks_->writer_holds_all()))
    return ranks_->rows_to_writer(arrays, p.size(), slot_of, row);
  if (ranks_ && ranks_->share_rank() != 0) return;
  std::vector<double> values(arrays.size());
  for (std::size_t k = 0; k < p.size(); ++k) {
    const std::size_t s = slot_of(k);
    for (std::size_t a = 0; a < arrays.size(); ++a) values[a] = (*arrays[a])[s];
    row(k, values.data());
  }
}

bool Simulation::own_contacts_current() const {
  return contact_ && (!ranks_ || ranks_->assigned_for(contact_->list().builds())) &&
         contact_->list().current_for(particles_);
}

const ParticleStore& Simulation::own_with_ghosts() const {
  const ParticleStore& p = local_particles();
  if (ranks_ && ranks_->partitioned()) ranks_->exchange_ghosts(const_cast<ParticleStore&>(particles_));
  return p;
}

Simulation::HeldContacts Simulation::hold_for_checkpoint() const {
  local_particles();  // the step completed, each process its own particles
  // The wall contacts, held on rank 0, go with the pair contacts' guard.
  if (ranks_ && contact_) ranks_->records_to_writer(contact_->list());
  return hold_contacts();
}

void Simulation::stream_shared(OutArchive& a) const {
  if (solver_ && solver_->divided()) {
    const fluid::PlaneShare* s = &solver_->planes();
    a.stream_planes(
        [s](OutArchive& o, const std::vector<double>& v, OutArchive::Planes l) { s->put_to_writer(o, v, l); });
  }
  if (!ranks_ || ranks_->writer_holds_all()) return;
  RankSplit* r = ranks_.get();
  a.stream_particles([r](OutArchive& o, const std::vector<double>& v) { r->put_gathered(o, v); });
}

std::vector<std::pair<std::uint32_t, std::uint32_t>> Simulation::counted_runs() const {
  const auto n = static_cast<std::uint32_t>(particles_.size());
  if (!ranks_) return {{0, n}};
  if (ranks_->partitioned()) return ranks_->own_runs(n);
  if (ranks_->share_rank() == 0) return {{0, n}};
  return {};
}

const fluid::PlaneShare& Simulation::gas_planes() const {
  static const fluid::PlaneShare whole(false);
  return solver_ ? solver_->planes() : whole;
}

void Simulation::gas_follows_particles() {
  reach_stated_ = true;
  if (!solver_ || !solver_->divided() || !contact_ || !ranks_) return;
  const fluid::StaggeredGrid& g = gas_->grid();
  if (g.two_d()) return;
  // Before the particles are dealt out every process moves every particle: every plane.
  if (!ranks_->partitioned()) return solver_->read_planes(0, g.n(2) - 1);
  // The own particles' extent along z. Until the next build each stays within half a skin
  // of its build position, as it is now: within a skin of where it is. What is read at a
  // particle reaches its kernel's width (3σ for the gaussian) and two planes of stencils
  // further (GasSolver::read_planes adds the planes its own step reads).
  const auto [lo, hi, finite] = own_extent(*ranks_, particles_.size(), particles_.z.data());
  const int nz = g.n(2);
  int k_lo = 1, k_hi = 0;  // none: no own particles
  if (!finite) {
    k_lo = 0, k_hi = nz - 1;
  } else if (lo <= hi) {
    const double width = spec_.kernel == coupling::Kernel::gaussian ? 3.0 * spec_.kernel_width : 0.0;
    const double margin = contact_->list().skin() + width;
    auto plane = [&](double z) { return std::clamp(std::floor((z - g.lo(2)) * g.inv_h(2)), -4.0, nz + 4.0); };
    k_lo = static_cast<int>(plane(lo - margin)) - 2;
    k_hi = static_cast<int>(plane(hi + margin)) + 2;
  }
  solver_->read_planes(k_lo, k_hi);
}

}  // namespace cdm
