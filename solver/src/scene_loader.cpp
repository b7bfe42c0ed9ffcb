/// @file scene_loader.cpp
/// @brief TOML scene → validated SceneSpec in SI units. The only place in solver/ that
/// reads TOML or converts units (cgs → SI, once, here).
#include "cdm/solver/scene_loader.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <tuple>
#include <toml++/toml.h>

#include "cdm/solver/contact/hertz_mindlin.hpp"
#include "cdm/solver/neighbour_search.hpp"
#include "scene_override.hpp"

namespace cdm {

std::string particle_source(const SceneSpec& spec, std::size_t i) {
  for (const auto& g : spec.groups)
    if (i >= g.first && i < g.first + g.count) {
      if (g.nx == 0) return g.key;
      const auto k = static_cast<long long>(i - g.first);
      return g.key + " (lattice site " + std::to_string(k % g.nx) + "," + std::to_string((k / g.nx) % g.ny) + "," +
             std::to_string(k / (g.nx * g.ny)) + ")";
    }
  return "particle " + std::to_string(i);
}

const char* to_string(IntegratorScheme s) {
  switch (s) {
    case IntegratorScheme::paper_euler: return "paper_euler";
    case IntegratorScheme::velocity_verlet: return "velocity_verlet";
    case IntegratorScheme::rk2: return "rk2";
    case IntegratorScheme::rk4: return "rk4";
    case IntegratorScheme::exponential_midpoint: return "exponential_midpoint";
  }
  return "?";
}

namespace {

// ---------------------------------------------------------------------------------
// Schema: every table the loader reads and the keys it accepts there. Keys not listed
// are errors; docs/scene-reference.md documents each and a test keeps them in step.
// ---------------------------------------------------------------------------------
const std::map<std::string, std::vector<std::string>>& schema() {
  static const std::map<std::string, std::vector<std::string>> s = {
      {"", {"units", "modules", "gravity", "materials", "contacts", "walls", "particles",
            "lattices", "shells", "random_particles", "gas", "drag", "coupling", "integrator", "output", "checks",
            "periodic", "neighbour_list"}},
      {"periodic", {"x", "y", "z"}},
      {"neighbour_list", {"sort_interval"}},
      {"modules", {"gravity", "normal_contact", "tangential", "rolling_resistance", "gas", "drag", "pressure_gradient",
                   "tracers"}},
      {"gas", {"dimension", "lower", "upper", "cells", "boundaries", "density", "viscosity", "interpolation", "field",
               "dt", "advection", "initial_velocity", "mean_pressure_gradient"}},
      {"gas.boundaries.*", {"type", "velocity", "pressure"}},
      {"coupling", {"mode", "method", "kernel", "kernel_width", "gas_velocity"}},
      {"gas.boundaries", {"x_lower", "x_upper", "y_lower", "y_upper", "z_lower", "z_upper"}},
      {"gas.field", {"type", "amplitude", "period", "wavenumber", "velocity", "pressure_gradient"}},
      {"drag", {"update", "void_fraction"}},
      {"shells[]", {"material", "radius", "center", "shell_radius", "count", "dimension"}},
      {"random_particles[]", {"material", "radius", "lower", "upper", "count", "seed", "allow_overlap"}},
      {"gravity", {"g"}},
      {"materials[]", {"name", "density", "youngs_modulus", "poisson_ratio", "fixed"}},
      {"contacts[]", {"pair", "model", "kn", "en", "damping", "kt_factor", "etat_factor", "mu", "rolling_mu"}},
      {"walls[]", {"name", "point", "normal", "material"}},
      {"particles[]", {"material", "radius", "position", "velocity", "angular_velocity"}},
      {"lattices[]", {"material", "radius", "origin", "spacing", "count", "velocity", "velocity_jitter", "seed"}},
      {"integrator", {"scheme", "dt", "dt_divisor", "impact_velocity", "rayleigh_fraction", "end_time"}},
      {"output", {"interval", "particles", "vtk", "checkpoint_interval"}},
      {"checks", {"allow_initial_overlap", "max_overlap_fraction"}},
  };
  return s;
}

// Physical dimension of a value, for cgs → SI conversion.
enum class Dim {
  none, length, time, density, velocity, acceleration, stiffness, angular_velocity,
  viscosity, pressure_gradient, wavenumber, pressure
};

constexpr std::size_t max_particles = 50'000'000;  // refuse scenes that would allocate without bound

std::string show(const toml::node& n) {
  std::ostringstream os;
  if (n.is_table()) os << "{table}";
  else if (auto a = n.as_array()) os << *a;
  else if (auto s = n.as_string()) os << '"' << s->get() << '"';
  else if (auto i = n.as_integer()) os << i->get();
  else if (auto f = n.as_floating_point()) os << f->get();
  else if (auto b = n.as_boolean()) os << (b->get() ? "true" : "false");
  else os << "(value)";
  std::string r = os.str();
  if (r.size() > 80) r = r.substr(0, 77) + "...";
  return r;
}

class Loader {
 public:
  Loader(std::string file, toml::table root) : file_(std::move(file)), root_(std::move(root)) {}

  SceneSpec load();

 private:
  std::string file_;
  toml::table root_;
  SceneSpec spec_;
  bool cgs_ = false;

  [[noreturn]] void fail_value(const std::string& key, const toml::node& n, const std::string& expected) const {
    throw SceneError(file_ + ": key '" + key + "' = " + show(n) + ": expected " + expected);
  }
  [[noreturn]] void fail_missing(const std::string& key, const std::string& expected) const {
    throw SceneError(file_ + ": key '" + key + "' is missing: expected " + expected);
  }
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw SceneError(file_ + ": key '" + key + "': " + what);
  }

