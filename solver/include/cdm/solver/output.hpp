#pragma once
/// @file output.hpp
/// @brief Plain whitespace-separated tables: a '#' header naming each column with its
/// unit, then full-precision rows (%.16e; integer columns as integers).
#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cdm/solver/io/durable_file.hpp"

namespace cdm {

class TableWriter {
 public:
  /// Opens @p path for writing and writes the header; with @p resume_at, continues the
  /// table already at @p path instead, cut back to its first *resume_at bytes (the header
  /// is there already). Every failure to open, write, flush or close throws OutputError
  /// naming the path and the system's reason. An empty path makes a writer that
  /// discards its rows.
  TableWriter(const std::string& path, const std::vector<std::string>& columns,
              const std::vector<std::string>& comments = {}, std::optional<std::uint64_t> resume_at = std::nullopt);
  ~TableWriter();
  TableWriter(const TableWriter&) = delete;
  TableWriter& operator=(const TableWriter&) = delete;
  /// Print the columns marked true as integers (their values are whole numbers).
  void set_integer_columns(std::vector<bool> integer) { integer_ = std::move(integer); }
  void row(const std::vector<double>& values);
  /// Whether the rows go to a file (false for an empty path, or once closed).
  bool writes() const { return f_ != nullptr; }
  void flush();
  /// Flush and fsync the rows written so far; returns the table's length in bytes.
  std::uint64_t sync();
  /// Flush and close, checked (the destructor closes without a word).
  void close();

 private:
  std::FILE* f_ = nullptr;
  std::size_t ncol_;
  std::string path_;
  std::vector<bool> integer_;  // columns printed as integers
};

class Simulation;

/// The output sample that the current step of @p sim belongs to: k for the first step
/// whose time reaches k·interval; the step count when the interval is not longer than dt
/// (every step is a sample), so the index never exceeds the step count.
long long output_sample(const Simulation& sim, double interval);

/// Which steps a table samples: the first step whose time reaches each multiple of the
/// interval, and the last step. After a restart the checkpoint's own sample is not
/// taken again (it was written before the checkpoint).
class SampleSchedule {
 public:
  SampleSchedule(const Simulation& sim, double interval);
  /// Whether the current step of @p sim is a sample (and, if so, marks it taken).
  bool due(const Simulation& sim);

 private:
  double interval_;
  long long last_ = -1;
};

/// Where a restarted run continues the table at @p path: the length the checkpoint
/// recorded, or nowhere (a new table) when there is no table there or no length was
/// recorded. A table shorter than recorded is not the one the checkpoint continues: an
/// error.
std::optional<std::uint64_t> table_resume_point(const std::string& path, const Simulation& sim,
                                                std::optional<std::uint64_t> recorded);

/// What the run's tables (particles.dat, log.dat, outlets.dat) share: a TableWriter
/// sampled by a SampleSchedule, continued after a restart from the length the checkpoint
/// recorded (table_resume_point).
class SampledTable {
 public:
  /// Flush and fsync the rows; the table's length in bytes (recorded by a checkpoint).
  std::uint64_t sync() { return table_.sync(); }
  void close() { table_.close(); }

 protected:
  SampledTable(const std::string& path, const Simulation& sim, double interval, const std::vector<std::string>& columns,
               const std::vector<std::string>& comments, std::optional<std::uint64_t> resume_at);
  TableWriter table_;
  SampleSchedule schedule_;
};

/// Writes every particle's state at the scene's output interval: one row per particle
/// per sample (t id x y z vx vy vz [wx wy wz] radius material; id and material, an
/// index into the materials the header names, as integers). A sample is taken at the first step
/// whose time reaches each multiple k·interval, and at the last step. After a restart
/// the rows continue the table the first run wrote: the table is cut back to the
/// length the checkpoint recorded (@p resume_at) and the rows appended, so a restarted
/// run's table equals an uninterrupted run's however the first run ended. A restart
/// without a table at @p path (or without a recorded length) starts a new table, header
/// first, whose rows begin after the checkpoint's time.
class ParticleTableObserver : public SampledTable {
 public:
  ParticleTableObserver(const std::string& path, const Simulation& sim,
                        std::optional<std::uint64_t> resume_at = std::nullopt);
  void operator()(const Simulation& sim);

 private:
  bool rot_;
};

}  // namespace cdm
