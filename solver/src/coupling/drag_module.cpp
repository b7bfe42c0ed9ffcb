#include "cdm/solver/coupling/drag_module.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/run_guards.hpp"
#include "cdm/solver/slot_pages.hpp"

namespace cdm::coupling {

namespace {
/// The explicit drag K slip on particle i, kept per particle for the reaction with @p two_way.
void add_explicit(ParticleStore& p, std::size_t i, double k, Vec3 slip, bool two_way) {
  p.fx[i] += k * slip.x; p.fy[i] += k * slip.y; p.fz[i] += k * slip.z;
  if (two_way) { p.dfx[i] = k * slip.x; p.dfy[i] = k * slip.y; p.dfz[i] = k * slip.z; }
}

/// The cell-centred ∇p weighted by the deposition weights at @p x, plus the imposed mean
/// gradient (particle_pressure_gradient); with @p eps, also Σ w ε_g there, summed in the
/// order Deposition::average sums it, in the same pass over the weights.
Vec3 deposited_pressure_gradient(const fluid::GasField& gas, const Deposition& kernel, Vec3 x, double* eps = nullptr) {
  const double* const E = gas.eps_g.data();
  const double* const gx = gas.cell_gpx.data();
  const double* const gy = gas.cell_gpy.data();
  const double* const gz = gas.cell_gpz.data();
  Vec3 g;
  double e = 0.0;
  kernel.for_each_weight(x, [&](std::size_t c, double w) {
    if (eps) e += w * E[c];
    g.x += w * gx[c]; g.y += w * gy[c]; g.z += w * gz[c];
  });
  if (eps) *eps = e;
  return g + gas.mean_pressure_gradient;
}
}  // namespace

Vec3 particle_pressure_gradient(const fluid::GasField& gas, const Deposition* kernel, Vec3 x) {
  return kernel ? deposited_pressure_gradient(gas, *kernel, x) : gas.pressure_gradient_at(x);
}

std::string DragModule::name() const { return std::string("drag_") + to_string(law_) + "_" + to_string(update_); }

double DragModule::void_fraction_at(Vec3 x) const {
  if (eps_fixed_ > 0.0) return eps_fixed_;
  if (kernel_) return kernel_->average(gas_->eps_g, x);
  // The value of the cell holding the particle (cell-centred, Garg et al. eq 33).
  const fluid::StaggeredGrid& g = gas_->grid();
  int c[3];
  const double xs[3] = {x.x, x.y, x.z};
  for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor((xs[a] - g.lo(a)) / g.h(a))), 0, g.n(a) - 1);
  return gas_->eps_g[g.at(c[0], c[1], c[2])];
}

void DragModule::add_forces(ParticleStore& p, double /*dt*/) {
  if (method_ == CouplingMethod::cell_average) {
    add_cell_average(p);
    return;
  }
  if (!clock_) {
    evaluate(p, false);
    return;
  }
  const bool relax = update_ != DragUpdate::explicit_force;
  const std::size_t n = p.size();
  const bool missing = !relax && (k_.size() != n || (grad_p_ && grad_p_->fx_.size() != n));
  if (clock_->due || missing) evaluate(p, !relax);
  if (!relax) add_cached_explicit(p);
}

void DragModule::take_pressure_gradient(PressureGradientModule& m) {
  if (!clock_ || m.clock_ != clock_ || update_ != DragUpdate::explicit_force || method_ != CouplingMethod::interpolate)
    throw std::logic_error("take_pressure_gradient: both modules once per gas step on one clock, the drag explicit");
  grad_p_ = &m;
  m.taken_ = true;
}

