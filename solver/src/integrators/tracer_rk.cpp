#include "cdm/solver/integrators/tracer_rk.hpp"

#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/slot_pages.hpp"

namespace cdm::integrators {

TracerRungeKutta::TracerRungeKutta(const IntegratorParts& parts, bool fourth_order)
    : p_(parts.particles), gas_(parts.gas), dt_(parts.spec.dt), box_(parts.spec.periodic),
      fourth_order_(fourth_order) {}

double TracerRungeKutta::step(StepHost& /*host*/, StepTimes times) {
  ParticleStore& p = p_;
  const std::size_t n = p.size();
  const double h = dt_, t = times.t;
  if (ranks_) ranks_->mark_stale(p_);  // this rank's particles move on
  // Among ranks the others' slots read zero: their pages stay uncommitted.
  copy_changed(x0_, p.x); copy_changed(y0_, p.y); copy_changed(z0_, p.z);
  for (auto* k : {&kx_, &ky_, &kz_}) assign_zeroed(*k, n);
  // Velocity at time ts of the point X0 + c·k_prev; adds weight·k to the sum.
  auto stage = [&](double ts, double c, double weight) {
    gas_->set_time(ts);
    for_own(ranks_, n, [&](std::size_t i) {
      const Vec3 x = gas_->wrap({x0_[i] + c * p.vx[i], y0_[i] + c * p.vy[i], z0_[i] + c * p.vz[i]});
      const Vec3 k = gas_->velocity_at(x);
      p.vx[i] = k.x; p.vy[i] = k.y; p.vz[i] = k.z;  // the stage slope, kept for the next stage
      kx_[i] += weight * k.x; ky_[i] += weight * k.y; kz_[i] += weight * k.z;
    });
  };
  // p.v holds the previous stage's slope; the first stage evaluates at X0 (c = 0).
  if (!fourth_order_) {
    stage(t, 0.0, 0.0);
    stage(t + 0.5 * h, 0.5 * h, 1.0);
  } else {
    stage(t, 0.0, 1.0 / 6.0);
    stage(t + 0.5 * h, 0.5 * h, 2.0 / 6.0);
    stage(t + 0.5 * h, 0.5 * h, 2.0 / 6.0);
    stage(t + h, h, 1.0 / 6.0);
  }
  for_own(ranks_, n, [&](std::size_t i) {
    p.x[i] = x0_[i] + h * kx_[i]; p.y[i] = y0_[i] + h * ky_[i]; p.z[i] = z0_[i] + h * kz_[i];
  });
  wrap_positions(p, box_, ranks_);
  // The tracers' velocity is the gas velocity where they are now.
  gas_->set_time(t + h);
  for_own(ranks_, n, [&](std::size_t i) {
    const Vec3 u = gas_->velocity_at(p.position(i));
    p.vx[i] = u.x; p.vy[i] = u.y; p.vz[i] = u.z;
  });
  return own_state_not_finite(ranks_, p);
}

void TracerRungeKutta::permute(const std::vector<std::uint32_t>& from) {
  permute_arrays({&x0_, &y0_, &z0_, &kx_, &ky_, &kz_}, p_.size(), from);
}

}  // namespace cdm::integrators
