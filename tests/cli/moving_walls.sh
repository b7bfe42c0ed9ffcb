#!/usr/bin/env bash
# Moving walls keep the guarantees of walls at rest (tests/cli/scenes/moving_walls.toml:
# a vibrating floor, a piston, an orbiting stirrer and a turning cone around 4,800
# frictional Hertz-Mindlin beads with rolling resistance): bit-identical particle tables
# on 1 and 2 OpenMP threads, and a run of 2N steps equals N steps, a checkpoint and a
# restart for the rest (tables and final checkpoints) — the walls are a function of time
# only, and their Verlet-list candidates are listed again after a restart.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
scene="$src/tests/cli/scenes/moving_walls.toml"

args=(run "$scene" -q --set integrator.end_time=0.002 --set output.interval=0.0005)
"$cdm" "${args[@]}" -o "$work/one" -j 1 > /dev/null || fail "1-thread run"
"$cdm" "${args[@]}" -o "$work/two" -j 2 > /dev/null || fail "2-thread run"
cmp -s "$work/one/particles.dat" "$work/two/particles.dat" || fail "1 and 2 threads differ"
awk '!/^#/ && ($9 != 0 || $10 != 0) {found = 1} END {exit !found}' "$work/one/particles.dat" || fail "no bead rotates: no contacts"

set_args=(--set random_particles[0].count=600 --set integrator.end_time=0.01 --set output.interval=0.0005
          --set output.checkpoint_interval=0.0025 -q)
restart_matches "moving walls" "$scene" "$work" 3001 "${set_args[@]}"
echo "moving_walls: threads and restart bit-identical"
