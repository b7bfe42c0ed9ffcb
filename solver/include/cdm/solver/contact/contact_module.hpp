#pragma once
/// @file contact_module.hpp
/// @brief Contacts between particles and with walls: the pair and wall loops over a
/// Verlet list (verlet_list.hpp), each contact resolved by its pair's force law.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "cdm/solver/contact/mesh_contacts.hpp"
#include "cdm/solver/contact/verlet_list.hpp"
#include "cdm/solver/force_module.hpp"
#include "cdm/solver/materials.hpp"
#include "cdm/solver/walls.hpp"

namespace cdm {

class RankSplit;

/// Largest overlap relative to a radius seen in the last force evaluation.
struct OverlapRecord {
  double ratio = 0.0;         // overlap / radius of the smaller partner [-]
  std::uint32_t particle = 0; // particle whose radius that is
  long partner = -1;          // other particle, or -1 - wall index for a wall (walls, then meshes)
};

namespace contact {
/// The larger overlap, ties broken by the lower particle then partner index, so the
/// record does not depend on the order threads (or ranks) report in.
inline bool worse_overlap(const OverlapRecord& a, const OverlapRecord& b) {
  if (a.ratio != b.ratio) return a.ratio > b.ratio;
  if (a.particle != b.particle) return a.particle < b.particle;
  return a.partner < b.partner;
}
}  // namespace contact

/// Normal contact between particles and with walls, each pair of materials with its own
/// force law (PairParams::law): the linear spring–dashpot (contact/
/// linear_spring_dashpot.hpp) or Hertz–Mindlin (contact/hertz_mindlin.hpp). With
/// @p with_friction each law adds its tangential spring with history and Coulomb limit
/// (only then is tangential history kept).
///
/// The loops are compiled once per combination of friction on/off and the laws present
/// (linear only, Hertz only, both), each law's kernel inlined: a scene with one law has
/// no per-pair dispatch, and in a mixed scene one well-predicted branch picks the law
/// per contact. The linear arithmetic is the same in every variant, so linear results
/// do not depend on which other laws a scene defines.
///
/// Pairs are visited slab by slab (VerletList), even slabs in parallel, then odd ones,
/// so every particle receives its contributions in the same order whatever the number
/// of threads. Wall contacts are split among threads as the integrator's pass is.
///
/// With @p record_normal_forces the module also keeps, for the current evaluation, each
/// contact's normal force magnitude, for modules that act through the same contacts
/// (rolling resistance).
class ContactModule final : public ForceModule {
 public:
  /// @p skin [m]: Verlet-list margin; 0 rebuilds every evaluation.
  ContactModule(PairTable pairs, std::vector<Wall> walls, bool with_friction, double skin = 0.0,
                bool record_normal_forces = false);
  std::string name() const override;
  void add_forces(ParticleStore& p, double dt) override;
  /// The list made valid for @p p's positions as add_forces() makes it (built when due,
  /// the slabs dealt out among MPI processes), without evaluating the contacts: the first
  /// build, ahead of the first step, so that the output at the start reads the run's own
  /// list (Simulation::run). Returns what the list's update did.
  VerletList::Update update_list(ParticleStore& p);
  /// The contacts' forces as listed, without updating the list, which must be current
  /// for @p p (Simulation::own_contacts_current): output's evaluation of the state a
  /// step left, within probe_listed(). Among MPI processes each evaluates its own
  /// particles', as a step does (a collective call).
  void add_listed_forces(ParticleStore& p);
  /// Calls @p read(*this) with this module, the run's, evaluating its contacts as listed
  /// (add_listed_forces) and recording their forces (set_recording, with @p vectors the
  /// force vectors), without changing what the run carries: every history (the pairs',
  /// the wall entries') is read and left as it is, and the counts, the recorded forces
  /// and the mesh contacts are put back as they were after @p read. For output between
  /// steps (output_fields.hpp), at the cost of the recorded forces, not of a copy of the
  /// list.
  void probe_listed(bool vectors, const std::function<void(ContactModule&)>& read);

