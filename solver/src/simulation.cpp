#include "cdm/solver/simulation.hpp"

#include "cdm/solver/contact/rolling_resistance_module.hpp"
#include "cdm/solver/gravity_module.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/scene_loader.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <new>
#include <numbers>
#include <sstream>
#include <utility>

#include <sys/mman.h>

namespace cdm {

Simulation::Simulation(SceneSpec spec) : spec_(std::move(spec)) {
  // Build only the modules the scene names. Rotation exists only with a module that
  // makes torque (friction, rolling resistance).
  if (spec_.tangential != TangentialModel::none || spec_.rolling != RollingModel::none) particles_.enable_rotation();
  for (const auto& ps : spec_.particles) {
    const Material& mat = spec_.materials[ps.material];
    particles_.add(ps.position, ps.velocity, ps.radius, mat.density, ps.material, mat.fixed);
    particles_.set_angular_velocity(particles_.size() - 1, ps.angular_velocity);
  }
  if (spec_.gas != GasModel::none) build_gas();
  if (spec_.gravity) {
    modules_.push_back(std::make_unique<GravityModule>(spec_.g));
    gravity_ = modules_.back().get();
  }
  if (spec_.normal_contact) {
    const bool rolling = spec_.rolling == RollingModel::constant_torque;
    auto c = std::make_unique<ContactModule>(spec_.pairs, spec_.walls,
                                             spec_.tangential == TangentialModel::spring_coulomb, spec_.verlet_skin, rolling);
    contact_ = c.get();
    contact_->set_periodic_box(spec_.periodic);
    // Velocity Verlet moves positions with its half-step velocities (hv, hw below).
    if (spec_.integrator == IntegratorScheme::velocity_verlet)
      contact_->set_step_velocities({&hvx_, &hvy_, &hvz_, &hwx_, &hwy_, &hwz_});
    modules_.push_back(std::move(c));
    // Rolling resistance acts through the contacts just evaluated, so it runs after them.
    if (rolling) modules_.push_back(std::make_unique<RollingResistanceModule>(*contact_));
  }
  if (spec_.drag) {
    if (spec_.drag_update != coupling::DragUpdate::explicit_force) particles_.enable_drag_relaxation();
    auto d = std::make_unique<coupling::DragModule>(*gas_, *spec_.drag, spec_.drag_update, spec_.drag_void_fraction,
                                                    spec_.coupling_method, deposition_.get(), spec_.two_way,
                                                    spec_.gas_velocity);
    if (spec_.gas_velocity == coupling::SlipVelocity::superficial) gas_->enable_superficial_velocity();
    drag_ = d.get();
    modules_.push_back(std::move(d));
  }
  if (spec_.pressure_gradient) modules_.push_back(std::make_unique<coupling::PressureGradientModule>(*gas_));
  if (spec_.tracers)  // a tracer moves with the gas from the start
    for (std::size_t i = 0; i < particles_.size(); ++i) {
      const Vec3 u = gas_->velocity_at(particles_.position(i));
      particles_.vx[i] = u.x; particles_.vy[i] = u.y; particles_.vz[i] = u.z;
    }
  total_steps_ = static_cast<std::uint64_t>(std::ceil(spec_.end_time / spec_.dt - 1e-9));
  // Without a gas nothing reads the particles' velocities between a step's force
  // evaluation and its final kick, so that kick can wait for the next step (step()).
  deferred_kick_ = spec_.integrator == IntegratorScheme::velocity_verlet && !gas_;
  // The particles live in the store now; the scene keeps only where they came from.
  spec_.particles.clear();
  spec_.particles.shrink_to_fit();
}

std::vector<std::string> Simulation::module_names() const {
  std::vector<std::string> names;
  for (const auto& m : modules_) names.push_back(m->name());
  return names;
}

void Simulation::sort_if_due() {
  // At a Verlet-list rebuild (the list is built anew from the sorted order anyway), at
  // most every sort_interval steps, and at the first build.
  if (!spec_.sort_interval || !contact_) return;
  ParticleStore& p = particles_;
  if (!p.id.empty() && steps_ - last_sort_ < spec_.sort_interval) return;
  if (!contact_->rebuild_due(p)) return;
  const std::vector<std::uint32_t> from = contact_->spatial_order(p);
  permute(from);
  last_sort_ = steps_;
}

void Simulation::permute(const std::vector<std::uint32_t>& from) {
  const std::size_t n = particles_.size();
  particles_.permute(from);
  // The integrators' per-particle arrays, where a step is under way.
  std::vector<double> tmp;
  for (auto* v : {&hvx_, &hvy_, &hvz_, &hwx_, &hwy_, &hwz_, &x0_, &y0_, &z0_, &kx_, &ky_, &kz_})
    if (v->size() == n) permute_array(*v, from, tmp);
  for (auto& m : modules_) m->permute(from);
}

void Simulation::compute_forces() {
  sort_if_due();
  if (!forces_zeroed_) particles_.clear_forces();  // else the integrator zeroed them as it read them
  // Where the integrator set the forces to m g instead, gravity has been applied.
  const ForceModule* applied = forces_hold_gravity_ ? gravity_ : nullptr;
  forces_zeroed_ = false;
  forces_hold_gravity_ = false;
  for (auto& m : modules_)
    if (m.get() != applied) m->add_forces(particles_, spec_.dt);
  forces_valid_ = true;
}

namespace {

/// The kick without a drag: v += τ/m F. Simulation::kick's common part, and the whole
/// kick of velocity Verlet's one pass per step (no gas, so no drag).
struct PlainKick {
  const double *inv_mass, *fx, *fy, *fz;
  void operator()(std::size_t i, double tau, double& vx, double& vy, double& vz, bool /*impulse*/ = true) const {
    const double a = tau * inv_mass[i];
    vx += a * fx[i]; vy += a * fy[i]; vz += a * fz[i];
  }
};

}  // namespace

inline void Simulation::kick(std::size_t i, double tau, double& vx, double& vy, double& vz, bool impulse) const {
  // Inline, the drag relaxation apart: as a call (its results passed through memory)
  // it took a third of the time of velocity Verlet's passes on the settle benchmark.
  ParticleStore& p = particles_;
  if (p.has_drag_relaxation()) {
    kick_relaxed(i, tau, vx, vy, vz, impulse);
    return;
  }
  PlainKick{p.inv_mass.data(), p.fx.data(), p.fy.data(), p.fz.data()}(i, tau, vx, vy, vz);
  if (impulse && p.has_two_way()) {  // the explicit drag's share of the kick
    p.jx[i] += tau * p.dfx[i]; p.jy[i] += tau * p.dfy[i]; p.jz[i] += tau * p.dfz[i];
  }
}

void Simulation::kick_relaxed(std::size_t i, double tau, double& vx, double& vy, double& vz, bool impulse) const {
  ParticleStore& p = particles_;
  const double im = p.inv_mass[i];
  const double ax = im * p.fx[i], ay = im * p.fy[i], az = im * p.fz[i];
  const double v0x = vx, v0y = vy, v0z = vz;
  // dv/dt = a + λ (u_g − v), λ = K/m, over tau with a, λ, u_g frozen.
  const double lam = im * p.drag_k[i];
  if (spec_.drag_update == coupling::DragUpdate::implicit) {
    // Backward Euler: v' = (v + τ(a + λ u_g)) / (1 + λτ).
    const double c = 1.0 / (1.0 + lam * tau);
    vx = c * (vx + tau * (ax + lam * p.ugx[i]));
    vy = c * (vy + tau * (ay + lam * p.ugy[i]));
    vz = c * (vz + tau * (az + lam * p.ugz[i]));
  } else {
    // Exact: v' = v + (a + λ(u_g − v)) φ, φ = (1 − e^(−λτ))/λ (→ τ as λ → 0).
    const double phi = lam * tau > 1e-12 ? -std::expm1(-lam * tau) / lam : tau;
    vx += phi * (ax + lam * (p.ugx[i] - vx));
    vy += phi * (ay + lam * (p.ugy[i] - vy));
    vz += phi * (az + lam * (p.ugz[i] - vz));
  }
  if (impulse && p.has_two_way()) {  // drag impulse = m Δv − τ F (F holds the other forces)
    const double m = p.mass[i];
    p.jx[i] += m * (vx - v0x) - tau * p.fx[i];
    p.jy[i] += m * (vy - v0y) - tau * p.fy[i];
    p.jz[i] += m * (vz - v0z) - tau * p.fz[i];
  }
}

void Simulation::wrap_positions() {
  const PeriodicBox& box = spec_.periodic;
  if (!box.any()) return;
  ParticleStore& p = particles_;
  parallel_for(p.size(), [&](std::size_t i) {
    p.x[i] = box.wrap(p.x[i], 0);
    p.y[i] = box.wrap(p.y[i], 1);
    p.z[i] = box.wrap(p.z[i], 2);
  });
}

void Simulation::step_tracers() {
  // Massless tracers: dX/dt = u_g(X, t), the gas velocity interpolated to the tracer,
  // by the midpoint rule (rk2) or the classical fourth-order Runge–Kutta (rk4).
  ParticleStore& p = particles_;
  const std::size_t n = p.size();
  const double h = spec_.dt, t = time_;
  x0_ = p.x; y0_ = p.y; z0_ = p.z;
  kx_.assign(n, 0.0); ky_.assign(n, 0.0); kz_.assign(n, 0.0);
  // Velocity at time ts of the point X0 + c·k_prev; adds weight·k to the sum.
  auto stage = [&](double ts, double c, double weight) {
    gas_->set_time(ts);
    parallel_for(n, [&](std::size_t i) {
      const Vec3 x = gas_->wrap({x0_[i] + c * p.vx[i], y0_[i] + c * p.vy[i], z0_[i] + c * p.vz[i]});
      const Vec3 k = gas_->velocity_at(x);
      p.vx[i] = k.x; p.vy[i] = k.y; p.vz[i] = k.z;  // the stage slope, kept for the next stage
      kx_[i] += weight * k.x; ky_[i] += weight * k.y; kz_[i] += weight * k.z;
    });
  };
  // p.v holds the previous stage's slope; the first stage evaluates at X0 (c = 0).
  if (spec_.integrator == IntegratorScheme::rk2) {
    stage(t, 0.0, 0.0);
    stage(t + 0.5 * h, 0.5 * h, 1.0);
  } else {
    stage(t, 0.0, 1.0 / 6.0);
    stage(t + 0.5 * h, 0.5 * h, 2.0 / 6.0);
    stage(t + 0.5 * h, 0.5 * h, 2.0 / 6.0);
    stage(t + h, h, 1.0 / 6.0);
  }
  parallel_for(n, [&](std::size_t i) {
    p.x[i] = x0_[i] + h * kx_[i]; p.y[i] = y0_[i] + h * ky_[i]; p.z[i] = z0_[i] + h * kz_[i];
  });
  wrap_positions();
  // The tracers' velocity is the gas velocity where they are now.
  gas_->set_time(t + h);
  parallel_for(n, [&](std::size_t i) {
    const Vec3 u = gas_->velocity_at(p.position(i));
    p.vx[i] = u.x; p.vy[i] = u.y; p.vz[i] = u.z;
  });
}

namespace {

/// The arrays velocity Verlet reads and writes per particle, as raw pointers: through
/// the store's vectors the compiler kept reloading them, and the per-particle work of
/// the one pass per step was two calls with their arguments passed through memory.
struct VerletArrays {
  double *x, *y, *z, *vx, *vy, *vz, *fx, *fy, *fz, *hvx, *hvy, *hvz;
  double *wx, *wy, *wz, *tx, *ty, *tz, *hwx, *hwy, *hwz;  // with rotation only
  const double *inv_mass, *inv_inertia;
  const double *x0 = nullptr, *y0 = nullptr, *z0 = nullptr;  // the contact list's build positions
  const double* mass = nullptr;  // with gravity applied in the pass
  Vec3 g{};                      // [m/s^2], with gravity applied in the pass
  // Where every particle has the same 1/m, 1/I and m (bit for bit): those values, which
  // verlet_pass then reads instead of three arrays (24 of its 360 bytes per particle).
  double one_inv_mass = 0.0, one_inv_inertia = 0.0, one_mass = 0.0;
};

VerletArrays verlet_arrays(ParticleStore& p, std::vector<double>& hvx, std::vector<double>& hvy,
                           std::vector<double>& hvz, std::vector<double>& hwx, std::vector<double>& hwy,
                           std::vector<double>& hwz) {
  return {p.x.data(),  p.y.data(),  p.z.data(),  p.vx.data(), p.vy.data(), p.vz.data(), p.fx.data(),
          p.fy.data(), p.fz.data(), hvx.data(),  hvy.data(),  hvz.data(),  p.wx.data(), p.wy.data(),
          p.wz.data(), p.tx.data(), p.ty.data(), p.tz.data(), hwx.data(),  hwy.data(),  hwz.data(),
          p.inv_mass.data(), p.inv_inertia.data()};
}

// Velocity Verlet per particle, for the two passes with a gas and the final kick (the
// one pass per step without a gas, verlet_pass, does the same arithmetic axis by axis);
// inline always, so that @p rot and @p wrap fold away where they are constants. @p kick
// is Simulation::kick.

/// The final half kick of particle i: its velocity @p v and spin @p w (set only with
/// @p rot) at the new time, from the half-step ones and the forces.
template <class Kick>
[[gnu::always_inline]] inline void verlet_final_velocity(const VerletArrays& a, bool rot, std::size_t i, double h,
                                                         const Kick& kick, Vec3& v, Vec3& w) {
  v = {a.hvx[i], a.hvy[i], a.hvz[i]};
  kick(i, h, v.x, v.y, v.z, true);
  if (!rot) return;
  const double b = h * a.inv_inertia[i];
  w = {a.hwx[i] + b * a.tx[i], a.hwy[i] + b * a.ty[i], a.hwz[i] + b * a.tz[i]};
}

/// Whether particle i's position and its velocity @p v and spin @p w (read only with
/// @p rot) are all finite. One test for all: a sum of finite values is finite (short of
/// overflow, itself a blow-up).
[[gnu::always_inline]] inline bool verlet_state_finite(const VerletArrays& a, bool rot, std::size_t i, Vec3 v, Vec3 w) {
  const double sum = a.x[i] + a.y[i] + a.z[i] + v.x + v.y + v.z;
  return std::isfinite(rot ? sum + (w.x + w.y + w.z) : sum);
}

/// The first half of a step for particle i, from its velocity @p v and spin @p w at t:
/// half kick, drift (wrapped into @p box if @p wrap), the predicted velocity and spin
/// v(t) + Δt a(t) for the velocity-dependent forces, and the forces and torques zeroed
/// once read; with @p grav the forces are set to the weight m g instead (the gravity
/// module's arithmetic on zeroed forces, 0 + m g, so the same to the bit).
template <class Kick>
[[gnu::always_inline]] inline void verlet_first_half(const VerletArrays& a, bool rot, bool wrap, bool grav,
                                                     const PeriodicBox& box, double dt, std::size_t i, Vec3 v, Vec3 w,
                                                     const Kick& kick) {
  const double h = 0.5 * dt;
  kick(i, h, v.x, v.y, v.z, true);
  a.hvx[i] = v.x; a.hvy[i] = v.y; a.hvz[i] = v.z;
  double x = a.x[i] + dt * v.x, y = a.y[i] + dt * v.y, z = a.z[i] + dt * v.z;
  if (wrap) { x = box.wrap(x, 0); y = box.wrap(y, 1); z = box.wrap(z, 2); }
  a.x[i] = x; a.y[i] = y; a.z[i] = z;
  kick(i, h, v.x, v.y, v.z, false);  // predicted v(t+Δt)
  a.vx[i] = v.x; a.vy[i] = v.y; a.vz[i] = v.z;
  if (grav) {
    const double m = a.mass[i];
    a.fx[i] = 0.0 + m * a.g.x; a.fy[i] = 0.0 + m * a.g.y; a.fz[i] = 0.0 + m * a.g.z;
  } else {
    a.fx[i] = 0.0; a.fy[i] = 0.0; a.fz[i] = 0.0;
  }
  if (rot) {
    const double b = h * a.inv_inertia[i];
    a.hwx[i] = w.x + b * a.tx[i]; a.hwy[i] = w.y + b * a.ty[i]; a.hwz[i] = w.z + b * a.tz[i];
    a.wx[i] = a.hwx[i] + b * a.tx[i]; a.wy[i] = a.hwy[i] + b * a.ty[i]; a.wz[i] = a.hwz[i] + b * a.tz[i];
    a.tx[i] = 0.0; a.ty[i] = 0.0; a.tz[i] = 0.0;
  }
}

/// f.template operator()<b...>() for the run-time flags @p b...: one instantiation per
/// combination, chosen once per call (for loops that test the flags per particle).
template <bool... Fixed, class F>
decltype(auto) with_flags(F&& f) {
  return f.template operator()<Fixed...>();
}
template <bool... Fixed, class F, class... Rest>
decltype(auto) with_flags(F&& f, bool b, Rest... rest) {
  return b ? with_flags<Fixed..., true>(f, rest...) : with_flags<Fixed..., false>(f, rest...);
}

/// One axis of the one pass per step (verlet_pass) for particles [i0, i1): for axis @p A
/// of position @p X, predicted velocity @p V, force @p F and half-step velocity @p HV,
/// the final kick of the last step if @p Pending, the half kick, drift (wrapped with
/// @p Wrap), predicted velocity, and the force set to the weight's component m @p g
/// (with @p Grav) or zeroed. Particle i's term of the squared displacement since the
/// build (@p Measure, from @p X0) or of this step's drift goes to @p d2[i - i0], set by
/// the first axis (@p First) and added to by the others, so d2 sums x² + y² + z² in the
/// order a single expression would. The same sum carries the finiteness check of the
/// state at t: each term comes with s − s for s = x + v at t, +0 where s is finite (the
/// sum unchanged, to the bit) and NaN where it is not. With @p One every particle has
/// VerletArrays' one_inv_mass and one_mass.
template <int A, bool First, bool Pending, bool Wrap, bool Measure, bool Grav, bool One>
[[gnu::always_inline]] inline void verlet_axis(const VerletArrays& a, double* __restrict X, double* __restrict V,
                                               double* __restrict F, double* __restrict HV,
                                               const double* __restrict X0, double g, const PeriodicBox& box, double dt,
                                               std::size_t i0, std::size_t i1, double* __restrict d2) {
  const double h = 0.5 * dt;
  const double* __restrict const IM = a.inv_mass;
  const double* __restrict const M = a.mass;
  for (std::size_t i = i0; i < i1; ++i) {
    const double c = h * (One ? a.one_inv_mass : IM[i]);  // PlainKick's factor
    const double f = F[i];
    double v = Pending ? HV[i] + c * f : V[i];  // v(t)
    const double s = X[i] + v;
    v += c * f;  // half kick
    HV[i] = v;
    double x = X[i] + dt * v;
    if constexpr (Wrap) x = box.wrap(x, A);
    X[i] = x;
    V[i] = v + c * f;  // predicted v(t+Δt)
    F[i] = Grav ? 0.0 + (One ? a.one_mass : M[i]) * g : 0.0;
    const double e = Measure ? box.min_image(x - X0[i], A) : dt * v;
    // A NaN e (a NaN force met this step) is left out: it says nothing of the state at t,
    // which is what this pass checks. The new state is checked at the next check, which
    // names the step that reached it.
    const double ee = e * e;
    const double term = (ee >= 0.0 ? ee : 0.0) + (s - s);
    d2[i - i0] = First ? term : d2[i - i0] + term;
  }
}

/// One axis of the spin in verlet_pass: the final kick of the last step if @p Pending,
/// the half kick and the predicted spin, the torque zeroed; w − w for the spin w at t
/// added to @p d2 (+0, or NaN where w is not finite: verlet_axis).
/// With @p One every particle has VerletArrays' one_inv_inertia.
template <bool Pending, bool One>
[[gnu::always_inline]] inline void verlet_spin_axis(const VerletArrays& a, double* __restrict W, double* __restrict T,
                                                    double* __restrict HW, double dt, std::size_t i0, std::size_t i1,
                                                    double* __restrict d2) {
  const double h = 0.5 * dt;
  const double* __restrict const II = a.inv_inertia;
  for (std::size_t i = i0; i < i1; ++i) {
    const double b = h * (One ? a.one_inv_inertia : II[i]);
    const double t = T[i];
    const double w = Pending ? HW[i] + b * t : W[i];  // ω(t)
    d2[i - i0] += w - w;
    const double hw = w + b * t;
    HW[i] = hw;
    W[i] = hw + b * t;
    T[i] = 0.0;
  }
}

/// The calling thread's scratch for verlet_pass, at least @p n doubles, kept between
/// steps. Not on the stack (a block's is 256 KiB, much for an OpenMP worker's) nor from
/// malloc: a long-lived block there kept the heap from giving back what the list
/// rebuilds freed below it (settle1e5's peak RSS 74.6 against 70.6 MB before; mapped on
/// its own, 71.2 MB).
double* pass_scratch(std::size_t n) {
  struct Mapping {
    void* p = nullptr;
    std::size_t bytes = 0;
    ~Mapping() {
      if (p) munmap(p, bytes);
    }
  };
  thread_local Mapping m;
  const std::size_t bytes = n * sizeof(double);
  if (m.bytes < bytes) {
    if (m.p) munmap(m.p, m.bytes);
    m = {};
    void* const p = mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) throw std::bad_alloc();
    m.p = p;
    m.bytes = bytes;
  }
  return static_cast<double*>(m.p);
}

/// Particles [i0, i1) of the one pass per step without a gas (Simulation::step): the
/// state at t, completed by the last step's final kick if @p Pending, checked for
/// finite values, then the first half of the step (the forces set to the weight with
/// @p Grav). Returns the largest squared displacement since the contact list's build
/// (with @p Measure; else the largest squared drift of this step), or +inf if some
/// particle's state at t was not finite.
///
/// The arithmetic per particle is verlet_final_velocity's and verlet_first_half's, to
/// the bit, but done one axis at a time over blocks of particles: a loop over all 24
/// arrays at once ran at half the speed the same traffic gets in loops over 4 to 6
/// arrays each (bench/pass_probe, layouts soa and soa-axis). The blocks are long: each
/// of the six loops per block starts four new streams, and in DRAM (1e5 particles and
/// up) a stream's first lines cost more than the rest; blocks of 32768 particles instead
/// of 2048 took 12 % off settle1e6's step on one thread (bench/README.md, session 16).
/// The finiteness test asks each of x + v_x, y + v_y, z + v_z and the spin's components
/// at t to be finite (through the squared displacement, verlet_axis), where
/// verlet_state_finite asks their sum: the same answer short of overflow (itself a
/// blow-up).
template <bool Pending, bool Rot, bool Wrap, bool Measure, bool Grav, bool One>
double verlet_pass(const VerletArrays& a, const PeriodicBox& box, double dt, std::size_t i0, std::size_t i1) {
  constexpr std::size_t block = 32768;
  // Each particle's squared displacement (NaN if its state is not finite), per block.
  double* const d2 = pass_scratch(std::min(block, i1 - i0));
  double worst = 0.0;
  for (std::size_t b0 = i0; b0 < i1; b0 += block) {
    const std::size_t b1 = std::min(i1, b0 + block);
    verlet_axis<0, true, Pending, Wrap, Measure, Grav, One>(a, a.x, a.vx, a.fx, a.hvx, a.x0, a.g.x, box, dt, b0, b1, d2);
    verlet_axis<1, false, Pending, Wrap, Measure, Grav, One>(a, a.y, a.vy, a.fy, a.hvy, a.y0, a.g.y, box, dt, b0, b1, d2);
    verlet_axis<2, false, Pending, Wrap, Measure, Grav, One>(a, a.z, a.vz, a.fz, a.hvz, a.z0, a.g.z, box, dt, b0, b1, d2);
    if constexpr (Rot) {
      verlet_spin_axis<Pending, One>(a, a.wx, a.tx, a.hwx, dt, b0, b1, d2);
      verlet_spin_axis<Pending, One>(a, a.wy, a.ty, a.hwy, dt, b0, b1, d2);
      verlet_spin_axis<Pending, One>(a, a.wz, a.tz, a.hwz, dt, b0, b1, d2);
    }
    for (std::size_t k = 0; k < b1 - b0; ++k)
      worst = std::max(worst, std::isfinite(d2[k]) ? d2[k] : std::numeric_limits<double>::infinity());
  }
  return worst;
}

}  // namespace

