#include "cdm/solver/gravity_module.hpp"

#include "cdm/solver/parallel.hpp"

namespace cdm {

void GravityModule::add_forces(ParticleStore& p, double /*dt*/) {
  const std::size_t n = p.size();
  parallel_for(n, [&](std::size_t i) {
    p.fx[i] += p.mass[i] * g_.x;
    p.fy[i] += p.mass[i] * g_.y;
    p.fz[i] += p.mass[i] * g_.z;
  });
}

}  // namespace cdm
