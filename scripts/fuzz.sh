#!/usr/bin/env bash
# Runs the libFuzzer targets for SECONDS (default 60) of wall time in all,
# two at a time (one core each; see "run" below for how the time is split).
# They are built in the sanitizer build (build-asan/, clang, ASan + UBSan +
# coverage; scripts/sanitize.sh), which this script brings up to date first.
#
#   scripts/fuzz.sh [SECONDS]
#
# Targets (tests/fuzz/): fuzz_image_reader (decode_image: PGM, PNG),
# fuzz_pipeline (the whole mesher on tiny images, checking the mesh
# invariants and the angle bounds), and the volume readers fuzz_nrrd_reader,
# fuzz_nifti_reader, fuzz_tiff_reader (fuzz_volume_checks.hpp).  Each starts from the committed seeds
# (tests/fuzz/corpus/NAME, NAME = the target without fuzz_) and the crash regressions
# (tests/fuzz/regressions/NAME); new inputs go to build-asan/fuzz/corpus/TARGET,
# crashes to build-asan/fuzz/artifacts/.  Exit status 1 if any target found a
# crash: copy the artifact into tests/fuzz/regressions/NAME/ (the tests
# replay it) and fix the bug.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-60}"
asan="${WARPMESH_ASAN_BUILD_DIR:-$root/build-asan}"
# (scripts/test.sh, which has just built and tested build-asan/, skips this
# second configure and build check with WARPMESH_FUZZ_BUILT=1.)
[ "${WARPMESH_FUZZ_BUILT:-0}" = 1 ] || "$root/scripts/sanitize.sh" build
build="$asan/fuzz"
mkdir -p "$build"
bin="$asan/tests/fuzz"

# --- run ----------------------------------------------------------------------
# Five targets share the two cores for SECONDS of wall time, in two lanes:
# lane 1 runs fuzz_pipeline (half) then fuzz_nrrd_reader (half); lane 2
# runs fuzz_image_reader, fuzz_nifti_reader and fuzz_tiff_reader (a third
# each).  So the whole run takes about SECONDS, as with two targets before.
mkdir -p "$build/artifacts"
# One thread per target: the two lanes already use both cores.
export OMP_NUM_THREADS=1
declare -A max_len=([fuzz_image_reader]=4096 [fuzz_pipeline]=700 [fuzz_nrrd_reader]=4096 [fuzz_nifti_reader]=4096 [fuzz_tiff_reader]=4096)
half=$(( (seconds + 1) / 2 )); third=$(( (seconds + 2) / 3 ))
declare -A budget=([fuzz_pipeline]=$half [fuzz_nrrd_reader]=$half [fuzz_image_reader]=$third [fuzz_nifti_reader]=$third [fuzz_tiff_reader]=$third)
run_target() {
  local t=$1
  mkdir -p "$build/corpus/$t"
  local extra=()
  [ -f "$root/tests/fuzz/$t.dict" ] && extra+=("-dict=$root/tests/fuzz/$t.dict")
  # -timeout: an input slower than 10 s is a hang; -rss_limit_mb: a leak or a
  # huge allocation is a bug too.  The first corpus directory receives new
  # inputs; the committed ones are only read.
  local seeds=()
  for d in "$root/tests/fuzz/corpus/${t#fuzz_}" "$root/tests/fuzz/regressions/${t#fuzz_}"; do
    [ -d "$d" ] && seeds+=("$d")
  done
  local rc=0
  "$bin/$t" "$build/corpus/$t" "${seeds[@]}" \
    -max_total_time="${budget[$t]}" -max_len="${max_len[$t]}" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$build/artifacts/$t-" "${extra[@]}" \
    >"$build/$t.log" 2>&1 || rc=$?
  echo "$rc" >"$build/$t.rc"
}
targets=(fuzz_pipeline fuzz_nrrd_reader fuzz_image_reader fuzz_nifti_reader fuzz_tiff_reader)
( run_target fuzz_pipeline; run_target fuzz_nrrd_reader ) &
lane1=$!
( run_target fuzz_image_reader; run_target fuzz_nifti_reader; run_target fuzz_tiff_reader ) &
lane2=$!
wait "$lane1" || true
wait "$lane2" || true
status=0
for t in "${targets[@]}"; do
  rc=$(cat "$build/$t.rc" 2>/dev/null || echo 1)
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$build/$t.log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$build/$t.log" | tail -1 || true)
  if [ "$rc" -eq 0 ]; then
    echo "fuzz: $t: ${execs:-?} executions in ${budget[$t]} s, ${cov:-cov: ?}, no crash"
  else
    status=1
    echo "fuzz: $t: FAILED (exit $rc) after ${execs:-?} executions; log $build/$t.log" >&2
    grep -E '^(==[0-9]+==ERROR|SUMMARY|fuzz invariant violated|.*runtime error)' "$build/$t.log" | head -5 >&2 || true
    ls "$build/artifacts/$t-"* 2>/dev/null | sed 's/^/fuzz:   crash input: /' >&2 || true
  fi
done
exit "$status"
