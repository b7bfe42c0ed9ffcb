#include "cdm/solver/fluid/gas_solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/mpi_session.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/slot_pages.hpp"

namespace cdm::fluid {

namespace {

/// f(i, j, k) for every stored sample of an array staggered as @p s (for the planes k of
/// @p share's process only, given one), k split among threads when @p threads (f must
/// then be safe to call from any thread).
template <class F>
void for_each_sample(const StaggeredGrid& g, Staggering s, bool threads, F&& f, const PlaneShare* share = nullptr) {
  const int n0 = g.samples(s, 0), n1 = g.samples(s, 1), n2 = g.samples(s, 2);
  // Not bindings: clang cannot share them with an OpenMP region.
  const std::pair<int, int> mine = share ? share->mine(n2) : std::pair{0, n2};
  const int k0 = mine.first, k1 = mine.second;
#pragma omp parallel for schedule(static) if (threads)
  for (int k = k0; k < k1; ++k)
    for (int j = 0; j < n1; ++j)
      for (int i = 0; i < n0; ++i) f(i, j, k);
}

}  // namespace

GasSolver::GasSolver(GasField& gas, const GasSolverSpec& spec) : gas_(gas), spec_(spec) {
  const StaggeredGrid& g = gas_.grid();
  force_u = g.make_array();
  force_v = g.make_array();
  force_w = g.make_array();
  us_ = g.make_array();
  vs_ = g.make_array();
  ws_ = g.make_array();
  phi_ = g.make_array();
  if (!gas_.has_pressure() || !gas_.has_void_fraction())
    throw std::logic_error("GasSolver: the gas field needs its pressure and volume fraction arrays");
  for (auto& d : d_) d = g.make_array();
  assign_zeroed(phi_cells_, g.cell_count());
  assign_zeroed(b_cells_, g.cell_count());
  share_ = PlaneShare(PlaneShare::divides(spec_.division, g, mpi_world().size));
  if (divided()) {
    // The planes the field holds from the start (first_planes(), or every plane) are this
    // process's reach until read_planes() states another.
    const auto [k0, k1] = g.window();
    share_.set_reach(k0, k1 - 1);
    whole_ = share_.reach_whole(g.n(2));
  }
  spec_.pressure.divided = divided();
  pressure_ = std::make_unique<PressureSolver>(g, spec_.pressure);
  g.fill_scalar_ghosts(gas_.eps_g);
  g.fill_velocity_ghosts(gas_.u, gas_.v, gas_.w);
  gas_.fill_pressure_ghosts();
  gas_.refresh();
}

GasSolver::~GasSolver() = default;

void GasSolver::clear_force() {
  const StaggeredGrid& g = gas_.grid();
  for (auto* f : {&force_u, &force_v, &force_w}) g.fill_window(*f, 0.0);
}

bool GasSolver::unknown_face(int axis, int index) const {
  const GridSpec& s = gas_.grid().spec();
  const int n = gas_.grid().n(axis);
  if (s.periodic(axis)) return index >= 0 && index < n;
  if (index > 0 && index < n) return true;
  if (index == 0) return s.faces[2 * axis].kind == BoundaryKind::pressure_outlet;
  if (index == n) return s.faces[2 * axis + 1].kind == BoundaryKind::pressure_outlet;
  return false;
}

std::vector<char> GasSolver::unknown_faces(int axis) const {
  std::vector<char> u(static_cast<std::size_t>(gas_.grid().n(axis)) + 1);
  for (std::size_t i = 0; i < u.size(); ++i) u[i] = unknown_face(axis, static_cast<int>(i));
  return u;
}

double GasSolver::max_cfl(double dt) const { return health(dt).courant; }

GasSolver::Health GasSolver::health(double dt) const {
  const StaggeredGrid& g = gas_.grid();
  const std::vector<double>* comp[3] = {&gas_.u, &gas_.v, &gas_.w};
  // This process's planes of the cells, and of the stored ones (ghost rows included) its
  // own too, the ghost planes beyond an end by the process owning the plane there: each
  // stored value is read by a process that holds it current, and a maximum and a
  // conjunction are the same over any division.
  const int nz = g.n(2);
  const auto [k0, k1] = share_.mine(nz);
  double c = 0.0;
  for (int a = 0; a < g.dims(); ++a)
    for (int k = k0; k < k1; ++k)
      for (int j = 0; j < g.n(1); ++j)
        for (int i = 0; i < g.n(0); ++i) c = std::max(c, std::abs((*comp[a])[g.at(i, j, k)]) * dt / g.h(a));
  bool finite = true;
  if (k0 < k1) {
    const std::size_t first = g.plane_start(k0 == 0 ? -StaggeredGrid::ghosts : k0);
    const std::size_t last = k1 == nz ? g.padded_size() : g.plane_start(k1);
    for (const auto* v : comp)
      for (std::size_t i = first; i < last; ++i) finite = finite && std::isfinite((*v)[i]);
  }
  double worst[2] = {c, finite ? 0.0 : 1.0};
  share_.max(worst, 2);
  return {worst[0], worst[1] == 0.0};
}

double GasSolver::diffusion_number(double dt) const {
  const StaggeredGrid& g = gas_.grid();
  double s = 0.0;
  for (int a = 0; a < g.dims(); ++a) s += 1.0 / (g.h(a) * g.h(a));
  return gas_.viscosity() / gas_.density() * dt * s;
}

void GasSolver::predictor(double dt) {
  const StaggeredGrid& g = gas_.grid();
  const int dims = g.dims();
  const double rho = gas_.density(), mu = gas_.viscosity();
  const double* const E = gas_.eps_g.data();
  const std::vector<double>* const vel_of[3] = {&gas_.u, &gas_.v, &gas_.w};
  const double* const vel[3] = {gas_.u.data(), gas_.v.data(), gas_.w.data()};
  std::vector<double>* star[3] = {&us_, &vs_, &ws_};
  const double* const force[3] = {force_u.data(), force_v.data(), force_w.data()};
  const double gvec[3] = {spec_.gravity.x, spec_.gravity.y, spec_.gravity.z};
  const double mean_gp[3] = {spec_.mean_pressure_gradient.x, spec_.mean_pressure_gradient.y,
                             spec_.mean_pressure_gradient.z};
  const bool upwind = spec_.advection == AdvectionScheme::upwind;
  const bool advect = spec_.advection != AdvectionScheme::none;
  const std::ptrdiff_t stride[3] = {g.stride(0), g.stride(1), g.stride(2)};
  // A user's source is called from one thread only.
  const bool threads = !momentum_source && g.cell_count() > parallel_threshold;

  for (int c = 0; c < dims; ++c) {
    const double* const U = vel[c];
    std::vector<double>& star_c = *star[c];
    g.copy_window(*vel_of[c], star_c);  // fixed boundary faces keep their value
    double* const out = star_c.data();
    const auto s = static_cast<Staggering>(c);
    const std::vector<char> unknown = unknown_faces(c);
    const std::ptrdiff_t sc = stride[c];
    // Face f and the cells either side of it along c: f − e_c (index l) and f.
    auto face = [&](int i, int j, int k) {
      const int along = c == 0 ? i : c == 1 ? j : k;
      if (!unknown[static_cast<std::size_t>(along)]) return;
      const std::ptrdiff_t f = static_cast<std::ptrdiff_t>(g.at(i, j, k)), l = f - sc;
      const double eps_f = 0.5 * (E[l] + E[f]);
      const double u0 = U[f];
      double adv = 0.0, diff = 0.0;
      for (int d = 0; d < dims; ++d) {
        const double hd = g.h(d);
        if (d == c) {
          // Fluxes at the cell centres l and f (faces m, m+1 around cell m).
          auto flux = [&](std::ptrdiff_t cell) {
            const double ua = U[cell], ub = U[cell + sc];
            const double m = E[cell] * 0.5 * (ua + ub);
            const double q = upwind ? (m >= 0.0 ? ua : ub) : 0.5 * (ua + ub);
            return std::pair{m * q, E[cell] * mu * (ub - ua) / hd};
          };
          const auto [fa, da] = flux(f);
          const auto [fb, db] = flux(l);
          if (advect) adv += (fa - fb) / hd;
          diff += (da - db) / hd;
        } else {
          // Fluxes at the edges f ± ½e_d: mass flux from the d-velocities on the d-faces
          // there (at the two cells along c), ε the mean of the four cells around the
          // edge. An edge's lower samples are at offset t (0 for the upper edge, −e_d for
          // the lower), its upper ones at t + e_d.
          const double* const V = vel[d];
          const std::ptrdiff_t sd = stride[d];
          auto flux = [&](std::ptrdiff_t t) {
            const double vd = 0.5 * (V[l + t + sd] + V[f + t + sd]);
            const double eps_e = 0.25 * (E[l + t] + E[f + t] + E[l + t + sd] + E[f + t + sd]);
            const double ua = U[f + t], ub = U[f + t + sd];
            const double m = eps_e * vd;
            const double q = upwind ? (m >= 0.0 ? ua : ub) : 0.5 * (ua + ub);
            return std::pair{m * q, eps_e * mu * (ub - ua) / hd};
          };
          const auto [fu, du] = flux(0);
          const auto [fl, dl] = flux(-sd);
          if (advect) adv += (fu - fl) / hd;
          diff += (du - dl) / hd;
        }
      }
      double src = force[c][f];
      if (momentum_source) src += momentum_source(g.position(s, i, j, k), time_, c);
      // ε_f^{n+1} u* = ε_f^n u^n + Δt/ρ (−adv + diff + ε_f^n ρ g + f) − Δt/ρ ε_f^{n+1} ∂p^n/∂x:
      // the explicit part here; project() divides by ε_f^{n+1} and applies ∂p^n/∂x.
      out[f] = eps_f * u0 + dt / rho * (-adv + diff + eps_f * (rho * gvec[c] - mean_gp[c]) + src);
    };
    for_each_sample(g, s, threads, face, &share_);  // project() gathers u*
  }
}

void GasSolver::project(double dt, const std::vector<double>& eps_new) {
  const StaggeredGrid& g = gas_.grid();
  const GridSpec& gs = g.spec();
  const int dims = g.dims();
  const int nx = g.n(0), ny = g.n(1), nz = g.n(2);
  const double rho = gas_.density();
  std::vector<double>* star[3] = {&us_, &vs_, &ws_};
  std::vector<double>* vel[3] = {&gas_.u, &gas_.v, &gas_.w};
  const double* const E1 = eps_new.data();
  const double* const E0 = gas_.eps_g.data();
  const double* const P = gas_.p.data();
  const std::ptrdiff_t stride[3] = {g.stride(0), g.stride(1), g.stride(2)};
  const bool threads = g.cell_count() > parallel_threshold;
  bool has_outlet = false;
  for (int f = 0; f < 2 * dims; ++f) has_outlet |= gs.faces[f].kind == BoundaryKind::pressure_outlet;
  // The implicit drag (drag_u/v/w): Δt β/ρ on a face, and the pressure operator's coefficient there.
  const bool implicit = !drag_u.empty();
  const double* const beta[3] = {drag_u.data(), drag_v.data(), drag_w.data()};
  const double* const target[3] = {drag_target_u.data(), drag_target_v.data(), drag_target_w.data()};
  // ε_f^{n+1} on face f (flat index) at index `along` on axis a.
  auto face_eps = [&](int a, int along, std::ptrdiff_t f) { return gas_.face_void_fraction(eps_new, a, along, f); };
  auto drag_c = [&](int a, std::ptrdiff_t f) { return dt / rho * beta[a][f]; };
  auto face_coef = [&](int a, int along, std::ptrdiff_t f) {
    const double e = face_eps(a, along, f);
    return implicit ? e * e / (e + drag_c(a, f)) : e;
  };
  auto along = [](int a, int i, int j, int k) { return a == 0 ? i : a == 1 ? j : k; };
  // This process's planes of the faces and cells (plane_share.hpp), and their gathers.
  auto own_faces_of = [&](int c, auto&& f) { for_each_sample(g, static_cast<Staggering>(c), threads, f, &share_); };
  auto own_cells_of = [&](auto&& f) { for_each_sample(g, Staggering::centre, threads, f, &share_); };
  auto gather_velocity = [&](std::vector<double>* const comp[3]) {
    for (int c = 0; c < dims; ++c) gather(*comp[c], static_cast<Staggering>(c));
  };
  const std::pair<int, int> mine = share_.mine(nz);  // not bindings: clang cannot share them with OpenMP
  const int own_k0 = mine.first, own_k1 = mine.second;

  // u* holds ε_f^{n+1} u* − Δt/ρ ε_f^{n+1} ∂p^n... without the pressure term yet: divide
  // by ε_f^{n+1} and apply the old pressure gradient, so that us_ is u*.
  for (int c = 0; c < dims; ++c) {
    const std::vector<char> unknown = unknown_faces(c);
    double* const S = star[c]->data();
    const double h = g.h(c);
    own_faces_of(c, [&](int i, int j, int k) {
      const int m = along(c, i, j, k);
      if (!unknown[static_cast<std::size_t>(m)]) return;
      const std::ptrdiff_t f = static_cast<std::ptrdiff_t>(g.at(i, j, k));
      const double dp = (P[f] - P[f - stride[c]]) / h;
      if (implicit) {
        const double e = face_eps(c, m, f);
        S[f] = (S[f] + dt / rho * (target[c][f] - e * dp)) / (e + drag_c(c, f));
      } else {
        S[f] = S[f] / face_eps(c, m, f) - dt / rho * dp;
      }
    });
  }
  // The divergence below reads u* and v* on this process's planes of cells, all set
  // here, and w* up to the faces above them, which the next process may have set.
  if (dims == 3) gather(ws_, Staggering::w);
  g.fill_velocity_ghosts(us_, vs_, ws_);

  // The coefficient of −∇·(d ∇φ) on the faces 0..n along each axis that the pressure
  // solve reads (this process's planes where it divides the solve): d = ε_f^{n+1}, or
  // ε_f²/(ε_f + Δt β/ρ) with the implicit drag.
  const std::pair<int, int> read = pressure_->coefficient_planes();
  for (int a = 0; a < dims; ++a) {
    double* const D = d_[a].data();
    const int n0 = a == 0 ? nx + 1 : nx, n1 = a == 1 ? ny + 1 : ny, n2 = std::min(a == 2 ? nz + 1 : nz, read.second);
#pragma omp parallel for schedule(static) if (threads)
    for (int k = read.first; k < n2; ++k)
      for (int j = 0; j < n1; ++j)
        for (int i = 0; i < n0; ++i) {
          const std::ptrdiff_t f = static_cast<std::ptrdiff_t>(g.at(i, j, k));
          D[f] = face_coef(a, along(a, i, j, k), f);
        }
  }

  // Right-hand side: −ρ/Δt [∇·(ε_f^{n+1} u*) + (ε^{n+1} − ε^n)/Δt − s].
  double* const b = b_cells_.data();
  auto row = [&](int i, int j, int k) { return static_cast<std::size_t>(i + nx * (j + ny * k)); };
  auto divergence = [&](const double* const comp[3], int i, int j, int k) {
    const std::ptrdiff_t cell = static_cast<std::ptrdiff_t>(g.at(i, j, k));
    const int idx[3] = {i, j, k};
    double d = 0.0;
    for (int a = 0; a < dims; ++a) {
      const std::ptrdiff_t up = cell + stride[a];
      d += (face_eps(a, idx[a] + 1, up) * comp[a][up] - face_eps(a, idx[a], cell) * comp[a][cell]) / g.h(a);
    }
    return d;
  };
  const double* const sc[3] = {us_.data(), vs_.data(), ws_.data()};
  auto rhs = [&](int i, int j, int k) {
    const std::size_t cell = g.at(i, j, k);
    double src = (E1[cell] - E0[cell]) / dt;
    if (mass_source) src -= mass_source(g.position(Staggering::centre, i, j, k), time_ + dt);
    b[row(i, j, k)] = -rho / dt * (divergence(sc, i, j, k) + src);
  };
  // A user's source is called from one thread only.
  if (mass_source) {
    for (int k = own_k0; k < own_k1; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) rhs(i, j, k);
  } else {
    own_cells_of(rhs);
  }
  const std::size_t cell_plane = static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny);
  if (!pressure_->reads_own_planes()) share_.gather_all(b_cells_, 0, cell_plane, nz);
  // A = −L, so L φ = rhs becomes A φ = −rhs, and b already carries the minus sign.
  // φ starts from zero, not from the previous step's φ: that warm start saved 3 % of the
  // iterations on bench/scenes/gas_scaling.toml, and it would make a run restarted from
  // a checkpoint (which does not hold φ) differ from the uninterrupted one. A divided
  // solve reads its own planes' start only; the gathers below set the rest it reads.
  const auto phi_first = static_cast<std::ptrdiff_t>(cell_plane) * (pressure_->solves_own_planes() ? own_k0 : 0);
  const auto phi_last = static_cast<std::ptrdiff_t>(cell_plane) * (pressure_->solves_own_planes() ? own_k1 : nz);
  std::fill(phi_cells_.begin() + phi_first, phi_cells_.begin() + phi_last, 0.0);
  last_solve_ = pressure_->solve({&d_[0], &d_[1], &d_[2]}, b_cells_, phi_cells_);
  // A divided solve leaves each process its own planes of φ: the pressure is updated on
  // the planes in its reach.
  if (pressure_->solves_own_planes()) share_.gather(phi_cells_, 0, cell_plane, nz);
  // φ is copied and the pressure updated on the grid's window.
  const std::pair<int, int> updated = g.window_planes(Staggering::centre);
  const int up_k0 = updated.first, up_k1 = updated.second;  // not bindings: clang cannot share them with OpenMP
#pragma omp parallel for schedule(static) if (threads)
  for (int k = up_k0; k < up_k1; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) phi_[g.at(i, j, k)] = phi_cells_[row(i, j, k)];
  // φ ghosts: periodic wrap, zero normal gradient at walls/inlets, −φ at outlets.
  {
    GridSpec zero = gs;
    for (auto& f : zero.faces) f.pressure = 0.0;
    StaggeredGrid zero_grid(zero);
    zero_grid.set_window(g.window().first, g.window().second);
    zero_grid.fill_scalar_ghosts(phi_);
    const auto [z0, z1] = g.window_lines(Staggering::centre);
    for (int a = 0; a < dims; ++a)
      for (int side = 0; side < 2; ++side) {
        if (gs.faces[2 * a + side].kind != BoundaryKind::pressure_outlet) continue;
        const int o1 = (a + 1) % 3, o2 = (a + 2) % 3;
        for (int q = 0; q < g.n(o2); ++q)
          for (int p = 0; p < g.n(o1); ++p) {
            int in[3], gh[3];
            in[a] = side ? g.n(a) - 1 : 0;
            gh[a] = side ? g.n(a) : -1;
            in[o1] = gh[o1] = p;
            in[o2] = gh[o2] = q;
            if (gh[2] < z0 || gh[2] > z1) continue;
            phi_[g.at(gh[0], gh[1], gh[2])] = -phi_[g.at(in[0], in[1], in[2])];
          }
      }
  }