auto Simulation::kick_fn() const {
  return [this](std::size_t i, double tau, double& vx, double& vy, double& vz, bool impulse) {
    kick(i, tau, vx, vy, vz, impulse);
  };
}

double Simulation::final_kick() const {
  ParticleStore& p = particles_;
  const bool rot = p.has_rotation();
  const double h = 0.5 * spec_.dt;
  const VerletArrays a = verlet_arrays(p, hvx_, hvy_, hvz_, hwx_, hwy_, hwz_);
  const auto kick = kick_fn();
  return parallel_max(p.size(), [&](std::size_t i) {
    Vec3 v, w;
    verlet_final_velocity(a, rot, i, h, kick, v, w);
    p.vx[i] = v.x; p.vy[i] = v.y; p.vz[i] = v.z;
    if (rot) { p.wx[i] = w.x; p.wy[i] = w.y; p.wz[i] = w.z; }
    return verlet_state_finite(a, rot, i, v, w) ? 0.0 : 1.0;
  });
}

void Simulation::complete_step() const {
  if (!kick_pending_) return;
  kick_pending_ = false;
  const double bad = final_kick();
  if (bad != 0.0) check_state(1.0);
}

void Simulation::step() {
  ParticleStore& p = particles_;
  const std::size_t n = p.size();
  const double dt = spec_.dt;
  const bool rot = p.has_rotation();
  const double t_new = static_cast<double>(steps_ + 1) * dt;
  double nonfinite = -1.0;  // 1 if some particle's state is not finite, 0 if none, -1 not yet checked
  switch (spec_.integrator) {
    case IntegratorScheme::rk2:
    case IntegratorScheme::rk4:
      step_tracers();
      break;
    case IntegratorScheme::exponential_midpoint: {
      // For particles moved by drag: the exact solution of x' = v, v' = λ(u_g − v) + a
      // with u_g, λ = K/m and a = F/m frozen, taken with the coefficients of the state
      // at mid-step (found by a first half step with those of the state at t). Second
      // order in dt and unconditionally stable whatever τ_p/dt: for τ_p ≫ dt it is the
      // midpoint rule of Newton's law, for τ_p ≪ dt the midpoint rule of dx/dt = u_g
      // (+ a τ_p), where velocity Verlet with an exact drag kick falls to first order.
      if (!forces_valid_) compute_forces();
      x0_ = p.x; y0_ = p.y; z0_ = p.z;
      kx_ = p.vx; ky_ = p.vy; kz_ = p.vz;  // v(t)
      auto exact = [&](std::size_t i, double h, bool impulse) {
        // x(h) = x0 + v0 φ1 + u (h − φ1) + a φ2,  v(h) = v0 + (λ(u − v0) + a) φ1,
        // φ1 = (1 − e^(−λh))/λ, φ2 = (h − φ1)/λ (series for small λh: no cancellation).
        const double im = p.inv_mass[i], lam = im * p.drag_k[i], z = lam * h;
        double phi1, phi2;
        if (z < 1e-4) {
          phi1 = h * (1.0 - z / 2.0 + z * z / 6.0);
          phi2 = h * h * (0.5 - z / 6.0 + z * z / 24.0);
        } else {
          phi1 = -std::expm1(-z) / lam;
          phi2 = (h - phi1) / lam;
        }
        const double ax = im * p.fx[i], ay = im * p.fy[i], az = im * p.fz[i];
        p.x[i] = x0_[i] + kx_[i] * phi1 + p.ugx[i] * (h - phi1) + ax * phi2;
        p.y[i] = y0_[i] + ky_[i] * phi1 + p.ugy[i] * (h - phi1) + ay * phi2;
        p.z[i] = z0_[i] + kz_[i] * phi1 + p.ugz[i] * (h - phi1) + az * phi2;
        p.vx[i] = kx_[i] + (lam * (p.ugx[i] - kx_[i]) + ax) * phi1;
        p.vy[i] = ky_[i] + (lam * (p.ugy[i] - ky_[i]) + ay) * phi1;
        p.vz[i] = kz_[i] + (lam * (p.ugz[i] - kz_[i]) + az) * phi1;
        if (impulse && p.has_two_way()) {
          const double m = p.mass[i];
          p.jx[i] += m * (p.vx[i] - kx_[i]) - h * p.fx[i];
          p.jy[i] += m * (p.vy[i] - ky_[i]) - h * p.fy[i];
          p.jz[i] += m * (p.vz[i] - kz_[i]) - h * p.fz[i];
        }
      };
      parallel_for(n, [&](std::size_t i) { exact(i, 0.5 * dt, false); });
      wrap_positions();
      if (gas_) gas_->set_time(time_ + 0.5 * dt);
      compute_forces();  // coefficients at mid-step
      // The full step starts again from x(t), v(t) (saved above), with mid-step coefficients.
      parallel_for(n, [&](std::size_t i) { exact(i, dt, true); });
      wrap_positions();
      if (gas_) gas_->set_time(t_new);
      compute_forces();
      break;
    }
    case IntegratorScheme::paper_euler: {
      // Garg et al. (2012) eqs A.1–A.3: V += F(t)/m Δt; X += V(t+Δt) Δt; ω += T(t)/I Δt.
      // F(t) was evaluated at the end of the previous step, so the guards below always
      // see the forces and overlaps of the state just reached.
      if (!forces_valid_) compute_forces();
      parallel_for(n, [&](std::size_t i) {
        kick(i, dt, p.vx[i], p.vy[i], p.vz[i]);
        p.x[i] += dt * p.vx[i]; p.y[i] += dt * p.vy[i]; p.z[i] += dt * p.vz[i];
      });
      if (rot)
        parallel_for(n, [&](std::size_t i) {
          const double b = dt * p.inv_inertia[i];
          p.wx[i] += b * p.tx[i]; p.wy[i] += b * p.ty[i]; p.wz[i] += b * p.tz[i];
        });
      wrap_positions();
      if (gas_) gas_->set_time(t_new);
      compute_forces();
      break;
    }
    case IntegratorScheme::velocity_verlet: {
      // Velocity Verlet. The dashpot makes the force depend on the velocity being
      // updated, which drops plain Verlet to first order; the force at t+Δt is
      // evaluated with the predicted velocity v(t) + Δt a(t) (error O(Δt²) in the
      // force, O(Δt³) in the step), which keeps second order.
      // Outside the contacts the step is memory-bound, so every pass over the particles
      // saved is a stream of the whole state saved. Where nothing but the particles
      // reads the velocities between steps (no gas), the final kick of a step is left
      // pending and done in the same pass as the next step's first half (complete_step
      // does it alone when the state is read in between): one pass per step. Otherwise
      // two passes, each fused: (half kick, drift, predicted velocity and spin, then
      // the forces zeroed once read) and (final kick and spin, and the finiteness check).
      // Both orders do the same arithmetic per particle: the results are identical.
      if (!forces_valid_) compute_forces();
      hvx_.resize(n); hvy_.resize(n); hvz_.resize(n);
      if (rot) { hwx_.resize(n); hwy_.resize(n); hwz_.resize(n); }
      const bool pending = kick_pending_;
      const PeriodicBox box = spec_.periodic;  // a local copy: the stores below cannot alias it
      const bool wrap = deferred_kick_ && box.any();
      VerletArrays a = verlet_arrays(p, hvx_, hvy_, hvz_, hwx_, hwy_, hwz_);
      if (deferred_kick_) {
        // The state at t, completed where the last step's final kick is pending, is
        // checked here (as complete_step checks it) before this step moves on from it.
        // The same pass measures how far the particles have moved since the contact
        // list was built (as ContactModule would in a pass of its own). One reduction
        // carries both: the squared displacement, or +inf for a state that is not finite.
        // Without a gas there is no drag: kick() is the plain one (verlet_pass).
        // The displacement is measured exactly (reading the build positions) only when
        // the module's bound on it nears half the skin; otherwise the pass returns this
        // step's largest drift, which the module adds to that bound.
        constexpr double not_finite = std::numeric_limits<double>::infinity();
        const bool listed = contact_ && contact_->listed(n);
        const bool measure = listed && contact_->displacement_needed();
        if (measure) {
          a.x0 = contact_->build_positions(0); a.y0 = contact_->build_positions(1); a.z0 = contact_->build_positions(2);
        }
        // With gravity the pass sets the forces to the weight instead of zeroing them,
        // sparing the gravity module a pass over masses and forces.
        const bool grav = gravity_ != nullptr;
        if (grav) {
          a.mass = p.mass.data();
          a.g = spec_.g;
        }
        // A bed of one kind of particle: its mass, 1/m and 1/I once, not per particle.
        if (one_mass_ < 0) one_mass_ = p.same_mass() ? 1 : 0;
        const bool one = one_mass_ == 1 && n > 0;
        if (one) {
          a.one_inv_mass = p.inv_mass[0];
          a.one_mass = p.mass[0];
          a.one_inv_inertia = rot ? p.inv_inertia[0] : 0.0;
        }
        // One contiguous range per thread, about the particles whose forces the same
        // thread's part of the pair loop wrote (ContactModule's thread_slabs).
        const double worst = parallel_max_ranges(n, [&](std::size_t i0, std::size_t i1) {
          return with_flags([&]<bool Pending, bool Rot, bool Wrap, bool Measure, bool Grav, bool One>() {
            return verlet_pass<Pending, Rot, Wrap, Measure, Grav, One>(a, box, dt, i0, i1);
          }, pending, rot, wrap, measure, grav, one);
        });
        kick_pending_ = false;
        if (worst == not_finite) check_state(1.0);  // names the state at t (time_ is still t)
        if (measure) contact_->set_displacement(worst);
        else if (listed) contact_->add_drift(worst);
        forces_zeroed_ = true;
        forces_hold_gravity_ = grav;
        compute_forces();
        kick_pending_ = true;
        nonfinite = 0.0;  // checked when the step is completed (complete_step, or the next step)
        break;
      }
      const auto kick = kick_fn();
      parallel_for(n, [&](std::size_t i) {
        verlet_first_half(a, rot, false, false, box, dt, i, p.velocity(i), p.angular_velocity(i), kick);
      });
      forces_zeroed_ = true;
      wrap_positions();
      if (gas_) gas_->set_time(t_new);
      compute_forces();
      nonfinite = final_kick();
      break;
    }
  }
  ++steps_;
  time_ = static_cast<double>(steps_) * dt;
  check_state(nonfinite);
  if (solver_) {
    if (particles_.has_two_way()) deposit_impulses();
    if (++substep_ == substeps_) {
      substep_ = 0;
      gas_step();
    }
  }
}

