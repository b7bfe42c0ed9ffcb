#include "cdm/solver/fluid/staggered_grid.hpp"

#include <algorithm>
#include <stdexcept>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/slot_pages.hpp"

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
  window_ = {0, n_[2]};
}

void StaggeredGrid::set_window(int lo, int hi) {
  if (spec_.two_d) return;
  lo = std::clamp(lo, 0, n_[2]);
  hi = std::clamp(hi, lo, n_[2]);
  if (wraps(lo, hi)) lo = 0, hi = n_[2];
  if (window_[0] == lo && window_[1] == hi) return;
  window_ = {lo, hi};
  ++window_moves_;
}

std::vector<double> StaggeredGrid::make_array() const {
  std::vector<double> a;
  assign_zeroed(a, padded_size());
  return a;
}

void StaggeredGrid::zero_outside_window(void* data, std::size_t bytes) const {
  if (window_whole()) return;
  const auto [lo, hi] = window_span();
  auto* const a = static_cast<unsigned char*>(data);
  zero_bytes(a, a + lo * bytes);
  zero_bytes(a + hi * bytes, a + padded_size() * bytes);
}

void StaggeredGrid::copy_window(const std::vector<double>& from, std::vector<double>& to) const {
  const auto [lo, hi] = window_span();
  std::copy(from.begin() + static_cast<std::ptrdiff_t>(lo), from.begin() + static_cast<std::ptrdiff_t>(hi),
            to.begin() + static_cast<std::ptrdiff_t>(lo));
}

void StaggeredGrid::get_window(InArchive& in, std::vector<double>& a) const {
  const std::size_t n = padded_size();
  if (in.get_length(n, sizeof(double)) != n) throw ArchiveError("a gas array has the wrong length");
  if (a.size() != n) a = make_array();
  else zero_outside_window(a);
  const auto [lo, hi] = window_span();
  in.skip(lo * sizeof(double));
  in.get_values(a.data() + lo, hi - lo);
  in.skip((n - hi) * sizeof(double));
}

void StaggeredGrid::fill_window(std::vector<double>& a, double value) const {
  const auto [lo, hi] = window_span();
  std::fill(a.begin() + static_cast<std::ptrdiff_t>(lo), a.begin() + static_cast<std::ptrdiff_t>(hi), value);
}

Vec3 StaggeredGrid::position(Staggering s, int i, int j, int k) const {
  return {lo_[0] + (i + offset(s, 0)) * h_[0], lo_[1] + (j + offset(s, 1)) * h_[1], lo_[2] + (k + offset(s, 2)) * h_[2]};
}

namespace {
int wrap(int m, int n) { return ((m % n) + n) % n; }

/// One grid line along an axis: sample m of it is at flat index base + m·stride.
struct GridLine {
  long base, stride;
  std::size_t operator()(int m) const { return static_cast<std::size_t>(base + static_cast<long>(m) * stride); }
};

/// Visit the grid lines along each axis, the ghost layers of the two other axes included:
/// wrap the ghosts of every line along a periodic axis, and call fill(axis, line) for every
/// line along a bounded one, with whether to fill its lower and its upper ghosts. A 2D
/// grid has one layer along z and nothing reads beyond it: no z pass, and the x and y
/// passes touch layer 0 only. Lines across z visit the window's planes only
/// (window_lines); the lines along z fill only the ends the window reaches.
template <class Fill>
void fill_ghosts_by_line(const StaggeredGrid& grid, std::vector<double>& a, Staggering s, Fill&& fill) {
  const int g = StaggeredGrid::ghosts;
  const bool two_d = grid.two_d();
  const auto [z0, z1] = grid.window_lines(s);
  for (int axis = 0; axis < grid.dims(); ++axis) {
    const int n = grid.n(axis);
    const bool lo_end = axis != 2 || z0 == -g, hi_end = axis != 2 || z1 == n + g;
    if (!lo_end && !hi_end) continue;
    const int o1 = (axis + 1) % 3, o2 = (axis + 2) % 3;
    int step[3] = {0, 0, 0};
    step[axis] = 1;
    const long stride = static_cast<long>(grid.at(step[0], step[1], step[2])) - static_cast<long>(grid.at(0, 0, 0));
    const bool periodic = grid.spec().periodic(axis);
    // A periodic line's ghost samples −g..−1 and n..n+g are copies of samples wrap(m, n).
    int from[2 * g + 1];
    for (int m = -g; m < 0; ++m) from[m + g] = wrap(m, n);
    for (int m = n; m <= n + g; ++m) from[g + m - n] = wrap(m, n);
    // The lines' indices along another axis b, its ghosts included: z's within the window.
    auto first = [&](int b) { return b != 2 ? -g : two_d ? 0 : z0; };
    auto last = [&](int b) { return b != 2 ? grid.n(b) + g : two_d ? 0 : z1; };
    const int q0 = first(o2), q1 = last(o2), p0 = first(o1), p1 = last(o1);
    for (int q = q0; q <= q1; ++q)
      for (int p = p0; p <= p1; ++p) {
        int start[3];  // sample 0 of the line at (p along o1, q along o2)
        start[axis] = 0;
        start[o1] = p;
        start[o2] = q;
        const GridLine idx{static_cast<long>(grid.at(start[0], start[1], start[2])), stride};
        if (periodic) {
          for (int m = -g; m < 0 && lo_end; ++m) a[idx(m)] = a[idx(from[m + g])];
          for (int m = n; m <= n + g && hi_end; ++m) a[idx(m)] = a[idx(from[g + m - n])];
          continue;
        }
        fill(axis, idx, lo_end, hi_end);
      }
  }
}
}  // namespace

