#pragma once
/// @file modules.hpp
/// @brief Physics modules. A scene builds only the modules it names; each adds its
/// contribution to the particles' forces (and torques) once per force evaluation.
#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/materials.hpp"
#include "cdm/solver/neighbour_search.hpp"
#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/walls.hpp"

namespace cdm {

class ForceModule {
 public:
  virtual ~ForceModule() = default;
  virtual std::string name() const = 0;
  /// Add this module's forces for the particles' current positions and velocities.
  /// @p dt is the step the contact history advances by.
  virtual void add_forces(ParticleStore& p, double dt) = 0;
  /// State carried from step to step (contact history...), for checkpoints.
  virtual void save_state(OutArchive&) const {}
  virtual void load_state(InArchive&) {}
  /// The particles were reordered (ParticleStore::permute): slot i now holds what slot
  /// @p from[i] held. Modules that keep per-particle state reorder it alike.
  virtual void permute(const std::vector<std::uint32_t>& /*from*/) {}
};

/// Uniform gravity: F = m g.
class GravityModule final : public ForceModule {
 public:
  explicit GravityModule(Vec3 g) : g_(g) {}
  std::string name() const override { return "gravity"; }
  void add_forces(ParticleStore& p, double dt) override;

 private:
  Vec3 g_;  // [m/s^2]
};

/// Largest overlap relative to a radius seen in the last force evaluation.
struct OverlapRecord {
  double ratio = 0.0;         // overlap / radius of the smaller partner [-]
  std::uint32_t particle = 0; // particle whose radius that is
  long partner = -1;          // other particle, or -1 - wall index for a wall
};

/// Normal contact between particles and with walls, each pair of materials with its own
/// force law (PairParams::law): the linear spring–dashpot (contact/
/// linear_spring_dashpot.hpp) or Hertz–Mindlin (contact/hertz_mindlin.hpp). With
/// @p with_friction each law adds its tangential spring with history and Coulomb limit
/// (only then is tangential history kept).
///
/// The kernel is compiled once per combination of friction on/off and the laws present
/// (linear only, Hertz only, both): a scene with one law has no per-pair dispatch at
/// all, and in a mixed scene one well-predicted branch picks the law per contact. The
/// linear arithmetic is the same in every variant, so linear results do not depend on
/// which other laws a scene defines.
///
/// Contacts are found through a Verlet list: the cell-list search collects every pair
/// closer than r_i + r_j + skin, and the list is rebuilt only once some particle has
/// moved more than skin/2 since the last build — until then no pair outside the list
/// can touch. Walls likewise: only particles within r + skin of a wall at the build
/// are tested against the walls until the next build. Tangential history lives beside each listed pair (and per particle and
/// wall), and is carried across rebuilds, so the hot loop does no hashing.
///
/// Threads: at each build the domain is cut into slabs along its longest side, at least
/// one interaction range wide, and each pair belongs to the lower of its particles'
/// slabs, so it adds forces only to particles of that slab and the next. Even slabs run
/// in parallel, then odd ones; each slab is one thread's, in a fixed order. Every
/// particle therefore receives its contributions in the same order whatever the number
/// of threads: trajectories are bit-identical for 1, 2, … threads. Each thread takes one
/// contiguous run of slabs with about an equal share of their estimated cost (listed
/// pairs, those in contact at the last evaluation counted kTouchCost times more; the
/// even slabs of its run, then the odd ones): after the spatial sort its slabs'
/// particles are about its share of the integrator's pass and of the wall loop
/// (thread_range), so a thread finds in its own cache the forces and positions it works
/// on. Where the contacts crowd into a few slabs (a bed forming at the bottom of a tall
/// box) the two shares part and the cross-core traffic returns. (Slabs handed
/// out one by one as threads came free made the pass on two threads at 1e4 particles
/// three times as slow per particle: most lines came from the other core's cache.)
///
/// With @p record_normal_forces the module also keeps, for the current evaluation, each
/// contact's normal force magnitude, for modules that act through the same contacts
/// (rolling resistance).
class ContactModule final : public ForceModule {
 public:
  /// @p skin [m]: Verlet-list margin; 0 rebuilds every evaluation.
  ContactModule(PairTable pairs, std::vector<PlaneWall> walls, bool with_friction, double skin = 0.0,
                bool record_normal_forces = false);
  std::string name() const override;
  void add_forces(ParticleStore& p, double dt) override;

