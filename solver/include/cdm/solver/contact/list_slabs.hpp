#pragma once
/// @file list_slabs.hpp
/// @brief How a Verlet-list build cuts the particles into slabs (verlet_list.hpp), and
/// what the processes that share a build exchange (SearchShare).
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace cdm {

/// How the particles' bounding box is cut into slabs (see verlet_list.hpp's file comment).
struct ListSlabs {
  int axis = 0;          // the cut axis (0 when nothing is cut)
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};  // bounding box of the centres [m]
  double range = 0.0;    // interaction range 2 r_max + skin [m]
  std::size_t count = 1; // slabs
  double width = 1.0;    // slab width along axis [m]
  bool wrap = false;     // along a periodic axis: the last slab's next is the first
};

/// What a cut is made from: the particles' centres' bounding box and largest radius. Of
/// several sets of particles, the extent of all of them is join()ed from theirs, to the
/// bit (minima and maxima).
struct SlabExtent {
  static constexpr double inf = std::numeric_limits<double>::infinity();
  double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};  // [m]; none: lo > hi
  double rmax = 0.0;                                           // [m]
  void join(const SlabExtent& o) {
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(lo[a], o.lo[a]);
      hi[a] = std::max(hi[a], o.hi[a]);
    }
    rmax = std::max(rmax, o.rmax);
  }
  bool empty() const { return lo[0] > hi[0]; }
};

/// Each particle's slab as a build cuts them (from the positions it lists).
struct SlabOf {
  const double* c;  // the positions along the cut axis [m]
  double lo, width;
  std::size_t count;
  bool wrap;  // the slabs wrap around a periodic axis (ListSlabs::wrap)
  std::uint32_t operator()(std::uint32_t i) const {
    return count == 1 ? 0 : static_cast<std::uint32_t>(std::min(count - 1, static_cast<std::size_t>((c[i] - lo) / width)));
  }
  /// The slab a pair of particles in slabs @p a and @p b belongs to: the lower, or the
  /// last across the periodic faces.
  std::uint32_t pair(std::uint32_t a, std::uint32_t b) const {
    return wrap && (a == 0 || b == 0) && std::max(a, b) + 1 == count ? std::max(a, b) : std::min(a, b);
  }
  std::uint32_t of_pair(std::uint32_t i, std::uint32_t j) const { return pair((*this)(i), (*this)(j)); }
};

/// A particle's place among its slab's particles in the order a build lists them
/// (VerletList::key_order): its cells (edge one interaction range, 17 bits an axis, a
/// wider box only coarsening the order; the cut axis most significant, then the other
/// two), then its identity, which makes the order total and independent of the slots.
struct SlabKey {
  std::uint64_t cells;
  std::uint32_t id, slot;
  static bool less(const SlabKey& a, const SlabKey& b) { return a.cells != b.cells ? a.cells < b.cells : a.id < b.id; }
  /// The cells of the particle at (@p at[0][i], @p at[1][i], @p at[2][i]) in cut @p g.
  static std::uint64_t cells_of(const ListSlabs& g, const double* const at[3], std::size_t i) {
    const double h = g.range > 0.0 ? g.range : 1.0;
    constexpr double cmax = double((1 << 17) - 1);
    std::uint64_t c3 = 0;
    for (int k = 0; k < 3; ++k) {
      const int a = (g.axis + k) % 3;
      const double c = std::clamp(std::floor((at[a][i] - g.lo[a]) / h), 0.0, cmax);
      c3 = (c3 << 17) | static_cast<std::uint64_t>(c);
    }
    return c3;
  }
};

/// The slabs one of several processes sharing a build searches: the rows of slabs
/// [s0, s1), a run of whole slabs about its share of the particles, the runs in process
/// order; and, ranked and searched as their partners, the particles of slabs [a, b) (the
/// rows' and the slab either side), and where the slabs wrap and the run starts at slab 0,
/// of the last slab too (last).
struct SearchSlabs {
  std::size_t s0 = 0, s1 = 0, a = 0, b = 0;
  bool last = false;
  /// Process @p r's of @p size, from @p count (the particles before each slab, nslab + 1
  /// running counts) and whether the slabs @p wrap.
  static SearchSlabs of(const std::vector<std::uint32_t>& count, std::size_t r, std::size_t size, bool wrap) {
    const std::size_t nslab = count.size() - 1, n = count.back();
    auto first_of = [&](std::size_t q) {
      if (q >= size) return nslab;
      return static_cast<std::size_t>(std::lower_bound(count.begin(), count.end() - 1, n * q / size) - count.begin());
    };
    SearchSlabs s;
    s.s0 = first_of(r);
    s.s1 = std::max(s.s0, first_of(r + 1));
    s.a = s.s0 > 0 ? s.s0 - 1 : 0;
    s.b = std::min(nslab, s.s1 + 1);
    s.last = wrap && s.s0 == 0 && s.s1 > 0 && s.b < nslab;
    return s;
  }
  /// Whether the particles of slab @p s are searched (of @p nslab).
  bool reads(std::size_t s, std::size_t nslab) const { return (s >= a && s < b) || (last && s + 1 == nslab); }
};

/// The first slab of each of @p size processes, and the slab count after them: runs of
/// slabs whose largest load is as small as it can be, a run's load being its slabs' cost
/// (@p cost: running sums from 0, one more entry than slabs) plus the @p work (its pairs'
/// estimated cost) of the slab below it, its shadow slab: none below slab 0, or where
/// the slabs @p wrap the last one unless the run holds every slab.
std::vector<std::uint32_t> deal_slabs(const std::vector<std::uint64_t>& cost, const std::vector<std::uint64_t>& work,
                                      std::size_t size, bool wrap);

/// Processes that share the contact search and the list (RankSplit). At a build each
/// lists the rows of a run of whole slabs, about its share of the particles, in the
/// order of their keys (VerletList::key_order); the slabs are dealt out in contiguous
/// runs, one per process, from the slabs' particles and pairs summed over the processes;
/// and each pair goes to the process whose slab holds it, and to the one above when its
/// slab is that process's shadow slab. Each process then holds the pairs of its slabs and
/// of its shadow slab only, in the one-process order.
class SearchShare {
 public:
  virtual int share_rank() const = 0;
  virtual int share_size() const = 0;
  /// Every process gets the sums of @p v over the processes.
  virtual void sum(std::vector<std::uint64_t>& v) = 0;
  /// Sends out[r] to process r and returns what the processes sent here, in process
  /// order; @p out is released.
  virtual std::vector<std::uint32_t> swap_values(std::vector<std::vector<std::uint32_t>>& out) = 0;
  virtual std::vector<double> swap_values(std::vector<std::vector<double>>& out) = 0;
  /// 1 where a slot holds this process's own particle (once the slabs are dealt out),
  /// else nullptr: every process then holds every particle.
  virtual const std::uint8_t* own_slots() const { return nullptr; }

 protected:
  ~SearchShare() = default;
};

}  // namespace cdm