  double factor(Dim d) const {
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

  static std::string join(const std::string& a, const std::string& b) { return a.empty() ? b : a + "." + b; }

  void check_keys(const toml::table& t, const std::string& schema_path, const std::string& key_path) const {
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

  const toml::table* table(const toml::table& parent, const std::string& key, const std::string& path, bool required) const {
    const toml::node* n = parent.get(key);
    if (!n) {
      if (required) fail_missing(join(path, key), "a table [" + join(path, key) + "]");
      return nullptr;
    }
    if (!n->is_table()) fail_value(join(path, key), *n, "a table");
    return n->as_table();
  }

  const toml::array* array_of_tables(const toml::table& parent, const std::string& key) const {
    const toml::node* n = parent.get(key);
    if (!n) return nullptr;
    if (!n->is_array_of_tables()) fail_value(key, *n, "an array of tables [[" + key + "]]");
    return n->as_array();
  }

  std::optional<double> number(const toml::table& t, const std::string& key, const std::string& path, Dim dim) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    double v = 0.0;
    if (auto i = n->as_integer()) v = static_cast<double>(i->get());
    else if (auto f = n->as_floating_point()) v = f->get();
    else fail_value(join(path, key), *n, "a number");
    if (!std::isfinite(v)) fail_value(join(path, key), *n, "a finite number");
    return v * factor(dim);
  }

  // Number with a range check made in the file's own units (so the message shows what was written).
  double number_in(const toml::table& t, const std::string& key, const std::string& path, Dim dim,
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

  double positive(const toml::table& t, const std::string& key, const std::string& path, Dim dim, bool required,
                  double dflt = 0.0) const {
    return number_in(t, key, path, dim, required, dflt, 0.0, true, std::numeric_limits<double>::infinity(), false,
                     "> 0");
  }

  std::optional<Vec3> vec3(const toml::table& t, const std::string& key, const std::string& path, Dim dim) const {
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

  Vec3 vec3_required(const toml::table& t, const std::string& key, const std::string& path, Dim dim) const {
    auto v = vec3(t, key, path, dim);
    if (!v) fail_missing(join(path, key), "an array of 3 numbers");
    return *v;
  }

  std::optional<std::string> string(const toml::table& t, const std::string& key, const std::string& path) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (!n->is_string()) fail_value(join(path, key), *n, "a string");
    return n->as_string()->get();
  }

  std::optional<bool> boolean(const toml::table& t, const std::string& key, const std::string& path) const {
    const toml::node* n = t.get(key);
    if (!n) return std::nullopt;
    if (!n->is_boolean()) fail_value(join(path, key), *n, "true or false");
    return n->as_boolean()->get();
  }

  int material_index(const toml::table& t, const std::string& key, const std::string& path) const {
    auto name = string(t, key, path);
    if (!name) fail_missing(join(path, key), "the name of a material in [[materials]]");
    for (std::size_t i = 0; i < spec_.materials.size(); ++i)
      if (spec_.materials[i].name == *name) return static_cast<int>(i);
    fail_value(join(path, key), *t.get(key), "the name of a material in [[materials]]");
  }

  // Reject a key that exists but belongs to a module the scene does not build.
  void reject_unused(const toml::table& t, const std::string& key, const std::string& path, const std::string& why) const {
    if (const toml::node* n = t.get(key))
      throw SceneError(file_ + ": key '" + join(path, key) + "' = " + show(*n) + " is not used: " + why);
  }

  void read_units();
  void read_modules();
  void read_materials();
  void read_contacts();
  void check_elastic_constants_used() const;
  void read_walls();
  void read_periodic();
  void read_particles();
  void read_gas();
  void read_solved_gas(const toml::table& gt);
  void read_integrator();
  void read_output_and_checks();
  void check_initial_state();
  void resolve_dt(const toml::table* integ);
};

void Loader::read_units() {
  const toml::node* n = root_.get("units");
  if (!n) fail_missing("units", "\"SI\" or \"cgs\"");
  if (!n->is_string()) fail_value("units", *n, "\"SI\" or \"cgs\"");
  const std::string u = n->as_string()->get();
  if (u != "SI" && u != "cgs") fail_value("units", *n, "\"SI\" or \"cgs\"");
  cgs_ = u == "cgs";
  spec_.units = u;
}

void Loader::read_modules() {
  const toml::table* m = table(root_, "modules", "", true);
  check_keys(*m, "modules", "modules");
  spec_.gravity = boolean(*m, "gravity", "modules").value_or(false);
  const std::string nc = string(*m, "normal_contact", "modules").value_or("none");
  if (nc == "none") spec_.normal_contact = NormalContactModel::none;
  else if (nc == "linear_spring_dashpot") spec_.normal_contact = NormalContactModel::linear_spring_dashpot;
  else if (nc == "hertz_mindlin") spec_.normal_contact = NormalContactModel::hertz_mindlin;
  else
    fail_value("modules.normal_contact", *m->get("normal_contact"),
               "\"none\", \"linear_spring_dashpot\" or \"hertz_mindlin\"");
  const std::string tg = string(*m, "tangential", "modules").value_or("none");
  if (tg == "none") spec_.tangential = TangentialModel::none;
  else if (tg == "spring_coulomb") spec_.tangential = TangentialModel::spring_coulomb;
  else fail_value("modules.tangential", *m->get("tangential"), "\"none\" or \"spring_coulomb\"");
  if (spec_.tangential != TangentialModel::none && spec_.normal_contact == NormalContactModel::none)
    fail_value("modules.tangential", *m->get("tangential"),
               "\"none\" while modules.normal_contact is \"none\" (friction is bounded by the normal force)");
  const std::string rr = string(*m, "rolling_resistance", "modules").value_or("none");
  if (rr == "none") spec_.rolling = RollingModel::none;
  else if (rr == "constant_torque") spec_.rolling = RollingModel::constant_torque;
  else fail_value("modules.rolling_resistance", *m->get("rolling_resistance"), "\"none\" or \"constant_torque\"");
  if (spec_.rolling != RollingModel::none && spec_.normal_contact == NormalContactModel::none)
    fail_value("modules.rolling_resistance", *m->get("rolling_resistance"),
               "\"none\" while modules.normal_contact is \"none\" (the torque is bounded by the normal force)");

  // The gas and what couples particles to it.
  const std::string gas = string(*m, "gas", "modules").value_or("none");
  if (gas == "none") spec_.gas = GasModel::none;
  else if (gas == "prescribed") spec_.gas = GasModel::prescribed;
  else if (gas == "solved") spec_.gas = GasModel::solved;
  else fail_value("modules.gas", *m->get("gas"), "\"none\", \"prescribed\" or \"solved\"");
  const std::string needs_gas = "while modules.gas is \"none\" (it acts between the particles and a gas)";
  const std::string drag = string(*m, "drag", "modules").value_or("none");
  const std::string laws = "\"none\", \"schiller_naumann\", \"wen_yu\", \"gidaspow\", \"di_felice\" or \"beetstra\"";
  if (drag == "schiller_naumann") spec_.drag = coupling::DragLaw::schiller_naumann;
  else if (drag == "wen_yu") spec_.drag = coupling::DragLaw::wen_yu;
  else if (drag == "gidaspow") spec_.drag = coupling::DragLaw::gidaspow;
  else if (drag == "di_felice") spec_.drag = coupling::DragLaw::di_felice;
  else if (drag == "beetstra") spec_.drag = coupling::DragLaw::beetstra;
  else if (drag != "none") fail_value("modules.drag", *m->get("drag"), laws);
  if (spec_.drag && spec_.gas == GasModel::none) fail_value("modules.drag", *m->get("drag"), "\"none\" " + needs_gas);
  spec_.pressure_gradient = boolean(*m, "pressure_gradient", "modules").value_or(false);
  if (spec_.pressure_gradient && spec_.gas == GasModel::none)
    fail_value("modules.pressure_gradient", *m->get("pressure_gradient"), "false " + needs_gas);
  spec_.tracers = boolean(*m, "tracers", "modules").value_or(false);
  if (spec_.tracers) {
    const toml::node& n = *m->get("tracers");
    if (spec_.gas != GasModel::prescribed)
      fail_value("modules.tracers", n, "false unless modules.gas is \"prescribed\" (tracers follow a given gas field)");
    if (spec_.gravity || spec_.normal_contact != NormalContactModel::none || spec_.drag || spec_.pressure_gradient)
      fail_value("modules.tracers", n,
                 "false while gravity, contacts, drag or the pressure gradient act on the particles (tracers are "
                 "massless: they only move with the gas)");
  }

  const toml::table* g = table(root_, "gravity", "", spec_.gravity);
  if (g && !spec_.gravity)
    throw SceneError(file_ + ": table [gravity] is not used: modules.gravity is not true");
  if (g) {
    check_keys(*g, "gravity", "gravity");
    spec_.g = vec3_required(*g, "g", "gravity", Dim::acceleration);
  }
}

void Loader::read_materials() {
  const toml::array* mats = array_of_tables(root_, "materials");
  if (!mats) fail_missing("materials", "at least one [[materials]] entry");
  for (std::size_t i = 0; i < mats->size(); ++i) {
    const toml::table& t = *mats->get(i)->as_table();
    const std::string path = "materials[" + std::to_string(i) + "]";
    check_keys(t, "materials[]", path);
    Material m;
    auto name = string(t, "name", path);
    if (!name || name->empty()) fail_missing(path + ".name", "a non-empty material name");
    for (const auto& other : spec_.materials)
      if (other.name == *name) fail_value(path + ".name", *t.get("name"), "a name not used by another material");
    m.name = *name;
    m.density = positive(t, "density", path, Dim::density, false, 0.0);
    // Elastic constants: only Hertz–Mindlin pairs use them (checked in read_contacts).
    if (t.get("youngs_modulus") || t.get("poisson_ratio")) {
      if (!t.get("youngs_modulus"))
        fail_missing(path + ".youngs_modulus", "a number > 0 [Pa] (poisson_ratio is given, so the pair is needed)");
      if (!t.get("poisson_ratio"))
        fail_missing(path + ".poisson_ratio", "a number in (-1, 0.5) (youngs_modulus is given, so the pair is needed)");
      m.youngs_modulus = positive(t, "youngs_modulus", path, Dim::pressure, true);
      m.poisson_ratio = number_in(t, "poisson_ratio", path, Dim::none, true, 0.0, -1.0, true, 0.5, true, "in (-1, 0.5)");
    }
    m.fixed = boolean(t, "fixed", path).value_or(false);
    if (m.fixed) {
      if (spec_.tracers) fail_value(path + ".fixed", *t.get("fixed"), "false for tracers (they move with the gas)");
    }
    spec_.materials.push_back(m);
  }
  spec_.pairs = PairTable(spec_.materials.size());
}

void Loader::read_contacts() {
  const toml::array* cs = array_of_tables(root_, "contacts");
  if (spec_.normal_contact == NormalContactModel::none) {
    if (cs) throw SceneError(file_ + ": [[contacts]] is not used: modules.normal_contact is \"none\"");
    return;
  }
  if (!cs) return;  // missing pairs are reported where they are needed (check_initial_state)
  for (std::size_t i = 0; i < cs->size(); ++i) {
    const toml::table& t = *cs->get(i)->as_table();
    const std::string path = "contacts[" + std::to_string(i) + "]";
    check_keys(t, "contacts[]", path);
    const toml::node* pn = t.get("pair");
    if (!pn) fail_missing(path + ".pair", "an array of two material names");
    const toml::array* pa = pn->as_array();
    if (!pa || pa->size() != 2 || !pa->get(0)->is_string() || !pa->get(1)->is_string())
      fail_value(path + ".pair", *pn, "an array of two material names");
    int idx[2];
    for (int k = 0; k < 2; ++k) {
      const std::string nm = pa->get(k)->as_string()->get();
      idx[k] = -1;
      for (std::size_t m = 0; m < spec_.materials.size(); ++m)
        if (spec_.materials[m].name == nm) idx[k] = static_cast<int>(m);
      if (idx[k] < 0) fail_value(path + ".pair", *pn, "two names of materials in [[materials]]");
    }
    if (spec_.pairs.get(idx[0], idx[1]).defined)
      fail_value(path + ".pair", *pn, "a pair not already given by an earlier [[contacts]] entry");
    PairParams p;
    // The pair's force law: the scene's default (modules.normal_contact) unless it names one.
    p.law = spec_.normal_contact == NormalContactModel::hertz_mindlin ? ContactLaw::hertz_mindlin
                                                                      : ContactLaw::linear_spring_dashpot;
    if (auto model = string(t, "model", path)) {
      if (*model == "linear_spring_dashpot") p.law = ContactLaw::linear_spring_dashpot;
      else if (*model == "hertz_mindlin") p.law = ContactLaw::hertz_mindlin;
      else fail_value(path + ".model", *t.get("model"), "\"linear_spring_dashpot\" or \"hertz_mindlin\"");
    }
    const bool hertz = p.law == ContactLaw::hertz_mindlin;
    p.en = number_in(t, "en", path, Dim::none, true, 1.0, 0.0, true, 1.0, false, "in (0, 1]");
    if (!hertz) {
      p.kn = positive(t, "kn", path, Dim::stiffness, true);
      reject_unused(t, "damping", path, "the pair's model is linear_spring_dashpot, whose dashpot follows from en (eq 29)");
    } else {
      const std::string why = "the pair's model is hertz_mindlin, whose stiffnesses follow from the materials' "
                              "youngs_modulus and poisson_ratio";
      reject_unused(t, "kn", path, why);
      reject_unused(t, "kt_factor", path, why);
      reject_unused(t, "etat_factor", path, why);
      for (int k = 0; k < 2; ++k)
        if (!(spec_.materials[idx[k]].youngs_modulus > 0.0))
          fail_missing("materials[" + std::to_string(idx[k]) + "].youngs_modulus",
                       "Young's modulus and Poisson ratio of material '" + spec_.materials[idx[k]].name + "', because " +
                           path + " uses model hertz_mindlin");
      const Material& a = spec_.materials[idx[0]];
      const Material& b = spec_.materials[idx[1]];
      p.e_star = contact::effective_youngs_modulus(a.youngs_modulus, a.poisson_ratio, b.youngs_modulus, b.poisson_ratio);
      p.g_star = contact::effective_shear_modulus(a.youngs_modulus, a.poisson_ratio, b.youngs_modulus, b.poisson_ratio);
      const std::string damping = string(t, "damping", path).value_or("exact_restitution");
      if (damping == "exact_restitution") p.hertz_damping = HertzDamping::exact_restitution;
      else if (damping == "tsuji") p.hertz_damping = HertzDamping::tsuji;
      else fail_value(path + ".damping", *t.get("damping"), "\"exact_restitution\" or \"tsuji\"");
    }
    if (spec_.tangential == TangentialModel::none) {
      const std::string why = "modules.tangential is \"none\"";
      reject_unused(t, "kt_factor", path, why);
      reject_unused(t, "etat_factor", path, why);
      reject_unused(t, "mu", path, why);
    } else {
      if (!hertz) {
        p.kt_factor = positive(t, "kt_factor", path, Dim::none, false, 0.4);
        p.etat_factor = number_in(t, "etat_factor", path, Dim::none, false, 0.5, 0.0, false,
                                  std::numeric_limits<double>::infinity(), false, ">= 0");
      }
      p.mu = number_in(t, "mu", path, Dim::none, true, 0.0, 0.0, false, std::numeric_limits<double>::infinity(),
                       false, ">= 0");
    }
    if (spec_.rolling == RollingModel::none)
      reject_unused(t, "rolling_mu", path, "modules.rolling_resistance is \"none\"");
    else
      p.rolling_mu = number_in(t, "rolling_mu", path, Dim::none, true, 0.0, 0.0, false,
                               std::numeric_limits<double>::infinity(), false, ">= 0");
    spec_.pairs.set(idx[0], idx[1], p);
  }
}

// A material's Young's modulus and Poisson ratio are used only by hertz_mindlin pairs.
void Loader::check_elastic_constants_used() const {
  const std::size_t nm = spec_.materials.size();
  for (std::size_t a = 0; a < nm; ++a) {
    if (!(spec_.materials[a].youngs_modulus > 0.0)) continue;
    bool used = false;
    for (std::size_t b = 0; b < nm && !used; ++b) {
      const PairParams& pp = spec_.pairs.get(static_cast<int>(a), static_cast<int>(b));
      used = pp.defined && pp.law == ContactLaw::hertz_mindlin;
    }
    if (!used) {
      const std::string path = "materials[" + std::to_string(a) + "]";
      const toml::table& t = *root_.get("materials")->as_array()->get(a)->as_table();
      reject_unused(t, "youngs_modulus", path,
                    "no [[contacts]] entry with model hertz_mindlin involves material '" + spec_.materials[a].name + "'");
    }
  }
}

void Loader::read_walls() {
  const toml::array* ws = array_of_tables(root_, "walls");
  if (!ws) return;
  if (spec_.normal_contact == NormalContactModel::none)
    throw SceneError(file_ + ": [[walls]] is not used: modules.normal_contact is \"none\", so nothing touches a wall");
  for (std::size_t i = 0; i < ws->size(); ++i) {
    const toml::table& t = *ws->get(i)->as_table();
    const std::string path = "walls[" + std::to_string(i) + "]";
    check_keys(t, "walls[]", path);
    PlaneWall w;
    w.name = string(t, "name", path).value_or("wall" + std::to_string(i));
    w.point = vec3_required(t, "point", path, Dim::length);
    const Vec3 n = vec3_required(t, "normal", path, Dim::none);
    const double len = norm(n);
    if (!(len > 0.0)) fail_value(path + ".normal", *t.get("normal"), "a non-zero vector (pointing into the domain)");
    w.normal = (1.0 / len) * n;
    w.material = material_index(t, "material", path);
    spec_.walls.push_back(w);
  }
}

void Loader::read_periodic() {
  PeriodicBox& box = spec_.periodic;
  if (spec_.gas != GasModel::none) {
    // The particles share the gas's periodic axes (a 2D gas has no z to wrap).
    if (const toml::node* n = root_.get("periodic"))
      fail_value("periodic", *n, "no [periodic] table with a gas: the particles are periodic where gas.boundaries are");
    const fluid::GridSpec& g = spec_.gas_spec.grid;
    const double lo[3] = {g.lo.x, g.lo.y, g.lo.z}, hi[3] = {g.hi.x, g.hi.y, g.hi.z};
    for (int a = 0; a < (g.two_d ? 2 : 3); ++a)
      if (g.periodic(a)) {
        box.on[a] = true;
        box.lo[a] = lo[a];
        box.len[a] = hi[a] - lo[a];
      }
    return;
  }
  const toml::node* n = root_.get("periodic");
  if (!n) return;
  const toml::table* t = n->as_table();
  if (!t) fail_value("periodic", *n, "a table with x, y and/or z = [lower, upper]");
  check_keys(*t, "periodic", "periodic");
  const char* axes[3] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    const toml::node* e = t->get(axes[a]);
    if (!e) continue;
    const std::string key = std::string("periodic.") + axes[a];
    const toml::array* arr = e->as_array();
    double c[2] = {0.0, 0.0};
    if (!arr || arr->size() != 2) fail_value(key, *e, "an array [lower, upper] of 2 numbers");
    for (int i = 0; i < 2; ++i) {
      const toml::node& v = *arr->get(static_cast<std::size_t>(i));
      if (auto iv = v.as_integer()) c[i] = static_cast<double>(iv->get());
      else if (auto fv = v.as_floating_point()) c[i] = fv->get();
      else fail_value(key, *e, "an array [lower, upper] of 2 numbers");
    }
    if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !(c[1] > c[0]))
      fail_value(key, *e, "[lower, upper] with finite lower < upper");
    box.on[a] = true;
    box.lo[a] = c[0] * factor(Dim::length);
    box.len[a] = (c[1] - c[0]) * factor(Dim::length);
  }
  if (!box.any()) fail_value("periodic", *n, "at least one of x, y, z");
}

void Loader::read_particles() {
  auto particle_material = [&](const toml::table& t, const std::string& path) {
    const int m = material_index(t, "material", path);
    if (!(spec_.materials[m].density > 0.0) && !spec_.tracers)
      fail_value(path + ".material", *t.get("material"),
                 "a material with a density (materials entry '" + spec_.materials[m].name + "' has none)");
    return m;
  };
  if (const toml::array* ps = array_of_tables(root_, "particles")) {
    for (std::size_t i = 0; i < ps->size(); ++i) {
      const toml::table& t = *ps->get(i)->as_table();
      const std::string path = "particles[" + std::to_string(i) + "]";
      check_keys(t, "particles[]", path);
      ParticleSpec p;
      p.material = particle_material(t, path);
      p.radius = positive(t, "radius", path, Dim::length, true);
      p.position = vec3_required(t, "position", path, Dim::length);
      if (spec_.tracers) reject_unused(t, "velocity", path, "modules.tracers is true: a tracer moves with the gas");
      p.velocity = vec3(t, "velocity", path, Dim::velocity).value_or(Vec3{});
      if (spec_.tangential == TangentialModel::none && spec_.rolling == RollingModel::none)
        reject_unused(t, "angular_velocity", path,
                      "modules.tangential and modules.rolling_resistance are \"none\", so particles do not rotate");
      p.angular_velocity = vec3(t, "angular_velocity", path, Dim::angular_velocity).value_or(Vec3{});
      spec_.groups.push_back({path, spec_.particles.size(), 1, 0, 0});
      spec_.particles.push_back(p);
    }
  }
  if (const toml::array* ls = array_of_tables(root_, "lattices")) {
    for (std::size_t i = 0; i < ls->size(); ++i) {
      const toml::table& t = *ls->get(i)->as_table();
      const std::string path = "lattices[" + std::to_string(i) + "]";
      check_keys(t, "lattices[]", path);
      const int mat = particle_material(t, path);
      const double r = positive(t, "radius", path, Dim::length, true);
      const Vec3 origin = vec3_required(t, "origin", path, Dim::length);
      const Vec3 spacing = vec3_required(t, "spacing", path, Dim::length);
      if (!(spacing.x > 0 && spacing.y > 0 && spacing.z > 0))
        fail_value(path + ".spacing", *t.get("spacing"), "3 numbers > 0");
      if (spec_.tracers) {
        reject_unused(t, "velocity", path, "modules.tracers is true: a tracer moves with the gas");
        reject_unused(t, "velocity_jitter", path, "modules.tracers is true: a tracer moves with the gas");
      }
      const Vec3 vel = vec3(t, "velocity", path, Dim::velocity).value_or(Vec3{});
      const double jitter = number_in(t, "velocity_jitter", path, Dim::velocity, false, 0.0, 0.0, false,
                                      std::numeric_limits<double>::infinity(), false, ">= 0");
      long long seed = 1;
      if (const toml::node* sn = t.get("seed")) {
        if (!sn->is_integer() || sn->as_integer()->get() < 0) fail_value(path + ".seed", *sn, "an integer >= 0");
        if (!(jitter > 0.0)) reject_unused(t, "seed", path, "velocity_jitter is 0");
        seed = sn->as_integer()->get();
      }
      // Uniform in [-jitter, jitter] per component from a 64-bit Mersenne twister with a
      // fixed mapping to doubles, so a scene gives the same particles on every platform.
      std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
      auto uniform = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53 * 2.0 - 1.0; };
      const toml::node* cn = t.get("count");
      if (!cn) fail_missing(path + ".count", "an array of 3 integers >= 1");
      const toml::array* ca = cn->as_array();
      long long c[3] = {0, 0, 0};
      if (!ca || ca->size() != 3) fail_value(path + ".count", *cn, "an array of 3 integers >= 1");
      for (int k = 0; k < 3; ++k) {
        auto iv = ca->get(k)->as_integer();
        if (!iv || iv->get() < 1) fail_value(path + ".count", *cn, "an array of 3 integers >= 1");
        c[k] = iv->get();
      }
      if (static_cast<double>(c[0]) * c[1] * c[2] + spec_.particles.size() > max_particles)
        fail_value(path + ".count", *cn, "at most " + std::to_string(max_particles) + " particles in the scene");
      spec_.groups.push_back({path, spec_.particles.size(), static_cast<std::size_t>(c[0] * c[1] * c[2]), c[0], c[1]});
      spec_.particles.reserve(spec_.particles.size() + static_cast<std::size_t>(c[0] * c[1] * c[2]));
      for (long long kz = 0; kz < c[2]; ++kz)
        for (long long ky = 0; ky < c[1]; ++ky)
          for (long long kx = 0; kx < c[0]; ++kx) {
            ParticleSpec p;
            p.material = mat;
            p.radius = r;
            p.position = origin + Vec3{kx * spacing.x, ky * spacing.y, kz * spacing.z};
            p.velocity = vel;
            if (jitter > 0.0) {
              const double a = uniform(), b = uniform(), c2 = uniform();
              p.velocity += Vec3{jitter * a, jitter * b, jitter * c2};
            }
            spec_.particles.push_back(p);
          }
    }
  }
  if (const toml::array* ss = array_of_tables(root_, "shells")) {
    // Particles evenly spread on a circle (dimension 2, in the plane z = center.z) or on
    // a sphere (dimension 3, a Fibonacci lattice: point k at height 1 − (2k+1)/n and
    // azimuth k·π(3 − √5)), at rest (or moving with the gas, for tracers).
    for (std::size_t i = 0; i < ss->size(); ++i) {
      const toml::table& t = *ss->get(i)->as_table();
      const std::string path = "shells[" + std::to_string(i) + "]";
      check_keys(t, "shells[]", path);
      const int mat = particle_material(t, path);
      const double r = positive(t, "radius", path, Dim::length, true);
      const Vec3 c = vec3_required(t, "center", path, Dim::length);
      const double R = positive(t, "shell_radius", path, Dim::length, true);
      const toml::node* cn = t.get("count");
      if (!cn) fail_missing(path + ".count", "an integer >= 1");
      if (!cn->is_integer() || cn->as_integer()->get() < 1 ||
          static_cast<double>(cn->as_integer()->get()) + spec_.particles.size() > max_particles)
        fail_value(path + ".count", *cn, "an integer >= 1 (at most " + std::to_string(max_particles) + " particles in the scene)");
      const auto count = static_cast<std::size_t>(cn->as_integer()->get());
      long long dim = 2;
      if (const toml::node* dn = t.get("dimension")) {
        if (!dn->is_integer() || (dn->as_integer()->get() != 2 && dn->as_integer()->get() != 3))
          fail_value(path + ".dimension", *dn, "2 (a circle in the x-y plane) or 3 (a sphere)");
        dim = dn->as_integer()->get();
      } else {
        fail_missing(path + ".dimension", "2 (a circle in the x-y plane) or 3 (a sphere)");
      }
      spec_.groups.push_back({path, spec_.particles.size(), count, 0, 0});
      const double golden = std::numbers::pi * (3.0 - std::sqrt(5.0));
      for (std::size_t k = 0; k < count; ++k) {
        ParticleSpec p;
        p.material = mat;
        p.radius = r;
        if (dim == 2) {
          const double a = 2.0 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(count);
          p.position = c + Vec3{R * std::cos(a), R * std::sin(a), 0.0};
        } else {
          const double zk = 1.0 - (2.0 * static_cast<double>(k) + 1.0) / static_cast<double>(count);
          const double rho = std::sqrt(std::max(0.0, 1.0 - zk * zk)), a = golden * static_cast<double>(k);
          p.position = c + Vec3{R * rho * std::cos(a), R * rho * std::sin(a), R * zk};
        }
        spec_.particles.push_back(p);
      }
    }
  }
  if (const toml::array* rs = array_of_tables(root_, "random_particles")) {
    // Centres uniform in a box, from a 64-bit Mersenne twister with a fixed mapping to
    // doubles (the same particles on every platform). With a normal-contact model each
    // new particle must clear every earlier one and the walls (random sequential
    // addition); without one, overlaps are allowed — nothing acts between particles.
    for (std::size_t i = 0; i < rs->size(); ++i) {
      const toml::table& t = *rs->get(i)->as_table();
      const std::string path = "random_particles[" + std::to_string(i) + "]";
      check_keys(t, "random_particles[]", path);
      const int mat = particle_material(t, path);
      const double r = positive(t, "radius", path, Dim::length, true);
      const Vec3 lo = vec3_required(t, "lower", path, Dim::length), hi = vec3_required(t, "upper", path, Dim::length);
      if (!(hi.x >= lo.x && hi.y >= lo.y && hi.z >= lo.z))
        fail_value(path + ".upper", *t.get("upper"), "a corner at or above " + path + ".lower along every axis");
      const toml::node* cn = t.get("count");
      if (!cn) fail_missing(path + ".count", "an integer >= 1");
      if (!cn->is_integer() || cn->as_integer()->get() < 1 ||
          static_cast<double>(cn->as_integer()->get()) + spec_.particles.size() > max_particles)
        fail_value(path + ".count", *cn, "an integer >= 1 (at most " + std::to_string(max_particles) + " particles in the scene)");
      const auto count = static_cast<std::size_t>(cn->as_integer()->get());
      long long seed = 1;
      if (const toml::node* sn = t.get("seed")) {
        if (!sn->is_integer() || sn->as_integer()->get() < 0) fail_value(path + ".seed", *sn, "an integer >= 0");
        seed = sn->as_integer()->get();
      }
      std::mt19937_64 rng(static_cast<std::uint64_t>(seed));
      auto uniform = [&] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
      const bool exclusive =
          !boolean(t, "allow_overlap", path).value_or(spec_.normal_contact == NormalContactModel::none);
      // Random sequential addition on a cell grid of edge 2r (contacts only).
      const double cell = 2.0 * r;
      std::map<std::tuple<long long, long long, long long>, std::vector<Vec3>> placed;
      auto key = [&](Vec3 x) {
        return std::make_tuple(static_cast<long long>(std::floor(x.x / cell)), static_cast<long long>(std::floor(x.y / cell)),
                               static_cast<long long>(std::floor(x.z / cell)));
      };
      auto clear = [&](Vec3 x) {
        for (const auto& w : spec_.walls)
          if (w.distance(x) < r) return false;
        const auto [a, b, c] = key(x);
        for (long long da = -1; da <= 1; ++da)
          for (long long db = -1; db <= 1; ++db)
            for (long long dc = -1; dc <= 1; ++dc) {
              auto it = placed.find({a + da, b + db, c + dc});
              if (it == placed.end()) continue;
              for (const Vec3& y : it->second)
                if (dot(x - y, x - y) < 4.0 * r * r) return false;
            }
        return true;
      };
      spec_.groups.push_back({path, spec_.particles.size(), count, 0, 0});
      // Jammed when this many tries in a row find no free place: the free volume left is
      // then below ~5e-5 of the box, and going on would only burn time (a bound on the
      // consecutive misses, not on the total, keeps the work per placed particle bounded).
      std::size_t misses = 0;
      const std::size_t max_misses = 20000;
      for (std::size_t k = 0; k < count;) {
        const double a = uniform(), b = uniform(), c = uniform();
        const Vec3 x{lo.x + a * (hi.x - lo.x), lo.y + b * (hi.y - lo.y), lo.z + c * (hi.z - lo.z)};
        if (exclusive && !clear(x)) {
          if (++misses > max_misses)
            fail_value(path + ".count", *cn,
                       "fewer particles: only " + std::to_string(k) + " fit without overlap (" +
                           std::to_string(max_misses) + " random tries in a row found no free place; random sequential "
                           "addition jams near a solids fraction of 0.38; use [[lattices]] for denser packings)");
          continue;
        }
        misses = 0;
        if (exclusive) placed[key(x)].push_back(x);
        ParticleSpec p;
        p.material = mat;
        p.radius = r;
        p.position = x;
        spec_.particles.push_back(p);
        ++k;
      }
    }
  }
  if (spec_.particles.empty() && spec_.gas != GasModel::solved)
    fail_missing("particles", "at least one [[particles]], [[lattices]], [[shells]] or [[random_particles]] entry");
}

