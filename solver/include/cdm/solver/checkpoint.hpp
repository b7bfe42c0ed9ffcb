#pragma once
/// @file checkpoint.hpp
/// @brief Checkpoints that restart bit for bit: every particle's full state, the
/// contact history and Verlet list, the integrator state (forces of the current step,
/// step counter), and the scene the run came from, under a format version and an
/// FNV-1a 64-bit checksum. Written to a temporary file and renamed into place, so a
/// crash mid-write leaves the previous checkpoint intact.
#include <stdexcept>
#include <string>
#include <vector>

#include "cdm/solver/scene_loader.hpp"

namespace cdm {

class Simulation;

class CheckpointError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Where a run came from: the scene file's text, its name and the overrides applied.
struct RunOrigin {
  std::string scene_name;
  std::string scene_text;
  std::vector<SceneOverride> overrides;
};

constexpr std::uint32_t checkpoint_format_version = 3;

/// Write atomically (temporary file + rename). Throws CheckpointError on I/O failure.
void write_checkpoint(const std::string& path, const Simulation& sim, const RunOrigin& origin);

/// Read and verify a checkpoint (magic, version, length, checksum) and return its origin
/// and the state payload. Throws CheckpointError naming the file and what is wrong.
struct CheckpointData {
  RunOrigin origin;
  std::vector<char> state;
};
CheckpointData read_checkpoint(const std::string& path);
/// The same, from bytes already in memory (@p name is used in messages).
CheckpointData read_checkpoint_bytes(const std::vector<char>& bytes, const std::string& name);

/// Restore @p sim (built from the same scene) to the checkpointed state.
void restore_checkpoint(const CheckpointData& data, Simulation& sim, const std::string& path);

}  // namespace cdm
