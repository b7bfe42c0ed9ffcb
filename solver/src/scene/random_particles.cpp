/// @file random_particles.cpp
/// @brief Particles at random places in a box ([[random_particles]]), kept apart by random
/// sequential addition when contacts act between them.
#include "sections.hpp"

#include <algorithm>
#include <limits>
#include <cmath>
#include <map>
#include <random>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace cdm::scene {

void read_random_particles(const Reader& rd, const toml::array& rs, SceneSpec& spec) {
  // Centres uniform in a box (uniform01). With a normal-contact model each
  // new particle must clear every earlier one and the walls (random sequential
  // addition); without one, overlaps are allowed — nothing acts between particles.
  for (std::size_t i = 0; i < rs.size(); ++i) {
    const toml::table& t = *rs.get(i)->as_table();
    const std::string path = "random_particles[" + std::to_string(i) + "]";
    rd.check_keys(t, "random_particles[]", path);
    const int mat = particle_material(rd, spec, t, path);
    const double r = rd.positive(t, "radius", path, Dim::length, true);
    const Vec3 lo = rd.vec3_required(t, "lower", path, Dim::length), hi = rd.vec3_required(t, "upper", path, Dim::length);
    if (!(hi.x >= lo.x && hi.y >= lo.y && hi.z >= lo.z))
      rd.fail_value(path + ".upper", *t.get("upper"), "a corner at or above " + path + ".lower along every axis");
    const std::size_t count = particle_count(rd, t, path);
    long long seed = 1;
    if (const toml::node* sn = t.get("seed")) {
      if (!sn->is_integer() || sn->as_integer()->get() < 0) rd.fail_value(path + ".seed", *sn, "an integer >= 0");
      seed = sn->as_integer()->get();
    }
    std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
    auto uniform = [&] { return uniform01(rng); };
    const bool exclusive =
        !rd.boolean(t, "allow_overlap", path).value_or(!spec.normal_contact);
    // Random sequential addition on a cell grid of edge r + the largest radius so far
    // (contacts only): a new centre clears every particle placed before it, of this block,
    // of earlier blocks and listed ones.
    double r_max = r;
    for (const auto& p : spec.particles) r_max = std::max(r_max, p.radius);
    const double cell = r + r_max;
    std::map<std::tuple<long long, long long, long long>, std::vector<std::pair<Vec3, double>>> placed;
    auto key = [&](Vec3 x) {
      return std::make_tuple(static_cast<long long>(std::floor(x.x / cell)), static_cast<long long>(std::floor(x.y / cell)),
                             static_cast<long long>(std::floor(x.z / cell)));
    };
    if (exclusive)
      for (const auto& p : spec.particles) placed[key(p.position)].emplace_back(p.position, p.radius);
    std::vector<Wall> walls_t0;
    for (const auto& w : spec.walls) walls_t0.push_back(w.at(0.0));
    auto clear = [&](Vec3 x) {
      for (const auto& w : walls_t0)
        if (w.gap(x, std::numeric_limits<double>::infinity()).gap < r) return false;
      const auto [a, b, c] = key(x);
      for (long long da = -1; da <= 1; ++da)
        for (long long db = -1; db <= 1; ++db)
          for (long long dc = -1; dc <= 1; ++dc) {
            auto it = placed.find({a + da, b + db, c + dc});
            if (it == placed.end()) continue;
            for (const auto& [y, ry] : it->second)
              if (dot(x - y, x - y) < (r + ry) * (r + ry)) return false;
          }
      return true;
    };
    spec.groups.push_back({path, spec.particles.size(), count, 0, 0});
    // Jammed when this many tries in a row find no free place: the free volume left is
    // then below ~5e-5 of the box, and going on would only burn time (a bound on the
    // consecutive misses, not on the total, keeps the work per placed particle bounded).
    std::size_t misses = 0;
    const std::size_t max_misses = 20000;
    for (std::size_t k = 0; k < count;) {
      const double a = uniform(), b = uniform(), c = uniform();
      const Vec3 x{lo.x + a * (hi.x - lo.x), lo.y + b * (hi.y - lo.y), lo.z + c * (hi.z - lo.z)};
      if (exclusive && !clear(x)) {
        if (++misses > max_misses)
          rd.fail_value(path + ".count", *t.get("count"),
                        "fewer particles: only " + std::to_string(k) + " fit without overlap (" +
                         std::to_string(max_misses) + " random tries in a row found no free place; random sequential "
                         "addition jams near a solids fraction of 0.38; use [[lattices]] for denser packings)");
        continue;
      }
      misses = 0;
      if (exclusive) placed[key(x)].emplace_back(x, r);
      ParticleSpec p;
      p.material = mat;
      p.radius = r;
      p.position = x;
      spec.particles.push_back(p);
      ++k;
    }
  }
}

}  // namespace cdm::scene
