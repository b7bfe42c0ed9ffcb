/// @file initial_state.cpp
/// @brief Checks of the initial state: particles inside the gas domain, the periods and the walls, and apart.
#include "sections.hpp"

#include "cdm/solver/contact/mesh_contacts.hpp"
#include "cdm/solver/neighbour_search.hpp"

#include <algorithm>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace cdm::scene {

void check_initial_state(const Reader& rd, const SceneSpec& spec) {
  // Every particle starts inside the gas domain.
  if (spec.gas != GasModel::none) {
    const fluid::GridSpec& g = spec.gas_spec.grid;
    for (std::size_t i = 0; i < spec.particles.size(); ++i) {
      const Vec3 x = spec.particles[i].position;
      if (x.x < g.lo.x || x.x > g.hi.x || x.y < g.lo.y || x.y > g.hi.y || x.z < g.lo.z || x.z > g.hi.z) {
        std::ostringstream os;
        os << rd.file() << ": key '" << particle_source(spec, i) << ".position' = [" << x.x << ", " << x.y << ", " << x.z
           << "] (SI) lies outside the gas domain [" << g.lo.x << ", " << g.hi.x << "] x [" << g.lo.y << ", " << g.hi.y
           << "] x [" << g.lo.z << ", " << g.hi.z << "] m: expected every particle inside gas.lower .. gas.upper";
        throw SceneError(os.str());
      }
    }
  }
  // Along a periodic axis every particle starts inside the period, and contacts (with
  // the Verlet skin) must reach less than half of it: particles meet only their nearest
  // images.
  const PeriodicBox& box = spec.periodic;
  if (box.any()) {
    double rmax = 0.0;
    for (const auto& p : spec.particles) rmax = std::max(rmax, p.radius);
    const char* axes[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      if (!box.on[a]) continue;
      const std::string where = spec.gas != GasModel::none ? std::string("gas.boundaries.") + axes[a] + "_lower"
                                                            : std::string("periodic.") + axes[a];
      for (std::size_t i = 0; i < spec.particles.size(); ++i) {
        const Vec3 x = spec.particles[i].position;
        const double c = a == 0 ? x.x : a == 1 ? x.y : x.z;
        if (c < box.lo[a] || c >= box.lo[a] + box.len[a]) {
          std::ostringstream os;
          os << rd.file() << ": key '" << particle_source(spec, i) << ".position' = [" << x.x << ", " << x.y << ", " << x.z
             << "] (SI) lies outside the period [" << box.lo[a] << ", " << box.lo[a] + box.len[a] << ") m along "
             << axes[a] << " (" << where << "): expected every particle inside it";
          throw SceneError(os.str());
        }
      }
      const double reach = 2.0 * rmax + spec.verlet_skin;
      if (spec.normal_contact && 2.0 * reach >= box.len[a]) {
        std::ostringstream os;
        os << rd.file() << ": the period along " << axes[a] << " (" << where << ") is " << box.len[a]
           << " m: expected more than 4.4 times the largest radius (" << 2.0 * reach
           << " m), so that a particle's contacts (2.2 r with the Verlet skin) reach less than half of it";
        throw SceneError(os.str());
      }
    }
  }
  // A centre outside a wall is always an error; touching a wall or another particle
  // only when the scene says the initial overlap is intended.
  for (std::size_t i = 0; i < spec.particles.size(); ++i) {
    const ParticleSpec& p = spec.particles[i];
    for (const auto& wall : spec.walls) {
      const Wall w = wall.at(0.0);
      // Unsigned beyond a finite surface's faces (a rim), signed on them.
      const double d = w.gap(p.position, std::numeric_limits<double>::infinity()).gap;
      if (d < 0.0 || (!spec.allow_initial_overlap && d < p.radius)) {
        std::ostringstream os;
        os << rd.file() << ": key '" << particle_source(spec, i) << ".position' = [" << p.position.x << ", " << p.position.y << ", "
           << p.position.z << "] (SI) lies " << (d < 0.0 ? "outside" : "across") << " wall '" << w.name
           << "' (centre distance " << d << " m, radius " << p.radius << " m): expected a particle inside the domain"
           << (d < 0.0 ? "" : " and clear of the wall (or checks.allow_initial_overlap = true)");
        throw SceneError(os.str());
      }
    }
  }
  // A particle touching a mesh only when the scene says the initial overlap is intended
  // (which side of an open mesh is inside is not defined, so only the touching is checked).
  if (!spec.meshes.empty() && !spec.allow_initial_overlap && !spec.particles.empty()) {
    MeshContacts meshes(spec.meshes);
    double rmax = 0.0;
    for (const auto& p : spec.particles) rmax = std::max(rmax, p.radius);
    meshes.build_grid(rmax);
    std::vector<MeshContacts::Contact> touch;
    for (std::size_t i = 0; i < spec.particles.size(); ++i) {
      const ParticleSpec& p = spec.particles[i];
      meshes.find(p.position, p.radius, static_cast<std::uint32_t>(i), touch);
      if (touch.empty()) continue;
      const MeshContacts::Contact& c = touch.front();
      std::ostringstream os;
      os << rd.file() << ": key '" << particle_source(spec, i) << ".position' = [" << p.position.x << ", "
         << p.position.y << ", " << p.position.z << "] (SI) lies across mesh '"
         << spec.meshes[meshes.mesh_of(c.triangle)].name << "' (centre distance " << c.lever << " m, radius "
         << p.radius << " m): expected a particle clear of the mesh (or checks.allow_initial_overlap = true)";
      throw SceneError(os.str());
    }
  }
  // Overlaps between particles matter only when a contact model acts between them.
  if (spec.particles.size() < 2 || !spec.normal_contact) return;
  // The search reads the scene's centres and radii in place: a copy of them would add
  // 32 B a particle on every process, at the start's peak.
  const std::size_t n = spec.particles.size();
  const ParticleSpec& first = spec.particles.front();
  const auto column = [](const double& v) {
    return StridedPoints::Column{reinterpret_cast<const char*>(&v), sizeof(ParticleSpec)};
  };
  const StridedPoints centres{column(first.position.x), column(first.position.y), column(first.position.z),
                              column(first.radius), n};
  std::vector<ContactPair> pairs;
  CellListSearch search;
  // Refused at the first overlap unless overlaps are allowed; allowed ones are listed
  // whole up to an average of max_overlaps_per_particle, which no packing reaches (a dense
  // one has about 6 contacts per particle, 12 at most for equal spheres).
  constexpr std::size_t max_overlaps_per_particle = 32;
  if (!search.find_contacts(centres, 0.0, pairs, spec.periodic,
                            spec.allow_initial_overlap ? max_overlaps_per_particle * n : 0) &&
      spec.allow_initial_overlap) {
    std::ostringstream os;
    os << rd.file() << ": the " << n << " particles overlap in more than " << max_overlaps_per_particle * n
       << " pairs at the start (over " << max_overlaps_per_particle
       << " per particle): expected a packing (checks.allow_initial_overlap = true accepts overlaps, not particles "
       << "piled on one another; check the lattice spacing or the block's box)";
    throw SceneError(os.str());
  }
  // Two particles at one centre have no contact normal: even an intended overlap needs
  // distinct centres.
  for (const auto& c : pairs)
    if (c.overlap >= spec.particles[c.i].radius + spec.particles[c.j].radius) {
      std::ostringstream os;
      const Vec3 x = spec.particles[c.j].position;
      os << rd.file() << ": key '" << particle_source(spec, c.j) << ".position' = [" << x.x << ", " << x.y << ", " << x.z
         << "] (SI) is the centre of '" << particle_source(spec, c.i)
         << "' too: expected distinct centres (two particles at one point have no contact normal, even with "
         << "checks.allow_initial_overlap = true)";
      throw SceneError(os.str());
    }
  if (!spec.allow_initial_overlap && !pairs.empty()) {
    const auto& c = pairs.front();
    std::ostringstream os;
    os << rd.file() << ": key '" << particle_source(spec, c.j) << ".position' overlaps '" << particle_source(spec, c.i)
       << "' by " << c.overlap << " m at the start: expected particles that do not overlap"
       << " (or checks.allow_initial_overlap = true if the compression is intended)";
    throw SceneError(os.str());
  }
}

}  // namespace cdm::scene
