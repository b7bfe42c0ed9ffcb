#pragma once
/// @file run_guards.hpp
/// @brief The checks after every step that stop a run going bad (a state no longer
/// finite, a particle outside the gas, an overlap beyond its bound, a gas step too long
/// for the flow), and the diagnostic that names the particles, the time and the likely
/// cause, with the integrators' stability limits.
#include <cstdint>
#include <stdexcept>

#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/scene.hpp"

namespace cdm {

class ContactModule;
namespace coupling {
class DragModule;
}

/// A run that went unstable: names the particle(s), the time and the likely cause.
class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The largest step an explicit drag update stays stable for, in units of the particle
/// relaxation time τ_p, with integrator @p s.
double explicit_drag_step_limit(IntegratorScheme s);

class RunGuards {
 public:
  /// The parts checked: @p gas, @p contact and @p drag may be nullptr (not built).
  RunGuards(const SceneSpec& spec, const ParticleStore& particles, const fluid::GasField* gas,
            const ContactModule* contact, const coupling::DragModule* drag)
      : spec_(spec), p_(particles), gas_(gas), contact_(contact), drag_(drag) {}

  /// Throws SimulationError if the particles' state at @p time (after @p step steps) is
  /// not finite, a particle left the gas domain, or an overlap reached its bound.
  /// @p nonfinite: the integrator's own finiteness check (1 found, 0 none), or −1 to
  /// check here. @p gas_read: whether the gas read (or is about to read) the particles'
  /// positions at this step; the gas domain is checked only then.
  void check(double time, std::uint64_t step, double nonfinite = -1.0, bool gas_read = true) const;
  /// Throws SimulationError if the gas state is not finite or its Courant number above
  /// 1 after a gas step of @p dtg ending at @p time.
  void check_gas(const fluid::GasSolver& solver, double dtg, double time) const;

 private:
  const SceneSpec& spec_;
  const ParticleStore& p_;
  const fluid::GasField* gas_;
  const ContactModule* contact_;
  const coupling::DragModule* drag_;
};

}  // namespace cdm
