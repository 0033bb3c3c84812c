#!/usr/bin/env bash
# The whole test suite under AddressSanitizer + UndefinedBehaviorSanitizer.
#
#   scripts/sanitize.sh
#
# Configures build-asan/ (WARPMESH_SANITIZE=ON, RelWithDebInfo, g++), builds
# everything — the library, the warpmesh binary that test_cli_errors runs, the
# prover, every test — and runs CTest there.  Any sanitizer report fails the
# test that triggered it (UBSan does not recover; ASan aborts).  Every test
# runs at its normal size: on the 2-core machine the build takes about 3
# minutes and the tests about 20 s.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_ASAN_BUILD_DIR:-$root/build-asan}"
jobs="${WARPMESH_JOBS:-$(nproc)}"
"$root/scripts/setup.sh" >/dev/null  # g++ ships libasan and libubsan

t0=$SECONDS
# RelWithDebInfo with lighter flags than CMake's "-O2 -g": -O1 and line
# tables only (-g1) are what the sanitizers' stack traces need, and compile
# markedly faster on 2 cores.  Override with WARPMESH_ASAN_FLAGS.
cmake -S "$root" -B "$build" -DWARPMESH_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="${WARPMESH_ASAN_FLAGS:--O1 -g1 -DNDEBUG}" >/dev/null
cmake --build "$build" -j "$jobs" >/dev/null
echo "sanitize: built in $((SECONDS - t0)) s"

t1=$SECONDS
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
ctest --test-dir "$build" --output-on-failure -j "$jobs"
echo "sanitize: tests ran in $((SECONDS - t1)) s; total $((SECONDS - t0)) s"
