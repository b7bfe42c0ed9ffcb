#!/usr/bin/env bash
# usage: install_consumer.sh BUILD_DIR SOURCE_DIR
# Installs the build into a temporary prefix and uses it as an outsider would:
#  1. a ten-line program built with find_package(cdm) runs a scene through cdm::solver;
#  2. pkg-config gives flags that compile and link the same program;
#  3. the installed `cdm` reports its version and verifies free_fall from the installed
#     cases, run from a folder where the build tree cannot be reached by a relative path,
#     and its binary holds no path into the source or build tree.
set -euo pipefail
build=$(realpath "$1"); src=$(realpath "$2")
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
prefix=$tmp/prefix
cmake --install "$build" --prefix "$prefix" > "$tmp/install.log"
for f in bin/cdm lib/libcdm_solver.a include/cdm/solver/simulation.hpp lib/cmake/cdm/cdmConfig.cmake \
         lib/pkgconfig/cdm.pc share/cdm/verification/cases/free_fall/scene.toml share/cdm/reports/make_report.py \
         share/cdm/docs/scene-reference.md; do
  [ -e "$prefix/$f" ] || { echo "FAIL: $f not installed"; exit 1; }
done

# 1. find_package(cdm)
cmake -S "$src/tests/install/consumer" -B "$tmp/consumer" -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_BUILD_TYPE=Release \
      > "$tmp/consumer.log" 2>&1 || { cat "$tmp/consumer.log"; exit 1; }
cmake --build "$tmp/consumer" > "$tmp/consumer-build.log" 2>&1 || { cat "$tmp/consumer-build.log"; exit 1; }
scene=$prefix/share/cdm/verification/cases/free_fall/scene.toml
out=$("$tmp/consumer/consumer" "$scene")
echo "find_package consumer: $out"
echo "$out" | grep -qE '^t = [0-9.e+-]+ s after [1-9][0-9]* steps, 1 particles$'

# 2. pkg-config
flags=$(PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config --cflags --libs cdm)
g++ -O1 "$src/tests/install/consumer/consumer.cpp" $flags -o "$tmp/consumer_pc"
out=$("$tmp/consumer_pc" "$scene")
echo "pkg-config consumer: $out"

# 3. the installed command
ver=$("$prefix/bin/cdm" --version)
echo "$ver"
echo "$ver" | grep -qE '^cdm [0-9]+\.[0-9]+\.[0-9]+ \(commit ([0-9a-f]{40}(\+uncommitted)?|unknown)\)(, built without MPI and hypre)?$'
if grep -qaF "$src" "$prefix/bin/cdm" || grep -qaF "$build" "$prefix/bin/cdm"; then
  echo "FAIL: the installed binary holds a path into the source or build tree"; exit 1
fi
"$prefix/bin/cdm" verify --help | grep -qF "$prefix/share/cdm/verification/cases" ||
  { echo "FAIL: the installed cdm does not default to its installed cases"; exit 1; }
"$prefix/bin/cdm" report --help | grep -qF "$prefix/share/cdm/reports/make_report.py" ||
  { echo "FAIL: the installed cdm does not default to its installed report script"; exit 1; }
mkdir "$tmp/elsewhere"
(cd "$tmp/elsewhere" && "$prefix/bin/cdm" verify free_fall --out v > verify.log 2>&1) || { cat "$tmp/elsewhere/verify.log"; exit 1; }
grep -q 'passed, 0 failed' "$tmp/elsewhere/verify.log"
grep -q "commit" "$tmp/elsewhere/v/provenance.dat"
echo "installed cdm verify free_fall: passed"
