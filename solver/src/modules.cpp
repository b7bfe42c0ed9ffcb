#include "cdm/solver/modules.hpp"

#include "cdm/solver/contact/hertz_mindlin.hpp"
#include "cdm/solver/contact/linear_spring_dashpot.hpp"
#include "cdm/solver/contact/rolling_resistance.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/platform.hpp"

#include <algorithm>
#include <limits>
#include <cmath>

namespace cdm {

void GravityModule::add_forces(ParticleStore& p, double /*dt*/) {
  const std::size_t n = p.size();
  parallel_for(n, [&](std::size_t i) {
    p.fx[i] += p.mass[i] * g_.x;
    p.fy[i] += p.mass[i] * g_.y;
    p.fz[i] += p.mass[i] * g_.z;
  });
}

ContactModule::ContactModule(PairTable pairs, std::vector<PlaneWall> walls, bool with_friction, double skin,
                             bool record_normal_forces)
    : pairs_(std::move(pairs)), walls_(std::move(walls)), friction_(with_friction), skin_(skin),
      record_(record_normal_forces) {
  const bool lin = pairs_.uses(ContactLaw::linear_spring_dashpot), hz = pairs_.uses(ContactLaw::hertz_mindlin);
  laws_ = lin && hz ? Laws::mixed : hz ? Laws::hertz : Laws::linear;
}

std::string ContactModule::name() const {
  const char* laws = laws_ == Laws::linear  ? "linear_spring_dashpot"
                     : laws_ == Laws::hertz ? "hertz_mindlin"
                                            : "linear_spring_dashpot,hertz_mindlin";
  return std::string(laws) + (friction_ ? "+spring_coulomb" : "");
}

void ContactModule::add_forces(ParticleStore& p, double dt) {
  worst_ = {};
  n_active_ = 0;
  if (!built_ || needs_rebuild(p)) {
    rebuild(p);
  } else {
    if (wall_candidates_stale_) list_wall_candidates(p);
    if (damping_stale_) tabulate_damping(p);
  }
  if (record_) {
    fn_pair_.resize(pi_.size());
    fn_wall_.resize(p.size() * walls_.size());
  }
  // One compiled kernel per (friction, laws present, recording): no per-pair dispatch
  // unless mixed, and nothing recorded unless a module reads it.
  if (record_) dispatch<true>(p, dt);
  else dispatch<false>(p, dt);
  displacement_ = -1.0;  // measured for these positions only
}

template <bool Record>
void ContactModule::dispatch(ParticleStore& p, double dt) {
  switch (laws_) {
    case Laws::linear:
      if (friction_) add_forces_impl<true, Laws::linear, Record>(p, dt);
      else add_forces_impl<false, Laws::linear, Record>(p, dt);
      break;
    case Laws::hertz:
      if (friction_) add_forces_impl<true, Laws::hertz, Record>(p, dt);
      else add_forces_impl<false, Laws::hertz, Record>(p, dt);
      break;
    case Laws::mixed:
      if (friction_) add_forces_impl<true, Laws::mixed, Record>(p, dt);
      else add_forces_impl<false, Laws::mixed, Record>(p, dt);
      break;
  }
}

void ContactModule::save_state(OutArchive& a) const {
  a.put(static_cast<std::uint8_t>(built_));
  a.put(static_cast<std::uint64_t>(builds_));
  a.put(static_cast<std::uint64_t>(n_active_));
  a.put(worst_.ratio); a.put(worst_.particle); a.put(worst_.partner);  // field by field: no padding bytes
  a.put(pi_); a.put(pj_); a.put(slab_start_); a.put(hist_); a.put(touch_);
  a.put(wall_hist_); a.put(wall_touch_);
  a.put(x0_); a.put(y0_); a.put(z0_);
}

void ContactModule::load_state(InArchive& a) {
  std::uint8_t built = 0;
  std::uint64_t builds = 0, active = 0;
  a.get(built); a.get(builds); a.get(active);
  a.get(worst_.ratio); a.get(worst_.particle); a.get(worst_.partner);
  a.get(pi_); a.get(pj_); a.get(slab_start_); a.get(hist_); a.get(touch_);
  a.get(wall_hist_); a.get(wall_touch_);
  a.get(x0_); a.get(y0_); a.get(z0_);
  const std::size_t n = x0_.size();
  bool ok = pi_.size() == pj_.size() && y0_.size() == n && z0_.size() == n;
  ok = ok && (slab_start_.empty() ? pi_.empty() : slab_start_.front() == 0 && slab_start_.back() == pi_.size());
  for (std::size_t s = 1; ok && s < slab_start_.size(); ++s) ok = slab_start_[s - 1] <= slab_start_[s];
  for (std::size_t k = 0; ok && k < pi_.size(); ++k) ok = pi_[k] < pj_[k] && pj_[k] < n;
  if (friction_) ok = ok && hist_.size() == pi_.size() && touch_.size() == pi_.size() &&
                      wall_hist_.size() == wall_touch_.size() && wall_hist_.size() == n * walls_.size();
  if (!ok) throw ArchiveError("the contact list is inconsistent");
  built_ = built != 0;
  builds_ = builds;
  displacement_ = -1.0;
  drift_bound_ = std::numeric_limits<double>::infinity();  // the moves since the build are unknown
  n_active_ = active;
  wall_candidates_stale_ = true;  // listed from the build's positions at the next evaluation
  damping_stale_ = true;
}

void ContactModule::list_wall_candidates(const ParticleStore& p) {
  // From the positions at the last build (x0_), so a restart lists exactly what the
  // build did. A particle moves less than skin/2 before the next build, so one farther
  // than r + skin from a wall cannot reach it: each particle is listed with the walls it
  // may touch. A wall not perpendicular to every periodic axis sees wrapped particles
  // jump, so then every particle is listed with every wall.
  const std::size_t n = x0_.size(), nw = walls_.size();
  wall_candidates_.clear();
  wall_begin_.assign(1, 0);
  wall_ids_.clear();
  wall_candidates_stale_ = false;
  bool filter = skin_ >= 0.0;
  for (const PlaneWall& w : walls_) {
    const double nrm[3] = {w.normal.x, w.normal.y, w.normal.z};
    for (int a = 0; a < 3; ++a)
      if (box_.on[a] && nrm[a] != 0.0) filter = false;
  }
  if (!nw) return;
  if (record_ && fn_wall_.size() != n * nw) fn_wall_.assign(n * nw, -1.0);
  const bool history = wall_touch_.size() == n * nw;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t before = wall_ids_.size();
    for (std::size_t w = 0; w < nw; ++w) {
      if (!filter || walls_[w].distance({x0_[i], y0_[i], z0_[i]}) < p.radius[i] + skin_) {
        wall_ids_.push_back(static_cast<std::uint32_t>(w));
      } else {  // not listed: not in contact with that wall
        if (history) wall_touch_[i * nw + w] = 0;
        if (record_) fn_wall_[i * nw + w] = -1.0;
      }
    }
    if (wall_ids_.size() != before) {
      wall_candidates_.push_back(static_cast<std::uint32_t>(i));
      wall_begin_.push_back(static_cast<std::uint32_t>(wall_ids_.size()));
    }
  }
}

