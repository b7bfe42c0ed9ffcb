// gas_poisson: the cost of one solve of the gas pressure equation −∇·(d ∇φ) = b
// (cdm::fluid::PressureSolver) on an N³ box (or NX x NY x NZ cells): velocity inlet below, pressure outlet above,
// no-slip walls around, d random in [0.4, 1] per face (a gas fraction), b random in
// [−1, 1] per cell. Each repetition draws a new d, so it times what a gas step with
// changing ε pays: the operator's setup (factorisation or multigrid hierarchy) and the
// solve. Prints one line:
//   N cells backend reps setup_s solve_s us_per_cell cpu_us_per_cell iterations rel_residual maxrss_MB
//   factor_work_per_cell processes
// (N as given: 32 or 4x32x2; backend the one used, what "auto" resolved to for auto;
// factor_work_per_cell cdm::fluid::direct_factor_work_per_cell, which "auto" decides by)
// (wall times, medians over the repetitions; cpu_us_per_cell the process's CPU time per
// cell and solve, setup included, which a shared machine inflates less than the wall
// time; maxrss the process's peak resident memory). Under mpirun the multigrid solve is
// divided among the processes (pressure_multigrid.cpp): rank 0 prints the line, with its
// own times and memory, and processes is the number of them.
// bench/gas_poisson.sh runs the table in bench/README.md.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "cdm/solver/fluid/pressure_solver.hpp"
#include "cdm/solver/mpi_session.hpp"

namespace {

using namespace cdm::fluid;

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

int usage() {
  std::fprintf(stderr,
               "usage: gas_poisson N|NXxNYxNZ auto|multigrid|direct [repetitions] (N in [2, 512], repetitions in [1, "
               "100])\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4) return usage();
  const std::string shape = argv[1];
  int cells[3] = {0, 0, 0};
  char tail = 0;
  if (std::sscanf(shape.c_str(), "%dx%dx%d%c", &cells[0], &cells[1], &cells[2], &tail) != 3) {
    if (std::sscanf(shape.c_str(), "%d%c", &cells[0], &tail) != 1) return usage();
    cells[1] = cells[2] = cells[0];
  }
  const std::string backend = argv[2];
  const int reps = argc == 4 ? std::atoi(argv[3]) : 3;
  for (int c : cells)
    if (c < 2 || c > 512) return usage();
  if (reps < 1 || reps > 100 || (backend != "auto" && backend != "multigrid" && backend != "direct")) return usage();
  if (backend == "multigrid" && !cdm::fluid::multigrid_available()) {
    std::fprintf(stderr, "gas_poisson: this build has no multigrid backend (built without MPI and hypre)\n");
    return 2;
  }

  GridSpec gs;
  gs.lo = {0, 0, 0};
  gs.hi = {0.1, 0.1, 0.1};
  gs.cells = {cells[0], cells[1], cells[2]};
  for (auto& f : gs.faces) f.kind = BoundaryKind::no_slip;
  gs.faces[2].kind = BoundaryKind::velocity_inlet;
  gs.faces[3].kind = BoundaryKind::pressure_outlet;
  const StaggeredGrid g(gs);
  PressureSolverSpec spec;
  spec.backend = backend == "direct"      ? PressureBackend::direct
                 : backend == "multigrid" ? PressureBackend::multigrid
                                          : PressureBackend::automatic;
  PressureSolver solver(g, spec);

  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> eps(0.4, 1.0), src(-1.0, 1.0);
  std::array<std::vector<double>, 3> d;
  for (auto& a : d) a = g.make_array();
  std::vector<double> b(g.cell_count()), phi(g.cell_count(), 0.0);
  std::vector<double> setup, solve, cpu;
  PressureSolveStats last;
  using clock = std::chrono::steady_clock;
  for (int r = 0; r < reps; ++r) {
    for (auto& a : d)
      for (double& x : a) x = eps(rng);
    for (double& x : b) x = src(rng);
    std::fill(phi.begin(), phi.end(), 0.0);
    // A zero right-hand side does the setup alone (the solve returns at once).
    std::vector<double> zero(g.cell_count(), 0.0), phi0(g.cell_count(), 0.0);
    const double c0 = cpu_seconds();
    const auto t0 = clock::now();
    solver.solve({&d[0], &d[1], &d[2]}, zero, phi0);
    const auto t1 = clock::now();
    last = solver.solve({&d[0], &d[1], &d[2]}, b, phi);
    const auto t2 = clock::now();
    cpu.push_back(cpu_seconds() - c0);
    setup.push_back(std::chrono::duration<double>(t1 - t0).count());
    solve.push_back(std::chrono::duration<double>(t2 - t1).count());
  }
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  const double ncell = static_cast<double>(g.cell_count());
  const double su = median(setup), so = median(solve);
  const cdm::WorldPlace world = cdm::mpi_world();
  if (world.rank != 0) return 0;
  std::printf("%s %.0f %s %d %.4f %.4f %.3f %.3f %d %.2e %.1f %.0f %d\n", shape.c_str(), ncell,
              to_string(solver.backend()), reps, su, so, (su + so) / ncell * 1e6, median(cpu) / ncell * 1e6,
              last.iterations, last.relative_residual, static_cast<double>(ru.ru_maxrss) / 1024.0,
              direct_factor_work_per_cell(g), world.size);
  return 0;
}