void DragModule::evaluate(ParticleStore& p, bool cache) {
  const std::size_t n = p.size();
  const fluid::GasField& gas = *gas_;
  const double rho = gas.density(), mu = gas.viscosity();
  const bool relax = update_ != DragUpdate::explicit_force;
  if (cache) {
    for (auto* a : {&k_, &ugx_, &ugy_, &ugz_}) resize_zeroed(*a, n);
  }
  PressureGradientModule* const gp = cache ? grad_p_ : nullptr;
  if (gp) {
    for (auto* a : {&gp->fx_, &gp->fy_, &gp->fz_}) resize_zeroed(*a, n);
  }
  // Two-way with the pressure gradient taken: ε_g and ∇p weighted by the particle's
  // deposition weights, in one pass over them (each sum in the order of its own function).
  const bool fused = gp && kernel_ && eps_fixed_ <= 0.0;
  const double rate = max_own(ranks_, n, [&](std::size_t i) {
    const Vec3 x = p.position(i);
    double eps = 0.0;
    Vec3 cell_grad;
    if (fused) cell_grad = deposited_pressure_gradient(gas, *kernel_, x, &eps);
    else eps = void_fraction_at(x);
    // The flux ε u is continuous where ε jumps (at a bed's surface or its distributor),
    // the interstitial velocity is not: interpolating the flux and dividing by the
    // particle's own ε gives a particle inside a packed layer U/ε, not a blend with the
    // clear gas beside it.
    Vec3 ug, grad_p;
    if (gp && !superficial_ && !kernel_) {
      gas.velocity_and_pressure_gradient_at(x, ug, grad_p);
    } else {
      ug = superficial_ ? (1.0 / eps) * gas.superficial_velocity_at(x) : gas.velocity_at(x);
      if (gp) grad_p = fused ? cell_grad : particle_pressure_gradient(gas, kernel_, x);
    }
    if (gp) {
      const Vec3 f = PressureGradientModule::force(p, i, grad_p);
      gp->fx_[i] = f.x; gp->fy_[i] = f.y; gp->fz_[i] = f.z;
    }
    const Vec3 slip = ug - p.velocity(i);
    const double k = drag_coefficient(law_, rho, mu, 2.0 * p.radius[i], eps, norm(slip));
    if (relax) {
      p.drag_k[i] = k;
      p.ugx[i] = ug.x; p.ugy[i] = ug.y; p.ugz[i] = ug.z;
    } else if (cache) {
      k_[i] = k;
      ugx_[i] = ug.x; ugy_[i] = ug.y; ugz_[i] = ug.z;
    } else {
      add_explicit(p, i, k, slip, two_way_);
    }
    const double r = p.inv_mass[i] * k;  // 1/τ_p: the max is the smallest τ_p
    return std::isfinite(r) ? r : 0.0;
  });
  tau_min_ = rate > 0.0 ? 1.0 / rate : std::numeric_limits<double>::infinity();
}

void DragModule::add_cached_explicit(ParticleStore& p) const {
  // add_explicit's arithmetic on raw pointers, one loop per axis and per variant, so that
  // the loops vectorise (through the store's vectors they did not); with the pressure
  // gradient taken, its cached force is subtracted right after the drag is added.
  const std::size_t n = p.size();
  const double* __restrict k = k_.data();
  const double* const ug[3] = {ugx_.data(), ugy_.data(), ugz_.data()};
  const double* const v[3] = {p.vx.data(), p.vy.data(), p.vz.data()};
  double* const f[3] = {p.fx.data(), p.fy.data(), p.fz.data()};
  double* const df[3] = {p.dfx.data(), p.dfy.data(), p.dfz.data()};
  const double* const gp[3] = {grad_p_ ? grad_p_->fx_.data() : nullptr, grad_p_ ? grad_p_->fy_.data() : nullptr,
                               grad_p_ ? grad_p_->fz_.data() : nullptr};
  auto axis = [&]<bool TwoWay, bool GradP>(int a, std::size_t i0, std::size_t i1) {
    const double* __restrict u = ug[a];
    const double* __restrict va = v[a];
    const double* __restrict c = gp[a];
    double* __restrict fa = f[a];
    double* __restrict d = df[a];
    for (std::size_t i = i0; i < i1; ++i) {
      const double fi = k[i] * (u[i] - va[i]);
      double fs = fa[i] + fi;
      if constexpr (GradP) fs -= c[i];
      fa[i] = fs;
      if constexpr (TwoWay) d[i] = fi;
    }
  };
  const bool two_way = two_way_, grad_p = grad_p_ != nullptr;
  for_own_ranges(ranks_, n, [&](std::size_t i0, std::size_t i1) {
    for (int a = 0; a < 3; ++a) {
      if (two_way && grad_p) axis.template operator()<true, true>(a, i0, i1);
      else if (two_way) axis.template operator()<true, false>(a, i0, i1);
      else if (grad_p) axis.template operator()<false, true>(a, i0, i1);
      else axis.template operator()<false, false>(a, i0, i1);
    }
  });
}

void DragModule::save_state(OutArchive& a) const {
  if (!clock_) return;  // nothing carried between steps
  a.put(tau_min_);
  for (const auto* v : {&k_, &ugx_, &ugy_, &ugz_}) a.put_particles(*v);
}

