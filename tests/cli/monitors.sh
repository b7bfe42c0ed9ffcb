#!/usr/bin/env bash
# The run log and the scene's monitors: log.dat and monitor_NAME.dat have one row per
# log_interval, their values follow from the state (a lattice bed's height at t = 0, the
# pressure-drop monitor spanning the domain equals the log's, a falling bed's mass flow
# is downward), a restarted run's tables equal an uninterrupted run's, and bad monitors
# are refused with exit 2 naming the key.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
scene="$work/bed.toml"
cat "$src/verification/cases/fluidization/scene.toml" - > "$scene" <<'TOML'

[output]
interval = 0.01
log_interval = 0.005
checkpoint_interval = 0.01

[[monitors]]
name = "dp"
type = "pressure_drop"
axis = "y"
from = 0.001
to = 0.079

[[monitors]]
name = "bed"
type = "bed_height"
axis = "y"
threshold = 0.1

[[monitors]]
name = "flow"
type = "mass_flow"
axis = "y"
position = 0.03
bin = 0.005

[[monitors]]
name = "p_point"
type = "pressure"
point = [0.005, 0.001, 0.0025]
TOML
args=(--set integrator.end_time=0.03 --set 'gas.boundaries.y_lower={type="velocity_inlet", velocity=0.05}')
"$cdm" run "$scene" -o "$work/full" "${args[@]}" > "$work/full.log" 2>&1 || fail "run: $(tail -3 "$work/full.log")"
for f in log monitor_dp monitor_bed monitor_flow monitor_p_point; do
  rows=$(grep -vc '^#' "$work/full/$f.dat")
  [ "$rows" -eq 7 ] || fail "$f.dat has $rows rows, expected 7 (t = 0, 0.005, ..., 0.03)"
done
grep -q '^  t 0.03 .*contacts' "$work/full.log" || fail "the log rows are not printed"
/usr/bin/python3 - "$work/full" <<'PY' || fail "monitor values"
import sys
d = sys.argv[1]
def rows(name):
    return [list(map(float, l.split())) for l in open(f"{d}/{name}.dat") if not l.startswith("#")]
log, dp, bed, flow = rows("log"), rows("monitor_dp"), rows("monitor_bed"), rows("monitor_flow")
# The lattice's top row of centres is at 59.4 mm: the bed fills the 2.5 mm layer below 60 mm.
assert abs(bed[0][1] - 0.06) < 1e-12, bed[0]
# Planes at the first and last cell centres: the log's domain pressure drop.
for a, b in zip(log, dp):
    assert a[0] == b[0] and a[7] == b[1], (a, b)
assert log[-1][7] > 0, log[-1]
# The bed falls onto the distributor: solids flow downward through y = 30 mm.
assert all(r[1] < 0 for r in flow[1:]), flow
assert all(r[6] == 1600 for r in log), log
PY
# Split at step 500 (between samples and checkpoints) and restarted: the same tables.
"$cdm" run "$scene" -o "$work/split" "${args[@]}" --max-steps 500 > /dev/null 2>&1 || fail "first part"
"$cdm" run "$scene" -o "$work/split" "${args[@]}" --restart "$work/split/checkpoint.cdmck" > /dev/null 2>&1 || fail "restart"
for f in log monitor_dp monitor_bed monitor_flow monitor_p_point particles; do
  cmp -s "$work/full/$f.dat" "$work/split/$f.dat" || fail "restarted $f.dat differs from the uninterrupted one"
done

# Refused monitors: exit 2, the key named, nothing written.
refuse() {  # TAG EXPECTED_TEXT SET...
  local tag=$1 text=$2
  shift 2
  "$cdm" run "$scene" -o "$work/bad" "$@" > /dev/null 2> "$work/err"; local rc=$?
  [ "$rc" -eq 2 ] && grep -qF "$text" "$work/err" || fail "$tag: rc $rc, $(cat "$work/err")"
  [ ! -e "$work/bad" ] || fail "$tag: a refused scene wrote output"
}
refuse "no log interval" "log_interval" --set 'output={interval=0.01}'
refuse "unknown type" "monitors[0].type" --set 'monitors[0].type="temperature"'
refuse "key of another type" "monitors[1].position is not used" --set 'monitors[1].position=0.01'
refuse "plane outside" "monitors[0].to" --set 'monitors[0].to=0.2'
refuse "duplicate name" "monitors[1].name" --set 'monitors[1].name="dp"'
refuse "bad axis" "monitors[2].axis" --set 'monitors[2].axis="w"'
refuse "threshold" "monitors[1].threshold" --set 'monitors[1].threshold=1.5'
# A pressure monitor in a scene without a gas.
printf '\n[[monitors]]\nname = "p"\ntype = "pressure"\npoint = [0, 0, 0]\n' |
  cat "$src/verification/cases/free_fall/scene.toml" - > "$work/nogas.toml"
