#!/usr/bin/env bash
# Install what is missing, build, and run every test with CTest: the release build's
# suite (unit, verification, stability; not the runs labelled "long"), the unit tests of a
# build without MPI and hypre (the nompi preset), then the unit tests and the fast
# verification cases labelled "fast" again under address and undefined-behaviour sanitizers.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh release
ctest --preset release -LE long
scripts/build.sh nompi
ctest --preset nompi -L unit
scripts/build.sh sanitize
ctest --preset sanitize -L 'unit|fast'
