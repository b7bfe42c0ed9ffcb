#pragma once
/// @file archive.hpp
/// @brief Byte archive for checkpoints: plain values and vectors of plain values,
/// written in the machine's byte order (a checkpoint restarts on the machine kind
/// that wrote it), under a checksum per block. Reading checks every length against what
/// is left and every block against its checksum before using any of its bytes, so a
/// truncated or corrupted archive is refused, never half-read.
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

/// A block whose bytes do not match their checksum.
class ArchiveCorrupt : public ArchiveError {
 public:
  using ArchiveError::ArchiveError;
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

/// An archive is checked by blocks of this many bytes (the last one shorter), each under
/// its own fnv1a64: a process that reads part of a checkpoint reads and checks the blocks
/// that hold that part, and no others.
inline constexpr std::uint64_t checksum_block = std::uint64_t{1} << 16;

/// The checksums of an archive's blocks, and where the archive lies in its file.
struct BlockSums {
  std::uint64_t at = 0;             ///< the archive's first byte in its file [bytes]
  std::uint64_t bytes = 0;          ///< the archive's length [bytes]
  std::vector<std::uint64_t> sums;  ///< fnv1a64 of each block
  /// How many blocks @p bytes bytes make.
  static std::uint64_t blocks(std::uint64_t bytes) { return (bytes + checksum_block - 1) / checksum_block; }
  /// The length of block @p b (< blocks(bytes)) [bytes].
  std::size_t length(std::uint64_t b) const {
    return static_cast<std::size_t>(std::min(checksum_block, bytes - b * checksum_block));
  }
  /// Throws ArchiveCorrupt unless @p data, block @p b's bytes, match its sum.
  void check(std::uint64_t b, const char* data) const {
    if (b < sums.size() && fnv1a64(data, length(b)) == sums[b]) return;
    const std::uint64_t start = b * checksum_block;
    throw ArchiveCorrupt("block " + std::to_string(b + 1) + " of " + std::to_string(sums.size()) + " (bytes " +
                         std::to_string(start) + " to " + std::to_string(start + length(b)) + " of its data)");
  }
};

/// Writes straight into a file (checkpoints: the state is never held twice in
/// memory), counting the bytes and keeping their blocks' checksums; without a file it
/// only counts (to learn a size before writing). A failed write is remembered (failed(),
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
  /// fnv1a64 of each block of checksum_block bytes written, the last one partial (a
  /// counting archive keeps none).
  std::vector<std::uint64_t> block_sums() const {
    std::vector<std::uint64_t> s = sums_;
    if (out_ && size_ % checksum_block != 0) s.push_back(hash_);
    return s;
  }
  bool failed() const { return error_ != 0; }
  int error() const { return error_; }

 private:
  void write(const char* b, std::size_t n) {
    if (!out_ || n == 0) {
      size_ += n;
      return;
    }
    if (error_ == 0 && std::fwrite(b, 1, n, out_) != n) error_ = errno ? errno : EIO;
    while (n > 0) {
      const auto k = static_cast<std::size_t>(std::min<std::uint64_t>(n, checksum_block - size_ % checksum_block));
      hash_ = fnv1a64(b, k, hash_);
      b += k;
      n -= k;
      size_ += k;
      if (size_ % checksum_block == 0) {
        sums_.push_back(hash_);
        hash_ = fnv1a64_basis;
      }
    }
  }
  std::FILE* out_ = nullptr;
  std::function<void(OutArchive&, const std::vector<double>&)> particles_;  // stream_particles
  std::function<void(OutArchive&, const std::vector<double>&, Planes)> planes_;  // stream_planes
  int error_ = 0;
  std::uint64_t size_ = 0;
  std::uint64_t hash_ = fnv1a64_basis;  // of the block being written
  std::vector<std::uint64_t> sums_;     // of the blocks written whole
};

class InArchive {
 public:
  InArchive(const char* data, std::size_t size) : begin_(data), p_(data), end_(data + size) {}
  /// Bytes [@p from, @p from + @p size) of the archive in @p in that @p sums describes
  /// (kept by the caller while this reads), read as they are asked for: a checkpoint's
  /// state goes from the file into the arrays it restores, never held whole in memory.
  /// Each block is read whole and checked against its sum before any of its bytes is
  /// used (ArchiveCorrupt otherwise); skip() passes over blocks without reading them.
  InArchive(std::FILE* in, const BlockSums& sums, std::uint64_t from, std::uint64_t size)
      : in_(in), sums_(&sums), from_(from), size_(size), next_(from), unread_(size) {
    if (from > sums.bytes || size > sums.bytes - from) throw ArchiveError("the data ends early");
  }
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
  /// Pass over the next @p bytes (from a file, without reading them).
  void skip(std::uint64_t bytes) {
    if (remaining() < bytes) throw ArchiveError("the data ends early");
    const std::size_t held = std::min<std::size_t>(bytes, static_cast<std::size_t>(end_ - p_));
    p_ += held;
    bytes -= held;
    next_ += bytes;
    unread_ -= bytes;
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
  /// Back to the archive's first byte. From a file, the block read last is kept, so what
  /// was read of it is not read again.
  void rewind() {
    if (!in_) {
      p_ = begin_;
      return;
    }
    p_ = end_ = nullptr;
    next_ = from_;
    unread_ = size_;
  }
  /// The bytes not read yet.
  std::uint64_t remaining() const { return static_cast<std::uint64_t>(end_ - p_) + unread_; }
  bool done() const { return remaining() == 0; }

 private:
  void read(void* to, std::size_t n) {
    if (remaining() < n) throw ArchiveError("the data ends early");
    char* d = static_cast<char*>(to);
    while (n > 0) {
      if (p_ == end_) load();
      const std::size_t k = std::min<std::size_t>(n, static_cast<std::size_t>(end_ - p_));
      std::memcpy(d, p_, k);
      p_ += k;
      d += k;
      n -= k;
    }
  }
  /// Makes [p_, end_) the next bytes of the file's block that holds them, reading and
  /// checking the block unless it is the one read last.
  void load() {
    const std::uint64_t b = next_ / checksum_block, start = b * checksum_block;
    const std::size_t length = sums_->length(b);
    if (b != block_) {
      buffer_.resize(length);
      block_ = UINT64_MAX;
      if (fseeko(in_, static_cast<off_t>(sums_->at + start), SEEK_SET) != 0 ||
          std::fread(buffer_.data(), 1, length, in_) != length)
        throw ArchiveError("reading the file failed");
      sums_->check(b, buffer_.data());
      block_ = b;
    }
    const auto k = static_cast<std::size_t>(std::min<std::uint64_t>(start + length - next_, unread_));
    p_ = buffer_.data() + (next_ - start);
    end_ = p_ + k;
    next_ += k;
    unread_ -= k;
  }
  const char* begin_ = nullptr;  // an archive in memory: its first byte
  const char* p_ = nullptr;
  const char* end_ = nullptr;
  std::FILE* in_ = nullptr;
  const BlockSums* sums_ = nullptr;
  std::uint64_t from_ = 0, size_ = 0;   // from a file: the archive's bytes
  std::uint64_t next_ = 0;              // the archive's next byte not in [p_, end_)
  std::uint64_t unread_ = 0;            // bytes from next_ on still to be read or skipped
  std::uint64_t block_ = UINT64_MAX;    // the block in buffer_
  std::vector<char> buffer_;
  SlotWindow window_;
};

}  // namespace cdm
