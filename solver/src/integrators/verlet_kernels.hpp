#pragma once
/// @file verlet_kernels.hpp
/// @brief Velocity Verlet's per-particle arithmetic, inlined into the loops of
/// velocity_verlet.cpp (only that file includes this one): the first half of a step and
/// the final kick per particle, and the one fused pass per step (deferred final kick), with
/// the compile-time flags that fold its branches away.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <new>
#include <vector>

#include <sys/mman.h>

#include "cdm/solver/integrators/kick.hpp"
#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/periodic_box.hpp"
#include "cdm/solver/vec3.hpp"

namespace cdm::integrators::verlet {

/// The arrays velocity Verlet reads and writes per particle, as raw pointers: through
/// the store's vectors the compiler would reload them, and pass the per-particle work
/// its arguments through memory.
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
  // The drag's part of verlet_pass's kick (DragKick): the drag coefficient K and the gas
  // velocity u_g of a relaxed drag, the explicit drag force F_d, and the two-way impulse
  // accumulator J, per axis (ParticleStore's drag_k, ugx..., dfx..., jx...); for the
  // exact relaxation, each particle's φ = (1 − e^(−λh))/λ and the λ it was computed
  // for (verlet_pass recomputes φ only where λ changed: e^x is most of the kick's cost).
  const double* drag_k = nullptr;
  double *phi = nullptr, *phi_lam = nullptr;
  const double *ug[3] = {nullptr, nullptr, nullptr}, *df[3] = {nullptr, nullptr, nullptr};
  double* j[3] = {nullptr, nullptr, nullptr};
};

/// The kick of verlet_pass (Kick's arithmetic, kick.hpp): the plain one; the plain one
/// with the explicit drag's impulse τ F_d added to J (two-way); the drag relaxed
/// implicitly (backward Euler over the kick) or exactly (exponential), without or with
/// its impulse m Δv − τ F added to J.
enum class DragKick { none, explicit_impulse, implicit, implicit_impulse, exponential, exponential_impulse };
/// Whether the kick relaxes the drag exactly; implicitly or exactly (reading K and u_g);
/// adds the drag impulse to J.
constexpr bool exact_kick(DragKick d) { return d == DragKick::exponential || d == DragKick::exponential_impulse; }
constexpr bool relaxed_kick(DragKick d) {
  return exact_kick(d) || d == DragKick::implicit || d == DragKick::implicit_impulse;
}
constexpr bool impulse_kick(DragKick d) {
  return d == DragKick::explicit_impulse || d == DragKick::implicit_impulse || d == DragKick::exponential_impulse;
}

inline VerletArrays verlet_arrays(ParticleStore& p, std::vector<double>& hvx, std::vector<double>& hvy,
                           std::vector<double>& hvz, std::vector<double>& hwx, std::vector<double>& hwy,
                           std::vector<double>& hwz) {
  return {p.x.data(),  p.y.data(),  p.z.data(),  p.vx.data(), p.vy.data(), p.vz.data(), p.fx.data(),
          p.fy.data(), p.fz.data(), hvx.data(),  hvy.data(),  hvz.data(),  p.wx.data(), p.wy.data(),
          p.wz.data(), p.tx.data(), p.ty.data(), p.tz.data(), hwx.data(),  hwy.data(),  hwz.data(),
          p.inv_mass.data(), p.inv_inertia.data()};
}

// Velocity Verlet per particle, for the two passes with a gas and the final kick (the
// one pass per step with the final kick deferred, verlet_pass, does the same arithmetic axis by axis);
// inline always, so that @p rot and @p wrap fold away where they are constants. @p kick
// is the integrator's Kick (kick.hpp).

