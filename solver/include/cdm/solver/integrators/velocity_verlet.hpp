#pragma once
/// @file velocity_verlet.hpp
/// @brief Velocity Verlet with a predicted velocity for the velocity-dependent forces.
#include <array>
#include <vector>

#include "cdm/solver/integrators/integrator.hpp"
#include "cdm/solver/integrators/kick.hpp"

namespace cdm::integrators {

/// Velocity Verlet. The dashpot makes the force depend on the velocity being updated,
/// which drops plain Verlet to first order; the force at t+Δt is evaluated with the
/// predicted velocity v(t) + Δt a(t) (error O(Δt²) in the force, O(Δt³) in the step),
/// which keeps second order.
///
/// Outside the contacts the step is memory-bound, so every pass over the particles
/// saved is a stream of the whole state saved. Where nothing but the particles reads
/// the velocities between steps, the final kick of a step is left pending and
/// done in the same pass as the next step's first half (complete() does it alone when
/// the state is read in between): one pass per step. With a gas that holds where the
/// drag's reaction is deposited once per gas step (the gas step completes the step
/// first). Otherwise two passes, each fused:
/// (half kick, drift, predicted velocity and spin, then the forces zeroed once read)
/// and (final kick and spin, and the finiteness check). Both orders do the same
/// arithmetic per particle: the results are identical.
class VelocityVerlet final : public Integrator {
 public:
  /// Gives the contact module the half-step velocities it moves positions with.
  explicit VelocityVerlet(const IntegratorParts& parts);
  double step(StepHost& host, StepTimes times) override;
  double complete() override;
  void discard_pending() override { kick_pending_ = false; }
  void masses_changed() override { one_mass_ = -1; }
  void permute(const std::vector<std::uint32_t>& from) override;
  void set_ranks(RankSplit* ranks) override;

 private:
  /// The one fused pass per step where nothing reads the velocities between steps.
  double step_deferred(StepHost& host, StepTimes times);
  /// The final half kick for every particle, into the store; 1 if the state is then
  /// not finite, else 0.
  double final_kick();

  ParticleStore& p_;
  fluid::GasField* gas_;
  ContactModule* contact_;
  double dt_;
  PeriodicBox box_;
  Vec3 g_;        // [m/s^2], applied in the pass where a gravity module is built
  bool gravity_;
  bool deferred_; // the final kick waits for the next step or a read
  int drag_kick_; // verlet::DragKick of the fused pass
  // The exact drag relaxation's φ = (1 − e^(−λΔt/2))/λ per slot and the λ it is for
  // (verlet_pass).
  std::vector<double> phi_, phi_lam_;
  Kick kick_;
  bool kick_pending_ = false;  // v, ω are the predicted ones; hv, hw and F complete them
  // Whether every particle has the same m, 1/m and 1/I (ParticleStore::same_mass): 1 yes,
  // 0 no, -1 not known (found at the next step); among MPI processes, of the process's
  // own particles as of ownership change one_for_ (RankSplit::ownership_changes). Then
  // one_values_: m, 1/m, 1/I.
  int one_mass_ = -1;
  std::uint64_t one_for_ = 0;
  std::array<double, 3> one_values_{};
  // v(t+Δt/2) and ω(t+Δt/2), kept between the half kicks.
  std::vector<double> hvx_, hvy_, hvz_, hwx_, hwy_, hwz_;
  RankSplit* ranks_ = nullptr;  // set_ranks: the passes move this rank's particles only
};

}  // namespace cdm::integrators
