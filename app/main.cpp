/// @file main.cpp
/// @brief The `cdm` command: thin wiring of the solver and the verification harness.
///   cdm run SCENE [-o DIR] [--set path=value ...] [--restart CHECKPOINT] [--max-steps N] [-q]
///   cdm verify [CASE ...] [--cases DIR] [--out DIR] [--sweep]
///   cdm report [--in DIR] [--out DIR] [--report-script FILE]
///   cdm --version
#include <CLI/CLI.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <deque>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <omp.h>
#include <optional>
#include <sstream>
#include <thread>
#include <unistd.h>
#include <filesystem>
#include <iostream>

#include "cdm/solver/checkpoint.hpp"
#include "cdm/solver/fluid/gas_solver.hpp"
#include "cdm/solver/io/monitors.hpp"
#include "cdm/solver/io/population_table.hpp"
#include "cdm/solver/io/thermo_log.hpp"
#include "cdm/solver/io/vtk_writer.hpp"
#include "cdm/solver/mpi_session.hpp"
#include "cdm/solver/output.hpp"
#include "cdm/solver/restart_origin.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"
#include "cdm/verification/harness.hpp"

#include "cdm/version.hpp"

namespace fs = std::filesystem;

namespace {

std::string shell_line(const std::string& cmd) {
  std::string out;
  if (FILE* p = popen(cmd.c_str(), "r")) {
    char buf[512];
    if (fgets(buf, sizeof buf, p)) out = buf;
    pclose(p);
  }
  while (!out.empty() && (out.back() == '\n' || out.back() == ' ')) out.pop_back();
  return out.empty() ? "unknown" : out;
}

/// The folder of the command's data (verification cases, report script): at
/// CDM_DATA_RELATIVE from the directory of the running executable, in an installed tree
/// (bin/../share/cdm) and in the build tree alike.
fs::path data_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return fs::path(CDM_DATA_RELATIVE);
  return (exe.parent_path() / CDM_DATA_RELATIVE).lexically_normal();
}

/// What a reader of the tables needs to reproduce them: commit, compiler, machine.
std::vector<std::pair<std::string, std::string>> provenance() {
  return {{"commit", CDM_GIT_COMMIT},
          {"compiler", CDM_COMPILER},
          {"flags", CDM_CXX_FLAGS},
          {"build_type", CDM_BUILD_TYPE},
          {"date_utc", shell_line("date -u +%Y-%m-%dT%H:%M:%SZ")},
          {"cpu_model", shell_line("grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'")},
          {"cores", shell_line("nproc")},
          {"host", shell_line("uname -srm")}};
}

std::atomic<int> g_signal{0};

/// The MPI processes this run is one of ({1, 0} without a launcher).
cdm::WorldPlace g_world;

/// Reports @p e and gives exit code @p rc. Among several processes, a failure on one
/// would leave the others waiting for it: the whole run is stopped (MPI_Abort). Every
/// process fails alike on a bad scene or an unstable state, so rank 0 reports and stops
/// the run; another rank reports only if it is still running a moment later (rank 0 did
/// not fail with it).
int fail(int rc, const char* prefix, const std::exception& e) {
  if (g_world.size > 1 && g_world.rank != 0) std::this_thread::sleep_for(std::chrono::seconds(2));
  std::cerr << (std::string(prefix) + e.what() +
                (g_world.size > 1 ? " (rank " + std::to_string(g_world.rank) + ")" : std::string()) + "\n");
  std::cerr.flush();
  if (g_world.size > 1) cdm::abort_world(rc);
  return rc;
}
extern "C" void on_signal(int sig) { g_signal.store(sig); }

