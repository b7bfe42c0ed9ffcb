#!/usr/bin/env bash
# Fault injection: a checkpointing run (343 spheres of the settle benchmark, a checkpoint
# every 2 ms of simulated time, particle table and VTK on) killed with SIGKILL at KILLS
# random moments, each time restarted from the checkpoint it left, and at last run to its
# end. The particle table and the VTK collection must equal the uninterrupted run's byte
# for byte, however many rows or frames the killed run wrote after its last checkpoint.
# Usage: kill_restart.sh CDM SRC WORK [KILLS]
set -u
cdm="$1" src="$2" work="$3" kills="${4:-5}"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
scene="$src/bench/scenes/settle_1e4.toml"
args=(--set 'lattices[0].count=[7,7,7]' --set integrator.end_time=0.05 --set output.interval=0.001
      --set output.checkpoint_interval=0.002 --set output.vtk=true -q -j1)

"$cdm" run "$scene" -o "$work/full" "${args[@]}" > /dev/null || fail "uninterrupted run"
start=$(date +%s%N)
"$cdm" run "$scene" -o "$work/probe" "${args[@]}" > /dev/null || fail "timing run"
run_ms=$(( ($(date +%s%N) - start) / 1000000 ))
rm -rf "$work/probe"

# check_chain DIR: DIR's table and VTK files are the uninterrupted run's.
check_chain() {
  cmp "$work/full/particles.dat" "$1/particles.dat" || fail "table after $killed kills differs from the uninterrupted run's"
  cmp "$work/full/particles.pvd" "$1/particles.pvd" || fail "VTK collection after $killed kills differs"
  cmp "$work/full/walls.pvd" "$1/walls.pvd" || fail "VTK wall collection after $killed kills differs"
  for f in "$work/full"/vtk/*.vtp; do
    cmp -s "$f" "$1/vtk/$(basename "$f")" || fail "VTK frame $(basename "$f") after $killed kills differs"
  done
}

# Each run is killed after a random delay; when a chain of restarts reaches the end
# before it is killed, its files are checked and a new chain starts in a fresh directory.
RANDOM=${KILL_SEED:-31}
chain=0 out="$work/killed0" killed=0
while [ "$killed" -lt "$kills" ]; do
  restart=()
  [ -s "$out/checkpoint.cdmck" ] && restart=(--restart "$out/checkpoint.cdmck")
  "$cdm" run "$scene" -o "$out" "${args[@]}" "${restart[@]}" > /dev/null 2> "$work/err" &
  pid=$!
  delay_ms=$(( 20 + RANDOM % (2 * run_ms / kills + 1) ))
  sleep "$(printf '%d.%03d' $((delay_ms / 1000)) $((delay_ms % 1000)))"
  kill -KILL "$pid" 2> /dev/null
  wait "$pid" 2> /dev/null
  rc=$?
  case $rc in
    137) killed=$((killed + 1)) ;;
    0) check_chain "$out"; chain=$((chain + 1)); out="$work/killed$chain" ;;
    *) fail "run killed after ${delay_ms} ms: exit status $rc: $(cat "$work/err")" ;;
  esac
done
restart=()
[ -s "$out/checkpoint.cdmck" ] && restart=(--restart "$out/checkpoint.cdmck")
"$cdm" run "$scene" -o "$out" "${args[@]}" "${restart[@]}" > /dev/null 2> "$work/err" || fail "last restart: $(cat "$work/err")"
check_chain "$out"
echo "kill_restart: ok ($killed kills, $((chain + 1)) chain(s))"
