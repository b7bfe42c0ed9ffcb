#pragma once
/// @file staggered_grid.hpp
/// @brief Uniform staggered (MAC) grid in 2D or 3D, with ghost layers.
///
/// Cell (i, j, k), 0 ≤ i < nx, spans [lo.x + i hx, lo.x + (i+1) hx] × … . Scalars
/// (pressure, gas volume fraction) live at cell centres; the velocity component along
/// an axis lives on the faces normal to that axis (Harlow & Welch 1965; Garg et al.
/// 2012 §2.1: u on east faces, v on north faces):
///   u(i, j, k) at (lo.x + i hx,       lo.y + (j+½) hy, lo.z + (k+½) hz),  0 ≤ i ≤ nx
///   v(i, j, k) at (lo.x + (i+½) hx,   lo.y + j hy,     lo.z + (k+½) hz),  0 ≤ j ≤ ny
///   w(i, j, k) at (lo.x + (i+½) hx,   lo.y + (j+½) hy, lo.z + k hz),      0 ≤ k ≤ nz
/// Every array has the same padded shape, (n+1+2g) per axis with g = 2 ghost layers,
/// so all stencils share one index map. A two-dimensional grid has nz = 1 and no z
/// dependence: w ≡ 0 and nothing is interpolated along z.
///
/// Ghost layers are filled from the boundary conditions (fill_ghosts):
///  - periodic: values wrap (face n ≡ face 0 for the normal component);
///  - no-slip wall: normal component = 0 on the wall face and mirrored evenly beyond
///    it (∂v_n/∂n = 0 at a wall where the tangential velocity vanishes, from
///    continuity); tangential components mirrored oddly about the wall, so that the
///    wall value is the wall's (zero) velocity to second order;
///  - free-slip wall: normal as no-slip, tangential mirrored evenly (zero shear);
///  - velocity inlet: normal component = the inlet velocity on the boundary face,
///    tangential components odd about the inlet's tangential velocity (zero);
///  - pressure outlet: zero normal gradient of every velocity component.
/// Cell-centred scalars get zero normal gradient at every non-periodic boundary.
#include <algorithm>
#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "cdm/solver/vec3.hpp"
#include "cdm/solver/keywords.hpp"

namespace cdm {
class InArchive;
}

namespace cdm::fluid {

enum class BoundaryKind { periodic, no_slip, free_slip, velocity_inlet, pressure_outlet };
inline constexpr Keywords<BoundaryKind, 5> boundary_keywords{{{"periodic", BoundaryKind::periodic}, {"no_slip", BoundaryKind::no_slip}, {"free_slip", BoundaryKind::free_slip}, {"velocity_inlet", BoundaryKind::velocity_inlet}, {"pressure_outlet", BoundaryKind::pressure_outlet}}};
inline const char* to_string(BoundaryKind k) { return keyword_of(boundary_keywords, k); }

struct Boundary {
  BoundaryKind kind = BoundaryKind::no_slip;
  double normal_velocity = 0.0;  // velocity_inlet: gas velocity along the inward normal [m/s]
  double pressure = 0.0;         // pressure_outlet: pressure on the boundary [Pa]
};

/// Geometry and boundary conditions of a grid (SI). Faces: 0 x−, 1 x+, 2 y−, 3 y+, 4 z−, 5 z+.
struct GridSpec {
  Vec3 lo, hi;                      // domain corners [m]
  std::array<int, 3> cells{1, 1, 1};  // nx, ny, nz (nz = 1 and two_d for a 2D grid)
  bool two_d = false;
  std::array<Boundary, 6> faces{};
  bool periodic(int axis) const { return faces[2 * axis].kind == BoundaryKind::periodic; }
};

/// Which array a component lives in; its location offset along each axis is 0 (on the
/// faces normal to that axis) or ½ (at cell centres).
enum class Staggering { u, v, w, centre };

/// The smallest flat range [first, last) holding the ranges @p a and @p b (a range with
/// first >= second is empty).
inline std::pair<std::size_t, std::size_t> span_union(std::pair<std::size_t, std::size_t> a,
                                                      std::pair<std::size_t, std::size_t> b) {
  if (b.first >= b.second) return a;
  if (a.first >= a.second) return b;
  return {std::min(a.first, b.first), std::max(a.second, b.second)};
}

class StaggeredGrid {
 public:
  static constexpr int ghosts = 2;

