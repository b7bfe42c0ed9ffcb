/// @file output_checks.cpp
/// @brief Output, neighbour-list and check settings ([output], [neighbour_list], [checks]).
#include "sections.hpp"

#include <cstdint>

namespace cdm::scene {

void read_output_and_checks(const Reader& rd, SceneSpec& spec) {
  if (const toml::table* o = rd.table(rd.root(), "output", "", false)) {
    rd.check_keys(*o, "output", "output");
    spec.output_particles = rd.boolean(*o, "particles", "output").value_or(true);
    spec.output_vtk = rd.boolean(*o, "vtk", "output").value_or(false);
    spec.output_vtk_format = rd.keyword(*o, "vtk_format", "output", vtk::encoding_keywords, vtk::Encoding::binary);
    spec.output_contacts = rd.boolean(*o, "contacts", "output").value_or(false);
    if (spec.output_contacts && !spec.output_vtk)
      rd.fail_value("output.contacts", *o->get("contacts"), "false unless output.vtk = true (the contacts are VTK files)");
    if (spec.output_contacts && !spec.normal_contact)
      rd.fail_value("output.contacts", *o->get("contacts"), "false: the scene has no contacts (modules.normal_contact)");
    spec.output_interval = rd.positive(*o, "interval", "output", Dim::time, true);
    spec.checkpoint_interval = rd.positive(*o, "checkpoint_interval", "output", Dim::time, false, 0.0);
    spec.log_interval = rd.positive(*o, "log_interval", "output", Dim::time, false, 0.0);
  } else {
    spec.output_particles = false;
  }
  if (const toml::table* nl = rd.table(rd.root(), "neighbour_list", "", false)) {
    rd.check_keys(*nl, "neighbour_list", "neighbour_list");
    if (!spec.normal_contact)
      rd.reject_unused(*nl, "sort_interval", "neighbour_list", "the scene has no contacts (modules.normal_contact), so no neighbour list");
    if (const toml::node* si = nl->get("sort_interval")) {
      if (!si->is_integer() || si->as_integer()->get() < 0)
        rd.fail_value("neighbour_list.sort_interval", *si, "an integer >= 0 (steps; 0 = never sort)");
      spec.sort_interval = static_cast<std::uint64_t>(si->as_integer()->get());
    }
  }
  if (const toml::table* c = rd.table(rd.root(), "checks", "", false)) {
    rd.check_keys(*c, "checks", "checks");
    spec.allow_initial_overlap = rd.boolean(*c, "allow_initial_overlap", "checks").value_or(false);
    spec.max_overlap_fraction = rd.number_in(*c, "max_overlap_fraction", "checks", Dim::none, false, 1.0, 0.0, true,
                                             1.0, false, "in (0, 1]");
  }
}

}  // namespace cdm::scene
