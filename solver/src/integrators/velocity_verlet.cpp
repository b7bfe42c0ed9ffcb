#include "cdm/solver/integrators/velocity_verlet.hpp"

#include <algorithm>
#include <limits>

#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/own_particles.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/rank_split.hpp"
#include "cdm/solver/slot_pages.hpp"
#include "verlet_kernels.hpp"

namespace cdm::integrators {

using verlet::VerletArrays;

namespace {
/// Whether the final kick of a step can wait for the next step's pass: nothing may read
/// the particles' velocities or impulses between a step's force evaluation and its final
/// kick. With a gas the reaction is then deposited only at the gas step (which completes
/// the step first), not after every step.
bool can_defer(const SceneSpec& s, bool gas) {
  if (!gas) return true;
  return !(s.two_way && !s.implicit_gas_drag && s.drag_evaluation == coupling::DragEvaluation::every_step);
}

/// verlet_pass's kick for the scene's drag.
verlet::DragKick drag_kick(const SceneSpec& s, bool gas) {
  if (!gas || !s.drag) return verlet::DragKick::none;
  if (s.drag_update == coupling::DragUpdate::implicit)
    return s.two_way ? verlet::DragKick::implicit_impulse : verlet::DragKick::implicit;
  if (s.drag_update == coupling::DragUpdate::exponential)
    return s.two_way ? verlet::DragKick::exponential_impulse : verlet::DragKick::exponential;
  return s.two_way ? verlet::DragKick::explicit_impulse : verlet::DragKick::none;
}
}  // namespace

VelocityVerlet::VelocityVerlet(const IntegratorParts& parts)
    : p_(parts.particles), gas_(parts.gas), contact_(parts.contact), dt_(parts.spec.dt),
      box_(parts.spec.periodic), g_(parts.spec.g), gravity_(parts.gravity),
      deferred_(can_defer(parts.spec, parts.gas != nullptr)),
      drag_kick_(static_cast<int>(drag_kick(parts.spec, parts.gas != nullptr))),
      kick_(parts.particles, parts.spec.drag_update) {
  // The contacts move positions with the half-step velocities.
  if (contact_) contact_->set_step_velocities({&hvx_, &hvy_, &hvz_, &hwx_, &hwy_, &hwz_});
}

double VelocityVerlet::final_kick() {
  ParticleStore& p = p_;
  const bool rot = p.has_rotation();
  const double h = 0.5 * dt_;
  const VerletArrays a = verlet::verlet_arrays(p, hvx_, hvy_, hvz_, hwx_, hwy_, hwz_);
  const Kick& kick = kick_;
  auto one = [&](std::size_t i) {
    Vec3 v, w;
    verlet::verlet_final_velocity(a, rot, i, h, kick, v, w);
    p.vx[i] = v.x; p.vy[i] = v.y; p.vz[i] = v.z;
    if (rot) { p.wx[i] = w.x; p.wy[i] = w.y; p.wz[i] = w.z; }
    return verlet::verlet_state_finite(a, rot, i, v, w) ? 0.0 : 1.0;
  };
  return max_own(ranks_, p.size(), one);
}

void VelocityVerlet::set_ranks(RankSplit* ranks) {
  ranks_ = ranks;
  ranks->set_extra_arrays({&hvx_, &hvy_, &hvz_, &hwx_, &hwy_, &hwz_});
}

double VelocityVerlet::complete() {
  if (!kick_pending_) return 0.0;
  kick_pending_ = false;
  if (ranks_) ranks_->mark_stale(p_);  // this rank's particles move on
  return final_kick();
}

double VelocityVerlet::step(StepHost& host, StepTimes times) {
  ParticleStore& p = p_;
  const std::size_t n = p.size();
  const double dt = dt_;
  const bool rot = p.has_rotation();
  host.ensure_forces();
  // This rank's particles move on: a gather since the last step (a gas step, an output)
  // no longer holds, and a build at this step must gather again.
  if (ranks_) ranks_->mark_stale(p_);
  for (auto* h : {&hvx_, &hvy_, &hvz_}) resize_zeroed(*h, n);
  if (rot)
    for (auto* h : {&hwx_, &hwy_, &hwz_}) resize_zeroed(*h, n);
  if (deferred_) return step_deferred(host, times);
  const PeriodicBox box = box_;
  const VerletArrays a = verlet::verlet_arrays(p, hvx_, hvy_, hvz_, hwx_, hwy_, hwz_);
  const Kick& kick = kick_;
  auto first_half = [&](std::size_t i) {
    verlet::verlet_first_half(a, rot, false, false, box, dt, i, p.velocity(i), p.angular_velocity(i), kick);
  };
  for_own(ranks_, n, first_half);
  wrap_positions(p, box_, ranks_);
  if (gas_) gas_->set_time(times.t_new);
  host.compute_forces(times.t_new, ForceStart::zeroed);
  return final_kick();
}

double VelocityVerlet::step_deferred(StepHost& host, StepTimes times) {
  ParticleStore& p = p_;
  const std::size_t n = p.size();
  const double dt = dt_;
  const bool rot = p.has_rotation();
  const bool pending = kick_pending_;
  const PeriodicBox box = box_;  // a local copy: the stores below cannot alias it
  const bool wrap = box.any();
  VerletArrays a = verlet::verlet_arrays(p, hvx_, hvy_, hvz_, hwx_, hwy_, hwz_);
  // The state at t, completed where the last step's final kick is pending, is checked
  // here (as complete() lets the simulation check it) before this step moves on from
  // it. The same pass measures how far the particles have moved since the contact list
  // was built (as ContactModule would in a pass of its own). One reduction carries
  // both: the squared displacement, or +inf for a state that is not finite. The kick is
  // the plain one, or with a drag the one Kick gives (verlet_pass's DragKick).
  // The displacement is measured exactly (reading the build positions) only when the
  // module's bound on it nears half the skin; otherwise the pass returns this step's
  // largest drift, which the module adds to that bound.
  constexpr double not_finite = std::numeric_limits<double>::infinity();
  const bool listed = contact_ && contact_->list().listed(n);
  const bool measure = listed && contact_->list().displacement_needed();
  if (measure) {
    a.x0 = contact_->list().build_positions(0); a.y0 = contact_->list().build_positions(1); a.z0 = contact_->list().build_positions(2);
  }
  // With gravity the pass sets the forces to the weight instead of zeroing them,
  // sparing the gravity module a pass over masses and forces.
  const bool grav = gravity_;
  if (grav) {
    a.mass = p.mass.data();
    a.g = g_;
  }
  // A bed of one kind of particle: its mass, 1/m and 1/I once, not per particle.
  // Among MPI processes, of this process's own particles (it holds no others' masses),
  // found again whenever they change.
  if (ranks_ && one_for_ != ranks_->ownership_changes()) one_mass_ = -1;
  if (one_mass_ < 0) {
    const std::vector<std::pair<std::uint32_t, std::uint32_t>> all{{0, static_cast<std::uint32_t>(n)}};
    const auto& runs = ranks_ ? ranks_->own_runs(n) : all;
    if (ranks_) one_for_ = ranks_->ownership_changes();
    const auto held = std::find_if(runs.begin(), runs.end(), [](const auto& r) { return r.first < r.second; });
    one_mass_ = held != runs.end() && p.same_mass(runs) ? 1 : 0;
    if (one_mass_ == 1) {
      const std::size_t i = held->first;
      one_values_ = {p.mass[i], p.inv_mass[i], rot ? p.inv_inertia[i] : 0.0};
    }
  }
  const bool one = one_mass_ == 1;
  if (one) {
    a.one_mass = one_values_[0];
    a.one_inv_mass = one_values_[1];
    a.one_inv_inertia = one_values_[2];
  }
  // The drag's share of the kicks (the kick Kick would give, DragKick).
  const auto dk = static_cast<verlet::DragKick>(drag_kick_);
  if (verlet::relaxed_kick(dk)) {
    a.drag_k = p.drag_k.data();
    a.ug[0] = p.ugx.data(); a.ug[1] = p.ugy.data(); a.ug[2] = p.ugz.data();
    a.mass = p.mass.data();
  }
  if (verlet::exact_kick(dk)) {
    // φ kept per slot with the λ it belongs to; a slot whose particle changed (a sort,
    // a migration, an insertion) holds some other λ, or NaN, and gets its φ computed.
    if (phi_.size() != n) {
      phi_.resize(n);
      phi_lam_.resize(n, std::numeric_limits<double>::quiet_NaN());
    }
    a.phi = phi_.data();
    a.phi_lam = phi_lam_.data();
  }
  if (dk == verlet::DragKick::explicit_impulse) { a.df[0] = p.dfx.data(); a.df[1] = p.dfy.data(); a.df[2] = p.dfz.data(); }
  if (verlet::impulse_kick(dk)) {
    a.j[0] = p.jx.data(); a.j[1] = p.jy.data(); a.j[2] = p.jz.data();
  }
  // One contiguous range per thread, about the particles whose forces the same
  // thread's part of the pair loop wrote (VerletList::thread_slabs).
  auto pass = [&](std::size_t i0, std::size_t i1) {
    return verlet::with_drag_kick(dk, [&]<verlet::DragKick D>() {
      return verlet::with_flags([&]<bool Pending, bool Rot, bool Wrap, bool Measure, bool Grav, bool One>() {
        return verlet::verlet_pass<Pending, Rot, Wrap, Measure, Grav, One, D>(a, box, dt, i0, i1);
      }, pending, rot, wrap, measure, grav, one);
    });
  };
  double worst = 0.0;
  if (!ranks_) {
    worst = parallel_max_ranges(n, pass);
  } else {  // this rank's particles; the largest drift (or not finite) over all ranks
    for (const auto& run : ranks_->own_runs(p.size())) {
      const std::size_t r0 = run.first, r1 = run.second;  // not bindings: clang cannot capture them
      worst = std::max(worst, parallel_max_ranges(r1 - r0, [&](std::size_t i0, std::size_t i1) {
                         return pass(r0 + i0, r0 + i1);
                       }));
    }
    worst = ranks_->max(worst);
  }
  kick_pending_ = false;
  if (worst == not_finite) host.fail_not_finite();  // names the state at t (the clock is still at t)
  if (measure) contact_->list().set_displacement(worst);
  else if (listed) contact_->list().add_drift(worst);
  if (gas_) gas_->set_time(times.t_new);
  host.compute_forces(times.t_new, grav ? ForceStart::weight : ForceStart::zeroed);
  kick_pending_ = true;
  return 0.0;  // checked when the step is completed (complete(), or the next step)
}

void VelocityVerlet::permute(const std::vector<std::uint32_t>& from) {
  permute_arrays({&hvx_, &hvy_, &hvz_, &hwx_, &hwy_, &hwz_}, p_.size(), from);
}

}  // namespace cdm::integrators
