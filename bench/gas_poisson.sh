#!/usr/bin/env bash
# The gas pressure-solve table of bench/README.md: bench/gas_poisson for multigrid at
# 16³ … 128³ and direct while affordable, each size in its own process (so that the peak
# memory is that size's). Usage: [NP=2] bench/gas_poisson.sh [BUILD_DIR] (default
# build/release); with NP the multigrid rows run divided among NP MPI processes
# (mpirun -np NP), then again on one process, size by size, for the ratio.
set -euo pipefail
build=${1:-build/release}
exe=$build/bench/gas_poisson
echo "# N cells backend reps setup_s solve_s us_per_cell cpu_us_per_cell iterations rel_residual maxrss_MB factor_work_per_cell processes"
if [ -n "${NP:-}" ]; then
  launch=(mpirun -np "$NP" --oversubscribe)
  [ "$(id -u)" -eq 0 ] && launch+=(--allow-run-as-root)
  for n in 16 32 64 96 128; do "${launch[@]}" "$exe" "$n" multigrid 3; "$exe" "$n" multigrid 3; done
  exit 0
fi
for n in 16 32 64 96 128; do "$exe" "$n" multigrid 3; done
for n in 16 24; do "$exe" "$n" direct 3; done
"$exe" 32 direct 1