  /// The Verlet list the loops run over: Simulation asks it when to rebuild and sort,
  /// and an integrator that measures the particles' drift tells it (VerletList).
  const VerletList& list() const { return list_; }
  VerletList& list() { return list_; }
  const OverlapRecord& worst_overlap() const { return worst_; }
  std::size_t active_contacts() const { return n_active_; }
  /// Contacts carrying tangential history (zero when frictionless).
  std::size_t history_size() const { return friction_ ? n_active_ : 0; }
  /// Whether the pair loop prefetches the positions and radii of the partner 128 pairs
  /// ahead. Memory order only, never the results. `automatic` (the default) prefetches
  /// when the particles' arrays (ParticleStore::bytes) exceed the largest cache
  /// (last_level_cache_bytes): the integrator's sweep over all particles then evicts the
  /// positions before the pair loop reads them, and the loop, gathering each pair's
  /// partner, loses the hardware prefetcher's streams; in cache the prefetches only cost
  /// instructions (bench/README.md has the measures). `on` and `off` force it.
  enum class Prefetch { automatic, on, off };
  void set_prefetch(Prefetch p) { prefetch_ = p; }
  /// Whether the last evaluation prefetched.
  bool prefetched() const { return prefetched_; }
  /// The walls where they stand at the time set by set_time().
  const std::vector<Wall>& walls() const { return list_.walls(); }
  /// The time [s] of the positions the next evaluation sees (where moving walls are).
  void set_time(double t) { list_.set_time(t); }
  /// Triangle-mesh walls (mesh_contacts.hpp), resolved after the analytic walls with the
  /// same laws; an OverlapRecord names mesh m as partner -1 - (walls().size() + m).
  void set_meshes(std::vector<TriangleMesh> meshes) { mesh_.emplace(std::move(meshes)); }
  const MeshContacts* meshes() const { return mesh_ ? &*mesh_ : nullptr; }
  /// The wall or mesh an OverlapRecord's negative partner names ("wall 'x'", "mesh 'y'").
  std::string wall_name(long partner) const;
  const PairTable& pairs() const { return pairs_; }
  /// The MPI ranks the pairs and walls are split among (rank_split.hpp), or nullptr: every
  /// particle's contacts here. A copy that evaluates alone sets nullptr.
  void set_ranks(RankSplit* r);
  /// The ranks sharing the step (rank_split.hpp), or nullptr.
  RankSplit* ranks() const { return ranks_; }
  void set_periodic_box(const PeriodicBox& box) { list_.set_periodic_box(box); }
  void save_state(OutArchive& a) const override;
  void load_state(InArchive& a) override;
  void permute(const std::vector<std::uint32_t>& from) override;
  void remap(const std::vector<std::uint32_t>& from, const ParticleStore& p) override {
    list_.remap(from, p);
    if (mesh_) mesh_->remap(from);
  }

  /// |F_n| [N] per listed pair, or -1 where the pair is not in contact (record_normal_forces).
  const std::vector<double>& pair_normal_force() const { return fn_pair_; }
  /// The force on the pair's first particle i from its second j, and its tangential part
  /// [N], per listed pair: 6 values (total x y z, tangential x y z), valid where
  /// pair_normal_force() is not -1 (set_recording on).
  const std::vector<double>& pair_force() const { return fv_pair_; }
  /// Recording on or off, the force vectors (pair_force, wall_force) with it (e.g. on a
  /// copy that evaluates the contacts for output). A module constructed with
  /// record_normal_forces records the normal forces only.
  void set_recording(bool on) { record_ = record_vectors_ = on; }
  /// |F_n| [N] per wall entry of the list (entry q of list().wall_ids(): a listed
  /// particle and wall), or -1 where not in contact.
  const std::vector<double>& wall_normal_force() const { return fn_wall_; }
  /// The force on the entry's particle from its wall [N], 3 values per wall entry
  /// (3 q + axis), valid where wall_normal_force() is not -1 (set_recording on).
  const std::vector<double>& wall_force() const { return fv_wall_; }
  /// |F_n| [N] per mesh contact of the current evaluation, in meshes()->contacts() order
  /// (recording on).
  const std::vector<double>& mesh_normal_force() const { return fn_mesh_; }