bool ContactModule::needs_rebuild(const ParticleStore& p) const {
  if (skin_ <= 0.0 || p.size() != x0_.size()) return true;
  const double lim2 = 0.25 * skin_ * skin_;
  const std::size_t n = p.size();
  if (displacement_ >= 0.0) return displacement_ > lim2;  // the integrator measured it
  return parallel_max(n, [&](std::size_t i) { return displacement(p, i); }) > lim2;
}

ContactModule::Slabs ContactModule::slabs(const ParticleStore& p) const {
  // Slabs along the longest side of the particles' bounding box, each at least one
  // interaction range (2 r_max + skin) wide, so listed partners are in the same or the
  // neighbouring slab. The slab count depends on the geometry only, never on threads.
  // A periodic axis is never cut (partners across its faces would sit in the first and
  // the last slab); with all three periodic, one slab.
  const std::size_t n = p.size();
  const std::vector<double>* axis_data[3] = {&p.x, &p.y, &p.z};
  Slabs g;
  double rmax = 0.0;
  if (n) {
    for (int a = 0; a < 3; ++a) g.lo[a] = g.hi[a] = (*axis_data[a])[0];
    for (std::size_t i = 0; i < n; ++i) {
      for (int a = 0; a < 3; ++a) {
        g.lo[a] = std::min(g.lo[a], (*axis_data[a])[i]);
        g.hi[a] = std::max(g.hi[a], (*axis_data[a])[i]);
      }
      rmax = std::max(rmax, p.radius[i]);
    }
  }
  int axis = -1;
  for (int a = 0; a < 3; ++a)
    if (!box_.on[a] && (axis < 0 || g.hi[a] - g.lo[a] > g.hi[axis] - g.lo[axis])) axis = a;
  const bool cut = axis >= 0;
  g.axis = cut ? axis : 0;
  g.range = 2.0 * rmax + skin_;
  const double extent = cut ? g.hi[g.axis] - g.lo[g.axis] : 0.0;
  g.count = g.range > 0.0
                ? std::max<std::size_t>(1, std::min<std::size_t>(4096, static_cast<std::size_t>(extent / g.range)))
                : 1;
  g.width = g.count > 1 ? extent / static_cast<double>(g.count) : 1.0;
  return g;
}

std::size_t ContactModule::thread_first_slab(std::size_t t, std::size_t nt) const {
  const std::size_t nslab = slab_cost_.empty() ? 0 : slab_cost_.size() - 1;
  if (t >= nt) return nslab;
  // The first slab that starts at or after thread t's share of the estimated cost.
  const std::uint64_t at = slab_cost_.empty() ? 0 : slab_cost_.back() * t / nt;
  return static_cast<std::size_t>(std::lower_bound(slab_cost_.begin(), slab_cost_.begin() + nslab, at) -
                                  slab_cost_.begin());
}

std::pair<std::size_t, std::size_t> ContactModule::thread_slabs() const {
  const auto [t, nt] = thread_id();
  return {thread_first_slab(t, nt), thread_first_slab(t + 1, nt)};
}

std::vector<std::uint32_t> ContactModule::spatial_order(const ParticleStore& p) const {
  const std::size_t n = p.size();
  const Slabs g = slabs(p);
  // Cell coordinates (edge = one interaction range, 21 bits per axis: a wider box only
  // coarsens the order), the slab axis most significant, then the other two.
  const std::vector<double>* data[3] = {&p.x, &p.y, &p.z};
  const int ax[3] = {g.axis, (g.axis + 1) % 3, (g.axis + 2) % 3};
  const double h = g.range > 0.0 ? g.range : 1.0;
  constexpr double cmax = double((1 << 21) - 1);
  std::vector<std::pair<std::uint64_t, std::uint32_t>> key(n);
  parallel_for(n, [&](std::size_t i) {
    std::uint64_t k = 0;
    for (int a : ax) {
      const double c = std::clamp(std::floor(((*data[a])[i] - g.lo[a]) / h), 0.0, cmax);
      k = (k << 21) | static_cast<std::uint64_t>(c);
    }
    key[i] = {k, static_cast<std::uint32_t>(i)};
  });
  std::sort(key.begin(), key.end());
  std::vector<std::uint32_t> from(n);
  for (std::size_t i = 0; i < n; ++i) from[i] = key[i].second;
  return from;
}

