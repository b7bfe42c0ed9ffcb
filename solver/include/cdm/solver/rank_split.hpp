#pragma once
/// @file rank_split.hpp
/// @brief The particles' work split among MPI ranks (mpirun -np N cdm run), with results
/// identical to one rank's.
///
/// Every rank keeps a slot for every particle; each rank moves and resolves only its own. The
/// Verlet list's slabs (verlet_list.hpp) are dealt out in contiguous runs, one per rank,
/// at every build, so that the largest load (a run's listed pairs, those in contact
/// weighed more, and particles, plus the pairs of its shadow slab, below) is the least
/// (deal_slabs). A rank owns the particles
/// of its slabs (each particle's slab at the build) and the pairs listed in them, and
/// holds only those pairs and the shadow slab's (below): the list is divided among the
/// ranks (SearchShare). Within the rank its threads split its slabs as before. Per step:
///  - the integrator's pass moves the rank's own particles (velocity Verlet's, or the
///    paper's Euler step);
///  - exchange_ghosts(): each rank receives the moved state of the first slab of the
///    rank above (the pairs of its last slab reach into it) and of the last slab of the
///    rank below (the shadow slab, whose pairs reach into its first slab); where the
///    slabs wrap around a periodic axis the rank holding slab 0 has the one holding the
///    last slab below it, and two ranks may be each other's neighbours both ways;
///  - the pair loop's even phase, then its odd phase, over the rank's slabs and the
///    shadow slab: the rank evaluates the shadow slab's pairs as the rank below does, so
///    that its first slab's particles receive every contribution in the one-rank order
///    (even slabs before odd ones) without forces passing between the ranks; the
///    contributions to the other rank's particles (its ghosts) are dropped, the shadow
///    pairs' history is updated alike on both (the same arithmetic on the same state),
///    and their contacts are counted by their owner; the wall contacts follow on the
///    owner alone;
///  - the largest displacement, the worst overlap and the not-finite flag are reduced
///    over the ranks, so that every rank rebuilds, sorts and stops at the same steps.
/// The other ranks' particles go stale meanwhile. synchronise() brings every rank the
/// whole state (each rank's own particles and wall history) only where every rank reads
/// it whole (the guards naming a particle that went wrong, Simulation::particles());
/// gather() brings every rank some arrays (the positions for an insertion, and the
/// positions and impulses deposited at every step where the particles are fewer than the
/// cells they reach); what rank 0 alone writes streams to it as it writes (a checkpoint's
/// per-particle arrays, put_gathered, with the contacts kept per particle beside them,
/// records_to_writer; the particle table's and a VTK frame's rows, rows_to_writer, with
/// each rank's own particles' contact forces evaluated with its part of the list, its
/// history left as it is (ContactModule::probe_listed), its ghosts brought to the same
/// state, and its own slabs' contacts for the contact
/// network, ordered_to_writer: output_fields.hpp); what sums over the particles (the run
/// log, the monitors, the outlets' table, a gas frame's solids velocity) reads each rank's
/// own instead, added up (Simulation::counted_runs, counted_sums.hpp). The pairs' history
/// stays with the pairs' ranks, and is gathered (gather_contacts) only for the checkpoint,
/// and for a VTK frame whose list changed since the step's update (an insertion or a
/// removal between them), which is gathered to rank 0 alone (gather_to_writer) and
/// evaluated there from the whole list. Before the
/// list is built again (prepare_build, VerletList::prepare_held_build) each rank finds
/// its own particles' extent and particles per slab, joined and summed over the ranks
/// into the same slab cut on every rank (the bits one rank's would have), and sends its
/// particles' positions to the ranks whose search reads their slabs: each searches the
/// rows of a run of slabs about its share of the particles, among the particles of those
/// slabs and the slab either side (in the order of their keys, VerletList::key_order,
/// which the pairs keep), the slabs are dealt out from the pairs per slab summed over the
/// ranks, and each pair with its slab, and each pair contact's history, goes to the ranks
/// that hold its slab (VerletList::divide); a rank's new slabs' particles that it did not
/// search come with their positions from their owners, which find their particles' new
/// owners and tell the others of those that change. A sort before a build
/// (neighbour_list.sort_interval, VerletList::held_spatial_order) likewise: each slab's
/// particles are ordered by the rank whose run of rows it is in, from the others' keys
/// of their particles in it, and every rank gets every run. The first build (and the
/// first after a restart), before every particle has an owner that holds it, gathers
/// every position instead. assign() then sends each particle whose slab now
/// belongs to another rank with its whole state (the arrays below, its mass, 1/m and 1/I,
/// its row of wall history, its mesh contacts) from its old owner to its new one, in
/// rounds of a few thousand particles each let go once sent, then the ghosts (with their
/// masses, as they are new). Each
/// particle's force is thus summed in the same order as on one rank: results are
/// bit-identical. With a gas every rank holds the whole gas; the gas step's loops are
/// divided by planes (plane_share.hpp) and its multigrid pressure solve likewise
/// (pressure_multigrid.cpp), each rank then getting every plane; the drag
/// and pressure-gradient forces are evaluated by each particle's owner, and what those
/// modules keep per particle between evaluations (the K, u_g and −V∇P of a once-per-gas-step
/// evaluation) travels with the gathered state and with a particle that changes rank
/// (ForceModule::share_among). Once per gas step each rank deposits its own particles'
/// impulses and volumes, in sums that do not depend on the order of their terms
/// (exact_sums.hpp), added up over the ranks (add_up()): the gas gets the same cells on
/// any number of ranks without a gather; the cell-average drag's cell volumes and
/// velocities likewise. The implicit gas drag likewise deposits each
/// rank's own particles' K and K v, and each rank kicks its own particles after the gas
/// step (implicit_drag.hpp).
/// Deposited at every step, the impulses go the same way, the run of cells the step
/// reached added up, or every rank deposits every particle from the gathered positions
/// and impulses where that is less to send (TwoWayExchange::deposit_impulses).
///
/// Each rank finds its own particles in the outlets, every rank gets all of those
/// (share_records: slot, outlet, and with a gas each one's position and impulse) and
/// removes them alike, in slot order, and the ownership follows the compacted slots
/// (keep()). The list is kept (VerletList::remap): its pairs, build positions and slabs
/// follow the slots, and nothing else moves between the ranks. An insertion reads the
/// positions of the particles near its box, which their owners share (share_records;
/// Simulation::share_near_insertions), or where the list is not kept gathers every
/// position (gather(): the list takes its build positions from them); every rank
/// inserts the same particles, rank 0's (added()), and the list, built again at the next
/// step, deals the slabs out anew and moves the particles to their new owners. Until the next listing of the wall candidates
/// the wall contacts are set aside (VerletList::pending_wall_contacts), each rank's own
/// particles' current, and a gather joins those (share_contact_records). Until the slabs
/// are first dealt out every rank holds, moves, removes and inserts every particle, and
/// at that build, once the sort's order is found, each keeps only its run of rows of the
/// sorted order (hold_rows()); a restart instead reads each rank's run of rows (rows())
/// of the state and of the pair contacts, and each rank moves those particles until the
/// first build (hold_rows()).
///
/// The rolling resistance's pass follows the same order: the ghosts' torques arrive
/// first (the pass reads each particle's torque so far), then its two phases over the
/// rank's slabs, each followed by boundary_torques(): the torques on a boundary slab's
/// particles travel between the two ranks in the one-rank order.
///
/// Against triangle meshes each rank finds and resolves its own particles' contacts; the
/// contact lists are joined, in particle order, whenever the whole state is gathered, and
/// a particle's contacts go with it to its new owner at assign().
///
/// Every rank keeps a slot for every particle, but of the other ranks' particles (not
/// its ghosts) it holds only the identities, materials and whether each is fixed
/// (ParticleStore::fixed_flag), which never change: their other values (the positions,
/// radii and masses too) are zero and their pages are returned to the system after each
/// assign() and after a whole-state gather once the rank moves on (release_foreign(),
/// slot_pages.hpp), and a sort's or a removal's permutation commits no page of them; a
/// build writes the positions and radii it is sent (those of the slabs it searches; of
/// the particles entering its slabs that it did not search, the list keeps the radii
/// for their wall candidates, VerletList::HeldBuild), an insertion those of the particles
/// near its boxes (or every one), and the radii travel like the masses: with the state,
/// with a particle that changes owner, to a ghost once.
/// The list's build positions are held for the rank's own particles only: a divided
/// build keeps its own slabs' (VerletList::build_positions_own_only), whose slots are
/// then the rank's particles at assign(), which reads every particle's slab from the
/// positions it just built from (where the build gathered every position; else each
/// rank its own particles', and its boundary slabs' from its neighbours). The wall candidates listed again between builds are
/// the own particles' then, so a gather of the whole state joins the wall contacts as
/// records instead of rows, and brings the build positions along (for a checkpoint, or
/// for rank 0 to list the whole list's pairs again from them), let go of with the rest.
///
/// Limits: memory is divided for the pair list, the particles' state and the build
/// positions but the identities, materials and owners (each rank holds those of
/// all the particles, and the whole gas), the gas step's
/// smaller loops (ghost layers, the pressure's update, the interpolators' refresh) and a
/// direct pressure solve are done whole by each rank, a build still passes over every
/// slot (1 or 2 bytes each: the owners, which slots it holds), a sort gives every rank
/// the whole permutation (4 bytes a particle).
///
/// Particles without contacts (moved by drag alone, by any integrator, or tracers) have no
/// list, so no slabs and no ghosts: each rank holds and
/// moves a fixed run of rows of the scene's order from the first step on
/// (divide_by_rows()), and no particle ever changes rank. An insertion's particles,
/// inserted alike by every rank, are dealt out by rows of their own (added()); a removal
/// keeps the others where they are (keep()). The drag, the deposits, the outputs and the
/// checkpoints read each rank's own particles as above.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "cdm/solver/contact/mesh_contacts.hpp"
#include "cdm/solver/contact/verlet_list.hpp"
#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/particle_store.hpp"

