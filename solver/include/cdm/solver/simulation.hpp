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
#include "cdm/solver/modules.hpp"
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
  ParticleStore& particles() { return particles_; }
  const ParticleStore& particles() const { return particles_; }
  double time() const { return time_; }
  double dt() const { return spec_.dt; }
  std::uint64_t steps() const { return steps_; }
  /// Number of steps to reach spec().end_time.
  std::uint64_t total_steps() const { return total_steps_; }
  /// Names of the modules built for this scene, in evaluation order.
  std::vector<std::string> module_names() const;
  const ContactModule* contact() const { return contact_; }

  /// Advance one time step (throws SimulationError if the state goes bad).
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
  void check_state() const;

  SceneSpec spec_;
  ParticleStore particles_;
  std::vector<std::unique_ptr<ForceModule>> modules_;
  ContactModule* contact_ = nullptr;
  double time_ = 0.0;
  std::uint64_t steps_ = 0, total_steps_ = 0;
  bool forces_valid_ = false;
  bool restarted_ = false;
  // Velocity Verlet keeps v(t+Δt/2) between the half kicks.
  std::vector<double> hvx_, hvy_, hvz_, hwx_, hwy_, hwz_;
};

}  // namespace cdm
