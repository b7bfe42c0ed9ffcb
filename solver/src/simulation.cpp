#include "cdm/solver/simulation.hpp"

#include "cdm/solver/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <utility>

namespace cdm {

Simulation::Simulation(SceneSpec spec) : spec_(std::move(spec)) {
  // Build only the modules the scene names. Rotation exists only with a module that
  // makes torque (friction, rolling resistance).
  if (spec_.tangential != TangentialModel::none || spec_.rolling != RollingModel::none) particles_.enable_rotation();
  for (const auto& ps : spec_.particles) {
    particles_.add(ps.position, ps.velocity, ps.radius, spec_.materials[ps.material].density, ps.material);
    particles_.set_angular_velocity(particles_.size() - 1, ps.angular_velocity);
  }
  if (spec_.gravity) modules_.push_back(std::make_unique<GravityModule>(spec_.g));
  if (spec_.normal_contact != NormalContactModel::none) {
    // Verlet-list skin: a tenth of the largest diameter (as the peers' benchmarks use).
    double d_max = 0.0;
    for (const auto& ps : spec_.particles) d_max = std::max(d_max, 2.0 * ps.radius);
    const bool rolling = spec_.rolling == RollingModel::constant_torque;
    auto c = std::make_unique<ContactModule>(spec_.pairs, spec_.walls,
                                             spec_.tangential == TangentialModel::spring_coulomb, 0.1 * d_max, rolling);
    contact_ = c.get();
    // Velocity Verlet moves positions with its half-step velocities (hv, hw below).
    if (spec_.integrator == IntegratorScheme::velocity_verlet)
      contact_->set_step_velocities({&hvx_, &hvy_, &hvz_, &hwx_, &hwy_, &hwz_});
    modules_.push_back(std::move(c));
    // Rolling resistance acts through the contacts just evaluated, so it runs after them.
    if (rolling) modules_.push_back(std::make_unique<RollingResistanceModule>(*contact_));
  }
  total_steps_ = static_cast<std::uint64_t>(std::ceil(spec_.end_time / spec_.dt - 1e-9));
  // The particles live in the store now; the scene keeps only where they came from.
  spec_.particles.clear();
  spec_.particles.shrink_to_fit();
}

std::vector<std::string> Simulation::module_names() const {
  std::vector<std::string> names;
  for (const auto& m : modules_) names.push_back(m->name());
  return names;
}

void Simulation::compute_forces() {
  particles_.clear_forces();
  for (auto& m : modules_) m->add_forces(particles_, spec_.dt);
  forces_valid_ = true;
}

void Simulation::step() {
  ParticleStore& p = particles_;
  const std::size_t n = p.size();
  const double dt = spec_.dt;
  const bool rot = p.has_rotation();
  switch (spec_.integrator) {
    case IntegratorScheme::paper_euler: {
      // Garg et al. (2012) eqs A.1–A.3: V += F(t)/m Δt; X += V(t+Δt) Δt; ω += T(t)/I Δt.
      // F(t) was evaluated at the end of the previous step, so the guards below always
      // see the forces and overlaps of the state just reached.
      if (!forces_valid_) compute_forces();
      parallel_for(n, [&](std::size_t i) {
        const double a = dt * p.inv_mass[i];
        p.vx[i] += a * p.fx[i]; p.vy[i] += a * p.fy[i]; p.vz[i] += a * p.fz[i];
        p.x[i] += dt * p.vx[i]; p.y[i] += dt * p.vy[i]; p.z[i] += dt * p.vz[i];
      });
      if (rot)
        parallel_for(n, [&](std::size_t i) {
          const double b = dt * p.inv_inertia[i];
          p.wx[i] += b * p.tx[i]; p.wy[i] += b * p.ty[i]; p.wz[i] += b * p.tz[i];
        });
      compute_forces();
      break;
    }
    case IntegratorScheme::velocity_verlet: {
      // Velocity Verlet. The dashpot makes the force depend on the velocity being
      // updated, which drops plain Verlet to first order; the force at t+Δt is
      // evaluated with the predicted velocity v(t) + Δt a(t) (error O(Δt²) in the
      // force, O(Δt³) in the step), which keeps second order.
      if (!forces_valid_) compute_forces();
      hvx_.resize(n); hvy_.resize(n); hvz_.resize(n);
      const double h = 0.5 * dt;
      parallel_for(n, [&](std::size_t i) {
        const double a = h * p.inv_mass[i];
        hvx_[i] = p.vx[i] + a * p.fx[i]; hvy_[i] = p.vy[i] + a * p.fy[i]; hvz_[i] = p.vz[i] + a * p.fz[i];
        p.x[i] += dt * hvx_[i]; p.y[i] += dt * hvy_[i]; p.z[i] += dt * hvz_[i];
        p.vx[i] = hvx_[i] + a * p.fx[i]; p.vy[i] = hvy_[i] + a * p.fy[i]; p.vz[i] = hvz_[i] + a * p.fz[i];
      });
      if (rot) {
        hwx_.resize(n); hwy_.resize(n); hwz_.resize(n);
        parallel_for(n, [&](std::size_t i) {
          const double b = h * p.inv_inertia[i];
          hwx_[i] = p.wx[i] + b * p.tx[i]; hwy_[i] = p.wy[i] + b * p.ty[i]; hwz_[i] = p.wz[i] + b * p.tz[i];
          p.wx[i] = hwx_[i] + b * p.tx[i]; p.wy[i] = hwy_[i] + b * p.ty[i]; p.wz[i] = hwz_[i] + b * p.tz[i];
        });
      }
      compute_forces();
      parallel_for(n, [&](std::size_t i) {
        const double a = h * p.inv_mass[i];
        p.vx[i] = hvx_[i] + a * p.fx[i]; p.vy[i] = hvy_[i] + a * p.fy[i]; p.vz[i] = hvz_[i] + a * p.fz[i];
      });
      if (rot)
        parallel_for(n, [&](std::size_t i) {
          const double b = h * p.inv_inertia[i];
          p.wx[i] = hwx_[i] + b * p.tx[i]; p.wy[i] = hwy_[i] + b * p.ty[i]; p.wz[i] = hwz_[i] + b * p.tz[i];
        });
      break;
    }
  }
  ++steps_;
  time_ = static_cast<double>(steps_) * dt;
  check_state();
}

void Simulation::check_state() const {
  const ParticleStore& p = particles_;
  const std::size_t n = p.size();
  // |sum| is finite exactly when every value is (barring overflow near 1e308).
  const bool rot = p.has_rotation();
  const double s = parallel_max(n, [&](std::size_t i) {
    const double v = p.x[i] + p.y[i] + p.z[i] + p.vx[i] + p.vy[i] + p.vz[i] +
                     (rot ? p.wx[i] + p.wy[i] + p.wz[i] : 0.0);
    return std::isfinite(v) ? 0.0 : 1.0;
  });
  const double t_col = spec_.t_col_min;
  auto cause = [&](std::ostringstream& os) {
    os << "; dt = " << spec_.dt << " s";
    if (t_col > 0.0) os << ", shortest collision time t_col = " << t_col << " s (dt/t_col = " << spec_.dt / t_col << ")";
  };
  if (s != 0.0) {
    std::ostringstream os;
    os << "state is no longer finite at t = " << time_ << " s (step " << steps_ << "), particle(s):";
    int listed = 0;
    for (std::size_t i = 0; i < n && listed < 5; ++i) {
      const bool bad = !is_finite(p.position(i)) || !is_finite(p.velocity(i)) ||
                       (p.has_rotation() && !is_finite(p.angular_velocity(i)));
      if (bad) { os << ' ' << i << " (" << particle_source(spec_, i) << ')'; ++listed; }
    }
    os << ". Likely cause: a time step too large for the stiffest force";
    cause(os);
    throw SimulationError(os.str());
  }
  if (contact_ && contact_->worst_overlap().ratio >= spec_.max_overlap_fraction) {
    const OverlapRecord& w = contact_->worst_overlap();
    std::ostringstream os;
    os << "overlap reached " << w.ratio << " of the radius (limit checks.max_overlap_fraction = "
       << spec_.max_overlap_fraction << ") at t = " << time_ << " s (step " << steps_ << "): particle " << w.particle
       << " (" << particle_source(spec_, w.particle) << ") against ";
    if (w.partner >= 0) os << "particle " << w.partner << " (" << particle_source(spec_, static_cast<std::size_t>(w.partner)) << ")";
    else os << "wall '" << contact_->walls()[static_cast<std::size_t>(-1 - w.partner)].name << "'";
    os << ". Likely cause: the normal spring is too soft to stop the particle within its radius at this impact "
          "speed (raise kn), or the time step is too large";
    cause(os);
    throw SimulationError(os.str());
  }
}

void Simulation::run(const std::function<void(const Simulation&)>& observer, const std::function<bool()>& stop) {
  if (observer && !restarted_) observer(*this);
  while (steps_ < total_steps_) {
    step();
    if (observer) observer(*this);
    if (stop && stop()) break;
  }
}

void Simulation::save_state(OutArchive& a) const {
  const ParticleStore& p = particles_;
  a.put(static_cast<std::uint64_t>(p.size()));
  a.put(steps_);
  a.put(time_);
  a.put(static_cast<std::uint8_t>(forces_valid_));
  a.put(p.x); a.put(p.y); a.put(p.z);
  a.put(p.vx); a.put(p.vy); a.put(p.vz);
  a.put(p.fx); a.put(p.fy); a.put(p.fz);
  a.put(p.wx); a.put(p.wy); a.put(p.wz);
  a.put(p.tx); a.put(p.ty); a.put(p.tz);
  a.put(static_cast<std::uint64_t>(modules_.size()));
  for (const auto& m : modules_) {
    a.put(m->name());
    m->save_state(a);
  }
}

void Simulation::load_state(InArchive& a) {
  ParticleStore& p = particles_;
  const std::uint64_t n0 = p.size();
  std::uint64_t n = 0;
  a.get(n);
  if (n != n0)
    throw ArchiveError("it holds " + std::to_string(n) + " particles, the scene " + std::to_string(n0));
  std::uint64_t steps = 0;
  double time = 0.0;
  std::uint8_t fv = 0;
  a.get(steps); a.get(time); a.get(fv);
  auto arr = [&](std::vector<double>& v, std::size_t want) {
    a.get(v, want);
    if (v.size() != want) throw ArchiveError("a particle array has the wrong length");
  };
  const std::size_t nr = p.has_rotation() ? n0 : 0;
  for (auto* v : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz}) arr(*v, n0);
  for (auto* v : {&p.wx, &p.wy, &p.wz, &p.tx, &p.ty, &p.tz}) arr(*v, nr);
  std::uint64_t nm = 0;
  a.get(nm);
  if (nm != modules_.size()) throw ArchiveError("its modules differ from the scene's");
  for (auto& m : modules_) {
    std::string name;
    a.get(name);
    if (name != m->name()) throw ArchiveError("it has module '" + name + "' where the scene has '" + m->name() + "'");
    m->load_state(a);
  }
  if (!a.done()) throw ArchiveError("it has data after the last module");
  if (steps > total_steps_ || !std::isfinite(time))
    throw ArchiveError("its step count " + std::to_string(steps) + " is beyond the scene's " + std::to_string(total_steps_));
  steps_ = steps;
  time_ = time;
  forces_valid_ = fv != 0;
  restarted_ = true;
}

}  // namespace cdm
