#!/usr/bin/env bash
# The main job on a fresh Debian 12 machine: install what is missing, build, and run
# the verification suite. Tables land in verification-out/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh release
exec build/release/app/cdm verify --out verification-out "$@"
