/// @file simulation_scene.cpp
/// @brief The scene's particles into the store: placed at the start, then given their
/// velocities, spins and masses, at once or, among processes, each its own rows'.
#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "cdm/solver/initial_motion.hpp"
#include "cdm/solver/rank_split.hpp"
#include "cdm/solver/simulation.hpp"
#include "cdm/solver/slot_pages.hpp"

namespace cdm {

void Simulation::place_scene() {
  // The scene's particles are placed once, into the store, at rest and without mass: the
  // pages read are returned as it goes, so that a large scene is not held twice at once,
  // and so are the store's pages that hold zeros only, which cost nothing until written
  // (slot_pages.hpp). Their velocities, spins and masses follow (fill_motion).
  const std::vector<ParticleSpec>& given = spec_.particles;
  particles_.reserve(given.size());
  constexpr std::size_t block = 1 << 14;
  for (std::size_t k = 0, b0 = 0; k < given.size(); ++k) {
    const ParticleSpec& ps = given[k];
    particles_.append(ps.position, ps.radius, ps.material, spec_.materials[ps.material].fixed);
    if ((k + 1) % block != 0) continue;
    release_pages(given.data(), given.data() + k + 1);
    particles_.release_zero_pages(b0, k + 1);
    b0 = k + 1;
  }
  spec_.particles.clear();
  spec_.particles.shrink_to_fit();
  motion_pending_ = particles_.size() > 0;
}

void Simulation::set_scene_mass(std::size_t i) {
  particles_.set_mass(i, spec_.materials[particles_.material[i]].density);
}

void Simulation::fill_motion() {
  if (!motion_pending_) return;
  motion_pending_ = false;
  InitialMotion motion(spec_.groups);
  std::uint32_t next = 0;  // the scene index of the particle motion.next() gives
  auto give = [&](std::uint32_t index, std::uint32_t slot) {
    for (; next < index; ++next) motion.next();
    const InitialMotion::Motion m = motion.next();
    ++next;
    particles_.vx[slot] = m.velocity.x; particles_.vy[slot] = m.velocity.y; particles_.vz[slot] = m.velocity.z;
    particles_.set_angular_velocity(slot, m.angular_velocity);
    set_scene_mass(slot);
  };
  // Every slot, or among processes those of this process's own particles, in the order
  // of their particles' scene indices (their identities).
  const std::size_t n = particles_.size();
  const std::vector<std::pair<std::uint32_t, std::uint32_t>> all{{0, static_cast<std::uint32_t>(n)}};
  const auto& runs = ranks_ ? ranks_->own_runs(n) : all;
  if (particles_.id.empty()) {  // never sorted: slot i holds particle i
    for (const auto& [first, last] : runs)
      for (std::uint32_t i = first; i < last; ++i) give(i, i);
  } else {
    std::vector<std::pair<std::uint32_t, std::uint32_t>> by_index;
    for (const auto& [first, last] : runs)
      for (std::uint32_t i = first; i < last; ++i) by_index.push_back({particles_.id[i], i});
    std::sort(by_index.begin(), by_index.end());
    for (const auto& [index, slot] : by_index) give(index, slot);
  }
  if (ranks_) integrator_->masses_changed();
}

}  // namespace cdm
