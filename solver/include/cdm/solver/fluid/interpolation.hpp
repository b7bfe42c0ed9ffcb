#pragma once
/// @file interpolation.hpp
/// @brief Interpolation of a staggered vector field (the gas velocity, or a pressure
/// gradient stored on the faces) to a point, chosen per scene:
///
///  - `trilinear`: each component interpolated linearly along every axis from its own
///    staggered lattice (8 samples in 3D, 4 in 2D); second order in the cell size.
///  - `paper_lagrange2`: Garg et al. (2012) §2.2.3 / MFIX's default. The face values are
///    first averaged to the cell corners (the "interpolation grid"), e.g. in 2D
///    u(I,J) = ½[u(i−1,j) + u(i−1,j−1)] in the paper's indices, i.e. the mean of the
///    faces that share the corner's edge (2 in 2D, 4 in 3D); then each component is
///    interpolated from the 3 corners nearest the point along each axis (27 in 3D, 9 in
///    2D) with the second-order Lagrange polynomial
///      L₋₁ = ξ(ξ−1)/2,  L₀ = 1 − ξ²,  L₊₁ = ξ(ξ+1)/2,  ξ = (x − x_I)/h ∈ [−½, ½].
///    The corner averaging is second-order accurate, so the scheme is second order.
///
/// Points must lie in the domain (periodic coordinates wrapped into it); samples beyond
/// the boundary come from the ghost layers (staggered_grid.hpp).
#include <vector>

#include "cdm/solver/fluid/staggered_grid.hpp"
#include "cdm/solver/keywords.hpp"

namespace cdm::fluid {

/// `analytic` (prescribed fields only) bypasses the grid: the closed form is evaluated at
/// the particle, which isolates time-integration error in verification studies.
enum class InterpolationScheme { trilinear, paper_lagrange2, analytic };
inline constexpr Keywords<InterpolationScheme, 3> interpolation_keywords{{{"paper_lagrange2", InterpolationScheme::paper_lagrange2}, {"trilinear", InterpolationScheme::trilinear}, {"analytic", InterpolationScheme::analytic}}};
inline const char* to_string(InterpolationScheme s) { return keyword_of(interpolation_keywords, s); }

class VectorInterpolator {
 public:
  VectorInterpolator(const StaggeredGrid& grid, InterpolationScheme scheme)
      : grid_(&grid), scheme_(scheme), sy_(grid.at(0, 1, 0) - grid.at(0, 0, 0)), sz_(grid.at(0, 0, 1) - grid.at(0, 0, 0)) {}

  /// The trilinear stencils of the three staggered components at a point: base sample
  /// and fractions along each axis. The same for every field of the grid's staggering,
  /// so one evaluation serves the velocity and the pressure gradient.
  struct Stencils {
    std::size_t base[3];
    double t[3][3];
  };
  Stencils stencils(Vec3 x) const;

  /// Take the face arrays (ghosts filled). The arrays must outlive the interpolator's
  /// use; the paper scheme averages them to the corners here, once per update.
  void update(const std::vector<double>& u, const std::vector<double>& v, const std::vector<double>& w);
  /// Zero the corner values outside the grid's window (StaggeredGrid::zero_outside_window).
  void zero_outside_window() {
    for (auto* c : {&cu_, &cv_, &cw_}) grid_->zero_outside_window(*c);
  }

  /// The field at @p x.
  Vec3 at(Vec3 x) const;
  /// The field at the point of @p s (trilinear scheme only).
  Vec3 sample(const Stencils& s) const;
  InterpolationScheme scheme() const { return scheme_; }

 private:
  double trilinear(const std::vector<double>& a, const Stencils& s, int comp) const;
  Vec3 lagrange2(Vec3 x) const;

  const StaggeredGrid* grid_;
  InterpolationScheme scheme_;
  std::size_t sy_, sz_;  // array strides along y and z
  const std::vector<double>* u_ = nullptr;
  const std::vector<double>* v_ = nullptr;
  const std::vector<double>* w_ = nullptr;
  std::vector<double> cu_, cv_, cw_;  // corner values (paper scheme)
};

}  // namespace cdm::fluid
