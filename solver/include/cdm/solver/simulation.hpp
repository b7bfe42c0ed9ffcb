#pragma once
/// @file simulation.hpp
/// @brief A Simulation holds the particles and the modules a scene named, and advances
/// them with the scene's integrator. Data flow per step: forces (each module adds its
/// part) → integrator update → guards (finite state, overlap bound) → observers, and
/// with a solved gas, the gas step after every substeps() particle steps.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/coupling/drag_module.hpp"
#include "cdm/solver/coupling/implicit_drag.hpp"
#include "cdm/solver/coupling/two_way_exchange.hpp"
#include "cdm/solver/fluid/gas_field.hpp"
#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/integrators/integrator.hpp"
#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/population.hpp"
#include "cdm/solver/rank_split.hpp"
#include "cdm/solver/run_guards.hpp"
#include "cdm/solver/scene.hpp"

namespace cdm {

class Simulation : private integrators::StepHost {
 public:
  /// Builds the scene's modules and particles; the per-particle list of @p spec is
  /// dropped once the particles are in the store (pass an rvalue to avoid a copy).
  explicit Simulation(SceneSpec spec);
  // The modules and the integrator hold the particles and the scene by reference.
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;
  ~Simulation();

  const SceneSpec& spec() const { return spec_; }
  /// The particles at time(). Reading them completes the last step where its final
  /// kick was left pending (see step()); a state that went non-finite in that step is
  /// reported here then (SimulationError).
  ParticleStore& particles() {
    complete_step();
    integrator_->masses_changed();  // the caller may change them
    return particles_;
  }
  const ParticleStore& particles() const { complete_step(); return particles_; }
  /// How many particles there are (without completing the step or gathering ranks).
  std::size_t particle_count() const { return particles_.size(); }
  /// The MPI processes of the run (1 without a launcher).
  int ranks() const;
  /// Whether @p flag is set on any of the processes (a collective call when several).
  bool any_rank(bool flag) const { return ranks_ ? ranks_->any(flag) : flag; }
  /// The sum of @p v over the processes, and the largest of @p x (collective calls
  /// when several): for what each process counts of its own part.
  std::uint64_t rank_sum(std::uint64_t v) const {
    std::vector<std::uint64_t> s{v};
    if (ranks_) ranks_->sum(s);
    return s[0];
  }
  double rank_max(double x) const { return ranks_ ? ranks_->max(x) : x; }
  void rank_max(std::vector<double>& v) const {
    if (ranks_) ranks_->max(v);
  }
  /// Every process gets the sums of @p s over the processes (collective when several).
  void add_up(ExactSums& s) const {
    if (ranks_) ranks_->add_up(s);
  }
  /// The particles as this process holds them at time(), without gathering the others'
  /// (the step completed as for particles()): the particles of counted_runs() are current
  /// there; on several processes the others' may be stale. For what is summed over the
  /// particles, each process its own part, and added up (counted_sums.hpp).
  const ParticleStore& local_particles() const;
  /// The particles at time() for what process 0 writes whole (a VTK frame's contacts
  /// where the list has changed since the step's update: output_fields.hpp): all of them
  /// current on process 0; on the others only those of counted_runs(). A collective call when several processes share the
  /// particles: every process makes it, then process 0 may read them again (no call
  /// after the first gathers until the state moves on).
  const ParticleStore& written_particles() const;
  /// For what process 0 writes row by row (the particle table): @p row(k, values) for
  /// each particle k in identity order with its values of @p arrays (per-particle
  /// arrays), on process 0 only. Where the processes share the particles they are
  /// gathered in rounds, each from its owner: process 0 does not hold the whole state for
  /// it. A collective call when several processes share the particles.
  /// With @p from_owners the values are gathered from each particle's owner even where
  /// process 0 holds the whole state: for arrays each process fills for its own
  /// particles only (own_contacts_current()). @p order is the identity order of
  /// local_particles(), built once by the caller for all the rows it writes.
  void written_rows(const IdentityOrder& order, const std::vector<const std::vector<double>*>& arrays,
                    const std::function<void(std::size_t, const double*)>& row, bool from_owners = false) const;
  /// Whether each process can evaluate its own particles' contacts at time() with the
  /// contact module as it stands (ContactModule::probe_listed): nothing has changed the
  /// list since the step's update or its first build (VerletList::current_for) and, where
  /// the processes share it, its slabs are dealt out for its current build. The same on
  /// every process. Where it holds, own_with_ghosts() gives the state to evaluate.
  bool own_contacts_current() const;
  /// For records process 0 writes in the one-rank order of which each process holds its
  /// own part, in order (the contact network): @p push(records, count) on process 0 with
  /// its own @p count records of @p bytes each at @p data, then each other process's in
  /// rank order, a round at a time (RankSplit::ordered_to_writer). A collective call when
  /// several processes share the particles.
  void ordered_to_writer(const void* data, std::size_t count, std::size_t bytes,
                         const std::function<void(const void*, std::size_t)>& push) const {
    if (ranks_) ranks_->ordered_to_writer(data, count, bytes, push);
    else if (count) push(data, count);
  }
  /// Whether this process is the one written_rows() gives the rows to (process 0, or the
  /// only one).
  bool writes_rows() const { return !ranks_ || ranks_->share_rank() == 0; }
  /// local_particles(), and the ghosts (the neighbouring ranks' boundary slabs) brought
  /// to the same completed state, so that a copy of the contact module evaluates this
  /// process's particles' contacts as a step does. A collective call.
  const ParticleStore& own_with_ghosts() const;
  /// The runs of slots [first, last) whose terms this process adds to a sum over the
  /// particles, so that over the processes each particle counts once: every particle on
  /// one process; among processes sharing the particles, this one's own; where each moves
  /// every particle (until the list deals the slabs out), all of them on rank 0 and none
  /// on the others.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> counted_runs() const;
  /// Whether the processes share the contact list, each holding its own slabs' pairs.
  bool shares_list() const { return ranks_ != nullptr; }
  /// For a checkpoint or a frame with contact forces, on every process (a collective
  /// call when the processes share the contact list, each holding its own slabs' pairs,
  /// rank_split.hpp): rank 0, which writes them, holds the whole list's contacts
  /// (VerletList::hold_contacts) until the returned guard goes; a no-op otherwise.
  class HeldContacts {
   public:
    explicit HeldContacts(VerletList* list) : list_(list) {}
    HeldContacts(const HeldContacts&) = delete;
    HeldContacts& operator=(const HeldContacts&) = delete;
    ~HeldContacts() {
      if (list_) list_->release_contacts();
    }

