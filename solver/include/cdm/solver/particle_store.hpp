#pragma once
/// @file particle_store.hpp
/// @brief Particle data as structure of arrays: one contiguous array per quantity, so
/// hot loops vectorise. Rotational fields exist only when a module needs them
/// (tangential friction); a frictionless scene carries none.
#include <bit>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <type_traits>
#include <utility>
#include <vector>

#include "cdm/solver/parallel.hpp"
#include "cdm/solver/slot_pages.hpp"
#include "cdm/solver/vec3.hpp"

namespace cdm {

/// v[i] ← v[from[i]] for every i (a gather through a permutation, as
/// ParticleStore::permute applies it); @p tmp is scratch. Parallel over i. An array of
/// doubles of at least sparse_permute_slots is written into zeroed pages where the value
/// is not zero only, so that slots whose values a process does not hold (zero,
/// slot_pages.hpp) commit no memory.
template <class T>
void permute_array(std::vector<T>& v, const std::vector<std::uint32_t>& from, std::vector<T>& tmp);

/// From this many slots (512 KiB of doubles) on, permute_array commits only the pages
/// it writes values other than zero to; a smaller array (at most 512 KiB) is gathered
/// plainly.
inline constexpr std::size_t sparse_permute_slots = std::size_t{1} << 16;

/// In a map of slots after particles were removed or added (ForceModule::remap): a slot
/// that holds a new particle.
inline constexpr std::uint32_t new_particle = 0xFFFFFFFFu;

struct ParticleStore {
  // Translational state [SI].
  std::vector<double> x, y, z;     // centre position [m]
  std::vector<double> vx, vy, vz;  // velocity [m/s]
  std::vector<double> fx, fy, fz;  // force accumulated this step [N]
  std::vector<double> radius;      // [m]
  std::vector<double> mass;        // [kg]
  std::vector<double> inv_mass;    // [1/kg]
  std::vector<std::uint8_t> material;  // index into Simulation::materials (max_materials)
  // 1 where the particle is fixed (zero 1/m and 1/I), every particle's, on every MPI
  // process alike; empty while none is. Among processes each holds the masses of its own
  // particles and ghosts only (rank_split.hpp), so a build reads whether a particle is
  // fixed here.
  std::vector<std::uint8_t> fixed_flag;

  // Rotational state, allocated only when has_rotation().
  std::vector<double> wx, wy, wz;  // angular velocity [rad/s]
  std::vector<double> tx, ty, tz;  // torque accumulated this step [N m]
  std::vector<double> inv_inertia; // 1/I, I = m d^2/10 (solid sphere) [1/(kg m^2)]

  // Drag relaxation, allocated only when the drag is updated implicitly or exactly
  // (coupling/drag_module.hpp): the integrator relaxes v towards the gas velocity.
  std::vector<double> drag_k;         // drag coefficient K, F = K (u_g - v) [kg/s]
  std::vector<double> ugx, ugy, ugz;  // gas velocity at the particle [m/s]

  // Two-way coupling: the explicit drag force of the last evaluation and the drag
  // impulse since the last deposition onto the gas grid.
  std::vector<double> dfx, dfy, dfz;  // [N]
  std::vector<double> jx, jy, jz;     // [N s]

  // Spatial sorting (Simulation, neighbour_list.sort_interval) reorders the arrays; each
  // particle keeps its identity, its index in the scene. Empty until the first sort: then
  // slot i holds particle id[i]. Its inverse, the slot of each identity, is built only
  // where rows are written in identity order (IdentityOrder), not held.
  std::vector<std::uint32_t> id;  // particle identity per slot

  std::size_t size() const { return x.size(); }
  /// The scene index of the particle in slot @p i (i itself until a sort).
  std::size_t id_of(std::size_t i) const { return id.empty() ? i : id[i]; }
  /// Reorder every array: slot i takes what slot @p from[i] held (a permutation of
  /// 0..size()-1). Identities move with their particles.
  void permute(const std::vector<std::uint32_t>& from);
  /// Keep only the particles in slots @p from (increasing), compacted in that order:
  /// slot i takes what slot from[i] held. Identities are renumbered 0..from.size()-1 in
  /// the order they had, so that "by identity" stays the order of the scene and of
  /// insertion among the particles left.
  void keep(const std::vector<std::uint32_t>& from);
  /// The bytes the arrays hold (size × element size, every array this scene carries):
  /// what one sweep over all the particles' state touches.
  std::size_t bytes() const;
  bool has_rotation() const { return rotation_enabled_; }
  bool has_drag_relaxation() const { return drag_relaxation_enabled_; }
  bool has_two_way() const { return two_way_enabled_; }

