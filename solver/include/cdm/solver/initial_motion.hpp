#pragma once
/// @file initial_motion.hpp
/// @brief The scene's particles' velocities and spins at the start, from their groups
/// (ParticleGroup), and a lattice's one stream of numbers (LatticeDraws) that gives its
/// sites' radii to the loader and their velocities' jitter to the run.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <random>
#include <vector>

#include "cdm/solver/size_distribution.hpp"
#include "cdm/solver/vec3.hpp"

namespace cdm {

struct ParticleGroup;

/// A lattice's stream of numbers, seeded by its seed: per site, in the lattice's order
/// (x fastest), its radius drawn from the size distribution, then, where the lattice has
/// a velocity jitter, three uniform numbers in [-1, 1) that scale it, one per component.
class LatticeDraws {
 public:
  LatticeDraws(const SizeDistribution& size, double jitter, std::uint64_t seed);
  struct Site {
    double radius = 0.0;  // [m]
    Vec3 jitter;          // added to the lattice's velocity [m/s]
  };
  Site next();

 private:
  const SizeDistribution& size_;
  double jitter_;
  std::mt19937_64 rng_;
};

/// The particles' initial velocities and spins in the scene's order (the groups cover the
/// particles in order): next() gives particle 0's, then 1's, and so on. A lattice's
/// jittered velocities are drawn again from its stream, so the scene need not hold them.
class InitialMotion {
 public:
  explicit InitialMotion(const std::vector<ParticleGroup>& groups);
  struct Motion {
    Vec3 velocity;          // [m/s]
    Vec3 angular_velocity;  // [rad/s]
  };
  Motion next();

 private:
  void enter(std::size_t g);
  const std::vector<ParticleGroup>& groups_;
  std::size_t group_ = 0, index_ = 0;  // the group of the next particle, its index there
  std::optional<LatticeDraws> draws_;  // the current group's stream, where it is jittered
};

}  // namespace cdm