void Loader::read_gas() {
  const toml::table* gt = table(root_, "gas", "", spec_.gas != GasModel::none);
  const toml::table* dt = table(root_, "drag", "", false);
  if (dt && !spec_.drag) throw SceneError(file_ + ": table [drag] is not used: modules.drag is \"none\"");
  if (spec_.drag) {
    static const toml::table empty;
    const toml::table& d = dt ? *dt : empty;
    check_keys(d, "drag", "drag");
    const std::string up = string(d, "update", "drag").value_or("explicit");
    if (up == "explicit") spec_.drag_update = coupling::DragUpdate::explicit_force;
    else if (up == "implicit") spec_.drag_update = coupling::DragUpdate::implicit;
    else if (up == "exponential") spec_.drag_update = coupling::DragUpdate::exponential;
    else fail_value("drag.update", *d.get("update"), "\"explicit\", \"implicit\" or \"exponential\"");
    if (spec_.drag_update != coupling::DragUpdate::explicit_force)
      for (const auto& m : spec_.materials)
        if (m.fixed)
          fail_value("drag.update", *d.get("update"),
                     "\"explicit\" while material '" + m.name + "' is fixed (a fixed particle's drag is a force on the "
                     "gas, not a velocity relaxation)");
    // Default: a solved gas supplies ε_g from the particles (0 = from the grid); a
    // prescribed gas has no particle volume, so a single particle's ε_g = 1.
    spec_.drag_void_fraction = number_in(d, "void_fraction", "drag", Dim::none, false,
                                         spec_.gas == GasModel::solved ? 0.0 : 1.0, 0.0, true, 1.0, false,
                                         "in (0, 1] (the gas volume fraction held in the drag law)");
  }
  if (!gt) return;
  if (spec_.gas == GasModel::none) throw SceneError(file_ + ": table [gas] is not used: modules.gas is \"none\"");
  check_keys(*gt, "gas", "gas");
  fluid::GasSpec& gs = spec_.gas_spec;
  fluid::GridSpec& grid = gs.grid;

  // Dimension and extent.
  long long dim = 3;
  if (const toml::node* dn = gt->get("dimension")) {
    if (!dn->is_integer() || (dn->as_integer()->get() != 2 && dn->as_integer()->get() != 3))
      fail_value("gas.dimension", *dn, "2 or 3");
    dim = dn->as_integer()->get();
  }
  grid.two_d = dim == 2;
  grid.lo = vec3_required(*gt, "lower", "gas", Dim::length);
  grid.hi = vec3_required(*gt, "upper", "gas", Dim::length);
  if (!(grid.hi.x > grid.lo.x && grid.hi.y > grid.lo.y && grid.hi.z > grid.lo.z))
    fail_value("gas.upper", *gt->get("upper"), "a corner above gas.lower along every axis");
  const toml::node* cn = gt->get("cells");
  const std::string cells_text = dim == 2 ? "an array of 2 integers >= 2 (cells along x and y)"
                                          : "an array of 3 integers >= 2 (cells along x, y and z)";
  if (!cn) fail_missing("gas.cells", cells_text);
  const toml::array* ca = cn->as_array();
  if (!ca || ca->size() != static_cast<std::size_t>(dim)) fail_value("gas.cells", *cn, cells_text);
  grid.cells = {1, 1, 1};
  double total = 1.0;
  for (long long a = 0; a < dim; ++a) {
    auto iv = ca->get(static_cast<std::size_t>(a))->as_integer();
    if (!iv || iv->get() < 2 || iv->get() > 100000) fail_value("gas.cells", *cn, cells_text + ", at most 100000 each");
    grid.cells[static_cast<std::size_t>(a)] = static_cast<int>(iv->get());
    total *= static_cast<double>(iv->get() + 5);
  }
  if (total > 2e8) fail_value("gas.cells", *cn, "at most about 2e8 grid samples in all");

  // Boundaries: one per face; periodic faces come in pairs.
  const toml::table* bt = table(*gt, "boundaries", "gas", true);
  check_keys(*bt, "gas.boundaries", "gas.boundaries");
  const char* face_names[6] = {"x_lower", "x_upper", "y_lower", "y_upper", "z_lower", "z_upper"};
  for (int f = 0; f < 6; ++f) {
    const std::string key = face_names[f];
    if (dim == 2 && f >= 4) {
      reject_unused(*bt, key, "gas.boundaries", "a two-dimensional gas has no z boundaries");
      grid.faces[f].kind = fluid::BoundaryKind::periodic;
      continue;
    }
    const bool solved = spec_.gas == GasModel::solved;
    const std::string kinds = solved ? "\"periodic\", \"no_slip\", \"free_slip\", { type = \"velocity_inlet\", velocity = "
                                       "<inward speed> } or { type = \"pressure_outlet\", pressure = <p> }"
                                     : "\"periodic\", \"no_slip\" or \"free_slip\"";
    const std::string bpath = "gas.boundaries." + key;
    const toml::node* bn = bt->get(key);
    if (!bn) fail_missing(bpath, kinds);
    std::string name;
    const toml::table* bopt = nullptr;
    if (bn->is_string()) {
      name = bn->as_string()->get();
    } else if (bn->is_table() && solved) {
      bopt = bn->as_table();
      check_keys(*bopt, "gas.boundaries.*", bpath);
      auto ty = string(*bopt, "type", bpath);
      if (!ty) fail_missing(bpath + ".type", "\"velocity_inlet\" or \"pressure_outlet\"");
      name = *ty;
      if (name != "velocity_inlet" && name != "pressure_outlet")
        fail_value(bpath + ".type", *bopt->get("type"), "\"velocity_inlet\" or \"pressure_outlet\"");
    } else {
      fail_value(bpath, *bn, kinds);
    }
    fluid::Boundary& b = grid.faces[f];
    if (name == "periodic") b.kind = fluid::BoundaryKind::periodic;
    else if (name == "no_slip") b.kind = fluid::BoundaryKind::no_slip;
    else if (name == "free_slip") b.kind = fluid::BoundaryKind::free_slip;
    else if (name == "velocity_inlet" && bopt) {
      b.kind = fluid::BoundaryKind::velocity_inlet;
      reject_unused(*bopt, "pressure", bpath, "a velocity inlet sets the velocity");
      auto vin = number(*bopt, "velocity", bpath, Dim::velocity);
      if (!vin) fail_missing(bpath + ".velocity", "the gas speed into the domain, normal to the face [m/s or cm/s]");
      b.normal_velocity = *vin;
    } else if (name == "pressure_outlet" && bopt) {
      b.kind = fluid::BoundaryKind::pressure_outlet;
      reject_unused(*bopt, "velocity", bpath, "a pressure outlet sets the pressure");
      b.pressure = number(*bopt, "pressure", bpath, Dim::pressure).value_or(0.0);
    } else {
      fail_value(bpath, *bn, kinds);
    }
  }
  for (int a = 0; a < dim; ++a)
    if ((grid.faces[2 * a].kind == fluid::BoundaryKind::periodic) != (grid.faces[2 * a + 1].kind == fluid::BoundaryKind::periodic))
      fail_value("gas.boundaries." + std::string(face_names[2 * a + 1]), *bt->get(face_names[2 * a + 1]),
                 "\"periodic\" exactly when gas.boundaries." + std::string(face_names[2 * a]) + " is");
  {
    bool inlet = false, outlet = false;
    for (const auto& f : grid.faces) {
      inlet |= f.kind == fluid::BoundaryKind::velocity_inlet;
      outlet |= f.kind == fluid::BoundaryKind::pressure_outlet;
    }
    if (inlet && !outlet)
      throw SceneError(file_ + ": key 'gas.boundaries': a velocity inlet without a pressure outlet: expected a "
                       "pressure_outlet face for the gas to leave by (the incompressible gas cannot accumulate)");
  }

  gs.density = positive(*gt, "density", "gas", Dim::density, true);
  gs.viscosity = positive(*gt, "viscosity", "gas", Dim::viscosity, true);
  const std::string interp = string(*gt, "interpolation", "gas").value_or("paper_lagrange2");
  if (interp == "paper_lagrange2") gs.interpolation = fluid::InterpolationScheme::paper_lagrange2;
  else if (interp == "trilinear") gs.interpolation = fluid::InterpolationScheme::trilinear;
  else if (interp == "analytic" && spec_.gas == GasModel::prescribed) gs.interpolation = fluid::InterpolationScheme::analytic;
  else
    fail_value("gas.interpolation", *gt->get("interpolation"),
               spec_.gas == GasModel::prescribed ? "\"paper_lagrange2\", \"trilinear\" or \"analytic\""
                                                 : "\"paper_lagrange2\" or \"trilinear\"");

  if (spec_.gas == GasModel::solved) {
    read_solved_gas(*gt);
    return;
  }
  for (const char* k : {"dt", "advection", "initial_velocity", "mean_pressure_gradient"})
    reject_unused(*gt, k, "gas", "modules.gas is \"prescribed\" (these set up a solved gas)");
  if (const toml::node* cn = root_.get("coupling"))
    throw SceneError(file_ + ": table [coupling] = " + show(*cn) + " is not used: modules.gas is not \"solved\"");
  // The prescribed field.
  const toml::table* ft = table(*gt, "field", "gas", spec_.gas == GasModel::prescribed);
  check_keys(*ft, "gas.field", "gas.field");
  fluid::PrescribedFieldSpec f;
  const std::string types = "\"single_vortex\", \"leveque_deformation\", \"taylor_green\" or \"uniform\"";
  auto type = string(*ft, "type", "gas.field");
  if (!type) fail_missing("gas.field.type", types);
  const toml::node& tn = *ft->get("type");
  if (*type == "single_vortex") f.type = fluid::FieldType::single_vortex;
  else if (*type == "leveque_deformation") f.type = fluid::FieldType::leveque_deformation;
  else if (*type == "taylor_green") f.type = fluid::FieldType::taylor_green;
  else if (*type == "uniform") f.type = fluid::FieldType::uniform;
  else fail_value("gas.field.type", tn, types);
  const bool vortex = f.type == fluid::FieldType::single_vortex || f.type == fluid::FieldType::leveque_deformation;
  if (f.type == fluid::FieldType::leveque_deformation && dim == 2)
    fail_value("gas.field.type", tn, "a two-dimensional field (leveque_deformation needs gas.dimension = 3)");
  const std::string field_name = "gas.field.type is \"" + *type + "\"";
  if (vortex) {
    f.period = positive(*ft, "period", "gas.field", Dim::time, true);
    f.amplitude = positive(*ft, "amplitude", "gas.field", Dim::velocity, false, 1.0 * factor(Dim::velocity));
  } else {
    reject_unused(*ft, "period", "gas.field", field_name + " (a steady field)");
  }
  if (f.type == fluid::FieldType::taylor_green) {
    f.amplitude = positive(*ft, "amplitude", "gas.field", Dim::velocity, true);
    const toml::node* kn = ft->get("wavenumber");
    if (!kn) fail_missing("gas.field.wavenumber", "an array of 2 wavenumbers [k_x, k_y] > 0");
    const toml::array* ka = kn->as_array();
    if (!ka || ka->size() != 2) fail_value("gas.field.wavenumber", *kn, "an array of 2 wavenumbers [k_x, k_y] > 0");
    double k[2];
    for (int c = 0; c < 2; ++c) {
      const toml::node& e = *ka->get(static_cast<std::size_t>(c));
      k[c] = e.is_integer() ? static_cast<double>(e.as_integer()->get()) : e.is_floating_point() ? e.as_floating_point()->get() : -1.0;
      if (!(k[c] > 0.0) || !std::isfinite(k[c])) fail_value("gas.field.wavenumber", *kn, "an array of 2 wavenumbers [k_x, k_y] > 0");
      k[c] *= factor(Dim::wavenumber);
    }
    f.kx = k[0];
    f.ky = k[1];
  } else {
    reject_unused(*ft, "wavenumber", "gas.field", field_name);
  }
  if (!vortex && f.type != fluid::FieldType::taylor_green) reject_unused(*ft, "amplitude", "gas.field", field_name);
  if (f.type == fluid::FieldType::uniform) f.velocity = vec3_required(*ft, "velocity", "gas.field", Dim::velocity);
  else reject_unused(*ft, "velocity", "gas.field", field_name);
  if (dim == 2 && f.velocity.z != 0.0)
    fail_value("gas.field.velocity", *ft->get("velocity"), "a velocity with no z component in a two-dimensional gas");
  f.pressure_gradient = vec3(*ft, "pressure_gradient", "gas.field", Dim::pressure_gradient).value_or(Vec3{});
  if (spec_.pressure_gradient && vortex)
    throw SceneError(file_ + ": key 'modules.pressure_gradient' = true: expected false with gas.field.type = \"" + *type +
                     "\", which defines no pressure (only \"uniform\" and \"taylor_green\" do)");
  gs.prescribed = f;
}

