#pragma once
/// @file thermo_log.hpp
/// @brief The run's own log (LAMMPS calls it thermo output): every output.log_interval
/// one row of whole-system quantities, appended to OUTDIR/log.dat and printed.
#include <cstdint>
#include <optional>
#include <string>

#include "cdm/solver/output.hpp"

namespace cdm {

class Simulation;

struct ThermoSample {
  double time = 0.0;
  std::uint64_t step = 0;
  double kinetic_translational = 0.0;  ///< Σ ½ m v² over the moving particles [J]
  double kinetic_rotational = 0.0;     ///< Σ ½ I ω² [J]
  std::uint64_t contacts = 0;          ///< particle pairs and particle–wall pairs that overlap
  double max_overlap_ratio = 0.0;      ///< largest overlap / radius (the smaller radius of a pair) [-]
  std::uint64_t particles = 0;
  bool has_gas = false;
  /// Pressure of the first cell layer minus the last along the flow axis (the axis with
  /// an inlet or outlet face, else the one gravity points along most) [Pa].
  double pressure_drop = 0.0;
  double max_courant = 0.0;  ///< largest |u| Δt_gas / h over the faces [-]
};

/// The sample at sim's time(): each process sums its own particles and pairs, added up
/// (counted_sums.hpp), without gathering the state. A collective call when several
/// processes share the particles.
ThermoSample thermo_sample(const Simulation& sim);

/// The flow axis of a solved or prescribed gas for pressure_drop (see ThermoSample).
int flow_axis(const Simulation& sim);

/// One line for a terminal: the sample's quantities with their names.
std::string thermo_line(const ThermoSample& s);

/// Writes a ThermoSample at each multiple of the scene's output.log_interval (and at the
/// last step) to the table at @p path. Restarts continue the table from the length the
/// checkpoint recorded, as ParticleTableObserver does.
class ThermoLogObserver : public SampledTable {
 public:
  ThermoLogObserver(const std::string& path, const Simulation& sim,
                    std::optional<std::uint64_t> resume_at = std::nullopt);
  /// The sample written at this step, if the step is one.
  std::optional<ThermoSample> operator()(const Simulation& sim);
};

}  // namespace cdm
