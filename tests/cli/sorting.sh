#!/usr/bin/env bash
# Spatial sorting (neighbour_list.sort_interval) reorders the particles in memory and
# changes nothing else:
# - the settle benchmark's 10,000 frictional spheres, 4,000 steps sorted every 100
#   steps: bit-identical tables on 1 and 2 threads; a run split by a checkpoint (taken
#   after several sorts) and restarted equals the uninterrupted one bit for bit; the
#   table lists the same ids in the same order as an unsorted run, at the same places
#   to round-off (bound below);
# - a Hertz–Mindlin pile with friction and rolling resistance (tests/cli/scenes/
#   hertz_pile.toml): sorted runs bit-identical on 1 and 2 threads, and, without the
#   rolling torque (see below), within the same bound of an unsorted run;
# - the small periodic chute (wrapping particles, fixed base): sorted against unsorted,
#   the same bound.
# Bound: the sorted run adds each particle's contact forces in another order, so the
# runs part by round-off, amplified through the contacts as the bed packs. Measured
# (2026-11-23) on the settle problem: 3e-16 m and 8e-16 m/s apart at the most over these
# 4,000 steps, 7e-13 m and 5e-9 m/s over 8,000; the chute 2e-15 m; a tangential history
# carried with the wrong sign across a sort gives 4e-5 m and 0.09 m/s within 2,500
# steps. The test allows 1e-9 m (1e-6 of a diameter) and 1e-5 m/s.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"

# Same ids in the same order, positions within dx [m] and velocities within dv [m/s],
# over every row of the two tables (columns t id x y z vx vy vz ...).
agree() {
  /usr/bin/python3 - "$1" "$2" <<'EOF' || fail "sorted and unsorted runs differ: $1 $2"
import sys
import numpy as np
a, b = np.loadtxt(sys.argv[1]), np.loadtxt(sys.argv[2])
ok = a.shape == b.shape and (a[:, :2] == b[:, :2]).all()
dx = np.abs(a[:, 2:5] - b[:, 2:5]).max() if ok else float("inf")
dv = np.abs(a[:, 5:8] - b[:, 5:8]).max() if ok else float("inf")
print(f"  {sys.argv[2]}: {a.shape[0]} rows, max |dx| = {dx:.2e} m, max |dv| = {dv:.2e} m/s")
sys.exit(0 if ok and dx <= 1e-9 and dv <= 1e-5 else 1)
EOF
}

settle="$src/bench/scenes/settle_1e4.toml"
args=(run "$settle" -q --set integrator.end_time=0.0064334 --set output.interval=0.002)
sorted=(--set neighbour_list.sort_interval=100)
"$cdm" "${args[@]}" --set neighbour_list.sort_interval=0 -o "$work/plain" -j 1 > /dev/null || fail "unsorted run"
"$cdm" "${args[@]}" "${sorted[@]}" -o "$work/one" -j 1 > /dev/null || fail "sorted 1-thread run"
"$cdm" "${args[@]}" "${sorted[@]}" -o "$work/two" -j 2 > /dev/null || fail "sorted 2-thread run"
cmp -s "$work/one/particles.dat" "$work/two/particles.dat" || fail "sorted: 1 and 2 threads differ"
agree "$work/plain/particles.dat" "$work/one/particles.dat"

# Restart with sorting: a checkpoint after several sorts.
set_args=("${sorted[@]}" --set integrator.end_time=0.0064334 --set output.interval=0.001
          --set output.checkpoint_interval=0.003 -q)
mkdir -p "$work/restart"
restart_matches "sorted" "$settle" "$work/restart" 2345 "${set_args[@]}"

# Hertz–Mindlin with friction and rolling resistance (its torques go through the
# contact list, in list order): sorted runs bit-identical on 1 and 2 threads. Against an
# unsorted run only with rolling_mu = 0: the constant-torque rule stops a contact's
# rolling exactly given the torques of the contacts visited before it, so the order the
# contacts are visited in (which sorting changes) moves results by more than round-off
# (measured: 1e-9 m, 0.05 rad/s after 2 ms; with rolling_mu = 0, 1e-17 m/s).
pile="$src/tests/cli/scenes/hertz_pile.toml"
pargs=(run "$pile" -q --set integrator.end_time=0.002 --set output.interval=0.0005 --set neighbour_list.sort_interval=50)
"$cdm" "${pargs[@]}" -o "$work/pile_one" -j 1 > /dev/null || fail "sorted pile, 1 thread"
"$cdm" "${pargs[@]}" -o "$work/pile_two" -j 2 > /dev/null || fail "sorted pile, 2 threads"
cmp -s "$work/pile_one/particles.dat" "$work/pile_two/particles.dat" || fail "sorted pile: 1 and 2 threads differ"
no_roll=(--set 'contacts[0].rolling_mu=0' --set 'contacts[1].rolling_mu=0')
"$cdm" "${pargs[@]}" "${no_roll[@]}" -o "$work/pile_sorted" > /dev/null || fail "sorted pile without rolling torque"
"$cdm" "${pargs[@]}" "${no_roll[@]}" --set neighbour_list.sort_interval=0 -o "$work/pile_plain" > /dev/null ||
  fail "unsorted pile without rolling torque"
agree "$work/pile_plain/particles.dat" "$work/pile_sorted/particles.dat"

# The periodic chute: particles wrap through the faces between sorts.
chute="$src/bench/scenes/chute32k.toml"
cargs=(run "$chute" --set 'lattices[0].count=[20,10,1]' --set 'lattices[1].count=[20,10,20]' --set 'periodic.x=[0.0,0.022]'
       --set 'periodic.y=[0.0,0.011]' --set integrator.end_time=0.01 --set 'output={interval=0.001, particles=true}' -q)
"$cdm" "${cargs[@]}" --set neighbour_list.sort_interval=0 -o "$work/chute_plain" > /dev/null || fail "unsorted chute"
"$cdm" "${cargs[@]}" --set neighbour_list.sort_interval=200 -o "$work/chute_sorted" > /dev/null || fail "sorted chute"
agree "$work/chute_plain/particles.dat" "$work/chute_sorted/particles.dat"
echo "sorting: threads and restart bit-identical; sorted runs agree with unsorted ones to round-off"
