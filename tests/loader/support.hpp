#pragma once
// Shared by the loader tests: editing a test scene and expecting it refused.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "cdm/solver/scene_loader.hpp"

namespace cdm::test {

/// @p s with the first @p from replaced by @p to (a test scene that lacks @p from is a bug).
inline std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  if (pos == std::string::npos) throw std::logic_error("test scene has no '" + from + "'");
  return s.replace(pos, from.size(), to);
}

/// Loads @p text as "bad.toml" and expects a SceneError whose message contains every
/// fragment and the file's name.
inline void expect_refused(const std::string& text, std::vector<std::string> fragments) {
  fragments.push_back("bad.toml");
  try {
    cdm::load_scene_from_string(text, "bad.toml");
    FAIL() << "accepted a bad scene; expected an error with '" << fragments.front() << "'";
  } catch (const cdm::SceneError& e) {
    const std::string msg = e.what();
    for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "message lacks '" << f << "': " << msg;
  }
}

}  // namespace cdm::test
