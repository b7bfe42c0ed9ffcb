/// @file monitors.cpp
/// @brief The scene's monitors ([[monitors]]), sampled every output.log_interval.
#include "sections.hpp"

#include <set>
#include <string>

namespace cdm::scene {

namespace {

/// The coordinate of @p v along @p axis.
double along(Vec3 v, int axis) { return axis == 0 ? v.x : axis == 1 ? v.y : v.z; }

}  // namespace

void read_monitors(const Reader& rd, SceneSpec& spec) {
  const toml::array* ms = rd.array_of_tables(rd.root(), "monitors");
  if (!ms) return;
  if (!(spec.log_interval > 0.0))
    throw SceneError(rd.file() + ": [[monitors]] are sampled every output.log_interval, and the scene sets none "
                                 "(add log_interval to [output])");
  std::set<std::string> names;
  for (std::size_t i = 0; i < ms->size(); ++i) {
    const toml::table& t = *ms->get(i)->as_table();
    const std::string path = "monitors[" + std::to_string(i) + "]";
    rd.check_keys(t, "monitors[]", path);
    MonitorSpec m;
    m.name = rd.string(t, "name", path).value_or("");
    if (m.name.empty() || m.name.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-") !=
                              std::string::npos || m.name.size() > 64) {
      if (const toml::node* n = t.get("name"))
        rd.fail_value(path + ".name", *n, "a name of 1 to 64 letters, digits, '_' or '-' (the table is monitor_NAME.dat)");
      rd.fail_missing(path + ".name", "a name of 1 to 64 letters, digits, '_' or '-' (the table is monitor_NAME.dat)");
    }
    if (!names.insert(m.name).second)
      rd.fail_value(path + ".name", *t.get("name"), "a name no other monitor has");
    if (!t.get("type")) rd.fail_missing(path + ".type", keyword_list(monitor_keywords, [](MonitorKind) { return true; }));
    m.kind = rd.keyword(t, "type", path, monitor_keywords, MonitorKind::pressure);
    const bool pressure = m.kind == MonitorKind::pressure || m.kind == MonitorKind::plane_pressure ||
                          m.kind == MonitorKind::pressure_drop;
    if (pressure && spec.gas != GasModel::solved)
      rd.fail_value(path + ".type", *t.get("type"), "a monitor the scene can feed: a pressure needs modules.gas = \"solved\"");
    if (m.kind == MonitorKind::wall_force && (!spec.normal_contact || spec.walls.empty()))
      rd.fail_value(path + ".type", *t.get("type"), "a monitor the scene can feed: wall_force needs modules.normal_contact and [[walls]]");
    if (m.kind == MonitorKind::bed_height && spec.gas == GasModel::none)
      rd.fail_value(path + ".type", *t.get("type"), "a monitor the scene can feed: bed_height measures within the gas domain, and the scene has no [gas]");
    auto allow = [&](std::initializer_list<const char*> keys) {
      for (const auto& [k, v] : t) {
        const std::string key(k.str());
        if (key == "name" || key == "type") continue;
        bool ok = false;
        for (const char* a : keys) ok |= key == a;
        if (!ok)
          throw SceneError(rd.file() + ": " + path + "." + key + " is not used by a monitor of type \"" +
                           to_string(m.kind) + "\"");
      }
    };
    if (t.get("axis")) {
      const std::string a = rd.string(t, "axis", path).value_or("");
      if (a != "x" && a != "y" && a != "z") rd.fail_value(path + ".axis", *t.get("axis"), "\"x\", \"y\" or \"z\"");
      m.axis = a[0] - 'x';
      if (spec.gas != GasModel::none && spec.gas_spec.grid.two_d && m.axis == 2)
        rd.fail_value(path + ".axis", *t.get("axis"), "\"x\" or \"y\" (the gas is 2D)");
    } else if (m.kind != MonitorKind::pressure) {
      rd.fail_missing(path + ".axis", "\"x\", \"y\" or \"z\"");
    }
    const fluid::GridSpec* grid = spec.gas != GasModel::none ? &spec.gas_spec.grid : nullptr;
    // A plane or point inside the gas domain (when there is one).
    auto inside = [&](const std::string& key, double v) {
      if (grid && !(v >= along(grid->lo, m.axis) && v <= along(grid->hi, m.axis)))
        rd.fail_value(path + "." + key, *t.get(key), "a coordinate within the gas domain along " +
                                                       std::string(1, "xyz"[m.axis]));
    };
    switch (m.kind) {
      case MonitorKind::pressure: {
        allow({"point"});
        m.point = rd.vec3_required(t, "point", path, Dim::length);
        for (int a = 0; a < 3; ++a)
          if (!(along(m.point, a) >= along(grid->lo, a) && along(m.point, a) <= along(grid->hi, a)))
            rd.fail_value(path + ".point", *t.get("point"), "a point within the gas domain");
        break;
      }
      case MonitorKind::plane_pressure:
        allow({"axis", "position"});
        m.position = rd.number(t, "position", path, Dim::length).value_or(0.0);
        if (!t.get("position")) rd.fail_missing(path + ".position", "the plane's coordinate along axis");
        inside("position", m.position);
        break;
      case MonitorKind::pressure_drop:
        allow({"axis", "from", "to"});
        if (!t.get("from")) rd.fail_missing(path + ".from", "the first plane's coordinate along axis");
        if (!t.get("to")) rd.fail_missing(path + ".to", "the second plane's coordinate along axis");
        m.from = *rd.number(t, "from", path, Dim::length);
        m.to = *rd.number(t, "to", path, Dim::length);
        inside("from", m.from);
        inside("to", m.to);
        break;
      case MonitorKind::bed_height: {
        allow({"axis", "threshold", "bin"});
        m.threshold = rd.number_in(t, "threshold", path, Dim::none, true, 0.0, 0.0, true, 1.0, true, "in (0, 1)");
        const double length = along(grid->hi, m.axis) - along(grid->lo, m.axis);
        const double cell = length / grid->cells[static_cast<std::size_t>(m.axis)];
        m.bin = rd.number_in(t, "bin", path, Dim::length, false, cell, 0.0, true, length, false,
                             "in (0, the domain's length along axis]");
        break;
      }
      case MonitorKind::mass_flow:
        allow({"axis", "position", "bin"});
        if (!t.get("position")) rd.fail_missing(path + ".position", "the plane's coordinate along axis");
        if (!t.get("bin")) rd.fail_missing(path + ".bin", "the slab thickness around the plane (> 0), e.g. a few particle diameters");
        m.position = *rd.number(t, "position", path, Dim::length);
        m.bin = rd.positive(t, "bin", path, Dim::length, true);
        break;
      case MonitorKind::wall_force:
        allow({"axis", "wall"});
        if (const toml::node* n = t.get("wall")) {
          const std::string w = rd.string(t, "wall", path).value_or("");
          for (std::size_t k = 0; k < spec.walls.size(); ++k)
            if (spec.walls[k].name == w) m.wall = static_cast<int>(k);
          if (m.wall < 0) rd.fail_value(path + ".wall", *n, "the name of one of the scene's [[walls]]");
        }
        break;
    }
    spec.monitors.push_back(m);
  }
}

}  // namespace cdm::scene
