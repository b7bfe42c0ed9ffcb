#!/usr/bin/env bash
# Each process's peak resident memory, the loop time and the final checkpoint's hash of
# settle 1e6 (bench/scenes/settle_1e4.toml on a 200 x 200 x 25 lattice) on NP MPI processes
# of one thread, STEPS steps: what bench/README.md's peaks per process since session 53
# were measured with. Each process runs under /usr/bin/time, which sees it alone (around
# mpirun it would see only the launcher). Each process's resident memory is also sampled
# every 50 ms: the median over the second half of the run is what it holds once settled
# (once the processes divide the gas by planes, say).
#   bench/peak_memory.sh NP STEPS [cdm run options ...]
#   SCENE=bench/scenes/bed_1e5.toml bench/peak_memory.sh 4 320 --set 'gas.cells=[48,192,48]'
# prints the run's loop-time line, the peaks in MiB by rank, the settled memory in MiB by
# rank, and the checkpoint's md5.
# Environment: CDM (default build/release/app/cdm), MPIRUN_ARGS (more options for mpirun,
# e.g. "-x LD_PRELOAD=..."), SCENE (another scene, run as it is instead of settle 1e6).
set -euo pipefail
[ $# -ge 2 ] || { echo "usage: bench/peak_memory.sh NP STEPS [cdm run options ...]" >&2; exit 2; }
np=$1 steps=$2
shift 2
[[ "$np" =~ ^[1-9][0-9]*$ && "$steps" =~ ^[1-9][0-9]*$ ]] ||
  { echo "bench/peak_memory.sh: NP '$np' and STEPS '$steps' must be positive integers" >&2; exit 2; }
here="$(cd "$(dirname "$0")" && pwd)"
cdm="${CDM:-$here/../build/release/app/cdm}"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMP_NUM_THREADS=1
[ "$(id -u)" = 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
read -r -a extra <<< "${MPIRUN_ARGS:-}"
if [ -n "${SCENE:-}" ]; then
  scene=("$SCENE")
else
  scene=("$here/scenes/settle_1e4.toml" --set "lattices[0].count=[200,200,25]" --set "walls[2].point=[0.22,0.0,0.0]"
         --set "walls[4].point=[0.0,0.22,0.0]" --set output.particles=false)
fi
# Each rank's peak and samples go to files of its own, named by the rank mpirun gives it;
# the samples are of cdm, the child of /usr/bin/time.
sampler='/usr/bin/time -f %M -o "$0/rss.$OMPI_COMM_WORLD_RANK" "$@" & pid=$!
f="$0/samples.$OMPI_COMM_WORLD_RANK"
while kill -0 "$pid" 2> /dev/null; do
  for c in $(cat "/proc/$pid/task/$pid/children" 2> /dev/null); do
    awk "/^VmRSS/ {print \$2}" "/proc/$c/status" >> "$f" 2> /dev/null || true
  done
  sleep 0.05
done
wait "$pid"'
mpirun --oversubscribe -np "$np" "${extra[@]}" bash -c "$sampler" "$tmp" "$cdm" run "${scene[@]}" -o "$tmp/out" -q \
  --set integrator.end_time=1.0 --max-steps "$steps" "$@" | grep '^loop time'
for r in $(seq 0 $((np - 1))); do printf "%s " $(( $(cat "$tmp/rss.$r") / 1024 )); done
echo MiB
for r in $(seq 0 $((np - 1))); do
  [ -s "$tmp/samples.$r" ] || { printf "- "; continue; }  # a run shorter than a sample
  n=$(wc -l < "$tmp/samples.$r")
  printf "%s " $(( $(tail -n $(((n + 1) / 2)) "$tmp/samples.$r" | sort -n | sed -n "$(((n + 3) / 4))p") / 1024 ))
done
echo MiB settled
md5sum "$tmp/out/checkpoint.cdmck" | cut -c1-12
