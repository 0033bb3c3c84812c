#!/usr/bin/env bash
# Configures and builds warpmesh into build/ (Release).  Used by run.sh, test.sh, bench.sh.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_BUILD_DIR:-$root/build}"
jobs="${WARPMESH_JOBS:-$(nproc)}"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE="${WARPMESH_BUILD_TYPE:-Release}" ${WARPMESH_CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j "$jobs"