namespace cdm {

class OutArchive;
struct OverlapRecord;
struct SceneSpec;

class RankSplit final : public SearchShare {
 public:
  /// On MPI_COMM_WORLD; nullptr when the world has one rank (or the build has no MPI).
  static std::unique_ptr<RankSplit> create();
  ~RankSplit();
  RankSplit(const RankSplit&) = delete;
  RankSplit& operator=(const RankSplit&) = delete;

  int size() const { return size_; }

  /// The per-particle arrays besides the store's that the step carries (the
  /// integrator's half-step velocities), exchanged with the store's.
  void set_extra_arrays(std::vector<std::vector<double>*> extra) { extra_ = std::move(extra); }
  /// Of those, the ones the pair loop reads of a ghost (ContactModule::set_ranks); the
  /// ghosts carry all of them until this is called.
  void set_ghost_extras(std::vector<const std::vector<double>*> read) {
    ghost_extras_ = std::move(read);
    ghost_extras_set_ = true;
  }
  /// The per-particle arrays the force modules keep between evaluations
  /// (ForceModule::share_among), which travel with the state when it is gathered and with
  /// a particle that changes rank at assign() (not with the ghosts, whose forces their
  /// owner evaluates).
  void set_carried_arrays(std::vector<std::vector<double>*> carried) { carried_ = std::move(carried); }
  /// The triangle-mesh contacts, whose list (each rank's particles' contacts between
  /// gathers) travels with the state.
  void set_meshes(MeshContacts* meshes) { meshes_ = meshes; }

