#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/coupling/two_way_exchange.hpp"
#include "cdm/solver/population.hpp"
#include "cdm/solver/rank_split.hpp"
#include "cdm/solver/simulation.hpp"

// Particles inserted and removed at the end of a step (population.hpp), on one process
// or among processes sharing the particles (rank_split.hpp), and their checkpoint section.

namespace cdm {

void Simulation::update_population() {
  Population& pop = *population_;
  // Among ranks each looks at its own particles, and all take part if any has one leaving.
  const bool leaving =
      ranks_ ? ranks_->any_own(particles_.size(), [&](std::size_t i0, std::size_t i1) { return pop.any_leaving(particles_, i0, i1); })
             : pop.any_leaving(particles_, 0, particles_.size());
  const bool due = pop.insertion_due(time_);
  if (!leaving && !due) return;
  // Among ranks that share the particles, each completes its own. A contact list that is
  // not kept (VerletList::remap) takes its build positions from the particles: then every
  // rank gets the positions alone. Else (or without contacts) an insertion reads the
  // positions of the particles near its boxes only, which their owners share
  // (insert_due). The leaving particles are found by their owners and removed alike
  // everywhere (remove_leaving). Until the particles are dealt out, every rank holds the
  // whole state.
  const bool own_part = ranks_ && ranks_->partitioned();
  bool positions_held = true;
  if (own_part) {
    local_particles();
    const VerletList* list = contact_list();
    positions_held = list && !(list->built() && list->listed(particles_.size()));
    if (positions_held) ranks_->gather({&particles_.x, &particles_.y, &particles_.z, &particles_.radius});
  } else {
    complete_step();  // the state at the step's end, velocities included
  }
  if (leaving) remove_leaving(own_part);
  if (due) insert_due(own_part, positions_held);
  // Every rank changed the whole state alike; the slots moved, so each moves all the
  // particles until the list, built again at the next step, deals the slabs out anew.
  if (ranks_ && !own_part) ranks_->unassign();
}

void Simulation::insert_due(bool own_part, bool positions_held) {
  // Each particle is placed clear of every other, from the same positions on every rank:
  // every rank inserts the same particles. Where each rank holds its own particles'
  // positions only, the owners share those near the insertions' boxes first.
  const std::size_t n0 = particles_.size();
  std::vector<std::uint32_t> near;
  if (!positions_held) near = share_near_insertions();
  if (population_->insert(particles_, time_, spec_.gravity ? spec_.g : Vec3{}, positions_held ? nullptr : &near) == 0)
    return;
  std::vector<std::uint32_t> from(particles_.size(), new_particle);
  for (std::size_t i = 0; i < n0; ++i) from[i] = static_cast<std::uint32_t>(i);
  remap(from);
  // The list took every slot's position as its build position (VerletList::remap): the
  // own particles' and the new ones' alone are current, as after a divided build.
  if (VerletList* list = contact_list(); list && !positions_held) list->build_positions_released();
  if (own_part) ranks_->added(particles_, particles_.size() - n0);
}

std::vector<std::uint32_t> Simulation::share_near_insertions() {
  const Population& pop = *population_;
  // Each process holds its own particles' radii (and its ghosts'): the largest over them all.
  const double r_max = ranks_->max(pop.reach_radius(particles_));
  std::vector<std::uint64_t> keys;
  std::vector<double> at;
  for (const auto& [i0, i1] : ranks_->own_runs(particles_.size()))
    for (std::size_t i = i0; i < i1; ++i)
      if (pop.near_insertion(particles_.position(i), r_max)) {
        keys.push_back(i);
        at.insert(at.end(), {particles_.x[i], particles_.y[i], particles_.z[i], particles_.radius[i]});
      }
  ranks_->share_records(keys, at, 4);
  std::vector<std::uint32_t> near(keys.size());
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const auto i = static_cast<std::uint32_t>(keys[k]);
    near[k] = i;
    particles_.x[i] = at[4 * k];
    particles_.y[i] = at[4 * k + 1];
    particles_.z[i] = at[4 * k + 2];
    particles_.radius[i] = at[4 * k + 3];
  }
  return near;
}

