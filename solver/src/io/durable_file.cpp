#include "cdm/solver/io/durable_file.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <sys/stat.h>
#include <unistd.h>

namespace cdm {

namespace fs = std::filesystem;

void throw_output_error(const std::string& path, const std::string& what, int err) {
  throw OutputError("cannot " + what + " '" + path + "': " + std::strerror(err));
}

void sync_file(std::FILE* f, const std::string& path) {
  if (std::fflush(f) != 0 || std::ferror(f)) throw_output_error(path, "write", errno);
  if (::fsync(fileno(f)) != 0 && errno != EINVAL && errno != EROFS)  // a device or pipe cannot be synced
    throw_output_error(path, "fsync", errno);
}

void close_file(std::FILE* f, const std::string& path) {
  const bool written = std::fflush(f) == 0 && !std::ferror(f);
  const int err = errno;
  if (std::fclose(f) != 0 && written) throw_output_error(path, "close", errno);
  if (!written) throw_output_error(path, "write", err);
}

void sync_directory(const std::string& dir) {
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (fd < 0) throw_output_error(dir, "open the directory", errno);
  const int rc = ::fsync(fd), err = errno;
  ::close(fd);
  if (rc != 0 && err != EINVAL && err != EROFS) throw_output_error(dir, "fsync the directory", err);
}

long long regular_file_size(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return -1;
  return static_cast<long long>(st.st_size);
}

void truncate_file(const std::string& path, std::uint64_t bytes) {
  if (::truncate(path.c_str(), static_cast<off_t>(bytes)) != 0) throw_output_error(path, "cut back", errno);
}

void make_output_directory(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw OutputError("cannot create the output directory '" + dir + "': " + ec.message());
  if (!fs::is_directory(dir, ec)) throw OutputError("cannot use '" + dir + "' as the output directory: it is not a directory");
}

AtomicFile::AtomicFile(std::string path) : path_(std::move(path)), tmp_(path_ + ".tmp") {
  f_ = std::fopen(tmp_.c_str(), "w");
  if (!f_) throw_output_error(tmp_, "open for writing", errno);
}

AtomicFile::~AtomicFile() {
  if (!f_) return;
  std::fclose(f_);
  std::remove(tmp_.c_str());
}

void AtomicFile::commit() {
  sync_file(f_, tmp_);
  std::FILE* f = f_;
  f_ = nullptr;
  try {
    close_file(f, tmp_);
  } catch (const OutputError&) {
    std::remove(tmp_.c_str());
    throw;
  }
  if (std::rename(tmp_.c_str(), path_.c_str()) != 0) {
    const int err = errno;
    std::remove(tmp_.c_str());
    throw_output_error(path_, "rename '" + tmp_ + "' onto", err);
  }
}

}  // namespace cdm
