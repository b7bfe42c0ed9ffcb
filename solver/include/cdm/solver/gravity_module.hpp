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
  /// Among MPI ranks each adds the weight of its own particles only: writing the others'
  /// would commit the pages their slots leave uncommitted (slot_pages.hpp).
  std::vector<std::vector<double>*> share_among(RankSplit* ranks) override {
    ranks_ = ranks;
    return {};
  }

 private:
  Vec3 g_;  // [m/s^2]
  RankSplit* ranks_ = nullptr;
};

}  // namespace cdm
