#pragma once
/// @file verlet_list.hpp
/// @brief The Verlet list of possible contacts, apart from the forces they carry.
///
/// The cell-list search collects every pair closer than r_i + r_j + skin, and the list
/// is rebuilt only once some particle has moved more than skin/2 since the last build:
/// until then no pair outside the list can touch. Walls likewise: only particles within
/// r + skin of a wall (Wall::reach_distance) at the build are tested against the walls
/// until the next build. A moving wall is listed again, from the build positions, once
/// its surface may have moved skin/2 since it was listed (Wall::shift_bound): a particle
/// then still comes no closer than its skin/2 of drift, the wall no closer than its own.
/// Each listed pair, and each listed particle–wall candidate, has a tangential-history
/// slot beside it, carried across rebuilds, relistings and reorderings, so the force
/// loop does no hashing. A particle has wall slots only for the walls it is listed with
/// (those within reach at the listing), not one per particle and wall: the few particles
/// near a wall pay for them, not the whole bed.
///
/// Slabs: at each build the particles' bounding box is cut into slabs along its longest
/// side (the preferred axis where it gives min_preferred_slabs slabs or is within a tenth
/// of it, else the first such side, x, y, z; along a periodic axis the period), each at least one
/// interaction range wide; a pair belongs to the lower of its particles' slabs. Along a periodic axis the slabs tile the period, an even number of
/// them and at least four, and wrap: the last slab's next is the first, and a pair across
/// the periodic faces belongs to the last slab. Even slabs may run in parallel,
/// then odd ones, each slab one thread's, in a fixed order: every particle receives its
/// contributions in the same order whatever the number of threads. Each thread takes one
/// contiguous run of slabs with about an equal share of their estimated cost (listed
/// pairs, those in contact at the last evaluation counted kTouchCost times more): after
/// the spatial sort its slabs' particles are about its share of the integrator's pass
/// (thread_range), so a thread finds in its own cache the forces and positions it works
/// on. Among MPI processes (SearchShare) the slabs are dealt out likewise, one run per
/// process, and each process holds only its slabs' pairs and those of the slab below
/// them (its shadow slab, whose pairs reach into its first slab): the list is divided.
///
/// Order: within a slab the pairs come in the order of their particles' keys (key_order:
/// the slab, the cells one interaction range wide, then the identity), each pair (i, j)
/// listed from i, the particle with the lower key at the build, its partners j in key
/// order, its history seen from i (a pair listed the other way round at a later build
/// takes the negative). None of it depends on the slots the particles sit in, so a sort,
/// or any other storage order, leaves every force's sum the same to the bit.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/contact/list_slabs.hpp"
#include "cdm/solver/neighbour_search.hpp"
#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/periodic_box.hpp"
#include "cdm/solver/walls.hpp"

namespace cdm {

class VerletList {
 public:
  /// @p skin [m]: the list's margin; 0 rebuilds at every update. With @p with_history
  /// each listed pair, and each listed particle and wall, keeps a tangential-history slot.
  VerletList(std::vector<Wall> walls, bool with_history, double skin);

  /// What update() did.
  struct Update {
    bool rebuilt = false;       // the list was built anew
    bool walls_listed = false;  // the wall candidates were listed anew
  };
  /// Make the list valid for the particles' current positions: rebuild it when due,
  /// list the wall candidates again when stale. Uses a measured displacement
  /// (set_displacement) once.
  Update update(const ParticleStore& p);

  double skin() const { return skin_; }
  /// Whether tangential history is kept (per pair, and per particle and wall).
  bool keeps_history() const { return history_; }
  /// The walls where they stand at time() (moved by their motion).
  const std::vector<Wall>& walls() const { return posed_; }
  /// Set the time [s] of the positions the next update and evaluation see: the moving
  /// walls are moved there.
  void set_time(double t);
  double time() const { return time_; }
  bool walls_move() const { return walls_move_; }      ///< whether any wall moves
  bool still_planes() const { return still_planes_; }  ///< whether every wall is a plane at rest
  /// Particles interact through their nearest images along the box's periodic axes.
  void set_periodic_box(const PeriodicBox& box) { box_ = box; }
  const PeriodicBox& periodic_box() const { return box_; }
  void prefer_slab_axis(int axis) { preferred_axis_ = axis; }  ///< the slabs' axis where it may be (cut_of)
  static constexpr std::size_t min_preferred_slabs = 8;
  std::size_t builds() const { return builds_; }
  bool built() const { return built_; }