void DragModule::load_state(InArchive& a) {
  if (!clock_) return;
  a.get(tau_min_);
  for (auto* v : {&k_, &ugx_, &ugy_, &ugz_}) get_slots(a, *v);  // this process's share (slot_pages.hpp)
  for (auto* v : {&ugx_, &ugy_, &ugz_})
    if (v->size() != k_.size()) throw ArchiveError("the cached drag arrays differ in length");
}

void DragModule::permute(const std::vector<std::uint32_t>& from) {
  std::vector<double> tmp;
  for (auto* v : {&k_, &ugx_, &ugy_, &ugz_})
    if (v->size() == from.size()) permute_array(*v, from, tmp);
}

void DragModule::remap(const std::vector<std::uint32_t>& /*from*/, const ParticleStore& /*p*/) {
  for (auto* v : {&k_, &ugx_, &ugy_, &ugz_}) v->clear();
}

void DragModule::add_cell_average(ParticleStore& p) {
  // Garg et al. eqs 33–35: every particle of a cell sees the cell-centred gas velocity
  // and the cell's volume-averaged solids velocity; K from the particle's diameter and
  // the cell's ε_g and slip |u_g − v_s|. The force does not depend on the particle's own
  // velocity (so only the explicit update applies).
  const fluid::GasField& gas = *gas_;
  const fluid::StaggeredGrid& g = gas.grid();
  const std::size_t n = p.size();
  const double rho = gas.density(), mu = gas.viscosity();
  const std::size_t nc = g.padded_size();
  // Each rank sums its own particles' volumes and volume-weighted velocities per cell,
  // in sums that do not depend on the order of their terms (exact_sums.hpp), added up
  // over the ranks: every rank gets every cell's average, and evaluates its own particles.
  RankSplit* const own = ranks_ && ranks_->partitioned() ? ranks_ : nullptr;
  auto cell_of = [&](Vec3 x) {
    int c[3];
    const double xs[3] = {x.x, x.y, x.z};
    for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor((xs[a] - g.lo(a)) / g.h(a))), 0, g.n(a) - 1);
    return std::array<int, 3>{c[0], c[1], c[2]};
  };
  // The sums' bounds: the largest volume and |volume × velocity component| of a particle.
  std::vector<double> bound{0.0, 0.0};
  for_own_in_order(own, n, [&](std::size_t i) {
    const double vol = p.volume(i);
    bound[0] = std::max(bound[0], vol);
    bound[1] = std::max({bound[1], vol * std::abs(p.vx[i]), vol * std::abs(p.vy[i]), vol * std::abs(p.vz[i])});
  });
  if (own) own->max(bound);
  if (!std::isfinite(bound[0]) || !std::isfinite(bound[1]))
    throw SimulationError("a particle's volume or velocity is not finite in the cell-average drag");
  const double count = static_cast<double>(n);
  cell_vol_.reset(nc, bound[0], count * bound[0]);
  cell_mom_.reset(3 * nc, bound[1], count * bound[1]);
  for_own_in_order(own, n, [&](std::size_t i) {
    const auto c = cell_of(p.position(i));
    const std::size_t k = g.at(c[0], c[1], c[2]);
    const double vol = p.volume(i);
    cell_vol_.add(k, vol);
    cell_mom_.add(k, vol * p.vx[i]); cell_mom_.add(nc + k, vol * p.vy[i]); cell_mom_.add(2 * nc + k, vol * p.vz[i]);
  });
  if (own) own->add_up(cell_vol_, cell_mom_);
  double rate = 0.0;
  for_own_in_order(own, n, [&](std::size_t i) {
    const auto c = cell_of(p.position(i));
    const std::size_t k = g.at(c[0], c[1], c[2]);
    const double cv = cell_vol_.value(k);
    const Vec3 vs{cell_mom_.value(k) / cv, cell_mom_.value(nc + k) / cv, cell_mom_.value(2 * nc + k) / cv};
    const Vec3 ug{0.5 * (gas.u[g.at(c[0], c[1], c[2])] + gas.u[g.at(c[0] + 1, c[1], c[2])]),
                  0.5 * (gas.v[g.at(c[0], c[1], c[2])] + gas.v[g.at(c[0], c[1] + 1, c[2])]),
                  g.two_d() ? 0.0 : 0.5 * (gas.w[g.at(c[0], c[1], c[2])] + gas.w[g.at(c[0], c[1], c[2] + 1)])};
    const double eps = eps_fixed_ > 0.0 ? eps_fixed_ : gas.eps_g[k];
    const Vec3 slip = gas.time_factor() * ug - vs;
    const double kd = drag_coefficient(law_, rho, mu, 2.0 * p.radius[i], eps, norm(slip));
    const Vec3 f = kd * slip;
    p.add_force(i, f);
    if (two_way_) { p.dfx[i] = f.x; p.dfy[i] = f.y; p.dfz[i] = f.z; }
    const double r = p.inv_mass[i] * kd;
    if (std::isfinite(r)) rate = std::max(rate, r);
  });
  if (own) rate = own->max(rate);
  tau_min_ = rate > 0.0 ? 1.0 / rate : std::numeric_limits<double>::infinity();
}

