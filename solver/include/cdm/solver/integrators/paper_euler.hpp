#pragma once
/// @file paper_euler.hpp
/// @brief The symplectic Euler step of Garg et al. (2012), eqs A.1–A.3.
#include "cdm/solver/integrators/integrator.hpp"
#include "cdm/solver/integrators/kick.hpp"

namespace cdm::integrators {

/// V += F(t)/m Δt; X += V(t+Δt) Δt; ω += T(t)/I Δt. F(t) was evaluated at the end of the
/// previous step, so the guards after a step always see the forces and overlaps of the
/// state just reached.
class PaperEuler final : public Integrator {
 public:
  explicit PaperEuler(const IntegratorParts& parts);
  double step(StepHost& host, StepTimes times) override;
  void set_ranks(RankSplit* ranks) override { ranks_ = ranks; }

 private:
  ParticleStore& p_;
  fluid::GasField* gas_;
  double dt_;
  PeriodicBox box_;
  Kick kick_;
  RankSplit* ranks_ = nullptr;  // set_ranks: the step moves this rank's particles only
};

}  // namespace cdm::integrators
