#!/usr/bin/env bash
# The tests of the readers, writers and meshers under AddressSanitizer +
# UndefinedBehaviorSanitizer, and the libFuzzer targets built in the same tree.
#
#   scripts/sanitize.sh          build build-asan/, run CTest there
#   scripts/sanitize.sh build    only build (scripts/fuzz.sh uses this)
#
# Configures build-asan/ with clang (WARPMESH_SANITIZE=ON, WARPMESH_FUZZ=ON,
# -O2 and line tables only): the library, the warpmesh binary that the
# command-line tests run, the tests listed in tests/CMakeLists.txt
# (WARPMESH_SANITIZED_TESTS: image and volume readers, writers, the 2D and 3D
# meshers and the optimisation pass, the command line on hostile inputs, the
# golden meshes, the random stress over every option and format, the 3D
# command line) and the five fuzz targets.  The prover's and checkers' tests
# run in the Release build only; WARPMESH_SANITIZE_ALL=ON (environment) builds
# and runs every test here (a reconfigure of build-asan/ switches it).  clang,
# not g++: it compiles the Boost.Test suites under the sanitizers about ten
# times faster, and the fuzzers need it anyway.  Any sanitizer report fails
# the test that triggered it (UBSan does not recover; ASan aborts).  The
# randomised suites run with WARPMESH_TEST_SCALE (default here 0.25: a
# quarter of their cases; tests/support.hpp, scaled()), and (with
# WARPMESH_SANITIZE_ALL) the checker tamper cases that rerun the checker on
# long certificate prefixes are skipped (full_scale_only()), since every case
# costs several times more under ASan; the Release run (scripts/test.sh) runs
# them all.  Installs clang-14, its sanitizer and fuzzer runtimes
# (libclang-rt-14-dev) and its OpenMP runtime (libomp-14-dev, so the parallel
# paths run under the sanitizers too) if missing.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_ASAN_BUILD_DIR:-$root/build-asan}"
jobs="${WARPMESH_JOBS:-$(nproc)}"
"$root/scripts/setup.sh" >/dev/null

have_pkg() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
need=()
for pkg in clang-14 libclang-rt-14-dev libomp-14-dev; do have_pkg "$pkg" || need+=("$pkg"); done
if ((${#need[@]})); then
  echo "sanitize: installing ${need[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}"
fi

t0=$SECONDS
# CMake's RelWithDebInfo "-O2 -g" with line tables only (-g1, which keeps the
# inlined frames the sanitizers' stack traces need).  Not -O1: clang's -O1
# barely inlines, so every std::array subscript and comparator in the
# libraries' hot loops stays a call that ASan instruments, and the tests ran
# about twice as long, more than -O2's extra compile time.  Override with
# WARPMESH_ASAN_FLAGS.
cmake -S "$root" -B "$build" -DCMAKE_CXX_COMPILER=clang++-14 -DWARPMESH_SANITIZE=ON -DWARPMESH_FUZZ=ON \
  -DWARPMESH_SANITIZE_ALL="${WARPMESH_SANITIZE_ALL:-OFF}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="${WARPMESH_ASAN_FLAGS:--O2 -g1 -DNDEBUG}" >/dev/null
cmake --build "$build" -j "$jobs" >/dev/null
echo "sanitize: built in $((SECONDS - t0)) s"
[ "${1:-}" = build ] && exit 0

t1=$SECONDS
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
export WARPMESH_TEST_SCALE="${WARPMESH_TEST_SCALE:-0.25}"
# clang's OpenMP runtime spins 200 ms at every barrier by default; with two
# tests running at once on two cores that spinning takes the other's core.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
ctest --test-dir "$build" --output-on-failure -j "$jobs"
echo "sanitize: tests ran in $((SECONDS - t1)) s; total $((SECONDS - t0)) s"
