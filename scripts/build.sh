#!/usr/bin/env bash
# Configures and builds warpmesh into build/ (Release).  Used by run.sh, test.sh, bench.sh.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_BUILD_DIR:-$root/build}"
jobs="${WARPMESH_JOBS:-$(nproc)}"
# The Python module (python/) is built for /usr/bin/python3, the interpreter
# with Debian's numpy, pytest, meshio and dask (scripts/setup.sh); turn it
# off with WARPMESH_PYTHON=OFF.
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE="${WARPMESH_BUILD_TYPE:-Release}" \
  -DWARPMESH_PYTHON="${WARPMESH_PYTHON:-ON}" -DPython3_EXECUTABLE=/usr/bin/python3 ${WARPMESH_CMAKE_ARGS:-} >/dev/null
cmake --build "$build" -j "$jobs"
