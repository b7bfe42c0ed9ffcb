#pragma once
/// @file mpi_session.hpp
/// @brief MPI for the library's distributed solvers, started on demand.
///
/// The first solver that needs MPI calls ensure_mpi(). If the program has not
/// initialised MPI, the library does (MPI_Init_thread with MPI_THREAD_FUNNELED: only the
/// thread that called it makes MPI calls; OpenMP regions make none) and finalises it at
/// exit. A program started without a launcher (no mpirun) becomes an Open MPI singleton,
/// a world of one process; it then defaults Open MPI's point-to-point layer to ob1
/// (OMPI_MCA_pml, unless set), which starts in about 0.1 s instead of about 0.4 s spent
/// probing network transports a single process never uses. It also starts no supporting
/// daemon and creates no session folder (OMPI_MCA_ess_singleton_isolated and
/// OMPI_MCA_orte_create_session_dirs, unless set; cdm never spawns processes and one
/// process shares no memory). The daemon would outlive the program and remove the user's
/// session folder after it, while an mpirun started next may be creating its own there;
/// without the daemon every singleton would share one such folder. hypre is initialised once.
/// In a build without MPI (CMake option CDM_WITH_MPI off, or MPI or hypre not found),
/// ensure_mpi() throws and mpi_world() reads the launcher's variables instead.

#include <string>

namespace cdm {

/// Whether this build has MPI and hypre (CDM_WITH_MPI).
bool built_with_mpi();

/// Initialise MPI and hypre once if not done yet; throws std::runtime_error if MPI
/// cannot start (or the build has none).
void ensure_mpi();

/// Whether ensure_mpi() started MPI (and so finalises it at exit).
bool mpi_started_by_library();

/// The number of processes in this program's MPI world and this one's rank: {1, 0}
/// without a launcher (mpirun, srun) in the environment; else MPI is started (ensure_mpi)
/// and asked (without MPI: the launcher's variables, OMPI_COMM_WORLD_SIZE and the like).
struct WorldPlace {
  int size = 1, rank = 0;
};
WorldPlace mpi_world();

/// Stop every process of a run of several with exit code @p rc (MPI_Abort); returns
/// when there is only one (or no MPI).
void abort_world(int rc);

/// Among a run's processes (every one calls it), the failure @p mine of the lowest rank
/// that had one, or empty where none had: a check each process makes on its own share
/// then ends the same way on every process. One process (or no MPI): @p mine.
std::string first_failure(const std::string& mine);

/// Throws std::runtime_error naming @p what where an MPI call's result @p rc is not
/// MPI_SUCCESS (with MPI; without, never called).
void mpi_check(int rc, const char* what);

}  // namespace cdm