/// Progress on the terminal (stderr) for runs longer than a few seconds: simulated time,
/// steps, particle-steps per second and the time left, from the rate over the last ten
/// seconds or so (a run's pace changes: a falling bed is fast, a settled one slow). Never
/// in the data files.
class Progress {
 public:
  explicit Progress(bool on) : on_(on), start_(clock::now()), last_(start_) {}
  void operator()(const cdm::Simulation& s) {
    if (!on_ || (s.steps() & 63) != 0) return;
    const auto now = clock::now();
    if (now - last_ < std::chrono::seconds(1) || now - start_ < std::chrono::seconds(3)) return;
    last_ = now;
    const double done = static_cast<double>(s.steps() - s0_), total = static_cast<double>(s.total_steps() - s0_);
    window_.push_back({now, done});
    while (window_.size() > 2 && now - window_[1].first >= std::chrono::seconds(10)) window_.pop_front();
    const auto& [t0, d0] = window_.front();
    const double span = std::chrono::duration<double>(now - (window_.size() > 1 ? t0 : start_)).count();
    const double steps = window_.size() > 1 ? done - d0 : done;
    const double step_rate = span > 0 ? steps / span : 0.0;
    const double rate = step_rate * static_cast<double>(s.particle_count());
    const double left = step_rate > 0 ? (total - done) / step_rate : 0.0;
    std::fprintf(stderr, "\r  t = %.4g s  step %llu/%llu  %.3g particle-steps/s  %.0f s left   ", s.time(),
                 static_cast<unsigned long long>(s.steps()), static_cast<unsigned long long>(s.total_steps()), rate, left);
    shown_ = true;
  }
  void start_at(std::uint64_t steps) { s0_ = steps; }
  /// Ends the progress line, so that what is printed next starts on a line of its own.
  void end_line() {
    if (shown_) std::fputs("\n", stderr);
    shown_ = false;
  }
  ~Progress() { end_line(); }

 private:
  using clock = std::chrono::steady_clock;
  bool on_, shown_ = false;
  clock::time_point start_, last_;
  std::deque<std::pair<clock::time_point, double>> window_;  // (wall, steps done) at each display
  std::uint64_t s0_ = 0;
};

/// @p s quoted for a POSIX shell.
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

