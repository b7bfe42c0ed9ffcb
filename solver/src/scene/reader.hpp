#pragma once
/// @file reader.hpp
/// @brief The TOML reading layer of the scene loader: typed values, cgs → SI factors,
/// keywords and the schema of accepted keys. Every error names the file, the key, the
/// value and what was expected.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <toml++/toml.h>
#include <vector>

#include "cdm/solver/keywords.hpp"
#include "cdm/solver/scene.hpp"
#include "cdm/solver/scene_loader.hpp"

namespace cdm::scene {

/// Physical dimension of a value, for cgs → SI conversion.
enum class Dim {
  none, length, time, density, velocity, acceleration, stiffness, angular_velocity,
  viscosity, pressure_gradient, wavenumber, pressure
};

constexpr std::size_t max_particles = 50'000'000;  // refuse scenes that would allocate without bound

/// The keys of a `motion` table (walls[].motion, and any wall-like block that moves).
inline std::vector<std::string> motion_keys() {
  return {"type", "velocity", "amplitude", "frequency", "phase", "origin", "axis", "angular_velocity"};
}

/// Every table the loader reads and the keys it accepts there ("" is the root, "x[]" the
/// entries of an array of tables). Keys not listed are errors.
const std::map<std::string, std::vector<std::string>>& schema();

/// The choices that are no enum: the file's units (value: cgs) and the coupling mode
/// (value: two-way).
inline constexpr Keywords<bool, 2> units_keywords{{{"SI", false}, {"cgs", true}}};
inline constexpr Keywords<bool, 2> coupling_mode_keywords{{{"one_way", false}, {"two_way", true}}};
inline constexpr Keywords<bool, 2> gas_drag_keywords{{{"implicit", true}, {"explicit", false}}};
/// The shapes a [[walls]] entry takes, and the ends a surface of revolution closes.
enum class WallType { plane, cylinder, cone };
inline constexpr Keywords<WallType, 3> wall_type_keywords{
    {{"plane", WallType::plane}, {"cylinder", WallType::cylinder}, {"cone", WallType::cone}}};
enum class WallCaps { none, start, end, both };
inline constexpr Keywords<WallCaps, 4> wall_caps_keywords{
    {{"none", WallCaps::none}, {"start", WallCaps::start}, {"end", WallCaps::end}, {"both", WallCaps::both}}};
/// walls[].side: true for particles inside.
inline constexpr Keywords<bool, 2> wall_side_keywords{{{"inside", true}, {"outside", false}}};
/// A gas face given by a table (solved gas) rather than a keyword.
inline bool is_open_face(fluid::BoundaryKind k) {
  return k == fluid::BoundaryKind::velocity_inlet || k == fluid::BoundaryKind::pressure_outlet;
}
/// The keywords each key that takes one accepts (scene_schema_keywords()).
const std::map<std::string, std::vector<std::string>>& keyword_schema();

/// A value as the file wrote it, shortened for messages.
std::string show(const toml::node& n);
inline std::string join(const std::string& a, const std::string& b) { return a.empty() ? b : a + "." + b; }

class Reader {
 public:
  Reader(std::string file, const toml::table& root) : file_(std::move(file)), root_(root) {}

  const std::string& file() const { return file_; }
  const toml::table& root() const { return root_; }
  void set_cgs(bool cgs) { cgs_ = cgs; }

  [[noreturn]] void fail_value(const std::string& key, const toml::node& n, const std::string& expected) const;
  [[noreturn]] void fail_missing(const std::string& key, const std::string& expected) const;

  /// SI value of one unit of @p d as the file writes it.
  double factor(Dim d) const;

  void check_keys(const toml::table& t, const std::string& schema_path, const std::string& key_path) const;
  const toml::table* table(const toml::table& parent, const std::string& key, const std::string& path, bool required) const;
  const toml::array* array_of_tables(const toml::table& parent, const std::string& key) const;

  std::optional<double> number(const toml::table& t, const std::string& key, const std::string& path, Dim dim) const;
  /// Number with a range check made in the file's own units (so the message shows what was written).
  double number_in(const toml::table& t, const std::string& key, const std::string& path, Dim dim, bool required,
                   double dflt, double lo, bool lo_open, double hi, bool hi_open, const std::string& range_text) const;
  double positive(const toml::table& t, const std::string& key, const std::string& path, Dim dim, bool required,
                  double dflt = 0.0) const;
  std::optional<Vec3> vec3(const toml::table& t, const std::string& key, const std::string& path, Dim dim) const;
  Vec3 vec3_required(const toml::table& t, const std::string& key, const std::string& path, Dim dim) const;
  std::optional<std::string> string(const toml::table& t, const std::string& key, const std::string& path) const;
  std::optional<bool> boolean(const toml::table& t, const std::string& key, const std::string& path) const;

  /// The value of the keyword at @p key (@p dflt when absent). A keyword not in @p kw, or
  /// one @p allowed refuses, is an error that lists the allowed keywords and @p note.
  template <class E, std::size_t N, class Allowed>
  E keyword(const toml::table& t, const std::string& key, const std::string& path, const Keywords<E, N>& kw, E dflt,
            Allowed allowed, const std::string& note = "") const {
    const auto s = string(t, key, path);
    if (!s) return dflt;
    const auto v = keyword_value(kw, *s);
    if (!v || !allowed(*v)) fail_value(join(path, key), *t.get(key), keyword_list(kw, allowed) + note);
    return *v;
  }
  template <class E, std::size_t N>
  E keyword(const toml::table& t, const std::string& key, const std::string& path, const Keywords<E, N>& kw,
            E dflt) const {
    return keyword(t, key, path, kw, dflt, [](E) { return true; });
  }
  /// Like keyword(), with "none" (or absence) for no value.
  template <class E, std::size_t N>
  std::optional<E> keyword_or_none(const toml::table& t, const std::string& key, const std::string& path,
                                   const Keywords<E, N>& kw) const {
    const auto s = string(t, key, path);
    if (!s || *s == "none") return std::nullopt;
    const auto v = keyword_value(kw, *s);
    if (!v) fail_value(join(path, key), *t.get(key), keyword_list(kw, [](E) { return true; }, "none"));
    return v;
  }

  /// Index of the material named at @p key.
  int material_index(const SceneSpec& spec, const toml::table& t, const std::string& key, const std::string& path) const;
  /// Reject a key that exists but belongs to a module the scene does not build.
  void reject_unused(const toml::table& t, const std::string& key, const std::string& path, const std::string& why) const;

 private:
  std::string file_;
  const toml::table& root_;
  bool cgs_ = false;
};

}  // namespace cdm::scene
