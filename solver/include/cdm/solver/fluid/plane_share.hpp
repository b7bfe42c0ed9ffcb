#pragma once
/// @file plane_share.hpp
/// @brief The gas step's loops divided among MPI processes by planes.
///
/// Under mpirun every process holds the whole gas (rank_split.hpp) and steps it alike.
/// The gas step's loops over faces and cells are divided by planes of the padded
/// arrays' slowest index (k): of an array's n stored planes, process r of P computes the
/// run [n r / P, n (r + 1) / P), and gather() then gives every process every plane.
/// Each value is computed by the same arithmetic whichever process computes it, so the
/// gas is the same to the bit on any number of processes. With one process (or a build
/// without MPI) a process's planes are all of them and gather() does nothing.
///
/// Dividing costs every gas step its exchanges (the gathers, and the multigrid solve's
/// halo exchanges and reductions on each of its levels), about a millisecond a step on
/// this machine's two cores whatever the grid, and saves the share of the work the other
/// processes take. On a small grid the exchanges cost more than they save, so there every
/// process steps the whole gas alone (the same arithmetic as one process, so the same
/// bits): GasDivision::automatic divides only where every process gets at least
/// min_divided_cells cells of the multigrid solve's planes (bench/README.md, "The gas step
/// divided or whole").
///
/// A process need not read every plane: its own and those next to them for its gas step,
/// and those under its particles. Each process states the run of planes it reads
/// (set_reach, collective), and gather() then sends each process the planes of its run
/// only, each from the process that computed it: a slab of particles over a run of planes
/// receives its run, not the grid. gather_all() sends every plane to every process. The
/// gas field then keeps that run current and no other plane (held(), the grid's window:
/// StaggeredGrid::set_window). Every process still allocates the whole grid's addresses,
/// but the arrays' planes beyond its window are zero, their pages returned to the system
/// (StaggeredGrid::zero_outside_window): a process holds the memory of its reach only.
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include "cdm/solver/archive.hpp"
#include "cdm/solver/fluid/staggered_grid.hpp"
#include "cdm/solver/keywords.hpp"

namespace cdm::fluid {

/// How the processes of an MPI run share the gas step (gas.division).
enum class GasDivision { automatic, planes, whole };
inline constexpr Keywords<GasDivision, 3> gas_division_keywords{
    {{"auto", GasDivision::automatic}, {"planes", GasDivision::planes}, {"whole", GasDivision::whole}}};
inline const char* to_string(GasDivision d) { return keyword_of(gas_division_keywords, d); }

class PlaneShare {
 public:
  /// The fewest cells a process must get for GasDivision::automatic to divide the gas step.
  static constexpr std::size_t min_divided_cells = 2048;
  /// Among the processes of the MPI world (mpi_world()) when @p divided, else this
  /// process alone: it computes every plane, as every other process does.
  explicit PlaneShare(bool divided = true);
  /// Whether @p d divides the gas step on @p g among @p processes processes: planes
  /// does (given more than one), whole does not, automatic does where each process's run
  /// of planes of the multigrid solve's slowest axis (the last) holds min_divided_cells
  /// cells or more.
  static bool divides(GasDivision d, const StaggeredGrid& g, int processes);
  /// The planes [first, last) of @p planes that process @p rank of @p size computes:
  /// contiguous runs by rank (the multigrid pressure solve owns the same).
  static std::pair<int, int> planes_of(int planes, int rank, int size) {
    const auto at = [&](int r) { return static_cast<int>(static_cast<long long>(planes) * r / size); };
    return {at(rank), at(rank + 1)};
  }
  /// This process's planes [first, last) of @p planes.
  std::pair<int, int> mine(int planes) const { return planes_of(planes, rank_, size_); }
  /// Every process gets the planes of [0, @p planes) of @p a in its reach (set_reach),
  /// each from the process that computed it; plane k holds the @p plane values from
  /// @p first + k @p plane.
  void gather(std::vector<double>& a, std::size_t first, std::size_t plane, int planes) const;
  /// gather() of every plane to every process, whatever their reach.
  void gather_all(std::vector<double>& a, std::size_t first, std::size_t plane, int planes) const;
  /// Writes @p a whole into process 0's archive @p out (the one that writes the files) as
  /// OutArchive::put() does, without gathering it: process 0 writes its own planes, then
  /// receives each other process's in rank order, a round at a time, and writes them. What
  /// lies before plane 0 is the first plane's owner's, what lies after the last the last
  /// plane's owner's (the ghost planes their steps fill). Where process 0's reach is every
  /// plane it writes its own copy. Collective.
  void put_to_writer(OutArchive& out, const std::vector<double>& a, OutArchive::Planes layout) const;
  /// The planes of cells [@p lo, @p hi] this process reads: gather() gives it plane k of
  /// an array of n planes for k in [lo, hi + 1] (a staggered array's upper face), besides
  /// its own. Collective. Returns whether any process's reach now holds a plane its last
  /// did not.
  bool set_reach(int lo, int hi);
  /// Whether every process reads every plane of an array of @p planes planes.
  bool reach_whole(int planes) const;
  /// Whether this process's reach holds the planes [@p lo, @p hi] of @p planes.
  bool within_reach(int lo, int hi, int planes) const;
  /// Integer sums in @p arrays (each laid out as gather()'s), each process's partial sums
  /// on the planes of its reach and zero elsewhere, added up over the processes onto the
  /// planes of each process's reach: each process's partial planes go to their owners,
  /// which add them up and send the totals to the processes whose reach holds them. The
  /// other planes keep this process's partial sums. Arrays that hold the planes from
  /// @p base on only (plane k from @p first + (k − @p base) @p plane) must hold this
  /// process's reach; where every reach is every plane they hold them all. Collective.
  void add_up(const std::vector<std::int64_t*>& arrays, std::size_t first, std::size_t plane, int planes,
              int base = 0) const;
  /// The smallest of @p value over the processes, and its @p at (the lowest at of equal
  /// values).
  std::pair<double, int> min_at(double value, int at) const;
  /// Each of @p x[0 … n) replaced by its sum over the processes.
  void sum(double* x, int n) const;
  /// The same for integer sums (ExactSums::data()): the same bits on any number of processes.
  void sum(std::int64_t* x, int n) const;
  /// The planes of cells [first, last) of @p planes this process stated to set_reach
  /// (every plane before it did).
  std::pair<int, int> held(int planes) const;
  /// The planes [first, last) of @p planes in process @p r's reach.
  std::pair<int, int> reach_of(int r, int planes) const;
  /// The largest of @p x over the processes.
  double max(double x) const;
  /// Each of @p x[0 … n) replaced by its largest over the processes.
  void max(double* x, int n) const;
  /// This process's rank among those sharing the planes (0 when each computes them all).
  int rank() const { return rank_; }
  /// The processes sharing the planes (1 when each computes them all).
  int processes() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
  std::vector<int> reach_;  // per process its planes of cells [lo, hi], 2 values; empty: all
};

}  // namespace cdm::fluid
