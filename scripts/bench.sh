#!/usr/bin/env bash
# Speed and memory of the mesher, as measured on this machine.
#
# For each case and thread count: output triangles, meshing time (the sum of
# the pipeline phases, excluding file output and the quality report),
# triangles per second, and peak resident memory of the whole process in bytes
# per output triangle.  No mesh file is written (the cost of .vtu/.msh output
# is a separate, I/O-bound matter).
#
#   scripts/bench.sh            all cases
#   scripts/bench.sh --quick    small cases only (used by the tests of the script)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh" >/dev/null
"$root/scripts/build.sh" >/dev/null
exe="${WARPMESH_BUILD_DIR:-$root/build}/mesher/warpmesh"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
brain="$root/mesher/examples/brain_axial_s128_labels16.pgm"

field() { sed -n "s/^  \"$1\": \\([^,]*\\),*$/\\1/p" "$2"; }

run_case() {  # name threads args...
  local name="$1" threads="$2"
  shift 2
  OMP_NUM_THREADS="$threads" "$exe" mesh "$@" --quiet --report "$tmp/r.json"
  local tris secs mem
  tris=$(field triangles "$tmp/r.json")
  secs=$(field total_seconds "$tmp/r.json")
  mem=$(field peak_memory_mb "$tmp/r.json")
  awk -v n="$name" -v th="$threads" -v t="$tris" -v s="$secs" -v m="$mem" 'BEGIN {
    printf "%-34s %2d  %11d  %8.3f  %8.2f  %9.1f  %6.1f\n", n, th, t, s, t / s / 1e6, m, m * 1048576 / t }'
  sed -n 's/^  "phase_seconds": /      phases: /p' "$tmp/r.json"
}

echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1)"
printf "%-34s %2s  %11s  %8s  %8s  %9s  %6s\n" case thr triangles seconds "Mtri/s" "peak MB" "B/tri"
modes=("")
[ "${1:-}" = "--graded" ] && modes=("--graded")
for g in "${modes[@]}" ${WARPMESH_BENCH_GRADED:+--graded}; do
  for th in 1 2; do
    run_case "atlas slice 256x256, s=1 ${g}" "$th" "$brain" --label nonzero --spacing 1 $g
    if [ "${1:-}" != "--quick" ]; then
      run_case "disc, 4096x4096 lattice ${g}" "$th" --shape circle:0,0,2047 --spacing 1 $g
      run_case "atlas upscaled, 4096x4096 ${g}" "$th" "$brain" --label nonzero --spacing 0.062255859375 $g
    fi
  done
done
