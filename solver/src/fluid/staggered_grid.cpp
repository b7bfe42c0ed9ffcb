#include "cdm/solver/fluid/staggered_grid.hpp"

#include <algorithm>
#include <stdexcept>

namespace cdm::fluid {

StaggeredGrid::StaggeredGrid(const GridSpec& spec) : spec_(spec) {
  const double lo[3] = {spec.lo.x, spec.lo.y, spec.lo.z}, hi[3] = {spec.hi.x, spec.hi.y, spec.hi.z};
  for (int a = 0; a < 3; ++a) {
    n_[a] = spec.cells[a];
    if (n_[a] < 1 || !(hi[a] > lo[a])) throw std::invalid_argument("StaggeredGrid: bad extent or cell count");
    lo_[a] = lo[a];
    h_[a] = (hi[a] - lo[a]) / n_[a];
    inv_h_[a] = 1.0 / h_[a];
    ext_[a] = static_cast<std::size_t>(n_[a] + 1 + 2 * ghosts);
  }
  if (spec.two_d && (n_[2] != 1 || !spec.periodic(2)))
    throw std::invalid_argument("StaggeredGrid: a 2D grid has one cell along z and no z boundaries");
}

Vec3 StaggeredGrid::position(Staggering s, int i, int j, int k) const {
  return {lo_[0] + (i + offset(s, 0)) * h_[0], lo_[1] + (j + offset(s, 1)) * h_[1], lo_[2] + (k + offset(s, 2)) * h_[2]};
}

namespace {
int wrap(int m, int n) { return ((m % n) + n) % n; }
}  // namespace

void StaggeredGrid::fill_component(std::vector<double>& a, Staggering s, bool even) const {
  const int g = ghosts;
  // A 2D grid has one layer along z and nothing reads beyond it: no z pass, and the x and
  // y passes touch layer 0 only.
  const int axes = spec_.two_d ? 2 : 3;
  for (int axis = 0; axis < axes; ++axis) {
    const int n = n_[axis];
    const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
    const bool normal = static_cast<int>(s) == axis;  // the component normal to these faces
    // Index with `m` along `axis` and (p, q) along the two other axes.
    // Index of (m along axis, p along o1, q along o2): a base and a stride (hot loop).
    const std::size_t stride[3] = {1, ext_[0], ext_[0] * ext_[1]};
    const std::size_t sa = stride[axis];
    auto idx = [&, sa](int m, int p, int q) {
      return static_cast<std::size_t>(static_cast<long>(at(0, 0, 0)) + static_cast<long>(m) * static_cast<long>(sa) +
                                      static_cast<long>(p) * static_cast<long>(stride[o1]) +
                                      static_cast<long>(q) * static_cast<long>(stride[o2]));
    };
    const Boundary& lower = spec_.faces[2 * axis];
    const Boundary& upper = spec_.faces[2 * axis + 1];
    const int q0 = spec_.two_d && o2 == 2 ? 0 : -g, q1 = spec_.two_d && o2 == 2 ? 0 : n_[o2] + g;
    const int p0 = spec_.two_d && o1 == 2 ? 0 : -g, p1 = spec_.two_d && o1 == 2 ? 0 : n_[o1] + g;
    for (int q = q0; q <= q1; ++q)
      for (int p = p0; p <= p1; ++p) {
        if (lower.kind == BoundaryKind::periodic) {
          for (int m = -g; m < 0; ++m) a[idx(m, p, q)] = a[idx(wrap(m, n), p, q)];
          for (int m = n; m <= n + g; ++m) a[idx(m, p, q)] = a[idx(wrap(m, n), p, q)];
          continue;
        }
        if (s == Staggering::centre || (even && !normal)) {
          // Zero normal gradient: mirror about the boundary face.
          for (int m = 0; m < g; ++m) a[idx(-1 - m, p, q)] = a[idx(m, p, q)];
          for (int m = 0; m <= g; ++m) a[idx(n + m, p, q)] = a[idx(n - 1 - m, p, q)];
          continue;
        }
        if (normal) {
          // The boundary faces are samples 0 and n.
          auto set_face = [&](const Boundary& b, int face, double inward_sign) {
            switch (b.kind) {
              case BoundaryKind::no_slip:
              case BoundaryKind::free_slip: a[idx(face, p, q)] = 0.0; break;
              case BoundaryKind::velocity_inlet: a[idx(face, p, q)] = inward_sign * b.normal_velocity; break;
              case BoundaryKind::pressure_outlet:
              case BoundaryKind::periodic: break;  // solved for, not imposed
            }
          };
          if (!even) {
            set_face(lower, 0, 1.0);
            set_face(upper, n, -1.0);
          }
          const bool lo_flat = !even && lower.kind == BoundaryKind::pressure_outlet;
          const bool hi_flat = !even && upper.kind == BoundaryKind::pressure_outlet;
          for (int m = 1; m <= g; ++m) {
            a[idx(-m, p, q)] = lo_flat ? a[idx(0, p, q)] : a[idx(m, p, q)];
            a[idx(n + m, p, q)] = hi_flat ? a[idx(n, p, q)] : a[idx(n - m, p, q)];
          }
        } else {
          // Tangential: odd about a no-slip wall or an inlet (zero tangential velocity on
          // the boundary), even for free slip and outlets.
          auto sign = [](const Boundary& b) {
            return b.kind == BoundaryKind::no_slip || b.kind == BoundaryKind::velocity_inlet ? -1.0 : 1.0;
          };
          const double sl = sign(lower), su = sign(upper);
          for (int m = 0; m < g; ++m) a[idx(-1 - m, p, q)] = sl * a[idx(m, p, q)];
          for (int m = 0; m <= g; ++m) a[idx(n + m, p, q)] = su * a[idx(n - 1 - m, p, q)];
        }
      }
  }
}

void StaggeredGrid::fill_velocity_ghosts(std::vector<double>& u, std::vector<double>& v, std::vector<double>& w) const {
  fill_component(u, Staggering::u, false);
  fill_component(v, Staggering::v, false);
  if (spec_.two_d) std::fill(w.begin(), w.end(), 0.0);
  else fill_component(w, Staggering::w, false);
}

void StaggeredGrid::fill_scalar_ghosts(std::vector<double>& s) const { fill_component(s, Staggering::centre, false); }

void StaggeredGrid::fill_pressure_ghosts(std::vector<double>& a) const {
  const int g = ghosts;
  const int axes = spec_.two_d ? 2 : 3;
  for (int axis = 0; axis < axes; ++axis) {
    const int n = n_[axis];
    const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
    // Index of (m along axis, p along o1, q along o2): a base and a stride (hot loop).
    const std::size_t stride[3] = {1, ext_[0], ext_[0] * ext_[1]};
    const std::size_t sa = stride[axis];
    auto idx = [&, sa](int m, int p, int q) {
      return static_cast<std::size_t>(static_cast<long>(at(0, 0, 0)) + static_cast<long>(m) * static_cast<long>(sa) +
                                      static_cast<long>(p) * static_cast<long>(stride[o1]) +
                                      static_cast<long>(q) * static_cast<long>(stride[o2]));
    };
    const Boundary& lower = spec_.faces[2 * axis];
    const Boundary& upper = spec_.faces[2 * axis + 1];
    const int q0 = spec_.two_d && o2 == 2 ? 0 : -g, q1 = spec_.two_d && o2 == 2 ? 0 : n_[o2] + g;
    const int p0 = spec_.two_d && o1 == 2 ? 0 : -g, p1 = spec_.two_d && o1 == 2 ? 0 : n_[o1] + g;
    for (int q = q0; q <= q1; ++q)
      for (int p = p0; p <= p1; ++p) {
        if (lower.kind == BoundaryKind::periodic) {
          for (int m = -g; m < 0; ++m) a[idx(m, p, q)] = a[idx(wrap(m, n), p, q)];
          for (int m = n; m <= n + g; ++m) a[idx(m, p, q)] = a[idx(wrap(m, n), p, q)];
          continue;
        }
        // Lower side: ghost −1−m mirrors cell m about the face.
        for (int m = 0; m < g; ++m) {
          const double inner = a[idx(m, p, q)];
          a[idx(-1 - m, p, q)] = lower.kind == BoundaryKind::pressure_outlet
                                     ? 2.0 * lower.pressure - inner
                                     : a[idx(0, p, q)] - (m + 1) * (a[idx(n > 1 ? 1 : 0, p, q)] - a[idx(0, p, q)]);
        }
        for (int m = 0; m <= g; ++m) {
          const double inner = a[idx(n - 1 - m, p, q)];
          a[idx(n + m, p, q)] = upper.kind == BoundaryKind::pressure_outlet
                                    ? 2.0 * upper.pressure - inner
                                    : a[idx(n - 1, p, q)] + (m + 1) * (a[idx(n - 1, p, q)] - a[idx(n > 1 ? n - 2 : n - 1, p, q)]);
        }
      }
  }
}

void StaggeredGrid::fill_even_ghosts(std::vector<double>& a, Staggering s) const { fill_component(a, s, true); }

}  // namespace cdm::fluid
