#include "cdm/solver/modules.hpp"

#include "cdm/solver/contact/linear_spring_dashpot.hpp"

namespace cdm {

void GravityModule::add_forces(ParticleStore& p, double /*dt*/) {
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    p.fx[i] += p.mass[i] * g_.x;
    p.fy[i] += p.mass[i] * g_.y;
    p.fz[i] += p.mass[i] * g_.z;
  }
}

LinearContactModule::LinearContactModule(PairTable pairs, std::vector<PlaneWall> walls, bool with_friction)
    : pairs_(std::move(pairs)), walls_(std::move(walls)), friction_(with_friction) {}

std::string LinearContactModule::name() const {
  return friction_ ? "linear_spring_dashpot+spring_coulomb" : "linear_spring_dashpot";
}

void LinearContactModule::add_forces(ParticleStore& p, double dt) {
  worst_ = {};
  n_active_ = 0;
  if (friction_) add_forces_impl<true>(p, dt);
  else add_forces_impl<false>(p, dt);
}

template <bool Friction>
void LinearContactModule::add_forces_impl(ParticleStore& p, double dt) {
  if constexpr (Friction) next_history_.clear();

  // Force on i for one contact (j's force is its negative); j may be a wall.
  auto resolve = [&](double overlap, Vec3 eta, Vec3 vrel, const PairParams& pp,
                     double m_eff, std::uint64_t key, Vec3& f_out, Vec3& ft_out) {
    const double eta_n = normal_damping(pp, m_eff);
    const double vn_mag = dot(vrel, eta);
    const Vec3 vn = vn_mag * eta;
    const Vec3 fn = contact::normal_force(pp.kn, eta_n, overlap, eta, vn);
    f_out = fn;
    ft_out = Vec3{};
    if constexpr (Friction) {
      const Vec3 vt = vrel - vn;
      auto it = history_.find(key);
      const bool is_new = it == history_.end();
      const Vec3 delta = contact::update_tangential_displacement(is_new ? Vec3{} : it->second, is_new, vt,
                                                                 std::abs(vn_mag), overlap, dt, eta);
      next_history_.emplace(key, delta);
      const double kt = pp.kt_factor * pp.kn;
      const double eta_t = pp.etat_factor * eta_n;
      ft_out = contact::tangential_force(kt, eta_t, pp.mu, norm(fn), delta, vt);
      f_out += ft_out;
    }
  };

  // Particle–particle.
  search_.find_contacts(p, 0.0, candidates_);
  for (const ContactPair& c : candidates_) {
    if (c.overlap <= 0.0) continue;
    const std::uint32_t i = c.i, j = c.j;
    ++n_active_;
    const Vec3 d = p.position(j) - p.position(i);
    const double dist = norm(d);
    const Vec3 eta = (1.0 / dist) * d;
    const double ri = p.radius[i], rj = p.radius[j];
    const double Li = (dist * dist + ri * ri - rj * rj) / (2.0 * dist);  // lever arms (eq 7)
    const double Lj = dist - Li;
    Vec3 vrel = p.velocity(i) - p.velocity(j);
    if constexpr (Friction) vrel += cross(Li * p.angular_velocity(i) + Lj * p.angular_velocity(j), eta);
    const PairParams& pp = pairs_.get(p.material[i], p.material[j]);
    const double m_eff = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
    Vec3 f, ft;
    resolve(c.overlap, eta, vrel, pp, m_eff, (std::uint64_t{i} << 32) | j, f, ft);
    p.add_force(i, f);
    p.add_force(j, -f);
    if constexpr (Friction) {
      const Vec3 t = cross(eta, ft);  // T_i = L_i η × F_t, T_j = L_j η × F_t
      p.add_torque(i, Li * t);
      p.add_torque(j, Lj * t);
    }
    const double ratio = c.overlap / std::min(ri, rj);
    if (ratio > worst_.ratio) worst_ = {ratio, ri <= rj ? i : j, static_cast<long>(ri <= rj ? j : i)};
  }

  // Particle–wall: the wall is a body of infinite mass at rest; m_eff = m_i.
  const std::size_t n = p.size();
  for (std::size_t w = 0; w < walls_.size(); ++w) {
    const PlaneWall& wall = walls_[w];
    for (std::size_t ii = 0; ii < n; ++ii) {
      const auto i = static_cast<std::uint32_t>(ii);
      const double dist = wall.distance(p.position(i));
      const double overlap = p.radius[i] - dist;
      if (overlap <= 0.0) continue;
      ++n_active_;
      const Vec3 eta = -wall.normal;  // from the particle towards the wall
      const double Li = dist;         // centre to contact point on the plane
      Vec3 vrel = p.velocity(i);
      if constexpr (Friction) vrel += cross(Li * p.angular_velocity(i), eta);
      const PairParams& pp = pairs_.get(p.material[i], wall.material);
      Vec3 f, ft;
      resolve(overlap, eta, vrel, pp, p.mass[i], (std::uint64_t{i} << 32) | (0xFFFFFFFFu - w), f, ft);
      p.add_force(i, f);
      if constexpr (Friction) p.add_torque(i, Li * cross(eta, ft));
      const double ratio = overlap / p.radius[i];
      if (ratio > worst_.ratio) worst_ = {ratio, i, -1 - static_cast<long>(w)};
    }
  }
  if constexpr (Friction) history_.swap(next_history_);
}

}  // namespace cdm
