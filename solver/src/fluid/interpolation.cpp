#include "cdm/solver/fluid/interpolation.hpp"

#include <algorithm>
#include <cmath>

namespace cdm::fluid {

void VectorInterpolator::update(const std::vector<double>& u, const std::vector<double>& v,
                                const std::vector<double>& w) {
  u_ = &u;
  v_ = &v;
  w_ = &w;
  if (scheme_ != InterpolationScheme::paper_lagrange2) return;
  const StaggeredGrid& g = *grid_;
  if (cu_.size() != g.padded_size()) {
    cu_ = g.make_array();
    cv_ = g.make_array();
    cw_ = g.make_array();
  }
  const bool d2 = g.two_d();
  // Corners (I, J, K) at lo + (I, J, K) h; the Lagrange stencils reach I−1 … I+1 for
  // I in [0, n], so corners −1 … n+1 are needed along each axis.
  // Along z, those of the grid's window (StaggeredGrid::set_window).
  const auto [z0, z1] = g.window_lines();
  const int k0 = d2 ? 0 : std::max(-1, z0), k1 = d2 ? 0 : std::min(g.n(2) + 1, z1);
  for (int K = k0; K <= k1; ++K)
    for (int J = -1; J <= g.n(1) + 1; ++J)
      for (int I = -1; I <= g.n(0) + 1; ++I) {
        const std::size_t c = g.at(I, J, K);
        if (d2) {
          cu_[c] = 0.5 * (u[g.at(I, J - 1, 0)] + u[g.at(I, J, 0)]);
          cv_[c] = 0.5 * (v[g.at(I - 1, J, 0)] + v[g.at(I, J, 0)]);
          cw_[c] = 0.0;
        } else {
          cu_[c] = 0.25 * (u[g.at(I, J - 1, K - 1)] + u[g.at(I, J, K - 1)] + u[g.at(I, J - 1, K)] + u[g.at(I, J, K)]);
          cv_[c] = 0.25 * (v[g.at(I - 1, J, K - 1)] + v[g.at(I, J, K - 1)] + v[g.at(I - 1, J, K)] + v[g.at(I, J, K)]);
          cw_[c] = 0.25 * (w[g.at(I - 1, J - 1, K)] + w[g.at(I, J - 1, K)] + w[g.at(I - 1, J, K)] + w[g.at(I, J, K)]);
        }
      }
}

VectorInterpolator::Stencils VectorInterpolator::stencils(Vec3 x) const {
  const StaggeredGrid& g = *grid_;
  const double xs[3] = {x.x, x.y, x.z};
  // Along each axis a component sits on the faces (offset 0) or at the centres (offset
  // ½): two fractional coordinates per axis serve all three components.
  int i0[2][3] = {{0, 0, 0}, {0, 0, 0}};
  double t[2][3] = {{0, 0, 0}, {0, 0, 0}};
  const int dims = g.dims();
  for (int d = 0; d < dims; ++d) {
    const double b = (xs[d] - g.lo(d)) * g.inv_h(d);
    for (int c = 0; c < 2; ++c) {
      const double f = b - (c == 0 ? 0.0 : 0.5);
      i0[c][d] = static_cast<int>(std::floor(f));
      t[c][d] = f - i0[c][d];
    }
  }
  Stencils s;
  for (int comp = 0; comp < 3; ++comp) {
    int i[3];
    for (int d = 0; d < 3; ++d) {
      const int c = StaggeredGrid::offset(static_cast<Staggering>(comp), d) == 0.0 ? 0 : 1;
      i[d] = i0[c][d];
      s.t[comp][d] = t[c][d];
    }
    s.base[comp] = g.at(i[0], i[1], i[2]);
  }
  return s;
}

double VectorInterpolator::trilinear(const std::vector<double>& a, const Stencils& s, int comp) const {
  // The 8 (2D: 4) samples from one base index and the array strides.
  const double* t = s.t[comp];
  const double* p = a.data() + s.base[comp];
  const std::size_t sy = sy_, sz = sz_;
  const double x00 = (1 - t[0]) * p[0] + t[0] * p[1];
  const double x10 = (1 - t[0]) * p[sy] + t[0] * p[sy + 1];
  const double y0 = (1 - t[1]) * x00 + t[1] * x10;
  if (grid_->dims() == 2) return y0;
  const double x01 = (1 - t[0]) * p[sz] + t[0] * p[sz + 1];
  const double x11 = (1 - t[0]) * p[sz + sy] + t[0] * p[sz + sy + 1];
  const double y1 = (1 - t[1]) * x01 + t[1] * x11;
  return (1 - t[2]) * y0 + t[2] * y1;
}

Vec3 VectorInterpolator::lagrange2(Vec3 x) const {
  const StaggeredGrid& g = *grid_;
  const double xs[3] = {x.x, x.y, x.z};
  int c[3] = {0, 0, 0};
  double L[3][3] = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  const int dims = g.dims();
  for (int d = 0; d < dims; ++d) {
    const double f = (xs[d] - g.lo(d)) / g.h(d);
    c[d] = static_cast<int>(std::lround(f));
    const double xi = f - c[d];
    L[d][0] = 0.5 * xi * (xi - 1.0);
    L[d][1] = 1.0 - xi * xi;
    L[d][2] = 0.5 * xi * (xi + 1.0);
  }
  Vec3 r;
  const int kr = dims == 3 ? 1 : 0;
  for (int dk = -kr; dk <= kr; ++dk)
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        const double wgt = L[0][di + 1] * L[1][dj + 1] * (dims == 3 ? L[2][dk + 1] : 1.0);
        const std::size_t idx = g.at(c[0] + di, c[1] + dj, c[2] + dk);
        r.x += wgt * cu_[idx];
        r.y += wgt * cv_[idx];
        r.z += wgt * cw_[idx];
      }
  return r;
}

Vec3 VectorInterpolator::at(Vec3 x) const {
  if (scheme_ == InterpolationScheme::paper_lagrange2) return lagrange2(x);
  return sample(stencils(x));
}

Vec3 VectorInterpolator::sample(const Stencils& s) const {
  const double wz = grid_->two_d() ? 0.0 : trilinear(*w_, s, 2);
  return {trilinear(*u_, s, 0), trilinear(*v_, s, 1), wz};
}

}  // namespace cdm::fluid
