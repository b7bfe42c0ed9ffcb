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

LinearContactModule::LinearContactModule(PairTable pairs, std::vector<PlaneWall> walls, bool with_friction, double skin)
    : pairs_(std::move(pairs)), walls_(std::move(walls)), friction_(with_friction), skin_(skin) {}

std::string LinearContactModule::name() const {
  return friction_ ? "linear_spring_dashpot+spring_coulomb" : "linear_spring_dashpot";
}

void LinearContactModule::add_forces(ParticleStore& p, double dt) {
  worst_ = {};
  n_active_ = 0;
  if (!built_ || needs_rebuild(p)) rebuild(p);
  if (friction_) add_forces_impl<true>(p, dt);
  else add_forces_impl<false>(p, dt);
}

void LinearContactModule::save_state(OutArchive& a) const {
  a.put(static_cast<std::uint8_t>(built_));
  a.put(static_cast<std::uint64_t>(builds_));
  a.put(static_cast<std::uint64_t>(n_active_));
  a.put(worst_);
  a.put(nbr_start_); a.put(nbr_j_); a.put(nbr_hist_); a.put(nbr_touch_);
  a.put(wall_hist_); a.put(wall_touch_);
  a.put(x0_); a.put(y0_); a.put(z0_);
}

void LinearContactModule::load_state(InArchive& a) {
  std::uint8_t built = 0;
  std::uint64_t builds = 0, active = 0;
  a.get(built); a.get(builds); a.get(active); a.get(worst_);
  a.get(nbr_start_); a.get(nbr_j_); a.get(nbr_hist_); a.get(nbr_touch_);
  a.get(wall_hist_); a.get(wall_touch_);
  a.get(x0_); a.get(y0_); a.get(z0_);
  const std::size_t n = x0_.size();
  const bool rows_ok = nbr_start_.empty() || (nbr_start_.size() == n + 1 && nbr_start_.back() == nbr_j_.size());
  bool j_ok = true;
  for (auto j : nbr_j_) j_ok = j_ok && j < n;
  const bool hist_ok = !friction_ || (nbr_hist_.size() == nbr_j_.size() && nbr_touch_.size() == nbr_j_.size() &&
                                      wall_hist_.size() == wall_touch_.size());
  if (!rows_ok || !j_ok || !hist_ok || y0_.size() != n || z0_.size() != n)
    throw ArchiveError("the contact list is inconsistent");
  built_ = built != 0;
  builds_ = builds;
  n_active_ = active;
}

bool LinearContactModule::needs_rebuild(const ParticleStore& p) const {
  if (skin_ <= 0.0 || p.size() != x0_.size()) return true;
  const double lim2 = 0.25 * skin_ * skin_;
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = p.x[i] - x0_[i], dy = p.y[i] - y0_[i], dz = p.z[i] - z0_[i];
    if (dx * dx + dy * dy + dz * dz > lim2) return true;
  }
  return false;
}

void LinearContactModule::rebuild(const ParticleStore& p) {
  const std::size_t n = p.size();
  search_.find_contacts(p, skin_, candidates_);  // sorted by (i, j)
  std::vector<std::uint32_t> start(n + 1, 0), js(candidates_.size());
  for (const auto& c : candidates_) ++start[c.i + 1];
  for (std::size_t i = 0; i < n; ++i) start[i + 1] += start[i];
  for (std::size_t k = 0; k < candidates_.size(); ++k) js[k] = candidates_[k].j;
  if (friction_) {
    // Carry the history of pairs listed before and after (both rows sorted by j);
    // every pair in contact is in both lists.
    std::vector<Vec3> hist(js.size());
    std::vector<std::uint8_t> touch(js.size(), 0);
    if (built_)
      for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t a = nbr_start_[i];
        const std::uint32_t a_end = nbr_start_[i + 1];
        for (std::uint32_t b = start[i]; b < start[i + 1] && a < a_end; ++b) {
          while (a < a_end && nbr_j_[a] < js[b]) ++a;
          if (a < a_end && nbr_j_[a] == js[b]) { hist[b] = nbr_hist_[a]; touch[b] = nbr_touch_[a]; }
        }
      }
    nbr_hist_.swap(hist);
    nbr_touch_.swap(touch);
    if (wall_hist_.size() != n * walls_.size()) {
      wall_hist_.assign(n * walls_.size(), Vec3{});
      wall_touch_.assign(n * walls_.size(), 0);
    }
  }
  nbr_start_.swap(start);
  nbr_j_.swap(js);
  x0_ = p.x; y0_ = p.y; z0_ = p.z;
  built_ = true;
  ++builds_;
}

