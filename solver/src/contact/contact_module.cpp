#include "cdm/solver/contact/contact_module.hpp"

#include <algorithm>
#include <cmath>

#include "cdm/solver/contact/hertz_mindlin.hpp"
#include "cdm/solver/contact/linear_spring_dashpot.hpp"
#include "cdm/solver/parallel.hpp"
#include "cdm/solver/rank_split.hpp"
#include "cdm/solver/platform.hpp"
#include "mesh_pass.hpp"

namespace cdm {

ContactModule::ContactModule(PairTable pairs, std::vector<Wall> walls, bool with_friction, double skin,
                             bool record_normal_forces)
    : pairs_(std::move(pairs)), friction_(with_friction), record_(record_normal_forces), record_vectors_(false),
      spins_shared_(record_normal_forces),
      list_(std::move(walls), with_friction, skin) {
  const bool lin = pairs_.uses(ContactLaw::linear_spring_dashpot), hz = pairs_.uses(ContactLaw::hertz_mindlin);
  laws_ = lin && hz ? LawsPresent::both : hz ? LawsPresent::hertz : LawsPresent::linear;
}

std::string ContactModule::name() const {
  const std::string lin = to_string(ContactLaw::linear_spring_dashpot), hz = to_string(ContactLaw::hertz_mindlin);
  const std::string laws = laws_ == LawsPresent::linear ? lin : laws_ == LawsPresent::hertz ? hz : lin + "," + hz;
  return laws + (friction_ ? "+spring_coulomb" : "");
}

void ContactModule::permute(const std::vector<std::uint32_t>& from) {
  list_.permute(from);
  if (mesh_) mesh_->permute(from);
  if (ranks_) ranks_->permute(from);  // the ownership follows the particles to the next build
}

void ContactModule::add_forces(ParticleStore& p, double dt) {
  worst_ = {};
  n_active_ = 0;
  evaluate(p, dt, update_list(p).walls_listed);
}

VerletList::Update ContactModule::update_list(ParticleStore& p) {
  const VerletList::Update u = list_.update(p);
  if (ranks_ && (u.rebuilt || !ranks_->assigned_for(list_.builds()))) ranks_->assign(list_, p);
  if (u.rebuilt) damping_stale_ = true;
  return u;
}

void ContactModule::evaluate(ParticleStore& p, double dt, bool walls_listed) {
  if (damping_stale_) tabulate_damping(p);
  if (record_) {
    // Per listed pair and per wall entry of the list; the force vectors only for a probe.
    const std::size_t nq = list_.wall_ids().size();
    fn_pair_.resize(list_.size());
    fv_pair_.resize(record_vectors_ ? 6 * list_.size() : 0);
    if (walls_listed) fn_wall_.assign(nq, -1.0);
    else fn_wall_.resize(nq);
    fv_wall_.resize(record_vectors_ ? 3 * nq : 0);
  }
  // One compiled kernel per (friction, laws present, recording): no per-pair dispatch
  // unless both laws are present, and nothing recorded unless a module reads it.
  if (record_) dispatch<true>(p, dt);
  else dispatch<false>(p, dt);
}

template <bool Record>
void ContactModule::dispatch(ParticleStore& p, double dt) {
  switch (laws_) {
    case LawsPresent::linear:
      if (friction_) add_forces_impl<true, LawsPresent::linear, Record>(p, dt);
      else add_forces_impl<false, LawsPresent::linear, Record>(p, dt);
      break;
    case LawsPresent::hertz:
      if (friction_) add_forces_impl<true, LawsPresent::hertz, Record>(p, dt);
      else add_forces_impl<false, LawsPresent::hertz, Record>(p, dt);
      break;
    case LawsPresent::both:
      if (friction_) add_forces_impl<true, LawsPresent::both, Record>(p, dt);
      else add_forces_impl<false, LawsPresent::both, Record>(p, dt);
      break;
  }
}

void ContactModule::set_ranks(RankSplit* r) {
  ranks_ = r;
  if (r && mesh_) r->set_meshes(&*mesh_);
  if (r) {
    // What the pair loops read of a ghost's step velocities (StepVelocities): Hertz–Mindlin
    // friction both particles' velocities and spins, rolling resistance (which reads the
    // recorded normal forces) their spins; the linear law neither.
    const bool hertz_friction = friction_ && laws_ != LawsPresent::linear;
    std::vector<const std::vector<double>*> read;
    if (hertz_friction) read = {step_.vx, step_.vy, step_.vz};
    if (hertz_friction || spins_shared_) read.insert(read.end(), {step_.wx, step_.wy, step_.wz});
    r->set_ghost_extras(read);
  }
  list_.set_search_share(r);
  if (!r) list_.clear_rank_slabs();
}

void ContactModule::tabulate_damping(const ParticleStore& p) {
  // Masses change only when particles are added, and that rebuilds the list. Among MPI
  // processes the others' particles read as fixed here (their masses are zero, rank_split.hpp):
  // what counts is the particles of this process's pairs, its own and its ghosts.
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
[[gnu::always_inline]] inline contact::linear_spring_dashpot::Params linear_params(const PairParams& pp) {
  return {pp.kn, pp.kt_factor, pp.etat_factor, pp.mu};
}

[[gnu::always_inline]] inline contact::hertz_mindlin::Params hertz_params(const PairParams& pp) {
  return {pp.e_star, pp.g_star, pp.hertz_alpha, pp.etat_hertz_factor, pp.mu};
}

/// A contact's history as the force law reads and advances it: the list's own, or with
/// @p keep (ContactModule::probe_listed) @p copy of it, so that the list's stays as it is.
struct HistoryCopy {
  Vec3 delta_t;
  std::uint8_t touching;
};
[[gnu::always_inline]] inline contact::TangentialSlot history_slot(Vec3* h, std::uint8_t* t, bool keep,
                                                                   HistoryCopy& copy) {
  if (!keep) return {h, t};
  copy = {*h, *t};
  return {&copy.delta_t, &copy.touching};
}
}  // namespace

template <bool Friction, ContactModule::LawsPresent L, bool Record>
void ContactModule::add_forces_impl(ParticleStore& p, double dt) {
  // Whether pair parameters @p pp take Hertz–Mindlin (the others the linear law).
  auto hertz = [](const PairParams& pp) {
    return L == LawsPresent::hertz || (L == LawsPresent::both && pp.law == ContactLaw::hertz_mindlin);
  };
  // One contact under its pair's law: @p eta_n_lin is the linear law's η_n, @p m_eff and
  // @p r_star are Hertz–Mindlin's.
  auto resolve = [dt, hertz](const PairParams& pp, double m_eff, double eta_n_lin, double r_star,
                             const contact::ContactGeometry& g, contact::TangentialSlot slot)
      __attribute__((always_inline)) {
    if (hertz(pp)) return contact::hertz_mindlin::force<Friction>(hertz_params(pp), m_eff, r_star, g, dt, slot);
    return contact::linear_spring_dashpot::force<Friction>(linear_params(pp), eta_n_lin, g, dt, slot);
  };
  constexpr bool record = Record;
  // A probe's evaluation (always a recording one) leaves every history as it is.
  const bool keep = record && keep_history_;
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
  // in its own run of slabs (VerletList::thread_slabs).
  const std::vector<std::uint32_t>& slab_start = list_.slab_start();
  const std::size_t n = p.size();
  const bool threads = n > parallel_threshold;
  const bool periodic = list_.periodic_box().any();
  const bool prefetch =
      prefetch_ == Prefetch::on || (prefetch_ == Prefetch::automatic && p.bytes() > last_level_cache_bytes());
  prefetched_ = prefetch;
  std::size_t active = 0;
  OverlapRecord worst;
  auto pair_range = [&](std::uint32_t k0, std::uint32_t k1, std::size_t& my_active, OverlapRecord& my_worst) {
    // The arrays' data pointers held in locals: the stores below (a byte among them,
    // which may alias anything) would otherwise make the compiler load each vector's
    // pointer again for every access.
    const std::uint32_t* const PI = list_.pair_i().data();
    const std::uint32_t* const PJ = list_.pair_j().data();
    const double *const X = p.x.data(), *const Y = p.y.data(), *const Z = p.z.data();
    const double *const VX = p.vx.data(), *const VY = p.vy.data(), *const VZ = p.vz.data();
    const double *const WX = p.wx.data(), *const WY = p.wy.data(), *const WZ = p.wz.data();
    const double *const R = p.radius.data(), *const M = p.mass.data(), *const IM = p.inv_mass.data();
    const std::uint8_t* const MAT = p.material.data();
    double *const FX = p.fx.data(), *const FY = p.fy.data(), *const FZ = p.fz.data();
    double *const TX = p.tx.data(), *const TY = p.ty.data(), *const TZ = p.tz.data();
    Vec3* const HIST = list_.pair_history();
    std::uint8_t* const TOUCH = list_.pair_touch();
    double* const FN = fn_pair_.data();
    double* const FV = fv_pair_.empty() ? nullptr : fv_pair_.data();
    // η_n per material pair when every free particle has one mass (tabulate_damping).
    const double* const ETA_N = eta_n_common_.empty() ? nullptr : eta_n_common_.data();
    const std::size_t nmat = pairs_.size();
    // Copies, for the same reason: through the closure and `this` the box's flags and
    // periods were loaded again for every listed pair.
    const PeriodicBox box = list_.periodic_box();
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
          if (!keep) TOUCH[k] &= static_cast<std::uint8_t>(-static_cast<int>(touching));
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
        if constexpr (Friction && L != LawsPresent::linear)
          if (hertz(pp))
            vrel_step = step_velocity(i) - step_velocity(j) + cross(Li * step_spin(i) + Lj * step_spin(j), eta);
        // A fixed particle is a body of infinite mass: m* is the other's mass.
        const bool one_fixed = IM[i] == 0.0 || IM[j] == 0.0;
        double m_eff = 0.0, eta_n = 0.0;
        if (!hertz(pp) && ETA_N)
          eta_n = ETA_N[2 * (static_cast<std::size_t>(MAT[i]) * nmat + static_cast<std::size_t>(MAT[j])) + one_fixed];
        else {
          m_eff = IM[i] == 0.0 ? M[j] : IM[j] == 0.0 ? M[i] : effective_mass(M[i], M[j]);
          if (!hertz(pp)) eta_n = normal_damping(pp, m_eff);
        }
        const double r_star = L == LawsPresent::linear ? 0.0 : ri * rj / (ri + rj);
        contact::TangentialSlot slot;
        HistoryCopy copy;
        if constexpr (Friction) slot = history_slot(HIST + k, TOUCH + k, keep, copy);
        const contact::ContactForce c = resolve(pp, m_eff, eta_n, r_star, {overlap, eta, vrel, vrel_step}, slot);
        const Vec3 f = c.total, ft = c.tangential;
        if constexpr (record) {
          FN[k] = c.normal_magnitude;
          if (FV) {
            double* const fv = FV + 6 * static_cast<std::size_t>(k);
            fv[0] = f.x; fv[1] = f.y; fv[2] = f.z;
            fv[3] = ft.x; fv[4] = ft.y; fv[5] = ft.z;
          }
        }
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
          if (contact::worse_overlap(rec, my_worst)) my_worst = rec;
        }
      }
    }
    my_active += active;
  };
  // This rank's slabs (all of them on one rank, rank_split.hpp), and in its phase the
  // shadow slab below them, the rank below's last: its pairs give this rank's first slab
  // its contributions in the one-rank order. Its contacts are the other rank's to count,
  // and its forces on that rank's particles are dropped (the owner computes them).
  const std::size_t shadow = list_.shadow_slab();
  auto shadow_pairs = [&](std::size_t pass) {
    if (shadow == VerletList::no_slab || (shadow & 1) != pass) return;
    std::size_t not_counted = 0;
    OverlapRecord not_recorded;
    pair_range(slab_start[shadow], slab_start[shadow + 1], not_counted, not_recorded);
  };
  if (!threads) {
    // Same order as the threaded path: even slabs, then odd slabs.
    list_.by_phase([&](std::size_t pass, std::size_t s0, std::size_t s1) {
      for (std::size_t s = s0; s < s1; s += 2) pair_range(slab_start[s], slab_start[s + 1], active, worst);
      shadow_pairs(pass);
    });
    list_.forget_slab_contacts();
  } else {
    list_.weigh_slabs();
#pragma omp parallel
    {
      std::size_t my_active = 0;
      OverlapRecord my_worst;
      const auto [s0, s1] = list_.thread_slabs();
      for (std::size_t pass = 0; pass < 2; ++pass) {
        for (std::size_t s = VerletList::phase_first(s0, pass); s < s1; s += 2) {
          const std::size_t before = my_active;
          pair_range(slab_start[s], slab_start[s + 1], my_active, my_worst);
          list_.set_slab_contacts(s, my_active - before);
        }
        if (thread_id().first == 0) shadow_pairs(pass);
        if (pass == 0) {
#pragma omp barrier
        }
      }
#pragma omp critical(cdm_contact_reduce)
      {
        active += my_active;
        if (contact::worse_overlap(my_worst, worst)) worst = my_worst;
      }
    }
  }

  // Particle–wall: the wall is a body of infinite mass; m_eff = m_i. Its surface moves
  // with the wall's motion (walls.hpp), at the time of the positions. Each particle only
  // touches its own force, so particles run in parallel.
  const std::vector<Wall>& walls = list_.walls();
  const double t_wall = list_.time();
  const std::size_t nw = walls.size();
  const std::vector<std::uint32_t>& candidates = list_.wall_candidates();
  const std::vector<std::uint32_t>& wall_begin = list_.wall_begin();
  const std::vector<std::uint32_t>& wall_ids = list_.wall_ids();
  Vec3* const WHIST = list_.wall_history();
  std::uint8_t* const WTOUCH = list_.wall_touch();
  // One particle–wall contact of overlap > 0: the centre at @p dist from the surface,
  // @p eta the unit normal towards it; a Moving wall's surface velocity @p v_wall at the
  // contact point enters the relative velocity. Its history is the list's entry @p q.
  auto wall_contact = [&]<bool Moving>(std::uint32_t i, std::size_t w, std::size_t q, const Wall& wall, double dist,
                                      double overlap, Vec3 eta, Vec3 v_wall, OverlapRecord& my_worst)
                                      __attribute__((always_inline)) {
    const double Li = dist;  // centre to contact point on the surface
    Vec3 vrel = p.velocity(i);
    if constexpr (Moving) vrel -= v_wall;
    if constexpr (Friction) vrel += cross(Li * p.angular_velocity(i), eta);
    const PairParams& pp = pairs_.get(p.material[i], wall.material);
    Vec3 vrel_step = vrel;
    if constexpr (Friction && L != LawsPresent::linear)
      if (hertz(pp)) {
        vrel_step = step_velocity(i) + cross(Li * step_spin(i), eta);
        if constexpr (Moving) vrel_step -= v_wall;
      }
    // Against a wall R* = R_i and m* = m_i.
    const double eta_n = !hertz(pp) ? normal_damping(pp, p.mass[i]) : 0.0;
    contact::TangentialSlot slot;
    HistoryCopy copy;
    if constexpr (Friction) slot = history_slot(WHIST + q, WTOUCH + q, keep, copy);
    const contact::ContactForce cf = resolve(pp, p.mass[i], eta_n, p.radius[i], {overlap, eta, vrel, vrel_step}, slot);
    const Vec3 f = cf.total, ft = cf.tangential;
    if constexpr (record) {
      fn_wall_[q] = cf.normal_magnitude;
      if (!fv_wall_.empty()) {
        double* const fv = &fv_wall_[3 * q];
        fv[0] = f.x; fv[1] = f.y; fv[2] = f.z;
      }
    }
    p.add_force(i, f);
    if constexpr (Friction) p.add_torque(i, Li * cross(eta, ft));
    const OverlapRecord rec{overlap / p.radius[i], i, -1 - static_cast<long>(w)};
    if (contact::worse_overlap(rec, my_worst)) my_worst = rec;
  };
  const std::uint8_t* const own = ranks_ ? ranks_->owned().data() : nullptr;
  // Only the wall candidates (listed at the build) can touch a wall; each is listed once.
  // Compiled twice: with General false (every wall a plane at rest, the common scene)
  // the loop is the plane loop alone, no other shape's code in it.
  auto wall_range = [&]<bool General>(std::size_t c0, std::size_t c1, std::size_t& my_active, OverlapRecord& my_worst) {
    for (std::size_t c = c0; c < c1; ++c) {
      const std::uint32_t i = candidates[c];
      if (own && !own[i]) continue;  // another rank's particle
      for (std::uint32_t q = wall_begin[c]; q < wall_begin[c + 1]; ++q) {
        const std::size_t w = wall_ids[q];
        const Wall& wall = walls[w];
        // A plane at rest inline (the common wall, as cheap as ever); other walls through
        // their closest point and surface velocity.
        const bool still_plane =
            !General || (wall.shape == WallShape::plane && wall.motion.kind == WallMotion::Kind::none);
        WallGap g;
        if (still_plane) {
          g.gap = wall.distance(p.position(i));
        } else if constexpr (General) {
          g = wall.gap(p.position(i), p.radius[i]);
        }
        const double overlap = p.radius[i] - g.gap;
        if (overlap <= 0.0) {
          if constexpr (Friction)
            if (!keep) WTOUCH[q] = 0;
          if constexpr (record) fn_wall_[q] = -1.0;
          continue;
        }
        ++my_active;
        if (still_plane) {
          wall_contact.template operator()<false>(i, w, q, wall, g.gap, overlap, -wall.normal, Vec3{}, my_worst);
        } else if constexpr (General) {
          const Vec3 eta = -g.normal;  // from the particle towards the wall
          const Vec3 v_wall = wall.surface_velocity(p.position(i) + g.gap * eta, t_wall);
          wall_contact.template operator()<true>(i, w, q, wall, g.gap, overlap, eta, v_wall, my_worst);
        }
      }
    }
  };
  const bool general = !list_.still_planes();
  auto walls_of = [&](std::size_t c0, std::size_t c1, std::size_t& my_active, OverlapRecord& my_worst) {
    if (general) wall_range.template operator()<true>(c0, c1, my_active, my_worst);
    else wall_range.template operator()<false>(c0, c1, my_active, my_worst);
  };
  const std::size_t nc = candidates.size();
  if (nw && !threads) {
    walls_of(0, nc, active, worst);
  } else if (nw) {
#pragma omp parallel
    {
      std::size_t my_active = 0;
      OverlapRecord my_worst;
      // The candidates among the particles this thread moves in the integrator's pass
      // (thread_range): their forces are in its cache.
      const auto [i0, i1] = thread_range(n);
      const auto c0 = std::lower_bound(candidates.begin(), candidates.end(), i0);
      const auto c1 = std::lower_bound(c0, candidates.end(), i1);
      walls_of(static_cast<std::size_t>(c0 - candidates.begin()), static_cast<std::size_t>(c1 - candidates.begin()),
               my_active, my_worst);
#pragma omp critical(cdm_contact_reduce)
      {
        active += my_active;
        if (contact::worse_overlap(my_worst, worst)) worst = my_worst;
      }
    }
  }
  if (mesh_) mesh_pass<Friction, L>(p, resolve, hertz, step_velocity, step_spin, active, worst);
  if (ranks_) ranks_->reduce_contacts(worst, active);
  n_active_ = active;
  worst_ = worst;
}

}  // namespace cdm
