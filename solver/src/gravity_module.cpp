#include "cdm/solver/gravity_module.hpp"

#include "cdm/solver/own_particles.hpp"

namespace cdm {

void GravityModule::add_forces(ParticleStore& p, double /*dt*/) {
  for_own(ranks_, p.size(), [&](std::size_t i) {
    p.fx[i] += p.mass[i] * g_.x;
    p.fy[i] += p.mass[i] * g_.y;
    p.fz[i] += p.mass[i] * g_.z;
  });
}

}  // namespace cdm
