#include "cdm/solver/mpi_session.hpp"

#include <cstdlib>
#include <initializer_list>
#include <stdexcept>
#include <string>

#ifdef CDM_WITH_MPI
#include <HYPRE_utilities.h>
#include <mpi.h>

#include <mutex>
#endif

namespace cdm {

namespace {

/// Launched by mpirun/srun (a world that may hold several processes)?
bool under_launcher() {
  for (const char* v : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID"})
    if (std::getenv(v)) return true;
  return false;
}

#ifdef CDM_WITH_MPI
bool started = false;

void finish() {
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (finalized) return;
  HYPRE_Finalize();
  MPI_Finalize();
}
#else
/// The first of the variables @p names that is set, as a number; @p fallback if none.
int env_int(std::initializer_list<const char*> names, int fallback) {
  for (const char* n : names)
    if (const char* v = std::getenv(n)) return std::atoi(v);
  return fallback;
}
#endif

}  // namespace

#ifdef CDM_WITH_MPI

bool built_with_mpi() { return true; }

void ensure_mpi() {
  static std::mutex m;
  static bool done = false;
  std::lock_guard<std::mutex> lock(m);
  if (done) return;
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) {
    if (!under_launcher()) {
      setenv("OMPI_MCA_pml", "ob1", 0);
      setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
      setenv("OMPI_MCA_orte_create_session_dirs", "0", 0);
    }
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

void abort_world(int rc) {
  int initialised = 0, finalized = 0, size = 1;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalized);
  if (!initialised || finalized) return;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (size > 1) MPI_Abort(MPI_COMM_WORLD, rc);
}

void mpi_check(int rc, const char* what) {
  if (rc != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

std::string first_failure(const std::string& mine) {
  int initialised = 0, size = 1, rank = 0;
  MPI_Initialized(&initialised);
  if (!initialised) return mine;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (size == 1) return mine;
  int failed = mine.empty() ? size : rank, first = size;
  mpi_check(MPI_Allreduce(&failed, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD), "MPI_Allreduce");
  if (first == size) return {};
  unsigned long long length = rank == first ? mine.size() : 0;
  mpi_check(MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, first, MPI_COMM_WORLD), "MPI_Bcast");
  std::string message = rank == first ? mine : std::string(static_cast<std::size_t>(length), ' ');
  mpi_check(MPI_Bcast(message.data(), static_cast<int>(length), MPI_CHAR, first, MPI_COMM_WORLD), "MPI_Bcast");
  return message;
}

#else

bool built_with_mpi() { return false; }

void ensure_mpi() {
  throw std::runtime_error("this cdm was built without MPI and hypre (CMake option CDM_WITH_MPI=OFF, or neither "
                           "found): nothing here can start MPI");
}

bool mpi_started_by_library() { return false; }

WorldPlace mpi_world() {
  // Without MPI the launcher's own variables say how many processes it started.
  if (!under_launcher()) return {};
  WorldPlace w;
  w.size = env_int({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "SLURM_NTASKS"}, 1);
  w.rank = env_int({"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID"}, 0);
  return w;
}

void abort_world(int) {}

void mpi_check(int, const char*) {}

std::string first_failure(const std::string& mine) { return mine; }

#endif

}  // namespace cdm
