#pragma once
/// @file archive.hpp
/// @brief Byte archive for checkpoints: plain values and vectors of plain values,
/// written in the machine's byte order (a checkpoint restarts on the machine kind
/// that wrote it). Reading checks every length against what is left, so a truncated
/// or corrupted archive is refused, never half-read.
#include <cstdint>
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

class OutArchive {
 public:
  template <class T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const auto* b = reinterpret_cast<const char*>(&v);
    bytes_.insert(bytes_.end(), b, b + sizeof(T));
  }
  template <class T>
  void put(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<std::uint64_t>(v.size());
    const auto* b = reinterpret_cast<const char*>(v.data());
    bytes_.insert(bytes_.end(), b, b + v.size() * sizeof(T));
  }
  void put(const std::string& s) { put(std::vector<char>(s.begin(), s.end())); }
  const std::vector<char>& bytes() const { return bytes_; }

 private:
  std::vector<char> bytes_;
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
