#!/usr/bin/env bash
# Run a scene from nothing: set-up (packages, build, meshes), then mortar2d with
# the scene's options file (default: the main scene). Extra arguments go to mortar2d.
#   bash tools/run.sh [SCENE.opts] [-option value ...]
# SCENE.opts is a path from the current directory (or options/NAME.opts of the
# repository); results go to output/NAME/ under the repository.
set -euo pipefail
root=$(realpath "$(dirname "$0")/..")
opts=""
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then
  for f in "$1" "$root/$1"; do [ -f "$f" ] && { opts=$(realpath "$f"); break; }; done
  [ -n "$opts" ] || { echo "run.sh: no options file '$1'" >&2; exit 1; }
  shift
fi
cd "$root"
bash tools/setup.sh
[ -n "$opts" ] || opts=$PWD/options/seed_patch.opts
name=$(basename "$opts" .opts)
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
./build/mortar2d -options_file "$opts" -summary "output/$name/summary.json" "$@"
echo "summary: output/$name/summary.json; open the .xmf (XDMF Reader) or .vtu in ParaView"
