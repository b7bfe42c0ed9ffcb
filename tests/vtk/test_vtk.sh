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

# Walls and meshes: moving ones written with every particle frame, read back where their
# motion puts them; walls at rest written once (the settling bed's box above).
"$cdm" run "$src/tests/cli/scenes/moving_walls.toml" -o "$work/walls" -q --set output.vtk=true \
  --set 'random_particles[0].count=200' --set integrator.end_time=0.004 --set output.interval=0.001 >> "$work/run.log"
"$cdm" run "$src/tests/cli/scenes/mesh_pile.toml" -o "$work/mesh" -q --set output.vtk=true \
  --set 'meshes[0].motion={ type = "rotation", origin = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], angular_velocity = 10.0 }' \
  --set 'lattices[0].count=[5, 5, 2]' --set integrator.end_time=0.004 --set output.interval=0.001 >> "$work/run.log"
/usr/bin/python3 "$src/tests/vtk/check_vtk_walls.py" "$work/walls" "$work/mesh" 10.0 "$work/binary"

# Writing a frame leaves the run as it was: each frame's contact forces (and the
# contacts, and the wall-force monitors, sampled at the same steps) are evaluated on the
# run's own lists, reading the tangential springs, wall entries, rolling state and mesh
# contacts without advancing them. The particle table, to the last bit, is the same
# with and without them.
walls_x_z='monitors=[{ name = "x", type = "wall_force", axis = "x" }, { name = "z", type = "wall_force", axis = "z" }]'
# unchanged NAME SCENE MONITORS ARGS...: the table with frames, contacts and MONITORS (a
# --set of the wall-force monitors, where the scene has walls) against the table without.
unchanged() {
  local name=$1 scene=$2 monitors=$3; shift 3
  "$cdm" run "$scene" -o "$work/$name.with" -q --set output.particles=true --set output.vtk=true \
    --set output.contacts=true --set output.log_interval=0.001 --set "$monitors" "$@" >> "$work/run.log"
  "$cdm" run "$scene" -o "$work/$name.without" -q --set output.particles=true "$@" >> "$work/run.log"
  if ! cmp -s "$work/$name.with/particles.dat" "$work/$name.without/particles.dat"; then
    echo "FAIL: $name: the particle table differs with VTK frames, contacts and wall-force monitors written"
    diff "$work/$name.with/particles.dat" "$work/$name.without/particles.dat" | head -4
    exit 1
  fi
}
unchanged settle "$work/settle2k.toml" "$walls_x_z"
unchanged walls "$src/tests/cli/scenes/moving_walls.toml" "$walls_x_z" --set 'random_particles[0].count=600' \
  --set integrator.end_time=0.004 --set output.interval=0.0005
unchanged mesh "$src/tests/cli/scenes/mesh_pile.toml" output.log_interval=0.001 \
  --set 'meshes[0].motion={ type = "rotation", origin = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0], angular_velocity = 10.0 }' \
  --set 'lattices[0].count=[5, 5, 2]' --set integrator.end_time=0.004 --set output.interval=0.0005
echo "frames, contacts and wall-force monitors leave the run unchanged: settle, moving walls with rolling, a rotating mesh"
