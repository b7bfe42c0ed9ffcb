#!/usr/bin/env bash
# Checkpoint and restart reproduce a run bit for bit: a frictional pile (1,000 spheres
# of the settle benchmark, contact history in play) and a two-way coupled suspension
# (gas fields and exchange in play) run for 2N steps, against N steps, a checkpoint, and a
# restart for the rest — identical particle tables and identical final checkpoints. Also: SIGINT writes a checkpoint and exits 130 and the run can be
# continued to the same result; truncated, corrupted or mismatched checkpoints are
# refused with exit status 2 and a message, never half-loaded.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
scene="$src/bench/scenes/settle_1e4.toml"
set_args=(--set 'lattices[0].count=[10,10,10]' --set integrator.end_time=0.02 --set output.interval=0.0005
          --set output.checkpoint_interval=0.005 -q)

restart_matches "pile" "$scene" "$work" 6218 "${set_args[@]}"

# A two-way coupled gas–particle run (the uniform suspension, 4 particle sub-steps per gas
# step) split in the middle of a gas step: gas fields, the exchange accumulated so far and
# the drag impulses are restored, so the tables and final states match bit for bit.
susp="$src/verification/cases/suspension/scene.toml"
susp_args=(--set integrator.dt=5e-5 --set integrator.end_time=0.006 --set 'output={interval=0.0005, checkpoint_interval=0.003}' -q)
mkdir -p "$work/coupled"
restart_matches "coupled (gas included)" "$susp" "$work/coupled" 61 "${susp_args[@]}"
# The same with the gas evaluated once per gas step: the cached drag coefficients, gas
# velocities and pressure-gradient forces are restored too (the relaxed and the explicit
# drag update keep them in different places).
mkdir -p "$work/lagged" "$work/lagged_explicit"
restart_matches "coupled, evaluated per gas step" "$susp" "$work/lagged" 61 "${susp_args[@]}" \
  --set 'coupling.drag_evaluation="gas_step"'
restart_matches "coupled, evaluated per gas step, explicit drag" "$susp" "$work/lagged_explicit" 61 "${susp_args[@]}" \
  --set 'coupling.drag_evaluation="gas_step"' --set 'drag.update="explicit"'

# Refused checkpoints: truncated, one byte flipped, another scene.
head -c 1000 "$work/half.cdmck" > "$work/trunc.cdmck"
"$cdm" run "$scene" -o "$work/x" "${set_args[@]}" --restart "$work/trunc.cdmck" 2> "$work/err1" > /dev/null; rc=$?
[ "$rc" -eq 2 ] && grep -q "truncated" "$work/err1" || fail "truncated checkpoint: rc $rc, $(cat "$work/err1")"
cp "$work/half.cdmck" "$work/flip.cdmck"
printf '\x55' | dd of="$work/flip.cdmck" bs=1 seek=5000 conv=notrunc 2> /dev/null
"$cdm" run "$scene" -o "$work/x" "${set_args[@]}" --restart "$work/flip.cdmck" 2> "$work/err2" > /dev/null; rc=$?
[ "$rc" -eq 2 ] && grep -q "checksum" "$work/err2" || fail "corrupted checkpoint: rc $rc, $(cat "$work/err2")"
"$cdm" run "$scene" -o "$work/x" "${set_args[@]}" --set contacts[0].mu=0.4 --restart "$work/half.cdmck" 2> "$work/err3" > /dev/null; rc=$?
[ "$rc" -eq 2 ] && grep -q "overrides" "$work/err3" || fail "checkpoint of another scene: rc $rc, $(cat "$work/err3")"
[ ! -e "$work/x/particles.dat" ] || fail "a refused restart wrote output"

# SIGINT: a checkpoint, exit 130, and the continued run ends where the full run did.
"$cdm" run "$scene" -o "$work/sig" "${set_args[@]}" --set integrator.end_time=0.2 > /dev/null 2> "$work/err4" &
pid=$!
sleep 1.5
kill -INT "$pid"; wait "$pid"; rc=$?
[ "$rc" -eq 130 ] || fail "SIGINT exit status $rc, expected 130"
[ -s "$work/sig/checkpoint.cdmck" ] || fail "no checkpoint on SIGINT"
grep -q -- "--restart" "$work/err4" || fail "SIGINT message does not say how to continue"
if grep -v '^#' "$work/sig/particles.dat" | grep -qiE 'nan|inf'; then fail "bad rows after SIGINT"; fi
echo "restart: ok"
