#!/usr/bin/env bash
# Side-by-side throughput of cdm, LAMMPS and LIGGGHTS on the settle and chute problems of
# ../../shared/bench-peers (decks copied to bench/peers/, cdm's scene in bench/scenes/).
# Runs alternate between codes (cdm on 1 thread, LAMMPS, LIGGGHTS, then each on two cores:
# cdm on 2 threads, the peers on 2 MPI ranks), REPS repetitions each; bench/summarise.py
# prints per code and problem: particles, steps, loop wall time (median and each run),
# particle-steps/s per core, peak RSS per particle, cdm's speed against the code on as
# many cores, two cores against one, and each code's cost per particle-step at 1e6
# against its own at 1e4. Installs the peers (Debian lammps, liggghts) if missing, without
# their recommendations (those pull python3-paraview, which removes python3-vtk9 that the tests need).
#   bench/run_bench.sh [PROBLEM ...]     PROBLEM in settle1e4early settle1e4 settle1e5 settle1e6 chute32k
#                                        (default: all)
# settle1e4early is settle1e4's first 1000 steps: the window settle1e6 is timed on, so the
# two compare the same physics at 1e4 and 1e6 (settle1e4's first 10,000-step segment runs
# on into collisions that settle1e6's 1000 steps do not reach).
# chute32k times 10,000 steps from a flowing state prepared once per code, as the peers'
# reference runs: 0.25 s of flow from the lattice (LAMMPS: in.chute_prep.lammps at
# dt = t_c/25, its data file read by both peers; cdm: its own scene at dt = t_c/50 up to
# a checkpoint, restarted for each timed run). Contact history starts empty in the
# peers' timed runs (they read a data file) and is carried over in cdm's (a restart).
# Then runs bench/pass_probe (the pass's memory traffic in four layouts, cdm's swept
# two ways, and three variants for a bed of one kind, without cdm) and appends its table
# to the summary.
# Environment: REPS (default 3), CDM (default build/release/app/cdm), OUT (default bench/results),
# PROBE (default build/release/bench/pass_probe), CODES (default "cdm lammps liggghts cdm2
# cdmmpi2 lammps2 liggghts2": the runs of each repetition, in this order; cdmmpi2 is cdm on
# two MPI ranks of one thread). The peak memory on two ranks is not reported: /usr/bin/time
# sees only the largest rank (or mpirun).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(dirname "$here")"
cdm="${CDM:-$root/build/release/app/cdm}"
probe="${PROBE:-$root/build/release/bench/pass_probe}"
cache_probe="${CACHE_PROBE:-$root/build/release/bench/cache_probe}"
reps="${REPS:-3}"
out="${OUT:-$here/results}"
problems=("$@")
[ ${#problems[@]} -gt 0 ] || problems=(settle1e4early settle1e4 settle1e5 settle1e6 chute32k)
read -r -a codes <<< "${CODES:-cdm lammps liggghts cdm2 cdmmpi2 lammps2 liggghts2}"
for code in "${codes[@]}"; do
  case $code in
    cdm|cdm2|cdmmpi2|lammps|lammps2|liggghts|liggghts2) ;;
    *) echo "CODES: unknown code '$code' (expected cdm, cdm2, cdmmpi2, lammps, lammps2, liggghts, liggghts2)" >&2; exit 2 ;;
  esac
done

[ -x "$cdm" ] || { echo "build cdm first (scripts/build.sh release)"; exit 1; }
export OMP_NUM_THREADS=1 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1

# problem -> nx ny steps (25 layers, segments as the peers' reference runs)
geometry() {
  case $1 in
    settle1e4early) echo "20 20 1000 1 1000" ;;
    settle1e4) echo "20 20 40000 4 10000" ;;
    settle1e5) echo "50 80 10000 1 10000" ;;
    settle1e6) echo "200 200 1000 1 1000" ;;
    chute32k) echo "40 20 10000 1 10000" ;;
    *) echo "unknown problem $1" >&2; exit 2 ;;
  esac
}

