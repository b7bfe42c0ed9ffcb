#pragma once
/// @file kick.hpp
/// @brief The velocity kick v += τ F/m of every particle integrator, with the drag
/// relaxation solved implicitly or exactly where the scene asks for it
/// (drag_module.hpp), and the drag impulse it carries added to the particle's two-way
/// accumulator.
#include <cmath>
#include <cstddef>

#include "cdm/solver/coupling/drag_laws.hpp"
#include "cdm/solver/particle_store.hpp"

namespace cdm::integrators {

/// φ = (1 − e^(−λτ))/λ of the exact drag relaxation over τ (→ τ as λ → 0): the kick is
/// then v' = v + (a + λ(u_g − v)) φ.
[[gnu::always_inline]] inline double exact_relaxation_phi(double lam, double tau) {
  return lam * tau > 1e-12 ? -std::expm1(-lam * tau) / lam : tau;
}

/// The kick without a drag: v += τ/m F.
struct PlainKick {
  const double *inv_mass, *fx, *fy, *fz;
  void operator()(std::size_t i, double tau, double& vx, double& vy, double& vz) const {
    const double a = tau * inv_mass[i];
    vx += a * fx[i]; vy += a * fy[i]; vz += a * fz[i];
  }
};

class Kick {
 public:
  Kick(ParticleStore& p, coupling::DragUpdate update) : p_(p), update_(update) {}

  /// Kick particle i's velocity by the forces over @p tau. With @p impulse the drag
  /// impulse of the kick is added to the particle's two-way accumulator (not for the
  /// velocity predictor of velocity Verlet). Inline, the drag relaxation apart: as a
  /// call, with its results passed through memory, it would cost the Verlet passes much.
  [[gnu::always_inline]] inline void operator()(std::size_t i, double tau, double& vx, double& vy, double& vz,
                                                bool impulse = true) const {
    ParticleStore& p = p_;
    if (p.has_drag_relaxation()) {
      relaxed(i, tau, vx, vy, vz, impulse);
      return;
    }
    PlainKick{p.inv_mass.data(), p.fx.data(), p.fy.data(), p.fz.data()}(i, tau, vx, vy, vz);
    if (impulse && p.has_two_way()) {  // the explicit drag's share of the kick
      p.jx[i] += tau * p.dfx[i]; p.jy[i] += tau * p.dfy[i]; p.jz[i] += tau * p.dfz[i];
    }
  }

 private:
  /// The kick for particles whose drag is relaxed implicitly or exactly.
  void relaxed(std::size_t i, double tau, double& vx, double& vy, double& vz, bool impulse) const {
    ParticleStore& p = p_;
    const double im = p.inv_mass[i];
    const double ax = im * p.fx[i], ay = im * p.fy[i], az = im * p.fz[i];
    const double v0x = vx, v0y = vy, v0z = vz;
    // dv/dt = a + λ (u_g − v), λ = K/m, over tau with a, λ, u_g frozen.
    const double lam = im * p.drag_k[i];
    if (update_ == coupling::DragUpdate::implicit) {
      // Backward Euler: v' = (v + τ(a + λ u_g)) / (1 + λτ).
      const double c = 1.0 / (1.0 + lam * tau);
      vx = c * (vx + tau * (ax + lam * p.ugx[i]));
      vy = c * (vy + tau * (ay + lam * p.ugy[i]));
      vz = c * (vz + tau * (az + lam * p.ugz[i]));
    } else {
      // Exact: v' = v + (a + λ(u_g − v)) φ.
      const double phi = exact_relaxation_phi(lam, tau);
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

  ParticleStore& p_;
  coupling::DragUpdate update_;
};

}  // namespace cdm::integrators