template <bool Friction>
void LinearContactModule::add_forces_impl(ParticleStore& p, double dt) {
  // Force on i for one contact (j's force is its negative); j may be a wall.
  // @p hist and @p touch are the contact's tangential history slot.
  auto resolve = [&](double overlap, Vec3 eta, Vec3 vrel, const PairParams& pp, double m_eff, Vec3& hist,
                     std::uint8_t& touch, Vec3& f_out, Vec3& ft_out) {
    const double eta_n = normal_damping(pp, m_eff);
    const double vn_mag = dot(vrel, eta);
    const Vec3 vn = vn_mag * eta;
    const Vec3 fn = contact::normal_force(pp.kn, eta_n, overlap, eta, vn);
    f_out = fn;
    if constexpr (Friction) {
      const Vec3 vt = vrel - vn;
      hist = contact::update_tangential_displacement(hist, touch == 0, vt, std::abs(vn_mag), overlap, dt, eta);
      touch = 1;
      const double kt = pp.kt_factor * pp.kn;
      const double eta_t = pp.etat_factor * eta_n;
      ft_out = contact::tangential_force(kt, eta_t, pp.mu, norm(fn), hist, vt);
      f_out += ft_out;
    } else {
      (void)hist; (void)touch;
      ft_out = Vec3{};
    }
  };
  Vec3 no_hist;
  std::uint8_t no_touch = 0;

  // Particle–particle, over the Verlet list.
  const std::size_t n = p.size();
  for (std::size_t ii = 0; ii < n; ++ii) {
    const auto i = static_cast<std::uint32_t>(ii);
    const Vec3 xi = p.position(i);
    const double ri = p.radius[i];
    for (std::uint32_t k = nbr_start_[i]; k < nbr_start_[i + 1]; ++k) {
      const std::uint32_t j = nbr_j_[k];
      const Vec3 d = p.position(j) - xi;
      const double rj = p.radius[j];
      const double reach = ri + rj;
      const double d2 = dot(d, d);
      if (d2 >= reach * reach) {
        if constexpr (Friction) nbr_touch_[k] = 0;  // contact over: history forgotten
        continue;
      }
      const double dist = std::sqrt(d2);
      const double overlap = reach - dist;
      ++n_active_;
      const Vec3 eta = (1.0 / dist) * d;
      const double Li = (dist * dist + ri * ri - rj * rj) / (2.0 * dist);  // lever arms (eq 7)
      const double Lj = dist - Li;
      Vec3 vrel = p.velocity(i) - p.velocity(j);
      if constexpr (Friction) vrel += cross(Li * p.angular_velocity(i) + Lj * p.angular_velocity(j), eta);
      const PairParams& pp = pairs_.get(p.material[i], p.material[j]);
      const double m_eff = p.mass[i] * p.mass[j] / (p.mass[i] + p.mass[j]);
      Vec3 f, ft;
      if constexpr (Friction) resolve(overlap, eta, vrel, pp, m_eff, nbr_hist_[k], nbr_touch_[k], f, ft);
      else resolve(overlap, eta, vrel, pp, m_eff, no_hist, no_touch, f, ft);
      p.add_force(i, f);
      p.add_force(j, -f);
      if constexpr (Friction) {
        const Vec3 t = cross(eta, ft);  // T_i = L_i η × F_t, T_j = L_j η × F_t
        p.add_torque(i, Li * t);
        p.add_torque(j, Lj * t);
      }
      const double ratio = overlap / std::min(ri, rj);
      if (ratio > worst_.ratio) worst_ = {ratio, ri <= rj ? i : j, static_cast<long>(ri <= rj ? j : i)};
    }
  }

  // Particle–wall: the wall is a body of infinite mass at rest; m_eff = m_i.
  const std::size_t nw = walls_.size();
  for (std::size_t w = 0; w < nw; ++w) {
    const PlaneWall& wall = walls_[w];
    for (std::size_t ii = 0; ii < n; ++ii) {
      const auto i = static_cast<std::uint32_t>(ii);
      const double dist = wall.distance(p.position(i));
      const double overlap = p.radius[i] - dist;
      if (overlap <= 0.0) {
        if constexpr (Friction) wall_touch_[ii * nw + w] = 0;
        continue;
      }
      ++n_active_;
      const Vec3 eta = -wall.normal;  // from the particle towards the wall
      const double Li = dist;         // centre to contact point on the plane
      Vec3 vrel = p.velocity(i);
      if constexpr (Friction) vrel += cross(Li * p.angular_velocity(i), eta);
      const PairParams& pp = pairs_.get(p.material[i], wall.material);
      Vec3 f, ft;
      if constexpr (Friction) resolve(overlap, eta, vrel, pp, p.mass[i], wall_hist_[ii * nw + w], wall_touch_[ii * nw + w], f, ft);
      else resolve(overlap, eta, vrel, pp, p.mass[i], no_hist, no_touch, f, ft);
      p.add_force(i, f);
      if constexpr (Friction) p.add_torque(i, Li * cross(eta, ft));
      const double ratio = overlap / p.radius[i];
      if (ratio > worst_.ratio) worst_ = {ratio, i, -1 - static_cast<long>(w)};
    }
  }
}

}  // namespace cdm
