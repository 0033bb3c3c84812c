#!/usr/bin/env bash
# Rewrites tests/expected/ from the current build: run it only when a change of
# the meshes is intended, and say in the commit why each changed file changed.
#   scripts/regen-golden.sh            every case
#   scripts/regen-golden.sh --only N   one case
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_BUILD_DIR:-$root/build}"
"$root/scripts/build.sh"
python3 "$root/tests/golden/golden.py" "$build/mesher/warpmesh" --regenerate "$@"
git -C "$root" diff --stat -- tests/expected || true
