#!/usr/bin/env bash
# Hertz-Mindlin contacts with friction and rolling resistance keep the guarantees of the
# linear model: a pile of 4,800 beads (tests/cli/scenes/hertz_pile.toml) gives
# bit-identical particle tables on 1 and 2 OpenMP threads, and a run of 2N steps equals
# N steps, a checkpoint and a restart for the rest (tables and final checkpoints).
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
scene="$src/tests/cli/scenes/hertz_pile.toml"

# Threads (4,800 particles: above the 4,096 where threads start).
args=(run "$scene" -q --set integrator.end_time=0.002 --set output.interval=0.0005)
"$cdm" "${args[@]}" -o "$work/one" -j 1 > /dev/null || fail "1-thread run"
"$cdm" "${args[@]}" -o "$work/two" -j 2 > /dev/null || fail "2-thread run"
cmp -s "$work/one/particles.dat" "$work/two/particles.dat" || fail "1 and 2 threads differ"
# Contacts happened: friction and rolling resistance spun the beads.
awk '!/^#/ && ($9 != 0 || $10 != 0) {found = 1} END {exit !found}' "$work/one/particles.dat" || fail "no bead rotates: no contacts"

# Restart (600 beads, 0.01 s).
set_args=(--set 'lattices[0].count=[10,10,6]' --set integrator.end_time=0.01 --set output.interval=0.0005
          --set output.checkpoint_interval=0.0025 -q)
restart_matches "hertz pile" "$scene" "$work" 5000 "${set_args[@]}"
echo "hertz_pile: threads and restart bit-identical"
