/// @file scene_loader.cpp
/// @brief TOML scene → validated SceneSpec in SI units: the public entry points, the
/// overrides and the order in which the sections (sections.hpp) are read. The scene
/// loader is the only place in solver/ that reads TOML or converts units.
#include "cdm/solver/scene_loader.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "overrides.hpp"
#include "sections.hpp"

namespace cdm {

std::string particle_source(const SceneSpec& spec, std::size_t i) {
  for (const auto& g : spec.groups)
    if (i >= g.first && i < g.first + g.count) {
      if (g.nx == 0 && g.count == 1) return g.key;
      if (g.nx == 0) return g.key + " (particle " + std::to_string(i - g.first) + " of " + std::to_string(g.count) + ")";
      const auto k = static_cast<long long>(i - g.first);
      return g.key + " (lattice site " + std::to_string(k % g.nx) + "," + std::to_string((k / g.nx) % g.ny) + "," +
             std::to_string(k / (g.nx * g.ny)) + ")";
    }
  return "particle " + std::to_string(i);
}

namespace {

SceneSpec load(const std::string& file, const toml::table& root) {
  using namespace scene;
  SceneSpec spec;
  spec.file = file;
  Reader rd(file, root);
  rd.check_keys(root, "", "");
  read_units(rd, spec);
  read_modules(rd, spec);
  read_materials(rd, spec);
  read_contacts(rd, spec);
  check_elastic_constants_used(rd, spec);
  read_walls(rd, spec);
  read_meshes(rd, spec);
  read_gas(rd, spec);
  read_periodic(rd, spec);
  // Every scalar before the particles are placed: a bad one is refused before a large
  // scene allocates anything.
  read_integrator(rd, spec);
  read_output_and_checks(rd, spec);
  read_monitors(rd, spec);
  read_insertions(rd, spec);
  read_outlets(rd, spec);
  read_particles(rd, spec);
  resolve_dt(rd, root.get("integrator")->as_table(), spec);
  check_initial_state(rd, spec);
  return spec;
}

SceneSpec load_table(toml::table root, const std::string& name, const std::vector<SceneOverride>& overrides) {
  for (const auto& o : overrides) apply_override(root, o, name);
  return load(name, root);
}

}  // namespace

SceneOverride parse_override(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError("override '" + text + "': expected path=value, e.g. contacts[0].kn=1e7");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

SceneSpec load_scene_from_string(const std::string& text, const std::string& name,
                                 const std::vector<SceneOverride>& overrides) {
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << name << ":" << e.source().begin.line << ":" << e.source().begin.column
       << ": does not parse as TOML: " << e.description();
    throw SceneError(os.str());
  }
  return load_table(std::move(root), name, overrides);
}

std::string read_scene_file(const std::string& path) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st))
    throw SceneError(path + ": cannot open the scene file" + (ec ? " (" + ec.message() + ")" : ""));
  if (!std::filesystem::is_regular_file(st))
    throw SceneError(path + ": is " + (std::filesystem::is_directory(st) ? "a directory" : "not a regular file") +
                     ": expected a scene file (TOML text)");
  const auto size = std::filesystem::file_size(path, ec);
  if (ec) throw SceneError(path + ": cannot read the scene file's size (" + ec.message() + ")");
  if (size > max_scene_file_bytes)
    throw SceneError(path + ": is " + std::to_string(size) + " bytes: expected a scene file of at most " +
                     std::to_string(max_scene_file_bytes) + " bytes (16 MiB)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  // Read at most the limit, in case the file grew since it was measured.
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(text.data(), static_cast<std::streamsize>(size));
  text.resize(static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw SceneError(path + ": cannot read the scene file");
  return text;
}

SceneSpec load_scene(const std::string& path, const std::vector<SceneOverride>& overrides) {
  return load_scene_from_string(read_scene_file(path), path, overrides);
}

std::vector<std::string> scene_schema_keys() {
  std::vector<std::string> keys;
  for (const auto& [table, ks] : scene::schema())
    for (const auto& k : ks) {
      // Sub-tables are listed by their own entries; list only leaf keys.
      const std::string full = table.empty() ? k : table + "." + k;
      const bool is_table = scene::schema().count(full) || scene::schema().count(full + "[]");
      if (!is_table) keys.push_back(full);
    }
  std::sort(keys.begin(), keys.end());
  return keys;
}

std::vector<std::pair<std::string, std::vector<std::string>>> scene_schema_keywords() {
  const auto& s = scene::keyword_schema();
  return {s.begin(), s.end()};
}

}  // namespace cdm
