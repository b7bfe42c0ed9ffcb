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

}  // namespace cdm
