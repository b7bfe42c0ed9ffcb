/// @file initial_motion.cpp
/// @brief The particles' initial velocities and spins from their groups; a lattice's stream.
#include "cdm/solver/initial_motion.hpp"

#include <stdexcept>

#include "cdm/solver/scene.hpp"

namespace cdm {

LatticeDraws::LatticeDraws(const SizeDistribution& size, double jitter, std::uint64_t seed)
    : size_(size), jitter_(jitter), rng_(seed) {}

LatticeDraws::Site LatticeDraws::next() {
  Site s;
  s.radius = size_.sample(rng_);
  if (jitter_ > 0.0) {
    const double a = uniform01(rng_) * 2.0 - 1.0, b = uniform01(rng_) * 2.0 - 1.0, c = uniform01(rng_) * 2.0 - 1.0;
    s.jitter = Vec3{jitter_ * a, jitter_ * b, jitter_ * c};
  }
  return s;
}

InitialMotion::InitialMotion(const std::vector<ParticleGroup>& groups) : groups_(groups) { enter(0); }

void InitialMotion::enter(std::size_t g) {
  group_ = g;
  index_ = 0;
  draws_.reset();
  if (g < groups_.size() && groups_[g].jitter > 0.0)
    draws_.emplace(groups_[g].size, groups_[g].jitter, groups_[g].seed);
}

InitialMotion::Motion InitialMotion::next() {
  while (group_ < groups_.size() && index_ == groups_[group_].count) enter(group_ + 1);
  if (group_ == groups_.size()) throw std::logic_error("InitialMotion: more particles than the groups hold");
  const ParticleGroup& g = groups_[group_];
  Motion m{g.velocity, g.angular_velocity};
  if (draws_) m.velocity += draws_->next().jitter;
  ++index_;
  return m;
}

}  // namespace cdm
