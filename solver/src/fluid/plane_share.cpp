#include "cdm/solver/fluid/plane_share.hpp"

#include <algorithm>
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

std::pair<int, int> PlaneShare::reach_of(int r, int planes) const {
  if (reach_.empty()) return {0, planes};
  const auto at = static_cast<std::size_t>(2 * r);
  return {std::clamp(reach_[at], 0, planes), std::clamp(reach_[at + 1] + 2, 0, planes)};
}

std::pair<int, int> PlaneShare::held(int planes) const {
  if (reach_.empty()) return {0, planes};
  const auto at = static_cast<std::size_t>(2 * rank_);
  return {std::clamp(reach_[at], 0, planes), std::clamp(reach_[at + 1] + 1, 0, planes)};
}

bool PlaneShare::reach_whole(int planes) const {
  for (int r = 0; r < size_; ++r)
    if (reach_of(r, planes) != std::pair{0, planes}) return false;
  return true;
}

bool PlaneShare::within_reach(int lo, int hi, int planes) const {
  const auto [k0, k1] = reach_of(rank_, planes);
  return lo > hi || (lo >= k0 && hi < k1);
}

#ifdef CDM_WITH_MPI

PlaneShare::PlaneShare(bool divided) {
  if (!divided) return;
  const WorldPlace w = mpi_world();
  rank_ = w.rank;
  size_ = w.size;
}

bool PlaneShare::set_reach(int lo, int hi) {
  if (size_ <= 1) return false;
  std::vector<int> all(2 * static_cast<std::size_t>(size_));
  const int mine[2] = {lo, hi};
  if (MPI_Allgather(mine, 2, MPI_INT, all.data(), 2, MPI_INT, MPI_COMM_WORLD) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allgather of the gas planes each process reads failed");
  bool grew = false;
  for (int r = 0; r < size_ && !reach_.empty(); ++r) {
    const auto at = static_cast<std::size_t>(2 * r);
    grew = grew || all[at] < reach_[at] || all[at + 1] > reach_[at + 1];
  }
  reach_ = std::move(all);
  return grew;
}

namespace {

/// The planes two runs [first, last) share.
std::pair<int, int> meet(std::pair<int, int> a, std::pair<int, int> b) {
  return {std::max(a.first, b.first), std::min(a.second, b.second)};
}

/// Planes [k0, k1) of each of @p arrays (@p plane values each, from @p first) one after
/// another in @p buf, or with @p back from it into them (@p add: added to them).
template <class T>
void pack(const std::vector<T*>& arrays, std::size_t first, std::size_t plane, std::pair<int, int> k,
          std::vector<T>& buf, bool back = false, bool add = false) {
  const std::size_t n = plane * static_cast<std::size_t>(k.second - k.first);
  if (!back) buf.resize(n * arrays.size());
  for (std::size_t a = 0; a < arrays.size(); ++a) {
    T* const at = arrays[a] + first + plane * static_cast<std::size_t>(k.first);
    T* const in = buf.data() + a * n;
    if (!back) std::copy_n(at, n, in);
    else if (!add) std::copy_n(in, n, at);
    else
      for (std::size_t i = 0; i < n; ++i) at[i] += in[i];
  }
}

}  // namespace

void PlaneShare::add_up(const std::vector<std::int64_t*>& arrays, std::size_t first, std::size_t plane, int planes,
                        int base) const {
  if (size_ <= 1) return;
  if (reach_whole(planes)) {
    if (base != 0) throw std::logic_error("PlaneShare::add_up: every plane is added up, the arrays hold some");
    for (std::int64_t* a : arrays)
      if (MPI_Allreduce(MPI_IN_PLACE, a + first, static_cast<int>(plane * static_cast<std::size_t>(planes)),
                        MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD) != MPI_SUCCESS)
        throw std::runtime_error("MPI: MPI_Allreduce of the deposited sums failed");
    return;
  }
  const std::pair<int, int> own = mine(planes), reach = reach_of(rank_, planes);
  const auto shift = [base](std::pair<int, int> k) { return std::pair{k.first - base, k.second - base}; };
  // First each process's partial sums to the planes' owners, then the owners' totals to
  // the processes whose reach holds them; one message each way between a pair.
  for (const bool totals : {false, true}) {
    std::vector<std::pair<int, std::pair<int, int>>> from;  // (process, planes) received
    std::vector<std::vector<std::int64_t>> out, in;
    std::vector<MPI_Request> req;
    for (int r = 0; r < size_; ++r) {
      if (r == rank_) continue;
      const std::pair<int, int> other_own = planes_of(planes, r, size_), other_reach = reach_of(r, planes);
      const auto send = totals ? meet(own, other_reach) : meet(reach, other_own);
      const auto recv = totals ? meet(other_own, reach) : meet(other_reach, own);
      if (recv.first < recv.second) {
        in.emplace_back(arrays.size() * plane * static_cast<std::size_t>(recv.second - recv.first));
        from.emplace_back(r, recv);
        req.emplace_back();
        if (MPI_Irecv(in.back().data(), static_cast<int>(in.back().size()), MPI_INT64_T, r, 1, MPI_COMM_WORLD,
                      &req.back()) != MPI_SUCCESS)
          throw std::runtime_error("MPI: a deposited sums exchange failed to start");
      }
      if (send.first < send.second) {
        out.emplace_back();
        pack(arrays, first, plane, shift(send), out.back());
        req.emplace_back();
        if (MPI_Isend(out.back().data(), static_cast<int>(out.back().size()), MPI_INT64_T, r, 1, MPI_COMM_WORLD,
                      &req.back()) != MPI_SUCCESS)
          throw std::runtime_error("MPI: a deposited sums exchange failed to start");
      }
    }
    if (MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE) != MPI_SUCCESS)
      throw std::runtime_error("MPI: a deposited sums exchange failed");
    for (std::size_t m = 0; m < from.size(); ++m)
      pack(arrays, first, plane, shift(from[m].second), in[m], true, !totals);
  }
}

