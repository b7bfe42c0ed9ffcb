#include "cdm/solver/coupling/two_way_exchange.hpp"

#include <algorithm>
#include <sstream>

#include "cdm/solver/run_guards.hpp"

namespace cdm::coupling {

TwoWayExchange::TwoWayExchange(const fluid::StaggeredGrid& grid, bool two_way, Kernel kernel, double width)
    : grid_(grid) {
  if (!two_way) return;
  deposition_ = std::make_unique<Deposition>(grid, kernel, width);
  imp_x_.assign(grid.padded_size(), 0.0);
  imp_y_ = imp_z_ = imp_x_;
}

template <class Also>
void TwoWayExchange::deposit_impulse(ParticleStore& p, std::size_t i, Vec3 at, Also&& also) {
  const double jx = p.jx[i], jy = p.jy[i], jz = p.jz[i];
  particle_impulse_ += Vec3{jx, jy, jz};
  deposition_->for_each_weight(at, [&](std::size_t c, double w) {
    imp_x_[c] -= w * jx; imp_y_[c] -= w * jy; imp_z_[c] -= w * jz;
    also(c, w);
  });
  p.jx[i] = p.jy[i] = p.jz[i] = 0.0;
}

void TwoWayExchange::deposit_void_fraction(const ParticleStore& p, std::vector<double>& eps, double time) const {
  eps.assign(grid_.padded_size(), 0.0);
  const double vc = grid_.cell_volume();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double vol = p.volume(i) / vc;
    deposition_->for_each_weight(p.position(i), [&](std::size_t c, double w) { eps[c] += w * vol; });
  }
  finish_void_fraction(eps, time);
}

void TwoWayExchange::deposit_impulses_and_void_fraction(ParticleStore& p, std::vector<double>& eps, double time) {
  eps.assign(grid_.padded_size(), 0.0);
  const double vc = grid_.cell_volume();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double vol = p.volume(i) / vc;
    deposit_impulse(p, i, p.position(i), [&](std::size_t c, double w) { eps[c] += w * vol; });
  }
  finish_void_fraction(eps, time);
}

void TwoWayExchange::finish_void_fraction(std::vector<double>& eps, double time) const {
  const fluid::StaggeredGrid& g = grid_;
  double worst = 1.0;
  int wc[3] = {0, 0, 0};
  for (int k = 0; k < g.n(2); ++k)
    for (int j = 0; j < g.n(1); ++j)
      for (int i = 0; i < g.n(0); ++i) {
        double& e = eps[g.at(i, j, k)];
        e = 1.0 - e;
        if (e < worst) { worst = e; wc[0] = i; wc[1] = j; wc[2] = k; }
      }
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

void TwoWayExchange::deposit_impulses(ParticleStore& p) {
  for (std::size_t i = 0; i < p.size(); ++i) deposit_impulse(p, i, p.position(i), [](std::size_t, double) {});
}

void TwoWayExchange::deposit_impulse_of_leaving(ParticleStore& p, std::size_t i) {
  const Vec3 x = p.position(i);
  double at[3] = {x.x, x.y, x.z};
  for (int a = 0; a < grid_.dims(); ++a)
    if (!grid_.spec().periodic(a)) at[a] = std::clamp(at[a], grid_.lo(a), grid_.lo(a) + grid_.length(a));
  deposit_impulse(p, i, {at[0], at[1], at[2]}, [](std::size_t, double) {});
}

FaceShares face_shares(const fluid::StaggeredGrid& g, int c, int i) {
  auto fixed_face = [&](int f) {
    if (g.spec().periodic(c) || (f > 0 && f < g.n(c))) return false;
    return g.spec().faces[2 * c + (f == 0 ? 0 : 1)].kind != fluid::BoundaryKind::pressure_outlet;
  };
  const bool lo_fixed = fixed_face(i), hi_fixed = fixed_face(i + 1);
  if (lo_fixed && hi_fixed) return {0.0, 0.0};  // a single cell between walls: the walls take it
  if (lo_fixed) return {0.0, 1.0};
  if (hi_fixed) return {1.0, 0.0};
  return {0.5, 0.5};
}

void TwoWayExchange::add_to_balance(const CouplingBalance& b) {
  balance_.particles += b.particles;
  balance_.gas_cells += b.gas_cells;
  balance_.gas_faces += b.gas_faces;
}

void TwoWayExchange::apply_reaction(fluid::GasSolver& gs, double dtg) {
  // The drag reaction, deposited on the cells, as a force per unit volume on the faces:
  // each cell gives half to each of its two faces along the component; the share of a
  // face whose velocity is fixed (a wall or an inlet) goes to the cell's other face, so
  // the gas receives all of it.
  const fluid::StaggeredGrid& g = grid_;
  const double per = 1.0 / (g.cell_volume() * dtg);
  std::vector<double>* force[3] = {&gs.force_u, &gs.force_v, &gs.force_w};
  const std::vector<double>* imp[3] = {&imp_x_, &imp_y_, &imp_z_};
  Vec3 cells, faces;
  double* cc[3] = {&cells.x, &cells.y, &cells.z};
  double* fc[3] = {&faces.x, &faces.y, &faces.z};
  for (int c = 0; c < g.dims(); ++c)
    for (int k = 0; k < g.n(2); ++k)
      for (int j = 0; j < g.n(1); ++j)
        for (int i = 0; i < g.n(0); ++i) {
          const double v = (*imp[c])[g.at(i, j, k)];
          *cc[c] += v;
          int lo[3] = {i, j, k}, hi[3] = {i, j, k};
          hi[c] += 1;
          if (g.spec().periodic(c)) hi[c] %= g.n(c);
          const FaceShares sh = face_shares(g, c, lo[c]);
          const double to_lo = sh.lo * v, to_hi = sh.hi * v;
          (*force[c])[g.at(lo[0], lo[1], lo[2])] += to_lo * per;
          (*force[c])[g.at(hi[0], hi[1], hi[2])] += to_hi * per;
          *fc[c] += to_lo + to_hi;
        }
  balance_ = {particle_impulse_, cells, faces};
  particle_impulse_ = {};
  std::fill(imp_x_.begin(), imp_x_.end(), 0.0);
  std::fill(imp_y_.begin(), imp_y_.end(), 0.0);
  std::fill(imp_z_.begin(), imp_z_.end(), 0.0);
}

void TwoWayExchange::save_state(OutArchive& a) const {
  a.put(imp_x_); a.put(imp_y_); a.put(imp_z_);
  a.put(particle_impulse_.x); a.put(particle_impulse_.y); a.put(particle_impulse_.z);
}

void TwoWayExchange::load_state(InArchive& a) {
  const std::size_t want = two_way() ? grid_.padded_size() : 0;
  for (auto* v : {&imp_x_, &imp_y_, &imp_z_}) {
    a.get(*v, want);
    if (v->size() != want) throw ArchiveError("a particle array has the wrong length");
  }
  a.get(particle_impulse_.x); a.get(particle_impulse_.y); a.get(particle_impulse_.z);
}

}  // namespace cdm::coupling
