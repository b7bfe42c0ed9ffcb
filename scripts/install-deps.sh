#!/usr/bin/env bash
# Install the Debian 12 packages cdm builds with, if any is missing. Idempotent.
# python3-matplotlib draws the report and python3-vtk9 reads VTK output back in a test
# (both run with /usr/bin/python3), chromium checks the report in
# a test, clang and its runtime build the fuzz target (fuzz/README.md); hypre and Open MPI
# solve the gas pressure equation.
set -euo pipefail
pkgs=(cmake g++ make pkg-config
      libeigen3-dev libsundials-dev libgsl-dev libgtest-dev
      libtomlplusplus-dev libcli11-dev zlib1g-dev
      libhypre-dev libopenmpi-dev openmpi-bin
      python3-matplotlib python3-vtk9 chromium
      clang libclang-rt-14-dev)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#pkgs[@]} packages present"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
