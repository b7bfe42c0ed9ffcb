#pragma once
/// @file insertion_spec.hpp
/// @brief What a scene's [[insertions]] and [[outlets]] say, in SI units: particles added
/// over time in a box at a rate until a total, and regions that remove the particles
/// reaching them (population.hpp runs both).
#include <cstdint>
#include <limits>
#include <string>

#include "cdm/solver/size_distribution.hpp"
#include "cdm/solver/placement_region.hpp"
#include "cdm/solver/vec3.hpp"

namespace cdm {

struct InsertionSpec {
  std::string key;                 ///< "insertions[0]", for messages
  PlacementRegion region;          ///< where the centres are drawn
  bool rate_by_mass = false;       ///< rate in kg/s (else particles per second)
  double rate = 0.0;               ///< [1/s] or [kg/s]
  bool total_by_mass = false;      ///< total in kg (else a particle count)
  double total = std::numeric_limits<double>::infinity();  ///< count or kg; infinite: until `end`
  double start = 0.0;              ///< first insertion time [s]
  double end = std::numeric_limits<double>::infinity();    ///< no insertion after it [s]
  double interval = 0.0;           ///< between insertion events [s]; 0: every step
  Vec3 velocity;                   ///< initial velocity [m/s]
  int material = 0;
  SizeDistribution size;
  std::uint64_t seed = 1;
};

struct OutletSpec {
  std::string name;
  bool plane = true;     ///< a plane (else a box)
  Vec3 point, normal;    ///< plane: removes the centres beyond it, (x − point)·normal > 0 [m], unit
  Vec3 lower, upper;     ///< box: removes the centres inside it [m]
  /// Whether a particle centred at @p x is removed.
  bool removes(Vec3 x) const {
    if (plane) return dot(x - point, normal) > 0.0;
    return x.x >= lower.x && x.x <= upper.x && x.y >= lower.y && x.y <= upper.y && x.z >= lower.z && x.z <= upper.z;
  }
};

}  // namespace cdm