  /// Whether the next build (and a sort before it) can read each process's own
  /// particles' positions only (prepare_build, VerletList::held_spatial_order): the same
  /// answer on every process, false where the whole positions are to be gathered
  /// (synchronise()) instead: before each process holds its rows (hold_rows()), or where
  /// every process holds the whole state already.
  bool holds_build(const ParticleStore& p);
  /// Where holds_build(), before a build of @p list: each process gets the positions of
  /// the particles the build's search reads from their owners
  /// (VerletList::prepare_held_build), instead of every particle's.
  void prepare_build(ParticleStore& p, VerletList& list);
  /// Deal the slabs of @p list out (after each build, or a list loaded from a
  /// checkpoint): the list's threads then split this rank's slabs only. After a build
  /// that gathered the positions only, the particles that changed owner move to their
  /// new one with their state, and the ghosts are exchanged.
  void assign(VerletList& list, ParticleStore& p);
  /// The particles were sorted (slot i now holds the particle of slot from[i]): the
  /// ownership follows them until the next assign().
  void permute(const std::vector<std::uint32_t>& from);
  /// Particles were removed from every rank's store alike (slot i now holds the particle
  /// of slot from[i]; ParticleStore::keep): the ownership and the boundary slabs' lists
  /// follow, and the rest of each rank's state stays its own.
  void keep(const std::vector<std::uint32_t>& from);
  /// @p count particles were appended to every rank's store @p p alike (the same state on
  /// each): rank 0's until the next assign() deals the slabs out; divided by rows
  /// (divide_by_rows()), each rank takes its run of rows of them and lets go of the rest.
  void added(ParticleStore& p, std::size_t count);
  /// For particles without contacts, which have no slabs and no ghosts: each rank holds
  /// and moves its run of rows (hold_rows(), no sort) for good, and takes its run of rows
  /// of an insertion's particles likewise (added()); a removal keeps the rest where they
  /// are (keep()). Called where every rank holds the whole state alike (!partitioned()).
  void divide_by_rows(ParticleStore& p);
  /// Each rank holds the state of its run of rows(p.size()) only, the rows of the order
  /// after @p from (a sort about to be made: slot i will take the particle of slot
  /// from[i]; empty, none), lets go of the other rows' state (release_foreign()), and
  /// moves its rows' particles until the first assign() sends each one's state on to its
  /// owner. Called before a build where every rank holds the whole state alike
  /// (!partitioned(): a fresh run, or particles inserted or removed before the slabs were
  /// dealt out), so that no rank holds every particle's state through the sort and the
  /// build; that build reads the positions and radii its search needs from the rows'
  /// holders (holds_build()). Called for a restart too (each rank read its rows of the
  /// checkpoint: InArchive::keep_slots): a restored list lists its pairs again from the
  /// build positions that the rows' holders send likewise (VerletList::prepare_held_build).
  void hold_rows(ParticleStore& p, const std::vector<std::uint32_t>& from);
  /// Whether ownership follows build number @p builds of the list.
  bool assigned_for(std::uint64_t builds) const { return assigned_ && !moving_ && !held_rows_ && builds == builds_; }

