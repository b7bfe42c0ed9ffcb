#!/usr/bin/env bash
# What each MPI process reads of the checkpoint as it restarts: a run of SCENE on NP
# processes writes a checkpoint after STEPS steps, then a restart from it on NP processes
# runs one more step, each process under strace. Prints, by rank, the bytes read from the
# checkpoint file and the number of reads, against the file's size; then the restart's
# wall time (one step, without strace), REPS rounds.
#   bench/restart_read.sh NP STEPS [cdm run options ...]
#   SCENE=bench/scenes/bed_1e5.toml bench/restart_read.sh 4 64 --set 'gas.cells=[48,192,48]' \
#       --set 'random_particles[0].count=20000' --set output.particles=false
# Environment: CDM (default build/release/app/cdm), SCENE (default bench/scenes/bed_1e5.toml),
# REPS (default 3).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: bench/restart_read.sh NP STEPS [cdm run options ...]" >&2; exit 2; }
np=$1 steps=$2
shift 2
[[ "$np" =~ ^[1-9][0-9]*$ && "$steps" =~ ^[1-9][0-9]*$ ]] ||
  { echo "bench/restart_read.sh: NP '$np' and STEPS '$steps' must be positive integers" >&2; exit 2; }
here="$(cd "$(dirname "$0")" && pwd)"
cdm="${CDM:-$here/../build/release/app/cdm}"
scene="${SCENE:-$here/scenes/bed_1e5.toml}"
reps=${REPS:-3}
command -v strace > /dev/null || { echo "bench/restart_read.sh: needs strace" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMP_NUM_THREADS=1
[ "$(id -u)" = 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
mpi=(mpirun --oversubscribe -np "$np")
"${mpi[@]}" "$cdm" run "$scene" -q -j 1 --max-steps "$steps" -o "$tmp/first" "$@" > "$tmp/first.log"
ck="$tmp/first/checkpoint.cdmck"
[ -s "$ck" ] || { echo "bench/restart_read.sh: the first run wrote no checkpoint" >&2; exit 1; }
# Each rank's reads of the checkpoint, traced into a file named by the rank mpirun gives it.
tracer='exec strace -e trace=openat,read,close -o "$0/trace.$OMPI_COMM_WORLD_RANK" "$@"'
"${mpi[@]}" sh -c "$tracer" "$tmp" "$cdm" run "$scene" -q -j 1 --max-steps $((steps + 1)) --restart "$ck" \
  -o "$tmp/traced" "$@" > "$tmp/traced.log"
echo "checkpoint: $(stat -c %s "$ck") bytes"
for r in $(seq 0 $((np - 1))); do
  # The checkpoint's descriptor from its openat to its close; the bytes its reads returned.
  awk -v ck="$ck" -v rank="$r" '
    /^openat\(/ && index($0, "\"" ck "\"") { split($0, eq, "= "); fd = eq[2] + 0; open = 1; next }
    open && /^read\(/ { split($0, a, "[(,]"); if (a[2] + 0 == fd) { split($0, eq, "= "); bytes += eq[2]; reads++ } }
    open && /^close\(/ { split($0, a, "[()]"); if (a[2] + 0 == fd) open = 0 }
    END { printf "rank %s: %d bytes in %d reads\n", rank, bytes, reads }' "$tmp/trace.$r"
done
for k in $(seq "$reps"); do
  start=$(date +%s.%N)
  "${mpi[@]}" "$cdm" run "$scene" -q -j 1 --max-steps $((steps + 1)) --restart "$ck" -o "$tmp/timed" "$@" > /dev/null
  end=$(date +%s.%N)
  echo "restart and one step, round $k: $(echo "$end - $start" | bc) s"
done
