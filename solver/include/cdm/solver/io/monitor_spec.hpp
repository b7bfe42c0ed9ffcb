#pragma once
/// @file monitor_spec.hpp
/// @brief A scene-defined monitor ([[monitors]]): a quantity sampled every
/// output.log_interval into its own table OUTDIR/monitor_NAME.dat.
#include <string>

#include "cdm/solver/vec3.hpp"
#include "cdm/solver/keywords.hpp"

namespace cdm {

enum class MonitorKind { pressure, plane_pressure, pressure_drop, bed_height, mass_flow, wall_force };
inline constexpr Keywords<MonitorKind, 6> monitor_keywords{{{"pressure", MonitorKind::pressure},
                                                            {"plane_pressure", MonitorKind::plane_pressure},
                                                            {"pressure_drop", MonitorKind::pressure_drop},
                                                            {"bed_height", MonitorKind::bed_height},
                                                            {"mass_flow", MonitorKind::mass_flow},
                                                            {"wall_force", MonitorKind::wall_force}}};
inline const char* to_string(MonitorKind k) { return keyword_of(monitor_keywords, k); }

struct MonitorSpec {
  std::string name;  ///< the table is monitor_<name>.dat
  MonitorKind kind = MonitorKind::pressure;
  Vec3 point;              ///< pressure: the point [m]
  int axis = 1;            ///< the axis of the plane(s) or the height (0 x, 1 y, 2 z)
  double position = 0.0;   ///< plane_pressure, mass_flow: the plane's coordinate along axis [m]
  double from = 0.0, to = 0.0;  ///< pressure_drop: the two planes [m]; the value is p(from) − p(to)
  double threshold = 0.0;  ///< bed_height: the solids fraction that counts as bed [-]
  double bin = 0.0;        ///< bed_height, mass_flow: the layer thickness [m]
  int wall = -1;           ///< wall_force: the wall (index into the scene's walls), -1 every wall
};

}  // namespace cdm
