#!/usr/bin/env bash
# Make level N of the S3 Hertz mesh (meshes/hertz.geo) if it is missing or older
# than the .geo, and print its path. Levels 0-4 are also made by the build
# (cmake --build build); level 5 (~1e6 dofs, gmsh ~1 min) and 6 (~4e6 dofs,
# gmsh ~8 min) only here. Levels >= 5 are written in gmsh's binary format 4.1
# (gmsh -bin: read 3x faster); an ASCII file of such a level left by an older
# run is converted in place (gmsh -0, seconds) instead of being remeshed.
#   tools/hertz_mesh.sh N [OUT]      (OUT default: build/meshes/hertz_N.msh)
# Relative paths are taken from the repository root. Idempotent.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: $0 N [OUT]" >&2; exit 2
fi
level=$1
case $level in
  ''|*[!0-9]*) echo "$0: level must be a non-negative integer, got '$level'" >&2; exit 2 ;;
esac
geo=$root/meshes/hertz.geo
out=${2:-build/meshes/hertz_$level.msh}
case $out in /*) ;; *) out=$root/$out ;; esac
bin=()
[ "$level" -ge 5 ] && bin=(-bin)
tmp=${out%.msh}.tmp$$.msh
trap 'rm -f "$tmp"' EXIT
if [ ! -s "$out" ] || [ "$geo" -nt "$out" ]; then
  mkdir -p "$(dirname "$out")"
  echo "hertz_mesh: gmsh level $level -> $out" >&2
  # gmsh's own messages go to stderr so that stdout holds only the path
  gmsh -2 -format msh41 "${bin[@]}" -v 2 -setnumber level "$level" "$geo" -o "$tmp" >&2
  mv -f "$tmp" "$out"
elif [ ${#bin[@]} -gt 0 ] && [ "$(sed -n 2p "$out" | cut -d' ' -f2)" = 0 ]; then
  echo "hertz_mesh: level $level ASCII -> binary, $out" >&2
  gmsh -0 -format msh41 -bin -v 2 "$out" -o "$tmp" >&2
  touch -r "$out" "$tmp"
  mv -f "$tmp" "$out"
fi
echo "$out"
