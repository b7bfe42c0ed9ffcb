#pragma once
/// @file gas_field.hpp
/// @brief The gas state on the staggered grid: face velocities, cell-centred pressure
/// and gas volume fraction, the pressure gradient on the faces, and the interpolators
/// that carry them to particle positions. Built only when a scene names a gas.
///
/// A prescribed field (prescribed_field.hpp) is sampled onto the faces — the grid, not
/// the closed form, is what particles see, so interpolation error is part of every
/// result. Every prescribed field here is separable in time, u(x, t) = shape(x) c(t):
/// the shape is sampled once and the time factor c(t) applied on interpolation, which
/// is exactly the grid sample of u(·, t) at each step (interpolation is linear).
#include <array>
#include <limits>
#include <memory>
#include <stdexcept>
#include <optional>
#include <utility>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/fluid/interpolation.hpp"
#include "cdm/solver/fluid/prescribed_field.hpp"
#include "cdm/solver/fluid/staggered_grid.hpp"

namespace cdm::fluid {

struct GasSpec {
  GridSpec grid;
  double density = 0.0;    // ρ_g [kg/m^3]
  double viscosity = 0.0;  // μ_g [Pa s]
  InterpolationScheme interpolation = InterpolationScheme::paper_lagrange2;
  std::optional<PrescribedFieldSpec> prescribed;  // set for modules.gas = "prescribed"
};

class GasField {
 public:
  /// @p gravity: the scene's g (zero without gravity), for the hydrostatic pressure.
  /// Only what the scene uses is allocated: the pressure and its face gradient when
  /// @p with_pressure, the gas volume fraction when @p with_void_fraction. It holds the
  /// planes of cells [@p planes.first, @p planes.second) along z from the start
  /// (hold_planes(); every plane by default): no other plane's memory is touched.
  GasField(const GasSpec& spec, Vec3 gravity, bool with_pressure, bool with_void_fraction,
           std::pair<int, int> planes = {0, std::numeric_limits<int>::max()});

  const GasSpec& spec() const { return spec_; }
  const StaggeredGrid& grid() const { return grid_; }
  /// Change the speed of the velocity inlet on @p face (0 x−, 1 x+, …, 5 z+).
  void set_inlet_velocity(int face, double v) {
    if (grid_.spec().faces[face].kind != BoundaryKind::velocity_inlet)
      throw std::logic_error("set_inlet_velocity: the face is not a velocity inlet");
    grid_.set_inlet_velocity(face, v);
  }
  /// The planes of cells [@p lo, @p hi) along z kept current (StaggeredGrid::set_window).
  void hold_planes(int lo, int hi) { grid_.set_window(lo, hi); }
  /// Zero every array's planes outside the window, their memory returned to the system
  /// (StaggeredGrid::zero_outside_window): after hold_planes() narrowed it.
  void zero_outside_window();
  double density() const { return spec_.density; }
  double viscosity() const { return spec_.viscosity; }
  const PrescribedField* prescribed() const { return prescribed_ ? &*prescribed_ : nullptr; }

  /// Bring a prescribed field to time @p t (a no-op for a solved gas).
  void set_time(double t);
  double time() const { return time_; }
  /// The factor c(t) the stored face velocities are scaled by (1 for a steady field).
  double time_factor() const { return scale_; }

