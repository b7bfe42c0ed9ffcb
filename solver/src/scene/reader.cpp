/// @file reader.cpp
/// @brief The TOML reading layer of the scene loader (reader.hpp) and the schema of keys.
#include "reader.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace cdm::scene {

// docs/scene-reference.md documents each key and a test keeps the two in step.
const std::map<std::string, std::vector<std::string>>& schema() {
  static const std::map<std::string, std::vector<std::string>> s = {
      {"", {"units", "modules", "gravity", "materials", "contacts", "walls", "particles",
            "lattices", "shells", "random_particles", "gas", "drag", "coupling", "integrator", "output", "checks",
            "periodic", "neighbour_list", "monitors",
            "meshes", "insertions", "outlets"}},
      {"periodic", {"x", "y", "z"}},
      {"neighbour_list", {"sort_interval"}},
      {"modules", {"gravity", "normal_contact", "tangential", "rolling_resistance", "gas", "drag", "pressure_gradient",
                   "tracers"}},
      {"gas", {"dimension", "lower", "upper", "cells", "boundaries", "density", "viscosity", "interpolation", "field",
               "dt", "advection", "pressure_solver", "pressure_tolerance", "division", "initial_velocity",
               "mean_pressure_gradient"}},
      {"gas.boundaries.*", {"type", "velocity", "pressure"}},
      {"coupling", {"mode", "method", "kernel", "kernel_width", "gas_velocity", "gas_drag", "drag_evaluation"}},
      {"gas.boundaries", {"x_lower", "x_upper", "y_lower", "y_upper", "z_lower", "z_upper"}},
      {"gas.field", {"type", "amplitude", "period", "wavenumber", "velocity", "pressure_gradient"}},
      {"drag", {"update", "void_fraction"}},
      {"shells[]", {"material", "radius", "center", "shell_radius", "count", "dimension"}},
      {"random_particles[]", {"material", "radius", "size", "lower", "upper", "cylinder", "count", "seed", "allow_overlap"}},
      {"random_particles[].size", {"distribution", "basis", "radii", "fractions", "mean", "std", "median", "sigma", "min", "max"}},
      {"insertions[]", {"material", "radius", "size", "lower", "upper", "cylinder", "count_rate", "mass_rate", "count", "mass", "start",
                        "end", "interval", "velocity", "seed"}},
      {"random_particles[].cylinder", {"point", "axis", "radius", "length"}},
      {"insertions[].cylinder", {"point", "axis", "radius", "length"}},
      {"insertions[].size", {"distribution", "basis", "radii", "fractions", "mean", "std", "median", "sigma", "min", "max"}},
      {"outlets[]", {"name", "type", "point", "normal", "lower", "upper"}},
      {"gravity", {"g"}},
      {"materials[]", {"name", "density", "youngs_modulus", "poisson_ratio", "fixed"}},
      {"contacts[]", {"pair", "model", "kn", "en", "damping", "kt_factor", "etat_factor", "mu", "rolling_mu"}},
      {"walls[]", {"name", "type", "point", "normal", "material", "axis", "radius", "radius_start", "radius_end",
                   "length", "caps", "side", "motion"}},
      {"walls[].motion", motion_keys()},
      {"meshes[]", {"name", "file", "scale", "offset", "rotation", "material", "motion"}},
      {"meshes[].motion", motion_keys()},
      {"particles[]", {"material", "radius", "position", "velocity", "angular_velocity"}},
      {"lattices[]", {"material", "radius", "size", "origin", "spacing", "count", "velocity", "velocity_jitter", "seed"}},
      {"lattices[].size", {"distribution", "basis", "radii", "fractions", "mean", "std", "median", "sigma", "min", "max"}},
      {"integrator", {"scheme", "dt", "dt_divisor", "impact_velocity", "rayleigh_fraction", "end_time"}},
      {"output", {"interval", "particles", "vtk", "vtk_format", "contacts", "checkpoint_interval", "log_interval"}},
      {"monitors[]", {"name", "type", "point", "axis", "position", "from", "to", "threshold", "bin", "wall"}},
      {"checks", {"allow_initial_overlap", "max_overlap_fraction"}},
  };
  return s;
}

namespace {

template <class E, std::size_t N, class Keep>
std::vector<std::string> names(const Keywords<E, N>& table, Keep keep, const char* first = nullptr) {
  std::vector<std::string> v;
  if (first) v.emplace_back(first);
  for (const auto& k : table)
    if (keep(k.value)) v.emplace_back(k.name);
  return v;
}

template <class E, std::size_t N>
std::vector<std::string> names(const Keywords<E, N>& table, const char* first = nullptr) {
  return names(table, [](E) { return true; }, first);
}

}  // namespace

