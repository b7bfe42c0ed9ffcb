#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install what is missing, build, run the
# verification suite and write the HTML report. Tables land in verification-out/, the
# report in report/index.html.
#   scripts/verify.sh            the default suite (the paper's sweeps and every case)
#   scripts/verify.sh --sweep    also the dense dt sweep for the work-precision plots
# Other arguments go to `cdm verify` (e.g. case names).
set -euo pipefail
cd "$(dirname "$0")/.."
sweep=0
args=()
for a in "$@"; do
  if [ "$a" = "--sweep" ]; then sweep=1; else args+=("$a"); fi
done
scripts/install-deps.sh
scripts/build.sh release
status=0
build/release/app/cdm verify --out verification-out "${args[@]}" || status=$?
if [ "$sweep" = 1 ]; then
  build/release/app/cdm verify --sweep --out verification-out "${args[@]}" > verification-out/sweep.log || status=$?
fi
build/release/app/cdm report --in verification-out --out report
exit $status