double DragModule::relaxation_time_at_rest(const ParticleStore& p) const {
  const double rho = gas_->density(), mu = gas_->viscosity();
  // Among MPI processes each holds its own particles' masses: the smallest over theirs,
  // then over the processes (every process reports a failure alike).
  double tau = std::numeric_limits<double>::infinity();
  for_own_in_order(ranks_, p.size(), [&](std::size_t i) {
    const Vec3 x = p.position(i);
    const double eps = is_finite(x) ? void_fraction_at(gas_->wrap(x)) : (eps_fixed_ > 0.0 ? eps_fixed_ : 1.0);
    const double k = drag_coefficient(law_, rho, mu, 2.0 * p.radius[i], eps, 0.0);
    if (k > 0.0) tau = std::min(tau, p.mass[i] / k);
  });
  return ranks_ ? -ranks_->max(-tau) : tau;
}

Vec3 PressureGradientModule::force(const ParticleStore& p, std::size_t i, Vec3 grad_p) {
  const double vol = p.volume(i);
  return {vol * grad_p.x, vol * grad_p.y, vol * grad_p.z};
}

void PressureGradientModule::add_forces(ParticleStore& p, double /*dt*/) {
  if (taken_) return;  // the drag module evaluates and applies it
  const std::size_t n = p.size();
  auto force = [&](std::size_t i) {
    return PressureGradientModule::force(p, i, particle_pressure_gradient(*gas_, kernel_, p.position(i)));
  };
  if (!clock_) {
    for_own(ranks_, n, [&](std::size_t i) {
      const Vec3 f = force(i);
      p.fx[i] -= f.x; p.fy[i] -= f.y; p.fz[i] -= f.z;
    });
    return;
  }
  if (clock_->due || fx_.size() != n) {
    for (auto* a : {&fx_, &fy_, &fz_}) resize_zeroed(*a, n);
    for_own(ranks_, n, [&](std::size_t i) {
      const Vec3 f = force(i);
      fx_[i] = f.x; fy_[i] = f.y; fz_[i] = f.z;
    });
  }
  // On raw pointers, one loop per axis, so that they vectorise.
  const double* const c[3] = {fx_.data(), fy_.data(), fz_.data()};
  double* const f[3] = {p.fx.data(), p.fy.data(), p.fz.data()};
  for_own_ranges(ranks_, n, [&](std::size_t i0, std::size_t i1) {
    for (int a = 0; a < 3; ++a) {
      const double* __restrict ca = c[a];
      double* __restrict fa = f[a];
      for (std::size_t i = i0; i < i1; ++i) fa[i] -= ca[i];
    }
  });
}

void PressureGradientModule::save_state(OutArchive& a) const {
  if (!clock_) return;
  for (const auto* v : {&fx_, &fy_, &fz_}) a.put_particles(*v);
}

void PressureGradientModule::load_state(InArchive& a) {
  if (!clock_) return;
  for (auto* v : {&fx_, &fy_, &fz_}) get_slots(a, *v);
  if (fy_.size() != fx_.size() || fz_.size() != fx_.size())
    throw ArchiveError("the cached pressure-gradient arrays differ in length");
}

void PressureGradientModule::permute(const std::vector<std::uint32_t>& from) {
  std::vector<double> tmp;
  for (auto* v : {&fx_, &fy_, &fz_})
    if (v->size() == from.size()) permute_array(*v, from, tmp);
}

void PressureGradientModule::remap(const std::vector<std::uint32_t>& /*from*/, const ParticleStore& /*p*/) {
  for (auto* v : {&fx_, &fy_, &fz_}) v->clear();
}

}  // namespace cdm::coupling
