#include "cdm/solver/coupling/deposition.hpp"

#include <algorithm>
#include <cmath>

namespace cdm::coupling {

Deposition::Deposition(const fluid::StaggeredGrid& grid, Kernel kernel, double width)
    : grid_(&grid), kernel_(kernel), sigma_(width) {}

int Deposition::fold(int axis, int i) const {
  const int n = grid_->n(axis);
  if (i >= 0 && i < n) return i;
  if (grid_->spec().periodic(axis)) return ((i % n) + n) % n;
  // Reflect about the wall: cell −1 mirrors cell 0, cell n mirrors n − 1.
  while (i < 0 || i >= n) i = i < 0 ? -1 - i : 2 * n - 1 - i;
  return i;
}

void Deposition::weights(Vec3 x, std::vector<std::size_t>& idx_, std::vector<double>& w_) const {
  const fluid::StaggeredGrid& g = *grid_;
  idx_.clear();
  w_.clear();
  const double xs[3] = {x.x, x.y, x.z};
  const int dims = g.dims();
  // Fractional cell-centre coordinate along each axis: centre of cell i at i.
  double f[3];
  for (int a = 0; a < 3; ++a) f[a] = (xs[a] - g.lo(a)) * g.inv_h(a) - 0.5;
  switch (kernel_) {
    case Kernel::cell: {
      int c[3] = {0, 0, 0};
      for (int a = 0; a < dims; ++a) c[a] = std::clamp(static_cast<int>(std::floor(f[a] + 0.5)), 0, g.n(a) - 1);
      idx_.push_back(g.at(c[0], c[1], c[2]));
      w_.push_back(1.0);
      return;
    }
    case Kernel::trilinear: {
      int i0[3] = {0, 0, 0};
      double t[3] = {0, 0, 0};
      for (int a = 0; a < dims; ++a) {
        i0[a] = static_cast<int>(std::floor(f[a]));
        t[a] = f[a] - i0[a];
      }
      const int kz = dims == 3 ? 2 : 1;
      for (int dk = 0; dk < kz; ++dk)
        for (int dj = 0; dj < 2; ++dj)
          for (int di = 0; di < 2; ++di) {
            const double w = (di ? t[0] : 1 - t[0]) * (dj ? t[1] : 1 - t[1]) * (dims == 3 ? (dk ? t[2] : 1 - t[2]) : 1.0);
            if (w == 0.0) continue;
            idx_.push_back(g.at(fold(0, i0[0] + di), fold(1, i0[1] + dj), dims == 3 ? fold(2, i0[2] + dk) : 0));
            w_.push_back(w);
          }
      return;
    }
    case Kernel::gaussian: {
      // Separable: exp(−r²/2σ²) = Π_a exp(−Δ_a²/2σ²) over the cell centres within 3σ along
      // each axis (a box-truncated gaussian), normalised to sum to one.
      int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
      double wa[3][64];
      for (int a = 0; a < 3; ++a) {
        if (a >= dims) { wa[a][0] = 1.0; continue; }
        const double r = 3.0 * sigma_ / g.h(a);
        lo[a] = static_cast<int>(std::floor(f[a] - r));
        hi[a] = std::min(static_cast<int>(std::ceil(f[a] + r)), lo[a] + 63);
        for (int i = lo[a]; i <= hi[a]; ++i) {
          const double dx = (i - f[a]) * g.h(a);
          wa[a][i - lo[a]] = std::exp(-0.5 * dx * dx / (sigma_ * sigma_));
        }
      }
      // Folded index offsets per axis, combined by the array strides (hot loop).
      const std::size_t base = g.at(0, 0, 0);
      const std::size_t sy = g.at(0, 1, 0) - base, sz = g.at(0, 0, 1) - base;
      std::size_t ox[64], oy[64], oz[64];
      for (int i = lo[0]; i <= hi[0]; ++i) ox[i - lo[0]] = static_cast<std::size_t>(fold(0, i));
      for (int j = lo[1]; j <= hi[1]; ++j) oy[j - lo[1]] = static_cast<std::size_t>(fold(1, j)) * sy;
      for (int k = lo[2]; k <= hi[2]; ++k) oz[k - lo[2]] = dims == 3 ? static_cast<std::size_t>(fold(2, k)) * sz : 0;
      const int nxw = hi[0] - lo[0] + 1;
      idx_.reserve(static_cast<std::size_t>(nxw) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1));
      w_.reserve(idx_.capacity());
      double sum = 0.0;
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j) {
          const double wjk = wa[1][j - lo[1]] * wa[2][k - lo[2]];
          const std::size_t row = base + oy[j - lo[1]] + oz[k - lo[2]];
          for (int i = 0; i < nxw; ++i) {
            const double w = wa[0][i] * wjk;
            idx_.push_back(row + ox[i]);
            w_.push_back(w);
            sum += w;
          }
        }
      if (sum <= 0.0) {  // narrower than a cell: fall back to the holding cell
        int c[3] = {0, 0, 0};
        for (int a = 0; a < dims; ++a) c[a] = std::clamp(static_cast<int>(std::floor(f[a] + 0.5)), 0, g.n(a) - 1);
        idx_.assign(1, g.at(c[0], c[1], c[2]));
        w_.assign(1, 1.0);
        return;
      }
      const double inv = 1.0 / sum;
      for (double& w : w_) w *= inv;
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
