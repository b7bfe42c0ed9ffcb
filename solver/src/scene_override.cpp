#include <toml++/toml.h>

#include "cdm/solver/scene_loader.hpp"

namespace cdm {

void check_override(const SceneOverride& o) {
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + o.value);
  } catch (const toml::parse_error&) {
    return;  // applying it says what is wrong with the value
  }
  for (const auto& [key, node] : parsed)
    if (key.str() != "v")
      throw SceneError("override '" + o.path + "=" + o.value + "': the value holds more than one TOML value ('" +
                       std::string(key.str()) + "' after a line break); give each path=value its own --set");
}

}  // namespace cdm
