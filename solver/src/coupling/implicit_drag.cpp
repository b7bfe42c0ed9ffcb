#include "cdm/solver/coupling/implicit_drag.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "cdm/solver/exact_sums.hpp"
#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/run_guards.hpp"

namespace cdm::coupling {

ImplicitDrag::ImplicitDrag(const fluid::StaggeredGrid& grid, const Deposition& deposition)
    : grid_(grid), deposition_(deposition) {
  k_cell_.assign(grid.padded_size(), 0.0);
  for (int c = 0; c < 3; ++c) kv_[c] = diff_[c] = pending_[c] = k_cell_;
}

namespace {

/// Calls f(c, cell, upper face, top) for every cell and component c: the cell's index
/// (that of its lower face along c), its upper face along c (wrapped on a periodic axis),
/// and whether that upper face is the grid's last face along c on a bounded axis (a
/// face no other cell names as its lower one). Each face takes half of a cell's value.
template <class F>
void for_each_cell_faces(const fluid::StaggeredGrid& g, F&& f) {
  for (int c = 0; c < g.dims(); ++c)
    for (int k = 0; k < g.n(2); ++k)
      for (int j = 0; j < g.n(1); ++j)
        for (int i = 0; i < g.n(0); ++i) {
          int hi[3] = {i, j, k};
          hi[c] += 1;
          const bool periodic = g.spec().periodic(c);
          if (periodic) hi[c] %= g.n(c);
          const bool top = !periodic && hi[c] == g.n(c);
          f(c, g.at(i, j, k), g.at(hi[0], hi[1], hi[2]), top);
        }
}

}  // namespace

void ImplicitDrag::prepare(const ParticleStore& p, const TwoWayExchange& exchange, fluid::GasSolver& gs,
                           RankSplit* ranks) {
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
  ExactSums ks, kvs;
  ks.reset(nc, kmax, static_cast<double>(n) * kmax);
  kvs.reset(3 * nc, kvmax, static_cast<double>(n) * kvmax);
  const double sk = ks.scale(), skv = kvs.scale();
  for_own_in_order(own, n, [&](std::size_t i) {
    const double k = p.drag_k[i] * sk, kx = p.drag_k[i] * p.vx[i] * skv, ky = p.drag_k[i] * p.vy[i] * skv,
                 kz = p.drag_k[i] * p.vz[i] * skv;
    deposition_.for_each_weight(p.position(i), [&](std::size_t c, double w) {
      ks.add_scaled(c, w * k);
      kvs.add_scaled(c, w * kx); kvs.add_scaled(nc + c, w * ky); kvs.add_scaled(2 * nc + c, w * kz);
    });
  });
  if (own) own->add_up(ks, kvs);
  for (std::size_t c = 0; c < nc; ++c) {
    k_cell_[c] = ks.value(c);
    for (std::size_t a = 0; a < 3; ++a) kv_[a][c] = kvs.value(a * nc + c);
  }
  double* gathered[3] = {&gathered_.x, &gathered_.y, &gathered_.z};
  for (int c = 0; c < 3; ++c) {
    diff_[c] = exchange.reaction(c);
    *gathered[c] = 0.0;
    for (std::size_t x = 0; x < diff_[c].size(); ++x) {
      *gathered[c] += diff_[c][x];
      diff_[c][x] += pending_[c][x];
    }
  }
  std::vector<double>* beta[3] = {&gs.drag_u, &gs.drag_v, &gs.drag_w};
  std::vector<double>* target[3] = {&gs.drag_target_u, &gs.drag_target_v, &gs.drag_target_w};
  for (int c = 0; c < 3; ++c) {
    beta[c]->assign(g.padded_size(), 0.0);
    target[c]->assign(g.padded_size(), 0.0);
  }
  const double inv_v = 1.0 / g.cell_volume();
  for_each_cell_faces(g, [&](int c, std::size_t cell, std::size_t hi, bool) {
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
    for (int k = 0; k < g.n(2); ++k)
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
  CouplingBalance b;
  double* cells[3] = {&b.gas_cells.x, &b.gas_cells.y, &b.gas_cells.z};
  // The gas's momentum per cell, G_c = −Δt (K_c ū_c − Σ w K v); the difference −G_c − J_c
  // to the particles (diff_ holds −J_c and what was pending): diff_c − G_c.
  for (auto& v : pending_) std::fill(v.begin(), v.end(), 0.0);
  for_each_cell_faces(g, [&](int c, std::size_t cell, std::size_t hi, bool) {
    const double u = 0.5 * (*u1[c])[cell] + 0.5 * (*u1[c])[hi];
    const double gc = -dtg * (k_cell_[cell] * u - kv_[c][cell]);
    *cells[c] += gc;
    diff_[c][cell] -= gc;
    if (k_cell_[cell] > 0.0) {
      diff_[c][cell] /= k_cell_[cell];  // per unit K, for the particles' shares
    } else {
      pending_[c][cell] = diff_[c][cell];
      diff_[c][cell] = 0.0;
    }
  });
  // The gas's momentum on its faces (the fixed ones' included: their share goes to the
  // wall or inlet), −Δt V Σ_f (β_f u_f − β V_s,f), summed on its own as a check.
  const std::vector<double>* beta[3] = {&gs.drag_u, &gs.drag_v, &gs.drag_w};
  const std::vector<double>* target[3] = {&gs.drag_target_u, &gs.drag_target_v, &gs.drag_target_w};
  double* faces[3] = {&b.gas_faces.x, &b.gas_faces.y, &b.gas_faces.z};
  const double vdt = g.cell_volume() * dtg;
  for_each_cell_faces(g, [&](int c, std::size_t cell, std::size_t hi, bool top) {
    *faces[c] -= vdt * ((*beta[c])[cell] * (*u1[c])[cell] - (*target[c])[cell]);
    if (top) *faces[c] -= vdt * ((*beta[c])[hi] * (*u1[c])[hi] - (*target[c])[hi]);
  });
  // The exchange recorded the gathered reaction −J as the gas's: replace it by the above.
  b.gas_cells -= gathered_;
  b.gas_faces -= gathered_;
  // Each rank kicks its own particles; what they receive is summed as the deposits are,
  // each kick at most the largest K times the largest difference per unit K.
  const std::size_t n = p.size();
  RankSplit* const own = ranks && ranks->partitioned() ? ranks : nullptr;
  double dmax = 0.0;
  for (const auto& v : diff_)
    for (double d : v) dmax = std::max(dmax, std::abs(d));
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

Vec3 ImplicitDrag::pending() const {
  Vec3 s;
  for (std::size_t x = 0; x < pending_[0].size(); ++x) s += Vec3{pending_[0][x], pending_[1][x], pending_[2][x]};
  return s;
}

void ImplicitDrag::save_state(OutArchive& a) const {
  for (const auto& v : pending_) a.put(v);
}

void ImplicitDrag::load_state(InArchive& a) {
  for (auto& v : pending_) {
    a.get(v, grid_.padded_size());
    if (v.size() != grid_.padded_size()) throw ArchiveError("a gas array has the wrong length");
  }
}

}  // namespace cdm::coupling
