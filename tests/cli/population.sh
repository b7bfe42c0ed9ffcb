#!/usr/bin/env bash
# Insertion and removal (tests/cli/scenes/feed_and_drain.toml): the mass balance over the
# whole time series and the insertion rate (check_population.py); restarts at several
# points, each from the last one's checkpoint, give the uninterrupted run's particles.dat,
# outlets.dat and final state bit for bit; 1 and 3 threads give the same tables.
set -u
cdm="$1" src="$2" work="$3"
. "$src/tests/cli/common.sh"
rm -rf "$work"; mkdir -p "$work"
scene="$src/tests/cli/scenes/feed_and_drain.toml"
check="$src/tests/cli/check_population.py"

# A smaller bed for the restarts (400 particles; the insertion and outlets as they are).
small=(--set 'lattices[0].count=[10,10,4]' --set output.checkpoint_interval=0.01)
"$cdm" run "$scene" -q -o "$work/full" "${small[@]}" > /dev/null || fail "uninterrupted run"
python3 "$check" "$work/full" 2500 20000 0.002 300 || fail "mass balance or rate"
# Stopped and restarted at steps 1 (before any insertion), 400 (the first events), 2000
# (insertion and removal under way) and 4500 (inserted all, draining).
"$cdm" run "$scene" -q -o "$work/split" "${small[@]}" --max-steps 1 > /dev/null || fail "part 1"
at=1
for next in 400 2000 4500; do
  cp "$work/split/checkpoint.cdmck" "$work/at$at.cdmck"
  "$cdm" run "$scene" -q -o "$work/split" "${small[@]}" --restart "$work/at$at.cdmck" --max-steps $((next - at)) > /dev/null ||
    fail "restart at step $at"
  at=$next
done
cp "$work/split/checkpoint.cdmck" "$work/at$at.cdmck"
"$cdm" run "$scene" -q -o "$work/split" "${small[@]}" --restart "$work/at$at.cdmck" > /dev/null || fail "last restart"
for f in particles.dat outlets.dat checkpoint.cdmck; do
  cmp -s "$work/full/$f" "$work/split/$f" || fail "restarted $f differs from the uninterrupted run's"
done
echo "population: restarts at steps 1, 400, 2000 and 4500 bit-identical"
# The same with the paper's Euler scheme (forces from the step before: the inserted
# particles' weight), restarted once.
restart_matches "paper_euler" "$scene" "$work/euler" 1777 "${small[@]}" -q --set 'integrator.scheme="paper_euler"' \
  --set integrator.end_time=0.015
python3 "$check" "$work/euler/full" 2500 20000 0.002 300 || fail "mass balance or rate (paper_euler)"

# 4,000 particles and more (threads start at 4,096): one and three threads.
args=(run "$scene" -q --set integrator.end_time=0.012)
"$cdm" "${args[@]}" -o "$work/one" -j 1 > /dev/null || fail "1-thread run"
"$cdm" "${args[@]}" -o "$work/three" -j 3 > /dev/null || fail "3-thread run"
python3 "$check" "$work/one" 2500 20000 0.002 300 || fail "mass balance or rate (4,000 particles)"
for f in particles.dat outlets.dat; do
  cmp -s "$work/one/$f" "$work/three/$f" || fail "1 and 3 threads give different $f"
done
echo "population: 1 and 3 threads bit-identical"

# A particle that leaves the gas domain through an outlet is removed; without the outlet
# there it stops the run (exit 3).
drop="$src/tests/cli/scenes/drop_through_outlet.toml"
"$cdm" run "$drop" -q -o "$work/drop" > /dev/null || fail "a particle leaving through an outlet stopped the run"
tail -1 "$work/drop/outlets.dat" | awk '{exit !($4 == 1 && $(NF-1) == 0)}' || fail "the outlet did not record the particle"
"$cdm" run "$drop" -q -o "$work/drop2" --set 'outlets[0].point=[0.0,0.0,-0.01]' > /dev/null 2> "$work/drop2.err"
rc=$?
[ $rc -eq 3 ] && grep -q "left the gas domain" "$work/drop2.err" || fail "leaving the gas domain elsewhere: exit $rc, expected 3"
echo "population: an outlet at the gas domain's face removes, elsewhere leaving it stops the run"

# The example (examples/bed_fed_from_above) runs as its README says, shortened to its
# first 0.08 s (the drain working, six insertions), and balances.
"$cdm" run "$src/examples/bed_fed_from_above/scene.toml" -q -o "$work/example" --set integrator.end_time=0.08 > /dev/null ||
  fail "the example does not run"
python3 "$check" "$work/example" 2500 4000 0.005 2000 0.05 || fail "the example's balance"