void StaggeredGrid::fill_component(std::vector<double>& a, Staggering s, bool even) const {
  const int g = ghosts;
  fill_ghosts_by_line(*this, a, s, [&](int axis, const GridLine& idx, bool lo_end, bool hi_end) {
    const int n = n_[axis];
    const bool normal = static_cast<int>(s) == axis;  // the component normal to these faces
    const Boundary& lower = spec_.faces[2 * axis];
    const Boundary& upper = spec_.faces[2 * axis + 1];
    if (s == Staggering::centre || (even && !normal)) {
      // Zero normal gradient: mirror about the boundary face.
      for (int m = 0; m < g && lo_end; ++m) a[idx(-1 - m)] = a[idx(m)];
      for (int m = 0; m <= g && hi_end; ++m) a[idx(n + m)] = a[idx(n - 1 - m)];
      return;
    }
    if (normal) {
      // The boundary faces are samples 0 and n.
      auto set_face = [&](const Boundary& b, int face, double inward_sign) {
        switch (b.kind) {
          case BoundaryKind::no_slip:
          case BoundaryKind::free_slip: a[idx(face)] = 0.0; break;
          case BoundaryKind::velocity_inlet: a[idx(face)] = inward_sign * b.normal_velocity; break;
          case BoundaryKind::pressure_outlet:
          case BoundaryKind::periodic: break;  // solved for, not imposed
        }
      };
      if (!even && lo_end) set_face(lower, 0, 1.0);
      if (!even && hi_end) set_face(upper, n, -1.0);
      const bool lo_flat = !even && lower.kind == BoundaryKind::pressure_outlet;
      const bool hi_flat = !even && upper.kind == BoundaryKind::pressure_outlet;
      for (int m = 1; m <= g; ++m) {
        if (lo_end) a[idx(-m)] = lo_flat ? a[idx(0)] : a[idx(m)];
        if (hi_end) a[idx(n + m)] = hi_flat ? a[idx(n)] : a[idx(n - m)];
      }
    } else {
      // Tangential: odd about a no-slip wall or an inlet (zero tangential velocity on
      // the boundary), even for free slip and outlets.
      auto sign = [](const Boundary& b) {
        return b.kind == BoundaryKind::no_slip || b.kind == BoundaryKind::velocity_inlet ? -1.0 : 1.0;
      };
      const double sl = sign(lower), su = sign(upper);
      for (int m = 0; m < g && lo_end; ++m) a[idx(-1 - m)] = sl * a[idx(m)];
      for (int m = 0; m <= g && hi_end; ++m) a[idx(n + m)] = su * a[idx(n - 1 - m)];
    }
  });
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
  fill_ghosts_by_line(*this, a, Staggering::centre, [&](int axis, const GridLine& idx, bool lo_end, bool hi_end) {
    const int n = n_[axis];
    const Boundary& lower = spec_.faces[2 * axis];
    const Boundary& upper = spec_.faces[2 * axis + 1];
    // Lower side: ghost −1−m mirrors cell m about the face.
    for (int m = 0; m < g && lo_end; ++m) {
      const double inner = a[idx(m)];
      a[idx(-1 - m)] = lower.kind == BoundaryKind::pressure_outlet
                           ? 2.0 * lower.pressure - inner
                           : a[idx(0)] - (m + 1) * (a[idx(n > 1 ? 1 : 0)] - a[idx(0)]);
    }
    for (int m = 0; m <= g && hi_end; ++m) {
      const double inner = a[idx(n - 1 - m)];
      a[idx(n + m)] = upper.kind == BoundaryKind::pressure_outlet
                          ? 2.0 * upper.pressure - inner
                          : a[idx(n - 1)] + (m + 1) * (a[idx(n - 1)] - a[idx(n > 1 ? n - 2 : n - 1)]);
    }
  });
}

void StaggeredGrid::fill_even_ghosts(std::vector<double>& a, Staggering s) const { fill_component(a, s, true); }

}  // namespace cdm::fluid
