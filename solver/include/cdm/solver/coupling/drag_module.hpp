#pragma once
/// @file drag_module.hpp
/// @brief Gas–particle force modules (Garg et al. 2012 eq 30):
///   F_i = −V_p ∇P(X_i) + β V_p/ε_s (u_g(X_i) − V_i) = F_pressure + K (u_g − V_i).
/// The two parts are separate modules, named separately in a scene:
///  - DragModule: K (u_g − V) with K from the scene's drag law (drag_laws.hpp), u_g
///    interpolated to the particle with the scene's scheme, ε_g either held at a value
///    given in the scene or taken from the grid.
///  - PressureGradientModule: −V_p ∇P, ∇P interpolated from the grid's face gradients
///    (for a gas at hydrostatic rest this is the buoyancy ρ_g V_p g).
///
/// How the drag enters the velocity update is chosen per scene (DragUpdate):
///  - explicit: the drag is one more force in the integrator — unstable once the step
///    exceeds 2τ_p with paper_euler, or τ_p with velocity_verlet (its force at t+Δt
///    uses the predicted velocity; the two-step recurrence of a linear drag has an
///    eigenvalue below −1 from Δt = τ_p on), τ_p = m/K;
///  - implicit: each kick of duration τ solves dv/dt = a + (K/m)(u_g − v) by backward
///    Euler, v ← (v + τ(a + λu_g))/(1 + λτ), λ = K/m;
///  - exponential: each kick solves it exactly with a, λ, u_g frozen,
///    v ← w + (v − w) e^(−λτ), w = u_g + a/λ.
/// Both stay bounded for any τ_p/Δt; the module then stores K and u_g per particle
/// (ParticleStore::enable_drag_relaxation) instead of adding a force.
#include <limits>

#include "cdm/solver/coupling/deposition.hpp"
#include "cdm/solver/coupling/drag_laws.hpp"
#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/fluid/gas_field.hpp"
#include "cdm/solver/force_module.hpp"

namespace cdm::coupling {

class PressureGradientModule;

/// ∇p [Pa/m] as the particle at @p x feels it, the gas's imposed mean gradient included.
/// With two-way coupling (@p kernel, the deposition that gives ε_g): the cell-centred
/// gradient (GasField::cell_gpx, …) averaged with the particle's own deposition weights,
/// the adjoint of ε_g's deposition. The gas feels −ε_f ∂p_f on each face, ε_f the mean of
/// its two cells, so the solids' share is Σ_f (1 − ε_f) V ∂p_f = Σ_c V (1 − ε_c) ∂p_c =
/// Σ_p V_p Σ_c w_pc ∂p_c: the particles take exactly the pressure force the gas's faces
/// leave to them (a fixed boundary face counts its half cell). Without a kernel: the
/// gradient interpolated from the faces (GasField::pressure_gradient_at).
Vec3 particle_pressure_gradient(const fluid::GasField& gas, const Deposition* kernel, Vec3 x);

class DragModule final : public ForceModule {
 public:
  /// @p fixed_void_fraction in (0, 1]: ε_g used in the law; 0 takes ε_g from the grid,
  /// averaged at the particle with @p kernel (the cell value without one).
  /// @p method: the paper's cell-average drag (eqs 33–35; explicit update only) or the
  /// gas velocity interpolated to each particle (eqs 30, 36). With @p two_way the explicit
  /// drag force is also kept per particle, for the reaction on the gas.
  DragModule(const fluid::GasField& gas, DragLaw law, DragUpdate update, double fixed_void_fraction,
             CouplingMethod method = CouplingMethod::interpolate, const Deposition* kernel = nullptr,
             bool two_way = false, SlipVelocity slip = SlipVelocity::interstitial)
      : gas_(&gas), law_(law), update_(update), eps_fixed_(fixed_void_fraction), method_(method), kernel_(kernel),
        two_way_(two_way), superficial_(slip == SlipVelocity::superficial) {}
  std::string name() const override;
  void add_forces(ParticleStore& p, double dt) override;
  /// Evaluate the gas at the particles only when @p clock is due, and in between apply
  /// K (u_g − v) with the K and u_g of that evaluation (coupling.drag_evaluation =
  /// "gas_step"; the interpolate method only).
  void evaluate_per_gas_step(const GasStepClock& clock) { clock_ = &clock; }
  /// With the explicit update evaluated once per gas step (after evaluate_per_gas_step):
  /// evaluate @p m's ∇P with the gas velocity, from the same interpolation stencils, into
  /// m's cache, and subtract m's force in this module's pass right after the drag (the
  /// sums m's own pass after this one gave); m's add_forces then does nothing. @p m runs
  /// once per gas step on the same clock and follows this module.
  void take_pressure_gradient(PressureGradientModule& m);
  void save_state(OutArchive& a) const override;
  void load_state(InArchive& a) override;
  void permute(const std::vector<std::uint32_t>& from) override;
  /// The cached values are dropped: evaluated again at the next force evaluation.
  void remap(const std::vector<std::uint32_t>& from, const ParticleStore& p) override;
  /// The cell-average method reads every particle's position and velocity (gathered
  /// first); the interpolation evaluates each rank's own particles. Carries the cached K
  /// and u_g.
  std::vector<std::vector<double>*> share_among(RankSplit* ranks) override {
    ranks_ = ranks;
    return {&k_, &ugx_, &ugy_, &ugz_};
  }

