#include "cdm/solver/contact/rolling_resistance_module.hpp"

#include "cdm/solver/contact/rolling_resistance.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/rank_split.hpp"

namespace cdm {

void RollingResistanceModule::add_forces(ParticleStore& p, double dt) {
  const PairTable& pairs = c_.pairs();
  const VerletList& list = c_.list();
  const std::vector<std::uint32_t>& pi = list.pair_i();
  const std::vector<std::uint32_t>& pj = list.pair_j();
  const std::vector<std::uint32_t>& slab_start = list.slab_start();
  const std::vector<double>& fn_pair = c_.pair_normal_force();
  const std::size_t n = p.size();
  const bool threads = n > parallel_threshold;
  // The spin the integrator's next kick starts from: ω itself for the first-order
  // scheme, the half-step spin for velocity Verlet (ContactModule::set_step_velocities).
  const ContactModule::StepVelocities& sv = c_.step_velocities();
  const bool half = sv.wx && sv.wx->size() == n;
  // ω_i after the next kick with the torques accumulated so far (the contact module's,
  // and the rolling torques of contacts visited before this one).
  auto free_spin = [&](std::uint32_t i) {
    const Vec3 w0 = half ? Vec3{(*sv.wx)[i], (*sv.wy)[i], (*sv.wz)[i]} : p.angular_velocity(i);
    return w0 + (dt * p.inv_inertia[i]) * Vec3{p.tx[i], p.ty[i], p.tz[i]};
  };

  auto pair_range = [&](std::uint32_t k0, std::uint32_t k1) {
    for (std::uint32_t k = k0; k < k1; ++k) {
      if (fn_pair[k] < 0.0) continue;  // not in contact
      const std::uint32_t i = pi[k], j = pj[k];
      const PairParams& pp = pairs.get(p.material[i], p.material[j]);
      if (pp.rolling_mu == 0.0) continue;
      const Vec3 d = list.periodic_box().min_image(p.position(j) - p.position(i));
      const Vec3 eta = (1.0 / norm(d)) * d;
      const double ri = p.radius[i], rj = p.radius[j];
      const double inertia_eff = 1.0 / (p.inv_inertia[i] + p.inv_inertia[j]);
      const Vec3 t = contact::rolling_torque(pp.rolling_mu, ri * rj / (ri + rj), fn_pair[k],
                                             free_spin(i) - free_spin(j), eta, inertia_eff, dt);
      p.add_torque(i, t);
      p.add_torque(j, -t);
    }
  };
  // The contact module's slab order: even slabs, then odd slabs (see VerletList), so
  // the contacts of a particle are visited in the same order for any thread count. Among
  // ranks, each visits its own slabs, as the contact module does (rank_split.hpp).
  RankSplit* const ranks = c_.ranks();
  if (ranks) ranks->exchange_ghost_torques(p);
  list.by_phase([&](std::size_t pass, std::size_t s0, std::size_t last_slab) {
    if (!threads) {
      for (std::size_t s = s0; s < last_slab; s += 2) pair_range(slab_start[s], slab_start[s + 1]);
    } else {
      const long jobs = static_cast<long>(last_slab > s0 ? (last_slab - s0 + 1) / 2 : 0);
#pragma omp parallel for schedule(dynamic, 1)
      for (long t = 0; t < jobs; ++t) {
        const std::size_t s = s0 + 2 * static_cast<std::size_t>(t);
        pair_range(slab_start[s], slab_start[s + 1]);
      }
    }
    if (ranks) ranks->boundary_torques(p, static_cast<int>(pass));
  });
  if (!c_.walls().empty()) wall_torques(p, dt, free_spin);
  if (c_.meshes()) mesh_torques(p, dt, free_spin, threads);
}

template <class FreeSpin>
void RollingResistanceModule::wall_torques(ParticleStore& p, double dt, FreeSpin& free_spin) const {
  const PairTable& pairs = c_.pairs();
  const std::vector<double>& fn_wall = c_.wall_normal_force();
  const std::vector<Wall>& walls = c_.walls();
  const VerletList& list = c_.list();
  const std::vector<std::uint32_t>& candidates = list.wall_candidates();
  const std::vector<std::uint32_t>& wall_begin = list.wall_begin();
  const std::vector<std::uint32_t>& wall_ids = list.wall_ids();
  // Among ranks, the owner of each particle (as for the contact module's walls). Each
  // particle's walls in wall order, as the contact module visited them.
  const std::uint8_t* const own = c_.ranks() ? c_.ranks()->owned().data() : nullptr;
  parallel_for(candidates.size(), [&](std::size_t c) {
    const std::uint32_t i = candidates[c];
    if (own && !own[i]) return;
    for (std::uint32_t q = wall_begin[c]; q < wall_begin[c + 1]; ++q) {
      const double fn = fn_wall[q];
      if (fn < 0.0) continue;
      const Wall& wall = walls[wall_ids[q]];
      const PairParams& pp = pairs.get(p.material[i], wall.material);
      if (pp.rolling_mu == 0.0) continue;
      // Against a wall: ω_rel = ω_i − the wall's spin, R* = R_i, I* = I_i; the normal
      // that of the contact just evaluated (the same positions and wall).
      const Vec3 eta = wall.shape == WallShape::plane ? -wall.normal : -wall.gap(p.position(i), p.radius[i]).normal;
      const Vec3 t = contact::rolling_torque(pp.rolling_mu, p.radius[i], fn, free_spin(i) - wall.motion.spin(), eta,
                                             1.0 / p.inv_inertia[i], dt);
      p.add_torque(i, t);
    }
  });
}

template <class FreeSpin>
void RollingResistanceModule::mesh_torques(ParticleStore& p, double dt, FreeSpin& free_spin, bool threads) const {
  // Against a mesh, as against a wall: R* = R_i, I* = I_i, ω_rel = ω_i − the mesh's spin,
  // the normal that of the contact just evaluated. The contacts are in particle order,
  // each particle's in triangle order, so its torques add in the same order for any
  // thread count; each thread takes the particles of its share of the pass.
  const MeshContacts& m = *c_.meshes();
  const std::vector<MeshContacts::Contact>& contacts = m.contacts();
  const std::vector<double>& fn = c_.mesh_normal_force();
  const PairTable& pairs = c_.pairs();
  auto range = [&](std::size_t k0, std::size_t k1) {
    for (std::size_t k = k0; k < k1; ++k) {
      const MeshContacts::Contact& c = contacts[k];
      const PairParams& pp = pairs.get(p.material[c.particle], m.material_of(c.triangle));
      if (pp.rolling_mu == 0.0 || !(fn[k] >= 0.0)) continue;
      const Vec3 spin = m.meshes()[m.mesh_of(c.triangle)].motion.spin();
      const Vec3 t = contact::rolling_torque(pp.rolling_mu, p.radius[c.particle], fn[k], free_spin(c.particle) - spin,
                                             c.eta, 1.0 / p.inv_inertia[c.particle], dt);
      p.add_torque(c.particle, t);
    }
  };
  if (!threads) {
    range(0, contacts.size());
    return;
  }
  const std::size_t n = p.size();
#pragma omp parallel
  {
    const auto [i0, i1] = thread_range(n);
    const auto [c0, c1] = m.contacts_of(i0, i1);
    range(c0, c1);
  }
}

}  // namespace cdm