void Simulation::build_gas() {
  const bool solved = spec_.gas == GasModel::solved;
  const bool grid_eps = solved || (spec_.drag && spec_.drag_void_fraction <= 0.0);
  gas_ = std::make_unique<fluid::GasField>(spec_.gas_spec, spec_.gravity ? spec_.g : Vec3{},
                                           spec_.pressure_gradient || solved, grid_eps);
  if (!solved) return;
  const fluid::StaggeredGrid& g = gas_->grid();
  // Initial gas velocity (the boundary conditions then impose theirs).
  std::fill(gas_->u.begin(), gas_->u.end(), spec_.gas_initial_velocity.x);
  std::fill(gas_->v.begin(), gas_->v.end(), spec_.gas_initial_velocity.y);
  std::fill(gas_->w.begin(), gas_->w.end(), g.two_d() ? 0.0 : spec_.gas_initial_velocity.z);
  substeps_ = static_cast<std::uint64_t>(std::llround(spec_.gas_dt / spec_.dt));
  if (spec_.two_way) {
    particles_.enable_two_way();
    const coupling::Kernel k =
        spec_.coupling_method == coupling::CouplingMethod::cell_average ? coupling::Kernel::cell : spec_.kernel;
    deposition_ = std::make_unique<coupling::Deposition>(g, k, spec_.kernel_width);
    imp_x_.assign(g.padded_size(), 0.0);
    imp_y_ = imp_z_ = imp_x_;
    // At the start nothing has run yet: a gas fraction the cells cannot represent is a
    // property of the scene (particles too large for the cells, or piled into them), so
    // it is refused as such, naming the file.
    try {
      deposit_void_fraction(gas_->eps_g);
    } catch (const SimulationError& e) {
      throw SceneError(spec_.file + ": the initial particles do not fit the gas cells: " + std::string(e.what()));
    }
  }
  gas_->mean_pressure_gradient = spec_.mean_pressure_gradient;
  solver_ = std::make_unique<fluid::GasSolver>(
      *gas_, fluid::GasSolverSpec{spec_.advection, spec_.gravity ? spec_.g : Vec3{}, spec_.mean_pressure_gradient});
}