   private:
    VerletList* list_;
  };
  [[nodiscard]] HeldContacts hold_contacts() const {
    if (!ranks_ || !contact_) return HeldContacts(nullptr);
    std::vector<VerletList::PairContact> all = ranks_->gather_contacts(contact_->list());
    if (ranks_->share_rank() != 0) return HeldContacts(nullptr);
    contact_->list().hold_contacts(std::move(all));
    return HeldContacts(&contact_->list());
  }
  /// For a checkpoint, on every process (a collective call when several share the
  /// particles): the step completed, and gathered to process 0 until the guard goes what
  /// it writes besides the per-particle arrays and the gas (the pair contacts, as
  /// hold_contacts(), and the wall and mesh contacts); those arrays then stream to it as
  /// it writes them (stream_shared()): process 0 does not gather the whole state for a
  /// checkpoint.
  [[nodiscard]] HeldContacts hold_for_checkpoint() const;
  /// Sets @p a, an archive save_state() is about to write on every process alike, to
  /// gather each per-particle array to process 0 as it is written, where the processes
  /// share the particles and process 0 does not hold them all (RankSplit::put_gathered),
  /// and each array of the gas's planes from their owners, where the processes divide the
  /// gas (PlaneShare::put_to_writer).
  void stream_shared(OutArchive& a) const;
  double time() const { return time_; }
  double dt() const { return spec_.dt; }
  std::uint64_t steps() const { return steps_; }
  /// Number of steps to reach spec().end_time.
  std::uint64_t total_steps() const { return total_steps_; }
  /// Names of the modules built for this scene, in evaluation order.
  std::vector<std::string> module_names() const;
  const ContactModule* contact() const { return contact_; }
  ContactModule* contact() { return contact_; }
  /// The gas, when the scene names one (nullptr for a DEM-only scene).
  const fluid::GasField* gas() const { return gas_.get(); }
  /// The gas for verification set-ups (manufactured solutions set ε, sources).
  fluid::GasField* gas_mutable() { return gas_.get(); }
  /// The gas solver (nullptr unless modules.gas = "solved").
  fluid::GasSolver* gas_solver() { return solver_.get(); }
  const fluid::GasSolver* gas_solver() const { return solver_.get(); }
  /// How the processes share the gas's planes: the gas solver's (GasSolver::planes()), or
  /// each process every plane (a prescribed gas, none, or a run of one process).
  const fluid::PlaneShare& gas_planes() const;
  /// Particle steps per gas step (1 without a solved gas).
  std::uint64_t substeps() const { return substeps_; }
  /// Momentum exchanged through drag over the last gas step [N s]: what the particles
  /// received and what the gas received (on the faces of the grid, coupling::CouplingBalance).
  using CouplingBalance = coupling::CouplingBalance;
  const CouplingBalance& coupling_balance() const;
  const coupling::DragModule* drag() const { return drag_; }
  /// The kernel that deposits the particles on the gas cells (nullptr without two-way
  /// coupling): what the particles' pressure force is weighted with
  /// (coupling::particle_pressure_gradient).
  const coupling::Deposition* deposition() const { return exchange_ ? exchange_->deposition() : nullptr; }
  /// The insertions and outlets (nullptr when the scene has neither).
  const Population* population() const { return population_.get(); }

