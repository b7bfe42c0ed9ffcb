#include "cdm/solver/integrators/paper_euler.hpp"

#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/parallel.hpp"

namespace cdm::integrators {

PaperEuler::PaperEuler(const IntegratorParts& parts)
    : p_(parts.particles), gas_(parts.gas), dt_(parts.spec.dt), box_(parts.spec.periodic),
      kick_(parts.particles, parts.spec.drag_update) {}

double PaperEuler::step(StepHost& host, StepTimes times) {
  ParticleStore& p = p_;
  const std::size_t n = p.size();
  const double dt = dt_;
  host.ensure_forces();
  if (ranks_) ranks_->mark_stale(p_);  // this rank's particles move on
  for_own(ranks_, n, [&](std::size_t i) {
    kick_(i, dt, p.vx[i], p.vy[i], p.vz[i]);
    p.x[i] += dt * p.vx[i]; p.y[i] += dt * p.vy[i]; p.z[i] += dt * p.vz[i];
  });
  const bool rot = p.has_rotation();
  if (rot)
    for_own(ranks_, n, [&](std::size_t i) {
      const double b = dt * p.inv_inertia[i];
      p.wx[i] += b * p.tx[i]; p.wy[i] += b * p.ty[i]; p.wz[i] += b * p.tz[i];
    });
  wrap_positions(p, box_, ranks_);
  const double bad = own_state_not_finite(ranks_, p);
  if (gas_) gas_->set_time(times.t_new);
  host.compute_forces(times.t_new);
  return bad;
}

}  // namespace cdm::integrators
