#pragma once
/// @file gravity_module.hpp
/// @brief Uniform gravity: F = m g.
#include "cdm/solver/force_module.hpp"
#include "cdm/solver/vec3.hpp"

namespace cdm {

class GravityModule final : public ForceModule {
 public:
  explicit GravityModule(Vec3 g) : g_(g) {}
  std::string name() const override { return "gravity"; }
  void add_forces(ParticleStore& p, double dt) override;

 private:
  Vec3 g_;  // [m/s^2]
};

}  // namespace cdm
