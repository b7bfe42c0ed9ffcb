/// @file units_modules.cpp
/// @brief The scene's units and the modules it builds ([modules], [gravity]).
#include "sections.hpp"

namespace cdm::scene {

void read_units(Reader& rd, SceneSpec& spec) {
  const toml::node* n = rd.root().get("units");
  if (!n) rd.fail_missing("units", keyword_list(units_keywords));
  if (!n->is_string()) rd.fail_value("units", *n, keyword_list(units_keywords));
  const std::string u = n->as_string()->get();
  const auto cgs = keyword_value(units_keywords, u);
  if (!cgs) rd.fail_value("units", *n, keyword_list(units_keywords));
  rd.set_cgs(*cgs);
  spec.units = u;
}

void read_modules(const Reader& rd, SceneSpec& spec) {
  const toml::table* m = rd.table(rd.root(), "modules", "", true);
  rd.check_keys(*m, "modules", "modules");
  spec.gravity = rd.boolean(*m, "gravity", "modules").value_or(false);
  spec.normal_contact = rd.keyword_or_none(*m, "normal_contact", "modules", contact_law_keywords);
  spec.tangential = rd.keyword(*m, "tangential", "modules", tangential_keywords, TangentialModel::none);
  if (spec.tangential != TangentialModel::none && !spec.normal_contact)
    rd.fail_value("modules.tangential", *m->get("tangential"),
                  "\"none\" while modules.normal_contact is \"none\" (friction is bounded by the normal force)");
  spec.rolling = rd.keyword(*m, "rolling_resistance", "modules", rolling_keywords, RollingModel::none);
  if (spec.rolling != RollingModel::none && !spec.normal_contact)
    rd.fail_value("modules.rolling_resistance", *m->get("rolling_resistance"),
                  "\"none\" while modules.normal_contact is \"none\" (the torque is bounded by the normal force)");

  // The gas and what couples particles to it.
  spec.gas = rd.keyword(*m, "gas", "modules", gas_model_keywords, GasModel::none);
  const std::string needs_gas = "while modules.gas is \"none\" (it acts between the particles and a gas)";
  spec.drag = rd.keyword_or_none(*m, "drag", "modules", coupling::drag_law_keywords);
  if (spec.drag && spec.gas == GasModel::none) rd.fail_value("modules.drag", *m->get("drag"), "\"none\" " + needs_gas);
  spec.pressure_gradient = rd.boolean(*m, "pressure_gradient", "modules").value_or(false);
  if (spec.pressure_gradient && spec.gas == GasModel::none)
    rd.fail_value("modules.pressure_gradient", *m->get("pressure_gradient"), "false " + needs_gas);
  spec.tracers = rd.boolean(*m, "tracers", "modules").value_or(false);
  if (spec.tracers) {
    const toml::node& n = *m->get("tracers");
    if (spec.gas != GasModel::prescribed)
      rd.fail_value("modules.tracers", n, "false unless modules.gas is \"prescribed\" (tracers follow a given gas field)");
    if (spec.gravity || spec.normal_contact || spec.drag || spec.pressure_gradient)
      rd.fail_value("modules.tracers", n,
                    "false while gravity, contacts, drag or the pressure gradient act on the particles (tracers are "
                    "massless: they only move with the gas)");
  }

  const toml::table* g = rd.table(rd.root(), "gravity", "", spec.gravity);
  if (g && !spec.gravity)
    throw SceneError(rd.file() + ": table [gravity] is not used: modules.gravity is not true");
  if (g) {
    rd.check_keys(*g, "gravity", "gravity");
    spec.g = rd.vec3_required(*g, "g", "gravity", Dim::acceleration);
  }
}

}  // namespace cdm::scene
