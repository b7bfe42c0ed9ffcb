/// @file integrator.cpp
/// @brief The integrator and the time-step rule: dt from the shortest collision time, the Rayleigh time and the gas step.
#include "sections.hpp"

#include "cdm/solver/contact/dashpot_limit.hpp"
#include "cdm/solver/coupling/substeps.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

namespace cdm::scene {

void read_integrator(const Reader& rd, SceneSpec& spec) {
  const toml::table* t = rd.table(rd.root(), "integrator", "", true);
  rd.check_keys(*t, "integrator", "integrator");
  // Tracers move with the gas by a Runge–Kutta scheme; particles by the others.
  const bool tracers = spec.tracers;
  const auto allowed = [tracers](IntegratorScheme s) {
    return (s == IntegratorScheme::rk2 || s == IntegratorScheme::rk4) == tracers;
  };
  const std::string note = tracers ? " (tracers move with the gas)" : "";
  if (!t->get("scheme")) rd.fail_missing("integrator.scheme", keyword_list(integrator_keywords, allowed) + note);
  spec.integrator =
      rd.keyword(*t, "scheme", "integrator", integrator_keywords, IntegratorScheme::paper_euler, allowed, note);
  if (spec.integrator == IntegratorScheme::exponential_midpoint &&
      (!spec.drag || spec.drag_update != coupling::DragUpdate::exponential ||
       spec.normal_contact))
    rd.fail_value("integrator.scheme", *t->get("scheme"),
                  "\"paper_euler\" or \"velocity_verlet\": \"exponential_midpoint\" is for particles moved by drag without "
                  "contacts (it needs modules.drag with drag.update = \"exponential\" and modules.normal_contact = \"none\"; "
                  "it evaluates the forces twice per step)");
  spec.end_time = rd.positive(*t, "end_time", "integrator", Dim::time, true);
}

void resolve_dt(const Reader& rd, const toml::table* t, SceneSpec& spec) {
  // Hertz–Mindlin pairs have no collision time of their own (it depends on the impact
  // speed): the scene states the largest expected impact speed, or asks for a fraction
  // of the Rayleigh time instead. Either key is refused when no pair is Hertz–Mindlin.
  const bool any_hertz = spec.pairs.uses(ContactLaw::hertz_mindlin);
  const std::string no_hertz = "no [[contacts]] entry uses model hertz_mindlin";
  spec.impact_velocity = 0.0;
  if (t->get("impact_velocity")) {
    if (!any_hertz) rd.reject_unused(*t, "impact_velocity", "integrator", no_hertz);
    spec.impact_velocity = rd.positive(*t, "impact_velocity", "integrator", Dim::velocity, true);
  }

  // Smallest collision time over every pair of materials that can meet: eq 28 for
  // linear pairs, the Hertz time t_H at integrator.impact_velocity for Hertz–Mindlin
  // ones; and the smallest Rayleigh time of the particles in Hertz–Mindlin contacts.
  double t_col = std::numeric_limits<double>::infinity(), t_ray = std::numeric_limits<double>::infinity();
  std::string t_col_pair, t_ray_material;
  double t_col_mass = 0.0;  // the effective mass of the pair with the shortest collision
  double t_dash = std::numeric_limits<double>::infinity();
  std::string t_dash_pair;
  bool hertz_meets = false;
  if (spec.normal_contact) {
    const std::size_t nm = spec.materials.size();
    std::vector<double> m_min(nm, std::numeric_limits<double>::infinity()), r_min(nm, 0.0);
    std::vector<std::size_t> count(nm, 0);
    for (std::size_t i = 0; i < spec.particles.size(); ++i) {
      const ParticleSpec& p = spec.particles[i];
      const double d = 2.0 * p.radius;
      const double m = spec.materials[p.material].density * std::numbers::pi * d * d * d / 6.0;
      if (!std::isnormal(m) && spec.materials[p.material].density > 0.0) {
        // A mass of 0 or infinity makes every collision time 0 or infinite.
        std::ostringstream os;
        os << rd.file() << ": key '" << particle_source(spec, i) << ".radius' = " << p.radius
           << " m (SI) with material '" << spec.materials[p.material].name << "' of density "
           << spec.materials[p.material].density << " kg/m^3 gives a particle mass of " << m
           << " kg, which " << (m > 0.0 ? "overflows" : "underflows")
           << ": expected a radius and a density whose mass pi rho d^3/6 is a normal positive number "
           << "(a particle of about 1e-300 kg to 1e300 kg)";
        throw SceneError(os.str());
      }
      if (m < m_min[p.material]) { m_min[p.material] = m; r_min[p.material] = p.radius; }
      ++count[p.material];
    }
    // Inserted particles: their smallest (the shortest collisions), many of each.
    for (const auto& in : spec.insertions) {
      const double r = in.size.smallest(), d = 2.0 * r;
      const double m = spec.materials[in.material].density * std::numbers::pi * d * d * d / 6.0;
      if (m < m_min[in.material]) { m_min[in.material] = m; r_min[in.material] = r; }
      count[in.material] += 2;
    }
    auto need = [&](int a, int b, const std::string& what) -> const PairParams& {
      const PairParams& pp = spec.pairs.get(a, b);
      if (!pp.defined)
        throw SceneError(rd.file() + ": key 'contacts' has no entry for pair [\"" + spec.materials[a].name + "\", \"" +
                         spec.materials[b].name + "\"]: expected a [[contacts]] entry, because " + what);
      return pp;
    };
    auto rayleigh = [&](std::size_t a) {
      const Material& mat = spec.materials[a];
      const double tr = contact::rayleigh_time(r_min[a], mat.density, mat.youngs_modulus, mat.poisson_ratio);
      if (tr < t_ray) { t_ray = tr; t_ray_material = mat.name; }
    };
    auto consider = [&](const PairParams& pp, double m_eff, double r_star, const std::string& what) {
      double tc = std::numeric_limits<double>::infinity();
      if (pp.law == ContactLaw::linear_spring_dashpot) {
        tc = collision_time(pp, m_eff);
      } else {
        hertz_meets = true;
        if (spec.impact_velocity > 0.0)
          tc = contact::hertz_collision_time(m_eff, r_star, pp.e_star, spec.impact_velocity);
      }
      if (tc < t_col) { t_col = tc; t_col_pair = what; t_col_mass = m_eff; }
      // The explicit dashpot's own step limit (contact/dashpot_limit.hpp), below t_col/10 for small en.
      const double td = contact::dashpot_dt_limit(pp, m_eff, r_star, spec.impact_velocity,
                                                  spec.integrator == IntegratorScheme::velocity_verlet);
      if (td < t_dash) { t_dash = td; t_dash_pair = what; }
    };
    for (std::size_t a = 0; a < nm; ++a) {
      if (!count[a]) continue;
      for (std::size_t b = a; b < nm; ++b) {
        if (!count[b] || (a == b && count[a] < 2)) continue;
        const bool fa = spec.materials[a].fixed, fb = spec.materials[b].fixed;
        if (fa && fb) continue;  // two fixed particles never interact
        const PairParams& pp = need(static_cast<int>(a), static_cast<int>(b),
                                    "particles of both materials are in the scene");
        // A fixed particle is of infinite mass in a contact: m* is the other's mass.
        const double me = fa ? m_min[b] : fb ? m_min[a] : m_min[a] * m_min[b] / (m_min[a] + m_min[b]);
        consider(pp, me, r_min[a] * r_min[b] / (r_min[a] + r_min[b]),
                 spec.materials[a].name + "-" + spec.materials[b].name);
        if (pp.law == ContactLaw::hertz_mindlin) { rayleigh(a); rayleigh(b); }
      }
      for (const auto& w : spec.walls) {
        const PairParams& pp = need(static_cast<int>(a), w.material, "wall '" + w.name + "' can touch particles of material '" + spec.materials[a].name + "'");
        consider(pp, m_min[a], r_min[a], spec.materials[a].name + "-wall '" + w.name + "'");
        if (pp.law == ContactLaw::hertz_mindlin) rayleigh(a);
      }
      for (const auto& m : spec.meshes) {
        const PairParams& pp = need(static_cast<int>(a), m.material, "mesh '" + m.name + "' can touch particles of material '" + spec.materials[a].name + "'");
        consider(pp, m_min[a], r_min[a], spec.materials[a].name + "-mesh '" + m.name + "'");
        if (pp.law == ContactLaw::hertz_mindlin) rayleigh(a);
      }
    }
  }
  spec.t_col_min = std::isfinite(t_col) ? t_col : 0.0;
  spec.rayleigh_time_min = std::isfinite(t_ray) ? t_ray : 0.0;

  const toml::node* dtn = t->get("dt");
  if (!dtn) rd.fail_missing("integrator.dt", "\"auto\" or a time step > 0 [s]");
  if (dtn->is_string()) {
    if (dtn->as_string()->get() != "auto") rd.fail_value("integrator.dt", *dtn, "\"auto\" or a time step > 0 [s]");
    spec.dt_auto = true;
    spec.rayleigh_fraction = 0.0;
    if (t->get("rayleigh_fraction")) {
      if (!any_hertz) rd.reject_unused(*t, "rayleigh_fraction", "integrator", no_hertz);
      spec.rayleigh_fraction = rd.number_in(*t, "rayleigh_fraction", "integrator", Dim::none, true, 0.0, 0.0, true, 1.0,
                                            false, "in (0, 1] (dt = rayleigh_fraction x the smallest Rayleigh time)");
    }
    if (hertz_meets && spec.impact_velocity == 0.0 && spec.rayleigh_fraction == 0.0)
      rd.fail_value("integrator.dt", *dtn,
                    "integrator.impact_velocity (the largest expected impact speed: dt = t_H/dt_divisor with the Hertz "
                    "collision time t_H = 2.868 (m*^2/(R* E*^2 v))^(1/5)) or integrator.rayleigh_fraction (dt = fraction "
                    "x the Rayleigh time) beside dt = \"auto\": a Hertz-Mindlin contact's duration depends on the impact "
                    "speed");
    if (!std::isfinite(t_col) && spec.rayleigh_fraction == 0.0)
      rd.fail_value("integrator.dt", *dtn,
                    "an explicit time step: \"auto\" derives dt from the collision time, and this scene has no contacts");
    if (std::isfinite(t_col)) {
      spec.dt_divisor = rd.number_in(*t, "dt_divisor", "integrator", Dim::none, false, 50.0, 10.0, false,
                                     std::numeric_limits<double>::infinity(), false,
                                     ">= 10 (dt = t_col/dt_divisor; fewer than 10 steps per collision is not resolved)");
      spec.dt = std::min(t_col / spec.dt_divisor, t_dash);
    } else {
      rd.reject_unused(*t, "dt_divisor", "integrator",
                       "no collision time is known (no linear pair meets, and integrator.impact_velocity is not given)");
      spec.dt = std::numeric_limits<double>::infinity();
    }
    if (spec.rayleigh_fraction > 0.0) spec.dt = std::min(spec.dt, spec.rayleigh_fraction * t_ray);
  } else {
    rd.reject_unused(*t, "dt_divisor", "integrator", "integrator.dt is not \"auto\"");
    rd.reject_unused(*t, "rayleigh_fraction", "integrator", "integrator.dt is not \"auto\"");
    spec.dt_auto = false;
    spec.dt = rd.positive(*t, "dt", "integrator", Dim::time, true);
    if (std::isfinite(t_col) && spec.dt > t_col / 10.0) {
      std::ostringstream os;
      os << "a time step <= t_col/10 = " << t_col / 10.0 << " s: the shortest collision (" << t_col_pair
         << ") lasts t_col = " << t_col << " s";
      if (spec.impact_velocity > 0.0) os << " (Hertz pairs at integrator.impact_velocity)";
      os << ", and with fewer than 10 steps per collision the contact force is not resolved (overlaps and "
         << "restitution come out wrong, or the run blows up); use dt = \"auto\" (t_col/50, as Garg et al. 2012) or "
         << "a smaller dt";
      rd.fail_value("integrator.dt", *dtn, os.str());
    }
    if (spec.dt > t_dash) {
      std::ostringstream os;
      os << "a time step <= " << t_dash << " s: the normal dashpot of pair " << t_dash_pair << " makes "
         << to_string(spec.integrator) << " unstable above " << t_dash / contact::dashpot_safety_factor
         << " s, and above " << contact::dashpot_safety_factor << " of that an impact can leave faster than it "
         << "arrived (the limit is of order m_eff/eta_n however long the collision lasts: small en); use a smaller "
         << "dt or dt = \"auto\"";
      rd.fail_value("integrator.dt", *dtn, os.str());
    }
    if (hertz_meets && spec.dt > t_ray) {
      std::ostringstream os;
      os << "a time step <= the Rayleigh time T_R = " << t_ray << " s of material '" << t_ray_material
         << "' (T_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766), the time an elastic surface wave takes across the "
         << "smallest particle): Hertz-Mindlin contact networks are unstable with longer steps (DEM codes use "
         << "0.1-0.3 T_R); use a smaller dt, or dt = \"auto\" with integrator.rayleigh_fraction";
      rd.fail_value("integrator.dt", *dtn, os.str());
    }
  }
  if (!std::isnormal(spec.dt) && !std::isinf(spec.dt)) {
    std::ostringstream os;
    os << "a time step that is a normal floating-point number (>= " << std::numeric_limits<double>::min()
       << " s); it comes out as dt = " << spec.dt << " s";
    if (spec.dt_auto) os << " from the shortest collision time t_col = " << t_col << " s (pair " << t_col_pair << ")";
    rd.fail_value("integrator.dt", *dtn, os.str());
  }
  if (spec.gas == GasModel::solved) {
    // Particles sub-step inside each gas step: a whole number of particle steps.
    const double ratio = spec.gas_dt / spec.dt;
    if (spec.dt_auto) {
      spec.dt = spec.gas_dt / coupling::gas_substeps(spec.gas_dt, spec.dt, true);  // rounded down to divide gas.dt
    } else if (ratio < 1.0 - 1e-9 || std::abs(ratio - std::round(ratio)) > 1e-6 * ratio) {
      std::ostringstream os;
      os << "a particle step that divides gas.dt = " << spec.gas_dt << " s a whole number of times (particles take "
         << "whole sub-steps inside each gas step); gas.dt/dt = " << ratio;
      rd.fail_value("integrator.dt", *dtn, os.str());
    } else {
      spec.dt = spec.gas_dt / coupling::gas_substeps(spec.gas_dt, spec.dt);
    }
  }
  if (spec.dt > spec.end_time) {
    if (!spec.dt_auto) rd.fail_value("integrator.end_time", *t->get("end_time"), "a time >= dt");
    // An automatic step longer than the run comes from an absurd collision time.
    std::ostringstream os;
    os << "a time step below integrator.end_time = " << spec.end_time << " s; \"auto\" gives dt = " << spec.dt << " s";
    if (std::isfinite(t_col))
      os << " from the shortest collision time t_col = " << t_col << " s (pair " << t_col_pair
         << ", effective mass " << t_col_mass << " kg): check the materials' densities, the particles' radii and the "
         << "contacts' kn";
    rd.fail_value("integrator.dt", *dtn, os.str());
  }
  // The step count, before anything casts it to an integer.
  const double steps = step_count(spec.end_time, spec.dt);
  if (steps > max_steps) {
    std::ostringstream os;
    os << "a run of at most " << max_steps << " steps: end_time = " << spec.end_time << " s at dt = " << spec.dt
       << " s" << (spec.dt_auto ? " (integrator.dt = \"auto\", t_col/dt_divisor of pair " + t_col_pair + ")" : "")
       << " needs " << steps << " steps; shorten end_time or use a longer time step (softer contacts)";
    rd.fail_value("integrator.end_time", *t->get("end_time"), os.str());
  }
}

}  // namespace cdm::scene
