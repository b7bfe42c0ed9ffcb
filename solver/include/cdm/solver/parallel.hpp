#pragma once
/// @file parallel.hpp
/// @brief OpenMP loops that cost nothing for small systems: below the threshold the
/// loop runs directly, without entering the OpenMP runtime (a parallel region costs a
/// microsecond even with if(false), which would dominate one-particle runs).
#include <algorithm>
#include <cstddef>
#include <utility>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace cdm {

inline constexpr std::size_t parallel_threshold = 4096;

/// The calling thread's number and the team's size (0 and 1 outside a parallel region).
inline std::pair<std::size_t, std::size_t> thread_id() {
#ifdef _OPENMP
  return {static_cast<std::size_t>(omp_get_thread_num()), static_cast<std::size_t>(omp_get_num_threads())};
#else
  return {0, 1};
#endif
}

/// The calling thread's share [i0, i1) of [0, n) split into contiguous, equal ranges
/// over the team (inside a parallel region; the whole of it outside one).
inline std::pair<std::size_t, std::size_t> thread_range(std::size_t n) {
  const auto [t, nt] = thread_id();
  return {n * t / nt, n * (t + 1) / nt};
}

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

/// max over f(i0, i1) for ranges [i0, i1) that cover [0, n): one contiguous range per
/// thread (thread_range), so a thread sweeps the same particles step after step (and
/// those of parallel_for's static schedule, to within a few at each end); the whole
/// range on the calling thread below the threshold.
template <class F>
inline double parallel_max_ranges(std::size_t n, F&& f) {
  double m = 0.0;
  if (n > parallel_threshold) {
#pragma omp parallel reduction(max : m)
    {
      const auto [i0, i1] = thread_range(n);
      if (i0 < i1) m = std::max(m, f(i0, i1));
    }
  } else {
    m = std::max(m, f(std::size_t{0}, n));
  }
  return m;
}

}  // namespace cdm
