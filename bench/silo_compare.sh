#!/bin/sh
# Silo discharge, cdm against LIGGGHTS and Beverloo: the steady discharge rate through
# three orifices (5 d, 8 d, 12 d). cdm runs examples/silo/silo.toml with the silo of each
# orifice (scripts/stl_meshes.py silo writes it as ASCII STL); LIGGGHTS
# (peers/in.silo.liggghts) starts from cdm's t = 0 positions (silo.data) in the same STL,
# with the same contact parameters and time step. The rate is measured alike for both
# (examples/silo/beverloo.py: the slope of the mass discharged over [FROM, END] s), and
# Beverloo's C and k are fitted to each code's three rates.
# Usage: bench/silo_compare.sh [OUT]   (env: ORIFICES="0.020 0.032 0.048", END="0.8 0.8 0.7",
#        FROM=0.3, CDM=build/release/app/cdm, SKIP_CDM=1 / SKIP_LIGGGHTS=1 to reuse
#        OUT/cdm_D* / OUT/liggghts_D*)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
out=${1:-/tmp/silo_compare}
CDM=${CDM:-$root/build/release/app/cdm}
ORIFICES=${ORIFICES:-"0.020 0.032 0.048"}
END=${END:-"0.8 0.8 0.7"}
FROM=${FROM:-0.3}
PY=/usr/bin/python3
BEV="$root/examples/silo/beverloo.py"
mkdir -p "$out"
out=$(cd "$out" && pwd)
set -- $END
fit_cdm="" fit_lig=""
for D in $ORIFICES; do
  end=$1; shift
  stl="$out/silo_$D.stl"
  $PY "$root/scripts/stl_meshes.py" silo "$stl" "$D"
  c="$out/cdm_D$D"
  # The t = 0 beads, for LIGGGHTS's start.
  [ -f "$c/t0/particles.dat" ] || "$CDM" run "$root/examples/silo/silo.toml" -o "$c/t0" -q -j 1 --max-steps 1 \
      --set "meshes[0].file=\"$stl\"" --set output.particles=true
  if [ -z "${SKIP_CDM:-}" ]; then
    nice -n 10 "$CDM" run "$root/examples/silo/silo.toml" -o "$c" -q -j 1 \
      --set "meshes[0].file=\"$stl\"" --set integrator.end_time=$end
  fi
  dt=$(sed -n 's/.*dt = \([0-9.e+-]*\) s.*/\1/p' "$c/t0/particles.dat" | head -1)
  l="$out/liggghts_D$D"
  mkdir -p "$l"
  cp "$stl" "$l/silo.stl"
  $PY "$here/drum_stl.py" --data "$c/t0/particles.dat" "$l/silo.data" --box -0.065 0.065 -0.065 0.065 -0.02 0.31
  every=$($PY -c "print(round(0.01/$dt))")              # thermo every 0.01 s, as cdm's outlets.dat
  nsteps=$($PY -c "print($every*round($end/0.01))")
  # gamma_n from en = 0.7 with meff = m/2 (as bench/peers/params.inc does for en = 0.9)
  gn=$($PY -c "import math; m=2500*math.pi/6*0.004**3; me=m/2; z=-math.log(0.7)/math.sqrt(math.pi**2+math.log(0.7)**2); print(2*z*math.sqrt(1e4/me))")
  [ -n "${SKIP_LIGGGHTS:-}" ] || (cd "$l" && nice -n 10 liggghts -in "$here/peers/in.silo.liggghts" -log log.liggghts \
     -var dt "$dt" -var nsteps "$nsteps" -var thermoevery "$every" -var gn "$gn" \
     -var kn 1e4 -var kt 2857.142857142857 -var mu 0.5 -var skin 0.0004 > screen.txt 2>&1)
  m=$($PY -c "import math; print(2500*math.pi/6*0.004**3)")
  w_cdm=$($PY "$BEV" rate "$c/outlets.dat" --from "$FROM" --to "$end" 2>&1) || w_cdm="(no cdm run)"
  w_lig=$($PY "$BEV" rate "$l/log.liggghts" --liggghts --dt "$dt" --mass "$m" --from "$FROM" --to "$end" 2>&1) || w_lig="(no LIGGGHTS run)"
  echo "D = $D m  cdm: $w_cdm  |  LIGGGHTS: $w_lig"
  fit_cdm="$fit_cdm $D:$(echo "$w_cdm" | sed 's/W = \([0-9.e+-]*\) .*/\1/')"
  fit_lig="$fit_lig $D:$(echo "$w_lig" | sed 's/W = \([0-9.e+-]*\) .*/\1/')"
done
# A fit needs each orifice's rate from the code (a skipped run has none).
case "$fit_cdm" in *"(no"*) ;; *) echo "Beverloo fit, cdm:"; $PY "$BEV" fit $fit_cdm ;; esac
case "$fit_lig" in *"(no"*) ;; *) echo "Beverloo fit, LIGGGHTS:"; $PY "$BEV" fit $fit_lig ;; esac
