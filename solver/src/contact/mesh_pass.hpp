#pragma once
/// @file mesh_pass.hpp
/// @brief ContactModule's pass over the mesh contacts, with the pair loop's force laws;
/// included by contact_module.cpp, whose kernels instantiate it.

#include <algorithm>
#include <cstddef>
#include <vector>

#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/parallel.hpp"

namespace cdm {

template <bool Friction, ContactModule::LawsPresent L, class Resolve, class Hertz, class StepVel, class StepSpin>
void ContactModule::mesh_pass(ParticleStore& p, Resolve& resolve, Hertz& hertz, StepVel& step_velocity,
                              StepSpin& step_spin, std::size_t& active, OverlapRecord& worst) {
  // As a wall's contact (ContactModule::add_forces_impl): the mesh is a body of infinite mass, m* = m_i and
  // R* = R_i, its surface moving with the mesh's motion; each particle only touches its
  // own force.
  const std::size_t n = p.size();
  const bool threads = n > parallel_threshold;
  // Among MPI ranks, the contacts of this rank's particles (the others' are gathered
  // with the state, RankSplit::synchronise).
  mesh_->update(p, threads, list_.builds(), list_.skin(), list_.time(), ranks_ ? &ranks_->own_runs(n) : nullptr);
  std::vector<MeshContacts::Contact>& contacts = mesh_->contacts();
  if (record_) fn_mesh_.resize(contacts.size());
  const long first = -1 - static_cast<long>(list_.walls().size());
  auto mesh_range = [&](std::size_t c0, std::size_t c1, std::size_t& my_active, OverlapRecord& my_worst) {
    for (std::size_t k = c0; k < c1; ++k) {
      MeshContacts::Contact& c = contacts[k];
      const std::uint32_t i = c.particle;
      ++my_active;
      const Vec3 eta = c.eta;
      const double Li = c.lever;
      // A moving mesh's surface velocity at the contact point (zero at rest).
      Vec3 vrel = p.velocity(i) - c.wall_velocity;
      if constexpr (Friction) vrel += cross(Li * p.angular_velocity(i), eta);
      const PairParams& pp = pairs_.get(p.material[i], mesh_->material_of(c.triangle));
      Vec3 vrel_step = vrel;
      if constexpr (Friction && L != LawsPresent::linear)
        if (hertz(pp)) vrel_step = step_velocity(i) - c.wall_velocity + cross(Li * step_spin(i), eta);
      const double eta_n = !hertz(pp) ? normal_damping(pp, p.mass[i]) : 0.0;
      contact::TangentialSlot slot;
      if constexpr (Friction) slot = {&c.delta_t, &c.touching};
      const contact::ContactForce cf = resolve(pp, p.mass[i], eta_n, p.radius[i], {c.overlap, eta, vrel, vrel_step}, slot);
      const Vec3 f = cf.total, ft = cf.tangential;
      p.add_force(i, f);
      if constexpr (Friction) p.add_torque(i, Li * cross(eta, ft));
      if (record_) fn_mesh_[k] = cf.normal_magnitude;
      const OverlapRecord rec{c.overlap / p.radius[i], i, first - static_cast<long>(mesh_->mesh_of(c.triangle))};
      if (contact::worse_overlap(rec, my_worst)) my_worst = rec;
    }
  };
  if (!threads) {
    mesh_range(0, contacts.size(), active, worst);
    return;
  }
#pragma omp parallel
  {
    std::size_t my_active = 0;
    OverlapRecord my_worst;
    // The contacts of the particles this thread moves in the integrator's pass.
    const auto [i0, i1] = thread_range(n);
    const auto [c0, c1] = mesh_->contacts_of(i0, i1);
    mesh_range(c0, c1, my_active, my_worst);
#pragma omp critical(cdm_contact_reduce)
    {
      active += my_active;
      if (contact::worse_overlap(my_worst, worst)) worst = my_worst;
    }
  }
}

}  // namespace cdm