void ContactModule::permute(const std::vector<std::uint32_t>& from) {
  const std::size_t n = from.size();
  if (x0_.size() != n) return;  // nothing listed yet: the next evaluation builds
  std::vector<std::uint32_t> to(n);
  for (std::size_t i = 0; i < n; ++i) to[from[i]] = static_cast<std::uint32_t>(i);
  // Pairs keep i < j: a pair whose order flips has its history seen from the other
  // particle, the tangential displacement of j relative to i (the negative).
  for (std::size_t k = 0; k < pi_.size(); ++k) {
    std::uint32_t i = to[pi_[k]], j = to[pj_[k]];
    if (i > j) {
      std::swap(i, j);
      if (friction_) hist_[k] = -hist_[k];
    }
    pi_[k] = i;
    pj_[k] = j;
  }
  auto rows = [&](auto& v) {
    const std::size_t w = walls_.size();
    if (!w || v.size() != n * w) return;
    auto out = v;
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t c = 0; c < w; ++c) out[i * w + c] = v[from[i] * w + c];
    v.swap(out);
  };
  rows(wall_hist_);
  rows(wall_touch_);
  rows(fn_wall_);
  std::vector<double> tmp;
  for (auto* v : {&x0_, &y0_, &z0_}) permute_array(*v, from, tmp);
  wall_candidates_stale_ = true;  // listed again, in the new order, from x0_
}

void ContactModule::rebuild(const ParticleStore& p) {
  const std::size_t n = p.size();
  // The rebuild sets the run's peak memory, so what it keeps alive at once is kept
  // small. First the history to carry over: only the pairs in contact have any (a pair
  // not in contact starts afresh), so their partner and history are set apart, by
  // particle i (a counting sort, stable: row i is [carry_first[i], carry_first[i+1])),
  // and the old list is released before the new one is built.
  std::vector<std::uint32_t> carry_first, carry_j;
  std::vector<Vec3> carry_hist;
  if (friction_ && built_ && !pi_.empty()) {
    const std::size_t rows = std::max(n, x0_.size());
    carry_first.assign(rows + 1, 0);
    for (std::size_t k = 0; k < pi_.size(); ++k)
      if (touch_[k]) ++carry_first[pi_[k] + 1];
    for (std::size_t r = 0; r < rows; ++r) carry_first[r + 1] += carry_first[r];
    carry_j.resize(carry_first[rows]);
    carry_hist.resize(carry_first[rows]);
    std::vector<std::uint32_t> fill(carry_first.begin(), carry_first.end() - 1);
    for (std::size_t k = 0; k < pi_.size(); ++k)
      if (touch_[k]) {
        const std::uint32_t at = fill[pi_[k]]++;
        carry_j[at] = pj_[k];
        carry_hist[at] = hist_[k];
      }
  }
  const std::size_t last_size = pi_.size();
  std::vector<std::uint32_t>().swap(pi_);
  std::vector<std::uint32_t>().swap(pj_);
  std::vector<Vec3>().swap(hist_);
  std::vector<std::uint8_t>().swap(touch_);
  // The candidates live only while the list is built, and are released before the
  // history is carried over. Reserved at the last list's size plus a margin, so that
  // they rarely grow by doubling. One chunk per thread (each lists its own particles'
  // pairs), in (i, j) order chunk after chunk.
  std::vector<std::vector<ContactPair>> candidates;
  search_.find_contacts(p, skin_, candidates, box_, last_size + last_size / 8 + 64);
  // Two fixed particles never move: their contact does nothing, so it is not listed.
  std::size_t listed = 0;
  for (auto& chunk : candidates) {
    chunk.erase(std::remove_if(chunk.begin(), chunk.end(),
                               [&](const ContactPair& c) { return p.inv_mass[c.i] == 0.0 && p.inv_mass[c.j] == 0.0; }),
                chunk.end());
    listed += chunk.size();
  }

  const Slabs g = slabs(p);
  const std::size_t nslab = g.count;
  const double width = g.width;
  const std::vector<double>* axis_data[3] = {&p.x, &p.y, &p.z};
  const std::vector<double>& c = *axis_data[g.axis];
  const double lo_axis = g.lo[g.axis];
  auto slab_of = [&](std::uint32_t i) {
    if (nslab == 1) return std::size_t{0};
    return std::min(nslab - 1, static_cast<std::size_t>((c[i] - lo_axis) / width));
  };

  // Counting sort of the pairs by owner slab (the lower of the two), keeping (i, j) order.
  std::vector<std::uint32_t> start(nslab + 1, 0), owner(listed);
  {
    std::size_t k = 0;
    for (const auto& chunk : candidates)
      for (const ContactPair& cp : chunk) {
        owner[k] = static_cast<std::uint32_t>(std::min(slab_of(cp.i), slab_of(cp.j)));
        ++start[owner[k++] + 1];
      }
  }
  for (std::size_t s = 0; s < nslab; ++s) start[s + 1] += start[s];
  std::vector<std::uint32_t> pi(listed), pj(listed);
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    std::size_t k = 0;
    for (auto& chunk : candidates) {
      for (const ContactPair& cp : chunk) {
        const std::uint32_t at = fill[owner[k++]]++;
        pi[at] = cp.i;
        pj[at] = cp.j;
      }
      std::vector<ContactPair>().swap(chunk);
    }
  }
  std::vector<std::vector<ContactPair>>().swap(candidates);
  std::vector<std::uint32_t>().swap(owner);
  if (friction_) {
    // Carry the history of every pair in contact at the last evaluation (each is in
    // both lists): a new pair looks for its j among the few carried pairs of its i.
    std::vector<Vec3> hist(pi.size());
    std::vector<std::uint8_t> touch(pi.size(), 0);
    if (!carry_j.empty()) {
      for (std::size_t k = 0; k < pi.size(); ++k) {
        const std::uint32_t i = pi[k], j = pj[k];
        for (std::uint32_t q = carry_first[i]; q < carry_first[i + 1]; ++q) {
          if (carry_j[q] != j) continue;
          hist[k] = carry_hist[q];
          touch[k] = 1;
          break;
        }
      }
    }
    hist_.swap(hist);
    touch_.swap(touch);
    if (wall_hist_.size() != n * walls_.size()) {
      wall_hist_.assign(n * walls_.size(), Vec3{});
      wall_touch_.assign(n * walls_.size(), 0);
    }
  }
  pi_.swap(pi);
  pj_.swap(pj);
  slab_start_.swap(start);
  slab_active_.assign(nslab, 0);  // the new slabs' contacts are not known yet
  x0_ = p.x; y0_ = p.y; z0_ = p.z;
  built_ = true;
  ++builds_;
  drift_bound_ = 0.0;
  list_wall_candidates(p);
  tabulate_damping(p);
}

