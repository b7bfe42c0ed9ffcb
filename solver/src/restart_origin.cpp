#include "cdm/solver/restart_origin.hpp"

#include <cstdio>
#include <cstdlib>
#include <optional>
#include <set>
#include <sstream>
#include <toml++/toml.h>

#include "scene/overrides.hpp"

namespace cdm {

std::vector<std::string> restart_changeable_keys() {
  return {"integrator.end_time", "gas.division", "neighbour_list.sort_interval", "output.*"};
}

namespace {

/// The scene as the loader sees it: the text parsed, the overrides applied, and the
/// keys a restart may change taken out.
toml::table effective_scene(const RunOrigin& o, const std::string& what) {
  toml::table root;
  try {
    root = toml::parse(o.scene_text, o.scene_name);
  } catch (const toml::parse_error& e) {
    throw CheckpointError(what + ": the scene does not parse as TOML: " + std::string(e.description()));
  }
  for (const auto& ov : o.overrides) apply_override(root, ov, o.scene_name);
  for (const std::string& key : restart_changeable_keys()) {  // "table.key", or "table.*" for the whole table
    const std::size_t dot = key.find('.');
    const std::string table = key.substr(0, dot), name = key.substr(dot + 1);
    if (name == "*") root.erase(table);
    else if (toml::table* t = root[table].as_table()) t->erase(name);
  }
  return root;
}

std::string shown(const toml::node* n) {
  if (!n) return "(absent)";
  if (const auto* f = n->as_floating_point()) {  // the shortest spelling that reads back as the same number
    char b[40];
    for (int digits = 15; digits <= 17; ++digits) {
      std::snprintf(b, sizeof b, "%.*g", digits, f->get());
      if (std::strtod(b, nullptr) == f->get()) break;
    }
    return b;
  }
  std::ostringstream os;
  n->visit([&](const auto& v) { os << v; });
  return os.str();
}

/// The first path under @p prefix where @p a and @p b differ; nothing when they agree.
/// Integers and floats that are the same number agree.
std::optional<std::string> first_difference(const toml::node* a, const toml::node* b, const std::string& prefix) {
  if (!a || !b) return (a || b) ? std::optional<std::string>(prefix) : std::nullopt;
  if (a->is_table() && b->is_table()) {
    const toml::table &ta = *a->as_table(), &tb = *b->as_table();
    std::set<std::string> keys;
    for (const auto& [k, v] : ta) keys.insert(std::string(k.str()));
    for (const auto& [k, v] : tb) keys.insert(std::string(k.str()));
    for (const auto& k : keys)
      if (auto d = first_difference(ta.get(k), tb.get(k), prefix.empty() ? k : prefix + "." + k)) return d;
    return std::nullopt;
  }
  if (a->is_array() && b->is_array()) {
    const toml::array &xa = *a->as_array(), &xb = *b->as_array();
    for (std::size_t i = 0; i < std::max(xa.size(), xb.size()); ++i)
      if (auto d = first_difference(xa.get(i), xb.get(i), prefix + "[" + std::to_string(i) + "]")) return d;
    return std::nullopt;
  }
  if (a->is_number() && b->is_number())
    return a->value<double>() == b->value<double>() ? std::nullopt : std::optional<std::string>(prefix);
  if (a->type() != b->type() || shown(a) != shown(b)) return prefix;
  return std::nullopt;
}

/// The node at a dotted path with [i] indices, as first_difference names them.
const toml::node* at(const toml::table& root, const std::string& path) {
  return root.at_path(path).node();
}

}  // namespace

void check_restart_origin(const RunOrigin& saved, const RunOrigin& now, const std::string& path) {
  const toml::table a = effective_scene(saved, path), b = effective_scene(now, now.scene_name);
  const auto d = first_difference(&a, &b, "");
  if (!d) return;
  throw CheckpointError(path + ": written from scene '" + saved.scene_name + "' where " + *d + " = " +
                        shown(at(a, *d)) + "; '" + now.scene_name + "' with the --set overrides given now has " +
                        shown(at(b, *d)) +
                        ". A restart may change only integrator.end_time, gas.division, neighbour_list.sort_interval and the keys "
                        "under [output]; "
                        "restart with the scene and overrides the run started with");
}

}  // namespace cdm
