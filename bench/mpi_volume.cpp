// mpi_volume: what each MPI process of a run receives, by kind of call.
//
// A library preloaded into a run (mpirun -x LD_PRELOAD=libmpi_volume.so), not linked into
// cdm: it defines the MPI calls cdm and hypre make and passes each on to its PMPI twin,
// counting the calls and the bytes the calling process receives by them (a receive's
// posted size; a reduction's count; a gather's contributions from the other processes).
// At MPI_Finalize it writes one line per kind, "kind calls bytes", to
// $CDM_MPI_VOLUME_DIR/volume.R (R: the rank in MPI_COMM_WORLD), where that is set.
// bench/README.md, "What a divided gas step receives".
#include <mpi.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

enum Kind { point_to_point, allreduce, allgather, gather, alltoall, kinds };
const char* const kNames[kinds] = {"point_to_point", "allreduce", "allgather", "gather", "alltoall"};

struct Count {
  std::uint64_t calls = 0, bytes = 0;
};
Count g_count[kinds];

std::uint64_t bytes_of(int count, MPI_Datatype t) {
  int size = 0;
  PMPI_Type_size(t, &size);
  return static_cast<std::uint64_t>(count < 0 ? 0 : count) * static_cast<std::uint64_t>(size);
}

void add(Kind k, std::uint64_t bytes) {
  ++g_count[k].calls;
  g_count[k].bytes += bytes;
}

int rank_in(MPI_Comm c) {
  int r = 0;
  PMPI_Comm_rank(c, &r);
  return r;
}

int size_of(MPI_Comm c) {
  int n = 1;
  PMPI_Comm_size(c, &n);
  return n;
}

/// Σ counts[r] over the processes r but this one.
std::uint64_t others(const int* counts, MPI_Datatype t, MPI_Comm c) {
  const int me = rank_in(c), n = size_of(c);
  std::uint64_t b = 0;
  for (int r = 0; r < n; ++r)
    if (r != me) b += bytes_of(counts[r], t);
  return b;
}

}  // namespace

extern "C" {

int MPI_Recv(void* buf, int count, MPI_Datatype t, int source, int tag, MPI_Comm c, MPI_Status* s) {
  add(point_to_point, bytes_of(count, t));
  return PMPI_Recv(buf, count, t, source, tag, c, s);
}

int MPI_Irecv(void* buf, int count, MPI_Datatype t, int source, int tag, MPI_Comm c, MPI_Request* r) {
  add(point_to_point, bytes_of(count, t));
  return PMPI_Irecv(buf, count, t, source, tag, c, r);
}

int MPI_Allreduce(const void* in, void* out, int count, MPI_Datatype t, MPI_Op op, MPI_Comm c) {
  add(allreduce, bytes_of(count, t));
  return PMPI_Allreduce(in, out, count, t, op, c);
}

int MPI_Allgather(const void* in, int n_in, MPI_Datatype t_in, void* out, int n_out, MPI_Datatype t_out, MPI_Comm c) {
  add(allgather, bytes_of(n_out, t_out) * static_cast<std::uint64_t>(size_of(c) - 1));
  return PMPI_Allgather(in, n_in, t_in, out, n_out, t_out, c);
}

int MPI_Allgatherv(const void* in, int n_in, MPI_Datatype t_in, void* out, const int* counts, const int* displs,
                   MPI_Datatype t_out, MPI_Comm c) {
  add(allgather, others(counts, t_out, c));
  return PMPI_Allgatherv(in, n_in, t_in, out, counts, displs, t_out, c);
}

int MPI_Gather(const void* in, int n_in, MPI_Datatype t_in, void* out, int n_out, MPI_Datatype t_out, int root,
               MPI_Comm c) {
  add(gather, rank_in(c) == root ? bytes_of(n_out, t_out) * static_cast<std::uint64_t>(size_of(c) - 1) : 0);
  return PMPI_Gather(in, n_in, t_in, out, n_out, t_out, root, c);
}

int MPI_Gatherv(const void* in, int n_in, MPI_Datatype t_in, void* out, const int* counts, const int* displs,
                MPI_Datatype t_out, int root, MPI_Comm c) {
  add(gather, rank_in(c) == root ? others(counts, t_out, c) : 0);
  return PMPI_Gatherv(in, n_in, t_in, out, counts, displs, t_out, root, c);
}

int MPI_Alltoall(const void* in, int n_in, MPI_Datatype t_in, void* out, int n_out, MPI_Datatype t_out, MPI_Comm c) {
  add(alltoall, bytes_of(n_out, t_out) * static_cast<std::uint64_t>(size_of(c) - 1));
  return PMPI_Alltoall(in, n_in, t_in, out, n_out, t_out, c);
}

int MPI_Alltoallv(const void* in, const int* n_in, const int* d_in, MPI_Datatype t_in, void* out, const int* n_out,
                  const int* d_out, MPI_Datatype t_out, MPI_Comm c) {
  add(alltoall, others(n_out, t_out, c));
  return PMPI_Alltoallv(in, n_in, d_in, t_in, out, n_out, d_out, t_out, c);
}

int MPI_Finalize() {
  const char* dir = std::getenv("CDM_MPI_VOLUME_DIR");
  if (dir && *dir) {
    const std::string path = std::string(dir) + "/volume." + std::to_string(rank_in(MPI_COMM_WORLD));
    if (std::FILE* f = std::fopen(path.c_str(), "w")) {
      for (int k = 0; k < kinds; ++k)
        std::fprintf(f, "%s %llu %llu\n", kNames[k], static_cast<unsigned long long>(g_count[k].calls),
                     static_cast<unsigned long long>(g_count[k].bytes));
      if (std::fclose(f) != 0) std::fprintf(stderr, "mpi_volume: could not write %s\n", path.c_str());
    } else {
      std::fprintf(stderr, "mpi_volume: could not open %s\n", path.c_str());
    }
  }
  return PMPI_Finalize();
}

}  // extern "C"