/// The final half kick of particle i: its velocity @p v and spin @p w (set only with
/// @p rot) at the new time, from the half-step ones and the forces.
template <class KickFn>
[[gnu::always_inline]] inline void verlet_final_velocity(const VerletArrays& a, bool rot, std::size_t i, double h,
                                                         const KickFn& kick, Vec3& v, Vec3& w) {
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
template <class KickFn>
[[gnu::always_inline]] inline void verlet_first_half(const VerletArrays& a, bool rot, bool wrap, bool grav,
                                                     const PeriodicBox& box, double dt, std::size_t i, Vec3 v, Vec3 w,
                                                     const KickFn& kick) {
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

/// f.template operator()<D>() for the run-time @p d (one instantiation per DragKick).
template <class F>
decltype(auto) with_drag_kick(DragKick d, F&& f) {
  switch (d) {
    case DragKick::explicit_impulse: return f.template operator()<DragKick::explicit_impulse>();
    case DragKick::implicit: return f.template operator()<DragKick::implicit>();
    case DragKick::implicit_impulse: return f.template operator()<DragKick::implicit_impulse>();
    case DragKick::exponential: return f.template operator()<DragKick::exponential>();
    case DragKick::exponential_impulse: return f.template operator()<DragKick::exponential_impulse>();
    case DragKick::none: break;
  }
  return f.template operator()<DragKick::none>();
}

/// One axis of the one pass per step (verlet_pass) for particles [i0, i1): for axis @p A
/// of position @p X, predicted velocity @p V, force @p F and half-step velocity @p HV,
/// the final kick of the last step if @p Pending, the half kick, drift (wrapped with
/// @p Wrap), predicted velocity, and the force set to the weight's component m @p g
/// (with @p Grav) or zeroed. The kicks are @p D's (DragKick), from VerletArrays' drag
/// arrays for axis A; the final and half kicks carry the drag impulse, the prediction
/// does not. Particle i's term of the squared displacement since the
/// build (@p Measure, from @p X0) or of this step's drift goes to @p d2[i - i0], set by
/// the first axis (@p First) and added to by the others, so d2 sums x² + y² + z² in the
/// order a single expression would. The same sum carries the finiteness check of the
/// state at t: each term comes with s − s for s = x + v at t, +0 where s is finite (the
/// sum unchanged, to the bit) and NaN where it is not. With @p One every particle has
/// VerletArrays' one_inv_mass and one_mass.
template <int A, bool First, bool Pending, bool Wrap, bool Measure, bool Grav, bool One, DragKick D>
[[gnu::always_inline]] inline void verlet_axis(const VerletArrays& a, double* __restrict X, double* __restrict V,
                                               double* __restrict F, double* __restrict HV,
                                               const double* __restrict X0, double g, const PeriodicBox& box, double dt,
                                               std::size_t i0, std::size_t i1, double* __restrict d2) {
  constexpr bool exact = exact_kick(D), relaxed = relaxed_kick(D), impulse = impulse_kick(D);
  const double h = 0.5 * dt;
  const double* __restrict const IM = a.inv_mass;
  const double* __restrict const M = a.mass;
  const double* __restrict const K = a.drag_k;
  const double* __restrict const PHI = a.phi;
  const double* __restrict const UG = a.ug[A];
  const double* __restrict const DF = a.df[A];
  double* __restrict const J = a.j[A];
  for (std::size_t i = i0; i < i1; ++i) {
    const double im = One ? a.one_inv_mass : IM[i];
    const double f = F[i];
    double v, s, x, jj = 0.0;
    if constexpr (impulse) jj = J[i];
    if constexpr (relaxed) {
      // dv/dt = a + λ (u_g − v), λ = K/m, over h with a, λ, u_g frozen (Kick::relaxed):
      // backward Euler, or exact with φ = (1 − e^(−λh))/λ.
      const double lam = im * K[i];
      const double c = exact ? 0.0 : 1.0 / (1.0 + lam * h);
      const double acc = im * f, ug = UG[i];
      const double m = One ? a.one_mass : M[i];
      auto kick = [&](double v0, bool with_impulse) {
        const double v1 = exact ? v0 + PHI[i] * (acc + lam * (ug - v0)) : c * (v0 + h * (acc + lam * ug));
        if (impulse && with_impulse) jj += m * (v1 - v0) - h * f;
        return v1;
      };
      v = Pending ? kick(HV[i], true) : V[i];  // v(t)
      s = X[i] + v;
      v = kick(v, true);  // half kick
      HV[i] = v;
      x = X[i] + dt * v;
      if constexpr (Wrap) x = box.wrap(x, A);
      X[i] = x;
      V[i] = kick(v, false);  // predicted v(t+Δt)
    } else {
      const double c = h * im;  // PlainKick's factor
      if constexpr (impulse) {
        if constexpr (Pending) jj += h * DF[i];
        jj += h * DF[i];
      }
      v = Pending ? HV[i] + c * f : V[i];  // v(t)
      s = X[i] + v;
      v += c * f;  // half kick
      HV[i] = v;
      x = X[i] + dt * v;
      if constexpr (Wrap) x = box.wrap(x, A);
      X[i] = x;
      V[i] = v + c * f;  // predicted v(t+Δt)
    }
    if constexpr (impulse) J[i] = jj;
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
/// malloc: a long-lived block there would keep the heap from giving back what the list
/// rebuilds free below it, which raises the peak memory.
inline double* pass_scratch(std::size_t n) {
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

/// Particles [i0, i1) of the one pass per step, final kick deferred (VelocityVerlet::step): the
/// state at t, completed by the last step's final kick if @p Pending, checked for
/// finite values, then the first half of the step (the forces set to the weight with
/// @p Grav). Returns the largest squared displacement since the contact list's build
/// (with @p Measure; else the largest squared drift of this step), or +inf if some
/// particle's state at t was not finite.
///
/// The arithmetic per particle is verlet_final_velocity's and verlet_first_half's, to
/// the bit, but done one axis at a time over blocks of particles: a loop over all 24
/// arrays at once runs at about half the speed the same traffic gets in loops over 4
/// to 6 arrays each (bench/pass_probe, layouts soa and soa-axis). The blocks are long:
/// each of the six loops per block starts four new streams, and in DRAM (1e5 particles
/// and up) a stream's first lines cost more than the rest (bench/README.md).
/// The finiteness test asks each of x + v_x, y + v_y, z + v_z and the spin's components
/// at t to be finite (through the squared displacement, verlet_axis), where
/// verlet_state_finite asks their sum: the same answer short of overflow (itself a
/// blow-up).
template <bool Pending, bool Rot, bool Wrap, bool Measure, bool Grav, bool One, DragKick D>
double verlet_pass(const VerletArrays& a, const PeriodicBox& box, double dt, std::size_t i0, std::size_t i1) {
  constexpr std::size_t block = 32768;
  // Each particle's squared displacement (NaN if its state is not finite), per block.
  double* const d2 = pass_scratch(std::min(block, i1 - i0));
  double worst = 0.0;
  for (std::size_t b0 = i0; b0 < i1; b0 += block) {
    const std::size_t b1 = std::min(i1, b0 + block);
    if constexpr (exact_kick(D)) {
      // Kick::relaxed's φ over the half step h (the same for the pass's three kicks on
      // each axis), computed again only where λ is not the one it was computed for: the
      // same φ to the bit, and between gas steps λ does not change.
      const double h = 0.5 * dt;
      for (std::size_t i = b0; i < b1; ++i) {
        const double lam = (One ? a.one_inv_mass : a.inv_mass[i]) * a.drag_k[i];
        if (a.phi_lam[i] == lam) continue;
        a.phi_lam[i] = lam;
        a.phi[i] = exact_relaxation_phi(lam, h);
      }
    }
    verlet_axis<0, true, Pending, Wrap, Measure, Grav, One, D>(a, a.x, a.vx, a.fx, a.hvx, a.x0, a.g.x, box, dt, b0, b1, d2);
    verlet_axis<1, false, Pending, Wrap, Measure, Grav, One, D>(a, a.y, a.vy, a.fy, a.hvy, a.y0, a.g.y, box, dt, b0, b1, d2);
    verlet_axis<2, false, Pending, Wrap, Measure, Grav, One, D>(a, a.z, a.vz, a.fz, a.hvz, a.z0, a.g.z, box, dt, b0, b1, d2);
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

}  // namespace cdm::integrators::verlet
