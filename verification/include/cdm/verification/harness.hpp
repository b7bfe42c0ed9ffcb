#pragma once
/// @file harness.hpp
/// @brief The verification harness: runs each case's scene across its sweep
/// (variants × integrators × dt), compares the whole time series with the case's
/// oracle, and writes error tables (case variant integrator dt_divisor dt quantity norm
/// error tolerance pass order wall steps) and the series it compared.
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cdm/solver/scene_loader.hpp"

namespace cdm::verification {

/// One sweep variant of a case: overrides applied to the scene (in the scene's units)
/// and the oracle's parameters (SI), written independently of the scene.
struct Variant {
  std::string name;
  std::string scene;  // scene file path: the case's, unless the variant names its own
  std::vector<SceneOverride> set;
  std::map<std::string, double> oracle;  // SI parameters for the oracle
  /// Grid refinement: variants of one family with a cell size h each; the harness
  /// reports the observed order across them (norm suffix "_grid_order").
  std::string family;
  double h = 0.0;  // [m], 0 = not part of a grid study
  bool sweep_only = false;  // run only by `cdm verify --sweep` (an expensive refinement level)
  double param(const std::string& key) const;
};

struct CaseDef {
  std::string name;       // folder name
  std::string dir;        // folder path
  std::string kind;       // which runner (free_fall, stacked, slipping_ball, ...)
  std::string scene;      // scene file path
  std::string title;
  std::vector<std::string> integrators;
  /// What the sweep's divisor N means, for the tables: "dt = t_col/N" (DEM cases), or
  /// e.g. "dt = T/N, T the vortex period" (from case.toml [sweep] divisor).
  std::string divisor_meaning = "dt = t_col/N";
  std::vector<double> dt_divisors;        // the paper's sweep (default run)
  std::vector<double> sweep_dt_divisors;  // the denser sweep of `cdm verify --sweep`
  std::vector<Variant> variants;
  std::map<std::string, std::string> options;
};

/// What one run measured: errors per quantity (unit given by the norm).
struct Measurement {
  std::string quantity;
  std::string norm;   // e.g. max_rel_pct: max over samples of 100|Q_A - Q|/|Q_A| (eq 37)
  double error;
};

struct RunConfig {
  std::string integrator;
  double dt_divisor;
  std::string series_path;  // where the runner writes the compared series
  bool timing_only = false;  // a repeat run for its wall time: skip the oracle and the tables
};

struct RunOutput {
  std::vector<Measurement> measurements;
  double wall_seconds = 0.0;     // solver time only (steady clock), oracle excluded
  std::size_t timing_repeats = 1;  // runs the wall time is the median of
  std::uint64_t steps = 0;
  std::uint64_t particles = 0;
  double dt = 0.0;
  std::string oracle_accuracy;   // what the oracle was computed to
};

using CaseRunner = std::function<RunOutput(const CaseDef&, const Variant&, const RunConfig&)>;

/// Runner per case kind (registry in one place: src/runners/registry.cpp).
const std::map<std::string, CaseRunner>& case_runners();

/// A tolerance from the case's tolerances.toml: first matching entry wins.
struct Tolerance {
  std::string variant = "*", integrator = "*", quantity, norm;
  double dt_divisor = 0.0;        // 0 = any
  double dt_divisor_below = 0.0;  // > 0: only runs coarser than dt = t/this (divisor below it)
  double max = 0.0;         // error must be <= max (for norm "order": slope must be >= max)
  // A tolerance that follows the scheme's known convergence: at dt = t_col/N the bound is
  // max * (ref_divisor / N)^order (order 0: the same bound at every dt).
  double order = 0.0;
  double ref_divisor = 50.0;
  bool report_only = false;  // reported without pass/fail (the reason says why)
  bool at_least = false;     // `min`: the quantity must be >= max (e.g. a clustering that must appear)
  double at(double divisor) const { return order == 0.0 ? max : max * std::pow(ref_divisor / divisor, order); }
  std::string reason;
};

CaseDef load_case(const std::string& dir);
std::vector<Tolerance> load_tolerances(const std::string& case_dir);

struct VerifyOptions {
  std::string cases_dir;
  std::string out_dir;
  std::vector<std::string> only;  // case names; empty = all
  double min_timing_seconds = 0.2;  // repeat a run until this much solver time is timed
  /// Cases run at once, each in its own process on cores/jobs threads (1: one after the
  /// other in this process).
  int jobs = 1;
  bool sweep = false;  // run sweep_dt_divisors and write work-precision tables
  /// Written to provenance.dat beside the tables (commit, compiler, flags, machine...).
  std::vector<std::pair<std::string, std::string>> provenance;
};

/// Runs the cases, writes tables, prints a summary; returns 0 if all pass, 1 otherwise.
int verify(const VerifyOptions& opt);

/// Least-squares slope of log(err) against log(dt): the observed order of convergence.
std::optional<double> observed_order(const std::vector<double>& dt, const std::vector<double>& err);

}  // namespace cdm::verification
