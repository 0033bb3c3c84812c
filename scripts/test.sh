#!/usr/bin/env bash
# Fresh machine → every test and the proof re-checked.  Installs, builds, runs
# the CTest suites, reruns the prover and compares with the committed
# certificates, and runs the independent checker on them.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_BUILD_DIR:-$root/build}"
"$root/scripts/setup.sh"
"$root/scripts/build.sh"

echo "== unit and property tests"
ctest --test-dir "$build" --output-on-failure -j "$(nproc)"

if [ -x "$build/prover/warpmesh-check" ]; then
  echo "== rerun the proof and compare with proofs/"
  fresh="$(mktemp -d)"
  trap 'rm -rf "$fresh"' EXIT
  "$build/mesher/warpmesh" prove --out "$fresh" --threads "$(nproc)"
  status=0
  for cert in "$root"/proofs/*.cert "$root"/proofs/key_table.txt; do
    if ! cmp -s "$cert" "$fresh/$(basename "$cert")"; then
      echo "test: $(basename "$cert") differs from the prover's fresh output" >&2
      status=1
    fi
  done
  [ "$status" -eq 0 ] || exit 1
  echo "== independent checker on the committed certificates"
  "$build/prover/warpmesh-check" "$root"/proofs/*.cert
fi
echo "test: all passed"