  /// True when the next update rebuilds the list (the moment to sort).
  bool rebuild_due(const ParticleStore& p) const { return !built_ || needs_rebuild(p); }
  /// True when the next update lists a loaded list's pairs again (its build not due).
  bool relist_due(const ParticleStore& p) const;
  /// Whether a list has been built for @p n particles, so that displacement() applies.
  bool listed(std::size_t n) const { return x0_.size() == n; }
  /// Whether the list stands as the last update left it for @p p's particles: built for
  /// them, no loaded pairs or wall entries to list again, no wall moved away since
  /// (ContactModule::add_listed_forces may evaluate it as it is).
  bool current_for(const ParticleStore& p) const {
    return built_ && listed(p.size()) && !pairs_pending_ && !wall_candidates_stale_ && !wall_carry_pending_ &&
           !walls_moved_away();
  }
  /// Particle i's squared displacement [m^2] since the last build; along a periodic axis
  /// a particle may have wrapped since, so it is the nearest image of the jump. For an
  /// integrator that measures as it moves the particles (set_displacement); the list
  /// measures the same way when nobody did.
  double displacement(const ParticleStore& p, std::size_t i) const {
    return displacement(box_, {p.x[i] - x0_[i], p.y[i] - y0_[i], p.z[i] - z0_[i]});
  }
  /// displacement() of a particle that moved by @p jump [m] since the build, in @p box.
  [[gnu::always_inline]] static double displacement(const PeriodicBox& box, Vec3 jump) {
    const double dx = box.min_image(jump.x, 0), dy = box.min_image(jump.y, 1), dz = box.min_image(jump.z, 2);
    return dx * dx + dy * dy + dz * dz;
  }
  /// The positions [m] at the last build, per axis (listed(n) particles), for an
  /// integrator that measures displacement() in a loop of its own.
  const double* build_positions(int axis) const { return axis == 0 ? x0_.data() : axis == 1 ? y0_.data() : z0_.data(); }
  /// Whether the build positions are held for this process's own particles only: after
  /// a build divided among processes, whose slots of the others' particles read zero
  /// (their pages uncommitted, slot_pages.hpp) until a gather of the whole state brings
  /// them (RankSplit). displacement() then applies to the own particles alone.
  bool build_positions_own_only() const { return own_only_; }
  /// The build positions' three arrays, which RankSplit gathers whole with the state
  /// (then build_positions_whole()) and lets go of with it (build_positions_released()).
  std::vector<std::vector<double>*> build_position_arrays() { return {&x0_, &y0_, &z0_}; }
  void build_positions_whole() { own_only_ = false; }
  void build_positions_released() { own_only_ = true; }
  /// The largest displacement() over the particles, at the current positions, measured
  /// by the integrator in its own pass: the next update takes it instead of a pass of
  /// its own. Used once; ignored if negative. The drift bound (displacement_needed)
  /// restarts from it: no particle is farther than its square root from its build
  /// position, so later drifts add to that instead of to the bound that called for the
  /// measure, and the steps after a measure below the margin need not measure again.
  /// Whether the next update has a measured (or bounded) displacement to go by.
  bool displacement_known() const { return displacement_ >= 0.0; }
  void set_displacement(double d2) {
    displacement_ = d2;
    if (d2 >= 0.0) drift_bound_ = std::sqrt(d2);
  }
  /// Whether the integrator must measure displacement() this step: false while the
  /// last measure (set_displacement) plus each later step's largest drift (add_drift),
  /// or that sum since the build, stays below 0.49 skin, where the exact measure could
  /// not call for a rebuild either (the margin is far beyond rounding), so lists are
  /// built at the same steps. Unknown, so true, after load_state until the next build.
  bool displacement_needed() const { return !(drift_bound_ < drift_limit()); }
  /// For an integrator that did not measure: the largest squared drift [m^2] of any
  /// particle over the step just taken (max_i |Δt v_i|²). Bounds the displacement for
  /// the next update, as set_displacement would, while below the margin.
  void add_drift(double d2) {
    drift_bound_ += std::sqrt(d2);
    if (drift_bound_ < drift_limit()) displacement_ = drift_bound_ * drift_bound_;
  }
  /// A spatial order of the particles (for ParticleStore::permute): by slab, then by cells one
  /// interaction range wide, the slab axis slowest, then by identity (key_order): the
  /// order in which a build lists the pairs, so that each slab's particles, and the
  /// partners of a particle, sit close together in memory. It does not depend on the
  /// current order.
  std::vector<std::uint32_t> spatial_order(const ParticleStore& p) const;
  /// The particles were reordered (ForceModule::permute).
  void permute(const std::vector<std::uint32_t>& from);
  /// Particles were removed or added (ForceModule::remap): the listed pairs of removed
  /// particles are dropped and the history of the others follows them. Where particles
  /// were only removed from a built list, the list is kept: the others keep their build
  /// positions and the slabs as the build cut them, and the wall candidates are listed
  /// again. Where particles were added it is built again at the next update (carrying
  /// that history over), so that the new ones find their partners.
  void remap(const std::vector<std::uint32_t>& from, const ParticleStore& p);

