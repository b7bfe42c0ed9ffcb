#!/usr/bin/env bash
# Spatial sorting (neighbour_list.sort_interval) reorders the particles in memory and
# changes nothing else, to the bit: the list lists its pairs in the order of their
# particles' keys (slab, cells, identity; VerletList::key_order), not of their slots, and
# orients each pair by identity, so each particle's contact forces are added in the same
# order however the particles are stored.
# - the settle benchmark's 10,000 frictional spheres, 4,000 steps sorted every 100
#   steps: tables bit-identical to an unsorted run's, on 1 and 2 threads; a run split
#   by a checkpoint (taken after several sorts) and restarted equals the uninterrupted
#   one bit for bit;
# - a Hertz–Mindlin pile with friction and rolling resistance (tests/cli/scenes/
#   hertz_pile.toml), whose constant-torque rule stops a contact's rolling given the
#   torques of the contacts visited before it: sorted and unsorted runs bit-identical;
# - the small periodic chute (wrapping particles, fixed base): sorted against unsorted,
#   bit-identical, also when a restart changes the sort interval.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"

same() { cmp -s "$1" "$2" || fail "$3: $1 and $2 differ"; }

settle="$src/bench/scenes/settle_1e4.toml"
args=(run "$settle" -q --set integrator.end_time=0.0064334 --set output.interval=0.002)
sorted=(--set neighbour_list.sort_interval=100)
"$cdm" "${args[@]}" --set neighbour_list.sort_interval=0 -o "$work/plain" -j 1 > /dev/null || fail "unsorted run"
"$cdm" "${args[@]}" "${sorted[@]}" -o "$work/one" -j 1 > /dev/null || fail "sorted 1-thread run"
"$cdm" "${args[@]}" "${sorted[@]}" -o "$work/two" -j 2 > /dev/null || fail "sorted 2-thread run"
same "$work/one/particles.dat" "$work/two/particles.dat" "sorted, 1 and 2 threads"
same "$work/plain/particles.dat" "$work/one/particles.dat" "settle, unsorted and sorted"

# Restart with sorting: a checkpoint after several sorts.
set_args=("${sorted[@]}" --set integrator.end_time=0.0064334 --set output.interval=0.001
          --set output.checkpoint_interval=0.003 -q)
mkdir -p "$work/restart"
restart_matches "sorted" "$settle" "$work/restart" 2345 "${set_args[@]}"

# Hertz–Mindlin with friction and rolling resistance (its torques go through the
# contact list, in list order): sorted and unsorted, 1 and 2 threads, bit-identical.
pile="$src/tests/cli/scenes/hertz_pile.toml"
pargs=(run "$pile" -q --set integrator.end_time=0.002 --set output.interval=0.0005 --set neighbour_list.sort_interval=50)
"$cdm" "${pargs[@]}" -o "$work/pile_one" -j 1 > /dev/null || fail "sorted pile, 1 thread"
"$cdm" "${pargs[@]}" -o "$work/pile_two" -j 2 > /dev/null || fail "sorted pile, 2 threads"
"$cdm" "${pargs[@]}" --set neighbour_list.sort_interval=0 -o "$work/pile_plain" > /dev/null || fail "unsorted pile"
same "$work/pile_one/particles.dat" "$work/pile_two/particles.dat" "sorted pile, 1 and 2 threads"
same "$work/pile_plain/particles.dat" "$work/pile_one/particles.dat" "pile, unsorted and sorted"

# The periodic chute: particles wrap through the faces between sorts.
chute="$src/bench/scenes/chute32k.toml"
cargs=(run "$chute" --set 'lattices[0].count=[20,10,1]' --set 'lattices[1].count=[20,10,20]' --set 'periodic.x=[0.0,0.022]'
       --set 'periodic.y=[0.0,0.011]' --set integrator.end_time=0.01 --set 'output={interval=0.001, particles=true}' -q)
"$cdm" "${cargs[@]}" --set neighbour_list.sort_interval=0 -o "$work/chute_plain" > /dev/null || fail "unsorted chute"
"$cdm" "${cargs[@]}" --set neighbour_list.sort_interval=200 -o "$work/chute_sorted" > /dev/null || fail "sorted chute"
same "$work/chute_plain/particles.dat" "$work/chute_sorted/particles.dat" "chute, unsorted and sorted"
# A restart may change the sort interval: the sorted chute stopped after 3000 steps and
# continued unsorted, and the unsorted one continued sorted every 50 steps, end with the
# tables of the runs not stopped.
for way in "200 0 sorted" "0 50 chute_plain"; do
  read -r before after whole <<< "$way"
  [ "$whole" = sorted ] && whole=chute_sorted
  dir="$work/chute_resorted_$before"
  "$cdm" "${cargs[@]}" --set neighbour_list.sort_interval="$before" -o "$dir" --max-steps 3000 > /dev/null ||
    fail "chute sorted every $before steps, first part"
  cp "$dir/checkpoint.cdmck" "$work/half_$before.cdmck"
  "$cdm" "${cargs[@]}" --set neighbour_list.sort_interval="$after" -o "$dir" --restart "$work/half_$before.cdmck" \
    > /dev/null || fail "chute sorted every $before steps, restarted sorting every $after"
  same "$work/$whole/particles.dat" "$dir/particles.dat" "chute, sort interval $before then $after after a restart"
done
echo "sorting: sorted runs bit-identical to unsorted ones (settle, a rolling pile, the chute), on 1 and 2 threads and across a restart, also one that changes the sort interval"
