/// @file motion.cpp
/// @brief A prescribed motion sub-table: `motion = { type = "translation" | "oscillation"
/// | "rotation", ... }` (walls/wall_motion.hpp), for any block that describes a body.
#include <cmath>
#include <string>

#include "sections.hpp"

namespace cdm::scene {

WallMotion read_motion(const Reader& rd, const toml::table& parent, const std::string& key, const std::string& path,
                       const std::string& schema_path) {
  WallMotion m;
  const toml::node* n = parent.get(key);
  if (!n) return m;
  const std::string mp = join(path, key);
  const toml::table* t = n->as_table();
  if (!t) rd.fail_value(mp, *n, "a table { type = " + keyword_list(wall_motion_keywords, [](auto) { return true; }) + ", ... }");
  rd.check_keys(*t, schema_path, mp);
  if (!t->get("type")) rd.fail_missing(mp + ".type", keyword_list(wall_motion_keywords, [](auto) { return true; }));
  m.kind = rd.keyword(*t, "type", mp, wall_motion_keywords, WallMotion::Kind::none);
  // The keys each motion takes; any other is refused, naming the type.
  const char* own[3] = {nullptr, nullptr, nullptr};
  switch (m.kind) {
    case WallMotion::Kind::translation: own[0] = "velocity"; break;
    case WallMotion::Kind::oscillation: own[0] = "amplitude"; own[1] = "frequency"; own[2] = "phase"; break;
    case WallMotion::Kind::rotation: own[0] = "origin"; own[1] = "axis"; own[2] = "angular_velocity"; break;
    case WallMotion::Kind::none: break;
  }
  const std::string type = keyword_of(wall_motion_keywords, m.kind);
  for (auto&& [k, v] : *t) {
    const std::string name(k.str());
    bool ok = name == "type";
    for (const char* o : own) ok = ok || (o && name == o);
    if (!ok) rd.fail_value(mp + "." + name, v, "no such key in a motion of type \"" + type + "\"");
  }
  switch (m.kind) {
    case WallMotion::Kind::translation:
      m.velocity = rd.vec3_required(*t, "velocity", mp, Dim::velocity);
      break;
    case WallMotion::Kind::oscillation: {
      m.amplitude = rd.vec3_required(*t, "amplitude", mp, Dim::length);
      if (!(dot(m.amplitude, m.amplitude) > 0.0))
        rd.fail_value(mp + ".amplitude", *t->get("amplitude"), "a non-zero vector (the oscillation's amplitude)");
      m.frequency = rd.positive(*t, "frequency", mp, Dim::none, true);
      m.phase = rd.number(*t, "phase", mp, Dim::none).value_or(0.0);
      break;
    }
    case WallMotion::Kind::rotation:
      m.origin = rd.vec3_required(*t, "origin", mp, Dim::length);
      m.axis = unit_vector(rd, *t, "axis", mp, "a non-zero vector (the rotation axis)");
      if (const auto w = rd.number(*t, "angular_velocity", mp, Dim::angular_velocity)) m.angular_velocity = *w;
      else rd.fail_missing(mp + ".angular_velocity", "a number [rad/s], right-handed about the axis");
      break;
    case WallMotion::Kind::none: break;
  }
  return m;
}

}  // namespace cdm::scene
