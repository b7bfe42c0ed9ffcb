#pragma once
/// @file own_particles.hpp
/// @brief Loops over the particles a rank moves and evaluates: all of them, or among MPI
/// ranks this rank's own (rank_split.hpp), the threads splitting each run.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>

#include "cdm/solver/parallel.hpp"
#include "cdm/solver/rank_split.hpp"

namespace cdm {

/// The smallest and largest of @p v over this rank's own particles of @p n (lo > hi for
/// none), and whether every one is finite.
struct OwnExtent {
  double lo, hi;
  bool finite;
};
inline OwnExtent own_extent(RankSplit& ranks, std::size_t n, const double* v) {
  OwnExtent e{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(), true};
  for (const auto& [i0, i1] : ranks.own_runs(n))
    for (std::size_t i = i0; i < i1; ++i) {
      e.finite = e.finite && std::isfinite(v[i]);
      e.lo = std::min(e.lo, v[i]);
      e.hi = std::max(e.hi, v[i]);
    }
  return e;
}

/// @p f(i) for each particle of @p n this rank moves (every one when @p ranks is nullptr).
template <class F>
void for_own(RankSplit* ranks, std::size_t n, F&& f) {
  if (!ranks) {
    parallel_for(n, f);
    return;
  }
  // Not structured bindings: clang (the fuzz build) cannot capture one in a lambda.
  for (const auto& run : ranks->own_runs(n)) {
    const std::size_t i0 = run.first, i1 = run.second;
    parallel_for(i1 - i0, [&](std::size_t k) { f(i0 + k); });
  }
}

/// @p f(i) for each particle of @p n this rank moves, in slot order on the calling thread.
template <class F>
void for_own_in_order(RankSplit* ranks, std::size_t n, F&& f) {
  if (!ranks) {
    for (std::size_t i = 0; i < n; ++i) f(i);
    return;
  }
  for (const auto& run : ranks->own_runs(n))
    for (std::size_t i = run.first; i < run.second; ++i) f(i);
}

/// @p f(first, last) over thread ranges of the particles this rank moves.
template <class F>
void for_own_ranges(RankSplit* ranks, std::size_t n, F&& f) {
  auto run = [&](std::size_t r0, std::size_t r1) {
    parallel_max_ranges(r1 - r0, [&](std::size_t i0, std::size_t i1) {
      f(r0 + i0, r0 + i1);
      return 0.0;
    });
  };
  if (!ranks) {
    run(0, n);
    return;
  }
  for (const auto& [i0, i1] : ranks->own_runs(n)) run(i0, i1);
}

/// The largest @p f(i) over the particles this rank moves (not over the ranks).
template <class F>
double max_local(RankSplit* ranks, std::size_t n, F&& f) {
  if (!ranks) return parallel_max(n, f);
  double worst = 0.0;
  for (const auto& run : ranks->own_runs(n)) {
    const std::size_t i0 = run.first, i1 = run.second;
    worst = std::max(worst, parallel_max(i1 - i0, [&](std::size_t k) { return f(i0 + k); }));
  }
  return worst;
}

/// The largest @p f(i) over the particles this rank moves, and then over the ranks.
template <class F>
double max_own(RankSplit* ranks, std::size_t n, F&& f) {
  const double worst = max_local(ranks, n, f);
  return ranks ? ranks->max(worst) : worst;
}

}  // namespace cdm
