#!/usr/bin/env bash
# Set-up from nothing: install the Debian packages mortar2d needs (only those
# missing; quiet and fast when everything is there), then configure and build
# under build/ (which also generates the .msh files from meshes/*.geo).
# Works as root or with sudo. Set M2D_WERROR=1 to make warnings errors (CI).
# libopenblas0-serial: an optimised single-threaded BLAS behind MUMPS' dense
# kernels (Debian's default reference BLAS makes every factorization about 2x
# slower); serial, so 1- and 2-rank timings compare one core per rank.
set -euo pipefail
cd "$(dirname "$0")/.."

PKGS="petsc-dev libmetis-dev libmumps-dev libmumps-headers-dev libopenblas0-serial gmsh libgmsh-dev cmake make gcc pkg-config openmpi-bin
      python3 python3-numpy python3-scipy python3-h5py python3-matplotlib
      paraview python3-paraview xvfb xauth valgrind"
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
if [ -n "$missing" ]; then
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO=sudo
  echo "setup: installing Debian packages:$missing"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends $missing >/dev/null
fi

cmake_args=(-S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DM2D_TEST_HOOKS="${M2D_TEST_HOOKS:-OFF}")
[ "${M2D_WERROR:-0}" = "1" ] && cmake_args+=(-DM2D_WERROR=ON)
cmake "${cmake_args[@]}" >/dev/null
cmake --build build -j"$(nproc)" 2>&1 | grep -E "warning|error|Error" || true
test -x build/mortar2d || { echo "setup: build failed (see: cmake --build build)" >&2; exit 1; }
echo "setup: build/mortar2d is ready"
