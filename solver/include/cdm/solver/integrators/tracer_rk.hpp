#pragma once
/// @file tracer_rk.hpp
/// @brief Massless tracers, dX/dt = u_g(X, t), by an explicit Runge–Kutta method.
#include <vector>

#include "cdm/solver/integrators/integrator.hpp"

namespace cdm::integrators {

/// The gas velocity interpolated to the tracer, integrated by the midpoint rule (rk2)
/// or the classical fourth-order Runge–Kutta (rk4). Forces play no part.
class TracerRungeKutta final : public Integrator {
 public:
  /// @p fourth_order: rk4, else rk2.
  TracerRungeKutta(const IntegratorParts& parts, bool fourth_order);
  double step(StepHost& host, StepTimes times) override;
  void permute(const std::vector<std::uint32_t>& from) override;
  void set_ranks(RankSplit* ranks) override { ranks_ = ranks; }

 private:
  ParticleStore& p_;
  fluid::GasField* gas_;  // the loader requires a gas for tracers
  double dt_;
  PeriodicBox box_;
  bool fourth_order_;
  std::vector<double> x0_, y0_, z0_, kx_, ky_, kz_;  // X at t, the weighted sum of the slopes
  RankSplit* ranks_ = nullptr;  // set_ranks: the step moves this rank's particles only
};

}  // namespace cdm::integrators
