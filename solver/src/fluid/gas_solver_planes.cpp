#include "cdm/solver/fluid/gas_solver.hpp"

// How a gas step divided among MPI processes by planes shares them: the planes each
// process reads (its reach) and keeps current, and what it receives when they change.

#include <algorithm>
#include <tuple>

#include "cdm/solver/mpi_session.hpp"
#include "cdm/solver/slot_pages.hpp"

namespace cdm::fluid {

void GasSolver::gather(std::vector<double>& a, Staggering s) const {
  const StaggeredGrid& g = gas_.grid();
  share_.gather(a, g.plane_start(0), g.plane_size(), g.samples(s, 2));
}

namespace {

/// The planes of cells [@p lo, @p hi] with a process's own planes @p own and two either
/// side of them (the step's stencils, and the ghosts and interpolators built from them);
/// along a periodic z the planes wrap, so a reach that reaches an end (whose ghosts read
/// the planes past the other) is all of them. Not clamped to the grid.
std::pair<int, int> with_own_planes(const StaggeredGrid& g, std::pair<int, int> own, int lo, int hi) {
  const auto [k0, k1] = own;
  if (k0 < k1) {
    lo = lo <= hi ? std::min(lo, k0 - 2) : k0 - 2;
    hi = std::max(hi, k1 + 1);
  }
  if (lo <= hi && g.wraps(lo, hi + 1)) lo = 0, hi = g.n(2) - 1;
  return {lo, hi};
}

}  // namespace

std::pair<int, int> GasSolver::first_planes(GasDivision division, const GridSpec& grid) {
  const StaggeredGrid g(grid);
  const int nz = g.n(2);
  const WorldPlace w = mpi_world();
  if (g.two_d() || !PlaneShare::divides(division, g, w.size)) return {0, nz};
  const auto own = PlaneShare::planes_of(nz, w.rank, w.size);
  // A process that owns no plane reads the planes of its particles only: until it knows
  // them, every plane.
  if (own.first == own.second) return {0, nz};
  const auto [lo, hi] = with_own_planes(g, own, 1, 0);
  return {std::max(lo, 0), std::min(hi, nz - 1) + 1};
}

void GasSolver::read_planes(int lo, int hi) {
  if (!divided()) return;
  const StaggeredGrid& g = gas_.grid();
  const int nz = g.n(2);
  std::tie(lo, hi) = with_own_planes(g, share_.mine(nz), lo, hi);
  // A pressure solve done whole by each process (the direct factorisation) reads the gas
  // fraction and the face coefficients of every cell: all.
  if (!pressure_->solves_own_planes()) lo = 0, hi = nz - 1;
  lo = std::max(lo, 0);
  hi = std::min(hi, nz - 1);
  const bool grew = share_.set_reach(lo, hi);
  if (whole_) return;
  hold_reach();
  if (grew) receive_gas();
}

void GasSolver::hold_reach() {
  if (!divided()) return;
  const StaggeredGrid& g = gas_.grid();
  const auto [lo, hi] = share_.held(g.n(2));
  gas_.hold_planes(lo, hi);
  if (g.window_moves() == zeroed_at_) return;
  // Nothing reads the planes beyond the window: they cost no memory until it moves there.
  zeroed_at_ = g.window_moves();
  gas_.zero_outside_window();
  for (auto* a : {&force_u, &force_v, &force_w, &drag_u, &drag_v, &drag_w, &drag_target_u, &drag_target_v,
                  &drag_target_w, &us_, &vs_, &ws_, &phi_, &d_[0], &d_[1], &d_[2]})
    g.zero_outside_window(*a);
  // φ and the right-hand side by cells: the window's planes are those the solve reads and
  // sets (its own) and those gathered (the reach).
  const std::size_t plane = static_cast<std::size_t>(g.n(0)) * static_cast<std::size_t>(g.n(1));
  const auto [k0, k1] = g.window();
  for (auto* a : {&phi_cells_, &b_cells_})
    zero_slots(*a, {{0, plane * static_cast<std::size_t>(k0)}, {plane * static_cast<std::size_t>(k1), a->size()}});
}

void GasSolver::receive_gas() {
  // The velocity, pressure, gas fraction and drag of each plane are its owner's (the
  // particles' deposit may leave each process the gas fraction and the drag on its reach
  // only: TwoWayExchange::share_planes, ImplicitDrag).
  const StaggeredGrid& g = gas_.grid();
  std::vector<double>* const vel[3] = {&gas_.u, &gas_.v, &gas_.w};
  std::vector<double>* const force[3] = {&force_u, &force_v, &force_w};
  // The drag gradients read the drag force, and the implicit drag's β and β V_s.
  std::vector<double>* const beta[3] = {&drag_u, &drag_v, &drag_w};
  std::vector<double>* const target[3] = {&drag_target_u, &drag_target_v, &drag_target_w};
  for (int c = 0; c < g.dims(); ++c) {
    const auto s = static_cast<Staggering>(c);
    gather(*vel[c], s);
    gather(*force[c], s);
    if (beta[c]->empty()) continue;
    gather(*beta[c], s);
    gather(*target[c], s);
  }
  for (auto* a : {&gas_.p, &gas_.eps_g}) gather(*a, Staggering::centre);
  hold_reach();
  g.fill_scalar_ghosts(gas_.eps_g);
  // As the step left them, now on the planes received too.
  g.fill_velocity_ghosts(gas_.u, gas_.v, gas_.w);
  if (!gradients_restored_) set_drag_gradients(gas_.eps_g);
  gas_.fill_pressure_ghosts();
  gas_.refresh();
}

}  // namespace cdm::fluid
