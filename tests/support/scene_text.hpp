#pragma once
// The opening most test scenes share, written once: SI units, gravity, the linear
// spring-dashpot (with Coulomb friction when a friction coefficient is given), a grain
// material and a wall material, and their contact pairs.
#include <cstdio>
#include <optional>
#include <string>

namespace cdm_test {

struct SceneHead {
  std::string grain = "glass";  ///< material of the particles, density 2500 kg/m^3
  std::string wall = "steel";   ///< material of the walls and meshes
  double kn = 1000.0;           ///< N/m, every pair
  double en = 0.5;              ///< every pair
  std::optional<double> mu = std::nullopt;  ///< friction (tangential = "spring_coulomb") when set
  bool grain_pairs = true;      ///< a grain-grain pair as well as grain-wall
};

/// A number as TOML reads it back to the same double.
inline std::string toml_number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  std::string s = b;
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

inline std::string scene_head(const SceneHead& h = {}) {
  std::string s = "units = \"SI\"\n[modules]\ngravity = true\nnormal_contact = \"linear_spring_dashpot\"\n";
  if (h.mu) s += "tangential = \"spring_coulomb\"\n";
  s += "[gravity]\ng = [0.0, 0.0, -9.81]\n";
  s += "[[materials]]\nname = \"" + h.grain + "\"\ndensity = 2500.0\n";
  s += "[[materials]]\nname = \"" + h.wall + "\"\n";
  auto pair = [&](const std::string& a, const std::string& b) {
    s += "[[contacts]]\npair = [\"" + a + "\", \"" + b + "\"]\nkn = " + toml_number(h.kn) + "\nen = " + toml_number(h.en) + "\n";
    if (h.mu) s += "mu = " + toml_number(*h.mu) + "\n";
  };
  if (h.grain_pairs) pair(h.grain, h.grain);
  pair(h.grain, h.wall);
  return s;
}

/// The floor z = 0, facing up, of @p material.
inline std::string floor_wall(const std::string& material = "steel") {
  return "[[walls]]\nname = \"floor\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\nmaterial = \"" + material + "\"\n";
}

/// A gas periodic along every axis.
inline const std::string periodic_gas_boundaries = R"([gas.boundaries]
x_lower = "periodic"
x_upper = "periodic"
y_lower = "periodic"
y_upper = "periodic"
z_lower = "periodic"
z_upper = "periodic"
)";

}  // namespace cdm_test
