#!/usr/bin/env bash
# Fresh machine → a mesh.  Installs what is missing, builds, and meshes the
# bundled example (an SPL brain-atlas axial slice, right cerebral white matter)
# unless arguments are given, in which case they go to `warpmesh` unchanged.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
exe="${WARPMESH_BUILD_DIR:-$root/build}/mesher/warpmesh"
if (($#)); then
  exec "$exe" "$@"
fi
out="$root/out"
mkdir -p "$out"
"$exe" mesh "$root/mesher/examples/brain_axial_s128_labels16.pgm" --label 41 --spacing 2 \
  -o "$out/brain_wm.vtu" --also "$out/brain_wm.msh" --also "$out/brain_wm.svg" --report "$out/brain_wm.json"
echo "run: wrote $out/brain_wm.vtu, .msh, .svg and the report brain_wm.json"