"$cdm" run "$work/nogas.toml" -o "$work/bad" --set output.log_interval=0.1 > /dev/null 2> "$work/err"; rc=$?
[ "$rc" -eq 2 ] && grep -qF 'monitors[0].type' "$work/err" && grep -qF 'modules.gas = "solved"' "$work/err" ||
  fail "pressure monitor without a gas: rc $rc, $(cat "$work/err")"

# A wall's force: a ball dropped onto a floor comes to rest on it, the floor then carries
# its weight (m g = 2.6 g/cm^3 * 4/3 pi (10 cm)^3 * 9.8 m/s^2) and the ceiling nothing;
# without `wall`, every wall's force.
printf '\n[[walls]]\nname = "ceiling"\npoint = [0.0, 100.0, 0.0]\nnormal = [0.0, -1.0, 0.0]\nmaterial = "floor"\n' |
  cat "$src/verification/cases/free_fall_bounces/scene.toml" - > "$work/ball.toml"
cat >> "$work/ball.toml" <<'TOML'

[[monitors]]
name = "floor"
type = "wall_force"
wall = "floor"
axis = "y"

[[monitors]]
name = "ceiling"
type = "wall_force"
wall = "ceiling"
axis = "y"

[[monitors]]
name = "walls"
type = "wall_force"
axis = "y"
TOML
ball=(--set integrator.end_time=3.0 --set 'contacts[0].en=0.3' --set 'integrator.scheme="velocity_verlet"'
      --set output.interval=0.5 --set output.log_interval=0.25)
"$cdm" run "$work/ball.toml" -o "$work/ball" -q "${ball[@]}" > "$work/ball.log" 2>&1 || fail "ball: $(tail -3 "$work/ball.log")"
/usr/bin/python3 - "$work/ball" <<'PY' || fail "wall_force values"
import math, sys
d = sys.argv[1]
def rows(name):
    return [list(map(float, l.split())) for l in open(f"{d}/monitor_{name}.dat") if not l.startswith("#")]
floor, ceiling, walls = rows("floor"), rows("ceiling"), rows("walls")
weight = 2.6e3 * 4.0 / 3.0 * math.pi * 0.1**3 * 9.8
assert len(floor) == 13, len(floor)
assert floor[0][1] == 0.0, floor[0]            # in the air at t = 0
assert abs(floor[-1][1] / weight - 1) < 1e-12, (floor[-1], weight)
assert all(r[1] == 0.0 for r in ceiling), ceiling
assert all(a[1] == b[1] for a, b in zip(floor, walls)), (floor, walls)
PY
grep -q '^# cdm monitor floor (wall_force): force along y on the particles from the wall floor' "$work/ball/monitor_floor.dat" ||
  fail "wall_force: the table does not say what it measures"
"$cdm" run "$work/ball.toml" -o "$work/bad" "${ball[@]}" --set 'monitors[1].wall="roof"' > /dev/null 2> "$work/err"; rc=$?
[ "$rc" -eq 2 ] && grep -qF 'monitors[1].wall' "$work/err" && [ ! -e "$work/bad" ] || fail "unknown wall: rc $rc, $(cat "$work/err")"
printf '\n[[monitors]]\nname = "w"\ntype = "wall_force"\naxis = "y"\n' |
  cat "$src/verification/cases/terminal_velocity/scene.toml" - > "$work/nowall.toml"
"$cdm" run "$work/nowall.toml" -o "$work/bad" --set 'output={interval=0.1,log_interval=0.1}' > /dev/null 2> "$work/err"; rc=$?
[ "$rc" -eq 2 ] && grep -qF 'monitors[0].type' "$work/err" && grep -qF '[[walls]]' "$work/err" ||
  fail "wall_force without walls: rc $rc, $(cat "$work/err")"
echo "monitors: all checks passed"
