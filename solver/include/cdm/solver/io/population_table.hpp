#pragma once
/// @file population_table.hpp
/// @brief OUTDIR/outlets.dat, the mass balance of a scene with [[insertions]] or
/// [[outlets]]: at each output sample (output.interval, as particles.dat) the particles
/// and mass inserted so far (all insertions), removed so far by each outlet, and those in
/// the domain. Counts balance exactly: in the domain = at the start + inserted −
/// removed; masses to the rounding of their sums.
#include <cstdint>
#include <optional>
#include <string>

#include "cdm/solver/output.hpp"

namespace cdm {

class Simulation;

class PopulationTableObserver : public SampledTable {
 public:
  PopulationTableObserver(const std::string& path, const Simulation& sim,
                          std::optional<std::uint64_t> resume_at = std::nullopt);
  void operator()(const Simulation& sim);
};

}  // namespace cdm
