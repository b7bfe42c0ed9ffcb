#pragma once
/// @file free_fall.hpp
/// @brief Exact solution of a sphere falling onto a fixed wall with a linear
/// spring–dashpot contact: Garg et al. (2012), Powder Technology 220, App. B.
///
/// Three stages, repeated for every bounce (τ restarts at 0 in each stage):
///  - flight:  y = y0 + v0 τ − ½ g τ², contact when y = r;
///  - contact: ÿ + 2βω₀ẏ + ω₀² y = ω₀² r − g, ω₀ = √(kn/m), β = ηn/(2√(kn m)) (< 1),
///    y = [ (g/ω₀²) cos ω_d τ + ((v_c + βg/ω₀)/ω_d) sin ω_d τ ] e^(−βω₀τ) + r − g/ω₀²,
///    ω_d = ω₀√(1−β²); the contact ends at the first τ_r > 0 where y = r again, found
///    with GSL's Brent bracketing solver between the first trough and the first crest
///    of the damped oscillation (if the crest stays below r the ball never leaves);
///  - rebound: flight again from y = r with v_r = ẏ(τ_r).
/// ηn from restitution, eq 29 with m_eff = m (wall): ηn = 2√(m kn)|ln e|/√(π²+ln²e).
/// The normal force is not clipped when the dashpot makes it attractive near exit.
/// Hard-sphere apex after k bounces (Fig 5): h_max,k = (h₀ − r) e^(2k) + r.
#include <vector>

#include "cdm/oracles/tolerance.hpp"

namespace cdm::oracles {

struct FreeFallParams {
  double radius;   // r [m]
  double density;  // rho [kg/m^3]
  double h0;       // initial centre height [m], released from rest
  double g;        // gravity magnitude [m/s^2] (> 0, pointing to -y)
  double kn;       // normal stiffness [N/m]
  double en;       // restitution coefficient, (0, 1]
};

class FreeFall {
 public:
  struct Stage {
    double t_start, t_end;  // [s]; t_end = +inf for a contact the ball never leaves
    bool contact;
    double y0, v0;          // state at t_start
  };

  FreeFall(const FreeFallParams& p, double t_end);

  double position(double t) const;  // centre height y(t) [m]
  double velocity(double t) const;  // dy/dt [m/s]
  const std::vector<Stage>& stages() const { return stages_; }
  /// Maximum centre height of the flight after each bounce k = 1, 2, ... that starts
  /// before t_end: r + v_r²/(2g) (exact for the soft-sphere model).
  std::vector<double> apex_heights() const;
  static double hard_sphere_apex(const FreeFallParams& p, int k);
  double mass() const { return m_; }
  double damping() const { return eta_n_; }
  double collision_time() const;
  OracleAccuracy accuracy() const { return {0.0, root_tol_, "closed-form+gsl-brent"}; }

 private:
  const Stage& stage_at(double t) const;
  void contact_state(const Stage& s, double tau, double& y, double& v) const;

  FreeFallParams p_;
  double m_, w0_, beta_, wd_, eta_n_;
  double root_tol_ = 0.0;
  std::vector<Stage> stages_;
};

}  // namespace cdm::oracles
