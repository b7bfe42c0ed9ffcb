/// @file mesh_contact.cpp
/// @brief Triangle-mesh walls (solver contact/mesh_contacts.hpp).
///
/// mesh_vs_walls: the variant's scene with [[meshes]] against the reference scene of
/// options.reference, the same with plane walls in their place (overrides of meshes[...]
/// apply to the mesh scene only, of walls[...] to the reference only). Where the mesh is the planes (a flat mesh, a concave
/// corner of two planes), every step's position, velocity, spin, force, torque and number
/// of contacts must agree to round-off, over the whole run.
///
/// mesh_impact: an elastic, frictionless impact on a convex edge or vertex of a mesh cube
/// of half-width options.half_width centred at the origin. The kinetic energy after the
/// impact against before (conserved up to the integrator's error, which must fall at its
/// order), and at every step in contact the force's direction against the direction from
/// the cube's closest point to the centre, the closest point computed here by clamping the
/// centre to the cube (the mesh's own closest points are not used).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "cdm/solver/output.hpp"
#include "support.hpp"

namespace cdm::verification::runners {

namespace {

/// One particle's state after a step, and the number of contacts of the last evaluation.
struct Sample {
  double t;
  Vec3 x, v, w, f, tq;
  double contacts;
};

Sample sample(const Simulation& s) {
  const ParticleStore& p = s.particles();
  const bool spin = !p.wx.empty();  // rotation is kept only with friction or rolling
  return {s.time(),
          p.position(0),
          p.velocity(0),
          spin ? p.angular_velocity(0) : Vec3{},
          {p.fx[0], p.fy[0], p.fz[0]},
          spin ? Vec3{p.tx[0], p.ty[0], p.tz[0]} : Vec3{},
          s.contact() ? static_cast<double>(s.contact()->active_contacts()) : 0.0};
}

double peak(const std::vector<Sample>& s, Vec3 Sample::*q) {
  double m = 0.0;
  for (const Sample& x : s) m = std::max(m, norm(x.*q));
  return m;
}

double max_diff(const std::vector<Sample>& a, const std::vector<Sample>& b, Vec3 Sample::*q) {
  double m = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) m = std::max(m, norm(a[k].*q - b[k].*q));
  return m;
}

}  // namespace

RunOutput mesh_vs_walls(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  auto ref_it = c.options.find("reference");
  if (ref_it == c.options.end()) throw std::runtime_error(c.name + ": case.toml needs options.reference (the plane-wall scene)");
  // Overrides of meshes[...] go to the mesh scene only, of walls[...] to the reference only.
  Variant plane = v, mesh = v;
  plane.scene = (std::filesystem::path(c.dir) / ref_it->second).string();
  plane.set.clear();
  mesh.set.clear();
  for (const SceneOverride& o : v.set) {
    if (o.path.rfind("meshes", 0) != 0) plane.set.push_back(o);
    if (o.path.rfind("walls", 0) != 0) mesh.set.push_back(o);
  }
  Simulation mesh_sim(scene_for(mesh, rc));
  Simulation plane_sim(scene_for(plane, rc));
  if (mesh_sim.particles().size() != 1 || plane_sim.particles().size() != 1)
    throw std::runtime_error(c.name + ": mesh_vs_walls compares one particle");
  if (mesh_sim.spec().dt != plane_sim.spec().dt)
    throw std::runtime_error(c.name + ": the mesh and plane scenes resolve different time steps");
  std::vector<Sample> a, b;
  RunOutput r = run_timed(mesh_sim, [&](const Simulation& s) { a.push_back(sample(s)); });
  if (rc.timing_only) return r;
  plane_sim.run([&](const Simulation& s) { b.push_back(sample(s)); });
  if (a.size() != b.size()) throw std::runtime_error(c.name + ": the two runs took different numbers of steps");
  const double R = mesh_sim.particles().radius[0];
  r.oracle_accuracy = "plane_walls(cdm)";
  double dn = 0.0, contact_steps = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    dn = std::max(dn, std::abs(a[k].contacts - b[k].contacts));
    contact_steps += b[k].contacts > 0.0;
  }
  // Differences relative to the reference's largest value over the run (a quantity that
  // passes through zero has no meaningful relative error at its zeros).
  auto rel_to_peak = [&](Vec3 Sample::*q) {
    const double p = peak(b, q);
    return p > 0.0 ? max_diff(a, b, q) / p : max_diff(a, b, q);
  };
  r.measurements.push_back({"position", "max_abs_of_radius", max_diff(a, b, &Sample::x) / R});
  r.measurements.push_back({"velocity", "max_abs_of_peak", rel_to_peak(&Sample::v)});
  r.measurements.push_back({"angular_velocity", "max_abs_of_peak", rel_to_peak(&Sample::w)});
  r.measurements.push_back({"force", "max_abs_of_peak", rel_to_peak(&Sample::f)});
  r.measurements.push_back({"torque", "max_abs_of_peak", rel_to_peak(&Sample::tq)});
  r.measurements.push_back({"contact_count", "max_abs", dn});
  r.measurements.push_back({"steps_in_contact", "count", contact_steps});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path,
                  {"t[s]", "x[m]", "y[m]", "z[m]", "z_plane[m]", "fz[N]", "fz_plane[N]", "position_difference[m]",
                   "force_difference[N]", "contacts[-]", "contacts_plane[-]"},
                  {series_title("mesh vs plane walls", v, rc, r.dt)});
    for (std::size_t k = 0; k < a.size(); ++k)
      w.row({a[k].t, a[k].x.x, a[k].x.y, a[k].x.z, b[k].x.z, a[k].f.z, b[k].f.z, norm(a[k].x - b[k].x),
             norm(a[k].f - b[k].f), a[k].contacts, b[k].contacts});
  }
  return r;
}

