#!/usr/bin/env bash
# scripts/stress.sh N SEED [WARPMESH] — N random inputs over every option of
# `warpmesh mesh`, each output read back and checked by an independent
# validator (tests/stress/stress.py: conformity, orientation, no folds, closed
# simple boundary and interface chains, tags, areas, sizes, certified bounds,
# --optimize never lowering the minimum angle).  Exit 0 iff every case passes;
# each failure is printed with its command line.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
n="${1:?usage: scripts/stress.sh N SEED [WARPMESH]}"
seed="${2:?usage: scripts/stress.sh N SEED [WARPMESH]}"
exe="${3:-$here/build/mesher/warpmesh}"
[ -x "$exe" ] || { echo "stress.sh: no warpmesh at $exe (run scripts/build.sh)" >&2; exit 2; }
exec /usr/bin/python3 "$here/tests/stress/stress.py" "$exe" "$n" "$seed"
