#!/usr/bin/env bash
# The verification report loads in headless Chromium and every figure it references
# exists and is non-empty. Runs a fast subset of the suite (stacked, slipping_ball and the
# gas case terminal_velocity), builds the report, checks that every case run has figures
# and every referenced figure and table exists, renders it, and keeps a screenshot of the
# first page beside it.
set -u
cdm="$1" src="$2" work="$3"
cases=(stacked slipping_ball terminal_velocity)
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"; mkdir -p "$work"
chromium=$(command -v chromium || true)
[ -n "$chromium" ] || fail "chromium is not installed (scripts/install-deps.sh installs it)"
"$cdm" verify "${cases[@]}" --out "$work/verify" > "$work/verify.log" || fail "cdm verify failed: $(tail -5 "$work/verify.log")"
# cdm report fails (make_report exits 3) if any figure could not be drawn.
"$cdm" report --in "$work/verify" --out "$work/report" > "$work/report.log" 2>&1 || fail "cdm report failed: $(cat "$work/report.log")"
page="$work/report/index.html"
[ -s "$page" ] || fail "no index.html"
[ "$(tail -1 "$work/report.log")" = "$page" ] || fail "cdm report did not print the report's path last: $(tail -1 "$work/report.log")"
# Every <img src> and every linked table exists and is non-empty.
n=0
for img in $(grep -o 'src="[^"]*"' "$page" | sed 's/src="//; s/"$//'); do
  [ -s "$work/report/$img" ] || fail "figure $img is missing or empty"
  n=$((n + 1))
done
for ref in $(grep -o 'href="data/[^"]*"' "$page" | sed 's/href="//; s/"$//'); do
  [ -s "$work/report/$ref" ] || fail "linked table $ref is missing or empty"
done
[ "$n" -ge $((2 * ${#cases[@]})) ] || fail "only $n figures in the report (a paper figure and a convergence plot per case expected)"
# Every case run has its own figures (convergence plot at least) and its section.
for c in "${cases[@]}"; do
  grep -q "src=\"fig/${c}_convergence.png\"" "$page" || fail "no convergence figure for $c"
  grep -q "id=\"$c\"" "$page" || fail "no section for $c"
done
grep -q 'src="fig/terminal_velocity_fig15.png"' "$page" || fail "no Fig 15 for terminal_velocity"
# Notes mark skipped figures; without `cdm verify --sweep` only the work-precision plots may be missing.
notes=$(grep -o 'class="note">[^<]*' "$page" | grep -v 'no errors_sweep.dat')
[ -z "$notes" ] || fail "the report skipped something: $notes"
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
       --disable-component-update --disable-sync --user-data-dir="$(mktemp -d)")
timeout 120 "$chromium" "${flags[@]}" --dump-dom "file://$page" > "$work/dom.html" 2> "$work/chromium.log" ||
  fail "chromium could not load the report: $(tail -3 "$work/chromium.log")"
grep -q "cdm verification report" "$work/dom.html" || fail "the loaded page lacks its title"
grep -q "<h2 id=\"summary\">Summary</h2>" "$work/dom.html" || fail "the loaded page lacks the summary"
for c in "${cases[@]}"; do
  grep -q "id=\"$c\"" "$work/dom.html" || fail "the loaded page lacks the $c case"
done
timeout 120 "$chromium" "${flags[@]}" --window-size=1280,2000 --screenshot="$work/first-page.png" "file://$page" \
  > /dev/null 2>> "$work/chromium.log" || fail "screenshot failed"
[ -s "$work/first-page.png" ] || fail "empty screenshot"
echo "report.chromium: ok ($n figures; screenshot $work/first-page.png)"
