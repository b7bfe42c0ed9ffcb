#!/bin/sh
# The chute with mesh side walls (issue #35): cdm's cost with the side walls as a triangle
# mesh (bench/scenes/chute_mesh.toml, 3,520 triangles) against the same chute with plane
# side walls, and beside LIGGGHTS on the same STL (peers/in.chute_mesh.liggghts), all
# from cdm's t = 0 lattice (LIGGGHTS reads it as chute.data) for STEPS steps on one core,
# REPS times alternating; prints each run's loop time, the medians and their ratios, and
# the kinetic energy each code ends with (the same flow, to the chaos of a granular flow).
# Usage: bench/chute_mesh_compare.sh [OUT]   (env: STEPS=20000, REPS=3,
#        CDM=build/release/app/cdm)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
out=${1:-/tmp/chute_mesh_compare}
CDM=${CDM:-$root/build/release/app/cdm}
STEPS=${STEPS:-20000}
REPS=${REPS:-3}
PY=/usr/bin/python3
mkdir -p "$out"
out=$(cd "$out" && pwd)
$PY "$root/scripts/stl_meshes.py" chute
scene="$here/scenes/chute_mesh.toml"
# The same chute with plane side walls: the [[meshes]] table replaced by two planes.
$PY - "$scene" "$out/chute_planes.toml" <<'PYEOF'
import re, sys
s = open(sys.argv[1]).read()
planes = ('[[walls]]\nname = "y_low"\ntype = "plane"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\nmaterial = "side"\n\n'
          '[[walls]]\nname = "y_high"\ntype = "plane"\npoint = [0.0, 0.022, 0.0]\nnormal = [0.0, -1.0, 0.0]\nmaterial = "side"\n')
s, n = re.subn(r'\[\[meshes\]\]\nname = "sides"\nfile = "[^"]*"\nmaterial = "side"\n', planes, s)
assert n == 1
open(sys.argv[2], "w").write(s)
PYEOF
"$CDM" run "$scene" -o "$out/t0" -q -j 1 --max-steps 1 --set output.particles=true > /dev/null
mkdir -p "$out/liggghts"
cp "$here/scenes/meshes/chute_sides.stl" "$here/peers/params.inc" "$out/liggghts/"
$PY "$here/drum_stl.py" --data "$out/t0/particles.dat" "$out/liggghts/chute.data" --box 0 0.044 -0.001 0.023 -0.001 0.2
dt=$(sed -n 's/.*dt = \([0-9.e+-]*\) s.*/\1/p' "$out/t0/particles.dat" | head -1)
every=$($PY -c "print(repr($STEPS * $dt * (1 - 1e-9)))")  # a log row at the last step, as LIGGGHTS's thermo
: > "$out/times.txt"
for r in $(seq 1 "$REPS"); do
  for kind in mesh planes; do
    s=$scene; [ $kind = planes ] && s="$out/chute_planes.toml"
    "$CDM" run "$s" -o "$out/cdm_$kind" -q -j 1 --max-steps "$STEPS" --set output.log_interval=$every > "$out/cdm_$kind.txt"
    t=$(sed -n 's/^loop time \([0-9.]*\) s.*/\1/p' "$out/cdm_$kind.txt")
    echo "cdm_$kind $r $t" | tee -a "$out/times.txt"
  done
  (cd "$out/liggghts" && liggghts -in "$here/peers/in.chute_mesh.liggghts" -var nsteps "$STEPS" -var thevery "$STEPS" \
     -log log.liggghts > screen.txt 2>&1)
  t=$(sed -n 's/^Loop time of \([0-9.]*\) on.*/\1/p' "$out/liggghts/log.liggghts")
  echo "liggghts_mesh $r $t" | tee -a "$out/times.txt"
done
$PY - "$out" <<'PYEOF'
import statistics, sys
out = sys.argv[1]
t = {}
for line in open(out + "/times.txt"):
    k, _, v = line.split()
    t.setdefault(k, []).append(float(v))
m = {k: statistics.median(v) for k, v in t.items()}
for k, v in m.items():
    print("%-14s median loop time %.2f s (runs: %s)" % (k, v, ", ".join("%.2f" % x for x in t[k])))
print("cdm mesh / cdm planes: %.3f" % (m["cdm_mesh"] / m["cdm_planes"]))
print("LIGGGHTS mesh / cdm mesh: %.2f" % (m["liggghts_mesh"] / m["cdm_mesh"]))
ke = [l.split() for l in open(out + "/cdm_mesh/log.dat") if not l.startswith("#")][-1]
lg = open(out + "/liggghts/log.liggghts").read().split("Step")[-1].splitlines()
last = [l.split() for l in lg if l.strip() and l.split()[0].isdigit()][-1]
print("kinetic energy at the last step: cdm %s J (t = %s s), LIGGGHTS %s J (step %s)" % (ke[2], ke[0], last[2], last[0]))
PYEOF