  // Listed pairs (i, j), i listed first (key_order), in processing order, slab by slab.
  std::size_t size() const { return pi_.size(); }
  const std::vector<std::uint32_t>& pair_i() const { return pi_; }
  const std::vector<std::uint32_t>& pair_j() const { return pj_; }
  /// Listed pairs of slab s are [slab_start()[s], slab_start()[s+1]).
  const std::vector<std::uint32_t>& slab_start() const { return slab_start_; }
  std::size_t slab_count() const { return slab_start_.empty() ? 0 : slab_start_.size() - 1; }
  // Tangential history (with_history only): displacement [m] and whether in contact at
  // the previous evaluation, per listed pair and per listed particle and wall (entry q
  // of wall_ids()).
  Vec3* pair_history() { return hist_.data(); }
  std::uint8_t* pair_touch() { return touch_.data(); }
  Vec3* wall_history() { return wall_hist_.data(); }
  std::uint8_t* wall_touch() { return wall_touch_.data(); }
  // Particles that may touch a wall before the next build (in index order); candidate c
  // may touch walls wall_ids()[wall_begin()[c] .. wall_begin()[c+1]), in wall order.
  const std::vector<std::uint32_t>& wall_candidates() const { return wall_candidates_; }
  const std::vector<std::uint32_t>& wall_begin() const { return wall_begin_; }
  const std::vector<std::uint32_t>& wall_ids() const { return wall_ids_; }
  /// Particle @p i's entries [q0, q1) of wall_ids() (empty when it is not a candidate).
  std::pair<std::uint32_t, std::uint32_t> wall_entries(std::uint32_t i) const;
  /// Whether the wall entries are those of the current order: false from a reordering
  /// or load_state until the next update lists the candidates again.
  bool wall_entries_current() const { return !wall_carry_pending_; }
  /// Whether the wall entries list some particles only: this process's own, listed again
  /// between builds from build positions held for those alone (build_positions_own_only),
  /// or at a divided build those it owned and those of its new slabs (list_wall_candidates).
  /// The others' rows then cannot be read into them: a gather of the whole state sets the
  /// wall contacts aside first (set_aside_walls), and joins them as records.
  bool wall_entries_own_only() const { return walls_own_only_; }
  /// Sets the wall contacts aside (pending_wall_contacts) until the next update lists the
  /// candidates again, as a change of the particles' slots does.
  void set_aside_walls() {
    set_aside_wall_history(nullptr);
    wall_candidates_stale_ = true;
  }
  /// A wall contact's history, kept by particle and wall.
  struct WallContact {
    std::uint32_t i, w;  // particle, wall
    Vec3 h;              // tangential displacement [m]
    std::uint64_t key() const { return wall_key(i, w); }
    static bool by_key(const WallContact& a, const WallContact& b) { return a.key() < b.key(); }
  };
  /// While the entries are not current: the wall contacts set aside for the next
  /// listing, in (particle, wall) order (among processes, each holds its own particles'
  /// current ones; a gather joins them, RankSplit).
  std::vector<WallContact>& pending_wall_contacts() { return wall_carry_; }
  /// The wall entries in contact, in (particle, wall) order: the carried ones while
  /// pending, else the listed ones.
  std::vector<WallContact> wall_contacts() const;
  /// Every process's particles' wall contacts, in (particle, wall) order, gathered for
  /// save_state until release_contacts() (RankSplit::records_to_writer).
  void hold_wall_contacts(std::vector<WallContact> all) {
    held_walls_ = std::move(all);
    holding_walls_ = true;
  }

