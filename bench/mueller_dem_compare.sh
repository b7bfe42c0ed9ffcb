#!/bin/sh
# The Müller bed's particles without the gas, on one process and on two, beside LAMMPS:
# what a bed of this size (9240 spheres) gives two processes when the gas is taken away,
# for issue #36's 2-against-1 target on the Müller bed. cdm runs the coupled scene to T
# once (the drag once per gas step, its particle table sampled at T), writes that sample
# as a DEM-only scene (bench/dem_only_state.py) and as a LAMMPS data file
# (bench/drum_stl.py --data), then times STEPS steps of each code on 1 and 2 processes,
# REPS rounds alternating (cdm's "loop time", LAMMPS's "Loop time"): the coupled scene
# restarted from its checkpoint at T, the DEM-only scene, and LAMMPS
# (peers/in.mueller_dem.lammps, the same particles, walls, contact parameters and time
# step). Both DEM-only runs start without contact history and the bed begins to fall.
# Usage: bench/mueller_dem_compare.sh [OUT]   (env: T=0.3, STEPS=3000, REPS=3,
#        CDM=build/release/app/cdm)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
out=${1:-/tmp/mueller_dem_compare}
CDM=${CDM:-$root/build/release/app/cdm}
T=${T:-0.3}
STEPS=${STEPS:-3000}
REPS=${REPS:-3}
PY=/usr/bin/python3
S="$root/bench/scenes/mueller_bubbling_bed.toml"
MPI="mpirun --oversubscribe -np 2"
[ "$(id -u)" = 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
export OMP_NUM_THREADS=1
mkdir -p "$out"
out=$(cd "$out" && pwd)
if [ ! -f "$out/state/checkpoint.cdmck" ]; then
  "$CDM" run "$S" -q -j 2 -o "$out/state" --set 'coupling.drag_evaluation="gas_step"' --set integrator.end_time="$T" \
      --set output.interval=0.05 --set output.checkpoint_interval="$T" --set output.vtk=false --set output.particles=true
fi
$PY "$here/dem_only_state.py" "$S" "$out/state/particles.dat" "$T" "$out/dem.toml"
dt=$(sed -n 's/.*dt = \([0-9.e+-]*\) s.*/\1/p' "$out/state/particles.dat" | head -1)
$PY "$here/drum_stl.py" --data "$out/state/particles.dat" "$out/mueller.data" --time "$T" --density 1000 \
    --box 0 0.044 0 0.12 0 0.01
quiet="--set output.vtk=false --set output.particles=false -q -j 1 --max-steps $STEPS"
cdm_loop() { sed -n 's/^loop time \([0-9.]*\) s.*/\1/p' "$1"; }
lmp_loop() { sed -n 's/^Loop time of \([0-9.]*\) on.*/\1/p' "$1" | tail -1; }
: > "$out/times.txt"
for r in $(seq "$REPS"); do
  for np in 1 2; do
    run=""; [ "$np" = 2 ] && run=$MPI
    $run "$CDM" run "$S" --restart "$out/state/checkpoint.cdmck" --set 'coupling.drag_evaluation="gas_step"' \
        $quiet -o "$out/run" > "$out/coupled$np.log" 2>&1
    echo "coupled $np $(cdm_loop "$out/coupled$np.log")" >> "$out/times.txt"
    $run "$CDM" run "$out/dem.toml" $quiet -o "$out/run" > "$out/dem$np.log" 2>&1
    echo "cdm_dem $np $(cdm_loop "$out/dem$np.log")" >> "$out/times.txt"
    (cd "$out" && $run lmp -in "$here/peers/in.mueller_dem.lammps" -log "lammps$np.log" -var data mueller.data \
        -var dt "$dt" -var nsteps "$STEPS" -var skin 0.00012 > "lammps$np.screen" 2>&1)
    echo "lammps $np $(lmp_loop "$out/lammps$np.log")" >> "$out/times.txt"
  done
done
$PY - "$out/times.txt" "$STEPS" <<'PYEOF'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    code, np, t = line.split()
    runs.setdefault((code, np), []).append(float(t))
print(f"| {sys.argv[2]} steps from the state at T | one process (s) | two processes (s) | two against one (medians) |")
print("|---|---|---|---|")
for code in ("coupled", "cdm_dem", "lammps"):
    one, two = runs[(code, "1")], runs[(code, "2")]
    fmt = lambda v: ", ".join(f"{x:.3f}" for x in v)
    print(f"| {code} | {fmt(one)} | {fmt(two)} | {statistics.median(one) / statistics.median(two):.2f}x |")
PYEOF
