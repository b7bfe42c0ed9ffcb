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
#include <cstddef>
#include <utility>
#include <vector>

namespace cdm::fluid {

class PlaneShare {
 public:
  /// Among the processes of the MPI world (mpi_world()).
  PlaneShare();
  /// The planes [first, last) of @p planes that process @p rank of @p size computes:
  /// contiguous runs by rank (the multigrid pressure solve owns the same).
  static std::pair<int, int> planes_of(int planes, int rank, int size) {
    const auto at = [&](int r) { return static_cast<int>(static_cast<long long>(planes) * r / size); };
    return {at(rank), at(rank + 1)};
  }
  /// This process's planes [first, last) of @p planes.
  std::pair<int, int> mine(int planes) const { return planes_of(planes, rank_, size_); }
  /// Every process gets the planes [0, @p planes) of @p a, each from the process that
  /// computed it; plane k holds the @p plane values from @p first + k @p plane.
  void gather(std::vector<double>& a, std::size_t first, std::size_t plane, int planes) const;
  /// The largest of @p x over the processes.
  double max(double x) const;

 private:
  int rank_ = 0, size_ = 1;
};

}  // namespace cdm::fluid