  // The thread split of the slabs (never the results).
  /// Before a threaded pass: each slab's estimated cost from its listed pairs and its
  /// contacts at the last threaded pass (set_slab_contacts).
  void weigh_slabs();
  /// Below the threshold nothing is split: the contacts per slab are not kept.
  void forget_slab_contacts() { slab_active_.clear(); }
  void set_slab_contacts(std::size_t s, std::size_t contacts) { slab_active_[s] = static_cast<std::uint32_t>(contacts); }
  /// The calling thread's slabs [s0, s1): contiguous, with about equal shares of the
  /// cost (inside a parallel region; all outside one).
  std::pair<std::size_t, std::size_t> thread_slabs() const;

  // The share of the slabs of this MPI rank (rank_split.hpp): its threads split
  // [first, last) only. The whole list when not set.
  void set_rank_slabs(std::size_t first, std::size_t last) {
    rank_slabs_ = {first, last};
    rank_split_ = true;
  }
  void clear_rank_slabs() { rank_split_ = false; }
  static constexpr std::size_t no_slab = static_cast<std::size_t>(-1);
  /// The slab just below this rank's share, another rank's, whose pairs reach into this
  /// rank's first slab: the contact pair loop evaluates its pairs too, in its phase, for
  /// their forces on this rank's particles (rank_split.hpp). no_slab on one rank, on a
  /// rank without slabs, and on the rank holding slab 0 unless the slabs wrap (then its
  /// shadow slab is the last, unless that is its own too).
  std::size_t shadow_slab() const {
    const auto [first, last] = rank_slabs_;
    if (!rank_split_ || first >= last) return no_slab;
    if (first > 0) return first - 1;
    return slabs_wrap() && last < slab_count() ? slab_count() - 1 : no_slab;
  }
  /// Whether the slabs of the last build wrap around a periodic axis (see the file
  /// comment): the slab below the first is the last.
  bool slabs_wrap() const { return cut_known_ && cut_.wrap; }
  /// Share the search at each build among processes (nullptr: search alone).
  void set_search_share(SearchShare* s) { share_ = s; }
  /// The slabs the pair loop visits: this rank's (set_rank_slabs), or all.
  std::pair<std::size_t, std::size_t> rank_slabs() const {
    return rank_split_ ? rank_slabs_ : std::pair<std::size_t, std::size_t>{0, slab_count()};
  }
  /// The first slab of phase @p pass (0: even slabs, 1: odd) among slabs from @p first:
  /// a phase visits it and every second slab after it.
  static std::size_t phase_first(std::size_t first, std::size_t pass) { return first + ((first & 1) != pass); }
  /// The pair loop's order over this rank's slabs: @p phase(pass, s0, s1) visits the
  /// slabs s0, s0 + 2, ... below s1, the even slabs (pass 0) and then the odd ones.
  template <class Phase>
  void by_phase(Phase&& phase) const {
    const auto [first, last] = rank_slabs();
    for (std::size_t pass = 0; pass < 2; ++pass) phase(pass, phase_first(first, pass), last);
  }
  /// Each particle's slab at the last build (the slab the build gave its pairs), from
  /// the build positions: listed(n) particles.
  std::vector<std::uint32_t> particle_slabs(const ParticleStore& p) const;
  using Slabs = ListSlabs;
  using SlabOf = cdm::SlabOf;
  /// The cut of the last build.
  const Slabs& cut() const { return cut_; }
  /// Each particle's slab in cut @p g, from the positions @p at.
  static SlabOf slab_map(const Slabs& g, const SearchPoints& at) {
    const double* const axis_data[3] = {at.x, at.y, at.z};
    return {axis_data[g.axis], g.lo[g.axis], g.width, g.count, g.wrap};
  }
  /// Before a build divided among processes that own their particles (SearchShare::
  /// own_slots), whose other particles' positions are not current here: the cut from
  /// the own particles' extents joined over the processes, the particles per slab summed,
  /// and into @p p the positions of the particles of the slabs this process searches
  /// (SearchSlabs), from their owners. The next update() builds from these; the
  /// particles of its new slabs that it did not receive then come with their positions
  /// from their owners, which only the owners read. Before a loaded list's listing
  /// (relist_due()) likewise, from the build positions of the processes' rows, in its
  /// cut; its contacts go to the processes that list their pairs. Every process calls it.
  void prepare_held_build(ParticleStore& p);
  /// spatial_order(), where the processes that share the list hold their own particles'
  /// positions only (as prepare_held_build): every process gets the whole order. Every
  /// process calls it.
  std::vector<std::uint32_t> held_spatial_order(const ParticleStore& p) const;