void Loader::read_solved_gas(const toml::table& gt) {
  reject_unused(gt, "field", "gas", "modules.gas is \"solved\" (a solved gas evolves from its initial velocity)");
  spec_.gas_dt = positive(gt, "dt", "gas", Dim::time, true);
  const std::string adv = string(gt, "advection", "gas").value_or("upwind");
  if (adv == "upwind") spec_.advection = fluid::AdvectionScheme::upwind;
  else if (adv == "central") spec_.advection = fluid::AdvectionScheme::central;
  else fail_value("gas.advection", *gt.get("advection"), "\"upwind\" or \"central\"");
  spec_.gas_initial_velocity = vec3(gt, "initial_velocity", "gas", Dim::velocity).value_or(Vec3{});
  spec_.mean_pressure_gradient = vec3(gt, "mean_pressure_gradient", "gas", Dim::pressure_gradient).value_or(Vec3{});
  if (spec_.gas_spec.grid.two_d && spec_.gas_initial_velocity.z != 0.0)
    fail_value("gas.initial_velocity", *gt.get("initial_velocity"), "no z component in a two-dimensional gas");
  const toml::table* ct = table(root_, "coupling", "", false);
  static const toml::table empty;
  const toml::table& c = ct ? *ct : empty;
  check_keys(c, "coupling", "coupling");
  const std::string mode = string(c, "mode", "coupling").value_or("one_way");
  if (mode == "one_way") spec_.two_way = false;
  else if (mode == "two_way") spec_.two_way = true;
  else fail_value("coupling.mode", *c.get("mode"), "\"one_way\" or \"two_way\"");
  const std::string method = string(c, "method", "coupling").value_or("interpolate");
  if (method == "interpolate") spec_.coupling_method = coupling::CouplingMethod::interpolate;
  else if (method == "cell_average") spec_.coupling_method = coupling::CouplingMethod::cell_average;
  else fail_value("coupling.method", *c.get("method"), "\"interpolate\" or \"cell_average\"");
  if (spec_.coupling_method == coupling::CouplingMethod::cell_average) {
    reject_unused(c, "kernel", "coupling", "coupling.method = \"cell_average\" deposits into the holding cell");
    if (spec_.drag && spec_.drag_update != coupling::DragUpdate::explicit_force)
      fail_value("coupling.method", *c.get("method"),
                 "\"interpolate\" with drag.update = \"" + std::string(coupling::to_string(spec_.drag_update)) +
                     "\": the cell-average drag does not depend on a particle's own velocity, so only the explicit "
                     "update applies");
  }
  const std::string kernel = string(c, "kernel", "coupling").value_or("trilinear");
  if (kernel == "cell") spec_.kernel = coupling::Kernel::cell;
  else if (kernel == "trilinear") spec_.kernel = coupling::Kernel::trilinear;
  else if (kernel == "gaussian") spec_.kernel = coupling::Kernel::gaussian;
  else fail_value("coupling.kernel", *c.get("kernel"), "\"cell\", \"trilinear\" or \"gaussian\"");
  if (spec_.kernel == coupling::Kernel::gaussian && spec_.coupling_method == coupling::CouplingMethod::interpolate) {
    spec_.kernel_width = positive(c, "kernel_width", "coupling", Dim::length, true);
    // The kernel reaches 3σ: its stencil, up to 16 cells either side, bounds the work per
    // particle (a wider kernel would cost (6σ/h)³ weights per particle and deposition).
    const fluid::GridSpec& g = spec_.gas_spec.grid;
    const double lo[3] = {g.lo.x, g.lo.y, g.lo.z}, hi[3] = {g.hi.x, g.hi.y, g.hi.z};
    double reach = std::numeric_limits<double>::max();
    for (int a = 0; a < (g.two_d ? 2 : 3); ++a) reach = std::min(reach, 16.0 * (hi[a] - lo[a]) / g.cells[a]);
    if (3.0 * spec_.kernel_width > reach) {
      std::ostringstream os;
      os << "a width whose reach, 3 sigma, spans at most 16 gas cells along every axis (sigma <= " << reach / 3.0
         << " m here)";
      fail_value("coupling.kernel_width", *c.get("kernel_width"), os.str());
    }
  } else
    reject_unused(c, "kernel_width", "coupling", "coupling.kernel is not \"gaussian\"");
  const std::string slip = string(c, "gas_velocity", "coupling").value_or("interstitial");
  if (slip == "interstitial") spec_.gas_velocity = coupling::SlipVelocity::interstitial;
  else if (slip == "superficial") spec_.gas_velocity = coupling::SlipVelocity::superficial;
  else fail_value("coupling.gas_velocity", *c.get("gas_velocity"), "\"interstitial\" or \"superficial\"");
  if (spec_.coupling_method == coupling::CouplingMethod::cell_average)
    reject_unused(c, "gas_velocity", "coupling", "coupling.method = \"cell_average\" uses the cell-centred gas velocity");
  if (!spec_.two_way) {
    for (const char* k : {"method", "kernel", "kernel_width", "gas_velocity"})
      reject_unused(c, k, "coupling", "coupling.mode is \"one_way\" (the particles do not act on the gas)");
  }
  if (spec_.two_way && !spec_.drag)
    throw SceneError(file_ + ": key 'coupling.mode' = \"two_way\": expected modules.drag to name a drag law (the "
                     "particles act on the gas through drag)");
}