  /// Switch on the rotational fields (called when a module that produces torque is built):
  /// zero angular velocities and torques, 1/I from each particle's mass as set_mass() gives
  /// it (zero for a fixed particle, or one without mass yet).
  void enable_rotation();
  /// Switch on the drag-relaxation fields (zero drag until a module fills them).
  void enable_drag_relaxation();
  /// Switch on the two-way coupling fields (drag force and impulse, zero).
  void enable_two_way();
  /// Append one particle; rotational fields get zero angular velocity if enabled. A
  /// @p fixed particle has zero inverse mass and inertia: forces act on it (its drag
  /// reaches the gas) but never move it.
  void add(Vec3 position, Vec3 velocity, double radius, double density, int material, bool fixed = false);
  /// Append one particle at rest and without mass (zero mass, 1/m and 1/I), which
  /// set_mass() gives it: a scene's particles are placed first, and each process gives
  /// masses and velocities to those it holds (Simulation::fill_motion).
  void append(Vec3 position, double radius, int material, bool fixed = false);
  /// Particle i's mass, 1/m and (with rotation) 1/I from its radius and @p density; a
  /// fixed particle's inverses zero.
  void set_mass(std::size_t i, double density);
  void set_angular_velocity(std::size_t i, Vec3 w);
  /// Room for @p n particles in every array add() appends to, its pages committed only as
  /// they are written (slot_pages.hpp): a scene's particles added one by one without the
  /// copies of arrays grown by doubling.
  void reserve(std::size_t n);

  Vec3 position(std::size_t i) const { return {x[i], y[i], z[i]}; }
  /// Particle i's volume π d³/6 [m³], d = 2 r.
  double volume(std::size_t i) const {
    const double d = 2.0 * radius[i];
    return std::numbers::pi * d * d * d / 6.0;
  }
  Vec3 velocity(std::size_t i) const { return {vx[i], vy[i], vz[i]}; }
  Vec3 angular_velocity(std::size_t i) const {
    return has_rotation() ? Vec3{wx[i], wy[i], wz[i]} : Vec3{};
  }
  /// Whether particle i's position, velocity and (with rotation) spin are all finite.
  bool state_finite(std::size_t i) const {
    return is_finite(position(i)) && is_finite(velocity(i)) && is_finite(angular_velocity(i));
  }
  void add_force(std::size_t i, Vec3 f) { fx[i] += f.x; fy[i] += f.y; fz[i] += f.z; }
  void add_torque(std::size_t i, Vec3 t) { tx[i] += t.x; ty[i] += t.y; tz[i] += t.z; }
  void clear_forces();
  /// Whether every particle has the same mass, 1/m and (with rotation) 1/I, bit for
  /// bit (a bed of one kind of particle; none fixed, or all).
  bool same_mass() const { return same_mass({{0, static_cast<std::uint32_t>(size())}}); }
  /// The same over the particles of the runs of slots [first, last) in @p runs (an MPI
  /// process's own particles).
  bool same_mass(const std::vector<std::pair<std::uint32_t, std::uint32_t>>& runs) const;
  /// Of the slots [@p first, @p last), the pages of every array of doubles whose values
  /// there are all zero go back to the system (slot_pages.hpp: they read as zero).
  void release_zero_pages(std::size_t first, std::size_t last);
  /// Whether particle i is fixed (it never moves; 1/m = 0).
  bool is_fixed(std::size_t i) const { return !fixed_flag.empty() && fixed_flag[i] != 0; }
  /// Sets fixed_flag from 1/m, which every process holds whole (the masses read from a
  /// checkpoint).
  void flag_fixed_from_masses();

 private:
  /// Particle i's 1/I from its mass and radius; zero where fixed or without mass.
  double inverse_inertia(std::size_t i) const;
  /// permute() and keep() of every array but the identities.
  void permute_state(const std::vector<std::uint32_t>& from);

  bool rotation_enabled_ = false;
  bool drag_relaxation_enabled_ = false;
  bool two_way_enabled_ = false;
};

/// The slot of each particle identity of a store: the inverse of ParticleStore::id, for a
/// pass over the particles in identity order (the rows a table, a frame or a check write).
/// Built when constructed, 4 B a particle while it lives (none before the store's first
/// sort); stale once the store is reordered.
class IdentityOrder {
 public:
  explicit IdentityOrder(const ParticleStore& p);
  /// The slot of the particle with identity @p k.
  std::size_t slot_of(std::size_t k) const { return slot_.empty() ? k : slot_[k]; }

 private:
  std::vector<std::uint32_t> slot_;
};

template <class T>
void permute_array(std::vector<T>& v, const std::vector<std::uint32_t>& from, std::vector<T>& tmp) {
  const std::size_t n = from.size();
  if constexpr (std::is_same_v<T, double>) {
    if (n >= sparse_permute_slots) {
      if (tmp.size() != n) tmp.assign(n, 0.0);
      zero_all(tmp);
      parallel_for(n, [&](std::size_t i) {
        const double s = v[from[i]];
        if (std::bit_cast<std::uint64_t>(s) != 0) tmp[i] = s;
      });
      v.swap(tmp);
      return;
    }
  }
  tmp.resize(n);
  parallel_for(n, [&](std::size_t i) { tmp[i] = v[from[i]]; });
  v.swap(tmp);
}

}  // namespace cdm
