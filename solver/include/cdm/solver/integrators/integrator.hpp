#pragma once
/// @file integrator.hpp
/// @brief The interface every time integrator implements, chosen once when the
/// Simulation is built (make_integrator), and what an integrator asks of the simulation
/// it steps (StepHost). A step is dispatched once through the interface; the loops over
/// the particles inside it are each integrator's own, so nothing is dispatched per
/// particle.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <memory>
#include <vector>

#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/scene.hpp"

namespace cdm {
class ContactModule;
class RankSplit;
}

namespace cdm::integrators {

/// What the forces hold when an integrator asks for their evaluation.
enum class ForceStart {
  stale,   ///< last step's forces: cleared before the modules add theirs
  zeroed,  ///< zeroed by the integrator as it read them
  weight,  ///< set to the weight m g by the integrator: the gravity module is skipped
};

/// The simulation as an integrator sees it.
class StepHost {
 public:
  /// Evaluate forces and torques at the particles' present state, which is that of
  /// time @p t [s] (where moving walls stand), every module adding its part, starting
  /// from @p start.
  virtual void compute_forces(double t, ForceStart start = ForceStart::stale) = 0;
  /// Evaluate them unless those of the present state are held already.
  virtual void ensure_forces() = 0;
  /// Report a state found not finite at the present time (throws SimulationError).
  virtual void fail_not_finite() const = 0;

 protected:
  ~StepHost() = default;
};

/// The two ends of a step: from @c t to @c t_new.
struct StepTimes {
  double t = 0.0, t_new = 0.0;
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  /// Advance the particles from @p times.t to @p times.t_new, the forces evaluated through
  /// @p host. Returns 1 if it found the state not finite, 0 if it checked it and found it
  /// finite (or leaves it to be checked when the step is completed), −1 if it did not check.
  virtual double step(StepHost& host, StepTimes times) = 0;
  /// Finish a step whose last part was left pending (velocity Verlet's final kick), so
  /// that the particles hold the state at the step's end. Returns 1 if that state is not
  /// finite, else 0 (also when nothing was pending).
  virtual double complete() { return 0.0; }
  /// Forget a pending part: the particles were set to a complete state (a restart).
  virtual void discard_pending() {}
  /// The particles' masses may have changed.
  virtual void masses_changed() {}
  /// Reorder the integrator's per-particle arrays (slot i takes what slot @p from[i] held).
  virtual void permute(const std::vector<std::uint32_t>& /*from*/) {}
  /// Move only this MPI rank's particles (rank_split.hpp), telling @p ranks which
  /// per-particle arrays of its own a step carries.
  virtual void set_ranks(RankSplit* ranks) = 0;
};

/// What an integrator is built from: the scene, the particles, the gas (or nullptr),
/// the contact module (or nullptr) and whether a gravity module is built.
struct IntegratorParts {
  const SceneSpec& spec;
  ParticleStore& particles;
  fluid::GasField* gas = nullptr;
  ContactModule* contact = nullptr;
  bool gravity = false;
};

/// The integrator the scene names.
std::unique_ptr<Integrator> make_integrator(const IntegratorParts& parts);

/// What a step returns of the state it reached: among MPI ranks (@p ranks) 1 if any
/// rank's own particles' state is not finite, else 0 (each rank checks its own, since the
/// guards see only the last gathered state of the others'); −1 on one rank, where the
/// guards check them all.
double own_state_not_finite(RankSplit* ranks, const ParticleStore& p);

/// Wrap the position of every particle this rank moves (every particle without @p ranks)
/// into @p box (nothing where it has no periodic axis).
void wrap_positions(ParticleStore& p, const PeriodicBox& box, RankSplit* ranks);

/// Reorder those of @p arrays that hold one value per particle (@p n of them).
void permute_arrays(std::initializer_list<std::vector<double>*> arrays, std::size_t n,
                    const std::vector<std::uint32_t>& from);

}  // namespace cdm::integrators
