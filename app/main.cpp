/// @file main.cpp
/// @brief The `cdm` command: thin wiring of the solver and the verification harness.
///   cdm run SCENE [-o DIR] [--set path=value ...]
///   cdm verify [CASE ...] [--cases DIR] [--out DIR]
#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "cdm/solver/output.hpp"
#include "cdm/solver/scene_loader.hpp"
#include "cdm/solver/simulation.hpp"
#include "cdm/verification/harness.hpp"

#ifndef CDM_SOURCE_DIR
#define CDM_SOURCE_DIR "."
#endif

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

/// What a reader of the tables needs to reproduce them: commit, compiler, machine.
std::vector<std::pair<std::string, std::string>> provenance() {
  const std::string src = CDM_SOURCE_DIR;
  std::string commit = shell_line("git -C '" + src + "' rev-parse HEAD 2>/dev/null");
  if (shell_line("git -C '" + src + "' status --porcelain --untracked-files=no 2>/dev/null | head -1") != "unknown")
    commit += "+uncommitted";
  return {{"commit", commit},
          {"compiler", CDM_COMPILER},
          {"flags", CDM_CXX_FLAGS},
          {"build_type", CDM_BUILD_TYPE},
          {"date_utc", shell_line("date -u +%Y-%m-%dT%H:%M:%SZ")},
          {"cpu_model", shell_line("grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ *//'")},
          {"cores", shell_line("nproc")},
          {"host", shell_line("uname -srm")}};
}

int run_scene(const std::string& scene, const std::string& out_dir, const std::vector<std::string>& sets) {
  std::vector<cdm::SceneOverride> ov;
  for (const auto& s : sets) ov.push_back(cdm::parse_override(s));
  // Everything is validated before anything is written.
  const cdm::SceneSpec spec = cdm::load_scene(scene, ov);
  cdm::Simulation sim(spec);
  std::cout << "cdm run: " << scene << ": " << sim.particles().size() << " particles, modules:";
  for (const auto& m : sim.module_names()) std::cout << ' ' << m;
  std::cout << "; integrator " << cdm::to_string(spec.integrator) << ", dt = " << spec.dt << " s";
  if (spec.t_col_min > 0) std::cout << " (t_col/" << spec.t_col_min / spec.dt << ")";
  std::cout << ", " << sim.total_steps() << " steps\n";
  fs::create_directories(out_dir);
  if (spec.output_particles) {
    const std::string path = (fs::path(out_dir) / "particles.dat").string();
    cdm::ParticleTableObserver obs(path, sim);
    sim.run([&](const cdm::Simulation& s) { obs(s); });
    std::cout << "wrote " << path << "\n";
  } else {
    sim.run();
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"cdm: CFD-DEM solver for gas-solid flows, verification first"};
  app.require_subcommand(1);

  std::string scene, out_dir = "cdm-out";
  std::vector<std::string> sets;
  auto* run = app.add_subcommand("run", "Run a scene and write its time series as plain tables");
  run->add_option("scene", scene, "scene file (TOML)")->required();
  run->add_option("-o,--out", out_dir, "output directory")->capture_default_str();
  run->add_option("--set", sets, "override a scene value before validation: path=value (TOML syntax, scene units)");

  std::vector<std::string> only;
  std::string cases_dir = std::string(CDM_SOURCE_DIR) + "/verification/cases", verify_out = "verification-out";
  auto* verify = app.add_subcommand("verify", "Run verification cases against their oracles and write error tables");
  verify->add_option("cases", only, "case names (default: all)");
  verify->add_option("--cases", cases_dir, "folder holding one folder per case")->capture_default_str();
  verify->add_option("-o,--out", verify_out, "output directory for tables")->capture_default_str();
  bool sweep = false;
  verify->add_flag("--sweep", sweep,
                   "run each case over the dense dt sweep (t_col/12.5 ... /1600) and write work-precision tables");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }

  try {
    if (*run) return run_scene(scene, out_dir, sets);
    if (*verify) {
      cdm::verification::VerifyOptions vo;
      vo.cases_dir = cases_dir;
      vo.out_dir = verify_out;
      vo.only = only;
      vo.sweep = sweep;
      vo.provenance = provenance();
      return cdm::verification::verify(vo);
    }
  } catch (const cdm::SceneError& e) {
    std::cerr << "cdm: error: " << e.what() << "\n";
    return 2;
  } catch (const cdm::SimulationError& e) {
    std::cerr << "cdm: the run went unstable and was stopped: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "cdm: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
