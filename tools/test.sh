#!/usr/bin/env bash
# The whole test suite from nothing: set-up (packages, build, meshes), then ctest.
set -euo pipefail
cd "$(dirname "$0")/.."
M2D_TEST_HOOKS=ON bash tools/setup.sh # the build with the tests' hooks (CMakeLists.txt)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
rc=0
ctest --test-dir build --output-on-failure -j2 "$@" || rc=$?
if [ $rc -ne 0 ]; then # the failed tests' last lines again, last: a log cut to its head and tail still shows them
  python3 - build/Testing/Temporary/LastTest.log <<'PY'
import re, sys
for block in re.split(r"\n(?=\d+/\d+ Testing: )", open(sys.argv[1], errors="replace").read()):
    m = re.search(r"Testing: (\S+)\n.*?\nOutput:\n-+\n(.*)<end of output>\n.*\nTest (\w+)", block, re.S)
    if m and m.group(3) != "Passed":
        print("\n==== %s failed; its output's last lines:\n%s" % (m.group(1), "\n".join(m.group(2).rstrip().splitlines()[-25:])))
PY
fi
exit $rc
