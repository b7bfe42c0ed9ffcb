#pragma once
/// @file exponential_midpoint.hpp
/// @brief An exponential midpoint step for particles moved by drag.
#include <vector>

#include "cdm/solver/integrators/integrator.hpp"

namespace cdm::integrators {

/// The exact solution of x' = v, v' = λ(u_g − v) + a with u_g, λ = K/m and a = F/m
/// frozen, taken with the coefficients of the state at mid-step (found by a first half
/// step with those of the state at t). Second order in dt and unconditionally stable
/// whatever τ_p/dt: for τ_p ≫ dt it is the midpoint rule of Newton's law, for τ_p ≪ dt
/// the midpoint rule of dx/dt = u_g (+ a τ_p), where velocity Verlet with an exact drag
/// kick falls to first order.
class ExponentialMidpoint final : public Integrator {
 public:
  explicit ExponentialMidpoint(const IntegratorParts& parts);
  double step(StepHost& host, StepTimes times) override;
  void permute(const std::vector<std::uint32_t>& from) override;
  void set_ranks(RankSplit* ranks) override { ranks_ = ranks; }

 private:
  /// Particle i advanced by @p h from the saved state at t with the present coefficients.
  void advance(std::size_t i, double h, bool impulse);

  ParticleStore& p_;
  fluid::GasField* gas_;
  double dt_;
  PeriodicBox box_;
  std::vector<double> x0_, y0_, z0_, vx0_, vy0_, vz0_;  // the state at t
  RankSplit* ranks_ = nullptr;  // set_ranks: the step moves this rank's particles only
};

}  // namespace cdm::integrators
