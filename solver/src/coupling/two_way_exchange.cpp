#include "cdm/solver/coupling/two_way_exchange.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/run_guards.hpp"
#include "cdm/solver/slot_pages.hpp"

namespace cdm::coupling {

TwoWayExchange::TwoWayExchange(const fluid::StaggeredGrid& grid, bool two_way, Kernel kernel, double width)
    : grid_(grid) {
  if (!two_way) return;
  deposition_ = std::make_unique<Deposition>(grid, kernel, width);
  for (auto* v : {&imp_x_, &imp_y_, &imp_z_}) *v = grid.make_array();
}

void TwoWayExchange::zero_outside_window() {
  if (grid_.window_moves() == zeroed_at_) return;
  zeroed_at_ = grid_.window_moves();
  for (auto* v : {&imp_x_, &imp_y_, &imp_z_}) grid_.zero_outside_window(*v);
  // The sums are zero between steps (between gas steps for the deposits' blocks of cells).
  for (ExactSums* s : {&impulse_sums_, &volume_sums_}) grid_.zero_blocks_outside_window(*s);
  const std::size_t nc = grid_.padded_size();
  if (step_sums_.size() >= 3 * nc) grid_.zero_outside_window(step_sums_.data(), 24);
  grid_.zero_outside_window(reached_);
}

std::pair<std::size_t, std::size_t> TwoWayExchange::held_span() const {
  return grid_.window_span();
}

std::pair<std::size_t, std::size_t> TwoWayExchange::deposited_span(const RankSplit* own) const {
  // Without own particles every process deposits every particle: each keeps the cells of
  // its window, whose sums are then whole (add_up_cells adds nothing up).
  return own ? std::pair<std::size_t, std::size_t>{0, grid_.padded_size()} : held_span();
}

void TwoWayExchange::touch(std::pair<std::size_t, std::size_t> span) {
  if (span.first >= span.second) return;
  touched_ = fluid::span_union(touched_, span);
  if (!held_whole()) reaction_whole_ = false;
}

void TwoWayExchange::deposit_impulse(Vec3 j, Vec3 at) {
  particle_impulse_ += j;
  const auto [lo, hi] = held_span();
  deposition_->for_each_weight(at, [&](std::size_t c, double w) {
    if (c < lo || c >= hi) return;
    imp_x_[c] -= w * j.x; imp_y_[c] -= w * j.y; imp_z_[c] -= w * j.z;
  });
  touch({lo, hi});
}

void TwoWayExchange::deposit_sums(const ParticleStore& p, RankSplit* own, ExactSums* imp, ExactSums& vol) const {
  const double vc = grid_.cell_volume();
  const std::size_t nc = grid_.padded_size();
  // Each thread deposits a contiguous range of the particles into sums of its own (the
  // first thread into imp and vol), added up afterwards: the same on any number of threads.
  std::size_t threads = 1;
#ifdef _OPENMP
  threads = static_cast<std::size_t>(omp_get_max_threads());
#endif
  // The other threads' sums are zero between deposits: each adds up and clears the cells
  // its particles reached (spans), not the grid.
  partial_.resize(2 * (threads - 1));
  for (std::size_t t = 1; t < threads; ++t) {
    if (imp) partial_[2 * t - 2].reset_like(*imp);
    partial_[2 * t - 1].reset_like(vol);
  }
  std::vector<std::pair<std::size_t, std::size_t>> spans(threads, {nc, 0});
  const double si = imp ? imp->scale() : 0.0, sv = vol.scale();
  const auto [lo, hi] = deposited_span(own);
  auto range = [&](std::size_t i0, std::size_t i1) {
    const std::size_t t = thread_id().first;
    ExactSums* const ti = t == 0 ? imp : imp ? &partial_[2 * t - 2] : nullptr;
    ExactSums& tv = t == 0 ? vol : partial_[2 * t - 1];
    std::size_t &c0 = spans[t].first, &c1 = spans[t].second;  // not bindings: clang cannot capture them
    for (std::size_t i = i0; i < i1; ++i) {
      const double v = p.volume(i) / vc * sv;
      if (!ti) {
        deposition_->for_each_weight(p.position(i), [&](std::size_t c, double w) {
          if (c < lo || c >= hi) return;
          tv.add_scaled(c, w * v);
          c0 = std::min(c0, c), c1 = std::max(c1, c + 1);
        });
        continue;
      }
      const double jx = p.jx[i], jy = p.jy[i], jz = p.jz[i];
      const double rx = -jx * si, ry = -jy * si, rz = -jz * si;
      deposition_->for_each_weight(p.position(i), [&](std::size_t c, double w) {
        if (c < lo || c >= hi) return;
        ti->add_scaled(c, w * rx); ti->add_scaled(nc + c, w * ry); ti->add_scaled(2 * nc + c, w * rz);
        tv.add_scaled(c, w * v);
        c0 = std::min(c0, c), c1 = std::max(c1, c + 1);
      });
      ti->add(3 * nc, jx); ti->add(3 * nc + 1, jy); ti->add(3 * nc + 2, jz);
    }
    return 0.0;
  };
  if (own) {
    for (const auto& run : own->own_runs(p.size())) {
      const std::size_t i0 = run.first, i1 = run.second;  // not bindings: clang cannot capture them
      parallel_max_ranges(i1 - i0, [&](std::size_t a, std::size_t b) { return range(i0 + a, i0 + b); });
    }
  } else {
    parallel_max_ranges(p.size(), range);
  }
  for (std::size_t t = 1; t < threads; ++t) {
    const std::size_t c0 = spans[t].first, c1 = spans[t].second;
    auto take = [&](ExactSums& to, ExactSums& from, std::size_t blocks) {
      for (std::size_t b = 0; b < blocks && c0 < c1; ++b) {
        to.add(from, b * nc + c0, b * nc + c1);
        from.clear(b * nc + c0, b * nc + c1);
      }
      to.add(from, blocks * nc, from.size());  // the totals
      from.clear(blocks * nc, from.size());
    };
    if (imp) take(*imp, partial_[2 * t - 2], 3);
    take(vol, partial_[2 * t - 1], 1);
  }
}

int TwoWayExchange::plane_of(std::size_t c) const {
  return static_cast<int>((c - grid_.plane_start(0)) / grid_.plane_size());
}

std::pair<int, int> TwoWayExchange::planes_reached(const ParticleStore& p, RankSplit& own) const {
  const int nz = grid_.n(2);
  const auto [lo, hi, finite] = own_extent(own, p.size(), p.z.data());
  if (!finite) return {-1, nz};
  if (lo > hi) return {1, 0};
  // The fractional cell-centre coordinate (deposition.cpp), a stencil's cells either side
  // of it within its width (3σ for the gaussian), a cell to spare; a cell beyond a wall
  // is folded back onto the one it mirrors.
  const double w = deposition_->kernel() == Kernel::gaussian ? 3.0 * deposition_->width() * grid_.inv_h(2) : 0.0;
  auto at = [&](double z) { return std::clamp((z - grid_.lo(2)) * grid_.inv_h(2) - 0.5, -2.0 * nz, 3.0 * nz); };
  int k0 = static_cast<int>(std::floor(at(lo) - w)) - 1, k1 = static_cast<int>(std::floor(at(hi) + w)) + 2;
  // Along a periodic z a stencil past an end wraps to the planes past the other: all.
  if (grid_.spec().periodic(2) && (k0 < 0 || k1 > nz - 1)) return {0, nz - 1};
  if (k0 < 0) k1 = std::max(k1, -1 - k0);
  if (k1 > nz - 1) k0 = std::min(k0, 2 * nz - 1 - k1);
  return {std::max(k0, 0), std::min(k1, nz - 1)};
}

bool TwoWayExchange::add_up_cells(const ParticleStore& p, RankSplit* own, CellSums a, CellSums b) const {
  if (!own) return false;
  const int nz = grid_.n(2);
  const std::size_t nc = grid_.padded_size();
  if (planes_ && !planes_->reach_whole(nz)) {
    // The totals, and whether some process's particles reached beyond its planes (then
    // every cell is added up: the same sums either way), in one reduction.
    const auto [k0, k1] = planes_reached(p, *own);
    std::vector<std::int64_t> rest;
    for (const CellSums& s : {a, b})
      if (s.sums) rest.insert(rest.end(), s.sums->data() + s.blocks * nc, s.sums->data() + s.sums->size());
    rest.push_back(planes_->within_reach(k0, k1, nz) ? 0 : 1);
    own->add_up(rest);
    if (rest.back() == 0) {
      std::vector<std::int64_t*> cells;
      auto total = rest.begin();
      for (const CellSums& s : {a, b}) {
        if (!s.sums) continue;
        std::int64_t* const d = s.sums->data();
        const auto totals = static_cast<std::ptrdiff_t>(s.sums->size() - s.blocks * nc);
        std::copy(total, total + totals, d + s.blocks * nc);
        total += totals;
        for (std::size_t k = 0; k < s.blocks; ++k) cells.push_back(d + k * nc);
      }
      planes_->add_up(cells, grid_.plane_start(0), grid_.plane_size(), nz);
      return true;
    }
  }
  if (b.sums) own->add_up(*a.sums, *b.sums);
  else own->add_up(*a.sums);
  return false;
}

void TwoWayExchange::deposit_void_fraction(const ParticleStore& p, std::vector<double>& eps, double time,
                                           RankSplit* ranks) {
  zero_outside_window();
  RankSplit* const own = ranks && ranks->partitioned() ? ranks : nullptr;
  ExactSums& sums = volume_sums_;
  start_volume_sums(p, own, sums);
  deposit_sums(p, own, nullptr, sums);
  const bool by_planes = add_up_cells(p, own, {&sums, 1});
  finish_void_fraction(sums, eps, time);
  clear_sums(sums, 1, by_planes, own);
}

void TwoWayExchange::start_sums(ExactSums& s, std::size_t n, double bound, double sum_bound) {
  if (s.size() == n) s.set_bounds(bound, sum_bound);
  else s.reset(n, bound, sum_bound);
}

void TwoWayExchange::clear_sums(ExactSums& s, std::size_t blocks, bool by_planes, const RankSplit* own) const {
  // Added up by planes, this process's sums are nonzero on its reach only: its own
  // particles deposited within it (add_up_cells) and the totals it received are of its
  // planes. Else on the cells deposited to.
  const std::size_t nc = grid_.padded_size();
  std::pair<std::size_t, std::size_t> cells = deposited_span(own);
  if (by_planes) {
    const auto [k0, k1] = planes_->reach_of(planes_->rank(), grid_.n(2));
    cells = {grid_.plane_start(k0), grid_.plane_start(k1)};
  }
  for (std::size_t b = 0; b < blocks; ++b) s.clear(b * nc + cells.first, b * nc + cells.second);
  s.clear(blocks * nc, s.size());
}

void TwoWayExchange::start_volume_sums(const ParticleStore& p, RankSplit* own, ExactSums& vol) const {
  const double vc = grid_.cell_volume();
  const std::size_t n = p.size();
  const double vmax = max_own(own, n, [&](std::size_t i) { return p.volume(i) / vc; });
  start_sums(vol, grid_.padded_size(), vmax, static_cast<double>(n) * vmax);
}

double TwoWayExchange::largest_impulse(const ParticleStore& p, RankSplit* own, double time) {
  const double jmax = max_own(own, p.size(), [&](std::size_t i) {
    return std::max({std::abs(p.jx[i]), std::abs(p.jy[i]), std::abs(p.jz[i])});
  });
  if (!std::isfinite(jmax))
    throw SimulationError("a particle's drag impulse is not finite at t = " + std::to_string(time) + " s");
  return jmax;
}

void TwoWayExchange::deposit_impulses_and_void_fraction(ParticleStore& p, std::vector<double>& eps, double time,
                                                        RankSplit* ranks) {
  zero_outside_window();
  const std::size_t n = p.size(), nc = grid_.padded_size();
  // Each rank deposits its own particles (all of them before the particles are dealt
  // out); the partial sums then add up to the same cells on any number of ranks.
  RankSplit* const own = ranks && ranks->partitioned() ? ranks : nullptr;
  const double jmax = largest_impulse(p, own, time);
  ExactSums& imp = impulse_sums_;
  ExactSums& vol = volume_sums_;
  // The reaction per cell along x, y, z, then the particles' total: each particle's
  // weights add up to one, so a sum's terms add up to at most n jmax.
  start_sums(imp, 3 * nc + 3, jmax, static_cast<double>(n) * jmax);
  start_volume_sums(p, own, vol);
  deposit_sums(p, own, &imp, vol);
  const bool by_planes = add_up_cells(p, own, {&imp, 3}, {&vol, 1});
  if (by_planes) reaction_whole_ = false;
  for_own(own, n, [&](std::size_t i) { p.jx[i] = p.jy[i] = p.jz[i] = 0.0; });
  const auto [c0, c1] = held_span();
  for (std::size_t c = c0; c < c1; ++c) {
    imp_x_[c] += imp.value(c); imp_y_[c] += imp.value(nc + c); imp_z_[c] += imp.value(2 * nc + c);
  }
  touch({c0, c1});
  particle_impulse_ += Vec3{imp.value(3 * nc), imp.value(3 * nc + 1), imp.value(3 * nc + 2)};
  finish_void_fraction(vol, eps, time);
  clear_sums(imp, 3, by_planes, own);
  clear_sums(vol, 1, by_planes, own);
}

void TwoWayExchange::finish_void_fraction(const ExactSums& vol, std::vector<double>& eps, double time) const {
  resize_zeroed(eps, vol.size());
  const auto [c0, c1] = held_span();
  for (std::size_t c = c0; c < c1; ++c) eps[c] = 1.0 - vol.value(c);
  // Beyond the window nothing reads it (those planes may have been written before the
  // window narrowed).
  grid_.zero_outside_window(eps);
  const fluid::StaggeredGrid& g = grid_;
  // Among processes sharing the gas's planes each looks at its own, and the smallest
  // (the first in cell order of equal ones) is taken over them.
  const auto [k0, k1] = planes_ ? planes_->mine(g.n(2)) : std::pair{0, g.n(2)};
  double worst = 1.0;
  int at = 0;
  for (int k = k0; k < k1; ++k)
    for (int j = 0; j < g.n(1); ++j)
      for (int i = 0; i < g.n(0); ++i)
        if (const double e = eps[g.at(i, j, k)]; e < worst) {
          worst = e;
          at = i + g.n(0) * (j + g.n(1) * k);
        }
  if (planes_) std::tie(worst, at) = planes_->min_at(worst, at);
  const int wc[3] = {at % g.n(0), at / g.n(0) % g.n(1), at / (g.n(0) * g.n(1))};
  // Random close packing leaves ε_g ≈ 0.36; a cell below 0.2 means the kernel is too
  // narrow for the cells (particles larger than cells) or the particles overlap.
  if (worst < 0.2) {
    std::ostringstream os;
    os << "the gas volume fraction fell to " << worst << " in cell (" << wc[0] << ", " << wc[1] << ", " << wc[2]
       << ") at t = " << time << " s. Likely cause: cells too small for the particles (a cell should hold several "
       << "particle volumes; coarsen gas.cells or widen the deposition with coupling.kernel = \"gaussian\" and a "
       << "larger coupling.kernel_width)";
    throw SimulationError(os.str());
  }
  g.fill_scalar_ghosts(eps);
}

void TwoWayExchange::deposit_impulses(ParticleStore& p, double time, RankSplit* ranks) {
  zero_outside_window();
  const std::size_t n = p.size(), nc = grid_.padded_size();
  RankSplit* own = ranks && ranks->partitioned() ? ranks : nullptr;
  // Among ranks the cells' sums are added up over the run of cells the step reaches; where
  // that run (3 sums a cell) outgrows the particles' positions and impulses (6 values a
  // particle), those are gathered instead and every rank deposits every particle: the
  // same sums either way. Chosen from the last step's run, alike on every rank. Where the
  // sums are added up by planes (share_planes), each process's reach is what travels.
  const bool by_planes = planes_ && !planes_->reach_whole(grid_.n(2));
  if (own && !by_planes && reached_span_ > 2 * n) {
    own->gather({&p.x, &p.y, &p.z, &p.jx, &p.jy, &p.jz});
    own = nullptr;
  }
  const double jmax = largest_impulse(p, own, time);
  // Cell c's reaction along a is sum 3 c + a, so the cells a step reaches on any rank,
  // [lo, hi], are one run of sums, which alone is added up over the ranks; the particles'
  // total follows the cells. The sums are zero between steps: only the cells reached are
  // read and cleared (on one process those listed as the particles reach them).
  ExactSums& s = step_sums_;
  const double count = static_cast<double>(n);
  start_sums(s, 3 * nc + 3, jmax, count * jmax);
  const double sc = s.scale();
  std::size_t lo = nc, hi = 0;
  reached_.resize(nc, 0);
  for_own_in_order(own, n, [&](std::size_t i) {
    const double jx = p.jx[i], jy = p.jy[i], jz = p.jz[i];
    if (jx == 0.0 && jy == 0.0 && jz == 0.0) return;
    const double rx = -jx * sc, ry = -jy * sc, rz = -jz * sc;
    deposition_->for_each_weight(p.position(i), [&](std::size_t c, double w) {
      s.add_scaled(3 * c, w * rx); s.add_scaled(3 * c + 1, w * ry); s.add_scaled(3 * c + 2, w * rz);
      if (reached_[c]) return;
      reached_[c] = 1;
      reached_cells_.push_back(static_cast<std::uint32_t>(c));
      lo = std::min(lo, c);
      hi = std::max(hi, c);
    });
    s.add(3 * nc, jx); s.add(3 * nc + 1, jy); s.add(3 * nc + 2, jz);
    p.jx[i] = p.jy[i] = p.jz[i] = 0.0;
  });
  // A cell whose sums are zero is left as it is, so the same cells change whether the
  // cells reached are read from this process's list or from the run over the ranks. A
  // cell beyond those kept (held_span) is only cleared.
  const auto [h0, h1] = held_span();
  touch({h0, h1});
  auto add_cell = [&](std::size_t c) {
    const std::int64_t* const a = s.data() + 3 * c;
    if (a[0] == 0 && a[1] == 0 && a[2] == 0) return;
    if (c >= h0 && c < h1) {
      imp_x_[c] += s.value(3 * c); imp_y_[c] += s.value(3 * c + 1); imp_z_[c] += s.value(3 * c + 2);
    }
    s.clear(3 * c, 3 * c + 3);
  };
  if (own) {
    // Where every process's particles reached only its planes (share_planes), the sums
    // are added up on each process's planes; else over the run of cells reached.
    const int nz = grid_.n(2);
    std::vector<double> reach{-static_cast<double>(lo), static_cast<double>(hi)};
    if (by_planes) reach.push_back(lo > hi || planes_->within_reach(plane_of(lo), plane_of(hi), nz) ? 0.0 : 1.0);
    own->max(reach);
    lo = static_cast<std::size_t>(-reach[0]);
    hi = static_cast<std::size_t>(reach[1]);
    reached_span_ = lo <= hi ? hi - lo + 1 : 0;  // alike on every process
    if (by_planes && reach[2] == 0.0) {
      std::vector<std::int64_t> total(s.data() + 3 * nc, s.data() + 3 * nc + 3);
      own->add_up(total);
      std::copy(total.begin(), total.end(), s.data() + 3 * nc);
      planes_->add_up({s.data()}, 3 * grid_.plane_start(0), 3 * grid_.plane_size(), nz);
      reaction_whole_ = false;
      // Beyond this process's reach its sums are zero.
      const auto [k0, k1] = planes_->reach_of(planes_->rank(), nz);
      lo = std::max(lo, grid_.plane_start(k0));
      hi = std::min(hi, grid_.plane_start(k1));
    } else {
      const std::size_t first = 3 * lo, cells = lo <= hi ? 3 * (hi - lo + 1) : 0;
      std::vector<std::int64_t> run(cells + 3);
      std::copy_n(s.data() + first, cells, run.begin());
      std::copy_n(s.data() + 3 * nc, 3, run.begin() + static_cast<std::ptrdiff_t>(cells));
      own->add_up(run);
      std::copy_n(run.begin(), cells, s.data() + first);
      std::copy_n(run.begin() + static_cast<std::ptrdiff_t>(cells), 3, s.data() + 3 * nc);
    }
    for (std::size_t c = lo; c <= hi; ++c) add_cell(c);
  } else {
    for (const std::uint32_t c : reached_cells_) add_cell(c);
    reached_span_ = lo <= hi ? hi - lo + 1 : 0;
  }
  for (const std::uint32_t c : reached_cells_) reached_[c] = 0;
  reached_cells_.clear();
  particle_impulse_ += Vec3{s.value(3 * nc), s.value(3 * nc + 1), s.value(3 * nc + 2)};
  s.clear(3 * nc, 3 * nc + 3);
}

void TwoWayExchange::deposit_impulse_of_leaving(Vec3 x, Vec3 j) {
  double at[3] = {x.x, x.y, x.z};
  for (int a = 0; a < grid_.dims(); ++a)
    if (!grid_.spec().periodic(a)) at[a] = std::clamp(at[a], grid_.lo(a), grid_.lo(a) + grid_.length(a));
  deposit_impulse(j, {at[0], at[1], at[2]});
}

void TwoWayExchange::add_to_balance(const CouplingBalance& b) {
  balance_.particles += b.particles;
  balance_.gas_cells += b.gas_cells;
  balance_.gas_faces += b.gas_faces;
}

void TwoWayExchange::apply_reaction(fluid::GasSolver& gs, double dtg) {
  // The drag reaction, deposited on the cells, as a force per unit volume on the faces:
  // each cell gives half to each of its two faces along the component. A face whose
  // velocity is fixed (a wall or an inlet) keeps its share: the gas solver does not
  // solve that face, and its drag sets the pressure gradient there
  // (GasField::drag_gradient).
  const fluid::StaggeredGrid& g = grid_;
  const double per = 1.0 / (g.cell_volume() * dtg);
  std::vector<double>* force[3] = {&gs.force_u, &gs.force_v, &gs.force_w};
  const std::vector<double>* imp[3] = {&imp_x_, &imp_y_, &imp_z_};
  Vec3 cells, faces;
  double* cc[3] = {&cells.x, &cells.y, &cells.z};
  double* fc[3] = {&faces.x, &faces.y, &faces.z};
  // Where the reaction is valid on each process's reach only, each process counts its own
  // planes in the balance, added up over the processes. The faces are set on the cells
  // kept (held_span).
  const bool counted_whole = reaction_whole_ && held_whole();
  const auto [k0, k1] = counted_whole ? std::pair{0, g.n(2)} : planes_->mine(g.n(2));
  const auto [w0, w1] = planes_ ? g.window_planes(fluid::Staggering::centre) : std::pair{0, g.n(2)};
  for (int c = 0; c < g.dims(); ++c)
    for (int k = w0; k < w1; ++k)
      for (int j = 0; j < g.n(1); ++j)
        for (int i = 0; i < g.n(0); ++i) {
          const double v = (*imp[c])[g.at(i, j, k)];
          if (k >= k0 && k < k1) *cc[c] += v;
          int lo[3] = {i, j, k}, hi[3] = {i, j, k};
          hi[c] += 1;
          if (g.spec().periodic(c)) hi[c] %= g.n(c);
          const double half = 0.5 * v;
          (*force[c])[g.at(lo[0], lo[1], lo[2])] += half * per;
          (*force[c])[g.at(hi[0], hi[1], hi[2])] += half * per;
          if (k >= k0 && k < k1) *fc[c] += half + half;
        }
  if (!counted_whole) {
    double sums[6] = {cells.x, cells.y, cells.z, faces.x, faces.y, faces.z};
    planes_->sum(sums, 6);
    cells = {sums[0], sums[1], sums[2]};
    faces = {sums[3], sums[4], sums[5]};
  }
  reaction_whole_ = true;  // zero below
  balance_ = {particle_impulse_, cells, faces};
  particle_impulse_ = {};
  const auto t0 = static_cast<std::ptrdiff_t>(touched_.first), t1 = static_cast<std::ptrdiff_t>(touched_.second);
  for (auto* v : {&imp_x_, &imp_y_, &imp_z_})
    if (t0 < t1) std::fill(v->begin() + t0, v->begin() + t1, 0.0);
  touched_ = {0, 0};
}

void TwoWayExchange::save_state(OutArchive& a) const {
  // Among processes each plane's reaction is its owner's.
  const OutArchive::Planes planes{grid_.plane_start(0), grid_.plane_size(), grid_.n(2)};
  for (const auto* v : {&imp_x_, &imp_y_, &imp_z_}) a.put_planes(*v, planes);
  a.put(particle_impulse_.x); a.put(particle_impulse_.y); a.put(particle_impulse_.z);
}

void TwoWayExchange::load_state(InArchive& a) {
  // The reaction on the planes held: the step reads no other (apply_reaction). Without a
  // two-way coupling, empty arrays (get() refuses any other).
  for (auto* v : {&imp_x_, &imp_y_, &imp_z_})
    if (two_way()) grid_.get_window(a, *v);
    else a.get(*v, 0);
  a.get(particle_impulse_.x); a.get(particle_impulse_.y); a.get(particle_impulse_.z);
  touched_ = two_way() ? held_span() : std::pair<std::size_t, std::size_t>{0, 0};
}

}  // namespace cdm::coupling