int run_scene(const std::string& scene, std::string out_dir, const std::vector<std::string>& sets,
              const std::string& restart, std::uint64_t max_steps, bool quiet) {
  cdm::RunOrigin origin;
  origin.scene_name = scene;
  origin.scene_text = cdm::read_scene_file(scene);
  for (const auto& s : sets) {
    origin.overrides.push_back(cdm::parse_override(s));
    cdm::check_override(origin.overrides.back());
  }
  // Everything is validated before anything is written.
  cdm::Simulation sim(cdm::load_scene_from_string(origin.scene_text, scene, origin.overrides));
  const cdm::SceneSpec& spec = sim.spec();
  std::optional<cdm::CheckpointData> ck;
  if (!restart.empty()) {
    ck = cdm::read_checkpoint(restart, g_world);
    cdm::check_restart_origin(ck->origin, origin, restart);
    cdm::restore_checkpoint(*ck, sim, restart);
    ck->release_state();  // only its output marks are read from here on
  }
  std::cout << "cdm run: " << scene << ": " << sim.particle_count() << " particles, modules:";
  for (const auto& m : sim.module_names()) std::cout << ' ' << m;
  std::cout << "; integrator " << cdm::to_string(spec.integrator) << ", dt = " << spec.dt << " s";
  if (spec.t_col_min > 0) std::cout << " (t_col/" << spec.t_col_min / spec.dt << ")";
  std::cout << ", " << sim.total_steps() << " steps";
  if (sim.restarted()) std::cout << ", restarting at step " << sim.steps() << " (t = " << sim.time() << " s)";
  const cdm::fluid::GasSolver* gas_solver = sim.gas_solver();
  if (gas_solver) std::cout << "; gas pressure solve: " << gas_solver->pressure_solver().method();
  std::cout << "\n";
  // The gas step's loops (plane_share.hpp) and its multigrid pressure solve
  // (pressure_multigrid.cpp) are divided among the processes where gas.division says so;
  // the direct solve is done whole by each.
  const bool gas_divided = gas_solver && gas_solver->divided();
  const bool solve_shared =
      gas_divided && gas_solver->pressure_solver().backend() == cdm::fluid::PressureBackend::multigrid;
  const std::string gas_part =
      std::string("the gas step") + (solve_shared ? "" : " (its direct pressure solve done whole by each)");
  std::string whole_gas;
  if (sim.ranks() > 1 && gas_solver && !gas_divided) {
    whole_gas = std::string("; each steps the whole gas (gas.division = \"") + cdm::fluid::to_string(spec.gas_division) +
                "\"";
    if (spec.gas_division == cdm::fluid::GasDivision::automatic)
      whole_gas += ": its " + std::to_string(sim.gas()->grid().cell_count()) + " cells give a process fewer than " +
                   std::to_string(cdm::fluid::PlaneShare::min_divided_cells);
    whole_gas += ")";
  }
  if (sim.ranks() > 1)
    std::cout << "cdm run: the particles' work" << (gas_divided ? " and " + gas_part + " are" : " is")
              << " shared among " << sim.ranks() << " MPI processes" << whole_gas << "\n";
  std::cout << std::flush;
  // Rank 0 writes the files. The other processes run the same observers, which read the
  // state (and so gather it) at the same steps, but write nothing: their paths are empty.
  const bool writes = sim.ranks() <= 1 || g_world.rank == 0;
  const std::string files_dir = writes ? out_dir : std::string();
  auto file = [&](const std::string& name) { return writes ? (fs::path(files_dir) / name).string() : std::string(); };
  const std::string ckpt = (fs::path(out_dir) / "checkpoint.cdmck").string();
  if (writes) {
    cdm::make_output_directory(out_dir);
    if (fs::exists(ckpt) && !fs::is_regular_file(ckpt))
      throw cdm::OutputError("cannot write the checkpoint '" + ckpt + "': it exists and is not a regular file");
  }

  // A restart cuts each output back to where the checkpoint recorded it before appending.
  std::optional<cdm::ParticleTableObserver> table;
  if (spec.output_particles)
    table.emplace(file("particles.dat"), sim, ck ? ck->outputs.particle_table : std::optional<std::uint64_t>());
  std::optional<cdm::VtkObserver> vtk;
  if (spec.output_vtk) vtk.emplace(files_dir, sim, ck ? ck->outputs.vtk : std::optional<cdm::VtkMark>());
  std::optional<cdm::ThermoLogObserver> log;
  if (spec.log_interval > 0) log.emplace(file("log.dat"), sim, ck ? ck->outputs.log : std::optional<std::uint64_t>());
  cdm::MonitorObserver monitors(files_dir, sim, ck ? ck->outputs.monitors : std::vector<std::uint64_t>());
  std::optional<cdm::PopulationTableObserver> population;
  if (spec.population_changes())
    population.emplace(file("outlets.dat"), sim,
                       ck ? ck->outputs.population : std::optional<std::uint64_t>());
  ck.reset();  // the state is restored; its bytes are not needed any more
  // The outputs are made durable and their lengths recorded in the checkpoint.
  auto checkpoint = [&](const cdm::Simulation& s) {
    cdm::OutputMarks marks;
    if (table) marks.particle_table = table->sync();
    if (vtk) marks.vtk = vtk->sync();
    if (log) marks.log = log->sync();
    marks.monitors = monitors.sync();
    if (population) marks.population = population->sync();
    const auto held = s.hold_for_checkpoint();  // the contacts, from every rank, to rank 0
    if (writes) cdm::write_checkpoint(ckpt, s, origin, marks);
    else cdm::send_checkpoint_state(s);         // the state streams to rank 0 as it writes
  };
  Progress progress(!quiet && isatty(STDERR_FILENO));
  progress.start_at(sim.steps());
  long long last_ck = spec.checkpoint_interval > 0
                          ? static_cast<long long>(std::floor(sim.time() / spec.checkpoint_interval + 1e-9))
                          : 0;
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  const std::uint64_t stop_at = max_steps ? std::min(sim.total_steps(), sim.steps() + max_steps) : sim.total_steps();
  const std::uint64_t steps_before = sim.steps();
  const auto loop_start = std::chrono::steady_clock::now();
  sim.run(
      [&](const cdm::Simulation& s) {
        if (table) (*table)(s);
        if (vtk) (*vtk)(s);
        monitors(s);
        if (population) (*population)(s);
        if (log)
          if (const auto row = (*log)(s); row && !quiet) {
            progress.end_line();
            std::printf("  %s\n", cdm::thermo_line(*row).c_str());
            std::fflush(stdout);
          }
        progress(s);
        if (spec.checkpoint_interval > 0) {
          const auto k = static_cast<long long>(std::floor(s.time() / spec.checkpoint_interval + 1e-9));
          if (k > last_ck) {
            last_ck = k;
            checkpoint(s);
          }
        }
      },
      [&] { return sim.any_rank(g_signal.load() != 0) || sim.steps() >= stop_at; });
  const double loop_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - loop_start).count();
  progress.end_line();
  const double psteps = static_cast<double>(sim.steps() - steps_before) * static_cast<double>(sim.particle_count());
  const std::string where = sim.ranks() > 1 ? std::to_string(sim.ranks()) + " processes of " +
                                                  std::to_string(omp_get_max_threads()) + " thread(s)"
                                            : std::to_string(omp_get_max_threads()) + " thread(s)";
  std::printf("loop time %.3f s for %llu steps of %zu particles on %s: %.4g particle-steps/s; simulated time %.6g s\n",
              loop_s, static_cast<unsigned long long>(sim.steps() - steps_before), sim.particle_count(),
              where.c_str(), loop_s > 0 ? psteps / loop_s : 0.0, sim.time());
  const int sig = g_signal.load();
  if (sig != 0 || sim.steps() < sim.total_steps() || spec.checkpoint_interval > 0) {
    checkpoint(sim);
    std::cout << "wrote checkpoint " << ckpt << " at step " << sim.steps() << " (t = " << sim.time() << " s)\n";
  }
  if (table) table->close();
  if (log) log->close();
  monitors.close();
  if (population) population->close();
  if (log) std::cout << "wrote " << (fs::path(out_dir) / "log.dat").string() << "\n";
  for (const auto& m : spec.monitors) std::cout << "wrote " << (fs::path(out_dir) / cdm::monitor_file(m)).string() << "\n";
  if (spec.output_particles) std::cout << "wrote " << (fs::path(out_dir) / "particles.dat").string() << "\n";
  if (population) std::cout << "wrote " << (fs::path(out_dir) / "outlets.dat").string() << "\n";
  if (spec.output_vtk)
    std::cout << "wrote " << (fs::path(out_dir) / "particles.pvd").string()
              << (sim.gas() ? " and " + (fs::path(out_dir) / "gas.pvd").string() : std::string()) << " (VTK)\n";
  if (sig != 0) {
    if (writes) {  // once, from the process that wrote the checkpoint
      std::cerr << "cdm run: stopped by signal " << sig << "; continue with: cdm run " << shell_quote(scene);
      for (const auto& s : sets) std::cerr << " --set " << shell_quote(s);
      std::cerr << " --restart " << shell_quote(ckpt) << " -o " << shell_quote(out_dir) << "\n";
    }
    return 128 + sig;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cdm: CFD-DEM solver for gas-solid flows, verification first"};
  app.set_version_flag("--version", std::string("cdm ") + CDM_VERSION + " (commit " + CDM_GIT_COMMIT + ")" +
                                        (cdm::built_with_mpi() ? "" : ", built without MPI and hypre"));
  app.require_subcommand(1);

  std::string scene, out_dir = "cdm-out";
  std::vector<std::string> sets;
  auto* run = app.add_subcommand("run", "Run a scene and write its time series as plain tables");
  run->add_option("scene", scene, "scene file (TOML)")->required();
  run->add_option("-o,--out", out_dir, "output directory")->capture_default_str();
  run->add_option("--set", sets, "override a scene value before validation: path=value (TOML syntax, scene units)");
  std::string restart;
  long long max_steps = 0;
  bool quiet = false;
  run->add_option("--restart", restart, "continue from a checkpoint written by a run of the same scene and overrides");
  run->add_option("--max-steps", max_steps, "stop after this many steps, N >= 1 (writing a checkpoint to continue from)")
      ->check(CLI::Validator(
          [](std::string& v) {
            return v.find_first_not_of("0123456789") == std::string::npos && v.find_first_not_of('0') != std::string::npos
                       ? std::string()
                       : "expected a whole number of steps >= 1, got '" + v + "'";
          },
          "N >= 1"));
  run->add_flag("-q,--quiet", quiet, "no progress display");
  int threads = 0;
  run->add_option("-j,--threads", threads,
                  "OpenMP threads (default: OMP_NUM_THREADS or all cores); results are bit-identical for any count")
      ->check(CLI::Range(1, 1024));

  std::vector<std::string> only;
  const fs::path data = data_dir();
  std::string cases_dir = (data / "verification" / "cases").string(), verify_out = "verification-out";
  auto* verify = app.add_subcommand("verify", "Run verification cases against their oracles and write error tables");
  verify->add_option("cases", only, "case names (default: all)");
  verify->add_option("--cases", cases_dir, "folder holding one folder per case")->capture_default_str();
  verify->add_option("-o,--out", verify_out, "output directory for tables")->capture_default_str();
  int verify_jobs = 0;
  verify->add_option("-j,--jobs", verify_jobs,
                     "cases run at once, each in its own process on its share of the cores (default: the cores; 1: "
                     "one after the other, for wall times on an otherwise idle machine)")
      ->check(CLI::Range(1, 1024));
  bool sweep = false;
  verify->add_flag("--sweep", sweep,
                   "run each case over the dense dt sweep (t_col/12.5 ... /1600) and write work-precision tables");

  std::string report_in = "verification-out", report_out = "report";
  auto* report = app.add_subcommand("report", "Build the HTML verification report from the tables of cdm verify");
  report->add_option("--in", report_in, "folder written by cdm verify (and cdm verify --sweep)")->capture_default_str();
  report->add_option("-o,--out", report_out, "report folder")->capture_default_str();
  std::string report_script = (data / "reports" / "make_report.py").string();
  report->add_option("--report-script", report_script, "the script that draws the report")->capture_default_str();

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }

  try {
    if (threads > 0) omp_set_num_threads(threads);
    // Started by mpirun/srun with several processes, each would run the whole problem
    // and write the same files: refused until the distributed run exists.
    if (*run || *verify) g_world = cdm::mpi_world();
    if (*run && g_world.size > 1 && !cdm::built_with_mpi()) {
      if (g_world.rank == 0)
        std::cerr << ("cdm: error: started on " + std::to_string(g_world.size) +
                      " MPI processes, but this cdm was built without MPI (CDM_WITH_MPI off), so each would run the "
                      "whole scene and write the same files. Expected mpirun -np 1 or no launcher, or a build with "
                      "MPI; nothing was written\n");
      return 2;
    }
    if (*verify && g_world.size > 1) {
      // One write: the launcher forwards output in chunks and would cut a message written
      // in pieces with its own lines.
      if (g_world.rank == 0)
        std::cerr << ("cdm: error: cdm verify was started on " + std::to_string(g_world.size) +
                      " MPI processes; it runs each case on one process (its threads: -j N). Expected mpirun -np "
                      "1 or no launcher; nothing was written\n");
      return 2;
    }
    if (*run && g_world.size > 1 && g_world.rank != 0) {
      // Rank 0 writes to the terminal (and the files: run_scene).
      if (!std::freopen("/dev/null", "w", stdout))
        throw std::runtime_error("cannot silence the output of rank " + std::to_string(g_world.rank));
    }
    if (*run) return run_scene(scene, out_dir, sets, restart, static_cast<std::uint64_t>(max_steps), quiet);
    if (*report) {
      // The report is built from the tables alone, by reports/make_report.py with
      // Debian's python3-matplotlib (the interpreter on PATH may not see it).
      const std::string py = "/usr/bin/python3", script = report_script;
      if (!fs::exists(py) || !fs::exists(script)) {
        std::cerr << "cdm report: needs " << py << " with python3-matplotlib (scripts/install-deps.sh installs it) and "
                  << script << "\n";
        return 1;
      }
      const std::string cmd = "'" + py + "' '" + script + "' --in '" + report_in + "' --out '" + report_out + "'";
      const int rc = std::system(cmd.c_str());
      return rc == 0 ? 0 : 1;
    }
    if (*verify) {
      cdm::verification::VerifyOptions vo;
      vo.cases_dir = cases_dir;
      vo.out_dir = verify_out;
      vo.only = only;
      vo.sweep = sweep;
      // Cases in processes of their own are forked, which must come before MPI starts:
      // under a launcher (MPI started already), one after the other.
      vo.jobs = cdm::mpi_started_by_library() ? 1 : verify_jobs > 0 ? verify_jobs : omp_get_num_procs();
      vo.provenance = provenance();
      return cdm::verification::verify(vo);
    }
  } catch (const cdm::SceneError& e) {
    return fail(2, "cdm: error: ", e);
  } catch (const cdm::CheckpointError& e) {
    return fail(2, "cdm: error: ", e);
  } catch (const cdm::OutputError& e) {
    return fail(4, "cdm: output error: ", e);
  } catch (const cdm::SimulationError& e) {
    return fail(3, "cdm: the run went unstable and was stopped: ", e);
  } catch (const std::exception& e) {
    return fail(1, "cdm: error: ", e);
  }
  return 0;
}