const std::map<std::string, std::vector<std::string>>& keyword_schema() {
  static const std::map<std::string, std::vector<std::string>> s = {
      {"units", names(units_keywords)},
      {"modules.normal_contact", names(contact_law_keywords, "none")},
      {"modules.tangential", names(tangential_keywords)},
      {"modules.rolling_resistance", names(rolling_keywords)},
      {"modules.gas", names(gas_model_keywords)},
      {"modules.drag", names(coupling::drag_law_keywords, "none")},
      {"contacts[].model", names(contact_law_keywords)},
      {"contacts[].damping", names(hertz_damping_keywords)},
      {"drag.update", names(coupling::drag_update_keywords)},
      {"gas.interpolation", names(fluid::interpolation_keywords)},
      {"gas.advection",
       names(fluid::advection_keywords, [](fluid::AdvectionScheme a) { return a != fluid::AdvectionScheme::none; })},
      {"gas.pressure_solver", names(fluid::pressure_backend_keywords)},
      {"gas.division", names(fluid::gas_division_keywords)},
      {"gas.boundaries.x_lower", names(fluid::boundary_keywords, [](fluid::BoundaryKind k) { return !is_open_face(k); })},
      {"gas.boundaries.*.type", names(fluid::boundary_keywords, is_open_face)},
      {"gas.field.type", names(fluid::field_type_keywords)},
      {"coupling.mode", names(coupling_mode_keywords)},
      {"coupling.method", names(coupling::coupling_method_keywords)},
      {"coupling.kernel", names(coupling::kernel_keywords)},
      {"coupling.gas_velocity", names(coupling::slip_velocity_keywords)},
      {"coupling.gas_drag", names(gas_drag_keywords)},
      {"integrator.scheme", names(integrator_keywords)},
      {"monitors[].type", names(monitor_keywords)},
      {"monitors[].axis", {"x", "y", "z"}},
      {"output.vtk_format", names(vtk::encoding_keywords)},
      {"walls[].type", names(wall_type_keywords)},
      {"walls[].caps", names(wall_caps_keywords)},
      {"walls[].side", names(wall_side_keywords)},
      {"walls[].motion.type", names(wall_motion_keywords)},
      {"lattices[].size.distribution", names(size_kind_keywords)},
      {"lattices[].size.basis", names(size_basis_keywords)},
      {"random_particles[].size.distribution", names(size_kind_keywords)},
      {"random_particles[].size.basis", names(size_basis_keywords)},
      {"insertions[].size.distribution", names(size_kind_keywords)},
      {"insertions[].size.basis", names(size_basis_keywords)},
      {"outlets[].type", {"plane", "box"}},
      {"meshes[].motion.type", names(wall_motion_keywords)},
  };
  return s;
}

std::string show(const toml::node& n) {
  std::ostringstream os;
  if (n.is_table()) os << "{table}";
  else if (auto a = n.as_array()) os << *a;
  else if (auto s = n.as_string()) os << '"' << s->get() << '"';
  else if (auto i = n.as_integer()) os << i->get();
  else if (auto f = n.as_floating_point()) os << f->get();
  else if (auto b = n.as_boolean()) os << (b->get() ? "true" : "false");
  else if (auto d = n.as_date()) os << *d << " (a date)";
  else if (auto tm = n.as_time()) os << *tm << " (a time)";
  else if (auto dt = n.as_date_time()) os << *dt << " (a date-time)";
  else os << "(value)";
  std::string r = os.str();
  if (r.size() > 80) r = r.substr(0, 77) + "...";
  return r;
}

void Reader::fail_value(const std::string& key, const toml::node& n, const std::string& expected) const {
  throw SceneError(file_ + ": key '" + key + "' = " + show(n) + ": expected " + expected);
}

void Reader::fail_missing(const std::string& key, const std::string& expected) const {
  throw SceneError(file_ + ": key '" + key + "' is missing: expected " + expected);
}

double Reader::factor(Dim d) const {
  if (!cgs_) return 1.0;
  switch (d) {
    case Dim::none: case Dim::time: case Dim::angular_velocity: return 1.0;
    case Dim::length: case Dim::velocity: case Dim::acceleration: return 1e-2;  // cm → m
    case Dim::density: return 1e3;    // g/cm^3 → kg/m^3
    case Dim::stiffness: return 1e-3; // dyn/cm → N/m
    case Dim::viscosity: return 0.1;  // P = g/(cm s) → Pa s
    case Dim::pressure_gradient: return 10.0;  // dyn/cm^3 → Pa/m
    case Dim::wavenumber: return 100.0;        // 1/cm → 1/m
    case Dim::pressure: return 0.1;            // dyn/cm^2 → Pa
  }
  return 1.0;
}

void Reader::check_keys(const toml::table& t, const std::string& schema_path, const std::string& key_path) const {
  const auto& allowed = schema().at(schema_path);
  for (auto&& [k, v] : t) {
    const std::string key(k.str());
    if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw SceneError(file_ + ": key '" + join(key_path, key) + "' is not a known key; expected one of: " + list);
    }
  }
}