  /// This rank's particles as runs of slots [first, last); all @p n of them until the
  /// first assign() (every rank then holds and moves the same whole state).
  const std::vector<std::pair<std::uint32_t, std::uint32_t>>& own_runs(std::size_t n) {
    if (!assigned_) runs_.assign(1, {0, static_cast<std::uint32_t>(n)});
    return runs_;
  }
  /// 1 where slot i is this rank's particle.
  const std::vector<std::uint8_t>& owned() const { return owned_; }
  /// Whether @p found(first, last) holds for a run of this rank's particles (of @p n), on
  /// any rank.
  template <class Found>
  bool any_own(std::size_t n, Found&& found) {
    bool hit = false;
    for (const auto& [i0, i1] : own_runs(n))
      if (!hit) hit = found(std::size_t{i0}, std::size_t{i1});
    return any(hit);
  }

  /// After the integrator's pass: receive the first slab of the rank above and the last
  /// of the rank below (the shadow slab, VerletList::shadow_slab). @p with_masses: their
  /// masses, 1/m and 1/I too (after a migration, when the ghosts are new).
  void exchange_ghosts(ParticleStore& p, bool with_masses = false);
  /// Counts the changes of which particles this rank owns (assign(), hold_rows(),
  /// added(), keep()): what is cached over a rank's own particles is stale when it moves.
  std::uint64_t ownership_changes() const { return ownership_changes_; }
  /// After phase @p pass (0 even, 1 odd) of the rolling resistance's pair loop: the
  /// boundary slabs' torques move on in the one-rank order. Called from one thread.
  void boundary_torques(ParticleStore& p, int pass);
  /// Before the rolling resistance's pass, which reads the torques accumulated so far:
  /// receive the ghosts' torques, complete with their contacts and walls.
  void exchange_ghost_torques(ParticleStore& p);

