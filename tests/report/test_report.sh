#!/usr/bin/env bash
# The verification report loads in headless Chromium and every figure it references
# exists and is non-empty. Runs a fast subset of the suite (stacked, slipping_ball),
# builds the report, renders it, and keeps a screenshot of the first page beside it.
set -u
cdm="$1" src="$2" work="$3"
fail() { echo "FAIL: $*"; exit 1; }
rm -rf "$work"; mkdir -p "$work"
chromium=$(command -v chromium || true)
[ -n "$chromium" ] || fail "chromium is not installed (scripts/install-deps.sh installs it)"
"$cdm" verify stacked slipping_ball --out "$work/verify" > "$work/verify.log" || fail "cdm verify failed: $(tail -5 "$work/verify.log")"
"$cdm" report --in "$work/verify" --out "$work/report" > "$work/report.log" 2>&1 || fail "cdm report failed: $(cat "$work/report.log")"
page="$work/report/index.html"
[ -s "$page" ] || fail "no index.html"
# Every <img src> exists and is non-empty.
n=0
for img in $(grep -o 'src="[^"]*"' "$page" | sed 's/src="//; s/"$//'); do
  [ -s "$work/report/$img" ] || fail "figure $img is missing or empty"
  n=$((n + 1))
done
[ "$n" -ge 4 ] || fail "only $n figures in the report"
flags=(--headless --no-sandbox --disable-gpu --disable-quic --no-first-run --disable-background-networking
       --disable-component-update --disable-sync --user-data-dir="$(mktemp -d)")
timeout 120 "$chromium" "${flags[@]}" --dump-dom "file://$page" > "$work/dom.html" 2> "$work/chromium.log" ||
  fail "chromium could not load the report: $(tail -3 "$work/chromium.log")"
grep -q "cdm verification report" "$work/dom.html" || fail "the loaded page lacks its title"
grep -q "<h2 id=\"summary\">Summary</h2>" "$work/dom.html" || fail "the loaded page lacks the summary"
grep -q "stacked" "$work/dom.html" || fail "the loaded page lacks the stacked case"
timeout 120 "$chromium" "${flags[@]}" --window-size=1280,2000 --screenshot="$work/first-page.png" "file://$page" \
  > /dev/null 2>> "$work/chromium.log" || fail "screenshot failed"
[ -s "$work/first-page.png" ] || fail "empty screenshot"
echo "report.chromium: ok ($n figures; screenshot $work/first-page.png)"