  /// Advance one time step (throws SimulationError if the state goes bad). With
  /// velocity Verlet and no gas, the step's final half kick (the velocities and spins
  /// at the new time) is done lazily: in the same pass as the next step's first half,
  /// or when the particles are read, whichever comes first. Either way the arithmetic
  /// is the same, so results do not depend on when the state is read.
  void step();
  /// Run to end_time, calling @p observer at t = 0 (not after a restart; the contact
  /// list built first, list_first) and after every step; @p stop is polled after each
  /// step and ends the run early when it returns true.
  void run(const std::function<void(const Simulation&)>& observer = {},
           const std::function<bool()>& stop = {});

  /// Everything that changes from step to step, for checkpoints (archive.hpp).
  void save_state(OutArchive& a) const;
  /// Restore a saved state into a Simulation built from the same scene; throws
  /// ArchiveError if the state does not fit this scene.
  void load_state(InArchive& a);
  bool restarted() const { return restarted_; }

 private:
  // StepHost: what the integrator asks of the simulation.
  void compute_forces(double t, integrators::ForceStart start = integrators::ForceStart::stale) override;
  void ensure_forces() override {
    if (!forces_valid_) compute_forces(time_);
  }
  void fail_not_finite() const override;

  /// Before the output at the start: the contact list's first build, and the particles'
  /// first sort, as the first step would do them from the same positions, so that the
  /// output reads the run's own list (and among MPI processes each process its own part
  /// of it, as at any later step) instead of a copy listing every pair again. Without
  /// contacts, among MPI processes, the rows divided instead (divide_rows_if_due).
  void list_first();
  /// Among MPI processes, particles without contacts not yet divided: each process keeps
  /// its run of rows (RankSplit::divide_by_rows) and gives them their motion.
  void divide_rows_if_due();
  /// The tracers this process moves take the gas velocity where they are (at the start).
  void tracers_follow_gas();
  /// Where a solved gas is divided among processes and the particles by slabs, each
  /// process reads the gas on the planes under its own particles (GasSolver::read_planes),
  /// from each gas step and each build on. Collective.
  void gas_follows_particles();
  /// Before the contact list's update for the positions at time @p t: the walls moved
  /// there; among MPI processes, where the list is due to be built, the positions the
  /// build (and a sort before it) reads, else the ghosts; the particles sorted where due
  /// (sort_if_due, or among processes VerletList::held_spatial_order). Without contacts,
  /// divide_rows_if_due() alone.
  void ready_for_list(double t);
  /// Sort the particles spatially when neighbour_list.sort_interval asks for it and
  /// the contact list is about to be rebuilt.
  void sort_if_due();
  /// Whether sort_if_due() sorts at a build now.
  bool sort_due_at_build() const;
  /// Reorder the particles by @p from (permute()): a sort.
  void sort_by(const std::vector<std::uint32_t>& from);
  /// Reorder every per-particle array, the particles', the integrator's and the
  /// modules' (slot i takes what slot @p from[i] held).
  void permute(const std::vector<std::uint32_t>& from);
  /// At the end of a step: remove the particles in the outlets, then insert what is due.
  void update_population();
  /// Remove the particles in the outlets from the state completed at the step's end:
  /// from the whole state, or with @p own_part each process finding its own particles
  /// and every process removing them all (RankSplit::share_records, RankSplit::keep).
  void remove_leaving(bool own_part);
  /// Run the insertion events due (Population::insert), placing each particle clear of
  /// every other: from every position where @p positions_held (one process, or every
  /// position gathered: update_population), else from those near the insertions
  /// (share_near_insertions). With @p own_part the particles inserted, the same on every
  /// process, are process 0's (RankSplit::added).
  void insert_due(bool own_part, bool positions_held);
  /// Among processes that hold their own particles' positions only: every process gets
  /// the positions of the particles near an insertion not done (Population::near_insertion)
  /// from their owners. Returns their slots, increasing.
  std::vector<std::uint32_t> share_near_insertions();
  /// The modules follow particles removed or added (ForceModule::remap).
  void remap(const std::vector<std::uint32_t>& from);
  /// The checkpoint's section on a changing population (its own function, so that the
  /// format can grow beside it): the particles' radii, masses and materials (inserted
  /// particles have their own) and the insertions' and outlets' state.
  void save_population(OutArchive& a) const;
  /// Reads what save_population wrote, sizing the store to @p n particles; false when
  /// the scene's population does not change (nothing else was read).
  bool load_population(InArchive& a, std::uint64_t n);
  RunGuards guards() const;
  /// The gas is evaluated at the particles once per gas step (coupling.drag_evaluation).
  bool lagged() const { return spec_.drag_evaluation == coupling::DragEvaluation::gas_step; }
  /// The run guards on the state at time() (run_guards.hpp); @p nonfinite: the
  /// integrator's own finiteness check (1 found, 0 none), or -1 to check here.
  void check_state(double nonfinite = -1.0) const;
  /// Finish the step the integrator left pending, if any, and check the state it gives.
  void complete_step() const;
  /// complete_step() before a gas step: among ranks, only what the gas step reads of the
  /// particles is gathered.
  void complete_for_gas_step();
  void build_gas();
  /// The scene's particles' velocities, spins and masses (InitialMotion), once: into every
  /// slot, or among processes into the slots of this process's own particles, once the
  /// first build has dealt out the rows (RankSplit::hold_rows).
  void fill_motion();
  /// The scene's particles into the store, at rest and without mass, handing the scene's
  /// pages back as it goes (fill_motion gives them their motion and masses).
  void place_scene();
  /// Particle i's mass, 1/m and 1/I from its radius and its material's density.
  void set_scene_mass(std::size_t i);
  /// Under mpirun with several processes: share the particles' work among them
  /// (rank_split.hpp).
  void split_among_ranks();
  /// Every rank gets the whole state (a no-op on one rank or when nothing is stale);
  /// @p for_build: for the list build that follows (RankSplit::synchronise).
  void synchronise_ranks(bool for_build = false) const;
  /// The contact list, or nullptr for particles without contacts.
  VerletList* contact_list() const;
  void gas_step();