  /// Every rank gets the whole state: every particle's and the wall history of the
  /// particles (not the pairs', which stay divided). A no-op while nothing is stale.
  /// @p for_build: the list is built next, which reads the positions only, so only those
  /// are sent; assign() then moves the rest with the particles that change owner.
  /// @p list: nullptr for particles without contacts.
  void synchronise(ParticleStore& p, VerletList* list, bool for_build = false);
  /// Rank 0, which writes what reads the whole state (a VTK frame whose list changed since
  /// the step's update: output_fields.hpp), gets all of it as
  /// synchronise() gives every rank; the others send
  /// their own particles and keep their state as it is. Called on every rank alike; a
  /// no-op while rank 0 holds the whole state already. @p list: nullptr without contacts.
  void gather_to_writer(ParticleStore& p, VerletList* list);
  /// Whether rank 0 holds every particle's current state (each rank moves every particle,
  /// or the state was gathered since the last step); the same on every rank.
  bool writer_holds_all() const { return !assigned_ || !stale_ || written_; }
  /// For a checkpoint whose per-particle arrays stream to rank 0 (put_gathered): rank 0
  /// gets what the particles carry besides them, their wall contacts (held by @p list
  /// until VerletList::release_contacts) and mesh contacts. Called on every rank alike; a
  /// no-op where writer_holds_all().
  void records_to_writer(VerletList& list);
  /// Writes @p v, a per-particle array, into @p a as OutArchive::put does: rank 0 gathers
  /// it in rounds of round_values() slots, each rank sending its own particles' values,
  /// and writes each round in slot order. Called on every rank alike (the others' @p a
  /// counts only), where !writer_holds_all().
  void put_gathered(OutArchive& a, const std::vector<double>& v);
  /// Rank 0 gets, for each particle k < @p n in turn (its slot @p slot_of(k)), the values
  /// of @p arrays, each from the particle's owner, and passes them to @p row(k, values):
  /// gathered round_values() values at a time. Called on every rank alike, where
  /// !writer_holds_all(); @p row is called on rank 0 only.
  void rows_to_writer(const std::vector<const std::vector<double>*>& arrays, std::size_t n,
                      const std::function<std::size_t(std::size_t)>& slot_of,
                      const std::function<void(std::size_t, const double*)>& row);
  /// Rank 0 gets each rank's @p count records of @p bytes each at @p data, rank after
  /// rank (its own first), round_values() doubles' worth at a time, and passes each piece
  /// to @p push(records, count) in that order; the other ranks pass none. For what each
  /// rank holds of its own slabs in the one-rank order (the contact network), written by
  /// rank 0 without holding it all. Called on every rank alike.
  void ordered_to_writer(const void* data, std::size_t count, std::size_t bytes,
                         const std::function<void(const void*, std::size_t)>& push);
  /// Every rank gets every particle's values of @p arrays (per-particle arrays), each
  /// from the rank that owns it; nothing else changes.
  void gather(const std::vector<std::vector<double>*>& arrays);
  /// The ranks' particles diverged (a step was taken). Where this rank got the whole
  /// state since (synchronise(), gather_to_writer()), what it holds of the other ranks'
  /// particles is let go (release_foreign()).
  void mark_stale(ParticleStore& p) {
    if (gathered_ && assigned_) release_foreign(p);
    stale_ = assigned_;
    written_ = false;
  }
  /// The particles' slots changed on every rank alike (particles were inserted or
  /// removed from the whole, gathered state): each rank moves all of them again until
  /// the next assign().
  void unassign() { assigned_ = stale_ = moving_ = written_ = held_rows_ = false; }

  /// The largest of @p x over the ranks.
  double max(double x) const;
  /// Each element of @p v becomes its largest over the ranks.
  void max(std::vector<double>& v) const;
  /// The worst overlap over the ranks (the one-rank choice among ties: contact::worse_overlap)
  /// and the sum of the active contacts.
  void reduce_contacts(OverlapRecord& worst, std::size_t& active) const;
  /// Whether @p flag is set on any rank.
  bool any(bool flag) const;
  /// Whether each particle is one rank's own (after assign(); before it, every rank
  /// moves every particle).
  bool partitioned() const { return assigned_; }
  /// Every rank gets the sums of @p s over the ranks (each rank's partial sums of the
  /// same terms' bound).
  void add_up(ExactSums& s) const;
  /// The same for integer sums packed by the caller (a part of an ExactSums' data()).
  void add_up(std::vector<std::int64_t>& v) const;
  /// add_up() of two sets of sums (of bounds of their own), in one reduction.
  void add_up(ExactSums& a, ExactSums& b) const;
  /// Every rank gets every rank's records: @p keys (distinct over the ranks, each rank's
  /// increasing) in increasing order, each with its @p per values in @p values, moved
  /// along. For what each rank finds among its own particles and every rank then applies
  /// alike, in the one-rank order.
  void share_records(std::vector<std::uint64_t>& keys, std::vector<double>& values, std::size_t per) const;

