#include "cdm/solver/walls/wall_motion.hpp"

#include <cmath>
#include <limits>
#include <numbers>

namespace cdm {

namespace {
/// R(θ) v about the unit axis k (Rodrigues).
Vec3 rotate(Vec3 v, Vec3 k, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  return c * v + s * cross(k, v) + (dot(k, v) * (1.0 - c)) * k;
}
}  // namespace

Vec3 WallMotion::point(Vec3 x0, double t) const {
  switch (kind) {
    case Kind::none: return x0;
    case Kind::translation: return x0 + t * velocity;
    case Kind::oscillation: return x0 + std::sin(2.0 * std::numbers::pi * frequency * t + phase) * amplitude;
    case Kind::rotation: return origin + rotate(x0 - origin, axis, angular_velocity * t);
  }
  return x0;
}

Vec3 WallMotion::direction(Vec3 d0, double t) const {
  return kind == Kind::rotation ? rotate(d0, axis, angular_velocity * t) : d0;
}

Vec3 WallMotion::surface_velocity(Vec3 x, double t) const {
  switch (kind) {
    case Kind::none: return {};
    case Kind::translation: return velocity;
    case Kind::oscillation: {
      const double w = 2.0 * std::numbers::pi * frequency;
      return (w * std::cos(w * t + phase)) * amplitude;
    }
    case Kind::rotation: return cross(angular_velocity * axis, x - origin);
  }
  return {};
}

double WallMotion::shift_bound(double t0, double t1, double reach) const {
  switch (kind) {
    case Kind::none: return 0.0;
    case Kind::translation: return norm(velocity) * std::abs(t1 - t0);
    case Kind::oscillation: {
      const double w = 2.0 * std::numbers::pi * frequency;
      return norm(amplitude) * std::abs(std::sin(w * t1 + phase) - std::sin(w * t0 + phase));
    }
    case Kind::rotation: {
      // An arc is longer than its chord.
      if (!std::isfinite(reach)) return std::numeric_limits<double>::infinity();
      return std::abs(angular_velocity * (t1 - t0)) * reach;
    }
  }
  return 0.0;
}

}  // namespace cdm
