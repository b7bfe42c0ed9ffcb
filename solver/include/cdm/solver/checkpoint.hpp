#pragma once
/// @file checkpoint.hpp
/// @brief Checkpoints that restart bit for bit: every particle's full state, the
/// contact history and Verlet list, the integrator state (forces of the current step,
/// step counter), and the scene the run came from, under a format version and an
/// FNV-1a 64-bit checksum per block, and where each output file of the run stood when it was
/// taken. Written to a temporary file, fsync'ed and renamed into place (and the
/// directory fsync'ed), so a crash mid-write leaves the previous checkpoint intact.
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/io/vtk_writer.hpp"
#include "cdm/solver/mpi_session.hpp"
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

/// Where the run's output files stood at the checkpoint, flushed and fsync'ed before
/// it was written: a restart cuts each back to this point before it appends, so the
/// files equal an uninterrupted run's however the first run ended (even by SIGKILL).
/// Empty for an output the run does not write.
struct OutputMarks {
  std::optional<std::uint64_t> particle_table;  ///< bytes of particles.dat
  std::optional<VtkMark> vtk;                   ///< frames of particles.pvd / gas.pvd
  std::optional<std::uint64_t> log;             ///< bytes of log.dat
  std::vector<std::uint64_t> monitors;          ///< bytes of each monitor's table, in scene order
  std::optional<std::uint64_t> population;      ///< bytes of outlets.dat
};

/// 6: the mesh contacts (in the contact module's state); 7: the population section
/// (Simulation::save_population) and outlets.dat's length; 8: the gas's drag gradients
/// on its fixed faces (GasField::drag_gradient); 9: the contact list's wall history as
/// the wall contacts only (particle, wall, displacement), not a slot per particle and wall;
/// 10: the pair contacts, not the listed pairs; 11: the slabs the pairs were listed in,
/// which a list kept after removals no longer derives from its build positions; 12: each
/// pair contact (i, j) as its build listed it, i the particle of the lower key
/// (VerletList::key_order), not the lower slot, its history seen from i; 13: a checksum
/// for each block of checksum_block bytes of the body, in a table after it, and in the
/// header the checksum of that table, not of the body.
constexpr std::uint32_t checkpoint_format_version = 13;

/// Write atomically (temporary file, fsync, rename, fsync of the directory). Throws
/// OutputError naming the path and the system's reason when it cannot; no temporary
/// file is left behind.
void write_checkpoint(const std::string& path, const Simulation& sim, const RunOrigin& origin,
                      const OutputMarks& marks = {});
/// Among MPI processes, what each process but the writer calls as the writer calls
/// write_checkpoint() (after Simulation::hold_for_checkpoint() on every process): the
/// state is written as it is gathered, each process sending its own particles' values.
void send_checkpoint_state(const Simulation& sim);

/// Read and verify a checkpoint (magic, version, length, its blocks' checksums) and return
/// its origin, output marks and where its state is: read_checkpoint keeps the file open
/// and notes where in it the state lies (so that a restart never holds the state twice in
/// memory, and each process reads and checks only the blocks that hold what it keeps),
/// read_checkpoint_bytes checks every block and copies the state's bytes. Throws
/// CheckpointError naming the file and what is wrong.
struct CheckpointData {
  RunOrigin origin;
  OutputMarks outputs;
  std::vector<char> state;            // read_checkpoint_bytes
  std::shared_ptr<std::FILE> file;    // read_checkpoint: the file, open
  BlockSums blocks;                   // read_checkpoint: its body's blocks' checksums
  std::uint64_t state_at = 0;         // where its state starts in the body [bytes]
  std::uint64_t state_size = 0;       // [bytes]
  /// Frees the state (its bytes, or the file) once it has been restored.
  void release_state() {
    std::vector<char>().swap(state);
    file.reset();
  }
};
/// Among the processes of @p world, every one calls read_checkpoint: each checks a share
/// of the blocks, and all refuse the checkpoint where any block does not match.
CheckpointData read_checkpoint(const std::string& path, WorldPlace world = {});
/// The same, from bytes already in memory (@p name is used in messages).
CheckpointData read_checkpoint_bytes(const std::vector<char>& bytes, const std::string& name);

/// Restore @p sim (built from the same scene) to the checkpointed state, validated as
/// strictly as a scene: the time finite and equal to what the step count gives (steps
/// times dt, as the run advances it), every position, velocity and gas value finite.
void restore_checkpoint(const CheckpointData& data, Simulation& sim, const std::string& path);

}  // namespace cdm