  /// One pair contact's history, seen from i (the pair as listed).
  struct PairContact {
    std::uint32_t i, j;  // particles
    Vec3 h;              // tangential displacement [m]
    std::uint64_t key() const { return (std::uint64_t{i} << 32) | j; }
    static bool by_key(const PairContact& a, const PairContact& b) { return a.key() < b.key(); }
  };
  /// The contacts of this process's own pairs (its slabs', not the shadow slab's, where
  /// the processes share the list; else all), in list order; the loaded ones while the
  /// pairs are not listed again (pairs_listed()), in (i, j) order: all of them, or where
  /// each process read its share (carry_partial()) those of its rows.
  std::vector<PairContact> own_contacts() const;
  bool pairs_listed() const { return !pairs_pending_; }
  /// Whether the loaded contacts are this process's share only: those whose particle i
  /// lies in its window of slots (InArchive::slot_window), the others' on the others.
  bool carry_partial() const { return pairs_pending_ && carry_partial_; }
  /// The whole list's contacts, in list order, gathered from the processes for
  /// save_state (and for list_held_again) until release_contacts().
  void hold_contacts(std::vector<PairContact> all) {
    held_ = std::move(all);
    holding_ = true;
  }
  void release_contacts() {
    std::vector<PairContact>().swap(held_);
    std::vector<WallContact>().swap(held_walls_);
    holding_ = holding_walls_ = false;
  }
  /// Drops the listed pairs: the next update lists them all again, carrying the held
  /// contacts (hold_contacts), for a copy that evaluates every contact on one process.
  /// Throws std::logic_error unless they are held.
  void list_held_again();
  /// This process's own listed pairs [k0, k1): its slabs' (not the shadow slab's) where
  /// the processes share the list, else all.
  std::pair<std::size_t, std::size_t> own_pairs() const;
  /// How the last build dealt the slabs among the processes that share the list: process
  /// r's are [rank_slab_first()[r], rank_slab_first()[r + 1]). Empty on one process.
  const std::vector<std::uint32_t>& rank_slab_first() const { return rank_slab_first_; }

  /// The list's contacts and build positions, for checkpoints: the pairs (in list order,
  /// the same on any number of processes) and the particle–wall entries (in (i, w)
  /// order) in contact, with their history, not the listed pairs, which
  /// the next update lists again from the build positions, as the build listed them
  /// (the same pairs in the same order: the search depends on the positions alone).
  /// The build flag and count are put by the caller, ahead of its own counters (the
  /// checkpoint's layout), and given back to load_state.
  void save_state(OutArchive& a) const;
  void load_state(InArchive& a, bool built, std::uint64_t builds);

