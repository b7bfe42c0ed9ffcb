#!/usr/bin/env bash
# DPMFoam's Goldschmidt tutorial (OpenFOAM v1912 from Debian) as shipped, on one core, for
# end_time simulated seconds; the cdm scene of the same bed is bench/scenes/goldschmidt.toml.
#   [WRITE_INTERVAL=s] bench/peers/dpmfoam_goldschmidt.sh [END_TIME [WORKDIR]]    (default 0.02 s, a new temp dir)
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
