#pragma once
/// @file restart_origin.hpp
/// @brief What a restart may change in the scene it continues. The steps already taken
/// stay valid when only keys that do not change their physics differ: the end time
/// (integrator.end_time), how processes share the gas step (gas.division: the same
/// results either way) and everything under [output] (tables, VTK, intervals, the
/// checkpoint interval). Everything else is compared by value: the scene files are
/// parsed and the --set overrides applied to each, so layout, comments, key order and
/// number spelling (1e7 or 10000000.0) do not count.
#include <string>
#include <vector>

#include "cdm/solver/checkpoint.hpp"

namespace cdm {

/// The keys a restart may change, as written in the reference ("output.*": any key of [output]).
std::vector<std::string> restart_changeable_keys();

/// Throws CheckpointError naming the checkpoint @p path, the first key whose value differs
/// between the run that wrote it (@p saved) and the restart (@p now), and both values.
void check_restart_origin(const RunOrigin& saved, const RunOrigin& now, const std::string& path);

}  // namespace cdm