void Loader::read_integrator() {
  const toml::table* t = table(root_, "integrator", "", true);
  check_keys(*t, "integrator", "integrator");
  const std::string scheme = string(*t, "scheme", "integrator").value_or("");
  const std::string allowed = spec_.tracers ? "\"rk2\" or \"rk4\" (tracers move with the gas)"
                                            : "\"paper_euler\", \"velocity_verlet\" or \"exponential_midpoint\"";
  if (scheme == "paper_euler") spec_.integrator = IntegratorScheme::paper_euler;
  else if (scheme == "velocity_verlet") spec_.integrator = IntegratorScheme::velocity_verlet;
  else if (scheme == "rk2") spec_.integrator = IntegratorScheme::rk2;
  else if (scheme == "rk4") spec_.integrator = IntegratorScheme::rk4;
  else if (scheme == "exponential_midpoint") spec_.integrator = IntegratorScheme::exponential_midpoint;
  else if (!t->get("scheme")) fail_missing("integrator.scheme", allowed);
  else fail_value("integrator.scheme", *t->get("scheme"), allowed);
  const bool rk = spec_.integrator == IntegratorScheme::rk2 || spec_.integrator == IntegratorScheme::rk4;
  if (rk != spec_.tracers) fail_value("integrator.scheme", *t->get("scheme"), allowed);
  if (spec_.integrator == IntegratorScheme::exponential_midpoint &&
      (!spec_.drag || spec_.drag_update != coupling::DragUpdate::exponential ||
       spec_.normal_contact != NormalContactModel::none))
    fail_value("integrator.scheme", *t->get("scheme"),
               "\"paper_euler\" or \"velocity_verlet\": \"exponential_midpoint\" is for particles moved by drag without "
               "contacts (it needs modules.drag with drag.update = \"exponential\" and modules.normal_contact = \"none\"; "
               "it evaluates the forces twice per step)");
  spec_.end_time = positive(*t, "end_time", "integrator", Dim::time, true);
}

