#!/usr/bin/env bash
# The gas step's cost against the grid (bench/README.md, "The gas pressure solve"):
# bench/scenes/gas_scaling.toml (10 gas steps, ε changing every step) at N³ cells, one
# thread, for each backend. Prints per run: N backend wall_s user_s loop_s maxrss_MB.
# Usage: bench/gas_scaling.sh [REPS] [multigrid sizes...] (default 3; 16 24 32 40 64);
# DIRECT="16 24" sets the sizes run with the direct solver (default "16 24 32", once each
# for 32). BUILD sets the build directory (default build/release). RANKS=N (N > 1) also
# runs each multigrid size on N MPI processes of one thread, straight after its one-process
# run (backend "multigrid-Np"; the gas step divided by planes; maxrss "-", since time sees
# only mpirun): bench/README.md, "The divided gas step sends less". CONTACTS=1 gives the
# particles a (soft) contact law, so that among processes they are dealt out in slabs along
# z and each process keeps only the gas's planes under its own (bench/README.md, "A divided
# gas keeps its reach's planes only").
set -euo pipefail
reps=${1:-3}
shift || true
sizes=${*:-16 24 32 40 64}
build=${BUILD:-build/release}
scene=$(dirname "$0")/scenes/gas_scaling.toml
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ranks=${RANKS:-1}
extra=()
if [ "${CONTACTS:-0}" = 1 ]; then
  extra=(--set 'modules.normal_contact="linear_spring_dashpot"' --set 'contacts=[{pair=["p","p"],kn=1.0e-3,en=0.9}]')
fi
if [ "$ranks" -gt 1 ]; then
  export OMP_NUM_THREADS=1
  [ "$(id -u)" = 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
run() {  # N backend [processes]
  local np=${3:-1} launch=() label=$2 out
  [ "$np" -gt 1 ] && launch=(mpirun -np "$np") && label="$2-${np}p"
  out=$( { /usr/bin/time -f "TIME %e %U %M" "${launch[@]}" "$build/app/cdm" run "$scene" -j 1 -q \
           --set "gas.cells=[$1,$1,$1]" --set "gas.pressure_solver=\"$2\"" "${extra[@]}" --out "$tmp/run"; } 2>&1 )
  local loop t rss
  loop=$(echo "$out" | sed -n 's/.*loop time \([0-9.]*\) s.*/\1/p')
  t=$(echo "$out" | grep '^TIME')
  rss=$(echo "$t" | awk '{printf "%.0f", $4/1024}')
  [ "$np" -gt 1 ] && rss=-
  echo "$1 $label $(echo "$t" | awk '{print $2, $3}') $loop $rss"
}
echo "# N backend wall_s user_s loop_s maxrss_MB"
for n in $sizes; do
  for r in $(seq "$reps"); do
    run "$n" multigrid
    if [ "$ranks" -gt 1 ]; then run "$n" multigrid "$ranks"; fi
  done
done
for n in ${DIRECT-16 24 32}; do
  k=$reps
  [ "$n" -ge 32 ] && k=1
  for r in $(seq "$k"); do run "$n" direct; done
done