  const OverlapRecord& worst_overlap() const { return worst_; }
  std::size_t active_contacts() const { return n_active_; }
  /// Contacts carrying tangential history (zero when frictionless).
  std::size_t history_size() const { return friction_ ? n_active_ : 0; }
  std::size_t list_builds() const { return builds_; }
  /// The Verlet-list margin [m]: the list is rebuilt once a particle has moved half of it.
  double skin() const { return skin_; }
  /// Whether the pair loop prefetches the positions and radii of the partner 128 pairs
  /// ahead. Memory order only, never the results. `automatic` (the default) prefetches
  /// when the particles' arrays (ParticleStore::bytes) exceed the largest cache
  /// (last_level_cache_bytes): the integrator's sweep over all particles then evicts the
  /// positions before the pair loop reads them, and the loop, gathering each pair's
  /// partner while the contacts' own loads and stores come and go, loses the hardware
  /// prefetcher's streams (bench/README.md, session 19: −22 % on settle1e6's collision
  /// phase). In cache the prefetches only cost instructions (+4 % at 1e4). `on` and
  /// `off` force it, for tests and benchmarks.
  enum class Prefetch { automatic, on, off };
  void set_prefetch(Prefetch p) { prefetch_ = p; }
  /// Whether the last evaluation prefetched.
  bool prefetched() const { return prefetched_; }
  std::size_t listed_pairs() const { return pi_.size(); }
  const std::vector<PlaneWall>& walls() const { return walls_; }
  const PairTable& pairs() const { return pairs_; }
  /// Particles interact through their nearest images along the box's periodic axes.
  void set_periodic_box(const PeriodicBox& box) { box_ = box; }
  const PeriodicBox& periodic_box() const { return box_; }
  void save_state(OutArchive& a) const override;
  void load_state(InArchive& a) override;
  void permute(const std::vector<std::uint32_t>& from) override;

  /// True when the next evaluation rebuilds the Verlet list (the moment to sort).
  bool rebuild_due(const ParticleStore& p) const { return !built_ || needs_rebuild(p); }
  /// Whether a list has been built for @p n particles, so that displacement() applies.
  bool listed(std::size_t n) const { return x0_.size() == n; }
  /// Particle i's squared displacement [m^2] since the last build; along a periodic axis
  /// a particle may have wrapped since, so it is the nearest image of the jump. For an
  /// integrator that measures as it moves the particles (set_displacement); the module
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
  /// The largest displacement() over the particles, at the current positions, measured
  /// by the integrator in its own pass: the next evaluation takes it instead of a pass
  /// of its own. Used once; ignored if negative. The drift bound (displacement_needed)
  /// restarts from it: no particle is farther than its square root from its build
  /// position, so later drifts add to that instead of to the bound that called for the
  /// measure, and the steps after a measure below the margin need not measure again.
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
  /// the next evaluation, as set_displacement would, while below the margin.
  void add_drift(double d2) {
    drift_bound_ += std::sqrt(d2);
    if (drift_bound_ < drift_limit()) displacement_ = drift_bound_ * drift_bound_;
  }
  /// A spatial order of the particles (for ParticleStore::permute): by cells one
  /// interaction range wide, the slab axis slowest, so that each slab's particles, and
  /// the partners of a particle, sit close together in memory. Deterministic: ties keep
  /// the current order.
  std::vector<std::uint32_t> spatial_order(const ParticleStore& p) const;

  // The contacts of the last evaluation (record_normal_forces only).
  const std::vector<std::uint32_t>& list_i() const { return pi_; }
  const std::vector<std::uint32_t>& list_j() const { return pj_; }
  /// Listed pairs of slab s are [slab_start()[s], slab_start()[s+1]).
  const std::vector<std::uint32_t>& slab_start() const { return slab_start_; }
  /// |F_n| [N] per listed pair, or -1 where the pair is not in contact.
  const std::vector<double>& pair_normal_force() const { return fn_pair_; }
  /// |F_n| [N] per particle and wall (i * walls + w), or -1 where not in contact.
  const std::vector<double>& wall_normal_force() const { return fn_wall_; }

  /// Velocities [m/s] and angular velocities [rad/s] with which the integrator moved the
  /// particles over the last step, when they differ from the velocities forces are
  /// evaluated at (velocity Verlet: x(t+Δt) = x(t) + Δt v(t+Δt/2), forces at the
  /// predicted v(t) + Δt a(t)). Hertz–Mindlin's tangential history is incremented with
  /// these, so that it follows the contact points' actual displacement; incrementing
  /// with the predicted velocity is an O(Δt) error per step in the spring, which makes
  /// a sticking contact first order. The arrays are read at each evaluation; they are
  /// ignored until they hold one value per particle (before the first step). The
  /// linear law keeps the paper's rule (the velocity of the evaluation), unchanged.
  struct StepVelocities {
    const std::vector<double>*vx = nullptr, *vy = nullptr, *vz = nullptr;
    const std::vector<double>*wx = nullptr, *wy = nullptr, *wz = nullptr;
  };
  void set_step_velocities(StepVelocities s) { step_ = s; }
  const StepVelocities& step_velocities() const { return step_; }