void Loader::resolve_dt(const toml::table* t) {
  // Hertz–Mindlin pairs have no collision time of their own (it depends on the impact
  // speed): the scene states the largest expected impact speed, or asks for a fraction
  // of the Rayleigh time instead. Either key is refused when no pair is Hertz–Mindlin.
  const bool any_hertz = spec_.pairs.uses(ContactLaw::hertz_mindlin);
  const std::string no_hertz = "no [[contacts]] entry uses model hertz_mindlin";
  spec_.impact_velocity = 0.0;
  if (t->get("impact_velocity")) {
    if (!any_hertz) reject_unused(*t, "impact_velocity", "integrator", no_hertz);
    spec_.impact_velocity = positive(*t, "impact_velocity", "integrator", Dim::velocity, true);
  }

  // Smallest collision time over every pair of materials that can meet: eq 28 for
  // linear pairs, the Hertz time t_H at integrator.impact_velocity for Hertz–Mindlin
  // ones; and the smallest Rayleigh time of the particles in Hertz–Mindlin contacts.
  double t_col = std::numeric_limits<double>::infinity(), t_ray = std::numeric_limits<double>::infinity();
  std::string t_col_pair, t_ray_material;
  bool hertz_meets = false;
  if (spec_.normal_contact != NormalContactModel::none) {
    const std::size_t nm = spec_.materials.size();
    std::vector<double> m_min(nm, std::numeric_limits<double>::infinity()), r_min(nm, 0.0);
    std::vector<std::size_t> count(nm, 0);
    for (const auto& p : spec_.particles) {
      const double d = 2.0 * p.radius;
      const double m = spec_.materials[p.material].density * std::numbers::pi * d * d * d / 6.0;
      if (m < m_min[p.material]) { m_min[p.material] = m; r_min[p.material] = p.radius; }
      ++count[p.material];
    }
    auto need = [&](int a, int b, const std::string& what) -> const PairParams& {
      const PairParams& pp = spec_.pairs.get(a, b);
      if (!pp.defined)
        throw SceneError(file_ + ": key 'contacts' has no entry for pair [\"" + spec_.materials[a].name + "\", \"" +
                         spec_.materials[b].name + "\"]: expected a [[contacts]] entry, because " + what);
      return pp;
    };
    auto rayleigh = [&](std::size_t a) {
      const Material& mat = spec_.materials[a];
      const double tr = contact::rayleigh_time(r_min[a], mat.density, mat.youngs_modulus, mat.poisson_ratio);
      if (tr < t_ray) { t_ray = tr; t_ray_material = mat.name; }
    };
    auto consider = [&](const PairParams& pp, double m_eff, double r_star, const std::string& what) {
      double tc = std::numeric_limits<double>::infinity();
      if (pp.law == ContactLaw::linear_spring_dashpot) {
        tc = collision_time(pp, m_eff);
      } else {
        hertz_meets = true;
        if (spec_.impact_velocity > 0.0)
          tc = contact::hertz_collision_time(m_eff, r_star, pp.e_star, spec_.impact_velocity);
      }
      if (tc < t_col) { t_col = tc; t_col_pair = what; }
    };
    for (std::size_t a = 0; a < nm; ++a) {
      if (!count[a]) continue;
      for (std::size_t b = a; b < nm; ++b) {
        if (!count[b] || (a == b && count[a] < 2)) continue;
        const bool fa = spec_.materials[a].fixed, fb = spec_.materials[b].fixed;
        if (fa && fb) continue;  // two fixed particles never interact
        const PairParams& pp = need(static_cast<int>(a), static_cast<int>(b),
                                    "particles of both materials are in the scene");
        // A fixed particle is of infinite mass in a contact: m* is the other's mass.
        const double me = fa ? m_min[b] : fb ? m_min[a] : m_min[a] * m_min[b] / (m_min[a] + m_min[b]);
        consider(pp, me, r_min[a] * r_min[b] / (r_min[a] + r_min[b]),
                 spec_.materials[a].name + "-" + spec_.materials[b].name);
        if (pp.law == ContactLaw::hertz_mindlin) { rayleigh(a); rayleigh(b); }
      }
      for (const auto& w : spec_.walls) {
        const PairParams& pp = need(static_cast<int>(a), w.material, "wall '" + w.name + "' can touch particles of material '" + spec_.materials[a].name + "'");
        consider(pp, m_min[a], r_min[a], spec_.materials[a].name + "-wall '" + w.name + "'");
        if (pp.law == ContactLaw::hertz_mindlin) rayleigh(a);
      }
    }
  }
  spec_.t_col_min = std::isfinite(t_col) ? t_col : 0.0;
  spec_.rayleigh_time_min = std::isfinite(t_ray) ? t_ray : 0.0;

  const toml::node* dtn = t->get("dt");
  if (!dtn) fail_missing("integrator.dt", "\"auto\" or a time step > 0 [s]");
  if (dtn->is_string()) {
    if (dtn->as_string()->get() != "auto") fail_value("integrator.dt", *dtn, "\"auto\" or a time step > 0 [s]");
    spec_.dt_auto = true;
    spec_.rayleigh_fraction = 0.0;
    if (t->get("rayleigh_fraction")) {
      if (!any_hertz) reject_unused(*t, "rayleigh_fraction", "integrator", no_hertz);
      spec_.rayleigh_fraction = number_in(*t, "rayleigh_fraction", "integrator", Dim::none, true, 0.0, 0.0, true, 1.0,
                                          false, "in (0, 1] (dt = rayleigh_fraction x the smallest Rayleigh time)");
    }
    if (hertz_meets && spec_.impact_velocity == 0.0 && spec_.rayleigh_fraction == 0.0)
      fail_value("integrator.dt", *dtn,
                 "integrator.impact_velocity (the largest expected impact speed: dt = t_H/dt_divisor with the Hertz "
                 "collision time t_H = 2.868 (m*^2/(R* E*^2 v))^(1/5)) or integrator.rayleigh_fraction (dt = fraction "
                 "x the Rayleigh time) beside dt = \"auto\": a Hertz-Mindlin contact's duration depends on the impact "
                 "speed");
    if (!std::isfinite(t_col) && spec_.rayleigh_fraction == 0.0)
      fail_value("integrator.dt", *dtn,
                 "an explicit time step: \"auto\" derives dt from the collision time, and this scene has no contacts");
    if (std::isfinite(t_col)) {
      spec_.dt_divisor = number_in(*t, "dt_divisor", "integrator", Dim::none, false, 50.0, 10.0, false,
                                   std::numeric_limits<double>::infinity(), false,
                                   ">= 10 (dt = t_col/dt_divisor; fewer than 10 steps per collision is not resolved)");
      spec_.dt = t_col / spec_.dt_divisor;
    } else {
      reject_unused(*t, "dt_divisor", "integrator",
                    "no collision time is known (no linear pair meets, and integrator.impact_velocity is not given)");
      spec_.dt = std::numeric_limits<double>::infinity();
    }
    if (spec_.rayleigh_fraction > 0.0) spec_.dt = std::min(spec_.dt, spec_.rayleigh_fraction * t_ray);
  } else {
    reject_unused(*t, "dt_divisor", "integrator", "integrator.dt is not \"auto\"");
    reject_unused(*t, "rayleigh_fraction", "integrator", "integrator.dt is not \"auto\"");
    spec_.dt_auto = false;
    spec_.dt = positive(*t, "dt", "integrator", Dim::time, true);
    if (std::isfinite(t_col) && spec_.dt > t_col / 10.0) {
      std::ostringstream os;
      os << "a time step <= t_col/10 = " << t_col / 10.0 << " s: the shortest collision (" << t_col_pair
         << ") lasts t_col = " << t_col << " s";
      if (spec_.impact_velocity > 0.0) os << " (Hertz pairs at integrator.impact_velocity)";
      os << ", and with fewer than 10 steps per collision the contact force is not resolved (overlaps and "
         << "restitution come out wrong, or the run blows up); use dt = \"auto\" (t_col/50, as Garg et al. 2012) or "
         << "a smaller dt";
      fail_value("integrator.dt", *dtn, os.str());
    }
    if (hertz_meets && spec_.dt > t_ray) {
      std::ostringstream os;
      os << "a time step <= the Rayleigh time T_R = " << t_ray << " s of material '" << t_ray_material
         << "' (T_R = pi R sqrt(rho/G)/(0.1631 nu + 0.8766), the time an elastic surface wave takes across the "
         << "smallest particle): Hertz-Mindlin contact networks are unstable with longer steps (DEM codes use "
         << "0.1-0.3 T_R); use a smaller dt, or dt = \"auto\" with integrator.rayleigh_fraction";
      fail_value("integrator.dt", *dtn, os.str());
    }
  }
  if (spec_.gas == GasModel::solved) {
    // Particles sub-step inside each gas step: a whole number of particle steps.
    const double ratio = spec_.gas_dt / spec_.dt;
    if (spec_.dt_auto) {
      spec_.dt = spec_.gas_dt / std::ceil(ratio - 1e-9);  // t_col/divisor rounded down to divide gas.dt
    } else if (ratio < 1.0 - 1e-9 || std::abs(ratio - std::round(ratio)) > 1e-6 * ratio) {
      std::ostringstream os;
      os << "a particle step that divides gas.dt = " << spec_.gas_dt << " s a whole number of times (particles take "
         << "whole sub-steps inside each gas step); gas.dt/dt = " << ratio;
      fail_value("integrator.dt", *dtn, os.str());
    } else {
      spec_.dt = spec_.gas_dt / std::round(ratio);
    }
  }
  if (spec_.dt > spec_.end_time) fail_value("integrator.end_time", *t->get("end_time"), "a time >= dt");
}

