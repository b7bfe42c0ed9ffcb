#include "cdm/solver/neighbour_search.hpp"

#include "cdm/solver/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace cdm {

namespace {
double radius(const ParticleStore& p, std::uint32_t i) { return p.radius[i]; }
template <class Points>
double radius(const Points& p, std::uint32_t i) {
  return p.r[i];
}

template <bool Periodic, class Points>
inline bool test_pair(const Points& p, std::uint32_t i, std::uint32_t j, double margin, double& overlap,
                      const PeriodicBox& box) {
  double dx = p.x[j] - p.x[i], dy = p.y[j] - p.y[i], dz = p.z[j] - p.z[i];
  if constexpr (Periodic) {
    dx = box.min_image(dx, 0);
    dy = box.min_image(dy, 1);
    dz = box.min_image(dz, 2);
  } else {
    (void)box;
  }
  const double reach = radius(p, i) + radius(p, j) + margin;
  const double d2 = dx * dx + dy * dy + dz * dz;
  if (d2 >= reach * reach) return false;
  overlap = radius(p, i) + radius(p, j) - std::sqrt(d2);
  return true;
}
template <class Pair>
bool by_pair(const Pair& a, const Pair& b) {
  return a.i != b.i ? a.i < b.i : a.j < b.j;
}

template <class Pair, class Points>
bool list_in_chunks(const Points& p, double margin, std::vector<std::vector<Pair>>& chunks,
                    const PeriodicBox& box, std::size_t expected, std::size_t limit,
                    const CellListSearch::KeyedRows& keyed_);

template <class Points>
bool list_flat(const Points& p, double margin, std::vector<ContactPair>& out, const PeriodicBox& box,
               std::size_t limit, const CellListSearch::KeyedRows& keyed) {
  std::vector<std::vector<ContactPair>> chunks;
  const bool whole = list_in_chunks<ContactPair>(p, margin, chunks, box, 0, limit, keyed);
  out.clear();
  if (chunks.size() == 1) {
    out.swap(chunks[0]);
    return whole;
  }
  std::size_t total = 0;
  for (const auto& c : chunks) total += c.size();
  out.reserve(total);
  for (const auto& c : chunks) out.insert(out.end(), c.begin(), c.end());
  return whole;
}
}  // namespace

void AllPairsSearch::find_contacts(const ParticleStore& p, double margin, std::vector<ContactPair>& out,
                                   const PeriodicBox& box) const {
  out.clear();
  const auto n = static_cast<std::uint32_t>(p.size());
  for (std::uint32_t i = 0; i < n; ++i)
    for (std::uint32_t j = i + 1; j < n; ++j) {
      double ov;
      if (box.any() ? test_pair<true>(p, i, j, margin, ov, box) : test_pair<false>(p, i, j, margin, ov, box))
        out.push_back({i, j, ov});
    }
}

bool CellListSearch::find_contacts(const SearchPoints& p, double margin, std::vector<ContactPair>& out,
                                   const PeriodicBox& box, std::size_t limit) {
  return list_flat(p, margin, out, box, limit, keyed_);
}

bool CellListSearch::find_contacts(const StridedPoints& p, double margin, std::vector<ContactPair>& out,
                                   const PeriodicBox& box, std::size_t limit) {
  return list_flat(p, margin, out, box, limit, keyed_);
}

bool CellListSearch::find_contacts(const SearchPoints& p, double margin,
                                   std::vector<std::vector<ListedPair>>& chunks, const PeriodicBox& box,
                                   std::size_t expected, std::size_t limit) {
  return list_in_chunks<ListedPair>(p, margin, chunks, box, expected, limit, keyed_);
}

