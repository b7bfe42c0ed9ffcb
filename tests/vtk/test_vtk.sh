#!/usr/bin/env bash
# cdm writes VTK; VTK's own readers (Debian python3-vtk9, under /usr/bin/python3) read
# it back and check_vtk.py compares counts and values with cdm's particle table and the
# Taylor-Green formula. Usage: test_vtk.sh CDM SOURCE_DIR WORK_DIR
set -euo pipefail
cdm=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
"$cdm" run "$src/tests/vtk/scene.toml" -o "$work/out" -q > "$work/run.log"
/usr/bin/python3 "$src/tests/vtk/check_vtk.py" "$work/out"

# A settling bed of 2000 particles with friction (bench/scenes/settle_1e4.toml cut to 5
# layers), binary and ASCII: every array read back against the table, contact forces
# present, and the binary files at most a third of the ASCII ones.
sed 's/count = \[20, 20, 25\]/count = [20, 20, 5]/; s/^end_time = .*/end_time = 0.004/; s/^interval = .*/interval = 0.001/' \
  "$src/bench/scenes/settle_1e4.toml" > "$work/settle2k.toml"
for fmt in binary ascii; do
  "$cdm" run "$work/settle2k.toml" -o "$work/$fmt" -q --set output.vtk=true --set "output.vtk_format=\"$fmt\"" >> "$work/run.log"
done
/usr/bin/python3 "$src/tests/vtk/check_vtk_settle.py" "$work/binary" "$work/ascii"

# The same bed with the contacts written (force chains): read back and checked against
# the particle frames.
"$cdm" run "$work/settle2k.toml" -o "$work/contacts" -q --set output.vtk=true --set output.contacts=true >> "$work/run.log"
/usr/bin/python3 "$src/tests/vtk/check_vtk_contacts.py" "$work/contacts"
