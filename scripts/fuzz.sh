#!/usr/bin/env bash
# Builds the libFuzzer targets with clang (ASan + UBSan) into build-fuzz/ and
# runs each for SECONDS (default 60), both at once (one core each).
#
#   scripts/fuzz.sh [SECONDS]
#
# Targets (tests/fuzz/): fuzz_image_reader (decode_image: PGM, PNG) and
# fuzz_pipeline (the whole mesher on tiny images, checking the mesh
# invariants and the angle bounds).  Each starts from the committed seeds
# (tests/fuzz/corpus/NAME, NAME = image_reader or pipeline) and the crash regressions
# (tests/fuzz/regressions/NAME); new inputs go to build-fuzz/corpus/TARGET,
# crashes to build-fuzz/artifacts/.  Exit status 1 if any target found a
# crash: copy the artifact into tests/fuzz/regressions/NAME/ (the tests
# replay it) and fix the bug.  Installs clang and its sanitizer/fuzzer
# runtimes (Debian: clang-14, libclang-rt-14-dev) if missing.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
seconds="${1:-60}"
build="${WARPMESH_FUZZ_BUILD_DIR:-$root/build-fuzz}"
jobs="${WARPMESH_JOBS:-$(nproc)}"

# --- dependencies ------------------------------------------------------------
have_pkg() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
need=()
for pkg in cmake make libpng-dev zlib1g-dev libtiff-dev libboost-dev; do have_pkg "$pkg" || need+=("$pkg"); done
cxx=""
for c in clang++-14 clang++; do
  if command -v "$c" >/dev/null; then cxx="$(command -v "$c")"; break; fi
done
[ -n "$cxx" ] || need+=(clang-14)
# libFuzzer and the sanitizer runtimes: libclang-rt-14-dev on bookworm.
if ! ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1; then
  need+=(libclang-rt-14-dev)
fi
if ((${#need[@]})); then
  echo "fuzz: installing ${need[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}"
  [ -n "$cxx" ] || cxx="$(command -v clang++-14 || command -v clang++)"
fi

# --- build --------------------------------------------------------------------
t0=$SECONDS
cmake -S "$root/tests/fuzz" -B "$build" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build "$build" -j "$jobs" >/dev/null
echo "fuzz: built in $((SECONDS - t0)) s with $cxx"

# --- run ----------------------------------------------------------------------
mkdir -p "$build/artifacts"
declare -A max_len=([fuzz_image_reader]=4096 [fuzz_pipeline]=700)
pids=()
for t in fuzz_image_reader fuzz_pipeline; do
  mkdir -p "$build/corpus/$t"
  extra=()
  [ -f "$root/tests/fuzz/$t.dict" ] && extra+=("-dict=$root/tests/fuzz/$t.dict")
  # -timeout: an input slower than 10 s is a hang; -rss_limit_mb: a leak or a
  # huge allocation is a bug too.  The first corpus directory receives new
  # inputs; the committed ones are only read.
  "$build/$t" "$build/corpus/$t" "$root/tests/fuzz/corpus/${t#fuzz_}" "$root/tests/fuzz/regressions/${t#fuzz_}" \
    -max_total_time="$seconds" -max_len="${max_len[$t]}" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$build/artifacts/$t-" "${extra[@]}" \
    >"$build/$t.log" 2>&1 &
  pids+=($!)
done
status=0
i=0
for t in fuzz_image_reader fuzz_pipeline; do
  rc=0
  wait "${pids[$i]}" || rc=$?
  i=$((i + 1))
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$build/$t.log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' "$build/$t.log" | tail -1 || true)
  if [ "$rc" -eq 0 ]; then
    echo "fuzz: $t: ${execs:-?} executions in ${seconds} s, ${cov:-cov: ?}, no crash"
  else
    status=1
    echo "fuzz: $t: FAILED (exit $rc) after ${execs:-?} executions; log $build/$t.log" >&2
    grep -E '^(==[0-9]+==ERROR|SUMMARY|fuzz invariant violated|.*runtime error)' "$build/$t.log" | head -5 >&2 || true
    ls "$build/artifacts/$t-"* 2>/dev/null | sed 's/^/fuzz:   crash input: /' >&2 || true
  fi
done
exit "$status"
