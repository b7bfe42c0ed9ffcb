#include "cdm/solver/fluid/plane_share.hpp"

#include <stdexcept>

#include "cdm/solver/mpi_session.hpp"

#ifdef CDM_WITH_MPI
#include <mpi.h>
#endif

namespace cdm::fluid {

bool PlaneShare::divides(GasDivision d, const StaggeredGrid& g, int processes) {
  if (processes <= 1 || d == GasDivision::whole) return false;
  if (d == GasDivision::planes) return true;
  const int slow = g.dims() - 1;
  const std::size_t per_plane = g.cell_count() / static_cast<std::size_t>(g.n(slow));
  for (int r = 0; r < processes; ++r) {
    const auto [first, last] = planes_of(g.n(slow), r, processes);
    if (per_plane * static_cast<std::size_t>(last - first) < min_divided_cells) return false;
  }
  return true;
}

#ifdef CDM_WITH_MPI

PlaneShare::PlaneShare(bool divided) {
  if (!divided) return;
  const WorldPlace w = mpi_world();
  rank_ = w.rank;
  size_ = w.size;
}

void PlaneShare::gather(std::vector<double>& a, std::size_t first, std::size_t plane, int planes) const {
  if (size_ <= 1) return;
  std::vector<int> counts(static_cast<std::size_t>(size_)), displs(counts.size());
  for (int r = 0; r < size_; ++r) {
    const auto [k0, k1] = planes_of(planes, r, size_);
    counts[static_cast<std::size_t>(r)] = static_cast<int>(plane * static_cast<std::size_t>(k1 - k0));
    displs[static_cast<std::size_t>(r)] = static_cast<int>(plane * static_cast<std::size_t>(k0));
  }
  if (MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, a.data() + first, counts.data(), displs.data(), MPI_DOUBLE,
                     MPI_COMM_WORLD) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allgatherv of the gas planes failed");
}

double PlaneShare::max(double x) const {
  max(&x, 1);
  return x;
}

void PlaneShare::max(double* x, int n) const {
  if (size_ <= 1) return;
  if (MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allreduce of the gas step's largest values failed");
}

#else  // one process: every plane is this one's

PlaneShare::PlaneShare(bool) {}
void PlaneShare::gather(std::vector<double>&, std::size_t, std::size_t, int) const {}
double PlaneShare::max(double x) const { return x; }
void PlaneShare::max(double*, int) const {}

#endif

}  // namespace cdm::fluid