# peer CODE DIR DECK [-var NAME VALUE ...]: LAMMPS or LIGGGHTS (CODE lammps or liggghts, on
# one process; with a 2 appended, on two MPI ranks) on bench/peers/DECK, logging to DIR.
peer() {
  local code=$1 dir=$2 deck=$3 exe=lmp launch=()
  shift 3
  [ "${code%2}" = liggghts ] && exe=liggghts
  [ "$code" != "${code%2}" ] && launch=(mpirun -np 2)
  (cd "$here/peers" && /usr/bin/time -v -o "$dir/time.txt" "${launch[@]}" "$exe" -in "$deck" -log "$dir/log.txt" \
    -screen none "$@" -var thevery 2000 > "$dir/stdout.txt" 2>&1)
}

# peak_rss DIR...: the largest peak RSS in kB of the runs timed in DIR... (their time.txt)
peak_rss() {
  local d
  for d in "$@"; do cat "$d/time.txt"; done |
    awk -F: '/Maximum resident set size/ {gsub(/ /, "", $2); if ($2 > m) m = $2} END {print m + 0}'
}

run_one() {  # code problem rep -> appends "code problem N steps loop_s rss_kb segments_s" to $out/runs.txt
  local code=$1 prob=$2 rep=$3 nx ny steps nseg seg
  read -r nx ny steps nseg seg < <(geometry "$prob")
  local dir="$out/raw/${code}_${prob}_r${rep}"
  rm -rf "$dir"; mkdir -p "$dir"
  local n=$((nx * ny * 25)) rss segs
  [ "$prob" = chute32k ] && n=32000
  case $code in
    cdm|cdm2|cdmmpi2)
      local threads=1 launch=(); [ "$code" = cdm2 ] && threads=2
      [ "$code" = cdmmpi2 ] && launch=(mpirun -np 2)  # two processes of one thread
      if [ "$prob" = chute32k ]; then
        OMP_NUM_THREADS=$threads /usr/bin/time -v -o "$dir/time.txt" "${launch[@]}" "$cdm" run "$here/scenes/chute32k.toml" -o "$dir" -q \
          --set integrator.end_time=1.0 --restart "$out/prep/cdm/checkpoint.cdmck" --max-steps "$steps" > "$dir/log.txt"
        rm -f "$dir/checkpoint.cdmck"
        segs=$(awk '/^loop time/ {print $3}' "$dir/log.txt")
        rss=$(peak_rss "$dir")
      else
        # One process per segment, each restarting from the previous one's checkpoint
        # (restarts are bit-identical), so each segment has its own loop time as the
        # peers' 'run' commands do; the loop time is their sum, the peak RSS their maximum.
        local lx ly k restart=()
        lx=$(awk -v n="$nx" 'BEGIN{printf "%.6g", n*1.1e-3}'); ly=$(awk -v n="$ny" 'BEGIN{printf "%.6g", n*1.1e-3}')
        for k in $(seq 1 "$nseg"); do
          mkdir -p "$dir/seg$k"
          OMP_NUM_THREADS=$threads /usr/bin/time -v -o "$dir/seg$k/time.txt" "${launch[@]}" "$cdm" run "$here/scenes/settle_1e4.toml" \
            -o "$dir/seg$k" -q --set "lattices[0].count=[$nx,$ny,25]" --set "walls[2].point=[$lx,0.0,0.0]" \
            --set "walls[4].point=[0.0,$ly,0.0]" --set output.particles=false --set integrator.end_time=1.0 \
            "${restart[@]}" --max-steps "$seg" > "$dir/seg$k/log.txt"
          [ "$k" -gt 1 ] && rm -f "$dir/seg$((k - 1))/checkpoint.cdmck"
          restart=(--restart "$dir/seg$k/checkpoint.cdmck")
        done
        rm -f "$dir/seg$nseg/checkpoint.cdmck"
        segs=$(cat "$dir"/seg*/log.txt | awk '/^loop time/ {printf "%s%s", sep, $3; sep = ","}')
        rss=$(peak_rss "$dir"/seg*)
      fi
      [ "$code" = cdmmpi2 ] && rss=0 ;;  # two ranks: not measured (time sees only mpirun)
    *)
      if [ "$prob" = chute32k ]; then
        peer "$code" "$dir" "in.chute.${code%2}" -var nsteps "$steps" -var data "$out/prep/chute32k.data"
      else
        peer "$code" "$dir" "in.settle.${code%2}" -var nx "$nx" -var ny "$ny" -var nz 25 -var nseg "$nseg" \
          -var segsteps "$seg"
      fi
      segs=$(awk '/^Loop time/ {printf "%s%s", sep, $4; sep = ","}' "$dir/log.txt")
      rss=$(peak_rss "$dir")
      [ "$code" = "${code%2}" ] || rss=0 ;;  # two ranks: not measured (time sees only the largest)
  esac
  local loop
  loop=$(echo "$segs" | tr ',' '\n' | awk '{s += $1} END {print s}')
  echo "$code $prob $n $steps $loop $rss $segs" | tee -a "$out/runs.txt"
}