  /// This rank's run of @p n rows (the r-th of size() equal runs): what it reads of a
  /// checkpoint at a restart.
  std::pair<std::size_t, std::size_t> rows(std::size_t n) const { return row_run(n, rank_); }
  // The contact search and list at a build (SearchShare): each pair goes to the ranks
  // that hold its slab.
  int share_rank() const override { return rank_; }
  int share_size() const override { return size_; }
  const std::uint8_t* own_slots() const override { return assigned_ ? owned_.data() : nullptr; }
  void sum(std::vector<std::uint64_t>& v) override;
  std::vector<std::uint32_t> swap_values(std::vector<std::vector<std::uint32_t>>& out) override;
  std::vector<double> swap_values(std::vector<std::vector<double>>& out) override;
  /// Rank 0 gets the contacts of the whole list (each rank's own pairs'), in the
  /// one-rank list's order; the others nothing: for the checkpoint and the output probes,
  /// which rank 0 writes.
  std::vector<VerletList::PairContact> gather_contacts(const VerletList& list);

  /// The send and receive buffers of the exchanges with the neighbouring ranks, one per
  /// message, kept between steps.
  struct LegBuffers {
    std::vector<std::vector<double>> out, in;
  };
  /// The values that travel with each particle besides its arrays' (its row of wall
  /// history: x, y, z and the contact flag per wall): @p put writes a particle's
  /// @p count values, @p get reads them back.
  struct WallRows {
    std::size_t count = 0;
    std::function<void(std::uint32_t, double*)> put;
    std::function<void(std::uint32_t, const double*)> get;
  };

 private:
  RankSplit(int rank, int size) : rank_(rank), size_(size) {}
  /// The per-particle arrays exchanged (the store's positions, velocities, forces,
  /// spins, radii, masses, 1/m and 1/I and drag values; and extra_), and @p with_carried
  /// carried_.
  std::vector<std::vector<double>*> dynamic_arrays(ParticleStore& p, bool with_carried = false) const;
  /// What the pair loop reads of a ghost: its position, velocity, spin and the extra_
  /// arrays it reads (set_ghost_extras: the integrator's step velocities, for
  /// Hertz–Mindlin friction and rolling resistance); not its forces (its owner sums
  /// them) nor the drag's values (its owner evaluates the drag).
  std::vector<std::vector<double>*> ghost_arrays(ParticleStore& p) const;

  /// Zero the per-particle state, positions and radii included, of the slots that are
  /// neither this rank's particles nor its ghosts, and the list's build positions of all
  /// but its own, and return their pages (slot_pages.hpp): a rank's memory for that state
  /// follows its own particles. The rank no longer holds the whole state (stale_).
  void release_foreign(ParticleStore& p);
  /// Every rank, or with @p to_writer rank 0 alone, gets the whole state (synchronise(),
  /// gather_to_writer()): every particle's arrays, @p list's build positions where a rank
  /// holds its own particles' only, the wall history (as rows, or as records where the
  /// entries list the own particles only: VerletList::wall_entries_own_only) and the
  /// contacts kept per particle; the arrays alone where there is no @p list.
  void share_whole_state(ParticleStore& p, VerletList* list, bool to_writer);

  /// Rank @p r's run of rows of @p n: the r-th of size() equal runs.
  std::pair<std::size_t, std::size_t> row_run(std::size_t n, int r) const {
    const auto k = static_cast<std::size_t>(r), m = static_cast<std::size_t>(size_);
    return {n * k / m, n * (k + 1) / m};
  }

