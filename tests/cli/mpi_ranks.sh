#!/usr/bin/env bash
# Under mpirun the particles' work is shared among the processes (rank_split.hpp), with
# results bit-identical to one process: the particle tables, run logs, wall-force monitors, VTK files (with the
# contact network) and final checkpoints of a settling bed (walls, friction; 5000
# particles, so that 2 threads per process split the slabs too) and of a periodic chute
# (a fixed base; slabs along its periodic x, which wrap) and of the fluidisation
# case's bed (a gas, two-way drag) are compared, byte for
# byte, on 1 process without a launcher against 2, 3 and 4 (oversubscribed) processes and
# 2 processes of 2 threads; a run stopped on 2 processes is restarted on 3 and must end
# as the uninterrupted one, and restarted on 3 with no step left writes one process's
# checkpoint (and so, between 2 and 3 either way, the fluidisation bed with
# the drag once per gas step, the bed fed from above and the mesh pile); the settling bed never sorted in memory (also fed
# and drained), with rolling resistance, and moved by the
# paper's Euler step, and moving walls are compared on 3 processes, a bed fed from above (insertions, an outlet), the silo (a mesh, an outlet)
# and the chute logged every few steps on 2. The Mueller bed (a gas, two-way drag) is compared on 2
# processes, also with the drag evaluated once per gas step (and the fluidisation bed so
# on 3), the fluidisation bed with the cell-average drag on 2, and the Mueller bed with the
# gas taking the drag implicitly on 3; the run logs, monitors and outlet tables are summed
# by each process over its own particles; particles without contacts (a gas scene, beads
# raining through a gas with an insertion and an outlet, a Taylor-Green vortex, tracers,
# with every integrator) are shared by rows. The gas step with the multigrid pressure
# solve, divided among the processes, gives the same files on 2, 3 and 4. A bed over
# the gas planes (each process reading its reach) is compared on 3, also with the direct
# pressure solve, in a closed box and with the gas taking the drag implicitly (restarted
# onto 2), and periodic along z on 4 (restarted onto 3).
# The processes other than rank 0 write no file (their temporary folder does not exist). A
# bed of 2e4 particles, whose state is gathered in rounds, is compared on 2, and the chute
# gathered in rounds of a few particles and pairs. The chute and the Mueller bed are
# compared on 2 over TCP, without Open MPI's shared memory, as between machines. A lattice
# thrown at the floor, stopped at each of 20 consecutive steps and continued on 2 or 3 (some
# restarts' first step builds the list), ends as one process's run. A run on 2
# stopped by SIGTERM to mpirun writes its checkpoint and continues on 3 to the same table;
# a run on 3 that loses a process (SIGKILL) exits non-zero and continues on 2 from its last
# checkpoint to the same files; rank 0's write failing on a full device stops both of 2
# processes with exit 4. A checkpoint changed where only rank 1 of 2 restores from is
# refused by both before either restores or writes anything.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
command -v mpirun > /dev/null || fail "mpirun not found (Debian's openmpi-bin)"
# Rank 0 alone writes the outputs; the others write no file anywhere, not even into a
# temporary folder: theirs does not exist.
launch=(mpirun --oversubscribe -x TMPDIR="$work/no-such-folder")
[ "$(id -u)" -eq 0 ] && launch+=(--allow-run-as-root)
# Open MPI's session folders go into one of this test's own (short: it holds sockets), so
# that no other Open MPI program of this user removes it while a launch here creates them.
OMPI_MCA_orte_tmpdir_base=$(mktemp -d) || fail "mktemp"
export OMPI_MCA_orte_tmpdir_base
trap 'rm -rf "$OMPI_MCA_orte_tmpdir_base"' EXIT

# same TAG DIR_A DIR_B: every file the runs wrote is the same, byte for byte.
same() {
  local tag=$1 a=$2 b=$3 n=0
  for f in $(cd "$a" && find . -type f | sort); do
    cmp -s "$a/$f" "$b/$f" || fail "$tag: $f differs from one process's"
    n=$((n + 1))
  done
  [ "$(cd "$b" && find . -type f | wc -l)" -eq "$n" ] || fail "$tag: not the same files as one process's"
}