const toml::table* Reader::table(const toml::table& parent, const std::string& key, const std::string& path, bool required) const {
  const toml::node* n = parent.get(key);
  if (!n) {
    if (required) fail_missing(join(path, key), "a table [" + join(path, key) + "]");
    return nullptr;
  }
  if (!n->is_table()) fail_value(join(path, key), *n, "a table");
  return n->as_table();
}

const toml::array* Reader::array_of_tables(const toml::table& parent, const std::string& key) const {
  const toml::node* n = parent.get(key);
  if (!n) return nullptr;
  if (!n->is_array_of_tables()) fail_value(key, *n, "an array of tables [[" + key + "]]");
  return n->as_array();
}

std::optional<double> Reader::number(const toml::table& t, const std::string& key, const std::string& path, Dim dim) const {
  const toml::node* n = t.get(key);
  if (!n) return std::nullopt;
  double v = 0.0;
  if (auto i = n->as_integer()) v = static_cast<double>(i->get());
  else if (auto f = n->as_floating_point()) v = f->get();
  else fail_value(join(path, key), *n, "a number");
  if (!std::isfinite(v)) fail_value(join(path, key), *n, "a finite number");
  return v * factor(dim);
}

double Reader::number_in(const toml::table& t, const std::string& key, const std::string& path, Dim dim,
                 bool required, double dflt, double lo, bool lo_open, double hi, bool hi_open,
                 const std::string& range_text) const {
  const toml::node* n = t.get(key);
  if (!n) {
    if (required) fail_missing(join(path, key), "a number " + range_text);
    return dflt;
  }
  const double si = *number(t, key, path, dim);
  const double v = si / factor(dim);
  const bool ok_lo = lo_open ? v > lo : v >= lo;
  const bool ok_hi = hi_open ? v < hi : v <= hi;
  if (!ok_lo || !ok_hi) fail_value(join(path, key), *n, "a number " + range_text);
  return si;
}

double Reader::positive(const toml::table& t, const std::string& key, const std::string& path, Dim dim, bool required,
                double dflt) const {
  return number_in(t, key, path, dim, required, dflt, 0.0, true, std::numeric_limits<double>::infinity(), false,
                   "> 0");
}

std::optional<Vec3> Reader::vec3(const toml::table& t, const std::string& key, const std::string& path, Dim dim) const {
  const toml::node* n = t.get(key);
  if (!n) return std::nullopt;
  const auto* a = n->as_array();
  if (!a || a->size() != 3) fail_value(join(path, key), *n, "an array of 3 numbers");
  double c[3];
  for (int i = 0; i < 3; ++i) {
    const toml::node& e = *a->get(i);
    if (auto iv = e.as_integer()) c[i] = static_cast<double>(iv->get());
    else if (auto fv = e.as_floating_point()) c[i] = fv->get();
    else fail_value(join(path, key), *n, "an array of 3 numbers");
    if (!std::isfinite(c[i])) fail_value(join(path, key), *n, "an array of 3 finite numbers");
  }
  const double f = factor(dim);
  return Vec3{c[0] * f, c[1] * f, c[2] * f};
}

Vec3 Reader::vec3_required(const toml::table& t, const std::string& key, const std::string& path, Dim dim) const {
  auto v = vec3(t, key, path, dim);
  if (!v) fail_missing(join(path, key), "an array of 3 numbers");
  return *v;
}

std::optional<std::string> Reader::string(const toml::table& t, const std::string& key, const std::string& path) const {
  const toml::node* n = t.get(key);
  if (!n) return std::nullopt;
  if (!n->is_string()) fail_value(join(path, key), *n, "a string");
  return n->as_string()->get();
}

std::optional<bool> Reader::boolean(const toml::table& t, const std::string& key, const std::string& path) const {
  const toml::node* n = t.get(key);
  if (!n) return std::nullopt;
  if (!n->is_boolean()) fail_value(join(path, key), *n, "true or false");
  return n->as_boolean()->get();
}

int Reader::material_index(const SceneSpec& spec, const toml::table& t, const std::string& key, const std::string& path) const {
  auto name = string(t, key, path);
  if (!name) fail_missing(join(path, key), "the name of a material in [[materials]]");
  for (std::size_t i = 0; i < spec.materials.size(); ++i)
    if (spec.materials[i].name == *name) return static_cast<int>(i);
  fail_value(join(path, key), *t.get(key), "the name of a material in [[materials]]");
}

void Reader::reject_unused(const toml::table& t, const std::string& key, const std::string& path, const std::string& why) const {
  if (const toml::node* n = t.get(key))
    throw SceneError(file_ + ": key '" + join(path, key) + "' = " + show(*n) + " is not used: " + why);
}

}  // namespace cdm::scene
