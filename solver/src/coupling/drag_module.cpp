#include "cdm/solver/coupling/drag_module.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "cdm/solver/parallel.hpp"

namespace cdm::coupling {

const char* to_string(DragLaw law) {
  switch (law) {
    case DragLaw::schiller_naumann: return "schiller_naumann";
    case DragLaw::wen_yu: return "wen_yu";
    case DragLaw::gidaspow: return "gidaspow";
    case DragLaw::di_felice: return "di_felice";
    case DragLaw::beetstra: return "beetstra";
  }
  return "?";
}

const char* to_string(DragUpdate u) {
  switch (u) {
    case DragUpdate::explicit_force: return "explicit";
    case DragUpdate::implicit: return "implicit";
    case DragUpdate::exponential: return "exponential";
  }
  return "?";
}

std::string DragModule::name() const { return std::string("drag_") + to_string(law_) + "_" + to_string(update_); }

double DragModule::void_fraction_at(Vec3 x) const {
  if (eps_fixed_ > 0.0) return eps_fixed_;
  // The value of the cell holding the particle (cell-centred, Garg et al. eq 33).
  const fluid::StaggeredGrid& g = gas_->grid();
  int c[3];
  const double xs[3] = {x.x, x.y, x.z};
  for (int a = 0; a < 3; ++a) c[a] = std::clamp(static_cast<int>(std::floor((xs[a] - g.lo(a)) / g.h(a))), 0, g.n(a) - 1);
  return gas_->eps_g[g.at(c[0], c[1], c[2])];
}

void DragModule::add_forces(ParticleStore& p, double /*dt*/) {
  const std::size_t n = p.size();
  const fluid::GasField& gas = *gas_;
  const double rho = gas.density(), mu = gas.viscosity();
  const bool relax = update_ != DragUpdate::explicit_force;
  const double rate = parallel_max(n, [&](std::size_t i) {
    const Vec3 x = p.position(i);
    const Vec3 ug = gas.velocity_at(x);
    const Vec3 slip = ug - p.velocity(i);
    const double k = drag_coefficient(law_, rho, mu, 2.0 * p.radius[i], void_fraction_at(x), norm(slip));
    if (relax) {
      p.drag_k[i] = k;
      p.ugx[i] = ug.x; p.ugy[i] = ug.y; p.ugz[i] = ug.z;
    } else {
      p.fx[i] += k * slip.x; p.fy[i] += k * slip.y; p.fz[i] += k * slip.z;
    }
    const double r = p.inv_mass[i] * k;  // 1/τ_p: the max is the smallest τ_p
    return std::isfinite(r) ? r : 0.0;
  });
  tau_min_ = rate > 0.0 ? 1.0 / rate : std::numeric_limits<double>::infinity();
}

double DragModule::relaxation_time_at_rest(const ParticleStore& p) const {
  const double rho = gas_->density(), mu = gas_->viscosity();
  double tau = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec3 x = p.position(i);
    const double eps = is_finite(x) ? void_fraction_at(gas_->wrap(x)) : (eps_fixed_ > 0.0 ? eps_fixed_ : 1.0);
    const double k = drag_coefficient(law_, rho, mu, 2.0 * p.radius[i], eps, 0.0);
    if (k > 0.0) tau = std::min(tau, p.mass[i] / k);
  }
  return tau;
}

void PressureGradientModule::add_forces(ParticleStore& p, double /*dt*/) {
  const std::size_t n = p.size();
  parallel_for(n, [&](std::size_t i) {
    const double d = 2.0 * p.radius[i];
    const double vol = std::numbers::pi * d * d * d / 6.0;
    const Vec3 gp = gas_->pressure_gradient_at(p.position(i));
    p.fx[i] -= vol * gp.x; p.fy[i] -= vol * gp.y; p.fz[i] -= vol * gp.z;
  });
}

}  // namespace cdm::coupling
