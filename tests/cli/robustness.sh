#!/usr/bin/env bash
# What a careless user or a failing disk does to `cdm run`, and what must come of it:
#  - a restart cuts the table back to where its checkpoint recorded it, so running the
#    same restart twice gives the same table, and a restart into an empty -o directory
#    starts a new table with its header;
#  - an output that cannot be written (a full device, a directory where a file goes, an
#    -o that cannot be a directory) stops with exit status 4, a message naming the path
#    and the system's reason, and no temporary file left;
#  - an override holding two values, a negative --max-steps, and a checkpoint with a
#    non-finite state or a time its step count does not give are refused (exit 2);
#  - a restart may extend the run and change its [output], and a comment added to the
#    scene is no change, but a change of physics is refused naming the key and both
#    values; the command printed after SIGINT continues the run to the same table.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
scene="$src/bench/scenes/settle_1e4.toml"
args=(--set 'lattices[0].count=[5,5,5]' --set integrator.end_time=0.01 --set output.interval=0.0005
      --set output.checkpoint_interval=0.002 -q -j1)
run() { "$cdm" run "$scene" "${args[@]}" "$@"; }
# expect RC TAG PATTERN CMD...: CMD exits with RC and says PATTERN on stderr.
expect() {
  local want=$1 tag=$2 pattern=$3
  shift 3
  "$@" > /dev/null 2> "$work/err"
  local rc=$?
  [ "$rc" -eq "$want" ] || fail "$tag: exit status $rc, expected $want: $(cat "$work/err")"
  grep -q -- "$pattern" "$work/err" || fail "$tag: message lacks '$pattern': $(cat "$work/err")"
}

# Restarts reconcile the table with the checkpoint.
run -o "$work/full" > /dev/null || fail "uninterrupted run"
run -o "$work/split" --max-steps 3000 > /dev/null || fail "first part"
cp "$work/split/checkpoint.cdmck" "$work/half.cdmck"
run -o "$work/split" --restart "$work/half.cdmck" > /dev/null || fail "restart"
cmp -s "$work/full/particles.dat" "$work/split/particles.dat" || fail "restarted table differs"
run -o "$work/split" --restart "$work/half.cdmck" > /dev/null || fail "second restart"
cmp -s "$work/full/particles.dat" "$work/split/particles.dat" || fail "the same restart run twice changes the table"
run -o "$work/empty" --restart "$work/half.cdmck" > /dev/null || fail "restart into an empty directory"
head -1 "$work/empty/particles.dat" | grep -q '^# cdm particle table' || fail "restart into an empty directory: no header"
grep -q '^# t\[s\] id' "$work/empty/particles.dat" || fail "restart into an empty directory: no column names"
cmp -s <(grep -v '^#' "$work/empty/particles.dat") <(tail -n "$(grep -vc '^#' "$work/empty/particles.dat")" "$work/full/particles.dat") ||
  fail "restart into an empty directory: its rows are not the uninterrupted run's last rows"
head -c 100000 "$work/full/particles.dat" > "$work/split/particles.dat"
expect 2 "table shorter than the checkpoint recorded" "fewer than" run -o "$work/split" --restart "$work/half.cdmck"

# Output failures: exit 4, the path and the reason.
mkdir -p "$work/devfull"; ln -s /dev/full "$work/devfull/particles.dat"
expect 4 "particles.dat on a full device" "devfull/particles.dat.*No space left on device" run -o "$work/devfull"
mkdir -p "$work/ckdir/checkpoint.cdmck"
expect 4 "checkpoint path a directory" "ckdir/checkpoint.cdmck" run -o "$work/ckdir"
ls "$work/ckdir" | grep -q '\.tmp' && fail "a temporary file was left behind"
mkdir -p "$work/ckfull"; ln -s /dev/full "$work/ckfull/checkpoint.cdmck.tmp"
expect 4 "checkpoint's temporary file on a full device" "ckfull/checkpoint.cdmck.tmp.*No space left on device" run -o "$work/ckfull"
[ ! -e "$work/ckfull/checkpoint.cdmck.tmp" ] || fail "the checkpoint's temporary file was left behind"
expect 4 "-o under /proc" "/proc/x" run -o /proc/x
touch "$work/afile"
expect 4 "-o an existing file" "afile.*Not a directory" run -o "$work/afile"
mkdir -p "$work/tabdir/particles.dat"
expect 4 "particles.dat a directory" "tabdir/particles.dat.*Is a directory" run -o "$work/tabdir"
expect 4 "cdm verify into /proc" "/proc/x" "$cdm" verify free_fall --out /proc/x

