# Open MPI's two transports between processes, as mpirun options, for scripts to source:
# shared memory, as between the processes of one node, and TCP on the loopback, as between
# nodes (the kernel's TCP stack without a wire). Read by bench/mpi_transport.sh,
# bench.mpi_latency (bench/CMakeLists.txt) and tests/cli/mpi_ranks.sh.
# shellcheck disable=SC2034
mpi_shared_memory=(--mca pml ob1 --mca btl self,vader)
mpi_tcp=(--mca pml ob1 --mca btl self,tcp --mca btl_tcp_if_include lo)
