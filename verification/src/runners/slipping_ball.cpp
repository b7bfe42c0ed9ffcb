/// @file slipping_ball.cpp
/// @brief Ball slipping on a rough wall (Garg et al. 2012 §3.3). The ball moves along +x
/// on a floor with normal +y; it spins about -z, and the slip velocity of its contact
/// point is s = v_x + R ω_z. The end of slip, and v and ω over the run, against the
/// closed form.
#include <cmath>
#include <limits>

#include "cdm/oracles/slipping_ball.hpp"
#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

RunOutput slipping_ball(const CaseDef& /*c*/, const Variant& v, const RunConfig& rc) {
  const SceneSpec spec = scene_for(v, rc);
  Simulation sim(spec);
  std::vector<double> t, vx, wz;
  RunOutput r = run_timed(sim, [&](const Simulation& s) {
    t.push_back(s.time());
    vx.push_back(s.particles().vx[0]);
    wz.push_back(s.particles().wz[0]);
  });
  if (rc.timing_only) return r;  // a repeat for timing: no oracle, no tables
  const oracles::SlippingParams p{v.param("radius"), v.param("v0"), v.param("mu"), v.param("g")};
  const double R = p.radius;
  r.oracle_accuracy = "closed_form";
  // End of slip: the zero of the sliding line. While the contact slides, the friction
  // force is the constant mu m g and the slip s decreases by the same amount every step;
  // the last step that still shows that decrement is extrapolated to s = 0. (Near s = 0
  // the Coulomb force flips with the sign of s, so the first sign change of s depends on
  // the integrator: velocity Verlet's predictor can hold s just above zero.)
  double ts = std::numeric_limits<double>::infinity(), vs = NAN, ws = NAN;
  auto slip = [&](std::size_t k) { return vx[k] + R * wz[k]; };
  if (t.size() > 12) {
    const double ds_ref = slip(9) - slip(10);  // sliding decrement, after the start-up steps
    for (std::size_t k = 11; k < t.size(); ++k) {
      const double ds = slip(k - 1) - slip(k);
      if (std::abs(ds - ds_ref) > 1e-2 * ds_ref || slip(k) <= 0.0) {
        const std::size_t j = k - 1;  // last step on the sliding line
        const double step = t[j] - t[j - 1];
        const double tau = slip(j) / (ds_ref / step);
        ts = t[j] + tau;
        vs = vx[j] - (vx[j - 1] - vx[j]) / step * tau;
        ws = -(wz[j] + (wz[j] - wz[j - 1]) / step * tau);
        break;
      }
    }
  }
  const double g = p.g, mu = p.mu, v0 = p.v0;
  r.measurements.push_back({"t_slip_nondim", "rel_pct", rel_pct(2.0 / 7.0, mu * g * ts / v0)});
  r.measurements.push_back({"v_slip_nondim", "rel_pct", rel_pct(5.0 / 7.0, vs / v0)});
  r.measurements.push_back({"w_slip_nondim", "rel_pct", rel_pct(5.0 / 7.0, ws * R / v0)});
  double ev = 0, ew = 0;
  TableWriter w(rc.series_path, {"t[s]", "vx[m/s]", "vx_oracle[m/s]", "omega[rad/s]", "omega_oracle[rad/s]"},
                {series_title("slipping ball", v, rc, r.dt) + "; omega = -wz (spin that rolls the ball along +x)"});
  for (std::size_t k = 0; k < t.size(); ++k) {
    const double va = oracles::slipping_velocity(p, t[k]);
    const double wa = oracles::slipping_angular_velocity(p, t[k]);
    ev = std::max(ev, rel_pct(va, vx[k]));
    ew = std::max(ew, 100.0 * std::abs(wa - (-wz[k])) * R / v0);
    w.row({t[k], vx[k], va, -wz[k], wa});
  }
  r.measurements.push_back({"v", "max_rel_pct", ev});
  r.measurements.push_back({"omega", "max_abs_pct_of_v0", ew});
  return r;
}

}  // namespace cdm::verification::runners