void Simulation::deposit_void_fraction(std::vector<double>& eps) const {
  const fluid::StaggeredGrid& g = gas_->grid();
  const ParticleStore& p = particles_;
  eps.assign(g.padded_size(), 0.0);
  const double vc = g.cell_volume();
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double d = 2.0 * p.radius[i], vol = std::numbers::pi * d * d * d / 6.0 / vc;
    deposition_->for_each_weight(p.position(i), [&](std::size_t c, double w) { eps[c] += w * vol; });
  }
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
       << ") at t = " << time_ << " s. Likely cause: cells too small for the particles (a cell should hold several "
       << "particle volumes; coarsen gas.cells or widen the deposition with coupling.kernel = \"gaussian\" and a "
       << "larger coupling.kernel_width)";
    throw SimulationError(os.str());
  }
  g.fill_scalar_ghosts(eps);
}

void Simulation::deposit_impulses() {
  ParticleStore& p = particles_;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double jx = p.jx[i], jy = p.jy[i], jz = p.jz[i];
    particle_impulse_ += Vec3{jx, jy, jz};
    deposition_->for_each_weight(p.position(i), [&](std::size_t c, double w) {
      imp_x_[c] -= w * jx; imp_y_[c] -= w * jy; imp_z_[c] -= w * jz;
    });
    p.jx[i] = p.jy[i] = p.jz[i] = 0.0;
  }
}

