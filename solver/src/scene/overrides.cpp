/// @file overrides.cpp
/// @brief --set overrides: checking one, and applying it to the scene's TOML table.
#include "overrides.hpp"

#include <string>
#include <utility>
#include <vector>

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

// Walk "a.b[2].c" inside a table and set the final key to value.
void apply_override(toml::table& root, const SceneOverride& o, const std::string& file) {
  auto bad = [&](const std::string& why) {
    throw SceneError(file + ": override '" + o.path + "=" + o.value + "': " + why);
  };
  toml::table parsed;
  try {
    parsed = toml::parse("v = " + o.value);
  } catch (const toml::parse_error& e) {
    bad("the value is not TOML (" + std::string(e.description()) + "); strings need quotes");
  }
  toml::node* value = parsed.get("v");
  std::vector<std::pair<std::string, long>> segs;  // key, index (-1 for none)
  std::string rest = o.path;
  while (!rest.empty()) {
    const auto dot = rest.find('.');
    std::string seg = rest.substr(0, dot);
    rest = dot == std::string::npos ? "" : rest.substr(dot + 1);
    long idx = -1;
    if (auto b = seg.find('['); b != std::string::npos) {
      const auto e = seg.find(']', b);
      if (e == std::string::npos) bad("unbalanced [ in the path");
      try { idx = std::stol(seg.substr(b + 1, e - b - 1)); } catch (...) { bad("array index is not a number"); }
      if (idx < 0) bad("negative array index");
      seg = seg.substr(0, b);
    }
    if (seg.empty()) bad("empty key in the path");
    segs.emplace_back(seg, idx);
  }
  if (segs.empty()) bad("empty path");
  toml::table* cur = &root;
  for (std::size_t s = 0; s < segs.size(); ++s) {
    const bool last = s + 1 == segs.size();
    const auto& [key, idx] = segs[s];
    if (last && idx < 0) { cur->insert_or_assign(key, *value); return; }
    toml::node* n = cur->get(key);
    if (!n) {
      if (idx >= 0) bad("no array '" + key + "' in the scene");
      cur->insert_or_assign(key, toml::table{});
      n = cur->get(key);
    }
    if (idx >= 0) {
      toml::array* a = n->as_array();
      if (!a || static_cast<std::size_t>(idx) >= a->size()) bad("no element " + std::to_string(idx) + " in '" + key + "'");
      if (last) { a->replace(a->begin() + idx, *value); return; }
      n = a->get(static_cast<std::size_t>(idx));
    }
    cur = n->as_table();
    if (!cur) bad("'" + key + "' is not a table");
  }
}

}  // namespace cdm
