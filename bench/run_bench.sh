#!/usr/bin/env bash
# Side-by-side throughput of cdm, LAMMPS and LIGGGHTS on the settle problems of
# ../../shared/bench-peers (decks copied to bench/peers/, cdm's scene in bench/scenes/).
# Runs alternate between codes (cdm on 1 thread, LAMMPS, LIGGGHTS, cdm on 2 threads),
# REPS repetitions each; prints per code and problem:
# particles, steps, loop wall time (median), particle-steps/s per core, peak RSS per
# particle, and the ratio cdm/peer. Installs the peers (Debian lammps, liggghts) if missing.
#   bench/run_bench.sh [PROBLEM ...]     PROBLEM in settle1e4 settle1e5 settle1e6 (default: all)
# Environment: REPS (default 3), CDM (default build/release/app/cdm), OUT (default bench/results).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"
cdm="${CDM:-$root/build/release/app/cdm}"
reps="${REPS:-3}"
out="${OUT:-$here/results}"
problems=("$@")
[ ${#problems[@]} -gt 0 ] || problems=(settle1e4 settle1e5 settle1e6)

if ! command -v lmp > /dev/null || ! command -v liggghts > /dev/null; then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq lammps liggghts openmpi-bin
fi
[ -x "$cdm" ] || { echo "build cdm first (scripts/build.sh release)"; exit 1; }
mkdir -p "$out"
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

# problem -> nx ny steps (25 layers, segments as the peers' reference runs)
geometry() {
  case $1 in
    settle1e4) echo "20 20 40000 4 10000" ;;
    settle1e5) echo "50 80 10000 1 10000" ;;
    settle1e6) echo "200 200 1000 1 1000" ;;
    *) echo "unknown problem $1" >&2; exit 2 ;;
  esac
}

run_one() {  # code problem rep -> appends "code problem N steps loop_s rss_kb" to $out/runs.txt
  local code=$1 prob=$2 rep=$3 nx ny steps nseg seg
  read -r nx ny steps nseg seg < <(geometry "$prob")
  local dir="$out/raw/${code}_${prob}_r${rep}"
  rm -rf "$dir"; mkdir -p "$dir"
  local n=$((nx * ny * 25)) loop
  case $code in
    cdm|cdm2)
      local threads=1; [ "$code" = cdm2 ] && threads=2
      local lx ly
      lx=$(awk -v n="$nx" 'BEGIN{printf "%.6g", n*1.1e-3}'); ly=$(awk -v n="$ny" 'BEGIN{printf "%.6g", n*1.1e-3}')
      OMP_NUM_THREADS=$threads /usr/bin/time -v -o "$dir/time.txt" "$cdm" run "$here/scenes/settle_1e4.toml" -o "$dir" -q \
        --set "lattices[0].count=[$nx,$ny,25]" --set "walls[2].point=[$lx,0.0,0.0]" --set "walls[4].point=[0.0,$ly,0.0]" \
        --set output.particles=false --set integrator.end_time=1.0 --max-steps "$steps" > "$dir/log.txt"
      rm -f "$dir/checkpoint.cdmck"
      loop=$(awk '/^loop time/ {print $3}' "$dir/log.txt") ;;
    lammps|liggghts)
      local exe=lmp; [ "$code" = liggghts ] && exe=liggghts
      (cd "$here/peers" && /usr/bin/time -v -o "$dir/time.txt" "$exe" -in "in.settle.$code" -log "$dir/log.txt" \
        -screen none -var nx "$nx" -var ny "$ny" -var nz 25 -var nseg "$nseg" -var segsteps "$seg" -var thevery 2000 \
        > "$dir/stdout.txt" 2>&1)
      loop=$(awk '/Loop time/ {s += $4} END {print s}' "$dir/log.txt") ;;
  esac
  local rss
  rss=$(awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); print $2}' "$dir/time.txt")
  echo "$code $prob $n $steps $loop $rss" | tee -a "$out/runs.txt"
}

: > "$out/runs.txt"
for prob in "${problems[@]}"; do
  for rep in $(seq 1 "$reps"); do
    for code in cdm lammps liggghts cdm2; do run_one "$code" "$prob" "$rep"; done
  done
done

/usr/bin/python3 - "$out/runs.txt" <<'PY' | tee "$out/summary.md"
import statistics, sys
from collections import defaultdict
runs = defaultdict(list)
for line in open(sys.argv[1]):
    code, prob, n, steps, loop, rss = line.split()
    runs[(prob, code)].append((float(loop), int(rss), int(n), int(steps)))
print("| problem | code | threads | N | steps | loop wall s (median of %d) | particle-steps/s per core | peak RSS bytes/particle | 1-thread cdm speed / code |" % max(len(v) for v in runs.values()))
print("|---|---|---|---|---|---|---|---|---|")
for prob in sorted({p for p, _ in runs}):
    med = {c: statistics.median(r[0] for r in runs[(prob, c)]) for (p, c) in runs if p == prob}
    for code in ("cdm", "cdm2", "lammps", "liggghts"):
        if (prob, code) not in runs: continue
        r = runs[(prob, code)]
        n, steps = r[0][2], r[0][3]
        threads = 2 if code == "cdm2" else 1
        rss = statistics.median(x[1] for x in r) * 1024 / n
        ratio = "-" if code == "cdm" else "%.2f" % (med[code] / med["cdm"])
        name = "cdm" if code == "cdm2" else code
        print(f"| {prob} | {name} | {threads} | {n} | {steps} | {med[code]:.2f} | {n*steps/med[code]/threads:.3g} | {rss:.0f} | {ratio} |")
PY