 private:
  bool needs_rebuild(const ParticleStore& p) const;
  /// Lists the pairs anew from @p at, the positions of the particles of @p (their own
  /// at a build; x0_ to list again the pairs of a loaded list, which is no new build).
  void list_pairs(const ParticleStore& p, const SearchPoints& at, bool build);
  /// Where the processes share the list: deals the slabs out (rank_slab_first_) and
  /// leaves this process the candidates of its slabs and shadow slab (@p chunks, with
  /// @p slab_of each particle's slab, @p count the particles before each slab), and of
  /// @p carry the contacts of those
  /// pairs. @p whole: every process holds every contact of @p carry (loaded, or
  /// list_held_again), else each its own pairs' (collect_contacts). @p pair_slab: the
  /// slab of each pair left in @p chunks (whose positions this process may not hold).
  void divide(std::vector<std::vector<ListedPair>>& chunks, const SlabOf& slab_of,
              const std::vector<std::uint32_t>& count, std::vector<PairContact>& carry, bool whole,
              std::vector<std::uint32_t>& pair_slab);
  /// The listed pairs in contact, in list order: this process's own pairs' only
  /// (@p own, where the list is shared: not the shadow slab's), or all.
  std::vector<PairContact> collect_contacts(bool own) const;
  double drift_limit() const { return 0.49 * skin_; }
  /// The particles of slabs [@p s0, @p s1) of @p g, positions @p at, identities @p id
  /// (null: the slots), in order of their keys: the slab, the cells (edge one interaction
  /// range, the cut axis first), the identity. With @p rank (one value a slot) the rank of
  /// each particle returned, for CellListSearch::KeyedRows: its place in that order among
  /// all particles; the other slots are not written. @p before: the particles before each
  /// slab (nslab + 1 running counts), where the caller has them. @p held: where not null,
  /// the slots whose positions are read (nonzero), the others' not current.
  static std::vector<std::uint32_t> key_order(const SearchPoints& at, const std::uint32_t* id, const Slabs& g,
                                              std::size_t s0, std::size_t s1, std::uint32_t* rank,
                                              const std::vector<std::uint32_t>* before,
                                              const std::uint8_t* held = nullptr);
  Slabs slabs(const ParticleStore& p) const { return slabs(p.x.data(), p.y.data(), p.z.data(), p.radius, p.size()); }
  Slabs slabs(const double* x, const double* y, const double* z, const std::vector<double>& radius,
              std::size_t n) const {
    return cut_of(extent(x, y, z, radius.data(), n, nullptr));
  }
  /// The extent of the @p n particles at @p x, @p y, @p z with radii @p r, or of those
  /// where @p only is nonzero.
  static SlabExtent extent(const double* x, const double* y, const double* z, const double* r, std::size_t n,
                           const std::uint8_t* only);
  /// The cut of particles of extent @p e.
  Slabs cut_of(const SlabExtent& e) const;
  /// Thread t's first slab of nt in thread_slabs.
  std::size_t thread_first_slab(std::size_t t, std::size_t nt) const;
  void rebuild(const ParticleStore& p);
  /// Lists the wall candidates from @p at, every particle's positions at the build (a
  /// build or a loaded list's listing), or without it from x0_: every particle's, or
  /// where the build positions are held for the own particles only, theirs.
  void list_wall_candidates(const ParticleStore& p, const SearchPoints* at = nullptr);
  /// After a build divided among processes: x0_ takes @p at (the build's positions) for
  /// the particles of this process's slabs only, the others' slots zero. At a held build
  /// those of them whose positions this process does not hold come from their owners.
  void keep_own_build_positions(const SearchPoints& at, const SlabOf& slab_of);
  /// What prepare_held_build() leaves the next build: its cut, the particles before each
  /// slab over all processes, and per slot whether its position is current here (bit 0:
  /// the process's own particles and those it received) and whether it is this
  /// process's after the build (bit 1, set by the build: its position then in x0_).
  struct HeldBuild {
    bool ready = false;
    bool relist = false;  // the loaded pairs listed again (prepare_held_build), not a build
    Slabs cut;
    std::vector<std::uint32_t> count;
    std::vector<std::uint8_t> held;
    /// The radii of the particles entering this process's slabs that it did not search
    /// (bit 1 of held but not bit 0), by slot: their owners send them with the positions.
    std::vector<std::pair<std::uint32_t, double>> entering_radius;
    /// Particle @p i's radius at this build, from @p p where the process holds it (bit 0).
    double radius(const ParticleStore& p, std::size_t i) const;
  };
  HeldBuild held_build_;
  /// Each slab's process, as the last build dealt them out (rank_slab_first_).
  std::vector<std::uint32_t> slab_owners() const;
  /// A held build's cut (prepare_held_build) from the own particles' extents.
  Slabs held_cut(const SearchPoints& at) const;
  /// At a held build or listing of a loaded list (prepare_held_build, its slabs @p slab_of):
  /// each loaded contact (pair_carry_) to the process whose search holds both particles.
  void route_loaded_contacts(const SlabOf& slab_of);
  /// The particles before each slab of @p slab_of (nslab + 1 running counts), counted by
  /// their owners and summed.
  std::vector<std::uint32_t> held_counts(const SlabOf& slab_of, std::size_t n) const;
  /// (particle, wall) as one number, in the wall entries' order: by particle, then wall.
  static std::uint64_t wall_key(std::uint32_t i, std::uint32_t w) { return (std::uint64_t{i} << 32) | w; }
  /// Renumbers the carried contacts by @p to (old slot -> new slot, or new_particle for
  /// a particle removed).
  void renumber_pair_carry(const std::vector<std::uint32_t>& to);
  /// Sets the wall entries in contact aside for the next listing, renumbered by @p to
  /// (old slot -> new slot, or new_particle for a particle removed) unless null; the
  /// entries are dropped until then.
  void set_aside_wall_history(const std::vector<std::uint32_t>* to);
  /// The build positions follow the particles (slot i takes slot from[i]'s), and the
  /// wall candidates are listed again from them.
  void follow_build_positions(const std::vector<std::uint32_t>& from);
  /// Drops the wall entries, whose contacts wall_carry_ now holds, until the next listing.
  void drop_wall_entries();

