#!/usr/bin/env bash
# `cdm verify -j N` runs N cases at once, each in a process of its own:
#  - the tables are those of the cases run one after the other (but for the wall-time
#    columns), the lines come in case order, and no temporary file is left;
#  - a case that cannot run (a bad scene key, an unwritable table) stops the suite with
#    the exit status and the message the same failure gives run one after the other,
#    naming the case and the file, and no summary is written.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
cases=(free_fall hertz_impact_pair slipping_ball stacked)  # in case order (by name)

"$cdm" verify --cases "$src/verification/cases" -j 1 "${cases[@]}" --out "$work/one" > "$work/one.log" || fail "-j 1"
"$cdm" verify --cases "$src/verification/cases" -j 3 "${cases[@]}" --out "$work/three" > "$work/three.log" || fail "-j 3"
# Columns 11, 12 and 14 are the wall time, its runs and the particle-steps per second.
strip() { grep -v '^#' "$1" | awk '{$11 = $12 = $14 = ""; print}'; }
for c in "${cases[@]}"; do
  [ -s "$work/three/$c/errors.dat" ] || fail "$c: no table with -j 3"
  cmp -s <(strip "$work/one/$c/errors.dat") <(strip "$work/three/$c/errors.dat") || fail "$c: -j 3 table differs from -j 1"
done
[ "$(grep '^== ' "$work/three.log" | cut -d: -f1)" = "$(printf '== %s\n' "${cases[@]}")" ] ||
  fail "-j 3: the cases' lines are not in case order: $(grep '^== ' "$work/three.log")"
[ "$(grep -v '^#' "$work/three/summary.dat" | cut -d' ' -f1-3)" = "$(grep -v '^#' "$work/one/summary.dat" | cut -d' ' -f1-3)" ] ||
  fail "-j 3: summary.dat differs from -j 1"
grep -q '^cases_at_once 3$' "$work/three/provenance.dat" || fail "-j 3: provenance.dat lacks cases_at_once 3"
grep -q '^cases_at_once 1$' "$work/one/provenance.dat" || fail "-j 1: provenance.dat lacks cases_at_once 1"
ls "$work/three" | grep -q 'tmp' && fail "-j 3 left a temporary file: $(ls "$work/three")"

# A case that cannot run.
cp -r "$src/verification/cases" "$work/cases"
sed -i 's/^\[modules\]/[modules]\nbogus_key = 1/' "$work/cases/stacked/scene.toml"
for j in 1 3; do
  "$cdm" verify --cases "$work/cases" -j $j "${cases[@]}" --out "$work/bad$j" > /dev/null 2> "$work/err$j"
  rc=$?
  [ "$rc" -eq 2 ] || fail "bad scene, -j $j: exit status $rc, expected 2: $(cat "$work/err$j")"
  grep -q 'stacked/scene.toml' "$work/err$j" && grep -q 'bogus_key' "$work/err$j" ||
    fail "bad scene, -j $j: the message names neither the file nor the key: $(cat "$work/err$j")"
  [ ! -e "$work/bad$j/summary.dat" ] || fail "bad scene, -j $j: a summary was written"
done
mkdir -p "$work/unwritable/free_fall/errors.dat"
"$cdm" verify --cases "$src/verification/cases" -j 3 "${cases[@]}" --out "$work/unwritable" > /dev/null 2> "$work/err"
rc=$?
[ "$rc" -eq 4 ] || fail "unwritable table, -j 3: exit status $rc, expected 4: $(cat "$work/err")"
grep -q 'free_fall/errors.dat' "$work/err" || fail "unwritable table, -j 3: the path is not named: $(cat "$work/err")"
[ ! -e "$work/unwritable/summary.dat" ] || fail "unwritable table, -j 3: a summary was written"
echo "verify -j: tables as one after the other, lines in case order, failures stop the suite"
