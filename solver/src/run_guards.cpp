#include "cdm/solver/run_guards.hpp"

#include <cmath>
#include <sstream>

#include "cdm/solver/coupling/drag_module.hpp"
#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/parallel.hpp"

namespace cdm {

double explicit_drag_step_limit(IntegratorScheme s) {
  return s == IntegratorScheme::velocity_verlet ? 1.0 : 2.0;
}

void RunGuards::check(double time, std::uint64_t step, double nonfinite, bool gas_read) const {
  const ParticleStore& p = p_;
  const std::size_t n = p.size();
  // |sum| is finite exactly when every value is (barring overflow near 1e308).
  const bool rot = p.has_rotation();
  const double s = nonfinite >= 0.0 ? nonfinite : parallel_max(n, [&](std::size_t i) {
    const double v = p.x[i] + p.y[i] + p.z[i] + p.vx[i] + p.vy[i] + p.vz[i] +
                     (rot ? p.wx[i] + p.wy[i] + p.wz[i] : 0.0);
    return std::isfinite(v) ? 0.0 : 1.0;
  });
  const double t_col = spec_.t_col_min;
  auto cause = [&](std::ostringstream& os) {
    os << "; dt = " << spec_.dt << " s";
    if (t_col > 0.0) os << ", shortest collision time t_col = " << t_col << " s (dt/t_col = " << spec_.dt / t_col << ")";
    if (drag_) {
      const double tp = drag_->relaxation_time_at_rest(p);
      const double limit = explicit_drag_step_limit(spec_.integrator);
      os << ", shortest particle relaxation time at zero slip tau_p = m/K = " << tp << " s (tau_p/dt = " << tp / spec_.dt
         << "; drag update '" << coupling::to_string(spec_.drag_update) << "'";
      if (spec_.drag_update == coupling::DragUpdate::explicit_force && tp < spec_.dt / limit)
        os << ": an explicit drag update is unstable for dt > " << (limit == 1.0 ? "" : "2 ") << "tau_p with "
           << to_string(spec_.integrator) << ", use drag.update = \"exponential\" or \"implicit\"";
      os << ")";
    }
  };
  if (s != 0.0) {
    std::ostringstream os;
    os << "state is no longer finite at t = " << time << " s (step " << step << "), particle(s):";
    int listed = 0;
    for (std::size_t i = 0; i < n && listed < 5; ++i) {
      if (!p.state_finite(i)) { os << ' ' << p.id_of(i) << " (" << particle_source(spec_, p.id_of(i)) << ')'; ++listed; }
    }
    os << ". Likely cause: a time step too large for the stiffest force";
    cause(os);
    throw SimulationError(os.str());
  }
  if (gas_ && gas_read) {
    // A particle must stay in the gas domain along every axis that is not periodic
    // (GasField::contains, with the bounds read once).
    const fluid::StaggeredGrid& g = gas_->grid();
    const double lo[3] = {g.lo(0), g.lo(1), g.lo(2)};
    const double hi[3] = {g.lo(0) + g.length(0), g.lo(1) + g.length(1), g.lo(2) + g.length(2)};
    const double out = parallel_max(n, [&](std::size_t i) {
      const bool in = p.x[i] >= lo[0] && p.x[i] <= hi[0] && p.y[i] >= lo[1] && p.y[i] <= hi[1] && p.z[i] >= lo[2] &&
                      p.z[i] <= hi[2];
      return in ? 0.0 : 1.0;
    });
    if (out != 0.0) {
      std::ostringstream os;
      os << "particle(s) left the gas domain at t = " << time << " s (step " << step << "):";
      int listed = 0;
      for (std::size_t i = 0; i < n && listed < 5; ++i)
        if (!gas_->contains(p.position(i))) {
          const Vec3 x = p.position(i);
          os << ' ' << p.id_of(i) << " (" << particle_source(spec_, p.id_of(i)) << ") at [" << x.x << ", " << x.y << ", " << x.z << "] m";
          ++listed;
        }
      os << ". Likely cause: the gas domain is too small for this run (make it larger, periodic, or bounded by "
            "walls), or the step is too large";
      cause(os);
      throw SimulationError(os.str());
    }
  }
  if (contact_ && contact_->worst_overlap().ratio >= spec_.max_overlap_fraction) {
    const OverlapRecord& w = contact_->worst_overlap();
    std::ostringstream os;
    os << "overlap reached " << w.ratio << " of the radius (limit checks.max_overlap_fraction = "
       << spec_.max_overlap_fraction << ") at t = " << time << " s (step " << step << "): particle "
       << p.id_of(w.particle) << " (" << particle_source(spec_, p.id_of(w.particle)) << ") against ";
    if (w.partner >= 0) {
      const std::size_t k = p.id_of(static_cast<std::size_t>(w.partner));
      os << "particle " << k << " (" << particle_source(spec_, k) << ")";
    }
    else os << contact_->wall_name(w.partner);
    os << ". Likely cause: the normal spring is too soft to stop the particle within its radius at this impact "
          "speed (raise kn), or the time step is too large";
    cause(os);
    throw SimulationError(os.str());
  }
}

void RunGuards::check_gas(const fluid::GasSolver& gs, double dtg, double time) const {
  const auto [cfl, finite] = gs.health(dtg);
  if (finite && cfl <= 1.0) return;
  std::ostringstream os;
  os << "the gas " << (finite ? "velocity exceeds one cell per gas step" : "state is no longer finite") << " at t = "
     << time << " s (Courant number " << cfl << ", diffusion number " << gs.diffusion_number(dtg)
     << "). Likely cause: gas.dt = " << dtg << " s too large for the flow (keep |u| dt/h below 1 and "
     << "mu dt/(rho h^2) summed over the axes below 1/2"
     << (p_.has_two_way() && !spec_.implicit_gas_drag
             ? "; with two-way coupling and coupling.gas_drag = \"explicit\" the drag on the gas is explicit, so "
               "gas.dt must also stay below 2 eps_g rho_g / beta, the time the gas takes to relax to the particles' "
               "velocity, which dense or fine-particle regions make short (\"implicit\" lifts this limit)"
             : "")
     << ")";
  throw SimulationError(os.str());
}

}  // namespace cdm