# shared TAG NP SCENE ARGS...: run on one process, then shared among NP: the same files.
shared() {
  local tag=$1 np=$2 dir=${1// /-}
  shift 2
  "$cdm" run "$@" -q -j 1 -o "$work/$dir-1" > /dev/null || fail "$tag: one process"
  "${launch[@]}" -np "$np" "$cdm" run "$@" -q -j 1 -o "$work/$dir-$np" > "$work/$dir-$np.out" 2>&1 ||
    fail "$tag: $np processes: $(tail -5 "$work/$dir-$np.out")"
  grep -q "shared among $np MPI processes" "$work/$dir-$np.out" || fail "$tag: not shared among $np processes"
  same "$tag, $np processes" "$work/$dir-1" "$work/$dir-$np"
}

settle=("$src/bench/scenes/settle_1e4.toml" --set 'lattices[0].count=[10,10,50]' --set integrator.end_time=0.03
        --set output.interval=0.01 --set output.log_interval=0.005 --set output.vtk=true --set output.contacts=true
        --set output.checkpoint_interval=0.015
        --set 'monitors=[{name="walls",type="wall_force",axis="z"},{name="side",type="wall_force",axis="x",wall="x-"}]')
chute=("$src/bench/scenes/chute32k.toml" --set 'periodic.x=[0.0,0.022]' --set 'periodic.y=[0.0,0.011]'
       --set 'lattices[0].count=[20,10,1]' --set 'lattices[1].count=[20,10,20]' --set integrator.end_time=0.02
       --set output.interval=0.005 --set output.particles=true --set output.log_interval=0.005)

# The fluidisation case's bed (periodic in x and z, a gas with two-way drag, the drag
# updated explicitly: velocity Verlet without the deferred kick) under an inflow, on
# 2.5 mm cells, which the cell-average drag below needs (a 1.25 mm cell packs beyond
# what the gas equations take when each particle counts whole in its cell).
fluid=("$src/verification/cases/fluidization/scene.toml" --set 'gas.cells=[4,32,2]'
       --set 'gas.boundaries.y_lower={type="velocity_inlet",velocity=0.3}'
       --set integrator.end_time=0.05 --set output.interval=0.01 --set output.log_interval=0.005 --set output.vtk=true
       --set output.particles=true)

for case in settle chute fluid; do
  declare -n args=$case
  "$cdm" run "${args[@]}" -q -j 1 -o "$work/$case-1" > /dev/null || fail "$case: one process"
  for np in 2 3 4; do
    "${launch[@]}" -np "$np" "$cdm" run "${args[@]}" -q -j 1 -o "$work/$case-$np" > "$work/$case-$np.out" 2>&1 ||
      fail "$case: $np processes: $(tail -5 "$work/$case-$np.out")"
    same "$case, $np processes" "$work/$case-1" "$work/$case-$np"
  done
  grep -q "on 4 processes of 1 thread" "$work/$case-4.out" || fail "$case: the run does not say it ran on 4 processes"
done

# Logged every 1e-5 s (about every 6 steps; each process sums its own particles and
# pairs for a line, without a gather): the chute on 2 processes.
shared "chute logged often" 2 "${chute[@]}" --set output.log_interval=1.0e-5
# VTK frames every 1e-5 s (about every 6 steps; for each, every process evaluates its own
# particles' contacts after bringing its ghosts to the frame's state), so that list builds
# fall on steps that follow a frame: a shallower chute on 2 processes.
shared "chute gathered often" 2 "${chute[@]}" --set 'lattices[1].count=[20,10,5]' --set integrator.end_time=0.004 \
  --set output.particles=false --set output.vtk=true --set output.interval=1.0e-5

# Gathered in rounds of 600 values (CDM_MPI_ROUND_VALUES): the flowing chute's state in
# rounds of a few particles, at each build the history of its pairs in contact in
# rounds of 100 pairs per process, its checkpoints' arrays streamed to the writer 600
# slots at a time, and its VTK frames' arrays and contacts 600 values' worth at a time.
small_rounds=("${launch[@]}")
launch+=(-x CDM_MPI_ROUND_VALUES=600)
shared "chute gathered in small rounds" 2 "${chute[@]}" --set output.checkpoint_interval=0.01 \
  --set output.vtk=true --set output.contacts=true
launch=("${small_rounds[@]}")

# 20,000 particles: their whole state (about 40 values each, with the wall history) is
# gathered in rounds of at most 2^18 values (RankSplit::share_particles), four here.
shared "settle 2e4 gathered in rounds" 2 "$src/bench/scenes/settle_1e4.toml" --set 'lattices[0].count=[40,20,25]' \
  --set 'walls[2].point=[0.044,0.0,0.0]' --set 'walls[4].point=[0.0,0.022,0.0]' --set output.particles=false \
  --set integrator.end_time=1.0 --max-steps 40

"${launch[@]}" -np 2 "$cdm" run "${settle[@]}" -q -j 2 -o "$work/settle-2x2" > "$work/settle-2x2.out" 2>&1 ||
  fail "settle: 2 processes of 2 threads: $(tail -5 "$work/settle-2x2.out")"
same "settle, 2 processes of 2 threads" "$work/settle-1" "$work/settle-2x2"

# Stopped on 2 processes, continued on 3: the same end as without the stop.
"${launch[@]}" -np 2 "$cdm" run "${settle[@]}" -q -j 1 -o "$work/split" --max-steps 7000 > /dev/null 2>&1 ||
  fail "restart: first part on 2 processes"
cp "$work/split/checkpoint.cdmck" "$work/half.cdmck"
"${launch[@]}" -np 3 "$cdm" run "${settle[@]}" -q -j 1 -o "$work/split" --restart "$work/half.cdmck" > /dev/null 2>&1 ||
  fail "restart: second part on 3 processes"
for f in particles.dat log.dat checkpoint.cdmck; do
  cmp -s "$work/settle-1/$f" "$work/split/$f" || fail "restart on 3 processes: $f differs from the uninterrupted run"
done

# A checkpoint changed in its last gas planes, which rank 0 of 2 neither keeps nor reads
# as it restores: every block is checked first, each process a share of them, so both
# refuse it (exit 2, the checksum named) before either restores, and nothing is written.
bed=("$src/bench/scenes/bed_1e5.toml" --set 'gas.cells=[24,96,24]' --set 'random_particles[0].count=20000'
     --set output.particles=false --set output.vtk=false -q -j 1)
"${launch[@]}" -np 2 "$cdm" run "${bed[@]}" --max-steps 4 -o "$work/bed" > /dev/null 2>&1 || fail "bed: 2 processes"
body=$(od -An -t u8 -j 12 -N 8 "$work/bed/checkpoint.cdmck")
cp "$work/bed/checkpoint.cdmck" "$work/changed.cdmck"
printf '\x55' | dd of="$work/changed.cdmck" bs=1 seek=$((28 + body - 100000)) conv=notrunc 2> /dev/null
"${launch[@]}" -np 2 "$cdm" run "${bed[@]}" --max-steps 5 -o "$work/refused" --restart "$work/changed.cdmck" \
  > /dev/null 2> "$work/refused.err"
rc=$?
[ "$rc" -eq 2 ] && grep -q "checksum does not match" "$work/refused.err" ||
  fail "a changed checkpoint on 2 processes: exit $rc, $(head -3 "$work/refused.err")"
[ ! -e "$work/refused" ] || fail "a changed checkpoint on 2 processes: the refused restart wrote $work/refused"

# A restart with no step left writes its checkpoint before any build, each process then
# holding the pair contacts of its run of the checkpoint's rows (gathered to rank 0 as they
# were read): on 3 processes the file one process's restart writes, and a run continued
# from it ends as one continued from the original checkpoint.
"${launch[@]}" -np 3 "$cdm" run "${settle[@]}" -q -j 1 -o "$work/ended-3" --restart "$work/split/checkpoint.cdmck" \
  > /dev/null 2>&1 || fail "a restart with no step left on 3 processes"
"$cdm" run "${settle[@]}" -q -j 1 -o "$work/ended-1" --restart "$work/split/checkpoint.cdmck" > /dev/null 2>&1 ||
  fail "a restart with no step left on one process"
cmp -s "$work/ended-1/checkpoint.cdmck" "$work/ended-3/checkpoint.cdmck" ||
  fail "a restart with no step left: the checkpoint written on 3 processes differs from one process's"
for from in "$work/split/checkpoint.cdmck" "$work/ended-3/checkpoint.cdmck"; do
  "$cdm" run "${settle[@]}" --set integrator.end_time=0.032 -q -j 1 -o "$from.more" --restart "$from" > /dev/null 2>&1 ||
    fail "continued from $from"
done
cmp -s "$work/split/checkpoint.cdmck.more/particles.dat" "$work/ended-3/checkpoint.cdmck.more/particles.dat" ||
  fail "continued from the checkpoint a restart with no step left wrote on 3 processes: not as from the original"

# The paper's Euler step (velocity kick and drift of the rank's own particles, the
# forces of the end of the step): the settling bed on 3 processes.
shared "paper Euler" 3 "${settle[@]}" --set 'integrator.scheme="paper_euler"'

# Rolling resistance (its pass reads the torques accumulated so far, and the ghosts'
# torques arrive first): the settling bed with it, on 3 processes (a middle rank).
rolling=("${settle[@]}" --set 'modules.rolling_resistance="constant_torque"' --set 'contacts[0].rolling_mu=0.1'
         --set 'contacts[1].rolling_mu=0.2')
shared "rolling resistance" 3 "${rolling[@]}"
# The chute's slabs wrap around its periodic x: on 2 processes each is the other's
# neighbour both ways, and the torques on both boundary slabs pass between the same two.
shared "chute with rolling resistance" 2 "${chute[@]}" --set 'modules.rolling_resistance="constant_torque"' \
  --set 'contacts[0].rolling_mu=0.1' --set 'contacts[1].rolling_mu=0.2'
# The fewest slabs a periodic axis is cut into, four (a 4.6 mm period), on 3 and 4
# processes: one slab each, the first process's shadow slab the last.
for np in 3 4; do
  shared "four wrapping slabs" "$np" "$src/bench/scenes/chute32k.toml" --set 'periodic.x=[0.0,0.0046]' \
    --set 'periodic.y=[0.0,0.0033]' --set 'lattices[0].count=[4,3,1]' --set 'lattices[1].count=[4,3,2]' \
    --set integrator.end_time=0.02 --set output.interval=0.005 --set output.particles=true
done

# Hertz-Mindlin friction reads both particles' step velocities and spins, a ghost's too,
# and the pile's rolling resistance their spins: the pile on 3 processes.
shared "Hertz-Mindlin pile" 3 "$src/tests/cli/scenes/hertz_pile.toml" --set integrator.end_time=0.004 \
  --set output.interval=0.0005

# Moving walls (translating, oscillating, turning; friction and rolling resistance): the
# wall candidates are listed again between builds, for each process's own particles
# (whose build positions alone it holds), and a frame's contact network and a checkpoint
# read every particle's wall contacts: on 3 processes.
shared "moving walls" 3 "$src/tests/cli/scenes/moving_walls.toml" --set integrator.end_time=0.01 \
  --set output.interval=0.001 --set output.vtk=true --set output.contacts=true --set output.checkpoint_interval=0.005

# Insertions (from 0.05 s) and an outlet (the lattice's corner leaves at once): every
# process gets the positions near the box and inserts the same particles, process 0's until the next
# build; the owners find the particles leaving. Samples fall on
# insertion steps, where the wall contacts are set aside until the next listing. Then
# an insertion at every step from 0.05 s, on 3 processes.
fed=("$src/examples/bed_fed_from_above/scene.toml" --set integrator.end_time=0.07 --set output.log_interval=0.002
     --set output.interval=0.01 --set output.checkpoint_interval=0.03)
shared "bed fed from above" 2 "${fed[@]}"
shared "bed fed at every step" 3 "${fed[@]}" --set 'insertions[0].interval=0.0'
# The settling column fed from above and drained at a corner, ending on an insertion step
# with its checkpoint and a VTK frame: the wall contacts set aside there are each
# process's own, joined on rank 0 (without the join the checkpoint lacks the others'),
# on 3 processes.
drained=(--set 'insertions=[{material="glass",lower=[0.001,0.001,0.06],upper=[0.021,0.021,0.07],count_rate=2000.0,count=40,start=0.0,interval=0.005,velocity=[0.0,0.0,-0.5],seed=7,size={distribution="normal",mean=0.001,std=0.0001}}]'
         --set 'outlets=[{name="corner",type="box",lower=[0.0,0.0,-0.001],upper=[0.004,0.004,0.002]}]')
shared "settle fed and drained" 3 "${settle[@]}" --set integrator.end_time=0.015 "${drained[@]}"
# Never sorted (neighbour_list.sort_interval = 0): the first build deals the scene's
# order as it is stored, each process's particles scattered over the store, and a removal
# and the insertions append where no sort gathers them: the settling bed, and it fed and
# drained, on 3 processes.
shared "settle never sorted" 3 "${settle[@]}" --set neighbour_list.sort_interval=0
shared "settle fed and drained, never sorted" 3 "${settle[@]}" --set integrator.end_time=0.015 "${drained[@]}" \
  --set neighbour_list.sort_interval=0

# An insertion among processes reads the positions of the particles near its box only,
# which their owners share: a box whose floor lies less than two radii above a settled
# layer's centres, so that the layer's particles, outside the box, turn placements away,
# on 3 processes.
shared "insertion above a layer" 3 "$src/bench/scenes/settle_1e4.toml" --set 'lattices[0].count=[10,10,5]' \
  --set integrator.end_time=0.002 --set output.interval=0.0005 --set output.log_interval=0.0001 \
  --set 'insertions=[{material="glass",lower=[0.0005,0.0005,0.0058],upper=[0.0105,0.0105,0.0085],count_rate=1.0e6,count=150,start=0.0005,interval=0.0005,radius=0.5e-3}]'

# Outlets among processes (each finds its own particles in them, every process removes
# them all alike, and with a gas deposits what their drag gave it so far, in slot order):
# the fluidisation bed falling through one box outlet halfway up, then draining into one
# in a corner of the distributor, on 3 processes.
shared "outlets" 3 "${fluid[@]}" --set output.vtk=false \
  --set 'outlets=[{name="middle",type="box",lower=[0.0,0.03,0.0],upper=[0.003,0.033,0.005]},{name="drain",type="box",lower=[0.0,0.0,0.0],upper=[0.004,0.004,0.005]}]'

# Beads that cross to another process while they touch a triangle mesh (a build gathers
# the positions only; each bead's mesh contacts, their tangential history, go with it to
# its new owner): the mesh pile rolling on its box's floor, on 2 processes.
shared "mesh pile" 2 "$src/tests/cli/scenes/mesh_pile.toml" --set integrator.end_time=0.01 \
  --set output.interval=0.005 --set output.log_interval=0.001

# Triangle meshes (each rank finds its own particles' contacts; the lists are joined at
# every gather) and an outlet: the silo, logged every step, on 2 processes.
shared "silo" 2 "$src/examples/silo/silo.toml" --max-steps 9000 --set output.log_interval=8.0e-6 --set output.interval=10

# A gas with two-way drag deposited at every step (the Mueller bed's first 300 steps,
# VTK of particles and gas, the gas evaluated at every step rather than the scene's once
# per gas step): bit-identical on 2 processes.
mueller=("$src/bench/scenes/mueller_bubbling_bed.toml" --set output.interval=0.0005 --set output.log_interval=0.0005)
every=(--set 'coupling.drag_evaluation="every_step"')
"$cdm" run "${mueller[@]}" "${every[@]}" -q -j 1 -o "$work/mueller-1" --max-steps 300 > /dev/null ||
  fail "mueller: one process"
# One process without a launcher (MPI for hypre) starts no daemon that would outlive it
# and remove Open MPI's session folder while the launch below creates its own there.
[ -z "$(ls -A "$OMPI_MCA_orte_tmpdir_base")" ] ||
  fail "mueller: one process left Open MPI's session folder behind: $(ls -A "$OMPI_MCA_orte_tmpdir_base")"
"${launch[@]}" -np 2 "$cdm" run "${mueller[@]}" "${every[@]}" -q -j 1 -o "$work/mueller-2" --max-steps 300 \
  > "$work/mueller-2.out" 2>&1 ||
  fail "mueller: 2 processes: $(tail -5 "$work/mueller-2.out")"
same "mueller, 2 processes" "$work/mueller-1" "$work/mueller-2"

# The drag evaluated once per gas step (its K and u_g, and the pressure-gradient force,
# kept per particle between gas steps travel with the particles to their next owner):
# the Mueller bed's first 3000 steps on 2 processes (its 15 x 40 x 3 cells solved by
# multigrid along y, x and y swapped for hypre; the gas step divided by planes, which on
# these 1800 cells "auto" would not do), the fluidisation bed on 3 (its gas whole on each).
shared "mueller once per gas step" 2 "${mueller[@]}" --max-steps 3000 --set output.vtk=false \
  --set 'coupling.drag_evaluation="gas_step"' --set 'gas.division="planes"'
shared "fluidisation once per gas step" 3 "${fluid[@]}" --set 'coupling.drag_evaluation="gas_step"'
# The drag deposited at every step by each process in exact sums, where the cells the
# particles reach outnumber them: the positions and impulses are gathered and every
# process deposits them all (the same sums). 640 beads in the case's 8 x 64 x 4 cells.
shared "every-step deposit gathered" 2 "${fluid[@]}" --set 'gas.cells=[8,64,4]' --set 'lattices[0].count=[8,20,4]' \
  --set output.vtk=false
# The paper's cell-average drag (each particle sees its cell's mean solids velocity, so
# every rank's particles are gathered first): the fluidisation bed on 2 processes.
shared "cell-average drag" 2 "${fluid[@]}" --set 'coupling={mode="two_way", method="cell_average"}'
# The gas taking the drag implicitly (each process deposits its own particles' K and K v
# and kicks its own particles after the gas step, without a gather): the Mueller bed's
# first 3000 steps, falling into place, on 3 processes.
shared "implicit gas drag" 3 "${mueller[@]}" --max-steps 3000 --set output.vtk=false \
  --set 'drag.update="exponential"' --set 'coupling.gas_drag="implicit"'

# Particles without contacts have no slabs: each process moves a fixed run of rows
# (RankSplit::divide_by_rows). By default (gas.division = "auto") each steps the whole gas
# on a grid this small, as it says; with gas.division = "planes" they divide the gas
# step's loops by planes (plane_share.hpp), as it says. The results are those of one
# process.
gas=("$src/bench/scenes/gas_scaling.toml" --set 'gas.cells=[8,8,8]' --set integrator.end_time=2.0e-4)
"$cdm" run "${gas[@]}" -q -o "$work/gas-1" > /dev/null || fail "gas scene: one process"
"${launch[@]}" -np 2 "$cdm" run "${gas[@]}" -q -o "$work/gas-2" > "$work/gas-2.out" 2>&1 ||
  fail "gas scene: 2 processes: $(tail -5 "$work/gas-2.out")"
[ "$(grep -c "the particles' work is shared among 2 MPI processes; each steps the whole gas (gas.division = \"auto\": its 512 cells give a process fewer than 2048)" "$work/gas-2.out")" -eq 1 ] ||
  fail "gas scene on 2 processes: not one notice of the whole gas step: $(cat "$work/gas-2.out")"
same "gas scene, 2 processes" "$work/gas-1" "$work/gas-2"
"${launch[@]}" -np 2 "$cdm" run "${gas[@]}" --set 'gas.division="planes"' -q -o "$work/gas-2p" > "$work/gas-2p.out" 2>&1 ||
  fail "gas scene, planes: 2 processes: $(tail -5 "$work/gas-2p.out")"
[ "$(grep -c "the particles' work and the gas step (its direct pressure solve done whole by each) are shared among 2 MPI processes" "$work/gas-2p.out")" -eq 1 ] ||
  fail "gas scene, planes, on 2 processes: not one notice: $(cat "$work/gas-2p.out")"
same "gas scene, gas step divided, 2 processes" "$work/gas-1" "$work/gas-2p"
# "auto" divides where every process gets 2048 cells or more: 16 x 16 x 16 on 2.
gas16=("$src/bench/scenes/gas_scaling.toml" --set 'gas.cells=[16,16,16]' --set integrator.end_time=2.0e-4)
"$cdm" run "${gas16[@]}" -q -o "$work/gas16-1" > /dev/null || fail "gas scene, 16^3: one process"
"${launch[@]}" -np 2 "$cdm" run "${gas16[@]}" -q -o "$work/gas16-2" > "$work/gas16-2.out" 2>&1 ||
  fail "gas scene, 16^3: 2 processes: $(tail -5 "$work/gas16-2.out")"
grep -q "the particles' work and the gas step are shared among 2 MPI processes" "$work/gas16-2.out" ||
  fail "gas scene, 16^3, on 2 processes: the divided gas step not reported: $(cat "$work/gas16-2.out")"
same "gas scene, 16^3, 2 processes" "$work/gas16-1" "$work/gas16-2"
# Beads without contacts raining through a gas, fed by an insertion (whose particles each
# process takes its run of rows of) and drained by an outlet: on 2, 3 and 4 processes; the
# drag once per gas step, the gas taking it implicitly and the paper's Euler step on 3;
# stopped on 3 and continued on 2 after the insertion (resumed, below). Inertial
# particles in a prescribed Taylor-Green vortex on 3.
rain=("$src/tests/cli/scenes/drag_rain.toml")
for np in 2 3 4; do shared "rain without contacts" "$np" "${rain[@]}"; done
shared "rain, drag once per gas step" 3 "${rain[@]}" --set 'coupling.drag_evaluation="gas_step"'
shared "rain, implicit gas drag" 3 "${rain[@]}" --set 'drag.update="exponential"' --set 'coupling.gas_drag="implicit"'
shared "rain, Euler step" 3 "${rain[@]}" --set 'integrator.scheme="paper_euler"'
shared "Taylor-Green clustering" 3 "$src/verification/cases/taylor_green_clustering/scene.toml" \
  --set integrator.end_time=0.4 --set output.interval=0.05 --set output.particles=true --set output.vtk=true
shared "rain, exponential midpoint" 3 "${rain[@]}" --set 'integrator.scheme="exponential_midpoint"' \
  --set 'drag.update="exponential"'
# Tracers (Runge-Kutta steps, the gas velocity read where each is): on 3, and a restart
# from 2 onto 3 (resumed, below).
tracers=("$src/verification/cases/circle_advection/scene.toml" --set integrator.end_time=0.05
         --set output.particles=true --set output.interval=0.01 --set output.vtk=true --set output.log_interval=0.01)
shared "tracers" 3 "${tracers[@]}"

# The gas step, its loops and its multigrid pressure solve, divided among the processes
# (gas.division = "planes": each owns whole planes of cells; plane_share.hpp,
# pressure_multigrid.cpp), with the gas the same to the bit: the gas
# scene without contacts (its 8 planes split 3, 3, 2 on 3 processes; VTK of the gas and a
# checkpoint), the periodic 2D gas of the MMS case on 2, and the fluidisation bed (2
# planes: the third and fourth process own none) on 4.
gas_mg=("${gas[@]}" --set 'gas.pressure_solver="multigrid"' --set output.interval=1.0e-4 --set output.vtk=true
        --set output.checkpoint_interval=1.0e-4 --set 'gas.division="planes"')
"$cdm" run "${gas_mg[@]}" -q -o "$work/gas-mg-1" > /dev/null || fail "gas scene, multigrid: one process"
"${launch[@]}" -np 3 "$cdm" run "${gas_mg[@]}" -q -o "$work/gas-mg-3" > "$work/gas-mg-3.out" 2>&1 ||
  fail "gas scene, multigrid: 3 processes: $(tail -5 "$work/gas-mg-3.out")"
grep -q "the particles' work and the gas step are shared among 3 MPI processes" "$work/gas-mg-3.out" ||
  fail "gas scene, multigrid, on 3 processes: the shared solve not reported: $(cat "$work/gas-mg-3.out")"
same "gas scene with the multigrid solve, 3 processes" "$work/gas-mg-1" "$work/gas-mg-3"
mms=("$src/verification/cases/gas_mms/scene.toml" --set 'gas.cells=[32,32]' --set 'gas.pressure_solver="multigrid"'
     --set 'gas.division="planes"'
     --set integrator.end_time=0.02 --set output.interval=0.01 --set output.vtk=true)
"$cdm" run "${mms[@]}" -q -o "$work/mms-1" > /dev/null || fail "MMS gas, multigrid: one process"
"${launch[@]}" -np 2 "$cdm" run "${mms[@]}" -q -o "$work/mms-2" > "$work/mms-2.out" 2>&1 ||
  fail "MMS gas, multigrid: 2 processes: $(tail -5 "$work/mms-2.out")"
same "MMS gas with the multigrid solve, 2 processes" "$work/mms-1" "$work/mms-2"
shared "fluidisation with the multigrid solve" 4 "${fluid[@]}" --set 'gas.pressure_solver="multigrid"' \
  --set 'gas.division="planes"'
grep -q "the particles' work and the gas step are shared among 4 MPI processes" \
  "$work/fluidisation-with-the-multigrid-solve-4.out" || fail "fluidisation, multigrid: the shared solve not reported"
# A bed as wide as it is deep over a gas divided by planes along z: its slabs are cut
# along z too, and each process receives the gas on the planes under its particles and
# next to its own (of 12 planes, 4 its own on 3 processes), not every plane, and adds up
# the particles' deposits on those planes only; a frame, the log's pressure drop and a
# checkpoint read the whole gas. 20,000 beads of the 1e5 bed falling into 12 x 48 x 12
# cells on 3 processes, the drag once per gas step and at every step, and stopped on 3 and
# continued on 2.
bed=("$src/bench/scenes/bed_1e5.toml" --set 'random_particles[0].count=20000' --set 'gas.cells=[12,48,12]'
     --set 'gas.division="planes"' --set integrator.end_time=0.002 --set output.interval=0.0005
     --set output.particles=true --set output.log_interval=0.0005 --set output.checkpoint_interval=0.001)
shared "bed over the gas planes" 3 "${bed[@]}"
shared "bed over the gas planes, drag every step" 3 "${bed[@]}" --set 'coupling.drag_evaluation="every_step"'
# The gas taking the drag implicitly adds up the particles' K and K v on each process's
# planes; a drain at the far corner (emptied cells, where what the gas took waits for a
# particle) leaves differences on the last process's planes, which its checkpoints hold.
implicit=(--set 'drag.update="exponential"' --set 'coupling.gas_drag="implicit"'
          --set 'outlets=[{name="drain", type="box", lower=[0.0,-0.01,0.04], upper=[0.06,0.03,0.06]}]')
shared "bed over the gas planes, implicit gas drag" 3 "${bed[@]}" "${implicit[@]}"
# In a closed box (inlet and outlet made walls) the pressure's mean and the right-hand
# side's are taken out, added up over each process's own planes in exact sums.
shared "bed over the gas planes, closed box" 3 "${bed[@]}" --set 'gas.boundaries.y_lower="no_slip"' \
  --set 'gas.boundaries.y_upper="no_slip"'
# Periodic along z (its walls there left out): a process whose reach meets neither end
# keeps and receives its reach only; one that meets an end reads every plane (the ghosts
# wrap). 24 planes on 4 processes: the two middle ones keep their reach.
periodic_z=(--set 'gas.cells=[12,48,24]' --set 'gas.boundaries.z_lower="periodic"'
            --set 'gas.boundaries.z_upper="periodic"'
            --set 'walls=[{name="distributor", point=[0.0,0.0,0.0], normal=[0.0,1.0,0.0], material="wall"},
                          {name="lid", point=[0.0,0.24,0.0], normal=[0.0,-1.0,0.0], material="wall"},
                          {name="x_lower", point=[0.0,0.0,0.0], normal=[1.0,0.0,0.0], material="wall"},
                          {name="x_upper", point=[0.06,0.0,0.0], normal=[-1.0,0.0,0.0], material="wall"}]')
shared "bed over periodic gas planes" 4 "${bed[@]}" "${periodic_z[@]}"
# The direct pressure solve is done whole by each process: it reads every plane.
shared "bed over the gas planes, direct solve" 3 "${bed[@]}" --set 'gas.pressure_solver="direct"'
# Fed from above (2,000 beads inserted high in the column, which each process deals out
# and whose planes it then reads) and drained at a floor corner (112 leave, their impulse
# deposited where they left).
shared "bed over the gas planes, fed and drained" 3 "${bed[@]}" \
  --set 'insertions=[{material="glass", lower=[0.005,0.1,0.005], upper=[0.055,0.12,0.055], count_rate=1.0e6, count=2000, start=0.0, interval=0.0005, velocity=[0.0,-1.0,0.0], seed=7, radius=5.0e-4}]' \
  --set 'outlets=[{name="drain", type="box", lower=[0.0,-0.01,0.0], upper=[0.02,0.003,0.02]}]'
# 2,000 beads: fewer than the cells they reach, which without the planes would have every
# process deposit every bead (the positions gathered); by planes each sends its reach.
shared "dilute bed over the gas planes" 3 "${bed[@]}" --set 'random_particles[0].count=2000' \
  --set 'coupling.drag_evaluation="every_step"'

# Between machines Open MPI talks over a network, not through shared memory: with its
# shared-memory transport left out (TCP on the loopback, as between two nodes) the chute
# and the Mueller bed (its gas step and multigrid solve divided by planes) give one
# process's files on 2 processes.
near_launch=("${launch[@]}")
source "$src/bench/mpi_transports.sh"
launch+=("${mpi_tcp[@]}")
shared "chute over TCP" 2 "${chute[@]}"
shared "mueller over TCP" 2 "${mueller[@]}" --max-steps 600 --set output.vtk=false \
  --set 'coupling.drag_evaluation="gas_step"' --set 'gas.division="planes"'
launch=("${near_launch[@]}")

# A restart reads each process's share of the state (its run of rows, the list's build
# positions too) and of the pair contacts; its first listing reads from the rows' holders
# the positions it searches and moves each particle's state to its owner: runs stopped on one count of processes and continued on another end as one
# process's uninterrupted run (the runs above), with a gas and the drag kept per particle
# between gas steps, with insertions and outlets, and with mesh contacts.
# resumed TAG ONE_DIR NP1 NP2 STEPS SCENE ARGS...
resumed() {
  local tag=$1 one=$2 np1=$3 np2=$4 steps=$5 dir="$work/resumed-${1// /-}" n=0
  shift 5
  "${launch[@]}" -np "$np1" "$cdm" run "$@" -q -j 1 -o "$dir" --max-steps "$steps" > "$dir.out" 2>&1 ||
    fail "$tag: first part on $np1 processes: $(tail -5 "$dir.out")"
  cp "$dir/checkpoint.cdmck" "$dir.cdmck"
  "${launch[@]}" -np "$np2" "$cdm" run "$@" -q -j 1 -o "$dir" --restart "$dir.cdmck" > "$dir.out" 2>&1 ||
    fail "$tag: continued on $np2 processes: $(tail -5 "$dir.out")"
  for f in particles.dat log.dat outlets.dat checkpoint.cdmck; do
    [ -e "$one/$f" ] || continue
    cmp -s "$one/$f" "$dir/$f" || fail "$tag, stopped on $np1 processes and continued on $np2: $f differs from one process's"
    n=$((n + 1))
  done
  [ "$n" -ge 2 ] || fail "$tag: $n files compared"
}
resumed "fluidisation once per gas step" "$work/fluidisation-once-per-gas-step-1" 2 3 1000 "${fluid[@]}" \
  --set 'coupling.drag_evaluation="gas_step"'
resumed "bed fed from above" "$work/bed-fed-from-above-1" 3 2 3000 "${fed[@]}"
resumed "rain without contacts" "$work/rain-without-contacts-1" 3 2 1111 "${rain[@]}"
resumed "tracers" "$work/tracers-1" 2 3 9 "${tracers[@]}"
resumed "bed over the gas planes" "$work/bed-over-the-gas-planes-1" 3 2 333 "${bed[@]}"
resumed "bed over the gas planes, implicit gas drag" "$work/bed-over-the-gas-planes,-implicit-gas-drag-1" 3 2 480 \
  "${bed[@]}" "${implicit[@]}"
resumed "bed over periodic gas planes" "$work/bed-over-periodic-gas-planes-1" 4 3 333 "${bed[@]}" "${periodic_z[@]}"
resumed "mesh pile" "$work/mesh-pile-1" 3 2 1000 "$src/tests/cli/scenes/mesh_pile.toml" --set integrator.end_time=0.01 \
  --set output.interval=0.005 --set output.log_interval=0.001

# A restart whose first step's build is due carries the loaded contacts into that build
# (no listing of the loaded pairs first): a lattice thrown at the floor at 2 m/s, its list
# built every 16 steps or so, stopped by one process at each of 20 consecutive steps and
# continued on 2 or 3 processes, ends with one process's checkpoint and log every time.
thrown=("$src/bench/scenes/settle_1e4.toml" --set 'lattices[0].count=[10,10,20]' --set 'lattices[0].velocity=[0.0,0.0,-2.0]'
        --set integrator.end_time=0.03 --set output.particles=false --set output.vtk=false --set output.log_interval=1e-4)
"$cdm" run "${thrown[@]}" -q -j 1 -o "$work/thrown-1" --max-steps 140 > /dev/null || fail "thrown: one process"
for k in $(seq 100 119); do
  d="$work/thrown-$k" np=$((2 + k % 2))
  "$cdm" run "${thrown[@]}" -q -j 1 -o "$d" --max-steps "$k" > /dev/null || fail "thrown: stopped at step $k"
  cp "$d/checkpoint.cdmck" "$d.cdmck"
  "${launch[@]}" -np "$np" "$cdm" run "${thrown[@]}" -q -j 1 -o "$d" --restart "$d.cdmck" --max-steps $((140 - k)) \
    > "$d.out" 2>&1 || fail "thrown: continued from step $k on $np processes: $(tail -3 "$d.out")"
  for f in log.dat checkpoint.cdmck; do
    cmp -s "$work/thrown-1/$f" "$d/$f" || fail "thrown, continued from step $k on $np processes: $f differs from one process's"
  done
done

# SIGTERM to mpirun, which passes it to every process (as Slurm does to each task): a
# checkpoint, the command to continue, and a restart on 3 processes that ends as one
# process's uninterrupted run.
sigrun=("$src/bench/scenes/settle_1e4.toml" --set 'lattices[0].count=[10,10,50]' --set integrator.end_time=0.1
        --set output.interval=0.01)
"$cdm" run "${sigrun[@]}" -q -j 1 -o "$work/sig-1" > /dev/null || fail "signal: one process"
"${launch[@]}" -np 2 "$cdm" run "${sigrun[@]}" -q -j 1 -o "$work/sig" > /dev/null 2> "$work/sig.err" &
pid=$!
# The signal once both processes are in the loop, whatever the machine's speed: the
# table's first bytes are written there, and it has grown since, a poll later.
first=0
for _ in $(seq 1 1200); do
  size=$(stat -c %s "$work/sig/particles.dat" 2> /dev/null || echo 0)
  [ "$first" = 0 ] && first=$size
  [ "$first" -gt 0 ] && [ "$size" -gt "$first" ] && break
  kill -0 "$pid" 2> /dev/null || fail "SIGTERM to mpirun: the run ended before its table grew"
  sleep 0.1
done
kill -TERM "$pid"
wait "$pid"
[ -s "$work/sig/checkpoint.cdmck" ] || fail "SIGTERM to mpirun: no checkpoint: $(tail -3 "$work/sig.err")"
stops=$(grep -c "stopped by signal 15; continue with" "$work/sig.err" || true)
[ "$stops" = 1 ] || fail "SIGTERM to mpirun: the command to continue printed $stops times, expected once"
"${launch[@]}" -np 3 "$cdm" run "${sigrun[@]}" -q -j 1 -o "$work/sig" --restart "$work/sig/checkpoint.cdmck" \
  > /dev/null 2>&1 || fail "restart on 3 processes after SIGTERM"
cmp -s "$work/sig-1/particles.dat" "$work/sig/particles.dat" || fail "the run stopped by SIGTERM and restarted differs"

# Rank 0's write failing (a full device) among processes: every process stops at once,
# exit 4 with the path and the reason, and the checkpoint's temporary file removed.
fullrun=("${settle[@]}" --set output.vtk=false --set output.contacts=false --set output.checkpoint_interval=0.01)
mkdir -p "$work/devfull" "$work/ckfull"
ln -s /dev/full "$work/devfull/particles.dat"
ln -s /dev/full "$work/ckfull/checkpoint.cdmck.tmp"
for d in devfull ckfull; do
  "${launch[@]}" -np 2 "$cdm" run "${fullrun[@]}" -q -j 1 -o "$work/$d" > "$work/$d.out" 2>&1
  rc=$?
  [ "$rc" -eq 4 ] || fail "$d on 2 processes: exit status $rc, expected 4: $(tail -3 "$work/$d.out")"
  grep -q "$d/[a-z.]*': No space left on device" "$work/$d.out" || fail "$d on 2 processes: no path and reason: $(cat "$work/$d.out")"
done
[ ! -e "$work/ckfull/checkpoint.cdmck.tmp" ] || fail "ckfull on 2 processes: the checkpoint's temporary file was left behind"

# One process lost (SIGKILL to rank 1, as when a node fails): mpirun stops the others and
# exits non-zero, rank 0's files stay as last written whole, and the run continued from
# its last checkpoint on 2 processes ends as one process's uninterrupted run: particle
# table, log and checkpoint.
lostrun=("${sigrun[@]}" --set output.checkpoint_interval=0.005 --set output.log_interval=0.005)
"$cdm" run "${lostrun[@]}" -q -j 1 -o "$work/lost-1" > /dev/null || fail "a lost process: one process"
"${launch[@]}" -np 3 "$cdm" run "${lostrun[@]}" -q -j 1 -o "$work/lost" > /dev/null 2> "$work/lost.err" &
pid=$!
for _ in $(seq 1200); do [ -s "$work/lost/checkpoint.cdmck" ] && break; sleep 0.05; done
[ -s "$work/lost/checkpoint.cdmck" ] || fail "a lost process: no first checkpoint within a minute"
victim=""
for c in $(pgrep -P "$pid"); do
  tr '\0' '\n' < "/proc/$c/environ" 2> /dev/null | grep -qx "OMPI_COMM_WORLD_RANK=1" && victim=$c
done
[ -n "$victim" ] || fail "a lost process: rank 1 not found among mpirun's processes"
kill -KILL "$victim"
wait "$pid" && fail "a lost process: mpirun exited 0 after rank 1 was killed (the run ended first?)"
cp "$work/lost/checkpoint.cdmck" "$work/lost.cdmck"
"${launch[@]}" -np 2 "$cdm" run "${lostrun[@]}" -q -j 1 -o "$work/lost" --restart "$work/lost.cdmck" \
  > "$work/lost.out" 2>&1 || fail "a lost process: the restart on 2 processes: $(tail -3 "$work/lost.out")"
for f in particles.dat log.dat checkpoint.cdmck; do
  cmp -s "$work/lost-1/$f" "$work/lost/$f" || fail "a lost process: $f after the restart differs from the uninterrupted run's"
done

echo "mpi_ranks: settle, chute and the fluidisation bed bit-identical on 1-4 processes and 2x2 threads, restart from 2 onto 3 and a restart with no step left on 3, a changed checkpoint refused by both of 2, rolling resistance and the Euler step on 3 (and on the chute on 2), four wrapping slabs on 3 and 4, a fed bed on 2 and 3, a fed and drained settle on 3, an insertion above a layer on 3, outlets in a gas on 3, restarts onto another count with a gas, insertions and meshes, the silo, the mesh pile and a chute logged often and one gathered often on 2, the implicit gas drag on 3, Mueller on 2 (also once per gas step), the drag once per gas step on 3, cell-averaged on 2 and deposited from gathered impulses on 2, particles without contacts shared by rows on 2-4 (fed, drained, restarted from 3 onto 2; every integrator; tracers on 3 and restarted from 2 onto 3), the multigrid pressure solve divided on 2-4, a bed over the gas planes on 3 (the drag once per gas step, at every step, implicit, with the direct solve, in a closed box; fed and drained; restarted onto 2), and periodic along z on 4 (restarted onto 3), a lattice thrown at the floor stopped at 20 steps in turn and continued on 2 or 3, a run stopped by SIGTERM on 2 and continued on 3, one with a process killed on 3 continued on 2, a full device on 2"