void ContactModule::tabulate_damping(const ParticleStore& p) {
  // Masses change only when particles are added, and that rebuilds the list.
  damping_stale_ = false;
  eta_n_common_.clear();
  const std::size_t n = p.size();
  std::size_t i = 0;
  while (i < n && p.inv_mass[i] == 0.0) ++i;
  if (i == n) return;
  const double m = p.mass[i];
  bool same = true;
  for (; i < n; ++i) same &= p.inv_mass[i] == 0.0 || p.mass[i] == m;
  if (!same) return;
  // The expressions of the per-contact path, so the values are the same to the bit.
  const std::size_t nmat = pairs_.size();
  eta_n_common_.resize(2 * nmat * nmat);
  for (std::size_t a = 0; a < nmat; ++a)
    for (std::size_t b = 0; b < nmat; ++b) {
      const PairParams& pp = pairs_.get(static_cast<int>(a), static_cast<int>(b));
      eta_n_common_[2 * (a * nmat + b)] = normal_damping(pp, effective_mass(m, m));  // two free particles
      eta_n_common_[2 * (a * nmat + b) + 1] = normal_damping(pp, m);             // one of them fixed
    }
}

namespace {
/// The larger overlap, ties broken by the lower particle then partner index, so the
/// record does not depend on the order threads report in.
bool worse(const OverlapRecord& a, const OverlapRecord& b) {
  if (a.ratio != b.ratio) return a.ratio > b.ratio;
  if (a.particle != b.particle) return a.particle < b.particle;
  return a.partner < b.partner;
}

// Force on i for one contact (j's force is its negative) under force law @p Law; j may
// be a wall. @p hist and @p touch are the contact's tangential history slot; @p m_eff
// and @p r_star are used by Hertz–Mindlin only, @p eta_n_lin (the normal damping η_n,
// from m*) by the linear law only. Writes the normal force magnitude to @p fn_mag if given.
// @p vrel is the relative contact velocity the forces are evaluated at; @p vrel_step
// the one the positions moved with over the last step (Hertz–Mindlin's history).
template <ContactLaw Law, bool Friction>
inline void resolve_contact(double dt, double overlap, Vec3 eta, Vec3 vrel, Vec3 vrel_step, const PairParams& pp,
                            double m_eff, double eta_n_lin, double r_star, Vec3& hist, std::uint8_t& touch, Vec3& f_out,
                            Vec3& ft_out, double* fn_mag) {
  if constexpr (Law == ContactLaw::linear_spring_dashpot) {
    (void)r_star; (void)m_eff;
    const double eta_n = eta_n_lin;
    const double vn_mag = dot(vrel, eta);
    const Vec3 vn = vn_mag * eta;
    // Eq 10 along η: F_n = −(k_n δ + η_n V_ij·η) η, so |F_n| is that scalar's magnitude,
    // with no square root heading the Coulomb test.
    const double fn_along = -(pp.kn * overlap + eta_n * vn_mag);
    const Vec3 fn = fn_along * eta;
    const double fn_abs = std::abs(fn_along);
    f_out = fn;
    if (fn_mag) *fn_mag = fn_abs;
    if constexpr (Friction) {
      const Vec3 vt = vrel - vn;
      // The history follows the displacement the contact points actually made over the
      // step (see ContactModule::set_step_velocities), as for Hertz–Mindlin.
      const double vs_n = dot(vrel_step, eta);
      // Held in a local: read back through the reference after the byte store to touch
      // (a char may alias anything), it would be stored and loaded again.
      const Vec3 h = contact::update_tangential_displacement(hist, touch == 0, vrel_step - vs_n * eta, std::abs(vs_n),
                                                             overlap, dt, eta);
      hist = h;
      touch = 1;
      const double kt = pp.kt_factor * pp.kn;
      const double eta_t = pp.etat_factor * eta_n;
      ft_out = contact::tangential_force(kt, eta_t, pp.mu, fn_abs, h, vt);
      f_out += ft_out;
    } else {
      (void)hist; (void)touch; (void)dt;
      ft_out = Vec3{};
    }
  } else {
    (void)eta_n_lin;
    // Hertz–Mindlin (contact/hertz_mindlin.hpp), with √R* and √δ taken once:
    // K = 4/3 E* √R*, F_n = −(K √δ) δ η − η_n V_n, η_n = α √(m* K √δ), k_t = 8 G* √R* √δ.
    const double sqrt_r = std::sqrt(r_star), sqrt_d = std::sqrt(overlap);
    const double k_hertz = 4.0 / 3.0 * pp.e_star * sqrt_r;
    const double eta_n = pp.hertz_alpha * std::sqrt(m_eff * k_hertz * sqrt_d);
    const double vn_mag = dot(vrel, eta);
    const Vec3 vn = vn_mag * eta;
    const Vec3 fn = contact::normal_force(k_hertz * sqrt_d, eta_n, overlap, eta, vn);
    f_out = fn;
    const double fn_abs = norm(fn);
    if (fn_mag) *fn_mag = fn_abs;
    if constexpr (Friction) {
      const Vec3 vt = vrel - vn;
      // The history follows the tangential displacement the contact points actually
      // made over the step (see ContactModule::set_step_velocities).
      const double vs_n = dot(vrel_step, eta);
      Vec3 h = contact::update_tangential_displacement(hist, touch == 0, vrel_step - vs_n * eta, std::abs(vs_n),
                                                       overlap, dt, eta);
      const double kt = 8.0 * pp.g_star * sqrt_r * sqrt_d;
      const double eta_t = pp.etat_hertz_factor * eta_n;
      ft_out = contact::mindlin_tangential_force(kt, eta_t, pp.mu, fn_abs, h, vt);
      hist = h;  // after the force, which may rescale the history (contact/hertz_mindlin.hpp)
      touch = 1;
      f_out += ft_out;
    } else {
      (void)hist; (void)touch; (void)dt; (void)vrel_step;
      ft_out = Vec3{};
    }
  }
}

}  // namespace