std::pair<double, int> PlaneShare::min_at(double value, int at) const {
  if (size_ <= 1) return {value, at};
  struct {
    double v;
    int at;
  } x{value, at};
  if (MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE_INT, MPI_MINLOC, MPI_COMM_WORLD) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allreduce of the smallest gas fraction failed");
  return {x.v, x.at};
}

void PlaneShare::gather(std::vector<double>& a, std::size_t first, std::size_t plane, int planes) const {
  if (size_ <= 1) return;
  if (reach_whole(planes)) return gather_all(a, first, plane, planes);
  // Each process sends its planes in another's reach there, and receives its reach's
  // planes from their owners: one message a pair whose runs meet.
  std::vector<MPI_Request> req;
  const std::pair<int, int> own = mine(planes), reach = reach_of(rank_, planes);
  for (int r = 0; r < size_; ++r) {
    if (r == rank_) continue;
    for (const bool send : {false, true}) {
      const auto [k0, k1] = send ? meet(own, reach_of(r, planes)) : meet(planes_of(planes, r, size_), reach);
      if (k0 >= k1) continue;
      double* const at = a.data() + first + plane * static_cast<std::size_t>(k0);
      const int count = static_cast<int>(plane * static_cast<std::size_t>(k1 - k0));
      req.emplace_back();
      const int rc = send ? MPI_Isend(at, count, MPI_DOUBLE, r, 0, MPI_COMM_WORLD, &req.back())
                          : MPI_Irecv(at, count, MPI_DOUBLE, r, 0, MPI_COMM_WORLD, &req.back());
      if (rc != MPI_SUCCESS) throw std::runtime_error("MPI: a gas plane exchange failed to start");
    }
  }
  if (MPI_Waitall(static_cast<int>(req.size()), req.data(), MPI_STATUSES_IGNORE) != MPI_SUCCESS)
    throw std::runtime_error("MPI: a gas plane exchange failed");
}

namespace {

/// Each process's own planes of @p planes, @p plane values each, as counts and
/// displacements of values for MPI_Allgatherv and MPI_Gatherv.
std::pair<std::vector<int>, std::vector<int>> own_runs(int planes, std::size_t plane, int size) {
  std::vector<int> counts(static_cast<std::size_t>(size)), displs(counts.size());
  for (int r = 0; r < size; ++r) {
    const auto [k0, k1] = PlaneShare::planes_of(planes, r, size);
    counts[static_cast<std::size_t>(r)] = static_cast<int>(plane * static_cast<std::size_t>(k1 - k0));
    displs[static_cast<std::size_t>(r)] = static_cast<int>(plane * static_cast<std::size_t>(k0));
  }
  return {counts, displs};
}

}  // namespace

