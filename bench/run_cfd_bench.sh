#!/usr/bin/env bash
# CFD-DEM throughput of cdm on three beds, and of DPMFoam on the one both codes run
# (bench/README.md, "CFD-DEM beside DPMFoam"), one core each, REPS repetitions:
#   mueller      bench/scenes/mueller_bubbling_bed.toml (9240 particles, 15 x 40 x 3 cells)
#   goldschmidt  bench/scenes/goldschmidt.toml and DPMFoam's Goldschmidt tutorial
#                (bench/peers/dpmfoam_goldschmidt.sh): 24,750 particles, 2 x 30 x 90 cells
#   bed1e5       bench/scenes/bed_1e5.toml (100,000 particles, 24 x 96 x 24 cells)
#   bench/run_cfd_bench.sh [PROBLEM ...]          (default: all three)
# Each run simulates the problem's time from its initial state and ends with a sample,
# from which bench/bed_stats.py takes the pressure drop (lowest minus highest layer of
# cells) and the bed height. bench/summarise_cfd.py prints per problem and code the
# median loop time and each run's, the wall time per simulated second, particle-steps/s,
# cdm's speed against DPMFoam, and the pressure drop and bed height (written to
# OUT/summary.md; raw logs in OUT/raw/, runs in OUT/runs.txt). Loop time is cdm's own
# timer around the time-stepping loop and DPMFoam's ClockTime; CPU time is the process's
# user + system time (cdm: /usr/bin/time, loading included; DPMFoam: its ExecutionTime),
# which a shared host inflates less than wall time; the 1-minute load average before and
# after each run is in OUT/load.txt.
# Environment: REPS (default 3), CDM (default build/release/app/cdm), OUT (default
# bench/results/cfd), MUELLER_T (simulated s, default 0.1), GOLDSCHMIDT_T (default 0.02),
# BED_T (default 0.1), CODES (default "cdm dpmfoam": dpmfoam runs goldschmidt only).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"
cdm="${CDM:-$root/build/release/app/cdm}"
reps="${REPS:-3}"
out="${OUT:-$here/results/cfd}"
problems=("$@")
[ ${#problems[@]} -gt 0 ] || problems=(mueller goldschmidt bed1e5)
read -r -a codes <<< "${CODES:-cdm dpmfoam}"
for code in "${codes[@]}"; do
  case $code in
    cdm|dpmfoam) ;;
    *) echo "CODES: unknown code '$code' (expected cdm, dpmfoam)" >&2; exit 2 ;;
  esac
done

# problem -> scene cells simulated_time vertical_axis
problem() {
  case $1 in
    mueller) echo "mueller_bubbling_bed.toml 1800 ${MUELLER_T:-0.1} y" ;;
    goldschmidt) echo "goldschmidt.toml 5400 ${GOLDSCHMIDT_T:-0.02} z" ;;
    bed1e5) echo "bed_1e5.toml 55296 ${BED_T:-0.1} y" ;;
    *) echo "unknown problem '$1' (expected mueller, goldschmidt, bed1e5)" >&2; exit 2 ;;
  esac
}
for prob in "${problems[@]}"; do problem "$prob" > /dev/null; done
[ -x "$cdm" ] || { echo "build cdm first (scripts/build.sh release)"; exit 1; }
export OMP_NUM_THREADS=1

field() { echo "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"; }  # field LINE KEY: the value of KEY=value

run_one() {  # code problem rep -> appends a line of summarise_cfd.py's runs file to $out/runs.txt
  local code=$1 prob=$2 rep=$3 scene cells t axis
  read -r scene cells t axis < <(problem "$prob")
  local dir="$out/raw/${code}_${prob}_r${rep}" line n psteps loop cpu stats
  rm -rf "$dir"; mkdir -p "$dir"
  echo "$code $prob r$rep $(cut -d' ' -f1 /proc/loadavg)" >> "$out/load.txt"
  if [ "$code" = cdm ]; then
    /usr/bin/time -f "%U %S" -o "$dir/time.txt" "$cdm" run "$here/scenes/$scene" -o "$dir" -q -j 1 \
      --set "integrator.end_time=$t" --set "output.interval=$t" --set output.vtk=true --set 'output.vtk_format="ascii"' --set output.particles=true \
      > "$dir/log.txt"
    cpu=$(awk '{printf "%.2f", $1 + $2}' "$dir/time.txt")
    # "loop time X s for S steps of N particles on 1 thread(s): ..."
    read -r loop steps n < <(awk '/^loop time/ {print $3, $6, $9}' "$dir/log.txt")
    psteps=$(awk -v s="$steps" -v n="$n" 'BEGIN {printf "%.0f", s * n}')
    stats=$(/usr/bin/python3 "$here/bed_stats.py" cdm "$dir" --axis "$axis")
    rm -rf "$dir/checkpoint.cdmck" "$dir/particles.dat" "$dir/vtk"  # hundreds of MB over the repetitions
  else
    line=$("$here/peers/dpmfoam_goldschmidt.sh" "$t" "$dir" | tee "$dir/summary.txt" | tail -1)
    loop=$(field "$line" wall_s)
    cpu=$(field "$line" cpu_s)
    n=24750
    psteps=$(awk -v s="$(field "$line" substeps)" -v n="$n" 'BEGIN {printf "%.0f", s * n}')
    stats=$line
    rm -rf "$dir/case/processor"* "$dir/case/"[0-9]*/lagrangian
  fi
  echo "$code $prob $n $cells $t $psteps $loop $cpu $(field "$stats" dp) $(field "$stats" bed_height) $(field "$stats" h99)" |
    tee -a "$out/runs.txt"
  echo "$code $prob r$rep end $(cut -d' ' -f1 /proc/loadavg)" >> "$out/load.txt"
}

mkdir -p "$out"
: > "$out/runs.txt"
: > "$out/load.txt"
for prob in "${problems[@]}"; do
  for rep in $(seq 1 "$reps"); do
    for code in "${codes[@]}"; do
      [ "$code" = dpmfoam ] && [ "$prob" != goldschmidt ] && continue
      run_one "$code" "$prob" "$rep"
    done
  done
done

/usr/bin/python3 "$here/summarise_cfd.py" "$out/runs.txt" | tee "$out/summary.md"