template <bool Friction, ContactModule::Laws L, bool Record>
void ContactModule::add_forces_impl(ParticleStore& p, double dt) {
  auto resolve = [dt](double overlap, Vec3 eta, Vec3 vrel, Vec3 vrel_step, const PairParams& pp, double m_eff,
                      double eta_n_lin, double r_star, Vec3& hist, std::uint8_t& touch, Vec3& f_out, Vec3& ft_out,
                      double* fn_mag) {
    if constexpr (L == Laws::linear)
      resolve_contact<ContactLaw::linear_spring_dashpot, Friction>(dt, overlap, eta, vrel, vrel_step, pp, m_eff, eta_n_lin,
                                                                   r_star, hist, touch, f_out, ft_out, fn_mag);
    else if constexpr (L == Laws::hertz)
      resolve_contact<ContactLaw::hertz_mindlin, Friction>(dt, overlap, eta, vrel, vrel_step, pp, m_eff, eta_n_lin, r_star,
                                                           hist, touch, f_out, ft_out, fn_mag);
    else if (pp.law == ContactLaw::hertz_mindlin)
      resolve_contact<ContactLaw::hertz_mindlin, Friction>(dt, overlap, eta, vrel, vrel_step, pp, m_eff, eta_n_lin, r_star,
                                                           hist, touch, f_out, ft_out, fn_mag);
    else
      resolve_contact<ContactLaw::linear_spring_dashpot, Friction>(dt, overlap, eta, vrel, vrel_step, pp, m_eff, eta_n_lin,
                                                                   r_star, hist, touch, f_out, ft_out, fn_mag);
  };
  // Whether pair parameters @p pp take the linear law's η_n (the others take m*).
  auto linear_law = [](const PairParams& pp) {
    return L == Laws::linear || (L == Laws::mixed && pp.law == ContactLaw::linear_spring_dashpot);
  };
  constexpr bool record = Record;
  // Velocities the positions moved with over the last step, where the integrator keeps
  // them apart from v (velocity Verlet); before the first step, v itself.
  const bool step_vel = Friction && step_.vx && step_.vx->size() == p.size() &&
                        step_.wx && step_.wx->size() == p.size();
  auto step_velocity = [&](std::uint32_t i) {
    return step_vel ? Vec3{(*step_.vx)[i], (*step_.vy)[i], (*step_.vz)[i]} : p.velocity(i);
  };
  auto step_spin = [&](std::uint32_t i) {
    return step_vel ? Vec3{(*step_.wx)[i], (*step_.wy)[i], (*step_.wz)[i]} : p.angular_velocity(i);
  };

  // Particle–particle, slab by slab: even slabs in parallel, then odd ones, each thread
  // in its own run of slabs (thread_slabs; see the class comment).
  const std::size_t nslab = slab_start_.empty() ? 0 : slab_start_.size() - 1;
  const std::size_t n = p.size();
  const bool threads = n > parallel_threshold;
  const bool periodic = box_.any();
  const bool prefetch =
      prefetch_ == Prefetch::on || (prefetch_ == Prefetch::automatic && p.bytes() > last_level_cache_bytes());
  prefetched_ = prefetch;
  std::size_t active = 0;
  OverlapRecord worst;
  auto pair_range = [&](std::uint32_t k0, std::uint32_t k1, std::size_t& my_active, OverlapRecord& my_worst) {
    Vec3 no_hist;
    std::uint8_t no_touch = 0;
    // The arrays' data pointers held in locals: the stores below (a byte among them,
    // which may alias anything) would otherwise make the compiler load each vector's
    // pointer again for every access.
    const std::uint32_t* const PI = pi_.data();
    const std::uint32_t* const PJ = pj_.data();
    const double *const X = p.x.data(), *const Y = p.y.data(), *const Z = p.z.data();
    const double *const VX = p.vx.data(), *const VY = p.vy.data(), *const VZ = p.vz.data();
    const double *const WX = p.wx.data(), *const WY = p.wy.data(), *const WZ = p.wz.data();
    const double *const R = p.radius.data(), *const M = p.mass.data(), *const IM = p.inv_mass.data();
    const int* const MAT = p.material.data();
    double *const FX = p.fx.data(), *const FY = p.fy.data(), *const FZ = p.fz.data();
    double *const TX = p.tx.data(), *const TY = p.ty.data(), *const TZ = p.tz.data();
    Vec3* const HIST = hist_.data();
    std::uint8_t* const TOUCH = touch_.data();
    double* const FN = fn_pair_.data();
    // η_n per material pair when every free particle has one mass (tabulate_damping).
    const double* const ETA_N = eta_n_common_.empty() ? nullptr : eta_n_common_.data();
    const std::size_t nmat = pairs_.size();
    // Copies, for the same reason: through the closure and `this` the box's flags and
    // periods were loaded again for every listed pair.
    const PeriodicBox box = box_;
    const bool wrap = periodic;
    std::size_t active = 0;  // counted here, not through the reference, for the same reason
    // Three passes per block of listed pairs. The first finds the pairs in contact without
    // a branch (in a flowing bed about half the listed pairs are, in no pattern a
    // predictor can learn, so a branch per pair mispredicts often), forgets the history
    // of the others and keeps the separations of the touching ones; the second takes
    // their geometry; the third resolves them in list order, so forces sum in the same
    // order as a single pass would.
    constexpr std::uint32_t block = 128;
    // Pairs below this one prefetch the partner of the pair `ahead` further on (see
    // ContactModule::Prefetch); with prefetching off, none.
    constexpr std::uint32_t ahead = 128;
    const std::uint32_t prefetch_end = prefetch && k1 - k0 > ahead ? k1 - ahead : k0;
    std::uint32_t hit[block];
    double hdx[block], hdy[block], hdz[block];   // separations, then unit normals
    double hov[block], hli[block], hlj[block];   // overlaps and lever arms
    double hvx[block], hvy[block], hvz[block];   // relative velocities at the contact points
    for (std::uint32_t b0 = k0; b0 < k1; b0 += block) {
      const std::uint32_t b1 = std::min(k1, b0 + block);
      std::uint32_t nhit = 0;
      for (std::uint32_t k = b0; k < b1; ++k) {
        const std::uint32_t i = PI[k], j = PJ[k];
        if (k < prefetch_end) {  // the partner only: the i run in order, which the hardware follows
          const std::uint32_t jf = PJ[k + ahead];
          __builtin_prefetch(X + jf);
          __builtin_prefetch(Y + jf);
          __builtin_prefetch(Z + jf);
          __builtin_prefetch(R + jf);
        }
        Vec3 d{X[j] - X[i], Y[j] - Y[i], Z[j] - Z[i]};
        if (wrap) d = box.min_image(d);
        const double reach = R[i] + R[j];
        const double d2 = dot(d, d);
        // Not "d2 < reach²": a NaN separation counts as a contact, and its NaN force is
        // caught by the integrator's finiteness check, as before.
        const bool touching = !(d2 >= reach * reach);
        hit[nhit] = k; hdx[nhit] = d.x; hdy[nhit] = d.y; hdz[nhit] = d.z;
        nhit += touching;
        if constexpr (Friction)  // contact over: history forgotten
          TOUCH[k] &= static_cast<std::uint8_t>(-static_cast<int>(touching));
        if constexpr (record) FN[k] = -1.0;  // overwritten below if in contact
      }
      active += nhit;
      // The contacts' geometry first, in a loop of its own: its square root and two
      // divisions per contact, independent from one contact to the next, overlap in the
      // processor, instead of each heading the long chain of its contact's force law.
      for (std::uint32_t h = 0; h < nhit; ++h) {
        const std::uint32_t k = hit[h];
        const std::uint32_t i = PI[k], j = PJ[k];
        const double ri = R[i], rj = R[j];
        const Vec3 d{hdx[h], hdy[h], hdz[h]};
        const double dist = std::sqrt(dot(d, d));
        const Vec3 eta = (1.0 / dist) * d;
        hdx[h] = eta.x; hdy[h] = eta.y; hdz[h] = eta.z;
        hov[h] = ri + rj - dist;
        const double Li = (dist * dist + ri * ri - rj * rj) / (2.0 * dist);  // lever arms (eq 7)
        const double Lj = dist - Li;
        hli[h] = Li; hlj[h] = Lj;
        Vec3 vrel{VX[i] - VX[j], VY[i] - VY[j], VZ[i] - VZ[j]};
        if constexpr (Friction) vrel += cross(Li * Vec3{WX[i], WY[i], WZ[i]} + Lj * Vec3{WX[j], WY[j], WZ[j]}, eta);
        hvx[h] = vrel.x; hvy[h] = vrel.y; hvz[h] = vrel.z;
      }
      for (std::uint32_t h = 0; h < nhit; ++h) {
        const std::uint32_t k = hit[h];
        const std::uint32_t i = PI[k], j = PJ[k];
        const double ri = R[i], rj = R[j];
        const double overlap = hov[h];
        const Vec3 eta{hdx[h], hdy[h], hdz[h]};
        const double Li = hli[h], Lj = hlj[h];
        const Vec3 vrel{hvx[h], hvy[h], hvz[h]};
        const PairParams& pp = pairs_.get(MAT[i], MAT[j]);
        Vec3 vrel_step = vrel;
        if constexpr (Friction && L != Laws::linear)
          if (L == Laws::hertz || pp.law == ContactLaw::hertz_mindlin)
            vrel_step = step_velocity(i) - step_velocity(j) + cross(Li * step_spin(i) + Lj * step_spin(j), eta);
        // A fixed particle is a body of infinite mass: m* is the other's mass.
        const bool one_fixed = IM[i] == 0.0 || IM[j] == 0.0;
        double m_eff = 0.0, eta_n = 0.0;
        if (linear_law(pp) && ETA_N)
          eta_n = ETA_N[2 * (static_cast<std::size_t>(MAT[i]) * nmat + static_cast<std::size_t>(MAT[j])) + one_fixed];
        else {
          m_eff = IM[i] == 0.0 ? M[j] : IM[j] == 0.0 ? M[i] : effective_mass(M[i], M[j]);
          if (linear_law(pp)) eta_n = normal_damping(pp, m_eff);
        }
        const double r_star = L == Laws::linear ? 0.0 : ri * rj / (ri + rj);
        double* fn_rec = nullptr;
        if constexpr (record) fn_rec = &FN[k];
        Vec3 f, ft;
        if constexpr (Friction)
          resolve(overlap, eta, vrel, vrel_step, pp, m_eff, eta_n, r_star, HIST[k], TOUCH[k], f, ft, fn_rec);
        else resolve(overlap, eta, vrel, vrel_step, pp, m_eff, eta_n, r_star, no_hist, no_touch, f, ft, fn_rec);
        FX[i] += f.x; FY[i] += f.y; FZ[i] += f.z;
        FX[j] -= f.x; FY[j] -= f.y; FZ[j] -= f.z;
        if constexpr (Friction) {
          const Vec3 tq = cross(eta, ft);  // T_i = L_i η × F_t, T_j = L_j η × F_t
          TX[i] += Li * tq.x; TY[i] += Li * tq.y; TZ[i] += Li * tq.z;
          TX[j] += Lj * tq.x; TY[j] += Lj * tq.y; TZ[j] += Lj * tq.z;
        }
        // The ratio's division only for a contact that may be the worst so far: the test
        // lets through every overlap whose ratio could reach my_worst's (it sits 1e-12
        // below, far beyond the division's rounding), so the record is the same.
        const double r_min = std::min(ri, rj);
        if (overlap >= my_worst.ratio * r_min * (1.0 - 1e-12)) {
          const OverlapRecord rec{overlap / r_min, ri <= rj ? i : j, static_cast<long>(ri <= rj ? j : i)};
          if (worse(rec, my_worst)) my_worst = rec;
        }
      }
    }
    my_active += active;
  };
  if (!threads) {
    // Same order as the threaded path: even slabs, then odd slabs.
    for (std::size_t pass = 0; pass < 2; ++pass)
      for (std::size_t s = pass; s < nslab; s += 2) pair_range(slab_start_[s], slab_start_[s + 1], active, worst);
    slab_active_.clear();  // below the threshold nothing is split among threads
  } else {
    // Each thread's share of the slabs by their estimated cost: a listed pair costs one,
    // a pair in contact at the last evaluation (slab_active_) kTouchCost more (its
    // geometry and force law). Only the split depends on it, never the results.
    if (slab_active_.size() != nslab) slab_active_.assign(nslab, 0);
    slab_cost_.resize(nslab + 1);
    slab_cost_[0] = 0;
    for (std::size_t s = 0; s < nslab; ++s)
      slab_cost_[s + 1] = slab_cost_[s] + (slab_start_[s + 1] - slab_start_[s]) + kTouchCost * slab_active_[s];
#pragma omp parallel
    {
      std::size_t my_active = 0;
      OverlapRecord my_worst;
      const auto [s0, s1] = thread_slabs();
      for (std::size_t pass = 0; pass < 2; ++pass) {
        for (std::size_t s = s0 + ((s0 & 1) != pass); s < s1; s += 2) {
          const std::size_t before = my_active;
          pair_range(slab_start_[s], slab_start_[s + 1], my_active, my_worst);
          slab_active_[s] = static_cast<std::uint32_t>(my_active - before);
        }
        if (pass == 0) {
#pragma omp barrier
        }
      }
#pragma omp critical(cdm_contact_reduce)
      {
        active += my_active;
        if (worse(my_worst, worst)) worst = my_worst;
      }
    }
  }

  // Particle–wall: the wall is a body of infinite mass at rest; m_eff = m_i. Each
  // particle only touches its own force, so particles run in parallel.
  const std::size_t nw = walls_.size();
  // Only the wall candidates (listed at the build) can touch a wall; each is listed once.
  auto wall_range = [&](std::size_t c0, std::size_t c1, std::size_t& my_active, OverlapRecord& my_worst) {
    Vec3 no_hist;
    std::uint8_t no_touch = 0;
    for (std::size_t c = c0; c < c1; ++c) {
      const std::uint32_t i = wall_candidates_[c];
      const std::size_t ii = i;
      for (std::uint32_t q = wall_begin_[c]; q < wall_begin_[c + 1]; ++q) {
        const std::size_t w = wall_ids_[q];
        const PlaneWall& wall = walls_[w];
        const double dist = wall.distance(p.position(i));
        const double overlap = p.radius[i] - dist;
        if (overlap <= 0.0) {
          if constexpr (Friction) wall_touch_[ii * nw + w] = 0;
          if constexpr (record) fn_wall_[ii * nw + w] = -1.0;
          continue;
        }
        ++my_active;
        const Vec3 eta = -wall.normal;  // from the particle towards the wall
        const double Li = dist;         // centre to contact point on the plane
        Vec3 vrel = p.velocity(i);
        if constexpr (Friction) vrel += cross(Li * p.angular_velocity(i), eta);
        const PairParams& pp = pairs_.get(p.material[i], wall.material);
        Vec3 vrel_step = vrel;
        if constexpr (Friction && L != Laws::linear)
          if (L == Laws::hertz || pp.law == ContactLaw::hertz_mindlin)
            vrel_step = step_velocity(i) + cross(Li * step_spin(i), eta);
        double* fn_rec = nullptr;
        if constexpr (record) fn_rec = &fn_wall_[ii * nw + w];
        // Against a wall R* = R_i and m* = m_i.
        const double eta_n = linear_law(pp) ? normal_damping(pp, p.mass[i]) : 0.0;
        Vec3 f, ft;
        if constexpr (Friction)
          resolve(overlap, eta, vrel, vrel_step, pp, p.mass[i], eta_n, p.radius[i], wall_hist_[ii * nw + w],
                  wall_touch_[ii * nw + w], f, ft, fn_rec);
        else resolve(overlap, eta, vrel, vrel_step, pp, p.mass[i], eta_n, p.radius[i], no_hist, no_touch, f, ft, fn_rec);
        p.add_force(i, f);
        if constexpr (Friction) p.add_torque(i, Li * cross(eta, ft));
        const OverlapRecord rec{overlap / p.radius[i], i, -1 - static_cast<long>(w)};
        if (worse(rec, my_worst)) my_worst = rec;
      }
    }
  };
  const std::size_t nc = wall_candidates_.size();
  if (nw && !threads) {
    wall_range(0, nc, active, worst);
  } else if (nw) {
#pragma omp parallel
    {
      std::size_t my_active = 0;
      OverlapRecord my_worst;
      // The candidates among the particles this thread moves in the integrator's pass
      // (thread_range): their forces are in its cache.
      const auto [i0, i1] = thread_range(n);
      const auto c0 = std::lower_bound(wall_candidates_.begin(), wall_candidates_.end(), i0);
      const auto c1 = std::lower_bound(c0, wall_candidates_.end(), i1);
      wall_range(static_cast<std::size_t>(c0 - wall_candidates_.begin()),
                 static_cast<std::size_t>(c1 - wall_candidates_.begin()), my_active, my_worst);
#pragma omp critical(cdm_contact_reduce)
      {
        active += my_active;
        if (worse(my_worst, worst)) worst = my_worst;
      }
    }
  }
  n_active_ = active;
  worst_ = worst;
}

