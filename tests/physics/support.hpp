#pragma once
// What the physics tests share: a scene, and comparisons to the bit.
#include <cstring>
#include <string>
#include <vector>

#include "cdm/solver/particle_store.hpp"
#include "scene_text.hpp"

namespace cdm_test {

// 6 x 6 x 6 frictional spheres thrown about a walled box: contacts, walls, spins.
inline const std::string box_scene = scene_head({.wall = "wall", .kn = 1.0e3, .en = 0.9, .mu = 0.5}) + floor_wall("wall") + R"(
[[walls]]
name = "x-"
point = [0.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
material = "wall"
[[walls]]
name = "x+"
point = [0.0066, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
material = "wall"
[[lattices]]
material = "glass"
radius = 0.5e-3
origin = [0.00055, 0.00055, 0.00055]
spacing = [0.0011, 0.0011, 0.0011]
count = [6, 6, 6]
velocity_jitter = 0.5
seed = 7
[integrator]
scheme = "velocity_verlet"
dt = "auto"
end_time = 0.05
)";

/// The two arrays hold the same doubles, bit for bit (-0 differs from +0, a NaN equals
/// only the same NaN).
inline bool same(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

/// Positions, velocities and angular velocities are the same, bit for bit.
inline bool same_motion(const cdm::ParticleStore& a, const cdm::ParticleStore& b) {
  for (auto m : {&cdm::ParticleStore::x, &cdm::ParticleStore::y, &cdm::ParticleStore::z, &cdm::ParticleStore::vx,
                 &cdm::ParticleStore::vy, &cdm::ParticleStore::vz, &cdm::ParticleStore::wx, &cdm::ParticleStore::wy,
                 &cdm::ParticleStore::wz})
    if (!same(a.*m, b.*m)) return false;
  return true;
}

}  // namespace cdm_test
