#pragma once
/// @file population.hpp
/// @brief Particles inserted and removed during a run: the scene's [[insertions]] add
/// particles in a box or a cylinder at a rate until a total, placed by random sequential addition
/// clear of every particle and wall (placement.hpp); its [[outlets]] remove the
/// particles whose centre reaches them. Both run at the end of a step (Simulation), and
/// keep what they did: per insertion the particles and mass inserted, per outlet those
/// removed, for the balance in outlets.dat.
///
/// Insertion events: an insertion with `interval` > 0 inserts at the first step whose
/// time reaches start + k·interval (k = 0, 1, ...), with interval 0 at every step from
/// start on. At an event at time t it inserts until the number inserted reaches
/// ⌊rate·(min(t, end) − start)⌋ (count_rate), or while the mass inserted is below
/// rate·(min(t, end) − start) (mass_rate: the mass runs ahead by less than one
/// particle), never beyond the total. A particle that finds no free place in 1000
/// tries ends the event; what it could not insert is due at the next event.
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/scene.hpp"

namespace cdm {

class Population {
 public:
  explicit Population(const SceneSpec& spec);

  /// Whether the centre of some particle of slots [@p i0, @p i1) is in an outlet.
  bool any_leaving(const ParticleStore& p, std::size_t i0, std::size_t i1) const;
  /// The outlet that takes a centre at @p x: the first in scene order that holds it, or
  /// the outlet count when none does.
  std::uint32_t outlet_of(Vec3 x) const {
    std::uint32_t o = 0;
    while (o < spec_.outlets.size() && !spec_.outlets[o].removes(x)) ++o;
    return o;
  }
  /// A particle in an outlet: its slot, and the outlet that takes it (outlet_of).
  struct Leaving {
    std::uint32_t slot = 0, outlet = 0;
    double mass = 0.0;  // [kg], from the particle's owner
  };
  /// The particles of slots [@p i0, @p i1) in an outlet, in slot order.
  std::vector<Leaving> leaving(const ParticleStore& p, std::size_t i0, std::size_t i1) const;
  /// Remove the particles @p gone (in slot order, each slot once), recording their
  /// number and mass per outlet. The store is compacted in order; returns, for each slot
  /// left, the slot it held before (ParticleStore::keep).
  std::vector<std::uint32_t> remove(ParticleStore& p, const std::vector<Leaving>& gone);
  /// Whether an insertion event is due at time @p t (one at every step only when it owes
  /// a particle).
  bool insertion_due(double t) const;
  /// Run the insertion events due at @p t: the particles are appended to the store at
  /// rest relative to the insertion's velocity, their force the weight m @p g (nothing
  /// else acts on a particle placed clear of all others). Returns how many were added.
  /// Each is placed clear of the particles near the insertion's box: of every particle
  /// of @p p, or with @p near of those slots (increasing) only, the others' positions
  /// not being held, and of the particles the events add.
  std::size_t insert(ParticleStore& p, double t, Vec3 g, const std::vector<std::uint32_t>* near = nullptr);
  /// The largest radius an insertion event can meet: of @p p's particles, and of the
  /// sizes any insertion draws.
  double reach_radius(const ParticleStore& p) const;
  /// Whether an insertion event may have to keep clear of a particle centred at @p x,
  /// given @p r_max from reach_radius(): its centre near the box of an insertion not
  /// done (within the insertion's largest radius plus @p r_max; along periodic axes
  /// through the faces too). The particles an event reads are among these.
  bool near_insertion(Vec3 x, double r_max) const;

  /// Totals since the start of the run.
  struct Tally {
    std::uint64_t count = 0;
    double mass = 0.0;  // [kg]
  };
  const std::vector<Tally>& inserted() const { return inserted_; }  ///< per insertion
  const std::vector<Tally>& removed() const { return removed_; }    ///< per outlet
  /// Insertion events that ended early (no free place): the box is full.
  std::uint64_t jammed_events() const { return jammed_; }

  void save_state(OutArchive& a) const;
  void load_state(InArchive& a);

 private:
  struct Feed {
    std::mt19937_64 rng;
    std::uint64_t next_event = 0;  // index k of the next event (interval > 0)
    bool done = false;             // total reached, or end passed
  };
  std::size_t run_event(std::size_t k, ParticleStore& p, double t, Vec3 g, const std::vector<std::uint32_t>* near,
                        std::size_t n_before);
  /// Whether a particle centred at @p x lies near insertion @p k's box (near_insertion).
  bool near_box(std::size_t k, Vec3 x, double r_max) const;
  /// Whether insertion @p k has particles left to insert before its total.
  bool total_left_of(std::size_t k) const;
  /// Whether insertion @p k owes a particle at time @p t: its rate's count (or mass) up
  /// to min(t, end) not reached, and its total not either.
  bool owed(std::size_t k, double t) const;

  const SceneSpec& spec_;
  std::vector<Feed> feeds_;
  std::vector<Tally> inserted_, removed_;
  std::uint64_t jammed_ = 0;
};

}  // namespace cdm