prepare_chute() {  # the flowing states the timed chute runs start from (once per code)
  mkdir -p "$out/prep/cdm"
  if [ ! -s "$out/prep/chute32k.data" ]; then
    (cd "$here/peers" && lmp -in in.chute_prep.lammps -log "$out/prep/log.lammps_prep" -screen none \
      -var out "$out/prep/chute32k.data" > /dev/null)
  fi
  # A state prepared by another cdm (another commit) may be in a checkpoint format this one
  # does not read, or come from other physics: prepared again.
  local made_by
  made_by=$("$cdm" --version)
  if [ "$(cat "$out/prep/cdm/made_by.txt" 2> /dev/null)" != "$made_by" ]; then rm -f "$out/prep/cdm/checkpoint.cdmck"; fi
  if [ ! -s "$out/prep/cdm/checkpoint.cdmck" ]; then
    OMP_NUM_THREADS=2 "$cdm" run "$here/scenes/chute32k.toml" -o "$out/prep/cdm" -q --set integrator.end_time=1.0 \
      --max-steps 155440 > "$out/prep/cdm/log.txt"
    echo "$made_by" > "$out/prep/cdm/made_by.txt"
  fi
}

# An unknown problem stops here, before anything is installed, written or run.
for prob in "${problems[@]}"; do geometry "$prob" > /dev/null; done
if ! command -v lmp > /dev/null || ! command -v liggghts > /dev/null; then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo="sudo"
  $sudo apt-get update -qq && DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends lammps liggghts openmpi-bin
fi
mkdir -p "$out"
for prob in "${problems[@]}"; do [ "$prob" = chute32k ] && prepare_chute; done

: > "$out/runs.txt"
for prob in "${problems[@]}"; do
  for rep in $(seq 1 "$reps"); do
    for code in "${codes[@]}"; do run_one "$code" "$prob" "$rep"; done
  done
done

/usr/bin/python3 "$here/summarise.py" "$out/runs.txt" | tee "$out/summary.md"

# probe_table BINARY TARGET TITLE [ARGS...]: a probe's table under TITLE, appended to the
# summary; or, where the probe is not built, how to build it.
probe_table() {
  local bin="$1" target="$2" title="$3"
  shift 3
  if [ ! -x "$bin" ]; then
    echo "no $bin: build it (cmake --build build/release --target $target) for its table"
    return
  fi
  {
    echo
    echo "$title:"
    echo
    echo '```'
    "$bin" "$@"
    echo '```'
  } | tee -a "$out/summary.md"
}

# What the memory system gives one core for the pass's traffic, on this machine, now.
probe_table "$probe" pass_probe "bench/pass_probe (velocity Verlet's pass without cdm, one thread; bench/README.md)" \
  1e4 1e5 1e6
# How much of the last-level cache one core gets here, against what the kernel reports.
probe_table "$cache_probe" cache_probe "bench/cache_probe (ns per dependent load by working set; the kernel reports a \
last-level cache of $(cat /sys/devices/system/cpu/cpu0/cache/index3/size 2>/dev/null || echo '?'))"
