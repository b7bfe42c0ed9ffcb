#pragma once
/// @file case_processes.hpp
/// @brief Inside the harness: one case's run (harness.cpp) and the pool that runs cases
/// in processes of their own (case_processes.cpp, `cdm verify -j N`).
#include <string>
#include <vector>

#include "cdm/verification/harness.hpp"

namespace cdm::verification {

/// What `cdm verify` reports of one case.
struct Summary {
  std::string name;
  int pass = 0, fail = 0;
  double worst_ratio = 0;
  std::string worst;
  double wall = 0;
};

/// Runs the case in @p dir: its tables under opt.out_dir/<case>, its lines on stdout.
Summary run_case(const std::string& dir, const VerifyOptions& opt);

/// Runs the cases in @p dirs, up to @p jobs at once, each in a forked process on its
/// share of the cores; prints their lines in case order and returns their summaries. A
/// case that cannot run sets @p status to the exit status it gives run in-process (no
/// further case is started; those running are waited for).
std::vector<Summary> run_cases_in_processes(const std::vector<std::string>& dirs, const VerifyOptions& opt, int jobs,
                                            int& status);

}  // namespace cdm::verification
