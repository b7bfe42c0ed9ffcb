#pragma once
/// @file periodic_box.hpp
/// @brief Periodic boundaries for the particles: along a periodic axis a particle that
/// leaves through one face re-enters through the other, and two particles interact
/// through their nearest images (the minimum-image convention, valid while the
/// interaction range is below half the period; the loader checks that).
#include <cmath>

#include "cdm/solver/vec3.hpp"

namespace cdm {

struct PeriodicBox {
  bool on[3] = {false, false, false};  // periodic along x, y, z
  double lo[3] = {0.0, 0.0, 0.0};      // lower face [m]
  double len[3] = {0.0, 0.0, 0.0};     // period [m]

  bool any() const { return on[0] || on[1] || on[2]; }

  /// @brief The separation @p d of two points along axis @p a, to its nearest image.
  /// d − L·nearbyint(d/L), with the rounding done inline for |d| < 1.5 L (always, for
  /// points inside the box): generic x86-64 has no rounding instruction, and the call
  /// to nearbyint made every caller spill its registers (the pair loop among them).
  /// The number of periods is decided by comparing |d| with L/2 (exact) and 1.5 L
  /// (rounded once), not by dividing: a division per periodic axis per listed pair was
  /// a good part of the pair loop's first pass. Same result bit for bit as rounding
  /// d/L, signed zeros included, except when d is within a rounding error of L/2 or
  /// 3L/2, where both images are equally near and either may be returned.
  double min_image(double d, int a) const {
    if (!on[a]) return d;
    const double l = len[a];
    const double ad = std::abs(d);
    const double k = ad <= 0.5 * l ? std::copysign(0.0, d) : ad < 1.5 * l ? std::copysign(1.0, d) : std::nearbyint(d / l);
    return d - l * k;
  }

  /// @brief The separation vector to the nearest image of the second point.
  Vec3 min_image(Vec3 d) const { return {min_image(d.x, 0), min_image(d.y, 1), min_image(d.z, 2)}; }

  /// @brief Coordinate @p c along axis @p a brought into [lo, lo + len).
  double wrap(double c, int a) const {
    if (!on[a] || (c >= lo[a] && c < lo[a] + len[a])) return c;  // inside already: no fmod
    double r = std::fmod(c - lo[a], len[a]);
    if (r < 0) r += len[a];
    if (r >= len[a]) r = 0.0;  // fmod of a value just below 0 can round to len
    return lo[a] + r;
  }
};

}  // namespace cdm
