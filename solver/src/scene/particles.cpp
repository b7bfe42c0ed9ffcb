/// @file particles.cpp
/// @brief Particles listed one by one, on lattices and on shells; the Verlet skin they set.
#include "sections.hpp"

#include "cdm/solver/initial_motion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

namespace cdm::scene {

int particle_material(const Reader& rd, const SceneSpec& spec, const toml::table& t, const std::string& path) {
  const int m = rd.material_index(spec, t, "material", path);
  if (!(spec.materials[m].density > 0.0) && !spec.tracers)
    rd.fail_value(path + ".material", *t.get("material"),
                  "a material with a density (materials entry '" + spec.materials[m].name + "' has none)");
  return m;
}

std::size_t particle_count(const Reader& rd, const toml::table& t, const std::string& path) {
  const toml::node* cn = t.get("count");
  if (!cn) rd.fail_missing(path + ".count", "an integer >= 1");
  if (!cn->is_integer() || cn->as_integer()->get() < 1 ||
      static_cast<double>(cn->as_integer()->get()) > max_particles)
    rd.fail_value(path + ".count", *cn, "an integer >= 1 (at most " + std::to_string(max_particles) + " particles in the scene)");
  return static_cast<std::size_t>(cn->as_integer()->get());
}

namespace {

// The counts of a lattice along x, y and z.
std::array<long long, 3> lattice_count(const Reader& rd, const toml::table& t, const std::string& path) {
  const toml::node* cn = t.get("count");
  if (!cn) rd.fail_missing(path + ".count", "an array of 3 integers >= 1");
  const toml::array* ca = cn->as_array();
  std::array<long long, 3> c = {0, 0, 0};
  if (!ca || ca->size() != 3) rd.fail_value(path + ".count", *cn, "an array of 3 integers >= 1");
  for (int k = 0; k < 3; ++k) {
    auto iv = ca->get(k)->as_integer();
    if (!iv || iv->get() < 1) rd.fail_value(path + ".count", *cn, "an array of 3 integers >= 1");
    c[k] = iv->get();
  }
  return c;
}

// The particles of every block counted, and held to max_particles, before any is placed.
void check_particle_total(const Reader& rd) {
  double total = 0.0;
  const auto add = [&](double n, const std::string& path, const toml::table& t) {
    total += n;
    if (total > max_particles) {
      std::ostringstream os;
      os << "at most " << max_particles << " particles in the scene; with the entries before it, " << path
         << " brings the total to " << std::fixed << std::setprecision(0) << total;
      rd.fail_value(path + ".count", *t.get("count"), os.str());
    }
  };
  const auto each = [&](const char* key, auto count) {
    if (const toml::array* a = rd.array_of_tables(rd.root(), key))
      for (std::size_t i = 0; i < a->size(); ++i) {
        const toml::table& t = *a->get(i)->as_table();
        const std::string path = std::string(key) + "[" + std::to_string(i) + "]";
        add(count(t, path), path, t);
      }
  };
  if (const toml::array* ps = rd.array_of_tables(rd.root(), "particles")) total += static_cast<double>(ps->size());
  each("lattices", [&](const toml::table& t, const std::string& path) {
    const auto c = lattice_count(rd, t, path);
    return static_cast<double>(c[0]) * c[1] * c[2];
  });
  const auto listed = [&](const toml::table& t, const std::string& path) {
    return static_cast<double>(particle_count(rd, t, path));
  };
  each("shells", listed);
  each("random_particles", listed);
}

}  // namespace

void read_particles(const Reader& rd, SceneSpec& spec) {
  check_particle_total(rd);
  if (const toml::array* ps = rd.array_of_tables(rd.root(), "particles")) {
    for (std::size_t i = 0; i < ps->size(); ++i) {
      const toml::table& t = *ps->get(i)->as_table();
      const std::string path = "particles[" + std::to_string(i) + "]";
      rd.check_keys(t, "particles[]", path);
      ParticleSpec p;
      p.material = particle_material(rd, spec, t, path);
      p.radius = rd.positive(t, "radius", path, Dim::length, true);
      p.position = rd.vec3_required(t, "position", path, Dim::length);
      if (spec.tracers) rd.reject_unused(t, "velocity", path, "modules.tracers is true: a tracer moves with the gas");
      ParticleGroup g{path, spec.particles.size(), 1, 0, 0};
      g.velocity = rd.vec3(t, "velocity", path, Dim::velocity).value_or(Vec3{});
      if (spec.tangential == TangentialModel::none && spec.rolling == RollingModel::none)
        rd.reject_unused(t, "angular_velocity", path,
                         "modules.tangential and modules.rolling_resistance are \"none\", so particles do not rotate");
      g.angular_velocity = rd.vec3(t, "angular_velocity", path, Dim::angular_velocity).value_or(Vec3{});
      spec.groups.push_back(std::move(g));
      spec.particles.push_back(p);
    }
  }
  if (const toml::array* ls = rd.array_of_tables(rd.root(), "lattices")) {
    for (std::size_t i = 0; i < ls->size(); ++i) {
      const toml::table& t = *ls->get(i)->as_table();
      const std::string path = "lattices[" + std::to_string(i) + "]";
      rd.check_keys(t, "lattices[]", path);
      const int mat = particle_material(rd, spec, t, path);
      const SizeDistribution size = read_size(rd, t, path);
      const Vec3 origin = rd.vec3_required(t, "origin", path, Dim::length);
      const Vec3 spacing = rd.vec3_required(t, "spacing", path, Dim::length);
      if (!(spacing.x > 0 && spacing.y > 0 && spacing.z > 0))
        rd.fail_value(path + ".spacing", *t.get("spacing"), "3 numbers > 0");
      if (spec.tracers) {
        rd.reject_unused(t, "velocity", path, "modules.tracers is true: a tracer moves with the gas");
        rd.reject_unused(t, "velocity_jitter", path, "modules.tracers is true: a tracer moves with the gas");
      }
      const Vec3 vel = rd.vec3(t, "velocity", path, Dim::velocity).value_or(Vec3{});
      const double jitter = rd.number_in(t, "velocity_jitter", path, Dim::velocity, false, 0.0, 0.0, false,
                                         std::numeric_limits<double>::infinity(), false, ">= 0");
      long long seed = 1;
      if (const toml::node* sn = t.get("seed")) {
        if (!sn->is_integer() || sn->as_integer()->get() < 0) rd.fail_value(path + ".seed", *sn, "an integer >= 0");
        if (!(jitter > 0.0) && size.kind == SizeKind::fixed)
          rd.reject_unused(t, "seed", path, "velocity_jitter is 0 and the radius is fixed");
        seed = sn->as_integer()->get();
      }
      // Sites far enough apart for the largest radius the distribution draws.
      if (size.kind != SizeKind::fixed && 2.0 * size.largest() > std::min({spacing.x, spacing.y, spacing.z}))
        rd.fail_value(path + ".spacing", *t.get("spacing"),
                      "a spacing of at least the largest diameter of " + path + ".size (" +
                          std::to_string(2.0 * size.largest() / rd.factor(Dim::length)) + ") along every axis");
      // Per site its radius; its velocity, jittered, is drawn again by the run
      // (InitialMotion) from the same stream.
      const std::array<long long, 3> c = lattice_count(rd, t, path);  // the total is checked
      ParticleGroup g{path, spec.particles.size(), static_cast<std::size_t>(c[0] * c[1] * c[2]), c[0], c[1]};
      g.velocity = vel;
      g.jitter = jitter;
      g.seed = static_cast<std::uint64_t>(seed);
      g.size = size;
      spec.groups.push_back(std::move(g));
      LatticeDraws draws(size, jitter, static_cast<std::uint64_t>(seed));
      spec.particles.reserve(spec.particles.size() + static_cast<std::size_t>(c[0] * c[1] * c[2]));
      for (long long kz = 0; kz < c[2]; ++kz)
        for (long long ky = 0; ky < c[1]; ++ky)
          for (long long kx = 0; kx < c[0]; ++kx) {
            ParticleSpec p;
            p.material = mat;
            p.radius = draws.next().radius;
            p.position = origin + Vec3{kx * spacing.x, ky * spacing.y, kz * spacing.z};
            spec.particles.push_back(p);
          }
    }
  }
  if (const toml::array* ss = rd.array_of_tables(rd.root(), "shells")) {
    // Particles evenly spread on a circle (dimension 2, in the plane z = center.z) or on
    // a sphere (dimension 3, a Fibonacci lattice: point k at height 1 − (2k+1)/n and
    // azimuth k·π(3 − √5)), at rest (or moving with the gas, for tracers).
    for (std::size_t i = 0; i < ss->size(); ++i) {
      const toml::table& t = *ss->get(i)->as_table();
      const std::string path = "shells[" + std::to_string(i) + "]";
      rd.check_keys(t, "shells[]", path);
      const int mat = particle_material(rd, spec, t, path);
      const double r = rd.positive(t, "radius", path, Dim::length, true);
      const Vec3 c = rd.vec3_required(t, "center", path, Dim::length);
      const double R = rd.positive(t, "shell_radius", path, Dim::length, true);
      const std::size_t count = particle_count(rd, t, path);
      long long dim = 2;
      if (const toml::node* dn = t.get("dimension")) {
        if (!dn->is_integer() || (dn->as_integer()->get() != 2 && dn->as_integer()->get() != 3))
          rd.fail_value(path + ".dimension", *dn, "2 (a circle in the x-y plane) or 3 (a sphere)");
        dim = dn->as_integer()->get();
      } else {
        rd.fail_missing(path + ".dimension", "2 (a circle in the x-y plane) or 3 (a sphere)");
      }
      spec.groups.push_back({path, spec.particles.size(), count, 0, 0});
      const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
      for (std::size_t k = 0; k < count; ++k) {
        ParticleSpec p;
        p.material = mat;
        p.radius = r;
        if (dim == 2) {
          const double a = 2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(count);
          p.position = c + Vec3{R * std::cos(a), R * std::sin(a), 0.0};
        } else {
          const double zk = 1.0 - (2.0 * static_cast<double>(k) + 1.0) / static_cast<double>(count);
          const double rho = std::sqrt(std::max(0.0, 1.0 - zk * zk)), a = golden * static_cast<double>(k);
          p.position = c + Vec3{R * rho * std::cos(a), R * rho * std::sin(a), R * zk};
        }
        spec.particles.push_back(p);
      }
    }
  }
  if (const toml::array* rs = rd.array_of_tables(rd.root(), "random_particles")) read_random_particles(rd, *rs, spec);
  if (spec.particles.empty() && spec.gas != GasModel::solved && spec.insertions.empty())
    rd.fail_missing("particles",
                    "at least one [[particles]], [[lattices]], [[shells]], [[random_particles]] or [[insertions]] entry");
  double d_max = 0.0;
  for (const auto& ps : spec.particles) d_max = std::max(d_max, 2.0 * ps.radius);
  for (const auto& in : spec.insertions) d_max = std::max(d_max, 2.0 * in.size.largest());
  spec.verlet_skin = 0.1 * d_max;
}

}  // namespace cdm::scene