void PlaneShare::gather_all(std::vector<double>& a, std::size_t first, std::size_t plane, int planes) const {
  if (size_ <= 1) return;
  const auto [counts, displs] = own_runs(planes, plane, size_);
  if (MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, a.data() + first, counts.data(), displs.data(), MPI_DOUBLE,
                     MPI_COMM_WORLD) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allgatherv of the gas planes failed");
}

void PlaneShare::put_to_writer(OutArchive& out, const std::vector<double>& a, OutArchive::Planes layout) const {
  const int planes = layout.planes;
  // An array without those planes (empty: a face without drag gradients) holds none.
  const bool laid_out = planes > 0 && a.size() >= layout.first + static_cast<std::size_t>(planes) * layout.plane;
  if (size_ <= 1 || a.empty() || !laid_out || reach_of(0, planes) == std::pair{0, planes}) return out.put(a);
  // Process r's values [b, e): its planes, with what lies before the first plane or after
  // the last where it owns them. The processes' runs follow each other in rank order.
  const auto part = [&](int r) -> std::pair<std::size_t, std::size_t> {
    const auto [k0, k1] = planes_of(planes, r, size_);
    if (k0 == k1) return {0, 0};
    const auto at = [&](int k) { return layout.first + static_cast<std::size_t>(k) * layout.plane; };
    return {k0 == 0 ? 0 : at(k0), k1 == planes ? a.size() : at(k1)};
  };
  constexpr int tag = 40;
  constexpr std::size_t round = std::size_t{1} << 17;  // values a message
  const auto fail = [] { throw std::runtime_error("MPI: sending the gas planes to the writer failed"); };
  if (rank_ != 0) {
    const auto [b, e] = part(rank_);
    for (std::size_t x = b; x < e; x += round)
      if (MPI_Send(a.data() + x, static_cast<int>(std::min(round, e - x)), MPI_DOUBLE, 0, tag, MPI_COMM_WORLD) !=
          MPI_SUCCESS)
        fail();
    return;
  }
  out.put(static_cast<std::uint64_t>(a.size()));
  const auto [b0, e0] = part(0);
  out.put_values(a.data() + b0, e0 - b0);
  std::vector<double> piece;
  for (int r = 1; r < size_; ++r) {
    const auto [b, e] = part(r);
    for (std::size_t x = b; x < e; x += round) {
      piece.resize(std::min(round, e - x));
      if (MPI_Recv(piece.data(), static_cast<int>(piece.size()), MPI_DOUBLE, r, tag, MPI_COMM_WORLD,
                   MPI_STATUS_IGNORE) != MPI_SUCCESS)
        fail();
      out.put_values(piece.data(), piece.size());
    }
  }
}

double PlaneShare::max(double x) const {
  max(&x, 1);
  return x;
}

void PlaneShare::sum(double* x, int n) const {
  if (size_ <= 1) return;
  if (MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allreduce of the coupling's balance failed");
}

void PlaneShare::sum(std::int64_t* x, int n) const {
  if (size_ <= 1) return;
  if (MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_INT64_T, MPI_SUM, MPI_COMM_WORLD) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allreduce of the gas's exact sums failed");
}

void PlaneShare::max(double* x, int n) const {
  if (size_ <= 1) return;
  if (MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD) != MPI_SUCCESS)
    throw std::runtime_error("MPI: MPI_Allreduce of the gas step's largest values failed");
}

#else  // one process: every plane is this one's

PlaneShare::PlaneShare(bool) {}
void PlaneShare::gather(std::vector<double>&, std::size_t, std::size_t, int) const {}
void PlaneShare::gather_all(std::vector<double>&, std::size_t, std::size_t, int) const {}
void PlaneShare::put_to_writer(OutArchive& out, const std::vector<double>& a, OutArchive::Planes) const { out.put(a); }
bool PlaneShare::set_reach(int, int) { return false; }
void PlaneShare::add_up(const std::vector<std::int64_t*>&, std::size_t, std::size_t, int, int) const {}
std::pair<double, int> PlaneShare::min_at(double value, int at) const { return {value, at}; }
double PlaneShare::max(double x) const { return x; }
void PlaneShare::max(double*, int) const {}
void PlaneShare::sum(double*, int) const {}
void PlaneShare::sum(std::int64_t*, int) const {}

#endif

}  // namespace cdm::fluid
