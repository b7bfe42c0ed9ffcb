/// @file coupling.cpp
/// @brief A solved gas's step and advection, and how it couples to the particles ([coupling]).
#include "sections.hpp"

#include <algorithm>
#include <limits>
#include <sstream>
#include <string>

namespace cdm::scene {

void read_solved_gas(const Reader& rd, const toml::table& gt, SceneSpec& spec) {
  rd.reject_unused(gt, "field", "gas", "modules.gas is \"solved\" (a solved gas evolves from its initial velocity)");
  spec.gas_dt = rd.positive(gt, "dt", "gas", Dim::time, true);
  spec.advection = rd.keyword(gt, "advection", "gas", fluid::advection_keywords, fluid::AdvectionScheme::upwind,
                              [](fluid::AdvectionScheme a) { return a != fluid::AdvectionScheme::none; });
  // "auto": the direct factorisation where it is the cheaper, else multigrid where the
  // build has it (MPI and hypre).
  const bool mg = fluid::multigrid_available();
  spec.pressure_solver.backend = rd.keyword(
      gt, "pressure_solver", "gas", fluid::pressure_backend_keywords, fluid::PressureBackend::automatic,
      [mg](fluid::PressureBackend b) { return mg || b != fluid::PressureBackend::multigrid; },
      mg ? "" : " (this cdm was built without MPI and hypre, which \"multigrid\" needs: CMake option CDM_WITH_MPI)");
  if (spec.pressure_solver.backend == fluid::PressureBackend::direct)
    rd.reject_unused(gt, "pressure_tolerance", "gas", "gas.pressure_solver is \"direct\" (exact to round-off)");
  {
    using P = fluid::PressureSolverSpec;
    std::ostringstream range;
    range << "a relative residual in [" << P::min_tolerance << ", " << P::max_tolerance << "]";
    spec.pressure_solver.tolerance = rd.number_in(gt, "pressure_tolerance", "gas", Dim::none, false, P{}.tolerance,
                                                  P::min_tolerance, false, P::max_tolerance, false, range.str());
  }
  if (spec.pressure_solver.backend == fluid::PressureBackend::automatic && gt.get("pressure_tolerance")) {
    const fluid::StaggeredGrid grid(spec.gas_spec.grid);
    if (fluid::automatic_backend(grid) == fluid::PressureBackend::direct)
      rd.reject_unused(gt, "pressure_tolerance", "gas",
                       "gas.pressure_solver is \"auto\", which on this grid of " + std::to_string(grid.cell_count()) +
                           " cells is the direct factorisation (exact to round-off); expected no tolerance" +
                           (mg ? ", or pressure_solver = \"multigrid\" to solve to it"
                               : " (this cdm was built without MPI and hypre: no multigrid solve)"));
  }
  spec.gas_division = rd.keyword(gt, "division", "gas", fluid::gas_division_keywords, fluid::GasDivision::automatic);
  spec.gas_initial_velocity = rd.vec3(gt, "initial_velocity", "gas", Dim::velocity).value_or(Vec3{});
  spec.mean_pressure_gradient = rd.vec3(gt, "mean_pressure_gradient", "gas", Dim::pressure_gradient).value_or(Vec3{});
  if (spec.gas_spec.grid.two_d && spec.gas_initial_velocity.z != 0.0)
    rd.fail_value("gas.initial_velocity", *gt.get("initial_velocity"), "no z component in a two-dimensional gas");
  const toml::table* ct = rd.table(rd.root(), "coupling", "", false);
  static const toml::table empty;
  const toml::table& c = ct ? *ct : empty;
  rd.check_keys(c, "coupling", "coupling");
  spec.two_way = rd.keyword(c, "mode", "coupling", coupling_mode_keywords, false);
  spec.coupling_method =
      rd.keyword(c, "method", "coupling", coupling::coupling_method_keywords, coupling::CouplingMethod::interpolate);
  if (spec.coupling_method == coupling::CouplingMethod::cell_average) {
    rd.reject_unused(c, "kernel", "coupling", "coupling.method = \"cell_average\" deposits into the holding cell");
    if (spec.drag && spec.drag_update != coupling::DragUpdate::explicit_force)
      rd.fail_value("coupling.method", *c.get("method"),
                    "\"interpolate\" with drag.update = \"" + std::string(coupling::to_string(spec.drag_update)) +
                     "\": the cell-average drag does not depend on a particle's own velocity, so only the explicit "
                     "update applies");
  }
  spec.kernel = rd.keyword(c, "kernel", "coupling", coupling::kernel_keywords, coupling::Kernel::trilinear);
  if (spec.kernel == coupling::Kernel::gaussian && spec.coupling_method == coupling::CouplingMethod::interpolate) {
    spec.kernel_width = rd.positive(c, "kernel_width", "coupling", Dim::length, true);
    // The kernel reaches 3σ: its stencil, up to 16 cells either side, bounds the work per
    // particle (a wider kernel would cost (6σ/h)³ weights per particle and deposition).
    const fluid::GridSpec& g = spec.gas_spec.grid;
    const double lo[3] = {g.lo.x, g.lo.y, g.lo.z}, hi[3] = {g.hi.x, g.hi.y, g.hi.z};
    double reach = std::numeric_limits<double>::max();
    for (int a = 0; a < (g.two_d ? 2 : 3); ++a) reach = std::min(reach, 16.0 * (hi[a] - lo[a]) / g.cells[a]);
    if (3.0 * spec.kernel_width > reach) {
      std::ostringstream os;
      os << "a width whose reach, 3 sigma, spans at most 16 gas cells along every axis (sigma <= " << reach / 3.0
         << " m here)";
      rd.fail_value("coupling.kernel_width", *c.get("kernel_width"), os.str());
    }
  } else
    rd.reject_unused(c, "kernel_width", "coupling", "coupling.kernel is not \"gaussian\"");
  spec.gas_velocity =
      rd.keyword(c, "gas_velocity", "coupling", coupling::slip_velocity_keywords, coupling::SlipVelocity::interstitial);
  if (spec.coupling_method == coupling::CouplingMethod::cell_average)
    rd.reject_unused(c, "gas_velocity", "coupling", "coupling.method = \"cell_average\" uses the cell-centred gas velocity");
  // The implicit treatment needs each particle's drag coefficient K, kept by the relaxed
  // drag updates; with the explicit update the gas takes the drag explicitly.
  const bool relaxed = spec.drag && spec.drag_update != coupling::DragUpdate::explicit_force;
  spec.implicit_gas_drag = spec.two_way && rd.keyword(c, "gas_drag", "coupling", gas_drag_keywords, relaxed);
  if (spec.implicit_gas_drag && !relaxed)
    rd.fail_value("coupling.gas_drag", *c.get("gas_drag"),
                  "\"explicit\" with drag.update = \"explicit\" (the implicit drag on the gas needs each particle's "
                  "drag coefficient, kept by drag.update = \"exponential\" or \"implicit\")");
  spec.drag_evaluation = rd.keyword(c, "drag_evaluation", "coupling", coupling::drag_evaluation_keywords,
                                    coupling::DragEvaluation::every_step);
  if (spec.drag_evaluation == coupling::DragEvaluation::gas_step &&
      spec.coupling_method == coupling::CouplingMethod::cell_average)
    rd.fail_value("coupling.drag_evaluation", *c.get("drag_evaluation"),
                  "\"every_step\" with coupling.method = \"cell_average\" (the per-gas-step evaluation caches each "
                  "particle's own drag coefficient and gas velocity, which the interpolate method gives)");
  if (!spec.two_way) {
    for (const char* k : {"method", "kernel", "kernel_width", "gas_velocity", "gas_drag"})
      rd.reject_unused(c, k, "coupling", "coupling.mode is \"one_way\" (the particles do not act on the gas)");
  }
  if (spec.two_way && !spec.drag)
    throw SceneError(rd.file() + ": key 'coupling.mode' = \"two_way\": expected modules.drag to name a drag law (the "
                     "particles act on the gas through drag)");
}

}  // namespace cdm::scene
