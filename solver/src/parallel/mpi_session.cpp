#include "cdm/solver/mpi_session.hpp"

#include <HYPRE_utilities.h>
#include <mpi.h>

#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>

namespace cdm {

namespace {

bool started = false;

void finish() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  HYPRE_Finalize();
  MPI_Finalize();
}

/// Launched by mpirun/srun (a world that may hold several processes)?
bool under_launcher() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID"})
    if (std::getenv(v)) return true;
  return false;
}

}  // namespace

void ensure_mpi() {
  static std::mutex m;
  static bool done = false;
  std::lock_guard<std::mutex> lock(m);
  if (done) return;
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) {
    if (!under_launcher()) setenv("OMPI_MCA_pml", "ob1", 0);
    int provided = 0;
    const int rc = MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    if (rc != MPI_SUCCESS) throw std::runtime_error("MPI_Init_thread failed (error " + std::to_string(rc) + ")");
    started = true;
    std::atexit(finish);
  }
  HYPRE_Init();
  done = true;
}

bool mpi_started_by_library() { return started; }

WorldPlace mpi_world() {
  if (!under_launcher()) return {};
  ensure_mpi();
  WorldPlace w;
  MPI_Comm_size(MPI_COMM_WORLD, &w.size);
  MPI_Comm_rank(MPI_COMM_WORLD, &w.rank);
  return w;
}

}  // namespace cdm
