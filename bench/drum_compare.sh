#!/bin/sh
# Rotating drum, cdm against LIGGGHTS: the dynamic angle of repose at two speeds.
# cdm runs examples/rotating_drum/drum.toml; LIGGGHTS (peers/in.drum.liggghts) starts
# from cdm's t = 0 positions (drum.data) in a drum triangulated by drum_stl.py (the faces
# at the cylinder's radius), with the same contact parameters and time step. The angle is
# measured alike for both (examples/rotating_drum/repose_angle.py) from FROM seconds on.
# Usage: bench/drum_compare.sh [OUT]   (env: SPEEDS="1.0 3.0", END="4.0 3.0", FROM=1.5,
#        CDM=build/release/app/cdm, SKIP_CDM=1 / SKIP_LIGGGHTS=1 to reuse OUT/cdm_w* /
#        OUT/liggghts_w*)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
out=${1:-/tmp/drum_compare}
CDM=${CDM:-$root/build/release/app/cdm}
SPEEDS=${SPEEDS:-"1.0 3.0"}
END=${END:-"4.0 3.0"}
FROM=${FROM:-1.5}
PY=/usr/bin/python3
mkdir -p "$out"
$PY "$here/drum_stl.py" "$out/drum.stl" --radius 0.05 --length 0.018 --segments 120
set -- $END
for w in $SPEEDS; do
  end=$1; shift
  c="$out/cdm_w$w"
  if [ -z "${SKIP_CDM:-}" ]; then
    nice -n 10 "$CDM" run "$root/examples/rotating_drum/drum.toml" -o "$c" -q -j 1 \
      --set walls[0].motion.angular_velocity=$w --set integrator.end_time=$end
  fi
  dt=$(sed -n 's/.*dt = \([0-9.e+-]*\) s.*/\1/p' "$c/particles.dat" | head -1)
  l="$out/liggghts_w$w"
  mkdir -p "$l"
  cp "$out/drum.stl" "$l/"
  $PY "$here/drum_stl.py" --data "$c/particles.dat" "$l/drum.data"
  every=$($PY -c "print(round(0.1/$dt))")               # a dump every 0.1 s, as cdm's output
  nsteps=$($PY -c "print($every*round($end/0.1))")      # ending on a dump
  period=$($PY -c "import math; print(2*math.pi/$w)")
  # gamma_n from en = 0.9 with meff = m/2 (bench/peers/params.inc)
  gn=$($PY -c "import math; m=2500*math.pi/6*0.003**3; me=m/2; z=-math.log(0.9)/math.sqrt(math.pi**2+math.log(0.9)**2); print(2*z*math.sqrt(1e3/me))")
  [ -n "${SKIP_LIGGGHTS:-}" ] || (cd "$l" && nice -n 10 liggghts -in "$here/peers/in.drum.liggghts" -log log.liggghts \
     -var dt "$dt" -var nsteps "$nsteps" -var period "$period" -var dumpevery "$every" -var gn "$gn" \
     -var kn 1e3 -var kt 285.7142857142857 -var mu 0.5 -var skin 0.0003 > screen.txt 2>&1)
  a_cdm=$($PY "$root/examples/rotating_drum/repose_angle.py" "$c/particles.dat" --from "$FROM")
  a_lig=$($PY "$root/examples/rotating_drum/repose_angle.py" "$l/dump.drum" --format liggghts --dt "$dt" --from "$FROM")
  echo "omega $w rad/s  cdm: $a_cdm  |  LIGGGHTS: $a_lig"
done
