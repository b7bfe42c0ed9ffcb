#pragma once
/// @file neighbour_search.hpp
/// @brief Particle–particle contact detection. CellListSearch is O(N) (cell-linked
/// lists, cell edge = largest diameter + margin); AllPairsSearch is the O(N^2)
/// reference the tests compare it with. Both return pairs i < j sorted by (i, j) (CellListSearch, unless given rows of its own: set_rows).
/// With a PeriodicBox, distances are to the nearest image along its periodic axes
/// (particles must lie inside the box along those axes).
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "cdm/solver/particle_store.hpp"
#include "cdm/solver/periodic_box.hpp"

namespace cdm {

/// The centres [m] and radii [m] of @p n particles that a search lists: a store's own, or
/// the positions a list was built from (VerletList::load_state lists them again).
struct SearchPoints {
  const double *x, *y, *z, *r;
  std::size_t n;
  static SearchPoints of(const ParticleStore& p) { return {p.x.data(), p.y.data(), p.z.data(), p.radius.data(), p.size()}; }
};

/// The centres [m] and radii [m] of @p n particles read in place from an array of records
/// (a scene's particles, which the initial overlap check reads without copying them):
/// each column is its first value and the records' size in bytes.
struct StridedPoints {
  struct Column {
    const char* first;
    std::size_t stride;
    double operator[](std::size_t i) const { return *reinterpret_cast<const double*>(first + i * stride); }
  };
  Column x, y, z, r;
  std::size_t n;
};

struct ContactPair {
  std::uint32_t i, j;
  double overlap;  // r_i + r_j - |X_j - X_i| [m]; >= -margin
};

/// A pair as a Verlet list's build lists it: the particles alone (8 B, not ContactPair's
/// 16), for the build's candidates are its largest transient.
struct ListedPair {
  std::uint32_t i, j;
};

/// Pairs with |X_j - X_i| < r_i + r_j + margin.
class AllPairsSearch {
 public:
  void find_contacts(const ParticleStore& p, double margin, std::vector<ContactPair>& out,
                     const PeriodicBox& box = {}) const;
};

class CellListSearch {
 public:
  /// @return false when the list was cut short: a run of particles stops listing once
  /// its pairs exceed @p limit (so @p out holds more than @p limit pairs, the first rows
  /// of each run), which keeps a degenerate input (thousands of particles piled at one
  /// point) from listing millions of pairs before a check refuses it.
  bool find_contacts(const ParticleStore& p, double margin, std::vector<ContactPair>& out,
                     const PeriodicBox& box = {}, std::size_t limit = SIZE_MAX) {
    return find_contacts(SearchPoints::of(p), margin, out, box, limit);
  }
  bool find_contacts(const SearchPoints& p, double margin, std::vector<ContactPair>& out,
                     const PeriodicBox& box = {}, std::size_t limit = SIZE_MAX);
  bool find_contacts(const StridedPoints& p, double margin, std::vector<ContactPair>& out,
                     const PeriodicBox& box = {}, std::size_t limit = SIZE_MAX);
  /// The same pairs, without their overlaps, in @p chunks, which concatenated in order
  /// are @p out above: above the parallel threshold each thread lists the pairs of its
  /// own run of particles i (thread_range) into a chunk of its own (so the list is built
  /// in parallel and never copied whole). @p expected: about how many pairs to expect in
  /// all (capacity).
  bool find_contacts(const ParticleStore& p, double margin, std::vector<std::vector<ListedPair>>& chunks,
                     const PeriodicBox& box = {}, std::size_t expected = 0, std::size_t limit = SIZE_MAX) {
    return find_contacts(SearchPoints::of(p), margin, chunks, box, expected, limit);
  }
  bool find_contacts(const SearchPoints& p, double margin, std::vector<std::vector<ListedPair>>& chunks,
                     const PeriodicBox& box = {}, std::size_t expected = 0, std::size_t limit = SIZE_MAX);
  /// Rows in an order of their own, for the chunked find_contacts (VerletList): the
  /// particles of @p rows, in order of their ranks (rank[i], every particle's, distinct
  /// among the rows and from every other particle they meet), each listing its pairs
  /// (i, j) with every particle j of a higher rank, in order of rank. The pairs then
  /// come, and are oriented, in an order that does not depend on the particles' slots.
  /// The arrays must outlive the searches; all rows in slot order (i < j) when never set.
  /// @p points: the only particles the rows can meet (the rows among them), the only ones
  /// binned, and the only ones whose ranks are read; every particle when null.
  struct KeyedRows {
    const std::vector<std::uint32_t>* rows = nullptr;
    const std::uint32_t* rank = nullptr;
    const std::vector<std::uint32_t>* points = nullptr;
  };
  void set_rows(const KeyedRows& rows) { keyed_ = rows; }

 private:
  KeyedRows keyed_;  // set_rows
};

}  // namespace cdm