void Simulation::gas_step() {
  fluid::GasSolver& gs = *solver_;
  const fluid::StaggeredGrid& g = gas_->grid();
  const double dtg = spec_.gas_dt;
  gs.clear_force();
  balance_ = {};
  if (particles_.has_two_way()) {
    // The drag reaction, deposited on the cells, as a force per unit volume on the faces:
    // each cell gives half to each of its two faces along the component; the share of a
    // face whose velocity is fixed (a wall or an inlet) goes to the cell's other face, so
    // the gas receives all of it.
    const double per = 1.0 / (g.cell_volume() * dtg);
    std::vector<double>* force[3] = {&gs.force_u, &gs.force_v, &gs.force_w};
    const std::vector<double>* imp[3] = {&imp_x_, &imp_y_, &imp_z_};
    Vec3 cells, faces;
    double* cc[3] = {&cells.x, &cells.y, &cells.z};
    double* fc[3] = {&faces.x, &faces.y, &faces.z};
    auto fixed_face = [&](int c, int f) {
      if (g.spec().periodic(c) || (f > 0 && f < g.n(c))) return false;
      return g.spec().faces[2 * c + (f == 0 ? 0 : 1)].kind != fluid::BoundaryKind::pressure_outlet;
    };
    for (int c = 0; c < g.dims(); ++c)
      for (int k = 0; k < g.n(2); ++k)
        for (int j = 0; j < g.n(1); ++j)
          for (int i = 0; i < g.n(0); ++i) {
            const double v = (*imp[c])[g.at(i, j, k)];
            *cc[c] += v;
            int lo[3] = {i, j, k}, hi[3] = {i, j, k};
            hi[c] += 1;
            if (g.spec().periodic(c)) hi[c] %= g.n(c);
            const bool lo_fixed = fixed_face(c, lo[c]), hi_fixed = fixed_face(c, lo[c] + 1);
            double to_lo = 0.5 * v, to_hi = 0.5 * v;
            if (lo_fixed && !hi_fixed) { to_hi = v; to_lo = 0.0; }
            if (hi_fixed && !lo_fixed) { to_lo = v; to_hi = 0.0; }
            if (lo_fixed && hi_fixed) to_lo = to_hi = 0.0;  // a single cell between walls: the walls take it
            (*force[c])[g.at(lo[0], lo[1], lo[2])] += to_lo * per;
            (*force[c])[g.at(hi[0], hi[1], hi[2])] += to_hi * per;
            *fc[c] += to_lo + to_hi;
          }
    balance_ = {particle_impulse_, cells, faces};
    particle_impulse_ = {};
    std::fill(imp_x_.begin(), imp_x_.end(), 0.0);
    std::fill(imp_y_.begin(), imp_y_.end(), 0.0);
    std::fill(imp_z_.begin(), imp_z_.end(), 0.0);
    deposit_void_fraction(eps_work_);
  } else {
    eps_work_ = gas_->eps_g;
  }
  gs.step(dtg, eps_work_);
  const double cfl = gs.max_cfl(dtg);
  bool finite = true;
  for (double x : gas_->u) finite = finite && std::isfinite(x);
  for (double x : gas_->v) finite = finite && std::isfinite(x);
  for (double x : gas_->w) finite = finite && std::isfinite(x);
  if (!finite || cfl > 1.0) {
    std::ostringstream os;
    os << "the gas " << (finite ? "velocity exceeds one cell per gas step" : "state is no longer finite") << " at t = "
       << time_ << " s (Courant number " << cfl << ", diffusion number " << gs.diffusion_number(dtg)
       << "). Likely cause: gas.dt = " << dtg << " s too large for the flow (keep |u| dt/h below 1 and "
       << "mu dt/(rho h^2) summed over the axes below 1/2"
       << (particles_.has_two_way() ? "; with two-way coupling the drag on the gas is explicit, so gas.dt must also "
                                      "stay below 2 eps_g rho_g / beta, the time the gas takes to relax to the particles' "
                                      "velocity, which dense or fine-particle regions make short"
                                    : "")
       << ")";
    throw SimulationError(os.str());
  }
}

