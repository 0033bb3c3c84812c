#!/usr/bin/env bash
# Fresh machine → a mesh.  Installs what is missing, builds, and meshes every
# label of the bundled example (an SPL brain-atlas axial slice) into one
# conforming multi-material mesh in out/ (scripts/example.sh): .vtu
# (ParaView), .msh (Gmsh), .xdmf (FEniCSx), a PNG coloured by label and the
# JSON report, and the same with --optimize; then prints where the files are
# and which angle bounds are certified for this mesh.
# With arguments, they go to `warpmesh` unchanged.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"
exe="${WARPMESH_BUILD_DIR:-$root/build}/mesher/warpmesh"
if (($#)); then
  exec "$exe" "$@"
fi
"$root/scripts/example.sh" "$exe" "$root/out"
