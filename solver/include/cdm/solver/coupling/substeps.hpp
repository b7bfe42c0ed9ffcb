#pragma once
/// @file substeps.hpp
/// @brief How many particle steps a solved gas step holds.
#include <cmath>
#include <cstdint>

namespace cdm::coupling {

/// The whole number of particle steps of about @p dt in a gas step @p gas_dt: the
/// nearest one, or with @p no_longer the fewest whose steps are no longer than @p dt.
/// The particle step is then gas_dt divided by it.
inline std::uint64_t gas_substeps(double gas_dt, double dt, bool no_longer = false) {
  const double ratio = gas_dt / dt;
  return static_cast<std::uint64_t>(no_longer ? std::ceil(ratio - 1e-9) : std::round(ratio));
}

}  // namespace cdm::coupling
