#pragma once
/// @file parallel.hpp
/// @brief OpenMP loops that cost nothing for small systems: below the threshold the
/// loop runs directly, without entering the OpenMP runtime (a parallel region costs a
/// microsecond even with if(false), which would dominate one-particle runs).
#include <algorithm>
#include <cstddef>

namespace cdm {

inline constexpr std::size_t parallel_threshold = 4096;

/// f(i) for i in [0, n); iterations must be independent.
template <class F>
inline void parallel_for(std::size_t n, F&& f) {
  if (n > parallel_threshold) {
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i) f(i);
  } else {
    for (std::size_t i = 0; i < n; ++i) f(i);
  }
}

/// max over i of f(i) (order-independent, so the same for any thread count).
template <class F>
inline double parallel_max(std::size_t n, F&& f) {
  double m = 0.0;
  if (n > parallel_threshold) {
#pragma omp parallel for schedule(static) reduction(max : m)
    for (std::size_t i = 0; i < n; ++i) m = std::max(m, f(i));
  } else {
    for (std::size_t i = 0; i < n; ++i) m = std::max(m, f(i));
  }
  return m;
}

/// max over blocks [i0, i1) covering [0, n) of f(i0, i1), for loops that want a range
/// of their own (pointers held in locals, flags tested once per block).
template <class F>
inline double parallel_max_blocks(std::size_t n, F&& f) {
  double m = 0.0;
  if (n > parallel_threshold) {
    constexpr std::size_t block = 4096;
    const long nblock = static_cast<long>((n + block - 1) / block);
#pragma omp parallel for schedule(static) reduction(max : m)
    for (long b = 0; b < nblock; ++b) {
      const std::size_t i0 = static_cast<std::size_t>(b) * block;
      m = std::max(m, f(i0, std::min(n, i0 + block)));
    }
  } else {
    m = std::max(m, f(std::size_t{0}, n));
  }
  return m;
}

}  // namespace cdm
