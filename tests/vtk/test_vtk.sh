#!/usr/bin/env bash
# cdm writes VTK; VTK's own readers (Debian python3-vtk9, under /usr/bin/python3) read
# it back and check_vtk.py compares counts and values with cdm's particle table and the
# Taylor-Green formula. Usage: test_vtk.sh CDM SOURCE_DIR WORK_DIR
set -euo pipefail
cdm=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
"$cdm" run "$src/tests/vtk/scene.toml" -o "$work/out" -q > "$work/run.log"
/usr/bin/python3 "$src/tests/vtk/check_vtk.py" "$work/out"