  SceneSpec spec_;
  ParticleStore particles_;
  std::vector<std::unique_ptr<ForceModule>> modules_;
  ContactModule* contact_ = nullptr;
  std::unique_ptr<RankSplit> ranks_;  // several MPI processes sharing the scene (split_among_ranks)
  int world_size_ = 1;                // MPI processes
  const ForceModule* gravity_ = nullptr;
  std::unique_ptr<fluid::GasField> gas_;
  coupling::DragModule* drag_ = nullptr;
  std::unique_ptr<fluid::GasSolver> solver_;
  std::unique_ptr<coupling::TwoWayExchange> exchange_;  // with a solved gas
  std::unique_ptr<coupling::ImplicitDrag> implicit_drag_;  // coupling.gas_drag = "implicit"
  std::unique_ptr<integrators::Integrator> integrator_;
  std::unique_ptr<Population> population_;  // [[insertions]], [[outlets]]
  std::uint64_t substeps_ = 1, substep_ = 0;
  coupling::GasStepClock gas_clock_;  // coupling.drag_evaluation = "gas_step": evaluation due
  std::vector<double> eps_work_;  // ε_g handed to the gas step
  double time_ = 0.0;
  std::uint64_t steps_ = 0, total_steps_ = 0;
  std::uint64_t last_sort_ = 0;  // step of the last spatial sort
  bool forces_valid_ = false;
  bool reach_stated_ = false;  // gas_follows_particles() has run (a restart's first listing builds nothing)
  bool restarted_ = false;
  bool motion_pending_ = false;  // fill_motion() still to come
};

}  // namespace cdm