  // Correct the unknown faces and the pressure.
  const double* const PHI = phi_.data();
  for (int c = 0; c < dims; ++c) {
    const std::vector<char> unknown = unknown_faces(c);
    const double* const S = star[c]->data();
    double* const V = vel[c]->data();
    const double h = g.h(c);
    own_faces_of(c, [&](int i, int j, int k) {
      const int m = along(c, i, j, k);
      const std::ptrdiff_t f = static_cast<std::ptrdiff_t>(g.at(i, j, k));
      if (!unknown[static_cast<std::size_t>(m)]) {
        V[f] = S[f];
        return;
      }
      const double dphi = PHI[f] - PHI[f - stride[c]];
      if (implicit) {
        const double e = face_eps(c, m, f);
        V[f] = S[f] - dt / rho * (e / (e + drag_c(c, f))) * dphi / h;
      } else {
        V[f] = S[f] - dt / rho * dphi / h;
      }
    });
  }
  gather_velocity(vel);
  double* const PN = gas_.p.data();
#pragma omp parallel for schedule(static) if (threads)
  for (int k = up_k0; k < up_k1; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) PN[g.at(i, j, k)] += PHI[g.at(i, j, k)];
  if (!has_outlet) {
    // Without an outlet the pressure is defined up to a constant: its mean over every
    // cell is taken out. Each process adds up its own planes in exact sums (their
    // result does not depend on the order of the terms: exact_sums.hpp), so the mean is
    // the same to the bit on any number of processes and threads.
    const auto own = [&](auto&& f) {
      for (int k = own_k0; k < own_k1; ++k)
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i) f(PN[g.at(i, j, k)]);
    };
    // A pressure not finite is left for the step's guard to name (RunGuards::check_gas).
    if (const auto pmean = exact_mean(
            static_cast<double>(g.cell_count()), own, [&](double m) { return share_.max(m); },
            [&](ExactSums& sum) { share_.sum(sum.data(), 1); })) {
#pragma omp parallel for schedule(static) if (threads)
      for (int k = up_k0; k < up_k1; ++k)
        for (int j = 0; j < ny; ++j)
          for (int i = 0; i < nx; ++i) PN[g.at(i, j, k)] -= *pmean;
    }
  }
  if (dims == 2) std::fill(gas_.w.begin(), gas_.w.end(), 0.0);
  g.fill_velocity_ghosts(gas_.u, gas_.v, gas_.w);

  // Continuity residual with the corrected velocity (round-off for an exact solve).
  const double* const vc[3] = {gas_.u.data(), gas_.v.data(), gas_.w.data()};
  auto residual = [&](int i, int j, int k) {
    const std::size_t cell = g.at(i, j, k);
    double r = divergence(vc, i, j, k) + (E1[cell] - E0[cell]) / dt;
    if (mass_source) r -= mass_source(g.position(Staggering::centre, i, j, k), time_ + dt);
    return std::abs(r);
  };
  double res = 0.0;
  if (mass_source) {
    for (int k = own_k0; k < own_k1; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) res = std::max(res, residual(i, j, k));
  } else {
#pragma omp parallel for schedule(static) if (threads) reduction(max : res)
    for (int k = own_k0; k < own_k1; ++k)
      for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) res = std::max(res, residual(i, j, k));
  }
  continuity_residual_ = share_.max(res);
}

