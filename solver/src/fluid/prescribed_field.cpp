#include "cdm/solver/fluid/prescribed_field.hpp"

#include <cmath>
#include <numbers>

namespace cdm::fluid {

Vec3 PrescribedField::shape(Vec3 x) const {
  constexpr double pi = std::numbers::pi;
  const double U = s_.amplitude;
  switch (s_.type) {
    case FieldType::single_vortex: {
      const double xi = (x.x - lo_.x) / (hi_.x - lo_.x), eta = (x.y - lo_.y) / (hi_.y - lo_.y);
      const double sx = std::sin(pi * xi), sy = std::sin(pi * eta);
      return {U * 2.0 * sx * sx * std::sin(2.0 * pi * eta), -U * std::sin(2.0 * pi * xi) * sy * sy, 0.0};
    }
    case FieldType::leveque_deformation: {
      const double xi = (x.x - lo_.x) / (hi_.x - lo_.x), eta = (x.y - lo_.y) / (hi_.y - lo_.y),
                   zeta = (x.z - lo_.z) / (hi_.z - lo_.z);
      const double sx = std::sin(pi * xi), sy = std::sin(pi * eta), sz = std::sin(pi * zeta);
      const double s2x = std::sin(2.0 * pi * xi), s2y = std::sin(2.0 * pi * eta), s2z = std::sin(2.0 * pi * zeta);
      return {U * 2.0 * sx * sx * s2y * s2z, -U * s2x * sy * sy * s2z, -U * s2x * s2y * sz * sz};
    }
    case FieldType::taylor_green:
      return {-U * std::cos(s_.kx * x.x) * std::sin(s_.ky * x.y), U * std::sin(s_.kx * x.x) * std::cos(s_.ky * x.y), 0.0};
    case FieldType::uniform: return s_.velocity;
  }
  return {};
}

double PrescribedField::time_factor(double t) const {
  if (s_.type == FieldType::single_vortex || s_.type == FieldType::leveque_deformation)
    return std::cos(std::numbers::pi * t / s_.period);
  return 1.0;
}

double PrescribedField::pressure(Vec3 x) const {
  const Vec3 r = x - lo_;
  double p = rho_ * dot(g_, r) + dot(s_.pressure_gradient, r);
  if (s_.type == FieldType::taylor_green) {
    const double U = s_.amplitude;
    p -= 0.25 * rho_ * U * U * (std::cos(2.0 * s_.kx * x.x) + std::cos(2.0 * s_.ky * x.y));
  }
  return p;
}

Vec3 PrescribedField::pressure_gradient(Vec3 x) const {
  Vec3 gp = rho_ * g_ + s_.pressure_gradient;
  if (s_.type == FieldType::taylor_green) {
    const double c = 0.5 * rho_ * s_.amplitude * s_.amplitude;  // ∂/∂x of −(ρU²/4) cos(2kx) = (ρU²/2) k sin(2kx)
    gp.x += c * s_.kx * std::sin(2.0 * s_.kx * x.x);
    gp.y += c * s_.ky * std::sin(2.0 * s_.ky * x.y);
  }
  return gp;
}

}  // namespace cdm::fluid
