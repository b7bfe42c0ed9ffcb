#pragma once
/// @file sections.hpp
/// @brief The sections of a scene file, each read into SceneSpec by its own function, in
/// the order load() calls them (a section may rely on those read before it).
#include <cstddef>
#include <random>
#include <string>
#include <toml++/toml.h>

#include "reader.hpp"
#include "cdm/solver/placement_region.hpp"
#include "cdm/solver/size_distribution.hpp"

namespace cdm::scene {

// units_modules.cpp
void read_units(Reader& rd, SceneSpec& spec);
void read_modules(const Reader& rd, SceneSpec& spec);
// materials_contacts.cpp
void read_materials(const Reader& rd, SceneSpec& spec);
void read_contacts(const Reader& rd, SceneSpec& spec);
void check_elastic_constants_used(const Reader& rd, const SceneSpec& spec);
// walls_periodic.cpp
void read_walls(const Reader& rd, SceneSpec& spec);
/// A direction at @p key of @p t, normalised (scaled by its largest component first when
/// its squared length would underflow or overflow); a zero vector is refused with
/// @p expected.
Vec3 unit_vector(const Reader& rd, const toml::table& t, const std::string& key, const std::string& path,
                 const std::string& expected);
// motion.cpp
/// The prescribed motion of the table at @p key of @p t (none when absent), read with the
/// schema entry @p schema_path (e.g. "walls[].motion").
WallMotion read_motion(const Reader& rd, const toml::table& t, const std::string& key, const std::string& path,
                       const std::string& schema_path);
void read_periodic(const Reader& rd, SceneSpec& spec);
// meshes.cpp
void read_meshes(const Reader& rd, SceneSpec& spec);
// gas.cpp, prescribed_field.cpp, coupling.cpp
void read_gas(const Reader& rd, SceneSpec& spec);
void read_prescribed_field(const Reader& rd, const toml::table& gt, SceneSpec& spec);
void read_solved_gas(const Reader& rd, const toml::table& gt, SceneSpec& spec);
// particles.cpp, random_particles.cpp
void read_particles(const Reader& rd, SceneSpec& spec);
/// The material of a placed particle: one with a density (tracers excepted).
int particle_material(const Reader& rd, const SceneSpec& spec, const toml::table& t, const std::string& path);
/// The count of particles an entry places: an integer >= 1 within max_particles (the total
/// over all blocks is checked before any is placed).
std::size_t particle_count(const Reader& rd, const toml::table& t, const std::string& path);
/// The radii of a block: `radius` (one) or a `size` table (a distribution), exactly one.
SizeDistribution read_size(const Reader& rd, const toml::table& t, const std::string& path);
void read_random_particles(const Reader& rd, const toml::array& rs, SceneSpec& spec);
// region.cpp
/// Where a block at @p path (schema entry @p schema_path, e.g. "insertions[]") draws its
/// centres: `lower` and `upper` (a box) or a `cylinder` table, exactly one.
PlacementRegion read_region(const Reader& rd, const toml::table& t, const std::string& path,
                            const std::string& schema_path);
// insertions.cpp: [[insertions]] and [[outlets]] (after the walls, the gas and the periodic box)
void read_insertions(const Reader& rd, SceneSpec& spec);
void read_outlets(const Reader& rd, SceneSpec& spec);
// integrator.cpp
void read_integrator(const Reader& rd, SceneSpec& spec);
void resolve_dt(const Reader& rd, const toml::table* t, SceneSpec& spec);
// output_checks.cpp
void read_output_and_checks(const Reader& rd, SceneSpec& spec);
/// [[monitors]] (after [gas] and [output]).
void read_monitors(const Reader& rd, SceneSpec& spec);
// initial_state.cpp
void check_initial_state(const Reader& rd, const SceneSpec& spec);

}  // namespace cdm::scene
