#include "cdm/solver/coupling/deposition.hpp"

#include <algorithm>
#include <cmath>

namespace cdm::coupling {

Deposition::Deposition(const fluid::StaggeredGrid& grid, Kernel kernel, double width)
    : grid_(&grid), base_(grid.at(0, 0, 0)),
      stride_{1, grid.at(0, 1, 0) - grid.at(0, 0, 0), grid.at(0, 0, 1) - grid.at(0, 0, 0)}, kernel_(kernel),
      sigma_(width) {}

int Deposition::fold_outside(int axis, int i) const {
  const int n = grid_->n(axis);
  if (grid_->spec().periodic(axis)) return ((i % n) + n) % n;
  // Reflect about the wall: cell −1 mirrors cell 0, cell n mirrors n − 1.
  while (i < 0 || i >= n) i = i < 0 ? -1 - i : 2 * n - 1 - i;
  return i;
}

void Deposition::holding_cell(const double f[3], Stencil& s) const {
  const fluid::StaggeredGrid& g = *grid_;
  int c[3] = {0, 0, 0};
  for (int a = 0; a < g.dims(); ++a) c[a] = std::clamp(static_cast<int>(std::floor(f[a] + 0.5)), 0, g.n(a) - 1);
  s.separable_ = false;
  s.count_ = 0;
  s.add(g.at(c[0], c[1], c[2]), 1.0);
}

void Deposition::stencil(Vec3 x, Stencil& s) const {
  const fluid::StaggeredGrid& g = *grid_;
  s.separable_ = false;
  s.count_ = 0;
  const double xs[3] = {x.x, x.y, x.z};
  const int dims = g.dims();
  // Fractional cell-centre coordinate along each axis: centre of cell i at i.
  double f[3];
  for (int a = 0; a < 3; ++a) f[a] = (xs[a] - g.lo(a)) * g.inv_h(a) - 0.5;
  switch (kernel_) {
    case Kernel::cell:
      holding_cell(f, s);
      return;
    case Kernel::trilinear: {
      auto add = [&](std::size_t i, double w) { s.add(i, w); };
      for_each_trilinear(x, add);
      return;
    }
    case Kernel::gaussian: {
      // Separable: exp(−r²/2σ²) = Π_a exp(−Δ_a²/2σ²) over the cell centres within 3σ along
      // each axis (a box-truncated gaussian), normalised to sum to one.
      int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
      for (int a = 0; a < 3; ++a) {
        if (a >= dims) { s.wa_[a][0] = 1.0; continue; }
        const double r = 3.0 * sigma_ / g.h(a);
        lo[a] = static_cast<int>(std::floor(f[a] - r));
        hi[a] = std::min(static_cast<int>(std::ceil(f[a] + r)), lo[a] + Stencil::max_axis - 1);
        for (int i = lo[a]; i <= hi[a]; ++i) {
          const double dx = (i - f[a]) * g.h(a);
          s.wa_[a][i - lo[a]] = std::exp(-0.5 * dx * dx / (sigma_ * sigma_));
        }
      }
      // Folded index offsets per axis, combined by the array strides.
      const std::size_t base = g.at(0, 0, 0);
      const std::size_t sy = g.at(0, 1, 0) - base, sz = g.at(0, 0, 1) - base;
      for (int i = lo[0]; i <= hi[0]; ++i) s.off_[0][i - lo[0]] = static_cast<std::size_t>(fold(0, i));
      for (int j = lo[1]; j <= hi[1]; ++j) s.off_[1][j - lo[1]] = static_cast<std::size_t>(fold(1, j)) * sy;
      for (int k = lo[2]; k <= hi[2]; ++k) s.off_[2][k - lo[2]] = dims == 3 ? static_cast<std::size_t>(fold(2, k)) * sz : 0;
      for (int a = 0; a < 3; ++a) s.n_[a] = hi[a] - lo[a] + 1;
      s.base_ = base;
      double sum = 0.0;
      for (int k = 0; k < s.n_[2]; ++k)
        for (int j = 0; j < s.n_[1]; ++j) {
          const double wjk = s.wa_[1][j] * s.wa_[2][k];
          for (int i = 0; i < s.n_[0]; ++i) sum += s.wa_[0][i] * wjk;
        }
      if (sum <= 0.0) {  // narrower than a cell: fall back to the holding cell
        holding_cell(f, s);
        return;
      }
      s.inv_ = 1.0 / sum;
      s.separable_ = true;
      return;
    }
  }
}

double Deposition::average(const std::vector<double>& cells, Vec3 x) const {
  double s = 0.0;
  for_each_weight(x, [&](std::size_t i, double w) { s += w * cells[i]; });
  return s;
}

}  // namespace cdm::coupling