# Refused input.
expect 2 "override with a line break" "contacts\[0\].kn" run -o "$work/x" --set $'contacts[0].kn=1e7\nen=5'
expect 2 "negative --max-steps" "max-steps" run -o "$work/x" --max-steps -5
mutate() { /usr/bin/python3 "$(dirname "$0")/mutate_checkpoint.py" "$work/half.cdmck" "$work/m.cdmck" "$@" || fail "mutate $*"; }
mutate x0 nan
expect 2 "NaN position in a checkpoint" "particle [0-9]* has x = nan" run -o "$work/x" --restart "$work/m.cdmck"
mutate vx0 inf
expect 2 "infinite velocity in a checkpoint" "particle [0-9]* has vx = inf" run -o "$work/x" --restart "$work/m.cdmck"
mutate time 0.0928
expect 2 "time and steps inconsistent" "is not what its 3000 steps" run -o "$work/x" --restart "$work/m.cdmck"
mutate steps 0
expect 2 "step count zeroed" "is not what its 0 steps" run -o "$work/x" --restart "$work/m.cdmck"
mutate time nan
expect 2 "NaN time" "its time is nan" run -o "$work/x" --restart "$work/m.cdmck"
[ ! -e "$work/x" ] || fail "a refused run wrote output"

# What a restart may change: the end time and [output]; a comment is no change.
run -o "$work/long" --set integrator.end_time=0.02 > /dev/null || fail "longer run"
run -o "$work/ext" --max-steps 3000 > /dev/null || fail "first part of the extended run"
{ echo "# a comment added after the run started"; cat "$scene"; } > "$work/commented.toml"
"$cdm" run "$work/commented.toml" "${args[@]}" -o "$work/ext" --set integrator.end_time=0.02 \
  --set output.checkpoint_interval=0.004 --restart "$work/ext/checkpoint.cdmck" > /dev/null 2> "$work/err" ||
  fail "extending the run refused: $(cat "$work/err")"
cmp -s "$work/long/particles.dat" "$work/ext/particles.dat" || fail "extended run's table differs from the longer run's"
expect 2 "changed friction" "contacts\[0\].mu = 0.5.*has 0.4" run -o "$work/x" --set 'contacts[0].mu=0.4' --restart "$work/half.cdmck"

# SIGINT: the printed command (with the overrides, quoted) continues the run.
sargs=(--set 'lattices[0].count=[5,5,5]' --set "integrator.end_time=0.4" --set 'output={interval=0.001, checkpoint_interval=0.01}')
"$cdm" run "$scene" -q -j1 "${sargs[@]}" -o "$work/sigfull" > /dev/null || fail "uninterrupted run for SIGINT"
"$cdm" run "$scene" -q -j1 "${sargs[@]}" -o "$work/sig" > /dev/null 2> "$work/sigerr" &
pid=$!
sleep 0.3
kill -INT "$pid"; wait "$pid"; rc=$?
[ "$rc" -eq 130 ] || fail "SIGINT exit status $rc, expected 130"
hint=$(sed -n 's/.*continue with: cdm run /cdm run /p' "$work/sigerr")
[ -n "$hint" ] || fail "no command after SIGINT: $(cat "$work/sigerr")"
(cdm() { "$cdm" "$@"; }; eval "$hint -q -j1") > /dev/null 2> "$work/err" || fail "the command printed after SIGINT fails: $hint: $(cat "$work/err")"
cmp -s "$work/sigfull/particles.dat" "$work/sig/particles.dat" || fail "the run continued after SIGINT differs"
echo "robustness: ok"