void Simulation::check_state(double nonfinite) const {
  const ParticleStore& p = particles_;
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
      const double tp = drag_->relaxation_time_at_rest(particles_);
      const bool verlet = spec_.integrator == IntegratorScheme::velocity_verlet;
      os << ", shortest particle relaxation time at zero slip tau_p = m/K = " << tp << " s (tau_p/dt = " << tp / spec_.dt
         << "; drag update '" << coupling::to_string(spec_.drag_update) << "'";
      if (spec_.drag_update == coupling::DragUpdate::explicit_force && tp < (verlet ? 1.0 : 0.5) * spec_.dt)
        os << ": an explicit drag update is unstable for dt > " << (verlet ? "tau_p with velocity_verlet" : "2 tau_p with paper_euler")
           << ", use drag.update = \"exponential\" or \"implicit\"";
      os << ")";
    }
  };
  if (s != 0.0) {
    std::ostringstream os;
    os << "state is no longer finite at t = " << time_ << " s (step " << steps_ << "), particle(s):";
    int listed = 0;
    for (std::size_t i = 0; i < n && listed < 5; ++i) {
      const bool bad = !is_finite(p.position(i)) || !is_finite(p.velocity(i)) ||
                       (p.has_rotation() && !is_finite(p.angular_velocity(i)));
      if (bad) { os << ' ' << p.id_of(i) << " (" << particle_source(spec_, p.id_of(i)) << ')'; ++listed; }
    }
    os << ". Likely cause: a time step too large for the stiffest force";
    cause(os);
    throw SimulationError(os.str());
  }
  if (gas_) {
    // A particle must stay in the gas domain along every axis that is not periodic.
    const double out = parallel_max(n, [&](std::size_t i) { return gas_->contains(p.position(i)) ? 0.0 : 1.0; });
    if (out != 0.0) {
      std::ostringstream os;
      os << "particle(s) left the gas domain at t = " << time_ << " s (step " << steps_ << "):";
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
       << spec_.max_overlap_fraction << ") at t = " << time_ << " s (step " << steps_ << "): particle "
       << p.id_of(w.particle) << " (" << particle_source(spec_, p.id_of(w.particle)) << ") against ";
    if (w.partner >= 0) {
      const std::size_t k = p.id_of(static_cast<std::size_t>(w.partner));
      os << "particle " << k << " (" << particle_source(spec_, k) << ")";
    }
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
  complete_step();
}

void Simulation::save_state(OutArchive& a) const {
  complete_step();  // a checkpoint holds the state at time()
  const ParticleStore& p = particles_;
  a.put(static_cast<std::uint64_t>(p.size()));
  a.put(steps_);
  a.put(time_);
  a.put(static_cast<std::uint8_t>(forces_valid_));
  a.put(p.id);  // the particles' order (empty until sorted); arrays below are in it
  a.put(last_sort_);
  a.put(p.x); a.put(p.y); a.put(p.z);
  a.put(p.vx); a.put(p.vy); a.put(p.vz);
  a.put(p.fx); a.put(p.fy); a.put(p.fz);
  a.put(p.wx); a.put(p.wy); a.put(p.wz);
  a.put(p.tx); a.put(p.ty); a.put(p.tz);
  a.put(p.drag_k); a.put(p.ugx); a.put(p.ugy); a.put(p.ugz);
  a.put(p.dfx); a.put(p.dfy); a.put(p.dfz); a.put(p.jx); a.put(p.jy); a.put(p.jz);
  a.put(static_cast<std::uint64_t>(modules_.size()));
  for (const auto& m : modules_) {
    a.put(m->name());
    m->save_state(a);
  }
  // A solved gas: its fields, the solver's clock, and the exchange accumulated so far in
  // the current gas step.
  a.put(static_cast<std::uint8_t>(solver_ ? 1 : 0));
  if (solver_) {
    a.put(gas_->u); a.put(gas_->v); a.put(gas_->w); a.put(gas_->p); a.put(gas_->eps_g);
    a.put(solver_->time());
    a.put(substep_);
    a.put(imp_x_); a.put(imp_y_); a.put(imp_z_);
    a.put(particle_impulse_.x); a.put(particle_impulse_.y); a.put(particle_impulse_.z);
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
  {
    // The saved order: a permutation of the particles, or empty (never sorted).
    std::vector<std::uint32_t> id;
    a.get(id, n0);
    std::uint64_t last_sort = 0;
    a.get(last_sort);
    if (!id.empty() && id.size() != n0) throw ArchiveError("its particle order has the wrong length");
    std::vector<std::uint8_t> seen(id.size(), 0);
    for (std::uint32_t k : id) {
      if (k >= n0 || seen[k]) throw ArchiveError("its particle order is not a permutation");
      seen[k] = 1;
    }
    if (!id.empty() || !p.id.empty()) {
      // Slot s takes particle id[s] (particle s when the saved run never sorted).
      std::vector<std::uint32_t> from(n0);
      for (std::size_t s = 0; s < n0; ++s) from[s] = static_cast<std::uint32_t>(p.slot_of(id.empty() ? s : id[s]));
      permute(from);
      if (id.empty()) { p.id.clear(); p.slot.clear(); }
    }
    last_sort_ = last_sort;
  }
  auto arr = [&](std::vector<double>& v, std::size_t want) {
    a.get(v, want);
    if (v.size() != want) throw ArchiveError("a particle array has the wrong length");
  };
  const std::size_t nr = p.has_rotation() ? n0 : 0;
  for (auto* v : {&p.x, &p.y, &p.z, &p.vx, &p.vy, &p.vz, &p.fx, &p.fy, &p.fz}) arr(*v, n0);
  for (auto* v : {&p.wx, &p.wy, &p.wz, &p.tx, &p.ty, &p.tz}) arr(*v, nr);
  const std::size_t nd = p.has_drag_relaxation() ? n0 : 0;
  for (auto* v : {&p.drag_k, &p.ugx, &p.ugy, &p.ugz}) arr(*v, nd);
  const std::size_t n2 = p.has_two_way() ? n0 : 0;
  for (auto* v : {&p.dfx, &p.dfy, &p.dfz, &p.jx, &p.jy, &p.jz}) arr(*v, n2);
  std::uint64_t nm = 0;
  a.get(nm);
  if (nm != modules_.size()) throw ArchiveError("its modules differ from the scene's");
  for (auto& m : modules_) {
    std::string name;
    a.get(name);
    if (name != m->name()) throw ArchiveError("it has module '" + name + "' where the scene has '" + m->name() + "'");
    m->load_state(a);
  }
  std::uint8_t has_gas = 0;
  a.get(has_gas);
  if ((has_gas != 0) != static_cast<bool>(solver_)) throw ArchiveError("its gas differs from the scene's");
  if (solver_) {
    const std::size_t cells = gas_->grid().padded_size();
    for (auto* v : {&gas_->u, &gas_->v, &gas_->w, &gas_->p, &gas_->eps_g}) arr(*v, cells);
    double gt = 0.0;
    a.get(gt);
    a.get(substep_);
    if (!std::isfinite(gt) || substep_ >= substeps_) throw ArchiveError("its gas clock is inconsistent");
    const std::size_t ni = particles_.has_two_way() ? cells : 0;
    for (auto* v : {&imp_x_, &imp_y_, &imp_z_}) arr(*v, ni);
    a.get(particle_impulse_.x); a.get(particle_impulse_.y); a.get(particle_impulse_.z);
    solver_->set_time(gt);
    gas_->refresh();
  }
  if (!a.done()) throw ArchiveError("it has data after the last module");
  if (steps > total_steps_ || !std::isfinite(time))
    throw ArchiveError("its step count " + std::to_string(steps) + " is beyond the scene's " + std::to_string(total_steps_));
  steps_ = steps;
  time_ = time;
  if (gas_) gas_->set_time(time_);
  forces_valid_ = fv != 0;
  kick_pending_ = false;  // the velocities read are those at time()
  one_mass_ = -1;
  restarted_ = true;
}

}  // namespace cdm