  /// Velocities [m/s] and angular velocities [rad/s] with which the integrator moved the
  /// particles over the last step, when they differ from the velocities forces are
  /// evaluated at (velocity Verlet: x(t+Δt) = x(t) + Δt v(t+Δt/2), forces at the
  /// predicted v(t) + Δt a(t)). Hertz–Mindlin's tangential history is incremented with
  /// these, so that it follows the contact points' actual displacement; incrementing
  /// with the predicted velocity is an O(Δt) error per step in the spring, which makes a
  /// sticking contact first order. The arrays are read at each evaluation; they are
  /// ignored until they hold one value per particle (before the first step). The linear
  /// law keeps the paper's rule (the velocity of the evaluation).
  struct StepVelocities {
    const std::vector<double>*vx = nullptr, *vy = nullptr, *vz = nullptr;
    const std::vector<double>*wx = nullptr, *wy = nullptr, *wz = nullptr;
  };
  void set_step_velocities(StepVelocities s) { step_ = s; }
  const StepVelocities& step_velocities() const { return step_; }

 private:
  /// The force laws the pair table uses: each set has its own compiled loops.
  enum class LawsPresent { linear, hertz, both };
  template <bool Record>
  void dispatch(ParticleStore& p, double dt);
  template <bool Friction, LawsPresent L, bool Record>
  void add_forces_impl(ParticleStore& p, double dt);
  /// The forces of the list as it stands (@p walls_listed: its wall entries are new).
  void evaluate(ParticleStore& p, double dt, bool walls_listed);
  /// The mesh contacts (mesh_contacts.hpp), after the plane walls, with the pair loop's laws.
  template <bool Friction, LawsPresent L, class Resolve, class Hertz, class StepVel, class StepSpin>
  void mesh_pass(ParticleStore& p, Resolve& resolve, Hertz& hertz, StepVel& step_velocity,
                 StepSpin& step_spin, std::size_t& active, OverlapRecord& worst);
  /// Fills eta_n_common_ when every free particle has the same mass, else empties it.
  void tabulate_damping(const ParticleStore& p);

  PairTable pairs_;
  bool friction_;
  bool record_;
  bool record_vectors_;  // set_recording: the force vectors as well
  bool keep_history_ = false;  // probe_listed: a recording evaluation leaves the history as it is
  bool spins_shared_;  // a module reads the step spins through these contacts (rolling resistance)
  LawsPresent laws_;
  VerletList list_;
  // When every free particle has one mass m (a monodisperse bed), m* takes two values,
  // m/2 and m (partner fixed), so the linear law's η_n one per material pair and kind
  // of partner: [2 (a n_materials + b) + partner fixed]. Empty otherwise; η_n is then
  // taken per contact. Tabulated at each build and after load_state.
  std::vector<double> eta_n_common_;
  bool damping_stale_ = true;
  std::vector<double> fn_pair_, fn_wall_;     // record_: |F_n| [N] or -1
  std::vector<double> fv_wall_;               // record_vectors_: the wall's force on the particle [N]
  std::vector<double> fn_mesh_;               // record_: |F_n| [N] per mesh contact
  std::vector<double> fv_pair_;               // record_vectors_: total and tangential force per pair
  StepVelocities step_;                       // see set_step_velocities
  Prefetch prefetch_ = Prefetch::automatic;
  bool prefetched_ = false;
  OverlapRecord worst_;
  std::size_t n_active_ = 0;
  std::optional<MeshContacts> mesh_;
  RankSplit* ranks_ = nullptr;  // set_ranks
};

}  // namespace cdm
