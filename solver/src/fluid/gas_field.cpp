#include "cdm/solver/fluid/gas_field.hpp"

#include <cmath>

namespace cdm::fluid {

GasField::GasField(const GasSpec& spec, Vec3 gravity, bool with_pressure, bool with_void_fraction,
                   std::pair<int, int> planes)
    : spec_(spec),
      grid_(spec.grid),
      velocity_interp_(grid_, spec.interpolation),
      gradient_interp_(grid_, spec.interpolation),
      flux_interp_(grid_, spec.interpolation == InterpolationScheme::analytic ? InterpolationScheme::trilinear
                                                                             : spec.interpolation) {
  grid_.set_window(planes.first, planes.second);
  u = grid_.make_array();
  v = grid_.make_array();
  w = grid_.make_array();
  if (with_pressure) {
    p = grid_.make_array();
    gpx = grid_.make_array();
    gpy = grid_.make_array();
    gpz = grid_.make_array();
  }
  if (with_void_fraction) {
    eps_g = grid_.make_array();
    grid_.fill_window(eps_g, 1.0);
  }
  if (with_pressure && !spec.prescribed)
    for (int a = 0; a < grid_.dims(); ++a)
      for (int side = 0; side < 2; ++side) {
        if (spec.grid.periodic(a) || spec.grid.faces[2 * a + side].kind == BoundaryKind::pressure_outlet) continue;
        const int o1 = a == 0 ? 1 : 0, o2 = a == 2 ? 1 : 2;
        drag_gradient_[static_cast<std::size_t>(2 * a + side)].assign(
            static_cast<std::size_t>(grid_.n(o1)) * static_cast<std::size_t>(grid_.n(o2)), 0.0);
      }
  if (spec.prescribed) {
    prescribed_.emplace(*spec.prescribed, spec.grid.lo, spec.grid.hi, spec.density, gravity);
    sample_prescribed();
    analytic_ = spec.interpolation == InterpolationScheme::analytic;
  }
  refresh();
  set_time(0.0);
}

void GasField::zero_outside_window() {
  for (auto* a : {&u, &v, &w, &p, &eps_g, &gpx, &gpy, &gpz, &cell_gpx, &cell_gpy, &cell_gpz, &flux_u_, &flux_v_, &flux_w_})
    grid_.zero_outside_window(*a);
  for (auto* i : {&velocity_interp_, &gradient_interp_, &flux_interp_}) i->zero_outside_window();
}

void GasField::sample_prescribed() {
  const StaggeredGrid& g = grid_;
  auto sample = [&](std::vector<double>& a, Staggering s, double Vec3::*comp) {
    for (int k = 0; k < g.samples(s, 2); ++k)
      for (int j = 0; j < g.samples(s, 1); ++j)
        for (int i = 0; i < g.samples(s, 0); ++i) a[g.at(i, j, k)] = prescribed_->shape(g.position(s, i, j, k)).*comp;
  };
  sample(u, Staggering::u, &Vec3::x);
  sample(v, Staggering::v, &Vec3::y);
  if (!g.two_d()) sample(w, Staggering::w, &Vec3::z);
  g.fill_velocity_ghosts(u, v, w);
  if (has_pressure() && prescribed_->has_pressure()) {
    for (int k = 0; k < g.n(2); ++k)
      for (int j = 0; j < g.n(1); ++j)
        for (int i = 0; i < g.n(0); ++i) p[g.at(i, j, k)] = prescribed_->pressure(g.position(Staggering::centre, i, j, k));
  }
}

void GasField::refresh() {
  const StaggeredGrid& g = grid_;
  velocity_interp_.update(u, v, w);
  if (with_flux_ && !prescribed_ && has_void_fraction()) {
    // Face fluxes ε_f u with ε_f as the gas solver's continuity uses it.
    if (flux_u_.size() != u.size())
      for (auto* f : {&flux_u_, &flux_v_, &flux_w_}) *f = grid_.make_array();
    std::vector<double>* flux[3] = {&flux_u_, &flux_v_, &flux_w_};
    const std::vector<double>* vel[3] = {&u, &v, &w};
    for (int a = 0; a < g.dims(); ++a) {
      const auto s = static_cast<Staggering>(a);
      const auto [k0, k1] = g.window_planes(s);
      for (int k = k0; k < k1; ++k)
        for (int j = 0; j < g.samples(s, 1); ++j)
          for (int i = 0; i < g.samples(s, 0); ++i) {
            const std::size_t at = g.at(i, j, k);
            (*flux[a])[at] = face_void_fraction(eps_g, a, i, j, k) * (*vel[a])[at];
          }
    }
    g.fill_velocity_ghosts(flux_u_, flux_v_, flux_w_);
    flux_interp_.update(flux_u_, flux_v_, flux_w_);
  }
  if (!has_pressure()) return;
  if (prescribed_ && prescribed_->has_pressure()) {
    // Face gradients from the closed-form pressure at the centres either side of each
    // face, boundary faces included (a hydrostatic pressure is linear, not mirrored).
    auto grad = [&](std::vector<double>& a, Staggering s, int axis) {
      for (int k = 0; k < g.samples(s, 2); ++k)
        for (int j = 0; j < g.samples(s, 1); ++j)
          for (int i = 0; i < g.samples(s, 0); ++i) {
            Vec3 x = g.position(s, i, j, k), lo = x, hi = x;
            double* l = axis == 0 ? &lo.x : axis == 1 ? &lo.y : &lo.z;
            double* h = axis == 0 ? &hi.x : axis == 1 ? &hi.y : &hi.z;
            *l -= 0.5 * g.h(axis);
            *h += 0.5 * g.h(axis);
            a[g.at(i, j, k)] = (prescribed_->pressure(hi) - prescribed_->pressure(lo)) / g.h(axis);
          }
    };
    grad(gpx, Staggering::u, 0);
    grad(gpy, Staggering::v, 1);
    if (!g.two_d()) grad(gpz, Staggering::w, 2);
  } else {
    const std::vector<double>& pp = p;
    fill_pressure_ghosts();
    std::vector<double>* grad[3] = {&gpx, &gpy, &gpz};
    for (int a = 0; a < g.dims(); ++a) {
      const auto s = static_cast<Staggering>(a);
      const std::size_t down = static_cast<std::size_t>(g.stride(a));
      const auto [k0, k1] = g.window_planes(s);
      for (int k = k0; k < k1; ++k)
        for (int j = 0; j < g.samples(s, 1); ++j)
          for (int i = 0; i < g.samples(s, 0); ++i) {
            const std::size_t f = g.at(i, j, k);
            (*grad[a])[f] = (pp[f] - pp[f - down]) / g.h(a);
          }
    }
  }
  // The gradient's ghosts: periodic wrap, else mirrored evenly (zero normal derivative
  // of the gradient), which is exact for the linear hydrostatic part.
  if (!prescribed_) fill_pressure_ghosts();
  else g.fill_scalar_ghosts(p);
  g.fill_even_ghosts(gpx, Staggering::u);
  g.fill_even_ghosts(gpy, Staggering::v);
  if (!g.two_d()) g.fill_even_ghosts(gpz, Staggering::w);
  gradient_interp_.update(gpx, gpy, gpz);
  if (!with_cell_gradient_ || prescribed_) return;
  if (cell_gpx.size() != gpx.size())
    for (auto* c : {&cell_gpx, &cell_gpy, &cell_gpz}) *c = g.make_array();
  const std::vector<double>* face[3] = {&gpx, &gpy, &gpz};
  std::vector<double>* cell[3] = {&cell_gpx, &cell_gpy, &cell_gpz};
  const auto [k0, k1] = g.window_planes(Staggering::centre);
  for (int a = 0; a < g.dims(); ++a) {
    const std::size_t up = static_cast<std::size_t>(g.stride(a));
    for (int k = k0; k < k1; ++k)
      for (int j = 0; j < g.n(1); ++j)
        for (int i = 0; i < g.n(0); ++i) {
          const std::size_t c = g.at(i, j, k);
          (*cell[a])[c] = 0.5 * ((*face[a])[c] + (*face[a])[c + up]);
        }
  }
}

void GasField::fill_pressure_ghosts() {
  const StaggeredGrid& g = grid_;
  g.fill_pressure_ghosts(p);
  for_each_fixed_face_cell([&](int a, int side, int c[3], std::size_t at) {
    const double d = g.h(a) * drag_gradient(2 * a + side)[at];
    if (d == 0.0) return;
    // Lower side: ghost −1−m lies m + 1 cells below cell 0; upper: ghost n + m lies
    // m + 1 above cell n − 1 (as the grid's extrapolation counts them).
    const int n = g.n(a);
    for (int m = 0; m < StaggeredGrid::ghosts + side; ++m) {
      c[a] = side == 0 ? -1 - m : n + m;
      p[g.at(c[0], c[1], c[2])] += side == 0 ? -(m + 1) * d : (m + 1) * d;
    }
  });
}

void GasField::save_state(OutArchive& a) const {
  const StaggeredGrid& g = grid_;
  const auto planes = [&](Staggering s) {
    return OutArchive::Planes{g.plane_start(0), g.plane_size(), g.samples(s, 2)};
  };
  a.put_planes(u, planes(Staggering::u));
  a.put_planes(v, planes(Staggering::v));
  a.put_planes(w, planes(Staggering::w));
  a.put_planes(p, planes(Staggering::centre));
  a.put_planes(eps_g, planes(Staggering::centre));
  // A face normal to x or y holds a row of cells a plane; one normal to z has no planes,
  // its values all before plane 0 (the lower face: the first plane's owner's) or after the
  // last (the upper: the last plane's owner's).
  for (int f = 0; f < 6; ++f) {
    const std::vector<double>& d = drag_gradient_[static_cast<std::size_t>(f)];
    const int axis = f / 2, across = axis == 0 ? 1 : 0;
    a.put_planes(d, axis < 2 ? OutArchive::Planes{0, static_cast<std::size_t>(g.n(across)), g.n(2)}
                             : OutArchive::Planes{f == 4 ? d.size() : 0, 0, g.n(2)});
  }
}

void GasField::load_state(InArchive& a) {
  auto arr = [&](std::vector<double>& x, std::size_t want) {
    a.get(x, want);
    if (x.size() != want) throw ArchiveError("a gas array has the wrong length");
  };
  // Each process keeps the planes it holds (hold_planes); it receives the others' it
  // reads from their owners (GasSolver::read_planes).
  for (auto* x : {&u, &v, &w, &p, &eps_g}) grid_.get_window(a, *x);
  for (auto& d : drag_gradient_) arr(d, d.size());
}

void GasField::set_time(double t) {
  time_ = t;
  scale_ = prescribed_ ? prescribed_->time_factor(t) : 1.0;
}

Vec3 GasField::wrap(Vec3 x) const {
  double* c[3] = {&x.x, &x.y, &x.z};
  for (int a = 0; a < (grid_.two_d() ? 2 : 3); ++a) {  // a 2D gas has no z dependence: z is not wrapped
    if (!grid_.spec().periodic(a)) continue;
    const double L = grid_.length(a), lo = grid_.lo(a);
    if (*c[a] >= lo && *c[a] < lo + L) continue;  // inside already: no fmod
    double r = std::fmod(*c[a] - lo, L);
    if (r < 0) r += L;
    if (r >= L) r = 0.0;  // fmod of a value just below 0 can round to L
    *c[a] = lo + r;
  }
  return x;
}

bool GasField::contains(Vec3 x) const {
  const double c[3] = {x.x, x.y, x.z};
  for (int a = 0; a < 3; ++a)
    if (!(c[a] >= grid_.lo(a) && c[a] <= grid_.lo(a) + grid_.length(a))) return false;
  return true;
}

}  // namespace cdm::fluid
