#pragma once
/// @file monitors.hpp
/// @brief The scene's [[monitors]]: each a table OUTDIR/monitor_NAME.dat with one row
/// every output.log_interval. Every monitor is a function of the state at the sample
/// alone (no history), so a restarted run's tables equal an uninterrupted run's.
///  - pressure: the pressure of the gas cell holding a point;
///  - plane_pressure: the mean pressure over the layer of cells holding a plane;
///  - pressure_drop: plane_pressure(from) − plane_pressure(to);
///  - bed_height: the top of the highest layer (of thickness bin, from the gas domain's
///    lower face along the axis) whose solids fraction — particle volume with centres in
///    the layer over the layer's volume — reaches the threshold, measured from the lower
///    face; 0 when none does;
///  - mass_flow: the solids mass flux through a plane, Σ m v_axis / bin over the particles
///    whose centres lie within bin/2 of it [kg/s] (the standard slab estimate; positive
///    along +axis);
///  - wall_force: the force along the axis that one wall, or every wall, exerts on the
///    particles (wall_forces(), output_fields.hpp) [N].
#include <memory>
#include <string>
#include <vector>

#include "cdm/solver/io/monitor_spec.hpp"
#include "cdm/solver/output.hpp"

namespace cdm {

class Simulation;

/// The value of monitor @p m for the state of @p sim. A wall_force monitor reads
/// @p walls, wall_forces(sim) of the same state, where given (one evaluation of the
/// contacts for all of a sample's wall monitors), else evaluates it.
double monitor_value(const MonitorSpec& m, const Simulation& sim, const std::vector<double>* walls = nullptr);

/// The file name of monitor @p m's table.
std::string monitor_file(const MonitorSpec& m);

/// One table per monitor of the scene, in scene order.
class MonitorObserver {
 public:
  /// @p resume_at: the table lengths a checkpoint recorded, in scene order (empty: new tables).
  /// With an empty @p out_dir the tables discard their rows (TableWriter).
  MonitorObserver(const std::string& out_dir, const Simulation& sim, const std::vector<std::uint64_t>& resume_at);
  void operator()(const Simulation& sim);
  /// Flush and fsync every table; their lengths in bytes, in scene order.
  std::vector<std::uint64_t> sync();
  void close();

 private:
  std::vector<std::unique_ptr<TableWriter>> tables_;
  SampleSchedule schedule_;
};

}  // namespace cdm