void GasSolver::step(double dt, const std::vector<double>& eps_new) {
  // The step computes and gathers the planes of each process's reach: those are kept.
  hold_reach();
  const StaggeredGrid& g = gas_.grid();
  g.fill_velocity_ghosts(gas_.u, gas_.v, gas_.w);
  gas_.fill_pressure_ghosts();
  predictor(dt);
  project(dt, eps_new);
  if (g.window_whole() || eps_new.size() != gas_.eps_g.size()) gas_.eps_g = eps_new;
  else g.copy_window(eps_new, gas_.eps_g);
  g.fill_scalar_ghosts(gas_.eps_g);
  set_drag_gradients(gas_.eps_g);
  gradients_restored_ = false;
  gas_.fill_pressure_ghosts();
  time_ += dt;
  gas_.set_time(time_);
  gas_.refresh();
  whole_ = !divided() || share_.reach_whole(g.n(2));
}

void GasSolver::set_drag_gradients(const std::vector<double>& eps) {
  const StaggeredGrid& g = gas_.grid();
  const std::vector<double>* force[3] = {&force_u, &force_v, &force_w};
  const std::vector<double>* beta[3] = {&drag_u, &drag_v, &drag_w};
  const std::vector<double>* target[3] = {&drag_target_u, &drag_target_v, &drag_target_w};
  const std::vector<double>* vel[3] = {&gas_.u, &gas_.v, &gas_.w};
  // The drag on the gas per unit volume held by face f [N/m^3], as the cells handed it
  // over (half of each neighbouring cell's, over a cell's volume).
  auto drag = [&](int a, std::size_t f) {
    double d = (*force[a])[f];
    if (!beta[a]->empty()) d += (*target[a])[f] - (*beta[a])[f] * (*vel[a])[f];
    return d;
  };
  gas_.for_each_fixed_face_cell([&](int a, int side, int c[3], std::size_t at) {
    // The boundary face b, the cell next to it and the first interior face f1.
    const int n = g.n(a);
    const std::size_t cell = g.at(c[0], c[1], c[2]);
    c[a] = side == 0 ? 0 : n;
    const std::size_t b = g.at(c[0], c[1], c[2]);
    const double eps_b = eps.empty() ? 1.0 : eps[cell];
    // The boundary face's control volume is the half cell inside: twice its share.
    double d = 2.0 * drag(a, b) / eps_b;
    if (n > 1) {
      c[a] = side == 0 ? 1 : n - 1;
      const std::size_t f1 = g.at(c[0], c[1], c[2]);
      const double eps_1 = eps.empty() ? 1.0 : 0.5 * (eps[f1 - g.stride(a)] + eps[f1]);
      d -= drag(a, f1) / eps_1;
    }
    gas_.drag_gradient(2 * a + side)[at] = d;
  });
}

}  // namespace cdm::fluid
