#!/usr/bin/env bash
# cdm run: a bad scene is refused with exit status 2, a message naming file, key, value
# and what was expected, and no output directory; a good scene writes a plain table
# with a '#' header naming columns and units, and only finite numbers.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
fail() { echo "FAIL: $*"; exit 1; }

scene="$src/verification/cases/free_fall/scene.toml"
sed 's/^en = 0.9 .*/en = 1.5/' "$scene" > "$work/bad.toml"
"$cdm" run "$work/bad.toml" -o "$work/out-bad" 2> "$work/err.txt"; rc=$?
[ "$rc" -eq 2 ] || fail "bad scene exited $rc, expected 2"
grep -q "bad.toml" "$work/err.txt" || fail "message does not name the file: $(cat "$work/err.txt")"
grep -q "contacts\[0\].en" "$work/err.txt" || fail "message does not name the key: $(cat "$work/err.txt")"
grep -q "1.5" "$work/err.txt" || fail "message does not show the value"
grep -q "expected" "$work/err.txt" || fail "message does not say what was expected"
[ ! -e "$work/out-bad" ] || fail "a refused scene left output behind"

"$cdm" run "$work/missing.toml" -o "$work/out-missing" 2>/dev/null; rc=$?
[ "$rc" -eq 2 ] || fail "missing scene file exited $rc, expected 2"

"$cdm" run "$scene" -o "$work/out-good" --set 'integrator.end_time=0.1' > "$work/log.txt"; rc=$?
[ "$rc" -eq 0 ] || fail "good scene exited $rc"
table="$work/out-good/particles.dat"
[ -s "$table" ] || fail "no particle table"
grep -q '^# t\[s\] id\[-\] x\[m\] y\[m\]' "$table" || fail "table header does not name columns with units"
if grep -v '^#' "$table" | grep -qiE 'nan|inf'; then fail "non-finite values in the table"; fi
rows=$(grep -vc '^#' "$table")
[ "$rows" -ge 100 ] || fail "expected >= 100 rows at 1 ms over 0.1 s, got $rows"
echo "cli.run_scene: ok ($rows rows)"