void Loader::read_output_and_checks() {
  if (const toml::table* o = table(root_, "output", "", false)) {
    check_keys(*o, "output", "output");
    spec_.output_particles = boolean(*o, "particles", "output").value_or(true);
    spec_.output_vtk = boolean(*o, "vtk", "output").value_or(false);
    spec_.output_interval = positive(*o, "interval", "output", Dim::time, true);
    spec_.checkpoint_interval = positive(*o, "checkpoint_interval", "output", Dim::time, false, 0.0);
  } else {
    spec_.output_particles = false;
  }
  if (const toml::table* nl = table(root_, "neighbour_list", "", false)) {
    check_keys(*nl, "neighbour_list", "neighbour_list");
    if (spec_.normal_contact == NormalContactModel::none)
      reject_unused(*nl, "sort_interval", "neighbour_list", "the scene has no contacts (modules.normal_contact), so no neighbour list");
    if (const toml::node* si = nl->get("sort_interval")) {
      if (!si->is_integer() || si->as_integer()->get() < 0)
        fail_value("neighbour_list.sort_interval", *si, "an integer >= 0 (steps; 0 = never sort)");
      spec_.sort_interval = static_cast<std::uint64_t>(si->as_integer()->get());
    }
  }
  if (const toml::table* c = table(root_, "checks", "", false)) {
    check_keys(*c, "checks", "checks");
    spec_.allow_initial_overlap = boolean(*c, "allow_initial_overlap", "checks").value_or(false);
    spec_.max_overlap_fraction = number_in(*c, "max_overlap_fraction", "checks", Dim::none, false, 1.0, 0.0, true,
                                           1.0, false, "in (0, 1]");
  }
}

