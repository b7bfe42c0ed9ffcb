#!/usr/bin/env bash
# Results do not depend on the thread count: the settle benchmark's 10,000 frictional
# spheres (above the 4,096-particle threshold where threads start) run 8,000 steps on
# 1, 2 and 3 OpenMP threads and write bit-identical particle tables. Each thread takes
# its own share of the particles and of the contact list's slabs, so 3 threads (more
# than the machine's cores, and an odd count: shares that start on odd slabs) check
# another split than 2.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
args=(run "$src/bench/scenes/settle_1e4.toml" -q --set integrator.end_time=0.0128667 --set output.interval=0.004)
"$cdm" "${args[@]}" -o "$work/one" -j 1 > /dev/null || { echo "FAIL: 1-thread run"; exit 1; }
"$cdm" "${args[@]}" -o "$work/two" -j 2 > /dev/null || { echo "FAIL: 2-thread run"; exit 1; }
"$cdm" "${args[@]}" -o "$work/three" -j 3 > /dev/null || { echo "FAIL: 3-thread run"; exit 1; }
cmp -s "$work/one/particles.dat" "$work/two/particles.dat" || { echo "FAIL: 1 and 2 threads differ"; exit 1; }
cmp -s "$work/one/particles.dat" "$work/three/particles.dat" || { echo "FAIL: 1 and 3 threads differ"; exit 1; }
echo "threads: 1, 2 and 3 threads bit-identical"
