/// @file registry.cpp
/// @brief The case kinds: case.toml's `kind` names the runner, a function of that name in
/// runners/<file>.cpp. A new kind is one line in the list below.
#include "cdm/verification/harness.hpp"

namespace cdm::verification {

#define CDM_CASE_KINDS(KIND)      \
  KIND(free_fall)                 \
  KIND(stacked)                   \
  KIND(slipping_ball)             \
  KIND(vortex_advection)          \
  KIND(terminal_velocity)         \
  KIND(terminal_velocity_coupled) \
  KIND(taylor_green)              \
  KIND(taylor_green_clustering)   \
  KIND(gas_mms)                   \
  KIND(suspension)                \
  KIND(packed_bed)                \
  KIND(fluidization)              \
  KIND(hertz_impact)              \
  KIND(hertz_restitution)         \
  KIND(oblique_impact)            \
  KIND(rolling_resistance)        \
  KIND(mesh_vs_walls)             \
  KIND(mesh_impact)               \
  KIND(population_balance)

namespace runners {
#define CDM_DECLARE_RUNNER(name) RunOutput name(const CaseDef&, const Variant&, const RunConfig&);
CDM_CASE_KINDS(CDM_DECLARE_RUNNER)
#undef CDM_DECLARE_RUNNER
}  // namespace runners

const std::map<std::string, CaseRunner>& case_runners() {
#define CDM_REGISTER_RUNNER(name) {#name, runners::name},
  static const std::map<std::string, CaseRunner> r = {CDM_CASE_KINDS(CDM_REGISTER_RUNNER)};
#undef CDM_REGISTER_RUNNER
  return r;
}

#undef CDM_CASE_KINDS

}  // namespace cdm::verification