  /// Smallest particle relaxation time m/K seen in the last evaluation [s].
  double min_relaxation_time() const { return tau_min_; }
  /// Smallest relaxation time at zero slip, m/K(w = 0) [s], over the particles: the
  /// Stokes-regime time scale, finite whatever the velocities (for diagnostics).
  double relaxation_time_at_rest(const ParticleStore& p) const;
  DragLaw law() const { return law_; }
  DragUpdate update() const { return update_; }

 private:
  double void_fraction_at(Vec3 x) const;
  void add_cell_average(ParticleStore& p);
  /// Evaluate K and u_g at every particle; store them (relaxed update, or @p cache for the
  /// explicit update of a per-gas-step evaluation) or add the explicit force.
  void evaluate(ParticleStore& p, bool cache);
  /// The explicit force K (u_g − v) from the cached K and u_g.
  void add_cached_explicit(ParticleStore& p) const;

  const fluid::GasField* gas_;
  DragLaw law_;
  DragUpdate update_;
  double eps_fixed_;
  CouplingMethod method_;
  const Deposition* kernel_;
  bool two_way_;
  bool superficial_;  // gas velocity at the particle = interpolated flux / particle's ε_g
  ExactSums cell_vol_, cell_mom_;  // cell-average method: volume, and volume × velocity per cell
  const GasStepClock* clock_ = nullptr;          // set: evaluate once per gas step
  std::vector<double> k_, ugx_, ugy_, ugz_;      // K and u_g of that evaluation (explicit update)
  double tau_min_ = std::numeric_limits<double>::infinity();
  RankSplit* ranks_ = nullptr;  // share_among
  PressureGradientModule* grad_p_ = nullptr;  // take_pressure_gradient
};

class PressureGradientModule final : public ForceModule {
 public:
  /// @p kernel: the two-way deposition (particle_pressure_gradient), or nullptr.
  explicit PressureGradientModule(const fluid::GasField& gas, const Deposition* kernel = nullptr)
      : gas_(&gas), kernel_(kernel) {}
  std::string name() const override { return "pressure_gradient"; }
  void add_forces(ParticleStore& p, double dt) override;
  /// Evaluate ∇P at the particles only when @p clock is due; apply that force in between.
  void evaluate_per_gas_step(const GasStepClock& clock) { clock_ = &clock; }
  void save_state(OutArchive& a) const override;
  void load_state(InArchive& a) override;
  void permute(const std::vector<std::uint32_t>& from) override;
  /// The cached values are dropped: evaluated again at the next force evaluation.
  void remap(const std::vector<std::uint32_t>& from, const ParticleStore& p) override;
  /// Evaluates each rank's own particles; carries the cached force.
  std::vector<std::vector<double>*> share_among(RankSplit* ranks) override {
    ranks_ = ranks;
    return {&fx_, &fy_, &fz_};
  }

 private:
  friend class DragModule;  // DragModule::take_pressure_gradient
  /// Particle @p i's V_p ∇P from the pressure gradient @p grad_p at it.
  static Vec3 force(const ParticleStore& p, std::size_t i, Vec3 grad_p);

  const fluid::GasField* gas_;
  const Deposition* kernel_;
  RankSplit* ranks_ = nullptr;  // share_among
  const GasStepClock* clock_ = nullptr;
  std::vector<double> fx_, fy_, fz_;  // V_p ∇P of the last evaluation (per gas step)
  bool taken_ = false;  // evaluated and applied by the drag module (take_pressure_gradient)
};

}  // namespace cdm::coupling
