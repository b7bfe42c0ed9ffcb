/// @file rank_collectives.cpp
/// @brief RankSplit's collectives that carry no particle state: the reductions every step
/// takes (the largest drift, a stop signal, the contacts' count and worst overlap, the
/// deposited sums) and the shared search's rows and gathered candidates.
#include "cdm/solver/rank_split.hpp"

#include "cdm/solver/contact/contact_module.hpp"
#include "cdm/solver/mpi_session.hpp"

#ifdef CDM_WITH_MPI
#include <mpi.h>
#endif

namespace cdm {

#ifdef CDM_WITH_MPI

std::pair<std::size_t, std::size_t> RankSplit::rows(std::size_t n) const {
  const auto r = static_cast<std::size_t>(rank_), p = static_cast<std::size_t>(size_);
  return {n * r / p, n * (r + 1) / p};
}

void RankSplit::gather_candidates(std::vector<std::vector<ContactPair>>& chunks) {
  std::vector<std::uint32_t> mine;
  for (const auto& c : chunks)
    for (const ContactPair& cp : c) mine.insert(mine.end(), {cp.i, cp.j});
  const auto size = static_cast<std::size_t>(size_);
  std::vector<int> counts(size), displs(size);
  const int count = static_cast<int>(mine.size());
  mpi_check(MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
  std::size_t total = 0;
  for (std::size_t r = 0; r < size; ++r) {
    displs[r] = static_cast<int>(total);
    total += static_cast<std::size_t>(counts[r]);
  }
  std::vector<std::uint32_t> all(total);
  mpi_check(MPI_Allgatherv(mine.data(), count, MPI_UINT32_T, all.data(), counts.data(), displs.data(), MPI_UINT32_T,
                           MPI_COMM_WORLD),
            "MPI_Allgatherv");
  // One chunk of every row's pairs, in row order (the overlap is not needed by the build).
  chunks.assign(1, {});
  chunks[0].reserve(total / 2);
  for (std::size_t k = 0; k + 1 < total; k += 2) chunks[0].push_back({all[k], all[k + 1], 0.0});
}

double RankSplit::max(double x) const {
  double out = x;
  mpi_check(MPI_Allreduce(&x, &out, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
  return out;
}

void RankSplit::add_up(ExactSums& s) const {
  mpi_check(MPI_Allreduce(MPI_IN_PLACE, s.data(), static_cast<int>(s.size()), MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD),
            "MPI_Allreduce");
}

bool RankSplit::any(bool flag) const {
  int in = flag ? 1 : 0, out = 0;
  mpi_check(MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD), "MPI_Allreduce");
  return out != 0;
}

void RankSplit::reduce_contacts(OverlapRecord& worst, std::size_t& active) const {
  const double mine[4] = {worst.ratio, static_cast<double>(worst.particle), static_cast<double>(worst.partner),
                          static_cast<double>(active)};
  std::vector<double> all(4 * static_cast<std::size_t>(size_));
  mpi_check(MPI_Allgather(mine, 4, MPI_DOUBLE, all.data(), 4, MPI_DOUBLE, MPI_COMM_WORLD), "MPI_Allgather");
  OverlapRecord w;
  std::size_t sum = 0;
  for (std::size_t r = 0; r < static_cast<std::size_t>(size_); ++r) {
    const OverlapRecord rec{all[4 * r], static_cast<std::uint32_t>(all[4 * r + 1]), static_cast<long>(all[4 * r + 2])};
    if (contact::worse_overlap(rec, w)) w = rec;
    sum += static_cast<std::size_t>(all[4 * r + 3]);
  }
  worst = w;
  active = sum;
}

#else  // a build without MPI has one rank: create() gives none, so nothing below runs

std::pair<std::size_t, std::size_t> RankSplit::rows(std::size_t n) const { return {0, n}; }
void RankSplit::gather_candidates(std::vector<std::vector<ContactPair>>&) {}
double RankSplit::max(double x) const { return x; }
bool RankSplit::any(bool flag) const { return flag; }
void RankSplit::reduce_contacts(OverlapRecord&, std::size_t&) const {}
void RankSplit::add_up(ExactSums&) const {}

#endif

}  // namespace cdm