  /// Gas velocity at a point of the domain (periodic coordinates wrapped into it).
  Vec3 velocity_at(Vec3 x) const {
    if (analytic_) return prescribed_->velocity(x, time_);
    return scale_ * velocity_interp_.at(x);
  }
  /// Superficial gas velocity ε_f u at a point: the face fluxes interpolated as the
  /// velocity is (after enable_superficial_velocity(), on a solved gas with a gas volume
  /// fraction; zero otherwise).
  Vec3 superficial_velocity_at(Vec3 x) const { return flux_interp_.at(x); }
  /// Keep the face fluxes ε_f u (and their interpolator) up to date at every refresh():
  /// only drag with coupling.gas_velocity = "superficial" reads them.
  void enable_superficial_velocity() {
    with_flux_ = true;
    refresh();
  }
  /// ∇p at a point, interpolated from the face differences of the cell-centred pressure.
  Vec3 pressure_gradient_at(Vec3 x) const {
    if (analytic_) return prescribed_->pressure_gradient(x);
    return gradient_interp_.at(x) + mean_pressure_gradient;
  }
  /// velocity_at(@p x) and pressure_gradient_at(@p x), to the bit, in @p u and @p grad_p:
  /// with trilinear interpolation from one set of stencils (the two fields share the
  /// staggering).
  void velocity_and_pressure_gradient_at(Vec3 x, Vec3& u, Vec3& grad_p) const {
    if (analytic_ || velocity_interp_.scheme() != InterpolationScheme::trilinear) {
      u = velocity_at(x);
      grad_p = pressure_gradient_at(x);
      return;
    }
    const VectorInterpolator::Stencils s = velocity_interp_.stencils(x);
    u = scale_ * velocity_interp_.sample(s);
    grad_p = gradient_interp_.sample(s) + mean_pressure_gradient;
  }
  /// Keep, at every refresh(), ∇p at the cell centres: along each axis the mean of the
  /// cell's two face gradients (cell_gpx/y/z; a solved gas). Two-way coupling reads them:
  /// weighted by a particle's deposition weights they give the pressure force whose sum
  /// over the particles is the one the gas's faces leave to the solids
  /// (coupling::particle_pressure_gradient).
  void enable_cell_pressure_gradient() {
    with_cell_gradient_ = true;
    refresh();
  }
  /// ∂p/∂x, ∂p/∂y, ∂p/∂z at the cell centres [Pa/m] (after enable_cell_pressure_gradient()).
  std::vector<double> cell_gpx, cell_gpy, cell_gpz;
  /// An imposed mean ∇P̄ [Pa/m] added to the grid's gradient (solved periodic gas).
  Vec3 mean_pressure_gradient;

  /// Wrap @p x into the domain along periodic axes.
  Vec3 wrap(Vec3 x) const;
  /// Whether @p x lies inside the domain (closed box).
  bool contains(Vec3 x) const;

  // Grid arrays (padded shape, ghosts filled).
  std::vector<double> u, v, w;     // face velocities [m/s] (for a prescribed field: the shape)
  std::vector<double> p;           // cell-centre pressure [Pa] (empty unless with_pressure)
  std::vector<double> eps_g;       // cell-centre gas volume fraction [-] (empty unless with_void_fraction)
  std::vector<double> gpx, gpy, gpz;  // ∂p/∂x on u-faces, ∂p/∂y on v-faces, ∂p/∂z on w-faces [Pa/m]
  bool has_pressure() const { return !p.empty(); }
  bool has_void_fraction() const { return !eps_g.empty(); }
  /// The gas volume fraction on face (i, j, k) of @p axis (between cells f − e_axis and
  /// f) from the cell values @p eps: their mean, and 1 on a velocity inlet. An inlet face
  /// carries the gas fraction of what enters, particle-free gas, as MFIX's inflow cells
  /// (BC_EP_G = 1): the inlet velocity is then the superficial velocity whatever the bed
  /// above it holds. Averaging with the cell inside would let a packed layer on the
  /// distributor throttle the inflow to ε·V.
  double face_void_fraction(const std::vector<double>& eps, int axis, int i, int j, int k) const {
    const int f[3] = {i, j, k};
    return face_void_fraction(eps, axis, f[axis], static_cast<std::ptrdiff_t>(grid_.at(i, j, k)));
  }
  /// The same for the face at index @p index along @p axis whose flat index (at()) is @p flat.
  double face_void_fraction(const std::vector<double>& eps, int axis, int index, std::ptrdiff_t flat) const {
    const GridSpec& gs = grid_.spec();
    if (!gs.periodic(axis) && (index == 0 || index == grid_.n(axis)) &&
        gs.faces[2 * axis + (index == 0 ? 0 : 1)].kind == BoundaryKind::velocity_inlet)
      return 1.0;
    return 0.5 * (eps[static_cast<std::size_t>(flat - grid_.stride(axis))] + eps[static_cast<std::size_t>(flat)]);
  }

  /// Recompute the face pressure gradient from p and refresh both interpolators; call
  /// after changing u, v, w or p.
  void refresh();

