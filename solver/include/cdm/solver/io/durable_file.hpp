#pragma once
/// @file durable_file.hpp
/// @brief What every output file of a run goes through: failures that name the path and
/// the system's reason, and the flushes, fsyncs and cuts that let a checkpoint say where
/// each output file stood.
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace cdm {

/// An output file or directory could not be written (`cdm run` exits with status 4).
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// OutputError "cannot WHAT 'PATH': <strerror(err)>".
[[noreturn]] void throw_output_error(const std::string& path, const std::string& what, int err);

/// Flush @p f's buffer and fsync its file; throws OutputError naming @p path.
void sync_file(std::FILE* f, const std::string& path);

/// Flush and close @p f, checked: throws OutputError naming @p path (the file is closed
/// either way).
void close_file(std::FILE* f, const std::string& path);

/// fsync the directory @p dir, so that files created or renamed in it survive a crash.
void sync_directory(const std::string& dir);

/// The size of the regular file @p path in bytes; -1 if there is none at @p path
/// (nothing, or a directory, a device, ...).
long long regular_file_size(const std::string& path);

/// Cut the file @p path back to its first @p bytes bytes.
void truncate_file(const std::string& path, std::uint64_t bytes);

/// Create the directory @p dir (and its parents) unless it exists; throws OutputError
/// when it cannot or when @p dir exists and is not a directory.
void make_output_directory(const std::string& dir);

/// A file written to PATH.tmp, flushed, fsync'ed and renamed onto PATH by commit(), so a
/// reader (or a restart after a crash) never sees half a file. Every failure throws
/// OutputError; a file not committed is removed.
class AtomicFile {
 public:
  explicit AtomicFile(std::string path);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  std::FILE* get() { return f_; }
  const std::string& temp_path() const { return tmp_; }
  void commit();

 private:
  std::string path_, tmp_;
  std::FILE* f_ = nullptr;
};

}  // namespace cdm
