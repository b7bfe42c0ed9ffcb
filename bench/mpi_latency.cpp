// mpi_latency: what one exchange between two MPI processes costs, by the transport
// mpirun gives them (bench/README.md, "Two processes over TCP"). mpi_transport.sh runs it
// over shared memory and over TCP beside its runs of cdm.
//
//   mpirun -np 2 [--mca btl ...] mpi_latency [REPS]
//
// Rank 0 prints, for messages of 1 and 8192 doubles (8 B and 64 KiB), the one-way time of
// a ping-pong (half a round trip) and the time of an MPI_Allreduce of one double, in µs:
// the median of five timed rounds of REPS exchanges each (default 20000), after one round
// untimed.
#include <mpi.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace {

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  char* end = nullptr;
  const long reps = argc > 1 ? std::strtol(argv[1], &end, 10) : 20000;
  if (size != 2 || (argc > 1 && (*end != '\0' || reps < 1))) {
    if (rank == 0)
      std::fprintf(stderr, "usage: mpirun -np 2 mpi_latency [REPS]: REPS a positive integer, two processes (got %d, '%s')\n",
                   size, argc > 1 ? argv[1] : "");
    MPI_Finalize();
    return 2;
  }
  std::vector<double> buf(8192, 0.0);
  const int other = 1 - rank;
  std::printf("%s", rank == 0 ? "# doubles one_way_us allreduce_us\n" : "");
  for (const int n : {1, 8192}) {
    std::vector<double> one_way, reduce;
    for (int round = 0; round < 6; ++round) {
      MPI_Barrier(MPI_COMM_WORLD);
      double t0 = MPI_Wtime();
      for (long i = 0; i < reps; ++i) {
        if (rank == 0) {
          MPI_Send(buf.data(), n, MPI_DOUBLE, other, 0, MPI_COMM_WORLD);
          MPI_Recv(buf.data(), n, MPI_DOUBLE, other, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        } else {
          MPI_Recv(buf.data(), n, MPI_DOUBLE, other, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
          MPI_Send(buf.data(), n, MPI_DOUBLE, other, 0, MPI_COMM_WORLD);
        }
      }
      const double ping = (MPI_Wtime() - t0) / static_cast<double>(reps) / 2.0 * 1e6;
      double x = 1.0;
      MPI_Barrier(MPI_COMM_WORLD);
      t0 = MPI_Wtime();
      for (long i = 0; i < reps; ++i) MPI_Allreduce(MPI_IN_PLACE, &x, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
      const double all = (MPI_Wtime() - t0) / static_cast<double>(reps) * 1e6;
      if (round > 0) {
        one_way.push_back(ping);
        reduce.push_back(all);
      }
    }
    if (rank == 0) std::printf("%d %.2f %.2f\n", n, median(one_way), median(reduce));
  }
  MPI_Finalize();
  return 0;
}
