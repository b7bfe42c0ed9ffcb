#pragma once
/// @file overrides.hpp
/// @brief The scene's TOML table with a --set override applied (inside the solver
/// library only: toml++ is not part of its public interface).
#include <string>
#include <toml++/toml.h>

#include "cdm/solver/scene_loader.hpp"

namespace cdm {

/// Walk "a.b[2].c" inside @p root and set the final key to the override's value;
/// throws SceneError naming @p file and the override when the path or value is wrong.
void apply_override(toml::table& root, const SceneOverride& o, const std::string& file);

}  // namespace cdm
