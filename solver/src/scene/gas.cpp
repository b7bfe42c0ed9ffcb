/// @file gas.cpp
/// @brief The gas grid, its boundaries and interpolation, and the drag table ([gas], [drag]).
#include "sections.hpp"

#include <string>

namespace cdm::scene {

void read_gas(const Reader& rd, SceneSpec& spec) {
  const toml::table* gt = rd.table(rd.root(), "gas", "", spec.gas != GasModel::none);
  const toml::table* dt = rd.table(rd.root(), "drag", "", false);
  if (dt && !spec.drag) throw SceneError(rd.file() + ": table [drag] is not used: modules.drag is \"none\"");
  if (spec.drag) {
    static const toml::table empty;
    const toml::table& d = dt ? *dt : empty;
    rd.check_keys(d, "drag", "drag");
    spec.drag_update = rd.keyword(d, "update", "drag", coupling::drag_update_keywords, coupling::DragUpdate::explicit_force);
    if (spec.drag_update != coupling::DragUpdate::explicit_force)
      for (const auto& m : spec.materials)
        if (m.fixed)
          rd.fail_value("drag.update", *d.get("update"),
                        "\"explicit\" while material '" + m.name + "' is fixed (a fixed particle's drag is a force on the "
                        "gas, not a velocity relaxation)");
    // Default: a solved gas supplies ε_g from the particles (0 = from the grid); a
    // prescribed gas has no particle volume, so a single particle's ε_g = 1.
    spec.drag_void_fraction = rd.number_in(d, "void_fraction", "drag", Dim::none, false,
                                           spec.gas == GasModel::solved ? 0.0 : 1.0, 0.0, true, 1.0, false,
                                           "in (0, 1] (the gas volume fraction held in the drag law)");
  }
  if (!gt) return;
  if (spec.gas == GasModel::none) throw SceneError(rd.file() + ": table [gas] is not used: modules.gas is \"none\"");
  rd.check_keys(*gt, "gas", "gas");
  fluid::GasSpec& gs = spec.gas_spec;
  fluid::GridSpec& grid = gs.grid;

  // Dimension and extent.
  long long dim = 3;
  if (const toml::node* dn = gt->get("dimension")) {
    if (!dn->is_integer() || (dn->as_integer()->get() != 2 && dn->as_integer()->get() != 3))
      rd.fail_value("gas.dimension", *dn, "2 or 3");
    dim = dn->as_integer()->get();
  }
  grid.two_d = dim == 2;
  grid.lo = rd.vec3_required(*gt, "lower", "gas", Dim::length);
  grid.hi = rd.vec3_required(*gt, "upper", "gas", Dim::length);
  if (!(grid.hi.x > grid.lo.x && grid.hi.y > grid.lo.y && grid.hi.z > grid.lo.z))
    rd.fail_value("gas.upper", *gt->get("upper"), "a corner above gas.lower along every axis");
  const toml::node* cn = gt->get("cells");
  const std::string cells_text = dim == 2 ? "an array of 2 integers >= 2 (cells along x and y)"
                                          : "an array of 3 integers >= 2 (cells along x, y and z)";
  if (!cn) rd.fail_missing("gas.cells", cells_text);
  const toml::array* ca = cn->as_array();
  if (!ca || ca->size() != static_cast<std::size_t>(dim)) rd.fail_value("gas.cells", *cn, cells_text);
  grid.cells = {1, 1, 1};
  double total = 1.0;
  for (long long a = 0; a < dim; ++a) {
    auto iv = ca->get(static_cast<std::size_t>(a))->as_integer();
    if (!iv || iv->get() < 2 || iv->get() > 100000) rd.fail_value("gas.cells", *cn, cells_text + ", at most 100000 each");
    grid.cells[static_cast<std::size_t>(a)] = static_cast<int>(iv->get());
    total *= static_cast<double>(iv->get() + 5);
  }
  if (total > 2e8) rd.fail_value("gas.cells", *cn, "at most about 2e8 grid samples in all");

  // Boundaries: one per face; periodic faces come in pairs.
  const toml::table* bt = rd.table(*gt, "boundaries", "gas", true);
  rd.check_keys(*bt, "gas.boundaries", "gas.boundaries");
  const char* face_names[6] = {"x_lower", "x_upper", "y_lower", "y_upper", "z_lower", "z_upper"};
  // A face is named by a keyword, or (solved gas) is an open face given by a table.
  using fluid::BoundaryKind;
  const auto closed = [](BoundaryKind k) { return !is_open_face(k); };
  for (int f = 0; f < 6; ++f) {
    const std::string key = face_names[f];
    if (dim == 2 && f >= 4) {
      rd.reject_unused(*bt, key, "gas.boundaries", "a two-dimensional gas has no z boundaries");
      grid.faces[f].kind = fluid::BoundaryKind::periodic;
      continue;
    }
    const bool solved = spec.gas == GasModel::solved;
    const std::string kinds = solved ? "\"periodic\", \"no_slip\", \"free_slip\", { type = \"velocity_inlet\", velocity = "
                                       "<inward speed> } or { type = \"pressure_outlet\", pressure = <p> }"
                                     : "\"periodic\", \"no_slip\" or \"free_slip\"";
    const std::string bpath = "gas.boundaries." + key;
    const toml::node* bn = bt->get(key);
    if (!bn) rd.fail_missing(bpath, kinds);
    BoundaryKind kind = BoundaryKind::periodic;
    const toml::table* bopt = nullptr;
    if (bn->is_string()) {
      const auto k = keyword_value(fluid::boundary_keywords, bn->as_string()->get());
      if (!k || !closed(*k)) rd.fail_value(bpath, *bn, kinds);
      kind = *k;
    } else if (bn->is_table() && solved) {
      bopt = bn->as_table();
      rd.check_keys(*bopt, "gas.boundaries.*", bpath);
      if (!bopt->get("type")) rd.fail_missing(bpath + ".type", keyword_list(fluid::boundary_keywords, is_open_face));
      kind = rd.keyword(*bopt, "type", bpath, fluid::boundary_keywords, kind, is_open_face);
    } else {
      rd.fail_value(bpath, *bn, kinds);
    }
    fluid::Boundary& b = grid.faces[f];
    b.kind = kind;
    if (kind == BoundaryKind::velocity_inlet) {
      rd.reject_unused(*bopt, "pressure", bpath, "a velocity inlet sets the velocity");
      auto vin = rd.number(*bopt, "velocity", bpath, Dim::velocity);
      if (!vin) rd.fail_missing(bpath + ".velocity", "the gas speed into the domain, normal to the face [m/s or cm/s]");
      b.normal_velocity = *vin;
    } else if (kind == BoundaryKind::pressure_outlet) {
      rd.reject_unused(*bopt, "velocity", bpath, "a pressure outlet sets the pressure");
      b.pressure = rd.number(*bopt, "pressure", bpath, Dim::pressure).value_or(0.0);
    }
  }
  for (int a = 0; a < dim; ++a)
    if ((grid.faces[2 * a].kind == fluid::BoundaryKind::periodic) != (grid.faces[2 * a + 1].kind == fluid::BoundaryKind::periodic))
      rd.fail_value("gas.boundaries." + std::string(face_names[2 * a + 1]), *bt->get(face_names[2 * a + 1]),
                    "\"periodic\" exactly when gas.boundaries." + std::string(face_names[2 * a]) + " is");
  {
    bool inlet = false, outlet = false;
    for (const auto& f : grid.faces) {
      inlet |= f.kind == fluid::BoundaryKind::velocity_inlet;
      outlet |= f.kind == fluid::BoundaryKind::pressure_outlet;
    }
    if (inlet && !outlet)
      throw SceneError(rd.file() + ": key 'gas.boundaries': a velocity inlet without a pressure outlet: expected a "
                       "pressure_outlet face for the gas to leave by (the incompressible gas cannot accumulate)");
  }

  gs.density = rd.positive(*gt, "density", "gas", Dim::density, true);
  gs.viscosity = rd.positive(*gt, "viscosity", "gas", Dim::viscosity, true);
  const bool prescribed = spec.gas == GasModel::prescribed;  // only a prescribed field has a closed form
  gs.interpolation =
      rd.keyword(*gt, "interpolation", "gas", fluid::interpolation_keywords, fluid::InterpolationScheme::paper_lagrange2,
                 [prescribed](fluid::InterpolationScheme s) { return prescribed || s != fluid::InterpolationScheme::analytic; });

  if (spec.gas == GasModel::solved) {
    read_solved_gas(rd, *gt, spec);
    return;
  }
  for (const char* k : {"dt", "advection", "pressure_solver", "pressure_tolerance", "division", "initial_velocity",
                        "mean_pressure_gradient"})
    rd.reject_unused(*gt, k, "gas", "modules.gas is \"prescribed\" (these set up a solved gas)");
  if (const toml::node* cn = rd.root().get("coupling"))
    throw SceneError(rd.file() + ": table [coupling] = " + show(*cn) + " is not used: modules.gas is not \"solved\"");
  read_prescribed_field(rd, *gt, spec);
}

}  // namespace cdm::scene