void Loader::check_initial_state() {
  // Every particle starts inside the gas domain.
  if (spec_.gas != GasModel::none) {
    const fluid::GridSpec& g = spec_.gas_spec.grid;
    for (std::size_t i = 0; i < spec_.particles.size(); ++i) {
      const Vec3 x = spec_.particles[i].position;
      if (x.x < g.lo.x || x.x > g.hi.x || x.y < g.lo.y || x.y > g.hi.y || x.z < g.lo.z || x.z > g.hi.z) {
        std::ostringstream os;
        os << file_ << ": key '" << particle_source(spec_, i) << ".position' = [" << x.x << ", " << x.y << ", " << x.z
           << "] (SI) lies outside the gas domain [" << g.lo.x << ", " << g.hi.x << "] x [" << g.lo.y << ", " << g.hi.y
           << "] x [" << g.lo.z << ", " << g.hi.z << "] m: expected every particle inside gas.lower .. gas.upper";
        throw SceneError(os.str());
      }
    }
  }
  // Along a periodic axis every particle starts inside the period, and contacts (with
  // the Verlet skin, a tenth of the largest diameter) must reach less than half of it:
  // particles meet only their nearest images.
  const PeriodicBox& box = spec_.periodic;
  if (box.any()) {
    double rmax = 0.0;
    for (const auto& p : spec_.particles) rmax = std::max(rmax, p.radius);
    const char* axes[3] = {"x", "y", "z"};
    for (int a = 0; a < 3; ++a) {
      if (!box.on[a]) continue;
      const std::string where = spec_.gas != GasModel::none ? std::string("gas.boundaries.") + axes[a] + "_lower"
                                                            : std::string("periodic.") + axes[a];
      for (std::size_t i = 0; i < spec_.particles.size(); ++i) {
        const Vec3 x = spec_.particles[i].position;
        const double c = a == 0 ? x.x : a == 1 ? x.y : x.z;
        if (c < box.lo[a] || c >= box.lo[a] + box.len[a]) {
          std::ostringstream os;
          os << file_ << ": key '" << particle_source(spec_, i) << ".position' = [" << x.x << ", " << x.y << ", " << x.z
             << "] (SI) lies outside the period [" << box.lo[a] << ", " << box.lo[a] + box.len[a] << ") m along "
             << axes[a] << " (" << where << "): expected every particle inside it";
          throw SceneError(os.str());
        }
      }
      if (spec_.normal_contact != NormalContactModel::none && 2.0 * 2.2 * rmax >= box.len[a]) {
        std::ostringstream os;
        os << file_ << ": the period along " << axes[a] << " (" << where << ") is " << box.len[a]
           << " m: expected more than 4.4 times the largest radius (" << 4.4 * rmax
           << " m), so that a particle's contacts (2.2 r with the Verlet skin) reach less than half of it";
        throw SceneError(os.str());
      }
    }
  }
  // A centre outside a wall is always an error; touching a wall or another particle
  // only when the scene says the initial overlap is intended.
  for (std::size_t i = 0; i < spec_.particles.size(); ++i) {
    const ParticleSpec& p = spec_.particles[i];
    for (const auto& w : spec_.walls) {
      const double d = w.distance(p.position);
      if (d < 0.0 || (!spec_.allow_initial_overlap && d < p.radius)) {
        std::ostringstream os;
        os << file_ << ": key '" << particle_source(spec_, i) << ".position' = [" << p.position.x << ", " << p.position.y << ", "
           << p.position.z << "] (SI) lies " << (d < 0.0 ? "outside" : "across") << " wall '" << w.name
           << "' (centre distance " << d << " m, radius " << p.radius << " m): expected a particle inside the domain"
           << (d < 0.0 ? "" : " and clear of the wall (or checks.allow_initial_overlap = true)");
        throw SceneError(os.str());
      }
    }
  }
  // Overlaps between particles matter only when a contact model acts between them.
  if (spec_.allow_initial_overlap || spec_.particles.size() < 2 || spec_.normal_contact == NormalContactModel::none) return;
  ParticleStore tmp;
  for (const auto& p : spec_.particles) tmp.add(p.position, {}, p.radius, 1.0, p.material);
  std::vector<ContactPair> pairs;
  CellListSearch search;
  search.find_contacts(tmp, 0.0, pairs, spec_.periodic);
  if (!pairs.empty()) {
    const auto& c = pairs.front();
    std::ostringstream os;
    os << file_ << ": key '" << particle_source(spec_, c.j) << ".position' overlaps '" << particle_source(spec_, c.i)
       << "' by " << c.overlap << " m at the start: expected particles that do not overlap"
       << " (or checks.allow_initial_overlap = true if the compression is intended); " << pairs.size()
       << " overlapping pair(s) in all";
    throw SceneError(os.str());
  }
}

SceneSpec Loader::load() {
  spec_.file = file_;
  check_keys(root_, "", "");
  read_units();
  read_modules();
  read_materials();
  read_contacts();
  check_elastic_constants_used();
  read_walls();
  read_gas();
  read_periodic();
  read_particles();
  read_integrator();
  read_output_and_checks();
  resolve_dt(root_.get("integrator")->as_table());
  check_initial_state();
  return spec_;
}

}  // namespace

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

namespace {

SceneSpec load_table(toml::table root, const std::string& name, const std::vector<SceneOverride>& overrides) {
  for (const auto& o : overrides) apply_override(root, o, name);
  return Loader(name, std::move(root)).load();
}

}  // namespace

SceneOverride parse_override(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0)
    throw SceneError("override '" + text + "': expected path=value, e.g. contacts[0].kn=1e7");
  return {text.substr(0, eq), text.substr(eq + 1)};
}

SceneSpec load_scene_from_string(const std::string& text, const std::string& name,
                                 const std::vector<SceneOverride>& overrides) {
  toml::table root;
  try {
    root = toml::parse(text, name);
  } catch (const toml::parse_error& e) {
    std::ostringstream os;
    os << name << ":" << e.source().begin.line << ":" << e.source().begin.column
       << ": does not parse as TOML: " << e.description();
    throw SceneError(os.str());
  }
  return load_table(std::move(root), name, overrides);
}

SceneSpec load_scene(const std::string& path, const std::vector<SceneOverride>& overrides) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  std::ostringstream ss;
  ss << in.rdbuf();
  return load_scene_from_string(ss.str(), path, overrides);
}

std::vector<std::string> scene_schema_keys() {
  std::vector<std::string> keys;
  for (const auto& [table, ks] : schema())
    for (const auto& k : ks) {
      // Sub-tables are listed by their own entries; list only leaf keys.
      const std::string full = table.empty() ? k : table + "." + k;
      const bool is_table = schema().count(full) || schema().count(full + "[]");
      if (!is_table) keys.push_back(full);
    }
  std::sort(keys.begin(), keys.end());
  return keys;
}

}  // namespace cdm
