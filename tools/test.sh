#!/usr/bin/env bash
# The whole test suite from nothing: set-up (packages, build, meshes), then ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
M2D_TEST_HOOKS=ON bash tools/setup.sh # the build with the tests' hooks (CMakeLists.txt)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
ctest --test-dir build --output-on-failure -j2 "$@"