RunOutput mesh_impact(const CaseDef& c, const Variant& v, const RunConfig& rc) {
  const std::vector<double> hw = numbers_in(c, "half_width");
  const double a = hw.at(0);
  Simulation sim(scene_for(v, rc));
  if (sim.particles().size() != 1) throw std::runtime_error(c.name + ": mesh_impact follows one particle");
  const ParticleStore& p = sim.particles();
  auto kinetic = [&]() { return 0.5 * p.mass[0] * dot(p.velocity(0), p.velocity(0)); };
  const double e0 = kinetic();
  std::vector<Sample> s;
  double normal_err = 0.0, contact_steps = 0.0, most = 0.0;
  RunOutput r = run_timed(sim, [&](const Simulation& sm) {
    const Sample x = sample(sm);
    most = std::max(most, x.contacts);
    if (x.contacts > 0.0) {
      ++contact_steps;
      // The closest point of the solid cube to the centre, and the direction from it.
      const Vec3 q{std::clamp(x.x.x, -a, a), std::clamp(x.x.y, -a, a), std::clamp(x.x.z, -a, a)};
      const Vec3 n = (1.0 / norm(x.x - q)) * (x.x - q);
      normal_err = std::max(normal_err, norm((1.0 / norm(x.f)) * x.f - n));
    }
    if (!rc.series_path.empty()) s.push_back(x);
  });
  if (rc.timing_only) return r;
  if (sim.contact()->active_contacts() != 0) throw std::runtime_error(c.name + ": still in contact at the end");
  if (contact_steps == 0.0) throw std::runtime_error(c.name + " " + v.name + ": the sphere never touched the mesh");
  r.oracle_accuracy = "closed_form";
  r.measurements.push_back({"kinetic_energy", "rel", std::abs(kinetic() - e0) / e0});
  r.measurements.push_back({"normal_direction", "max_abs", normal_err});
  r.measurements.push_back({"simultaneous_contacts", "max", most});
  if (!rc.series_path.empty()) {
    TableWriter w(rc.series_path,
                  {"t[s]", "x[m]", "y[m]", "z[m]", "fx[N]", "fy[N]", "fz[N]", "kinetic_energy[J]", "contacts[-]"},
                  {series_title("mesh edge/vertex impact", v, rc, r.dt)});
    for (const Sample& x : s)
      w.row({x.t, x.x.x, x.x.y, x.x.z, x.f.x, x.f.y, x.f.z, 0.5 * p.mass[0] * dot(x.v, x.v), x.contacts});
  }
  return r;
}

}  // namespace cdm::verification::runners