  int rank_, size_;
  std::vector<std::vector<double>*> extra_, carried_;
  std::vector<const std::vector<double>*> ghost_extras_;  // set_ghost_extras
  bool ghost_extras_set_ = false;
  MeshContacts* meshes_ = nullptr;
  VerletList* list_ = nullptr;  // the list assign() dealt out, whose build positions release_foreign() lets go of
  bool assigned_ = false, stale_ = false;
  bool moving_ = false;  // positions gathered for a build: the owners change at assign()
  bool held_rows_ = false;  // hold_rows(): the owners change at assign()
  bool by_rows_ = false;  // divide_by_rows(): the owners never change
  bool held_build_ = false;  // prepare_build(): each process holds its own particles' positions only
  bool written_ = false;  // rank 0 holds the whole state (gather_to_writer) though stale_
  bool gathered_ = false;  // this rank got the whole state since release_foreign()
  std::uint64_t builds_ = 0;
  std::uint64_t ownership_changes_ = 0;  // ownership_changes
  /// A particle's owner: 2 bytes a slot on every rank (create() refuses more ranks).
  using Owner = std::uint16_t;
  std::vector<int> slab_owner_;                      // per slab
  std::vector<Owner> owner_;                         // per particle slot
  std::vector<std::uint32_t> slab_first_;            // per rank: first slab (size_ + 1 entries)
  std::vector<std::pair<std::uint32_t, std::uint32_t>> runs_;
  std::vector<std::uint8_t> owned_;
  // The lower boundary: this rank's first slab (sent down), shared with rank below_;
  // the upper one: the first slab of rank above_ (ghosts).
  std::vector<std::uint32_t> lower_, upper_;
  // This rank's last slab (sent up) and the rank below's last, the shadow slab (ghosts).
  std::vector<std::uint32_t> top_, under_;
  int below_ = -1, above_ = -1;
  bool lower_odd_ = false, upper_odd_ = false;  // parity of the boundary slab
  /// Every rank, or with @p to_writer rank 0 alone, gets every rank's records of @p list
  /// (trivially copyable, each naming its particle: particle_of(record)), its own
  /// particles', in the order @p less.
  template <class Record, class ParticleOf, class Less>
  void join_own(std::vector<Record>& list, ParticleOf&& particle_of, Less&& less, bool to_writer);
  /// join_own() for the contacts kept per particle outside the arrays: the mesh contacts
  /// (meshes_), and the wall contacts of @p list where they are set aside.
  void share_contact_records(VerletList& list, bool to_writer = false);
  /// No boundary slabs and no neighbouring ranks, until assign() finds them.
  void drop_boundaries();
  /// This rank's particles' runs and flags from owner_.
  void own_from_owners();
  /// After a held build (prepare_build): owner_ from @p before, each process finding its
  /// own particles' new owners from their positions (the build's) and telling the
  /// others of those that change.
  void new_owners(const VerletList& list, const ParticleStore& p, const std::vector<Owner>& before);
  /// After a held build: this rank's boundary slabs (its slabs [@p s0, @p s1)' first and
  /// last) from its own particles' build positions, and the ghost slabs from the
  /// neighbouring ranks, which hold theirs.
  void boundaries_from_neighbours(const VerletList& list, std::uint32_t s0, std::uint32_t s1);
  /// The particles whose owner was @p before and is owner_ now travel with their state.
  void migrate(ParticleStore& p, VerletList& list, const std::vector<Owner>& before);
  /// migrate()'s mesh contacts: each moving particle's go with it.
  void migrate_mesh_contacts(const std::vector<Owner>& before);
  /// Sends out[r] to rank r (released) and returns what each rank sent, in rank order.
  std::vector<std::uint8_t> swap_bytes(std::vector<std::vector<std::uint8_t>>& out);
  /// Every rank, or with @p to_writer rank 0 alone, gets each rank's particles' values
  /// of @p arrays and, after them, their @p rows.
  void share_particles(const std::vector<std::vector<double>*>& arrays, const WallRows& rows, bool to_writer = false);
  // The buffers of a gather's rounds: at most round_values() values each, kept between
  // gathers, so that they add that much to every rank's memory whatever its size:
  // kRoundValues (2 MiB), or the environment's CDM_MPI_ROUND_VALUES (a positive integer,
  // for tests: a small scene gathered in many rounds; the results do not depend on it).
  static constexpr std::size_t kRoundValues = std::size_t{1} << 18;
  static std::size_t round_values();
  std::vector<double> send_, recv_;
  /// A round's gather: each rank's send_ (@p counts[r] values from rank r) into rank 0's
  /// recv_, in rank order; @p next[r] is where rank r's values begin in recv_.
  void gather_round(const std::vector<int>& counts, std::vector<std::size_t>& next);
  /// The rows of @p list's wall history, where it keeps one for @p n particles.
  static WallRows wall_rows(VerletList& list, std::size_t n);
  LegBuffers legs_;
};

}  // namespace cdm