void Simulation::remove_leaving(bool own_part) {
  Population& pop = *population_;
  const std::size_t n = particles_.size();
  std::vector<std::pair<std::uint32_t, std::uint32_t>> runs{{0, static_cast<std::uint32_t>(n)}};
  if (own_part) runs = ranks_->own_runs(n);
  std::vector<Population::Leaving> gone;
  for (const auto& [i0, i1] : runs) {
    const std::vector<Population::Leaving> l = pop.leaving(particles_, i0, i1);
    gone.insert(gone.end(), l.begin(), l.end());
  }
  // What the leaving particles' drag gave the gas since their impulses were last
  // deposited (at the last step, or over the gas step so far) goes to the gas now, in
  // slot order: each particle's position and impulse, from its owner.
  const bool deposit = exchange_ && exchange_->two_way() && !particles_.jx.empty();
  // Per particle gone: its mass, and to deposit x y z jx jy jz.
  const std::size_t per = deposit ? 7 : 1;
  std::vector<double> at;
  for (const auto& g : gone) {
    const std::size_t i = g.slot;
    at.push_back(g.mass);
    if (deposit)
      at.insert(at.end(), {particles_.x[i], particles_.y[i], particles_.z[i], particles_.jx[i], particles_.jy[i],
                           particles_.jz[i]});
  }
  if (own_part) {
    // Every rank gets every rank's, in slot order: keyed by slot, then outlet.
    std::vector<std::uint64_t> keys;
    for (const auto& g : gone) keys.push_back(std::uint64_t{g.slot} << 32 | g.outlet);
    ranks_->share_records(keys, at, per);
    gone.resize(keys.size());
    for (std::size_t k = 0; k < keys.size(); ++k)
      gone[k] = {static_cast<std::uint32_t>(keys[k] >> 32), static_cast<std::uint32_t>(keys[k]), at[k * per]};
  }
  if (deposit)
    for (std::size_t k = 0; k < at.size(); k += per)
      exchange_->deposit_impulse_of_leaving({at[k + 1], at[k + 2], at[k + 3]}, {at[k + 4], at[k + 5], at[k + 6]});
  const std::vector<std::uint32_t> from = pop.remove(particles_, gone);
  remap(from);
  if (own_part) ranks_->keep(from);
  // The identities shifted: messages name particles by number, not by scene key.
  spec_.groups.clear();
}

void Simulation::save_population(OutArchive& a) const {
  a.put(static_cast<std::uint8_t>(population_ ? 1 : 0));
  if (!population_) return;
  const ParticleStore& p = particles_;
  // Among processes each holds its own particles' radii and masses: those stream to the writer.
  a.put_particles(p.radius);
  a.put_particles(p.mass); a.put_particles(p.inv_mass); a.put_particles(p.inv_inertia);
  // On disk as 4-byte integers, in blocks (the store holds each in one byte).
  a.put<std::uint64_t>(p.material.size());
  std::int32_t block[4096];
  for (std::size_t k0 = 0; k0 < p.material.size(); k0 += std::size(block)) {
    const std::size_t m = std::min(std::size(block), p.material.size() - k0);
    for (std::size_t k = 0; k < m; ++k) block[k] = p.material[k0 + k];
    a.put_values(block, m);
  }
  population_->save_state(a);
}

bool Simulation::load_population(InArchive& a, std::uint64_t n) {
  std::uint8_t has = 0;
  a.get(has);
  if ((has != 0) != static_cast<bool>(population_)) throw ArchiveError("its insertions and outlets differ from the scene's");
  if (!population_) return false;
  ParticleStore& p = particles_;
  auto arr = [&](auto& v, std::size_t want) {
    a.get(v, want);
    if (v.size() != want) throw ArchiveError("a particle array has the wrong length");
  };
  arr(p.radius, n); arr(p.mass, n); arr(p.inv_mass, n);
  arr(p.inv_inertia, p.has_rotation() ? n : 0);
  if (a.get_length(n, sizeof(std::int32_t)) != n) throw ArchiveError("a particle array has the wrong length");
  p.material.resize(n);
  std::int32_t block[4096];
  for (std::size_t k0 = 0; k0 < n; k0 += std::size(block)) {
    const std::size_t m = std::min(std::size(block), n - k0);
    a.get_values(block, m);
    for (std::size_t k = 0; k < m; ++k) {
      if (block[k] < 0 || static_cast<std::size_t>(block[k]) >= spec_.materials.size())
        throw ArchiveError("particle " + std::to_string(k0 + k) + "'s material is not valid");
      p.material[k0 + k] = static_cast<std::uint8_t>(block[k]);
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!(p.radius[i] > 0.0) || !(p.mass[i] > 0.0) || !std::isfinite(p.inv_mass[i]))
      throw ArchiveError("particle " + std::to_string(i) + "'s radius or mass is not valid");
  p.flag_fixed_from_masses();
  // The store holds n particles from here: the arrays read next are sized to it.
  for (auto* v : {&p.x, &p.y, &p.z}) v->resize(n);
  population_->load_state(a);
  for (const auto& r : population_->removed())
    if (r.count) spec_.groups.clear();  // as after the removal (update_population)
  return true;
}

}  // namespace cdm
