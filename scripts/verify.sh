#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install what is missing, build, run the
# verification suite (the paper's sweeps, then the dense dt sweep for the
# work-precision tables), and write the HTML report. Tables land in verification-out/,
# the report in report/index.html.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh release
status=0
build/release/app/cdm verify --out verification-out "$@" || status=$?
build/release/app/cdm verify --sweep --out verification-out "$@" > verification-out/sweep.log || status=$?
build/release/app/cdm report --in verification-out --out report
exit $status
