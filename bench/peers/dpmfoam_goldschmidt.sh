#!/usr/bin/env bash
# DPMFoam's Goldschmidt tutorial (OpenFOAM v1912 from Debian) as shipped, on one core, for
# end_time simulated seconds; the cdm scene of the same bed is bench/scenes/goldschmidt.toml.
#   [WRITE_INTERVAL=s] [LAYERS=n] [PROBES=1] bench/peers/dpmfoam_goldschmidt.sh [END_TIME [WORKDIR]]
#                                                   (default 0.02 s, a new temp dir)
# LAYERS=n keeps the lowest n of the lattice's 99 layers (5 x 50 sites each, 3 mm apart;
# cdm: --set 'lattices[0].count=[5,50,n]'). PROBES=1 adds a `probes` function object that
# writes p every fluid step at the cell centres of the lowest layer of cells and of layer
# 70 (z = 0.3525 m, the freeboard): `bed_stats.py openfoam CASE --probes --window W` reads
# them (single samples of DPMFoam's pressure drop are noise: average them).
# Copies the case from openfoam-examples, sets endTime (and writes in ascii, only at the
# end unless WRITE_INTERVAL is set, so that bench/bed_stats.py can read the fields; with it,
# `bed_stats.py openfoam CASE --series` gives the time series), runs blockMesh and DPMFoam
# (serial: the case's decomposeParDict is not used) and prints one line
#   dpmfoam goldschmidt end_time=.. steps=.. substeps=.. wall_s=.. cpu_s=.. wall_per_sim_s=.. dp=.. bed_height=.. h99=.. load=..
# steps counts fluid steps, substeps the collision sub-cycles of them all; wall_s is
# DPMFoam's ClockTime (blockMesh not included), cpu_s its ExecutionTime; load is the
# 1-minute load average when DPMFoam started and ended (the host is shared).
# Installs openfoam and openfoam-examples from Debian if missing, without their
# recommendations (those would replace python3-vtk9).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
end="${1:-0.02}"
every="${WRITE_INTERVAL:-$end}"
work="${2:-$(mktemp -d /tmp/dpmfoam_goldschmidt.XXXXXX)}"
src=/usr/share/doc/openfoam-examples/examples/lagrangian/DPMFoam/Goldschmidt
if [ ! -x /usr/bin/DPMFoam ] || [ ! -d "$src" ]; then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
    openfoam openfoam-examples
fi
case=$work/case
rm -rf "$case"; mkdir -p "$work"; cp -r "$src" "$case"
[ -f "$case/constant/kinematicCloudPositions.gz" ] && gunzip "$case/constant/kinematicCloudPositions.gz"
sed -i "s/^endTime .*/endTime         $end;/; s/^writeInterval .*/writeInterval   $every;/; s/^writeFormat .*/writeFormat     ascii;/" \
  "$case/system/controlDict"
if [ -n "${LAYERS:-}" ]; then
  [[ "$LAYERS" =~ ^[0-9]+$ ]] && [ "$LAYERS" -ge 1 ] && [ "$LAYERS" -le 99 ] ||
    { echo "LAYERS=$LAYERS: expected a whole number of layers from 1 to 99" >&2; exit 2; }
  # The sites' heights are 0.0015 + 0.003 k; keep k < LAYERS.
  awk -v top="$(awk -v n="$LAYERS" 'BEGIN {print 0.0015 + 0.003 * (n - 0.5)}')" '
    /^\(-?[0-9.eE+-]+ -?[0-9.eE+-]+ -?[0-9.eE+-]+\)$/ { z = $3; sub(/\)$/, "", z); if (z + 0 > top) next }
    { print }' "$case/constant/kinematicCloudPositions" > "$case/positions.tmp"
  mv "$case/positions.tmp" "$case/constant/kinematicCloudPositions"
  kept=$(grep -c '^(.*)$' "$case/constant/kinematicCloudPositions")
  [ "$kept" -eq $((250 * LAYERS)) ] || { echo "LAYERS=$LAYERS kept $kept sites, expected $((250 * LAYERS))" >&2; exit 1; }
fi
if [ "${PROBES:-0}" = 1 ]; then
  points=$(for z in 0.0025 0.3525; do for j in $(seq 0 29); do for x in -0.00375 0.00375; do
    awk -v x="$x" -v j="$j" -v z="$z" 'BEGIN {printf "            (%s %.4f %s)\n", x, -0.0725 + 0.005 * j, z}'
  done; done; done)
  marker=$(grep -n '^// \*\*\*' "$case/system/controlDict" | tail -1 | cut -d: -f1)
  {
    head -n $((marker - 1)) "$case/system/controlDict"
    printf 'functions\n{\n    pprobe\n    {\n        type probes;\n        libs ("libsampling.so");\n'
    printf '        fields (p);\n        writeControl timeStep;\n        writeInterval 1;\n        probeLocations\n        (\n'
    echo "$points"
    printf '        );\n    }\n}\n\n'
    tail -n +"$marker" "$case/system/controlDict"
  } > "$case/controlDict.tmp"
  mv "$case/controlDict.tmp" "$case/system/controlDict"
fi
load() { awk '{print $1}' /proc/loadavg; }
(
  cd "$case"
  set +u
  # shellcheck disable=SC1091
  source /usr/share/openfoam/etc/bashrc > /dev/null 2>&1 || true
  set -u
  blockMesh > log.blockMesh 2>&1
  load > load.txt
  DPMFoam > log.DPMFoam 2>&1
  load >> load.txt
)
log=$case/log.DPMFoam
grep -q '^End' "$log" || { echo "DPMFoam did not finish: see $log" >&2; exit 1; }
steps=$(grep -c '^Time = ' "$log")
# DEM steps: each fluid step's collision sub-cycles (a step without the line has one).
substeps=$(awk -v n="$steps" '/move-collide subCycles/ {s += $1; k++} END {print s + n - k}' "$log")
read -r cpu wall < <(awk '/^ExecutionTime/ {c = $3; w = $7} END {print c, w}' "$log")
stats=$(/usr/bin/python3 "$here/../bed_stats.py" openfoam "$case" --axis z)
dp=$(echo "$stats" | sed 's/.*dp=\([^ ]*\).*/\1/')
h=$(echo "$stats" | sed 's/.*bed_height=\([^ ]*\).*/\1/')
h99=$(echo "$stats" | sed 's/.*h99=\([^ ]*\).*/\1/')
per=$(awk -v w="$wall" -v e="$end" 'BEGIN {printf "%.6g", w / e}')
echo "dpmfoam goldschmidt end_time=$end steps=$steps substeps=$substeps wall_s=$wall cpu_s=$cpu wall_per_sim_s=$per dp=$dp bed_height=$h h99=$h99 load=$(paste -sd/ "$case/load.txt") case=$case"
