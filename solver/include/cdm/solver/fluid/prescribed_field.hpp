#pragma once
/// @file prescribed_field.hpp
/// @brief Gas velocity (and pressure) fields given in closed form, named in a scene and
/// sampled onto the staggered grid. With ξ = (x − lo)/L per axis (the domain mapped to
/// the unit square or cube) and U the amplitude:
///
///  - single_vortex (Garg et al. 2012 eq 43, as printed), 2D:
///      u = 2U sin²(πξ) sin(2πη) c(t),  v = −U sin(2πξ) sin²(πη) c(t).
///    As printed it is not solenoidal (∇·u = πU/L sin 2πξ sin 2πη c); that does not
///    matter for one-way tracers, and it is the field the paper's numbers refer to.
///  - leveque_deformation (LeVeque 1996), 3D: u = 2U sin²(πξ) sin(2πη) sin(2πζ) c(t),
///      v = −U sin(2πξ) sin²(πη) sin(2πζ) c(t),  w = −U sin(2πξ) sin(2πη) sin²(πζ) c(t);
///  - c(t) = cos(πt/T): the flow reverses at T/2 and every tracer returns exactly to its
///    start at t = nT (the fields are separable in time);
///  - taylor_green (eq 44), steady: u = −U cos(k_x x) sin(k_y y), v = U sin(k_x x) cos(k_y y),
///      pressure p = −(ρ_g U²/4)[cos(2k_x x) + cos(2k_y y)] (the steady Euler solution);
///  - uniform: a constant velocity.
/// Every field's pressure also carries the hydrostatic part ρ_g g·(x − lo) when the scene
/// has gravity, and an optional imposed uniform gradient; the vortex fields define no
/// dynamic pressure (a scene that asks for their pressure-gradient force is refused).
#include <string>

#include "cdm/solver/vec3.hpp"
#include "cdm/solver/keywords.hpp"

namespace cdm::fluid {

enum class FieldType { single_vortex, leveque_deformation, taylor_green, uniform };
inline constexpr Keywords<FieldType, 4> field_type_keywords{{{"single_vortex", FieldType::single_vortex}, {"leveque_deformation", FieldType::leveque_deformation}, {"taylor_green", FieldType::taylor_green}, {"uniform", FieldType::uniform}}};
inline const char* to_string(FieldType f) { return keyword_of(field_type_keywords, f); }

struct PrescribedFieldSpec {
  FieldType type = FieldType::uniform;
  double amplitude = 1.0;      // U [m/s] (vortex fields: the velocity scale of the unit-square formula)
  double period = 1.0;         // T [s] (vortex fields)
  double kx = 0.0, ky = 0.0;   // Taylor–Green wavenumbers [1/m]
  Vec3 velocity;               // uniform [m/s]
  Vec3 pressure_gradient;      // imposed uniform ∇p [Pa/m], added to every field's pressure
};

class PrescribedField {
 public:
  PrescribedField(const PrescribedFieldSpec& spec, Vec3 lo, Vec3 hi, double gas_density, Vec3 gravity)
      : s_(spec), lo_(lo), hi_(hi), rho_(gas_density), g_(gravity) {}

  /// u(x, t) = shape(x) · time_factor(t) for every field here (steady ones have factor 1).
  Vec3 shape(Vec3 x) const;
  double time_factor(double t) const;
  Vec3 velocity(Vec3 x, double t) const { return time_factor(t) * shape(x); }
  /// Whether the field defines a pressure (for the pressure-gradient force).
  bool has_pressure() const { return s_.type == FieldType::uniform || s_.type == FieldType::taylor_green; }
  /// Pressure [Pa] at x, relative to the domain's lower corner (steady fields only).
  double pressure(Vec3 x) const;
  /// Its gradient ∇p [Pa/m] in closed form.
  Vec3 pressure_gradient(Vec3 x) const;
  const PrescribedFieldSpec& spec() const { return s_; }

 private:
  PrescribedFieldSpec s_;
  Vec3 lo_, hi_;
  double rho_;
  Vec3 g_;
};

}  // namespace cdm::fluid