  explicit StaggeredGrid(const GridSpec& spec);

  const GridSpec& spec() const { return spec_; }
  /// Change a velocity inlet's speed (a run that ramps its inflow).
  void set_inlet_velocity(int face, double v) { spec_.faces[face].normal_velocity = v; }
  int n(int axis) const { return n_[axis]; }
  double h(int axis) const { return h_[axis]; }
  double inv_h(int axis) const { return inv_h_[axis]; }
  double lo(int axis) const { return lo_[axis]; }
  double length(int axis) const { return n_[axis] * h_[axis]; }
  bool two_d() const { return spec_.two_d; }
  int dims() const { return spec_.two_d ? 2 : 3; }
  double cell_volume() const { return h_[0] * h_[1] * h_[2]; }
  std::size_t cell_count() const { return static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]; }

  /// Flat index of (i, j, k); each may range over [-ghosts, n + ghosts].
  std::size_t at(int i, int j, int k) const {
    return (static_cast<std::size_t>(k + ghosts) * ext_[1] + static_cast<std::size_t>(j + ghosts)) * ext_[0] +
           static_cast<std::size_t>(i + ghosts);
  }
  std::size_t padded_size() const { return ext_[0] * ext_[1] * ext_[2]; }
  /// The flat index where stored plane @p k along z begins (its ghost rows included), and
  /// the values a stored plane holds.
  std::size_t plane_start(int k) const { return at(-ghosts, -ghosts, k); }
  std::size_t plane_size() const { return ext_[0] * ext_[1]; }
  /// What at() adds for one step along @p axis.
  std::ptrdiff_t stride(int axis) const {
    return axis == 0 ? 1 : static_cast<std::ptrdiff_t>(axis == 1 ? ext_[0] : ext_[0] * ext_[1]);
  }
  /// A zero-filled array of the padded shape, its pages uncommitted until written
  /// (slot_pages.hpp): a plane no loop writes costs no memory.
  std::vector<double> make_array() const;

  /// Position of sample (i, j, k) of an array with the given staggering.
  Vec3 position(Staggering s, int i, int j, int k) const;
  /// Offset (0 or ½) of a staggering along @p axis.
  static double offset(Staggering s, int axis) {
    return static_cast<int>(s) == axis ? 0.0 : 0.5;
  }
  /// Number of stored (non-ghost) samples along @p axis: n + 1 for the face-normal
  /// component on a non-periodic axis, n otherwise (face n ≡ face 0 when periodic).
  int samples(Staggering s, int axis) const {
    return static_cast<int>(s) == axis && !spec_.periodic(axis) ? n_[axis] + 1 : n_[axis];
  }

