#!/usr/bin/env bash
# The cost of insertion and outlets (issue #35) on the settle benchmark's 10,000
# frictional spheres, 8000 steps, one thread, each run REPS times (median loop time):
#   bed          settle_1e4 as it is;
#   outlet       the same with a plane outlet below the floor that never removes (the
#                scan every step pays);
#   feed40       the same with 2,000 more spheres inserted above the bed at 150,000/s in
#                events every 0.0003 s (about 45 inserted per event, 43 events);
#   feed_every   the same rate with an insertion at every step that owes one (about 1,000
#                events of 2: each scans the particles and rebuilds the contact list).
# Usage: bench/insertion.sh [CDM] (default build/release/app/cdm); REPS=3.
set -eu
here=$(cd "$(dirname "$0")" && pwd)
cdm=${1:-$here/../build/release/app/cdm}
reps=${REPS:-3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
base="$here/scenes/settle_1e4.toml"
cp "$base" "$work/bed.toml"
{ cat "$base"; printf '\n[[outlets]]\nname = "never"\ntype = "plane"\npoint = [0.0, 0.0, -1.0]\nnormal = [0.0, 0.0, -1.0]\n'; } > "$work/outlet.toml"
feed='\n[[insertions]]\nmaterial = "glass"\nlower = [0.001, 0.001, 0.031]\nupper = [0.021, 0.021, 0.036]\ncount_rate = 150000.0\ncount = 2000\nvelocity = [0.0, 0.0, -0.5]\n'
{ cat "$base"; printf "$feed"; printf 'radius = 0.5e-3\ninterval = 0.0003\n'; } > "$work/feed40.toml"
{ cat "$base"; printf "$feed"; printf 'radius = 0.5e-3\n'; } > "$work/feed_every.toml"
printf '| run | CPU time [s] (median of %s) | loop wall time [s] (median) | particles at the end |\n|---|---|---|---|\n' "$reps"
for run in bed outlet feed40 feed_every; do
  times=() cpus=()
  for ((r = 0; r < reps; ++r)); do
    out=$(/usr/bin/time -f 'cpu %U %S' "$cdm" run "$work/$run.toml" -q -j 1 -o "$work/out-$run" \
            --set integrator.end_time=0.0128667 --set output.interval=1.0 2>&1)
    line=$(echo "$out" | grep '^loop time')
    times+=("$(echo "$line" | awk '{print $3}')")
    cpus+=("$(echo "$out" | awk '/^cpu/ {print $2 + $3}')")
    n=$(echo "$line" | awk '{print $9}')
  done
  median() { printf '%s\n' "$@" | sort -g | awk '{a[NR]=$1} END{print a[int((NR+1)/2)]}'; }
  printf '| %s | %s | %s | %s |\n' "$run" "$(median "${cpus[@]}")" "$(median "${times[@]}")" "$n"
done
