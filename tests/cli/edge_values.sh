#!/usr/bin/env bash
# cdm run with the edge values a careless user types: each absurd value is refused with
# exit status 2, a message naming the key at fault and no output directory; extreme but
# meaningful values run, and the output samples stay right for any interval.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
. "$(dirname "$0")/common.sh"

scene="$src/verification/cases/free_fall/scene.toml"

# refused TAG SCENE 'FRAGMENT...' ARGS...: exit 2, every fragment in the message, nothing written.
refused() {
  local tag=$1 sc=$2 frags=$3 f
  shift 3
  timeout 20 "$cdm" run "$sc" -o "$work/out-$tag" "$@" > /dev/null 2> "$work/err-$tag.txt"; local rc=$?
  [ "$rc" -eq 2 ] || fail "$tag: exited $rc, expected 2: $(cat "$work/err-$tag.txt")"
  IFS='|' read -ra parts <<< "$frags"
  for f in "${parts[@]}"; do
    grep -qF -- "$f" "$work/err-$tag.txt" || fail "$tag: message lacks '$f': $(cat "$work/err-$tag.txt")"
  done
  [ ! -e "$work/out-$tag" ] || fail "$tag: a refused scene left output behind"
}

# rows ARGS...: the number of table rows of the free-fall case run with ARGS.
rows() {
  rm -rf "$work/out-rows"
  timeout 60 "$cdm" run "$scene" -o "$work/out-rows" "$@" > /dev/null || fail "run with $* failed"
  grep -vc '^#' "$work/out-rows/particles.dat"
}

# Overflows: a step count beyond the ceiling, a time step or a mass that underflows.
refused end_time "$scene" "integrator.end_time|1e+12 steps|1.07778e+20 steps" --set integrator.end_time=1e17
refused stiff "$scene" "integrator.end_time|7.62105e+13 steps" --set 'contacts[0].kn=1e30'
refused tiny "$scene" "particles[0].radius|underflows" --set 'particles[0].radius=1e-300'
refused subnormal_dt "$scene" "integrator.dt|normal floating-point" --set integrator.dt=1e-320

# The output samples: an interval below dt samples every step (540 steps and t = 0).
for iv in 1e-20 1e-100; do
  n=$(rows --set output.interval=$iv)
  [ "$n" -eq 540 ] || fail "output.interval = $iv wrote $n rows, expected 540 (every step)"
done
n=$(rows)
[ "$n" -eq 501 ] || fail "output.interval = 1e-3 wrote $n rows, expected 501"

# Scene files refused before reading: a directory, a device that never ends.
refused scene_dir "$work" "is a directory|expected a scene file"
refused dev_zero /dev/zero "is not a regular file|expected a scene file"

# Messages that name the real fault.
refused dense "$scene" "integrator.dt|collision time|densities" --set 'materials[0].density=1e300'
refused huge "$scene" "particles[0].radius|overflows" --set 'particles[0].radius=1e300'
refused date "$scene" "particles[0].position|1979-05-27" --set 'particles[0].position=1979-05-27'
for n in '[0,1e200,0]' '[0,1e-320,0]'; do
  "$cdm" run "$scene" -o "$work/out-normal" --set "walls[0].normal=$n" --set integrator.end_time=0.01 > /dev/null \
    2> "$work/err-normal.txt" || fail "walls[0].normal = $n refused: $(cat "$work/err-normal.txt")"
  rm -rf "$work/out-normal"
done
ball_ball=$'\n[[contacts]]\npair = ["ball", "ball"]\nkn = 5.0e7\nen = 0.9\n'
{ cat "$scene"; echo "$ball_ball"; printf '[[particles]]\nmaterial = "ball"\nradius = 10.0\nposition = [0.0, 50.0, 0.0]\n'
  printf '[checks]\nallow_initial_overlap = true\n'; } > "$work/coincident.toml"
refused coincident "$work/coincident.toml" "particles[1].position|particles[0]|distinct centres"
mkdir -p "$work/ckdir"
timeout 20 "$cdm" run "$scene" -o "$work/out-ck" --restart "$work/ckdir" > /dev/null 2> "$work/err-ck.txt"
grep -q "is a directory" "$work/err-ck.txt" || fail "a directory as the checkpoint: $(cat "$work/err-ck.txt")"

# random_particles blocks sharing a box place against each other (and the listed particle).
{ cat "$scene"; echo "$ball_ball"
  for r in 2.0 3.0; do
    printf '[[random_particles]]\nmaterial = "ball"\nradius = %s\nlower = [-50.0, 20.0, -50.0]\nupper = [50.0, 120.0, 50.0]\ncount = 300\n' "$r"
  done; } > "$work/random.toml"
"$cdm" run "$work/random.toml" -o "$work/out-random" --set integrator.end_time=0.002 > /dev/null 2> "$work/err-random.txt" \
  || fail "random_particles blocks sharing a box refused: $(cat "$work/err-random.txt")"
echo "cli.edge_values: ok"
