#pragma once
/// @file archive.hpp
/// @brief Byte archive for checkpoints: plain values and vectors of plain values,
/// written in the machine's byte order (a checkpoint restarts on the machine kind
/// that wrote it). Reading checks every length against what is left, so a truncated
/// or corrupted archive is refused, never half-read.
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace cdm {

class ArchiveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// FNV-1a 64 of p[0..n), continued from @p h: the checkpoints' checksum.
inline constexpr std::uint64_t fnv1a64_basis = 14695981039346656037ull;
inline std::uint64_t fnv1a64(const char* p, std::size_t n, std::uint64_t h = fnv1a64_basis) {
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(p[i]);
    h *= 1099511628211ull;
  }
  return h;
}

/// Writes straight into a file (checkpoints: the state is never held twice in
/// memory), counting the bytes and keeping their checksum; without a file it only
/// counts (to learn a size before writing). A failed write is remembered (failed(),
/// error() is its errno) and the bytes after it are counted only.
class OutArchive {
 public:
  OutArchive() = default;
  explicit OutArchive(std::FILE* out) : out_(out) {}
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    write(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  template <class T>
  void put(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<std::uint64_t>(v.size());
    write(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void put(const std::string& s) {
    put<std::uint64_t>(s.size());
    write(s.data(), s.size());
  }
  std::uint64_t size() const { return size_; }
  /// fnv1a64 of every byte written (a counting archive keeps none).
  std::uint64_t checksum() const { return hash_; }
  bool failed() const { return error_ != 0; }
  int error() const { return error_; }

 private:
  void write(const char* b, std::size_t n) {
    size_ += n;
    if (!out_ || n == 0) return;
    hash_ = fnv1a64(b, n, hash_);
    if (error_ == 0 && std::fwrite(b, 1, n, out_) != n) error_ = errno ? errno : EIO;
  }
  std::FILE* out_ = nullptr;
  int error_ = 0;
  std::uint64_t size_ = 0;
  std::uint64_t hash_ = fnv1a64_basis;
};

class InArchive {
 public:
  InArchive(const char* data, std::size_t size) : p_(data), end_(data + size) {}
  template <class T>
  void get(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T));
    std::memcpy(&v, p_, sizeof(T));
    p_ += sizeof(T);
  }
  template <class T>
  void get(std::vector<T>& v, std::uint64_t max_elements = UINT64_MAX) {
    std::uint64_t n = 0;
    get(n);
    if (n > max_elements || n > static_cast<std::uint64_t>(end_ - p_) / sizeof(T))
      throw ArchiveError("an array's length (" + std::to_string(n) + ") does not fit the data that follows");
    v.resize(n);
    if (n) std::memcpy(v.data(), p_, n * sizeof(T));  // an empty vector's data() may be null
    p_ += n * sizeof(T);
  }
  void get(std::string& s) {
    std::vector<char> c;
    get(c);
    s.assign(c.begin(), c.end());
  }
  bool done() const { return p_ == end_; }

 private:
  void need(std::size_t n) const {
    if (static_cast<std::size_t>(end_ - p_) < n) throw ArchiveError("the data ends early");
  }
  const char* p_;
  const char* end_;
};

}  // namespace cdm
