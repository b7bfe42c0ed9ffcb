#!/usr/bin/env bash
# Install what is missing, build, and run every test (unit and verification) with CTest.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh release
ctest --preset release
