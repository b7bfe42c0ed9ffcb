#pragma once
/// @file scene_loader.hpp
/// @brief Load a TOML scene file into a validated SceneSpec (SI units).
///
/// Every error names the file, the key, the value and what was expected, and is
/// thrown as SceneError before anything is built or written. The accepted keys are
/// listed once, in scene_schema(); docs/scene-reference.md documents each of them and a
/// unit test keeps the two in step.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "cdm/solver/scene.hpp"

namespace cdm {

class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A "path=value" override applied to the scene before validation, in the scene's own
/// units, e.g. {"contacts[0].kn", "1e7"} or {"integrator.scheme", "\"velocity_verlet\""}.
/// The value is TOML syntax.
struct SceneOverride {
  std::string path;
  std::string value;
};

/// Parse "path=value" (as given on the command line).
SceneOverride parse_override(const std::string& text);

/// Refuse an override whose value is more than one TOML value (a line break followed
/// by another key=value would otherwise be dropped without a word).
void check_override(const SceneOverride& o);

/// The largest scene file read: 16 MiB. Scenes place many particles through
/// [[lattices]] and [[random_particles]] blocks, so a real scene is a few kilobytes.
constexpr std::uintmax_t max_scene_file_bytes = 16u << 20;

/// The text of the scene file at @p path: a regular file of at most max_scene_file_bytes
/// (a directory, a device or a larger file is refused with SceneError before reading).
std::string read_scene_file(const std::string& path);

SceneSpec load_scene(const std::string& path, const std::vector<SceneOverride>& overrides = {});
SceneSpec load_scene_from_string(const std::string& toml_text, const std::string& name,
                                 const std::vector<SceneOverride>& overrides = {});

/// Every key the loader accepts, as dotted paths with [] for array elements
/// (e.g. "materials[].density").
std::vector<std::string> scene_schema_keys();

/// The keywords accepted by each key whose value is a keyword, e.g. {"modules.gas",
/// {"none", "prescribed", "solved"}}. The loader parses, prints and lists these keywords
/// from one table per choice (keywords.hpp).
std::vector<std::pair<std::string, std::vector<std::string>>> scene_schema_keywords();

}  // namespace cdm
