#pragma once
/// @file archive.hpp
/// @brief Byte archive for checkpoints: plain values and vectors of plain values,
/// written in the machine's byte order (a checkpoint restarts on the machine kind
/// that wrote it). Reading checks every length against what is left, so a truncated
/// or corrupted archive is refused, never half-read.
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
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
  /// The next @p n values, without a length.
  template <class T>
  void put_values(const T* v, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    write(reinterpret_cast<const char*>(v), n * sizeof(T));
  }
  /// A per-particle array: as put(), or through stream_particles()'s function.
  void put_particles(const std::vector<double>& v) {
    if (particles_) particles_(*this, v);
    else put(v);
  }
  /// Where the MPI processes share the particles and the writing process does not hold
  /// them all, @p put writes each per-particle array, gathering it in rounds (every
  /// process's archive takes part; the others' count only).
  void stream_particles(std::function<void(OutArchive&, const std::vector<double>&)> put) {
    particles_ = std::move(put);
  }
  /// Where an array's values lie along the gas's planes (PlaneShare): [0, first) before
  /// plane 0, then @p planes planes of @p plane values each, then the rest.
  struct Planes {
    std::size_t first = 0, plane = 0;
    int planes = 0;
  };
  /// An array of the gas's planes: as put(), or through stream_planes()'s function.
  void put_planes(const std::vector<double>& v, Planes layout) {
    if (planes_) planes_(*this, v, layout);
    else put(v);
  }
  /// Where the MPI processes share the gas's planes, each holding its own current, @p put
  /// writes each array of planes, each process sending its own to the writing process
  /// (every process's archive takes part; the others' count only).
  void stream_planes(std::function<void(OutArchive&, const std::vector<double>&, Planes)> put) {
    planes_ = std::move(put);
  }
  std::uint64_t size() const { return size_; }
  /// Whether the bytes go to a file (else they are counted only).
  bool writes() const { return out_ != nullptr; }
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
  std::function<void(OutArchive&, const std::vector<double>&)> particles_;  // stream_particles
  std::function<void(OutArchive&, const std::vector<double>&, Planes)> planes_;  // stream_planes
  int error_ = 0;
  std::uint64_t size_ = 0;
  std::uint64_t hash_ = fnv1a64_basis;
};

class InArchive {
 public:
  InArchive(const char* data, std::size_t size) : p_(data), end_(data + size) {}
  /// The next @p size bytes of @p in, read as they are asked for (a checkpoint's state
  /// goes from the file into the arrays it restores, never held whole in memory).
  InArchive(std::FILE* in, std::uint64_t size) : in_(in), unread_(size) {}
  InArchive(const InArchive&) = delete;
  InArchive& operator=(const InArchive&) = delete;
  template <class T>
  void get(T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    read(&v, sizeof(T));
  }
  template <class T>
  void get(std::vector<T>& v, std::uint64_t max_elements = UINT64_MAX) {
    const std::uint64_t n = get_length(max_elements, sizeof(T));
    v.resize(n);
    if (n) read(v.data(), n * sizeof(T));  // an empty vector's data() may be null
  }
  /// An array's length, as get() reads it: at most @p max_elements, of elements of
  /// @p element_bytes that fit the data that follows.
  std::uint64_t get_length(std::uint64_t max_elements, std::size_t element_bytes) {
    std::uint64_t n = 0;
    get(n);
    if (n > max_elements || n > remaining() / element_bytes)
      throw ArchiveError("an array's length (" + std::to_string(n) + ") does not fit the data that follows");
    return n;
  }
  /// The next @p n values, into @p to.
  template <class T>
  void get_values(T* to, std::size_t n) {
    static_assert(std::is_trivially_copyable_v<T>);
    if (n) read(to, n * sizeof(T));
  }
  /// Read past the next @p bytes.
  void skip(std::uint64_t bytes) {
    char b[4096];
    while (bytes > 0) {
      const auto k = static_cast<std::size_t>(std::min<std::uint64_t>(bytes, sizeof b));
      read(b, k);
      bytes -= k;
    }
  }
  /// Of the per-particle arrays of @p n values, this process keeps the slots
  /// [@p first, @p last) only (a restart among MPI processes: each reads its share,
  /// get_slots() in slot_pages.hpp).
  struct SlotWindow {
    std::uint64_t n = 0;
    std::size_t first = 0, last = 0;
    bool set = false;
    bool holds(std::size_t i) const { return !set || (i >= first && i < last); }
  };
  void keep_slots(std::uint64_t n, std::size_t first, std::size_t last) { window_ = {n, first, last, true}; }
  const SlotWindow& slot_window() const { return window_; }
  void get(std::string& s) {
    std::vector<char> c;
    get(c);
    s.assign(c.begin(), c.end());
  }
  /// The bytes not read yet.
  std::uint64_t remaining() const { return static_cast<std::uint64_t>(end_ - p_) + unread_; }
  bool done() const { return remaining() == 0; }

 private:
  void read(void* to, std::size_t n) {
    if (remaining() < n) throw ArchiveError("the data ends early");
    char* d = static_cast<char*>(to);
    const std::size_t held = std::min<std::size_t>(n, static_cast<std::size_t>(end_ - p_));
    if (held) std::memcpy(d, p_, held);
    p_ += held;
    d += held;
    n -= held;
    if (n == 0) return;
    // From the file: a large read straight into place, a small one through the buffer.
    if (n >= kBuffer) {
      fill(d, n);
      return;
    }
    const auto k = static_cast<std::size_t>(std::min<std::uint64_t>(kBuffer, unread_));
    buffer_.resize(k);
    fill(buffer_.data(), k);
    p_ = buffer_.data();
    end_ = p_ + k;
    std::memcpy(d, p_, n);
    p_ += n;
  }
  void fill(char* d, std::size_t n) {
    if (std::fread(d, 1, n, in_) != n) throw ArchiveError("reading the file failed");
    unread_ -= n;
  }
  static constexpr std::size_t kBuffer = std::size_t{1} << 16;
  const char* p_ = nullptr;
  const char* end_ = nullptr;
  std::FILE* in_ = nullptr;
  std::uint64_t unread_ = 0;  // bytes of the file not read yet
  std::vector<char> buffer_;
  SlotWindow window_;
};

}  // namespace cdm
