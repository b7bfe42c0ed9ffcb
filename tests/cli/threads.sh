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
# A bed two-way coupled to a gas, the drag evaluated once per gas step: each thread
# deposits its share of the 8,000 beads' impulses and volumes in sums of its own, added
# up over the cells its beads reached (TwoWayExchange::deposit_sums). The particle table
# and the checkpoint (the gas with them) on 1, 2 and 3 threads.
bed=(run "$src/bench/scenes/bed_1e5.toml" -q --set 'random_particles[0].count=8000' --set integrator.end_time=7.5e-4
     --set output.interval=2.5e-4 --set output.vtk=false --set output.particles=true --set output.checkpoint_interval=7.5e-4)
for j in 1 2 3; do
  "$cdm" "${bed[@]}" -o "$work/bed-$j" -j "$j" > /dev/null || { echo "FAIL: the coupled bed on $j threads"; exit 1; }
done
for j in 2 3; do
  for f in particles.dat checkpoint.cdmck; do
    cmp -s "$work/bed-1/$f" "$work/bed-$j/$f" || { echo "FAIL: the coupled bed's $f on 1 and $j threads differ"; exit 1; }
  done
done
echo "threads: 1, 2 and 3 threads bit-identical (the settling bed, and a coupled bed's deposits)"
