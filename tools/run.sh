#!/usr/bin/env bash
# Run a scene from nothing: set-up (packages, build, meshes), then mortar2d with
# the scene's options file (default: the main scene). Extra arguments go to mortar2d.
#   bash tools/run.sh [options/SCENE.opts] [-option value ...]
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/setup.sh
opts=options/seed_patch.opts
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then opts=$1; shift; fi
name=$(basename "$opts" .opts)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
./build/mortar2d -options_file "$opts" -summary "output/$name/summary.json" "$@"
echo "summary: output/$name/summary.json; open the .xmf (XDMF Reader) or .vtu in ParaView"