  /// Whether a moving wall may have moved skin/2 since the candidates were listed.
  bool walls_moved_away() const;

  std::vector<Wall> walls_;  // as the scene placed them (t = 0)
  std::vector<Wall> posed_;  // at time_
  bool walls_move_ = false;
  bool still_planes_ = true;
  double time_ = 0.0;         // [s]
  double listed_time_ = 0.0;  // when the wall candidates were listed [s]
  bool history_;
  double skin_;
  CellListSearch search_;
  PeriodicBox box_;
  // Listed pairs (i, j) (key_order) in processing order: slab by slab, pairs of slab s in
  // [slab_start_[s], slab_start_[s+1]).
  std::vector<std::uint32_t> pi_, pj_, slab_start_;
  // For splitting the slabs among threads only: each slab's pairs in contact at the
  // last threaded evaluation, and the running sum of the slabs' estimated cost (listed
  // pairs + kTouchCost × those in contact: a contact's geometry and force law).
  static constexpr std::uint64_t kTouchCost = 3;
  std::vector<std::uint32_t> slab_active_;
  std::vector<std::uint64_t> slab_cost_;
  std::pair<std::size_t, std::size_t> rank_slabs_{0, 0};  // set_rank_slabs
  bool rank_split_ = false;
  SearchShare* share_ = nullptr;  // set_search_share
  std::vector<PairContact> pair_carry_;  // while pairs_pending_: the contacts to carry
  std::vector<PairContact> held_;        // hold_contacts
  bool holding_ = false;
  std::vector<WallContact> held_walls_;  // hold_wall_contacts
  bool holding_walls_ = false;
  std::vector<std::uint32_t> rank_slab_first_;  // rank_slab_first
  bool pairs_pending_ = false;          // load_state, list_held_again: listed at the next update
  bool carry_sorted_ = false;           // pair_carry_ is in (i, j) order
  bool carry_partial_ = false;          // carry_partial()
  std::vector<Vec3> hist_;              // tangential displacement per listed pair [m]
  std::vector<std::uint8_t> touch_;     // in contact at the previous evaluation
  std::vector<Vec3> wall_hist_;         // per entry of wall_ids_
  std::vector<std::uint8_t> wall_touch_;
  std::vector<std::uint32_t> wall_candidates_, wall_begin_, wall_ids_;
  std::vector<WallContact> wall_carry_;  // set_aside_wall_history, in (i, w) order
  bool wall_carry_pending_ = false;
  bool wall_candidates_stale_ = true;  // after load_state or permute: list again from x0_, y0_, z0_
  std::vector<double> x0_, y0_, z0_;    // positions at the last build
  bool own_only_ = false;               // build_positions_own_only
  bool walls_own_only_ = false;         // wall_entries_own_only
  // The slabs the pairs were listed in: cut at a build, kept when particles are removed
  // and in checkpoints, so that listing the pairs again from x0_ gives the same list.
  Slabs cut_;
  bool cut_known_ = false;
  int preferred_axis_ = -1;             // prefer_slab_axis; -1: none
  double displacement_ = -1.0;          // see set_displacement; < 0: measure
  double drift_bound_ = 0.0;            // see displacement_needed [m]
  bool built_ = false;
  std::size_t builds_ = 0;
};

}  // namespace cdm
