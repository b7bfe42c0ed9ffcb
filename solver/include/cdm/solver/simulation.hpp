#pragma once
/// @file simulation.hpp
/// @brief A Simulation holds the particles and the modules a scene named, and advances
/// them with the scene's integrator. Data flow per step: forces (each module adds its
/// part) → integrator update → guards (finite state, overlap bound) → observers.
#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/coupling/drag_module.hpp"
#include "cdm/solver/fluid/gas_field.hpp"
#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/scene.hpp"

namespace cdm {

/// A run that went unstable: names the particle(s), the time and the likely cause.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Simulation {
 public:
  /// Builds the scene's modules and particles; the per-particle list of @p spec is
  /// dropped once the particles are in the store (pass an rvalue to avoid a copy).
  explicit Simulation(SceneSpec spec);

  const SceneSpec& spec() const { return spec_; }
  /// The particles at time(). Reading them completes the last step where its final
  /// kick was left pending (see step()); a state that went non-finite in that step is
  /// reported here then (SimulationError).
  ParticleStore& particles() {
    complete_step();
    one_mass_ = -1;  // the caller may change masses
    return particles_;
  }
  const ParticleStore& particles() const { complete_step(); return particles_; }
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
  /// Particle steps per gas step (1 without a solved gas).
  std::uint64_t substeps() const { return substeps_; }
  /// Momentum exchanged through drag over the last gas step [N s]: what the particles
  /// received and what the gas received (on the unknown faces of the grid).
  struct CouplingBalance { Vec3 particles, gas_cells, gas_faces; };
  const CouplingBalance& coupling_balance() const { return balance_; }
  const coupling::DragModule* drag() const { return drag_; }

  /// Advance one time step (throws SimulationError if the state goes bad). With
  /// velocity Verlet and no gas, the step's final half kick (the velocities and spins
  /// at the new time) is done lazily: in the same pass as the next step's first half,
  /// or when the particles are read, whichever comes first. Either way the arithmetic
  /// is the same, so results do not depend on when the state is read.
  void step();
  /// Run to end_time, calling @p observer at t = 0 (not after a restart) and after every
  /// step; @p stop is polled after each step and ends the run early when it returns true.
  void run(const std::function<void(const Simulation&)>& observer = {},
           const std::function<bool()>& stop = {});

  /// Everything that changes from step to step, for checkpoints (archive.hpp).
  void save_state(OutArchive& a) const;
  /// Restore a saved state into a Simulation built from the same scene; throws
  /// ArchiveError if the state does not fit this scene.
  void load_state(InArchive& a);
  bool restarted() const { return restarted_; }

 private:
  void compute_forces();
  /// Sort the particles spatially when neighbour_list.sort_interval asks for it and
  /// the contact list is about to be rebuilt.
  void sort_if_due();
  /// Reorder every per-particle array, the particles' and the modules' (slot i takes
  /// what slot @p from[i] held).
  void permute(const std::vector<std::uint32_t>& from);
  /// @p nonfinite: the integrator's own finiteness check (1 found, 0 none), or -1 to check here.
  void check_state(double nonfinite = -1.0) const;
  void step_tracers();
  /// The final half kick for every particle, into the store; 1 if the state is then
  /// not finite, else 0.
  double final_kick() const;
  /// kick() as a callable (i, τ, vx, vy, vz, impulse), for the per-particle Verlet steps.
  auto kick_fn() const;
  /// Do the pending final kick, if any, and check the state it gives.
  void complete_step() const;
  /// Kick particle i's velocity by the forces over @p tau, with the drag relaxation
  /// solved implicitly or exactly when the scene asks for it (drag_module.hpp).
  /// With @p impulse the drag impulse of the kick is added to the particle's two-way
  /// accumulator (not for the velocity predictor of velocity Verlet).
  void kick(std::size_t i, double tau, double& vx, double& vy, double& vz, bool impulse = true) const;
  /// kick() for particles whose drag is relaxed implicitly or exactly.
  void kick_relaxed(std::size_t i, double tau, double& vx, double& vy, double& vz, bool impulse) const;
  void wrap_positions();
  void build_gas();
  /// ε_g on the cells from the particles' volumes (deposition kernel); stops the run if
  /// a cell is packed beyond what the gas equations can take.
  void deposit_void_fraction(std::vector<double>& eps) const;
  /// Move the particles' drag impulses onto the grid (as the reaction on the gas).
  void deposit_impulses();
  void gas_step();

  SceneSpec spec_;
  // Mutable: the final kick a step leaves pending is done when the particles are read.
  mutable ParticleStore particles_;
  std::vector<std::unique_ptr<ForceModule>> modules_;
  ContactModule* contact_ = nullptr;
  const ForceModule* gravity_ = nullptr;
  std::unique_ptr<fluid::GasField> gas_;
  coupling::DragModule* drag_ = nullptr;
  std::unique_ptr<fluid::GasSolver> solver_;
  std::unique_ptr<coupling::Deposition> deposition_;
  std::uint64_t substeps_ = 1, substep_ = 0;
  std::vector<double> imp_x_, imp_y_, imp_z_;  // drag reaction on the gas per cell [N s]
  std::vector<double> eps_work_;
  Vec3 particle_impulse_;  // Σ drag impulse on the particles since the gas step began
  CouplingBalance balance_;
  double time_ = 0.0;
  std::uint64_t steps_ = 0, total_steps_ = 0;
  std::uint64_t last_sort_ = 0;  // step of the last spatial sort
  bool forces_valid_ = false;
  bool forces_zeroed_ = false;  // the integrator zeroed forces and torques as it read them
  bool forces_hold_gravity_ = false;  // velocity Verlet's one pass applied gravity: gravity_ is skipped once
  bool deferred_kick_ = false;  // velocity Verlet without gas: the final kick waits (step())
  mutable bool kick_pending_ = false;  // v, ω are the predicted ones; hv, hw and F complete them
  // Whether every particle has the same m, 1/m and 1/I (ParticleStore::same_mass): 1 yes,
  // 0 no, -1 not known (found at the next step).
  int one_mass_ = -1;
  bool restarted_ = false;
  // Velocity Verlet keeps v(t+Δt/2) between the half kicks (mutable: with the pending
  // kick, part of the state that the const complete_step() completes).
  mutable std::vector<double> hvx_, hvy_, hvz_, hwx_, hwy_, hwz_;
  // Tracer Runge–Kutta stages (rk2, rk4).
  std::vector<double> x0_, y0_, z0_, kx_, ky_, kz_;
};

}  // namespace cdm
