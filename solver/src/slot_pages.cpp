#include "cdm/solver/slot_pages.hpp"

#include "cdm/solver/archive.hpp"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <utility>

#include <sys/mman.h>

namespace cdm {

namespace {

std::uintptr_t page_size() {
  static const std::uintptr_t size = [] {
    const long s = sysconf(_SC_PAGESIZE);
    return s > 0 ? static_cast<std::uintptr_t>(s) : std::uintptr_t{4096};
  }();
  return size;
}

// The whole pages inside [first, last), as [begin, end) addresses (begin >= end if none).
std::pair<std::uintptr_t, std::uintptr_t> whole_pages(const void* first, const void* last) {
  const std::uintptr_t page = page_size();
  const auto a = reinterpret_cast<std::uintptr_t>(first), b = reinterpret_cast<std::uintptr_t>(last);
  return {(a + page - 1) / page * page, b / page * page};
}

void clear_range(double* first, double* last) {
  for (double* d = first; d < last; ++d)
    if (std::bit_cast<std::uint64_t>(*d) != 0) *d = 0.0;
}

void clear_range(unsigned char* first, unsigned char* last) {
  for (unsigned char* d = first; d < last; ++d)
    if (*d != 0) *d = 0;
}

}  // namespace

SlotRuns merged(SlotRuns runs) {
  std::sort(runs.begin(), runs.end());
  SlotRuns out;
  for (const auto& r : runs) {
    if (!out.empty() && r.first <= out.back().second) out.back().second = std::max(out.back().second, r.second);
    else out.push_back(r);
  }
  return out;
}

void zero_slots(std::vector<double>& v, const SlotRuns& runs) {
  for (const auto& [i0, i1] : runs) {
    double* first = v.data() + i0;
    double* last = v.data() + std::min(i1, v.size());
    if (first < last) zero_bytes(first, last);
  }
}

void zero_bytes(void* first, void* last) {
  auto* const a = static_cast<unsigned char*>(first);
  auto* const b = static_cast<unsigned char*>(last);
  if (a >= b) return;
  const auto [pa, pb] = whole_pages(a, b);
  // Only whole pages go back; a page that also holds bytes outside the range keeps them.
  if (pa < pb && madvise(reinterpret_cast<void*>(pa), pb - pa, MADV_DONTNEED) == 0) {
    clear_range(a, reinterpret_cast<unsigned char*>(pa));
    clear_range(reinterpret_cast<unsigned char*>(pb), b);
  } else {
    clear_range(a, b);
  }
}

void release_pages(const void* first, const void* last) {
  const auto [pa, pb] = whole_pages(first, last);
  if (pa < pb) madvise(reinterpret_cast<void*>(pa), pb - pa, MADV_DONTNEED);
}

void zero_all(std::vector<double>& v) { zero_slots(v, {{0, v.size()}}); }

void assign_zeroed(std::vector<double>& v, std::size_t n) {
  std::vector<double>().swap(v);
  resize_zeroed(v, n);
}

void reserve_zeroed(std::vector<double>& v, std::size_t capacity) {
  if (capacity <= v.capacity()) return;
  std::vector<double> w;
  w.reserve(capacity);
  w.resize(v.size());
  zero_all(w);
  const std::size_t n = v.size();
  for (std::size_t i = 0; i < n; ++i)
    if (std::bit_cast<std::uint64_t>(v[i]) != 0) w[i] = v[i];
  v.swap(w);
}

void resize_zeroed(std::vector<double>& v, std::size_t n) {
  const std::size_t m = v.size();
  if (m == n) return;
  if (n > v.capacity()) reserve_zeroed(v, std::max(n, 2 * v.capacity()));
  v.resize(n);
  if (n > m) zero_slots(v, {{m, n}});
}

void clear_nonzero(std::vector<double>& v) { clear_range(v.data(), v.data() + v.size()); }

void copy_changed(std::vector<double>& v, const std::vector<double>& from) {
  const std::size_t n = from.size();
  if (v.size() > n) v.resize(n);
  else resize_zeroed(v, n);
  for (std::size_t i = 0; i < n; ++i)
    if (std::bit_cast<std::uint64_t>(v[i]) != std::bit_cast<std::uint64_t>(from[i])) v[i] = from[i];
}

void get_slots(InArchive& a, std::vector<double>& v, std::uint64_t max_elements) {
  const InArchive::SlotWindow& w = a.slot_window();
  const std::uint64_t n = a.get_length(max_elements, sizeof(double));
  if (!w.set || n != w.n) {
    v.resize(n);
    a.get_values(v.data(), n);
    return;
  }
  const auto count = static_cast<std::size_t>(n);
  if (v.size() == count) {
    zero_slots(v, {{0, w.first}, {w.last, count}});
  } else {
    assign_zeroed(v, count);
  }
  a.skip(std::uint64_t{w.first} * sizeof(double));
  a.get_values(v.data() + w.first, w.last - w.first);
  a.skip(std::uint64_t{count - w.last} * sizeof(double));
}

}  // namespace cdm
