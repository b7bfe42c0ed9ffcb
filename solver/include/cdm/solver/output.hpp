#pragma once
/// @file output.hpp
/// @brief Plain whitespace-separated tables: a '#' header naming each column with its
/// unit, then full-precision rows (%.16e).
#include <cstdio>
#include <string>
#include <vector>

namespace cdm {

class TableWriter {
 public:
  /// Opens @p path for writing; throws std::runtime_error if it cannot. An empty path
  /// makes a writer that discards its rows.
  TableWriter(const std::string& path, const std::vector<std::string>& columns,
              const std::vector<std::string>& comments = {}, bool append = false);
  ~TableWriter();
  TableWriter(const TableWriter&) = delete;
  TableWriter& operator=(const TableWriter&) = delete;
  void row(const std::vector<double>& values);
  void flush();

 private:
  std::FILE* f_ = nullptr;
  std::size_t ncol_;
  std::string path_;
};

class Simulation;

/// The output sample that the current step of @p sim belongs to: k for the first step
/// whose time reaches k·interval; the step count when the interval is not longer than dt
/// (every step is a sample), so the index never exceeds the step count.
long long output_sample(const Simulation& sim, double interval);

/// Writes every particle's state at the scene's output interval: one row per particle
/// per sample (t id x y z vx vy vz [wx wy wz]). A sample is taken at the first step
/// whose time reaches each multiple k·interval, and at the last step. After a restart
/// the rows continue the table the first run wrote (appended, same grid), so a
/// restarted run's table equals an uninterrupted run's.
class ParticleTableObserver {
 public:
  ParticleTableObserver(const std::string& path, const Simulation& sim);
  void operator()(const Simulation& sim);

 private:
  TableWriter table_;
  double interval_;
  long long last_ = -1;
  bool rot_;
};

}  // namespace cdm
