/// @file prescribed_field.cpp
/// @brief A prescribed gas velocity field ([gas.field]): its type and parameters.
#include "sections.hpp"

#include <cmath>
#include <string>

namespace cdm::scene {

void read_prescribed_field(const Reader& rd, const toml::table& gt, SceneSpec& spec) {
  fluid::GasSpec& gs = spec.gas_spec;
  const toml::table* ft = rd.table(gt, "field", "gas", spec.gas == GasModel::prescribed);
  rd.check_keys(*ft, "gas.field", "gas.field");
  fluid::PrescribedFieldSpec f;
  if (!ft->get("type")) rd.fail_missing("gas.field.type", keyword_list(fluid::field_type_keywords));
  f.type = rd.keyword(*ft, "type", "gas.field", fluid::field_type_keywords, fluid::FieldType::uniform);
  const toml::node& tn = *ft->get("type");
  const std::string type = to_string(f.type);
  const bool vortex = f.type == fluid::FieldType::single_vortex || f.type == fluid::FieldType::leveque_deformation;
  if (f.type == fluid::FieldType::leveque_deformation && spec.gas_spec.grid.two_d)
    rd.fail_value("gas.field.type", tn, "a two-dimensional field (leveque_deformation needs gas.dimension = 3)");
  const std::string field_name = "gas.field.type is \"" + type + "\"";
  if (vortex) {
    f.period = rd.positive(*ft, "period", "gas.field", Dim::time, true);
    f.amplitude = rd.positive(*ft, "amplitude", "gas.field", Dim::velocity, false, 1.0 * rd.factor(Dim::velocity));
  } else {
    rd.reject_unused(*ft, "period", "gas.field", field_name + " (a steady field)");
  }
  if (f.type == fluid::FieldType::taylor_green) {
    f.amplitude = rd.positive(*ft, "amplitude", "gas.field", Dim::velocity, true);
    const toml::node* kn = ft->get("wavenumber");
    if (!kn) rd.fail_missing("gas.field.wavenumber", "an array of 2 wavenumbers [k_x, k_y] > 0");
    const toml::array* ka = kn->as_array();
    if (!ka || ka->size() != 2) rd.fail_value("gas.field.wavenumber", *kn, "an array of 2 wavenumbers [k_x, k_y] > 0");
    double k[2];
    for (int c = 0; c < 2; ++c) {
      const toml::node& e = *ka->get(static_cast<std::size_t>(c));
      k[c] = e.is_integer() ? static_cast<double>(e.as_integer()->get()) : e.is_floating_point() ? e.as_floating_point()->get() : -1.0;
      if (!(k[c] > 0.0) || !std::isfinite(k[c])) rd.fail_value("gas.field.wavenumber", *kn, "an array of 2 wavenumbers [k_x, k_y] > 0");
      k[c] *= rd.factor(Dim::wavenumber);
    }
    f.kx = k[0];
    f.ky = k[1];
  } else {
    rd.reject_unused(*ft, "wavenumber", "gas.field", field_name);
  }
  if (!vortex && f.type != fluid::FieldType::taylor_green) rd.reject_unused(*ft, "amplitude", "gas.field", field_name);
  if (f.type == fluid::FieldType::uniform) f.velocity = rd.vec3_required(*ft, "velocity", "gas.field", Dim::velocity);
  else rd.reject_unused(*ft, "velocity", "gas.field", field_name);
  if (spec.gas_spec.grid.two_d && f.velocity.z != 0.0)
    rd.fail_value("gas.field.velocity", *ft->get("velocity"), "a velocity with no z component in a two-dimensional gas");
  f.pressure_gradient = rd.vec3(*ft, "pressure_gradient", "gas.field", Dim::pressure_gradient).value_or(Vec3{});
  if (spec.pressure_gradient && vortex)
    throw SceneError(rd.file() + ": key 'modules.pressure_gradient' = true: expected false with gas.field.type = \"" + type +
                     "\", which defines no pressure (only \"uniform\" and \"taylor_green\" do)");
  gs.prescribed = f;
}

}  // namespace cdm::scene