  /// The solved gas's state in a checkpoint: u, v, w, p, ε_g and the drag gradients.
  /// load_state throws ArchiveError if an array has the wrong length; call refresh() after.
  /// Each array goes through OutArchive::put_planes(): among processes that hold their
  /// reach only, each plane from its owner (the drag gradients of the faces normal to z
  /// from the owners of the end planes).
  void save_state(OutArchive& a) const;
  void load_state(InArchive& a);

  /// Fill p's ghost layers (solved gas): the grid's rule (StaggeredGrid::
  /// fill_pressure_ghosts), and on each face whose velocity is fixed the drag gradient
  /// below added to the extrapolated one.
  void fill_pressure_ghosts();
  /// On a face whose gas velocity is fixed (a wall or a velocity inlet; @p face 0 x−,
  /// 1 x+, …, 5 z+), per boundary cell (boundary_index()): what the drag on that face adds
  /// to the pressure gradient extrapolated from the first interior face [Pa/m]. The gas
  /// equations do not solve a fixed face, but the particles next to it feel its gradient:
  /// the face's own steady momentum balance sets it, ε ∂p/∂n = ε ρ_g g_n + f, so the
  /// ghost carries f_b/ε_b − f_1/ε_1, the boundary face's drag per unit volume (its half
  /// cell's) less the first interior face's, over their gas fractions; zero without drag,
  /// where the ghost extrapolates linearly. GasSolver::step sets it. Empty on periodic
  /// and outlet faces.
  std::vector<double>& drag_gradient(int face) { return drag_gradient_[static_cast<std::size_t>(face)]; }
  const std::vector<double>& drag_gradient(int face) const { return drag_gradient_[static_cast<std::size_t>(face)]; }
  /// Calls f(axis, side, c, index) for every cell within the grid's window
  /// (StaggeredGrid::set_window) next to a face with a drag_gradient():
  /// the face normal to @p axis on its lower (side 0) or upper (1) end, c the cell's
  /// (i, j, k), index its place in drag_gradient(2 axis + side).
  template <class F>
  void for_each_fixed_face_cell(F&& f) const {
    for (int a = 0; a < grid_.dims(); ++a)
      for (int side = 0; side < 2; ++side) {
        if (drag_gradient(2 * a + side).empty()) continue;
        const int o1 = a == 0 ? 1 : 0, o2 = a == 2 ? 1 : 2;
        // z within the grid's window (StaggeredGrid::set_window).
        const auto [k0, k1] = grid_.window();
        const int q0 = o2 == 2 ? k0 : 0, q1 = o2 == 2 ? k1 : grid_.n(o2);
        if (a == 2 && (side == 0 ? k0 > 0 : k1 < grid_.n(2))) continue;
        for (int q = q0; q < q1; ++q)
          for (int r = 0; r < grid_.n(o1); ++r) {
            int c[3];
            c[o1] = r;
            c[o2] = q;
            c[a] = side == 0 ? 0 : grid_.n(a) - 1;
            f(a, side, c, boundary_index(a, c[0], c[1], c[2]));
          }
      }
  }
  /// Index into drag_gradient() of the boundary cell (i, j, k) of a face normal to @p axis:
  /// the other two indices, the lower axis fastest.
  std::size_t boundary_index(int axis, int i, int j, int k) const {
    const int t[3] = {i, j, k};
    const int o1 = axis == 0 ? 1 : 0, o2 = axis == 2 ? 1 : 2;
    return static_cast<std::size_t>(t[o1]) + static_cast<std::size_t>(grid_.n(o1)) * static_cast<std::size_t>(t[o2]);
  }

 private:
  void sample_prescribed();

  GasSpec spec_;
  StaggeredGrid grid_;
  std::optional<PrescribedField> prescribed_;
  VectorInterpolator velocity_interp_, gradient_interp_, flux_interp_;
  std::vector<double> flux_u_, flux_v_, flux_w_;  // ε_f u on the faces (solved gas with ε_g)
  std::array<std::vector<double>, 6> drag_gradient_;
  bool with_flux_ = false;                         // see enable_superficial_velocity()
  bool with_cell_gradient_ = false;                // see enable_cell_pressure_gradient()
  double scale_ = 1.0;
  double time_ = 0.0;
  bool analytic_ = false;  // interpolation "analytic": the closed form at the particle
};

}  // namespace cdm::fluid