  /// The planes of cells [@p lo, @p hi) along z whose values are kept current: among MPI
  /// processes sharing the gas by planes, a process's reach (plane_share.hpp); every plane
  /// by default, always on a 2D grid, and along a periodic z wherever the window would
  /// reach an end (its ghosts wrap to the planes past the other end). The ghost fills and the
  /// loops that derive one array from another visit these planes only (and the ghost
  /// planes beyond them where they reach an end of the grid); elsewhere nothing reads the
  /// arrays, and their owners zero them there (zero_outside_window), which costs no memory.
  void set_window(int lo, int hi);
  /// Whether a window of planes [@p lo, @p hi) is every plane because it wraps: along a
  /// periodic z, one that reaches an end (set_window makes it whole).
  bool wraps(int lo, int hi) const { return spec_.periodic(2) && (lo <= 0 || hi >= n_[2]); }
  std::pair<int, int> window() const { return {window_[0], window_[1]}; }
  /// How many times set_window() has changed the window: an array's owner that compares
  /// it with the count at its last zero_outside_window() knows whether to call it again.
  std::size_t window_moves() const { return window_moves_; }
  /// Zero the samples of an array of the padded shape at @p data (@p bytes a sample: 8
  /// for a double, 24 for three interleaved) outside window_span(), their whole pages
  /// returned to the system (zero_bytes): planes beyond a process's reach then cost no
  /// memory until written. Nothing where the window is whole. Only for arrays whose
  /// values beyond the window nothing reads (set_window).
  void zero_outside_window(void* data, std::size_t bytes) const;
  /// The same for an array @p a of padded_size() values (nothing for one of another size,
  /// such as one not allocated).
  template <class T>
  void zero_outside_window(std::vector<T>& a) const {
    if (a.size() == padded_size()) zero_outside_window(a.data(), sizeof(T));
  }
  /// The same for each whole block of padded_size() values of @p s, sums by cells block
  /// after block (ExactSums); what follows the last whole block is left as it is.
  template <class Sums>
  void zero_blocks_outside_window(Sums& s) const {
    for (std::size_t b = 0; (b + 1) * padded_size() <= s.size(); ++b)
      zero_outside_window(s.data() + b * padded_size(), sizeof(*s.data()));
  }
  bool window_whole() const { return window_[0] == 0 && window_[1] == n_[2]; }
  /// The stored planes [first, last) along z of an array staggered as @p s within the
  /// window (for w, the face above the window's last cell too).
  std::pair<int, int> window_planes(Staggering s) const {
    return {window_[0], std::min(window_[1] + (s == Staggering::w ? 1 : 0), samples(s, 2))};
  }
  /// The planes along z, ghost planes included, [first, last] of an array staggered as
  /// @p s that the window's ghost fills visit: window_planes(), and the ghost planes
  /// beyond an end of the grid it reaches.
  std::pair<int, int> window_lines(Staggering s = Staggering::w) const {
    return {window_[0] == 0 ? -ghosts : window_[0], window_[1] == n_[2] ? n_[2] + ghosts : window_planes(s).second - 1};
  }
  /// The flat range [first, last) of the stored planes window_lines() spans (the faces
  /// along z's: every array's).
  std::pair<std::size_t, std::size_t> window_span() const {
    const auto [lo, hi] = window_lines();
    return {plane_start(lo), plane_start(hi) + plane_size()};
  }
  /// @p to = @p from, and @p a = @p value, over window_span() (arrays of the padded shape).
  void copy_window(const std::vector<double>& from, std::vector<double>& to) const;
  void fill_window(std::vector<double>& a, double value) const;
  /// Read an array of the padded shape from @p in (as OutArchive::put() wrote it) into
  /// @p a, keeping window_span() only: the values outside are read past, and @p a's
  /// planes there left zero, their memory uncommitted (a restart among processes).
  void get_window(InArchive& in, std::vector<double>& a) const;

  /// Fill the ghost layers of the three velocity components from the boundary conditions
  /// (and impose the boundary-face normal velocity on walls and inlets).
  void fill_velocity_ghosts(std::vector<double>& u, std::vector<double>& v, std::vector<double>& w) const;
  /// Fill the ghost layers of a cell-centred scalar: periodic wrap or zero normal gradient.
  void fill_scalar_ghosts(std::vector<double>& s) const;
  /// Fill the ghost layers of a cell-centred pressure: periodic wrap, the outlet pressure
  /// on a pressure-outlet face (Dirichlet), linear extrapolation at walls and inlets (so
  /// that a hydrostatic gradient continues to the boundary face).
  void fill_pressure_ghosts(std::vector<double>& p) const;
  /// Fill the ghost layers of any staggered array by periodic wrap or even mirroring
  /// (zero normal gradient), whatever the boundary kind; boundary samples are kept.
  void fill_even_ghosts(std::vector<double>& a, Staggering s) const;

 private:
  void fill_component(std::vector<double>& a, Staggering s, bool even) const;

  GridSpec spec_;
  std::array<int, 3> n_;
  std::array<double, 3> h_, inv_h_, lo_;
  std::array<std::size_t, 3> ext_;
  std::array<int, 2> window_;
  std::size_t window_moves_ = 0;
};

}  // namespace cdm::fluid