 private:
  enum class Laws { linear, hertz, mixed };
  template <bool Record>
  void dispatch(ParticleStore& p, double dt);
  template <bool Friction, Laws L, bool Record>
  void add_forces_impl(ParticleStore& p, double dt);
  bool needs_rebuild(const ParticleStore& p) const;
  double drift_limit() const { return 0.49 * skin_; }
  /// How the particles' bounding box is cut into slabs (see the class comment).
  struct Slabs {
    int axis = 0;          // the cut axis (0 when nothing is cut)
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  // bounding box of the centres [m]
    double range = 0.0;    // interaction range 2 r_max + skin [m]
    std::size_t count = 1; // slabs
    double width = 1.0;    // slab width along axis [m]
  };
  Slabs slabs(const ParticleStore& p) const;
  /// The calling thread's slabs [s0, s1) in the pair loop: contiguous, with about
  /// equal shares of slab_cost_ (inside a parallel region; all outside one).
  std::pair<std::size_t, std::size_t> thread_slabs() const;
  /// Thread t's first slab of nt in thread_slabs.
  std::size_t thread_first_slab(std::size_t t, std::size_t nt) const;
  void rebuild(const ParticleStore& p);
  void list_wall_candidates(const ParticleStore& p);
  /// Fills eta_n_common_ when every free particle has the same mass, else empties it.
  void tabulate_damping(const ParticleStore& p);

  PairTable pairs_;
  std::vector<PlaneWall> walls_;
  bool friction_;
  double skin_;
  bool record_;
  Laws laws_;
  CellListSearch search_;
  PeriodicBox box_;
  // Listed pairs (i < j) in processing order: slab by slab, pairs of slab s in
  // [slab_start_[s], slab_start_[s+1]).
  std::vector<std::uint32_t> pi_, pj_, slab_start_;
  // For splitting the slabs among threads only (never the results): each slab's pairs
  // in contact at the last threaded evaluation, and the running sum of the slabs'
  // estimated cost (listed pairs + kTouchCost × those in contact).
  static constexpr std::uint64_t kTouchCost = 3;
  std::vector<std::uint32_t> slab_active_;
  std::vector<std::uint64_t> slab_cost_;
  std::vector<Vec3> hist_;              // tangential displacement per listed pair [m]
  std::vector<std::uint8_t> touch_;     // in contact at the previous evaluation
  std::vector<Vec3> wall_hist_;         // per particle and wall (i * walls + w)
  std::vector<std::uint8_t> wall_touch_;
  // Particles that may touch a wall before the next build (within r + skin of one at
  // the build, in index order), or every particle; only these are tested against walls.
  std::vector<std::uint32_t> wall_candidates_;
  // The walls candidate c may touch: wall_ids_[wall_begin_[c] .. wall_begin_[c+1]), in
  // wall order.
  std::vector<std::uint32_t> wall_begin_, wall_ids_;
  bool wall_candidates_stale_ = true;  // after load_state: list again from x0_, y0_, z0_
  std::vector<double> x0_, y0_, z0_;    // positions at the last build
  // When every free particle has one mass m (a monodisperse bed), m* takes two values,
  // m/2 and m (partner fixed), so the linear law's η_n one per material pair and kind
  // of partner: [2 (a n_materials + b) + partner fixed]. Empty otherwise; η_n is then
  // taken per contact. Tabulated at each build and after load_state.
  std::vector<double> eta_n_common_;
  bool damping_stale_ = true;
  double displacement_ = -1.0;          // see set_displacement; < 0: measure
  double drift_bound_ = 0.0;            // see displacement_needed [m]
  std::vector<double> fn_pair_, fn_wall_;     // record_: |F_n| [N] or -1
  StepVelocities step_;                       // see set_step_velocities
  Prefetch prefetch_ = Prefetch::automatic;
  bool prefetched_ = false;
  bool built_ = false;
  std::size_t builds_ = 0;
  OverlapRecord worst_;
  std::size_t n_active_ = 0;
};

/// Constant-torque rolling resistance (contact/rolling_resistance.hpp) on every contact
/// of a ContactModule, with each pair's μ_r. Runs after the contact module in the same
/// force evaluation (it must be the last module to add torques: it reads the torques
/// already accumulated, to stop a rolling contact exactly) and reads the contact
/// module's normal forces; it keeps no state of its own. Pairs are visited in the
/// contact module's slab order, so results stay independent of the thread count.
class RollingResistanceModule final : public ForceModule {
 public:
  explicit RollingResistanceModule(const ContactModule& contacts) : c_(contacts) {}
  std::string name() const override { return "rolling_resistance(constant_torque)"; }
  void add_forces(ParticleStore& p, double dt) override;

 private:
  const ContactModule& c_;
};

}  // namespace cdm