namespace {

template <class Pair, class Points>
bool list_in_chunks(const Points& p, double margin, std::vector<std::vector<Pair>>& chunks,
                    const PeriodicBox& box, std::size_t expected, std::size_t limit,
                    const CellListSearch::KeyedRows& keyed_) {
  // The particles binned: the rows' possible partners where given (KeyedRows::points),
  // else every particle; point(k) is the k-th one's slot.
  const std::vector<std::uint32_t>* const points = keyed_.rows ? keyed_.points : nullptr;
  const std::size_t n = points ? points->size() : p.n;
  auto point = [points](std::size_t k) -> std::size_t { return points ? (*points)[k] : k; };
  const bool threads = n > parallel_threshold;
  if (!threads) {  // one chunk; with threads, one per thread (sized in the parallel region)
    chunks.resize(1);
    chunks[0].clear();
  }
  if (n < 2) return true;
  double lo[3] = {std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
                  std::numeric_limits<double>::max()};
  double hi[3] = {-lo[0], -lo[1], -lo[2]};
  double rmax = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = point(k);
    const double c[3] = {p.x[i], p.y[i], p.z[i]};
    for (int k = 0; k < 3; ++k) { lo[k] = std::min(lo[k], c[k]); hi[k] = std::max(hi[k], c[k]); }
    rmax = std::max(rmax, p.r[i]);
  }
  // Along a periodic axis the cells tile the period exactly, so the cells at either
  // face are neighbours.
  for (int k = 0; k < 3; ++k)
    if (box.on[k]) { lo[k] = box.lo[k]; hi[k] = box.lo[k] + box.len[k]; }
  // Cell edge >= the largest possible contact distance, so only the 27 neighbouring
  // cells can hold partners. If the box would need more than ~2N cells, the edge grows
  // along the axis with the most cells only: a long, mostly empty periodic axis then
  // gets long cells while the short axes keep theirs (growing all three would pile the
  // particles into a few cells and make the search quadratic).
  const double h0 = 2.0 * rmax + margin;
  double h[3] = {h0, h0, h0};
  long dims[3];
  double w[3];  // cell edge per axis [m]
  for (;;) {
    double cells = 1.0;
    for (int k = 0; k < 3; ++k) {
      if (box.on[k]) {
        dims[k] = std::max(1L, static_cast<long>(box.len[k] / h[k]));
        w[k] = box.len[k] / static_cast<double>(dims[k]);
      } else {
        dims[k] = std::max(1L, static_cast<long>((hi[k] - lo[k]) / h[k]) + 1);
        w[k] = h[k];
      }
      cells *= static_cast<double>(dims[k]);
    }
    if (cells <= 2.0 * static_cast<double>(n) + 27.0) break;
    int k_max = 0;
    for (int k = 1; k < 3; ++k)
      if (dims[k] > dims[k_max]) k_max = k;
    h[k_max] *= 1.5;
  }
  const std::size_t ncell = static_cast<std::size_t>(dims[0] * dims[1] * dims[2]);
  auto coord = [&](double v, int k) {
    return std::min(dims[k] - 1, std::max(0L, static_cast<long>((v - lo[k]) / w[k])));
  };
  // Particles by cell (counting sort). Locals, not kept between searches: a search runs
  // once per list build, and kept arrays would stay resident between builds (about 12 B
  // a particle).
  std::vector<std::uint32_t> cell_start(ncell + 1, 0), sorted(n);
  {
    std::vector<std::uint32_t> cell_of(n);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = point(k);
      const long c = (coord(p.z[i], 2) * dims[1] + coord(p.y[i], 1)) * dims[0] + coord(p.x[i], 0);
      cell_of[k] = static_cast<std::uint32_t>(c);
      ++cell_start[c + 1];
    }
    for (std::size_t c = 0; c < ncell; ++c) cell_start[c + 1] += cell_start[c];
    std::vector<std::uint32_t> fill(cell_start.begin(), cell_start.end() - 1);
    for (std::size_t k = 0; k < n; ++k) sorted[fill[cell_of[k]]++] = static_cast<std::uint32_t>(point(k));
  }
  // The neighbouring cell coordinates along axis k of cell coordinate c: c-1..c+1 cut at
  // the ends, or wrapped along a periodic axis (each cell once when there are < 3).
  auto neighbours = [&](long c, int k, long (&out)[3]) {
    int m = 0;
    for (long d = -1; d <= 1; ++d) {
      long q = c + d;
      if (box.on[k]) q = q < 0 ? q + dims[k] : q >= dims[k] ? q - dims[k] : q;  // c is in [0, dims)
      else if (q < 0 || q >= dims[k]) continue;
      bool seen = false;
      for (int r = 0; r < m; ++r) seen |= out[r] == q;
      if (!seen) out[m++] = q;
    }
    return m;
  };
  const bool periodic = box.any();
  const bool keyed = keyed_.rows != nullptr;
  const std::uint32_t* const rank = keyed_.rank;
  // Whether particle a comes before b: by slot, or by rank.
  auto before = [keyed, rank](std::uint32_t a, std::uint32_t b) { return keyed ? rank[a] < rank[b] : a < b; };
  // Particle i's pairs with every j after it, appended to @p out in order of j.
  auto row = [&](std::size_t i, std::vector<Pair>& out) {
    const std::size_t first = out.size();
    long nx[3], ny[3], nz[3];
    const int mx = neighbours(coord(p.x[i], 0), 0, nx), my = neighbours(coord(p.y[i], 1), 1, ny),
              mz = neighbours(coord(p.z[i], 2), 2, nz);
    for (int a = 0; a < mz; ++a)
      for (int b = 0; b < my; ++b)
        for (int e = 0; e < mx; ++e) {
          const long c = (nz[a] * dims[1] + ny[b]) * dims[0] + nx[e];
          for (std::uint32_t s = cell_start[c]; s < cell_start[c + 1]; ++s) {
            const std::uint32_t j = sorted[s];
            const auto ii = static_cast<std::uint32_t>(i);
            if (j == ii || !before(ii, j)) continue;
            double ov;
            if (!(periodic ? test_pair<true>(p, ii, j, margin, ov, box) : test_pair<false>(p, ii, j, margin, ov, box)))
              continue;
            if constexpr (std::is_same_v<Pair, ContactPair>)
              out.push_back({ii, j, ov});
            else
              out.push_back({ii, j});
          }
        }
    // i's pairs follow those of every row before it, so sorting each row sorts the whole
    // list (a few pairs each, not a sort of them all).
    const auto b = out.begin() + static_cast<std::ptrdiff_t>(first);
    if (!keyed) {
      std::sort(b, out.end(), by_pair<Pair>);
      return;
    }
    std::sort(b, out.end(), [&](const Pair& x, const Pair& y) { return before(x.j, y.j); });
  };
  const std::size_t nrows = keyed ? keyed_.rows->size() : n;
  auto row_at = [&](std::size_t k) -> std::size_t { return keyed ? (*keyed_.rows)[k] : k; };
  if (!threads) {
    chunks[0].reserve(expected);
    for (std::size_t k = 0; k < nrows; ++k) {
      row(row_at(k), chunks[0]);
      if (chunks[0].size() > limit) return false;
    }
    return true;
  }
  bool whole = true;
  // Each thread lists the rows of its own particles (thread_range) into its chunk: the
  // chunks in thread order are the rows in order, whatever the thread count.
#pragma omp parallel
  {
    // Not a structured binding: clang (the fuzz build) cannot name one inside the nested
    // OpenMP construct below.
    const std::pair<std::size_t, std::size_t> tn = thread_id();
    const std::size_t t = tn.first, nt = tn.second;
#pragma omp single
    {
      chunks.resize(nt);
      for (auto& c : chunks) c.clear();
    }
    const auto [k0, k1] = thread_range(nrows);
    chunks[t].reserve(expected / nt + 64);
    for (std::size_t k = k0; k < k1; ++k) {
      row(row_at(k), chunks[t]);
      if (chunks[t].size() > limit) {
#pragma omp atomic write
        whole = false;
        break;
      }
    }
  }
  return whole;
}

}  // namespace

}  // namespace cdm
