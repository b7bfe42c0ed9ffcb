#!/usr/bin/env bash
# In a build without MPI, under mpirun with 2 processes cdm refuses (exit 2, one message,
# nothing written) instead of running the whole problem twice into the same files; with
# 1 process it runs as without a launcher.
set -u
cdm="$1" src="$2" work="$3"
rm -rf "$work"; mkdir -p "$work"
source "$(dirname "$0")/common.sh"
command -v mpirun > /dev/null || fail "mpirun not found (Debian's openmpi-bin)"
root=(); [ "$(id -u)" -eq 0 ] && root=(--allow-run-as-root)
scene="$src/bench/scenes/settle_1e4.toml"
mpirun "${root[@]}" --oversubscribe -np 2 "$cdm" run "$scene" -q -o "$work/two" --max-steps 10 > "$work/out2" 2> "$work/err2"
rc=$?
[ "$rc" -ne 0 ] || fail "2 processes: exit 0"
[ "$(grep -c "started on 2 MPI processes, but this cdm was built without MPI" "$work/err2" "$work/out2" | awk -F: '{s += $2} END {print s}')" -eq 1 ] ||
  fail "2 processes: not one message: $(cat "$work/err2")"
[ ! -e "$work/two" ] || fail "2 processes: the output directory was created"
mpirun "${root[@]}" -np 1 "$cdm" run "$scene" -q -o "$work/one" --max-steps 10 > /dev/null 2>&1 || fail "1 process"
"$cdm" run "$scene" -q -o "$work/plain" --max-steps 10 > /dev/null || fail "no launcher"
cmp -s "$work/one/particles.dat" "$work/plain/particles.dat" || fail "1 process and no launcher differ"
echo "mpi_refused: 2 processes refused, 1 process as without mpirun"
