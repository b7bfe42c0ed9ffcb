#!/usr/bin/env bash
# Triangle-mesh walls keep the guarantees of plane walls: a pile of 5,103 frictional
# beads in a closed mesh box (tests/cli/scenes/mesh_pile.toml) gives bit-identical
# particle tables on 1 and 3 OpenMP threads, and a run of 2N steps equals N steps, a
# checkpoint (with the mesh contacts' tangential history) and a restart for the rest
# (tables and final checkpoints), also with the box turning (and threads with rolling
# resistance at its contacts); a checkpoint whose meshes
# differ from the scene's is refused.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
scene="$src/tests/cli/scenes/mesh_pile.toml"

# Threads (5,103 particles: above the 4,096 where threads start; 3 threads split the
# particles and their mesh contacts differently from 2).
args=(run "$scene" -q --set integrator.end_time=0.002 --set output.interval=0.0005)
"$cdm" "${args[@]}" -o "$work/one" -j 1 > /dev/null || fail "1-thread run"
"$cdm" "${args[@]}" -o "$work/three" -j 3 > /dev/null || fail "3-thread run"
cmp -s "$work/one/particles.dat" "$work/three/particles.dat" || fail "1 and 3 threads differ"
# The beads touched the mesh: the ones beside it spin (friction at the mesh, no other
# cause of spin in the first layer x = -0.01445 before they meet each other).
awk '!/^#/ && $1 > 0.0019 && $3 < -0.0144 && ($9 != 0 || $10 != 0 || $11 != 0) {found = 1} END {exit !found}' \
  "$work/one/particles.dat" || fail "no bead beside the mesh spins: no mesh contacts"

# The box turning about its vertical axis (a moving mesh: the beads are taken into its
# frame, its surface velocity enters the contacts): threads and restart still bit-identical.
turn=(--set 'meshes[0].motion={type="rotation", origin=[0.0, 0.0, 0.0], axis=[0.0, 0.0, 1.0], angular_velocity=20.0}')
"$cdm" "${args[@]}" "${turn[@]}" -o "$work/one_turn" -j 1 > /dev/null || fail "1-thread turning run"
"$cdm" "${args[@]}" "${turn[@]}" -o "$work/three_turn" -j 3 > /dev/null || fail "3-thread turning run"
cmp -s "$work/one_turn/particles.dat" "$work/three_turn/particles.dat" || fail "turning box: 1 and 3 threads differ"
cmp -s "$work/one/particles.dat" "$work/one_turn/particles.dat" && fail "the turning box changed nothing"
# Rolling resistance at the turning mesh's contacts too (each particle's mesh torques in
# contact order, whatever thread takes it).
roll=(--set 'modules.rolling_resistance="constant_torque"' --set contacts[0].rolling_mu=0.1 --set contacts[1].rolling_mu=0.2)
"$cdm" "${args[@]}" "${turn[@]}" "${roll[@]}" -o "$work/one_roll" -j 1 > /dev/null || fail "1-thread rolling run"
"$cdm" "${args[@]}" "${turn[@]}" "${roll[@]}" -o "$work/three_roll" -j 3 > /dev/null || fail "3-thread rolling run"
cmp -s "$work/one_roll/particles.dat" "$work/three_roll/particles.dat" || fail "rolling resistance: 1 and 3 threads differ"
cmp -s "$work/one_turn/particles.dat" "$work/one_roll/particles.dat" && fail "rolling resistance changed nothing"
mkdir -p "$work/turn"

# Restart (600 beads in the corner of the box, 0.01 s, sorted every 200 steps).
set_args=(--set 'lattices[0].count=[10,10,6]' --set integrator.end_time=0.01 --set output.interval=0.0005
          --set output.checkpoint_interval=0.0025 -q)
restart_matches "mesh pile" "$scene" "$work" 5000 "${set_args[@]}"
restart_matches "mesh pile, turning box" "$scene" "$work/turn" 5000 "${set_args[@]}" "${turn[@]}"

# A restart whose STL file changed since the checkpoint (same scene text) is refused.
mkdir -p "$work/edit"
sed 's|file = ".*cube.stl"|file = "cube.stl"|' "$scene" > "$work/edit/scene.toml"
cp "$src/verification/cases/mesh_edge_impact/cube.stl" "$work/edit/cube.stl"
"$cdm" run "$work/edit/scene.toml" -o "$work/edit/out" "${set_args[@]}" --max-steps 100 > /dev/null || fail "edited: first part"
sed -i 's/ 0.050000000000000003 / 0.051000000000000004 /' "$work/edit/cube.stl"
"$cdm" run "$work/edit/scene.toml" -o "$work/edit/out" "${set_args[@]}" --restart "$work/edit/out/checkpoint.cdmck" \
  2> "$work/err" > /dev/null; rc=$?
[ "$rc" -eq 2 ] && grep -q "meshes differ" "$work/err" || fail "restart with an edited STL: rc $rc, $(cat "$work/err")"
echo "mesh_pile: threads and restart bit-identical"
