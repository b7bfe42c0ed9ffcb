#pragma once
/// @file wall_motion.hpp
/// @brief Prescribed rigid motion of a wall (or any body fixed in space): where a point
/// given in the scene is at time t, and the velocity of the surface at a point.
///
/// One motion per wall, a function of time only (so a restart and any thread count see
/// the same wall at the same step):
///   translation:  x(t) = x₀ + V t,                         v = V
///   oscillation:  x(t) = x₀ + A sin(2π f t + φ),           v = 2π f A cos(2π f t + φ)
///   rotation:     x(t) = o + R(Ω t)(x₀ − o),               v = Ω k × (x − o)
/// with R(θ) the rotation by θ about the unit axis k (right-handed, Rodrigues' formula
/// R v = v cos θ + (k × v) sin θ + k (k·v)(1 − cos θ)). The scene's position is the
/// wall at t = 0 for translation and rotation, the centre of the oscillation otherwise.
#include "cdm/solver/keywords.hpp"
#include "cdm/solver/vec3.hpp"

namespace cdm {

struct WallMotion {
  enum class Kind { none, translation, oscillation, rotation };
  Kind kind = Kind::none;
  Vec3 velocity;                 // translation: V [m/s]
  Vec3 amplitude;                // oscillation: A [m]
  double frequency = 0.0;        // oscillation: f [Hz]
  double phase = 0.0;            // oscillation: φ [rad]
  Vec3 origin;                   // rotation: a point o on the axis [m]
  Vec3 axis{0.0, 0.0, 1.0};      // rotation: unit axis k [-]
  double angular_velocity = 0.0; // rotation: Ω [rad/s], right-handed about k

  bool moving() const { return kind != Kind::none; }
  /// Where the point @p x0 of the scene is at time @p t [s].
  Vec3 point(Vec3 x0, double t) const;
  /// The direction @p d0 of the scene (an axis, a normal) at time @p t.
  Vec3 direction(Vec3 d0, double t) const;
  /// The velocity [m/s] at time @p t of the surface point now at @p x.
  Vec3 surface_velocity(Vec3 x, double t) const;
  /// The wall's angular velocity [rad/s] (zero unless rotating).
  Vec3 spin() const { return kind == Kind::rotation ? angular_velocity * axis : Vec3{}; }
  /// A bound [m] on how far any point of the body within @p reach [m] of the rotation
  /// axis moved between @p t0 and @p t1 (reach is ignored by translations).
  double shift_bound(double t0, double t1, double reach) const;
};

/// The scene's `motion.type` keywords.
inline constexpr Keywords<WallMotion::Kind, 3> wall_motion_keywords{{{"translation", WallMotion::Kind::translation},
                                                                    {"oscillation", WallMotion::Kind::oscillation},
                                                                    {"rotation", WallMotion::Kind::rotation}}};

}  // namespace cdm
