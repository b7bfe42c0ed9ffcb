/// @file random_particles.cpp
/// @brief Particles at random places in a box or a cylinder ([[random_particles]]), kept apart by random
/// sequential addition when contacts act between them.
#include "sections.hpp"

#include "cdm/solver/placement.hpp"

#include <algorithm>
#include <limits>
#include <cmath>
#include <random>
#include <string>
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
    const SizeDistribution size = read_size(rd, t, path);
    const PlacementRegion region = read_region(rd, t, path, "random_particles[]");
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
    // Random sequential addition (placement.hpp): a new centre clears every particle
    // placed before it, of this block, of earlier blocks and listed ones, and the walls;
    // along periodic axes their images too where contacts act through the faces (as the
    // initial-overlap check sees them; without contacts the faces are not looked through).
    double r_max = size.largest();
    for (const auto& p : spec.particles) r_max = std::max(r_max, p.radius);
    SequentialPlacement placed(r_max, spec.walls, spec.meshes, 0.0, spec.normal_contact ? spec.periodic : PeriodicBox{});
    if (exclusive)
      for (const auto& p : spec.particles) placed.add(p.position, p.radius);
    spec.groups.push_back({path, spec.particles.size(), count, 0, 0});
    // Jammed when this many tries in a row find no free place: the free volume left is
    // then below ~5e-5 of the box, and going on would only burn time (a bound on the
    // consecutive misses, not on the total, keeps the work per placed particle bounded).
    std::size_t misses = 0;
    const std::size_t max_misses = 20000;
    // The radius is drawn first, then centres until one is clear (one stream of numbers).
    double r = size.sample(rng);
    for (std::size_t k = 0; k < count;) {
      const double a = uniform(), b = uniform(), c = uniform();
      const Vec3 x = region.draw(a, b, c);
      if (exclusive && !placed.clear(x, r)) {
        if (++misses > max_misses)
          rd.fail_value(path + ".count", *t.get("count"),
                        "fewer particles: only " + std::to_string(k) + " fit without overlap (" +
                         std::to_string(max_misses) + " random tries in a row found no free place; random sequential "
                         "addition jams near a solids fraction of 0.38; use [[lattices]] for denser packings)");
        continue;
      }
      misses = 0;
      if (exclusive) placed.add(x, r);
      ParticleSpec p;
      p.material = mat;
      p.radius = r;
      p.position = x;
      spec.particles.push_back(p);
      if (++k < count) r = size.sample(rng);
    }
  }
}

}  // namespace cdm::scene
