#!/usr/bin/env bash
# What each MPI process receives per gas step of the 1e5 bed (bench/scenes/bed_1e5.toml,
# the drag once per gas step), by kind of call: the bed run for 640 and for 1280 steps
# under libmpi_volume.so (bench/mpi_volume.cpp), and the difference over the 20 gas steps
# between, so that the start and the final checkpoint drop out. What bench/README.md's
# "What a divided gas step receives" was measured with.
#   bench/mpi_volume.sh NP [cdm run options...]
# (the options added to the runs', e.g. --set output.log_interval=1e-4 for a log row every gas
# step) prints per rank the MB received per gas step by kind and in all. Point-to-point holds
# the particles' ghosts (every step), hypre's halos and the gas planes.
# Environment: CDM (default build/release/app/cdm), VOLUME_LIB (default
# build/release/bench/libmpi_volume.so).
set -euo pipefail
[ $# -ge 1 ] && [[ "$1" =~ ^[1-9][0-9]*$ ]] ||
  { echo "usage: bench/mpi_volume.sh NP [cdm run options...] (NP a positive integer)" >&2; exit 2; }
np=$1
shift
here="$(cd "$(dirname "$0")" && pwd)"
cdm="${CDM:-$here/../build/release/app/cdm}"
lib="${VOLUME_LIB:-$here/../build/release/bench/libmpi_volume.so}"
[ -f "$lib" ] || { echo "bench/mpi_volume.sh: no $lib (build the release preset)" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export OMP_NUM_THREADS=1
[ "$(id -u)" = 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
for steps in 640 1280; do
  mkdir -p "$tmp/$steps"
  mpirun --oversubscribe -np "$np" -x CDM_MPI_VOLUME_DIR="$tmp/$steps" -x LD_PRELOAD="$lib" \
    "$cdm" run "$here/scenes/bed_1e5.toml" -q -j 1 --max-steps "$steps" --set output.vtk=false \
    --set 'coupling.drag_evaluation="gas_step"' "$@" -o "$tmp/$steps/out" > /dev/null
done
for r in $(seq 0 $((np - 1))); do
  # kind calls bytes, the same kinds in the same order in both files
  paste -d ' ' "$tmp/640/volume.$r" "$tmp/1280/volume.$r" |
    awk -v r="$r" '{ d = ($6 - $3) / 20 / 1e6; t += d; s = s sprintf(" %s %.3f", $1, d) }
                   END { printf "rank %s MB per gas step:%s total %.3f\n", r, s, t }'
done
