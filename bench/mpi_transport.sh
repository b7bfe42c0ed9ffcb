#!/usr/bin/env bash
# Two MPI processes over Open MPI's shared memory (as on one node) and over TCP (as
# between nodes; the loopback here, so the network's latency and bandwidth are the
# kernel's, not a wire's), against one process, on the problems of the speed targets:
# settle 1e5 (3000 steps from the lattice), the chute (4000 steps from the lattice), the
# Müller bed (coupled, drag once per gas step, 20,000 steps: 0.059 s) and the 1e5 bed (640 steps).
# Runs alternate one process, two over shared memory, two over TCP, REPS times (default
# 3); prints each run's loop time, then per problem the medians, two processes' speed-up
# over one by each transport, and what TCP costs against shared memory; first, what one
# exchange costs by each transport (mpi_latency).
#   bench/mpi_transport.sh [REPS] [PROBLEM ...]   PROBLEM in settle1e5 chute mueller bed1e5
# Environment: CDM (default build/release/app/cdm), LATENCY (default
# build/release/bench/mpi_latency). bench/README.md, "Two processes over TCP".
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
cdm="${CDM:-$here/../build/release/app/cdm}"
latency="${LATENCY:-$here/../build/release/bench/mpi_latency}"
reps=${1:-3}
shift || true
problems=("$@")
[ ${#problems[@]} -gt 0 ] || problems=(settle1e5 chute mueller bed1e5)
export OMP_NUM_THREADS=1
[ "$(id -u)" = 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

args() {  # the problem's scene and options
  case "$1" in
    settle1e5) echo "$here/scenes/settle_1e4.toml --set lattices[0].count=[50,80,25] --set walls[2].point=[0.055,0.0,0.0]
                --set walls[4].point=[0.0,0.088,0.0] --set output.particles=false --set integrator.end_time=1.0
                --max-steps 3000" ;;
    chute) echo "$here/scenes/chute32k.toml --set integrator.end_time=1.0 --set output.particles=false --max-steps 4000" ;;
    mueller) echo "$here/scenes/mueller_bubbling_bed.toml --set output.vtk=false --set coupling.drag_evaluation=\"gas_step\"
                   --max-steps 20000" ;;
    bed1e5) echo "$here/scenes/bed_1e5.toml --set output.vtk=false --set coupling.drag_evaluation=\"gas_step\"
                  --max-steps 640" ;;
    *) echo "unknown problem '$1' (expected settle1e5, chute, mueller, bed1e5)" >&2; exit 2 ;;
  esac
}

source "$here/mpi_transports.sh"
shm=(mpirun -np 2 "${mpi_shared_memory[@]}")
tcp=(mpirun -np 2 "${mpi_tcp[@]}")
echo "shared memory:"; "${shm[@]}" "$latency"
echo "TCP:"; "${tcp[@]}" "$latency"

results="$tmp/results"
for p in "${problems[@]}"; do
  read -r -a a <<< "$(args "$p" | tr '\n' ' ')"
  for r in $(seq "$reps"); do
    for how in one shm tcp; do
      case $how in
        one) launch=() ;;
        shm) launch=("${shm[@]}") ;;
        tcp) launch=("${tcp[@]}") ;;
      esac
      t=$("${launch[@]}" "$cdm" run "${a[@]}" -q -j 1 -o "$tmp/run" | sed -n 's/^loop time \([0-9.]*\) s.*/\1/p')
      [ -n "$t" ] || { echo "$p $how: no loop time" >&2; exit 1; }
      echo "$p $how $t" | tee -a "$results"
    done
  done
done
/usr/bin/python3 - "$results" <<'EOF'
import collections, statistics, sys
t = collections.defaultdict(list)
for line in open(sys.argv[1]):
    p, how, s = line.split()
    t[(p, how)].append(float(s))
print("\n| problem | one process | two, shared memory | two, TCP | speed-up, shared memory | speed-up, TCP | TCP / shared memory |")
print("|---|---|---|---|---|---|---|")
for p in dict.fromkeys(k[0] for k in t):
    one, shm, tcp = (statistics.median(t[(p, h)]) for h in ("one", "shm", "tcp"))
    print(f"| {p} | {one:.3f} | {shm:.3f} | {tcp:.3f} | {one / shm:.2f}x | {one / tcp:.2f}x | {tcp / shm:.3f} |")
EOF