void RollingResistanceModule::add_forces(ParticleStore& p, double dt) {
  const PairTable& pairs = c_.pairs();
  const std::vector<std::uint32_t>& pi = c_.list_i();
  const std::vector<std::uint32_t>& pj = c_.list_j();
  const std::vector<std::uint32_t>& slab_start = c_.slab_start();
  const std::vector<double>& fn_pair = c_.pair_normal_force();
  const std::vector<double>& fn_wall = c_.wall_normal_force();
  const std::vector<PlaneWall>& walls = c_.walls();
  const std::size_t n = p.size(), nw = walls.size();
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
      const Vec3 d = c_.periodic_box().min_image(p.position(j) - p.position(i));
      const Vec3 eta = (1.0 / norm(d)) * d;
      const double ri = p.radius[i], rj = p.radius[j];
      const double inertia_eff = 1.0 / (p.inv_inertia[i] + p.inv_inertia[j]);
      const Vec3 t = contact::rolling_torque(pp.rolling_mu, ri * rj / (ri + rj), fn_pair[k],
                                             free_spin(i) - free_spin(j), eta, inertia_eff, dt);
      p.add_torque(i, t);
      p.add_torque(j, -t);
    }
  };
  // The contact module's slab order: even slabs, then odd slabs (see ContactModule), so
  // the contacts of a particle are visited in the same order for any thread count.
  const std::size_t nslab = slab_start.empty() ? 0 : slab_start.size() - 1;
  for (std::size_t pass = 0; pass < 2; ++pass) {
    if (!threads) {
      for (std::size_t s = pass; s < nslab; s += 2) pair_range(slab_start[s], slab_start[s + 1]);
      continue;
    }
    const long jobs = static_cast<long>((nslab + 1 - pass) / 2);
#pragma omp parallel for schedule(dynamic, 1)
    for (long t = 0; t < jobs; ++t) {
      const std::size_t s = pass + 2 * static_cast<std::size_t>(t);
      pair_range(slab_start[s], slab_start[s + 1]);
    }
  }
  if (!nw) return;
  parallel_for(n, [&](std::size_t ii) {
    const auto i = static_cast<std::uint32_t>(ii);
    for (std::size_t w = 0; w < nw; ++w) {
      const double fn = fn_wall[ii * nw + w];
      if (fn < 0.0) continue;
      const PairParams& pp = pairs.get(p.material[i], walls[w].material);
      if (pp.rolling_mu == 0.0) continue;
      // Against a wall: ω_rel = ω_i, R* = R_i, I* = I_i.
      const Vec3 t = contact::rolling_torque(pp.rolling_mu, p.radius[i], fn, free_spin(i), -walls[w].normal,
                                             1.0 / p.inv_inertia[i], dt);
      p.add_torque(i, t);
    }
  });
}

}  // namespace cdm
