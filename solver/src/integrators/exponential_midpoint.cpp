#include "cdm/solver/integrators/exponential_midpoint.hpp"

#include <cmath>

#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/slot_pages.hpp"

namespace cdm::integrators {

ExponentialMidpoint::ExponentialMidpoint(const IntegratorParts& parts)
    : p_(parts.particles), gas_(parts.gas), dt_(parts.spec.dt), box_(parts.spec.periodic) {}

inline void ExponentialMidpoint::advance(std::size_t i, double h, bool impulse) {
  // x(h) = x0 + v0 φ1 + u (h − φ1) + a φ2,  v(h) = v0 + (λ(u − v0) + a) φ1,
  // φ1 = (1 − e^(−λh))/λ, φ2 = (h − φ1)/λ (series for small λh: no cancellation).
  ParticleStore& p = p_;
  const double im = p.inv_mass[i], lam = im * p.drag_k[i], z = lam * h;
  double phi1, phi2;
  if (z < 1e-4) {
    phi1 = h * (1.0 - z / 2.0 + z * z / 6.0);
    phi2 = h * h * (0.5 - z / 6.0 + z * z / 24.0);
  } else {
    phi1 = -std::expm1(-z) / lam;
    phi2 = (h - phi1) / lam;
  }
  const double ax = im * p.fx[i], ay = im * p.fy[i], az = im * p.fz[i];
  p.x[i] = x0_[i] + vx0_[i] * phi1 + p.ugx[i] * (h - phi1) + ax * phi2;
  p.y[i] = y0_[i] + vy0_[i] * phi1 + p.ugy[i] * (h - phi1) + ay * phi2;
  p.z[i] = z0_[i] + vz0_[i] * phi1 + p.ugz[i] * (h - phi1) + az * phi2;
  p.vx[i] = vx0_[i] + (lam * (p.ugx[i] - vx0_[i]) + ax) * phi1;
  p.vy[i] = vy0_[i] + (lam * (p.ugy[i] - vy0_[i]) + ay) * phi1;
  p.vz[i] = vz0_[i] + (lam * (p.ugz[i] - vz0_[i]) + az) * phi1;
  if (impulse && p.has_two_way()) {
    const double m = p.mass[i];
    p.jx[i] += m * (p.vx[i] - vx0_[i]) - h * p.fx[i];
    p.jy[i] += m * (p.vy[i] - vy0_[i]) - h * p.fy[i];
    p.jz[i] += m * (p.vz[i] - vz0_[i]) - h * p.fz[i];
  }
}

double ExponentialMidpoint::step(StepHost& host, StepTimes times) {
  ParticleStore& p = p_;
  const std::size_t n = p.size();
  const double dt = dt_;
  host.ensure_forces();
  if (ranks_) ranks_->mark_stale(p_);  // this rank's particles move on
  // Among ranks the others' slots read zero in both: their pages stay uncommitted.
  copy_changed(x0_, p.x); copy_changed(y0_, p.y); copy_changed(z0_, p.z);
  copy_changed(vx0_, p.vx); copy_changed(vy0_, p.vy); copy_changed(vz0_, p.vz);
  for_own(ranks_, n, [&](std::size_t i) { advance(i, 0.5 * dt, false); });
  wrap_positions(p, box_, ranks_);
  if (gas_) gas_->set_time(times.t + 0.5 * dt);
  host.compute_forces(times.t + 0.5 * dt);  // coefficients at mid-step
  // The full step starts again from x(t), v(t) (saved above), with mid-step coefficients.
  for_own(ranks_, n, [&](std::size_t i) { advance(i, dt, true); });
  wrap_positions(p, box_, ranks_);
  const double bad = own_state_not_finite(ranks_, p);
  if (gas_) gas_->set_time(times.t_new);
  host.compute_forces(times.t_new);
  return bad;
}

void ExponentialMidpoint::permute(const std::vector<std::uint32_t>& from) {
  permute_arrays({&x0_, &y0_, &z0_, &vx0_, &vy0_, &vz0_}, p_.size(), from);
}

}  // namespace cdm::integrators
