#include "cdm/solver/coupling/implicit_drag.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/run_guards.hpp"

namespace cdm::coupling {

ImplicitDrag::ImplicitDrag(const fluid::StaggeredGrid& grid, const TwoWayExchange& exchange)
    : grid_(grid), exchange_(exchange), deposition_(*exchange.deposition()) {
  k_cell_ = grid.make_array();
  for (int c = 0; c < 3; ++c)
    for (auto* v : {&kv_[c], &diff_[c], &pending_[c]}) *v = grid.make_array();
}

void ImplicitDrag::zero_outside_window() {
  if (grid_.window_moves() == zeroed_at_) return;
  zeroed_at_ = grid_.window_moves();
  grid_.zero_outside_window(k_cell_);
  for (int c = 0; c < 3; ++c)
    for (auto* v : {&kv_[c], &diff_[c], &pending_[c]}) grid_.zero_outside_window(*v);
  // The sums are zero between gas steps.
  for (ExactSums* s : {&k_sums_, &kv_sums_}) grid_.zero_blocks_outside_window(*s);
}

namespace {

/// Calls f(c, k, cell, upper face, top) for every cell of the planes [@p k0, @p k1) along
/// z and component c: the cell's plane, its index (that of its lower face along c), its
/// upper face along c (wrapped on a periodic axis), and whether that upper face is the
/// grid's last face along c on a bounded axis (a face no other cell names as its lower
/// one). Each face takes half of a cell's value.
template <class F>
void for_each_cell_faces(const fluid::StaggeredGrid& g, std::pair<int, int> planes, F&& f) {
  for (int c = 0; c < g.dims(); ++c)
    for (int k = planes.first; k < planes.second; ++k)
      for (int j = 0; j < g.n(1); ++j)
        for (int i = 0; i < g.n(0); ++i) {
          int hi[3] = {i, j, k};
          hi[c] += 1;
          const bool periodic = g.spec().periodic(c);
          if (periodic) hi[c] %= g.n(c);
          const bool top = !periodic && hi[c] == g.n(c);
          f(c, k, g.at(i, j, k), g.at(hi[0], hi[1], hi[2]), top);
        }
}

}  // namespace

std::pair<int, int> ImplicitDrag::counted_planes() const {
  return divided() ? exchange_.planes()->mine(grid_.n(2)) : std::pair{0, grid_.n(2)};
}

void ImplicitDrag::prepare(const ParticleStore& p, fluid::GasSolver& gs, RankSplit* ranks) {
  zero_outside_window();
  const fluid::StaggeredGrid& g = grid_;
  const std::size_t n = p.size(), nc = g.padded_size();
  // Each rank deposits its own particles (all of them before the particles are dealt
  // out) in sums that add up to the same cells on any number of ranks; each particle's
  // weights add up to one, so a sum's terms add up to at most n times the largest.
  RankSplit* const own = ranks && ranks->partitioned() ? ranks : nullptr;
  // The two bounds reduced over the ranks at once.
  std::vector<double> bound{max_local(own, n, [&](std::size_t i) { return std::abs(p.drag_k[i]); }),
                            max_local(own, n, [&](std::size_t i) {
                              return std::abs(p.drag_k[i]) *
                                     std::max({std::abs(p.vx[i]), std::abs(p.vy[i]), std::abs(p.vz[i])});
                            })};
  if (own) own->max(bound);
  const double kmax = k_max_ = bound[0], kvmax = bound[1];
  ExactSums &ks = k_sums_, &kvs = kv_sums_;
  TwoWayExchange::start_sums(ks, nc, kmax, static_cast<double>(n) * kmax);
  TwoWayExchange::start_sums(kvs, 3 * nc, kvmax, static_cast<double>(n) * kvmax);
  const double sk = ks.scale(), skv = kvs.scale();
  for_own_in_order(own, n, [&](std::size_t i) {
    const double k = p.drag_k[i] * sk, kx = p.drag_k[i] * p.vx[i] * skv, ky = p.drag_k[i] * p.vy[i] * skv,
                 kz = p.drag_k[i] * p.vz[i] * skv;
    deposition_.for_each_weight(p.position(i), [&](std::size_t c, double w) {
      ks.add_scaled(c, w * k);
      kvs.add_scaled(c, w * kx); kvs.add_scaled(nc + c, w * ky); kvs.add_scaled(2 * nc + c, w * kz);
    });
  });
  const bool by_planes = exchange_.add_up_cells(p, own, {&ks, 1}, {&kvs, 3});
  // Where the planes are shared the sums, the reaction and the gas are current on the
  // grid's window (this process's reach) only, and its own planes are counted.
  const auto [c0, c1] = g.window_span();
  for (std::size_t c = c0; c < c1; ++c) {
    k_cell_[c] = ks.value(c);
    for (std::size_t a = 0; a < 3; ++a) kv_[a][c] = kvs.value(a * nc + c);
  }
  exchange_.clear_sums(ks, 1, by_planes, own);
  exchange_.clear_sums(kvs, 3, by_planes, own);
  if (pending_any_ && divided()) {
    // The differences kept are their cells' owners' (give_back).
    const fluid::PlaneShare& s = *exchange_.planes();
    for (auto& v : pending_) s.gather(v, g.plane_start(0), g.plane_size(), g.n(2));
    const auto [r0, r1] = s.reach_of(s.rank(), g.n(2));
    pending_span_ = fluid::span_union(pending_span_, {g.plane_start(r0), g.plane_start(r1)});
  }
  const auto [k0, k1] = counted_planes();
  double gathered[3] = {};
  for (int c = 0; c < 3; ++c) {
    const std::vector<double>& r = exchange_.reaction(c);
    for (std::size_t x = g.plane_start(k0); x < g.plane_start(k1); ++x) gathered[c] += r[x];
    for (std::size_t x = c0; x < c1; ++x) diff_[c][x] = r[x] + pending_[c][x];
  }
  gathered_ = {gathered[0], gathered[1], gathered[2]};
  std::vector<double>* beta[3] = {&gs.drag_u, &gs.drag_v, &gs.drag_w};
  std::vector<double>* target[3] = {&gs.drag_target_u, &gs.drag_target_v, &gs.drag_target_w};
  for (int c = 0; c < 3; ++c)
    for (auto* v : {beta[c], target[c]}) {
      if (v->size() != nc) *v = g.make_array();
      else g.fill_window(*v, 0.0);
    }
  const double inv_v = 1.0 / g.cell_volume();
  const auto planes = g.window_planes(fluid::Staggering::centre);
  for_each_cell_faces(g, planes, [&](int c, int, std::size_t cell, std::size_t hi, bool) {
    const double b = 0.5 * k_cell_[cell] * inv_v, t = 0.5 * kv_[c][cell] * inv_v;
    (*beta[c])[cell] += b;
    (*beta[c])[hi] += b;
    (*target[c])[cell] += t;
    (*target[c])[hi] += t;
  });
  // A periodic axis's last face, n, is its face 0 (the pressure operator reads it there).
  for (int c = 0; c < g.dims(); ++c) {
    if (!g.spec().periodic(c)) continue;
    const int n = g.n(c);
    for (int k = planes.first; k < planes.second; ++k)
      for (int j = 0; j < g.n(1); ++j)
        for (int i = 0; i < g.n(0); ++i) {
          const int x[3] = {i, j, k};
          if (x[c] != 0) continue;
          int e[3] = {i, j, k};
          e[c] = n;
          const std::size_t from = g.at(i, j, k), to = g.at(e[0], e[1], e[2]);
          (*beta[c])[to] = (*beta[c])[from];
          (*target[c])[to] = (*target[c])[from];
        }
  }
}

CouplingBalance ImplicitDrag::give_back(ParticleStore& p, const fluid::GasField& gas, const fluid::GasSolver& gs,
                                        double dtg, RankSplit* ranks) {
  const fluid::StaggeredGrid& g = grid_;
  const std::vector<double>* u1[3] = {&gas.u, &gas.v, &gas.w};
  // The cells of the window, each process's own planes counted in the balance (added up
  // over the processes below).
  const auto planes = g.window_planes(fluid::Staggering::centre);
  const auto [k0, k1] = counted_planes();
  double cells[3] = {}, faces[3] = {}, kept = 0.0;
  // The gas's momentum per cell, G_c = −Δt (K_c ū_c − Σ w K v); the difference −G_c − J_c
  // to the particles (diff_ holds −J_c and what was pending): diff_c − G_c. What is kept
  // for the next step is zero beyond the cells set here.
  for (auto& v : pending_)
    std::fill(v.begin() + static_cast<std::ptrdiff_t>(pending_span_.first),
              v.begin() + static_cast<std::ptrdiff_t>(std::max(pending_span_.first, pending_span_.second)), 0.0);
  pending_span_ = g.window_span();
  for_each_cell_faces(g, planes, [&](int c, int k, std::size_t cell, std::size_t hi, bool) {
    const double u = 0.5 * (*u1[c])[cell] + 0.5 * (*u1[c])[hi];
    const double gc = -dtg * (k_cell_[cell] * u - kv_[c][cell]);
    const bool counted = k >= k0 && k < k1;
    if (counted) cells[c] += gc;
    diff_[c][cell] -= gc;
    if (k_cell_[cell] > 0.0) {
      diff_[c][cell] /= k_cell_[cell];  // per unit K, for the particles' shares
    } else {
      pending_[c][cell] = diff_[c][cell];
      diff_[c][cell] = 0.0;
      if (counted && pending_[c][cell] != 0.0) kept += 1.0;
    }
  });
  // The gas's momentum on its faces (the fixed ones' included: their share goes to the
  // wall or inlet), −Δt V Σ_f (β_f u_f − β V_s,f), summed on its own as a check.
  const std::vector<double>* beta[3] = {&gs.drag_u, &gs.drag_v, &gs.drag_w};
  const std::vector<double>* target[3] = {&gs.drag_target_u, &gs.drag_target_v, &gs.drag_target_w};
  const double vdt = g.cell_volume() * dtg;
  for_each_cell_faces(g, {k0, k1}, [&](int c, int, std::size_t cell, std::size_t hi, bool top) {
    faces[c] -= vdt * ((*beta[c])[cell] * (*u1[c])[cell] - (*target[c])[cell]);
    if (top) faces[c] -= vdt * ((*beta[c])[hi] * (*u1[c])[hi] - (*target[c])[hi]);
  });
  // The largest difference per unit K, on the counted planes (those beyond are zero).
  double dmax = 0.0;
  for (const auto& v : diff_)
    for (std::size_t x = g.plane_start(k0); x < g.plane_start(k1); ++x) dmax = std::max(dmax, std::abs(v[x]));
  if (divided()) {
    double sums[7] = {cells[0], cells[1], cells[2], faces[0], faces[1], faces[2], kept};
    exchange_.planes()->sum(sums, 7);
    std::copy_n(sums, 3, cells);
    std::copy_n(sums + 3, 3, faces);
    kept = sums[6];
    dmax = exchange_.planes()->max(dmax);
  }
  pending_any_ = kept > 0.0;
  // The exchange recorded the gathered reaction −J as the gas's: replaced by the sums above.
  CouplingBalance b;
  b.gas_cells = Vec3{cells[0], cells[1], cells[2]} - gathered_;
  b.gas_faces = Vec3{faces[0], faces[1], faces[2]} - gathered_;
  // Each rank kicks its own particles; what they receive is summed as the deposits are,
  // each kick at most the largest K times the largest difference per unit K.
  const std::size_t n = p.size();
  RankSplit* const own = ranks && ranks->partitioned() ? ranks : nullptr;
  const double jmax = k_max_ * dmax;
  if (!std::isfinite(jmax))
    throw SimulationError("the implicit gas drag's kick on the particles is not finite (the largest drag coefficient " +
                          std::to_string(k_max_) + " kg/s, the largest difference per unit of it " +
                          std::to_string(dmax) + " m): a cell's drag coefficient too small to divide by");
  ExactSums sum;
  sum.reset(3, jmax, static_cast<double>(n) * jmax);
  for_own_in_order(own, n, [&](std::size_t i) {
    Vec3 d;
    deposition_.for_each_weight(p.position(i), [&](std::size_t c, double w) {
      d.x += w * diff_[0][c]; d.y += w * diff_[1][c]; d.z += w * diff_[2][c];
    });
    const Vec3 j = p.drag_k[i] * d;
    p.vx[i] += p.inv_mass[i] * j.x; p.vy[i] += p.inv_mass[i] * j.y; p.vz[i] += p.inv_mass[i] * j.z;
    sum.add(0, j.x); sum.add(1, j.y); sum.add(2, j.z);
  });
  if (own) own->add_up(sum);
  b.particles += Vec3{sum.value(0), sum.value(1), sum.value(2)};
  return b;
}

void ImplicitDrag::save_state(OutArchive& a) const {
  // Among processes each plane's differences are its owner's.
  const OutArchive::Planes planes{grid_.plane_start(0), grid_.plane_size(), grid_.n(2)};
  for (const auto& v : pending_) a.put_planes(v, planes);
}

void ImplicitDrag::load_state(InArchive& a) {
  pending_any_ = false;
  for (auto& v : pending_) {
    a.get(v, grid_.padded_size());
    if (v.size() != grid_.padded_size()) throw ArchiveError("a gas array has the wrong length");
    for (double d : v) pending_any_ |= d != 0.0;
  }
  pending_span_ = {0, grid_.padded_size()};
}

}  // namespace cdm::coupling
