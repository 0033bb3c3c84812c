#!/usr/bin/env bash
# Fresh machine → every test and the proof re-checked.  Installs, builds, runs
# the CTest suites, reruns the prover and compares with the committed
# certificates, runs the independent checker on them, then the readers',
# writers' and meshers' tests again under ASan + UBSan in one clang build that
# also holds the five libFuzzer targets (scripts/sanitize.sh), and runs those for
# WARPMESH_FUZZ_SECONDS of wall time in all (default 30, two at a time;
# scripts/fuzz.sh splits it).  Each stage prints the seconds elapsed;
# docs/performance.md, "The test suite", gives a measured run.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_BUILD_DIR:-$root/build}"
# Each stage is announced with the wall seconds elapsed since the start and
# the CPU seconds (user + system) its programs have used since: on a shared
# machine the wall time says as much about the others' load as about the
# suite, the CPU time much less.
cpu_times="$(mktemp)"
trap 'rm -f "$cpu_times"' EXIT
stage() {
  times >"$cpu_times"  # in this shell: the second line is the waited-for children's
  echo "== [$SECONDS s, $(awk 'NR == 2 {for (i = 1; i <= NF; i++) {split($i, t, "m"); s += t[1] * 60 + t[2]}} END {printf "%d", s}' "$cpu_times") s CPU] $*"
}
"$root/scripts/setup.sh"
stage "build (Release)"
"$root/scripts/build.sh"

stage "layering (scripts/check-layers.py)"
python3 "$root/scripts/check-layers.py"

stage "unit and property tests"
# Two tests at a time, each with OpenMP's default of one thread a core: with
# libgomp's default active waiting, a thread waiting at a barrier spins on the
# core the other test needs (test_mesh3d_materials' block tests, many small
# parallel regions, took 15.4 s of CPU instead of 2.0).  Passive waiting keeps
# the parallel paths tested at the cores' count without the spinning.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
ctest --test-dir "$build" --output-on-failure -j "$(nproc)"

if [ -x "$build/checker/warpmesh-check" ]; then
  stage "rerun the proof and compare with proofs/"
  fresh="$(mktemp -d)"
  trap 'rm -rf "$fresh" "$cpu_times"' EXIT
  status=0
  # The 2D certificates: a deterministic sample of every one's keys (every
  # 8th, the witnesses' and the claims' keys) rerun, its lines byte-identical
  # to the certificate's, and key_table.txt rebuilt from them
  # (scripts/sample-2d-proofs.sh); scripts/prove-all.sh reruns them whole.
  "$root/scripts/sample-2d-proofs.sh" "$fresh/2d" || exit 1
  certs2d=("$root"/proofs/{maxmin,separating,materials,fan,materials_fan,rhombic_maxmin,rhombic_separating}.cert)
  # The 3D proof: a deterministic sample of its keys (every 13th, the prover
  # numbers them in canonical order) rerun, each key's line byte-identical to
  # the certificate's (a key's line is a function of the key alone);
  # scripts/prove-all.sh reruns it whole.
  nbcc="$(sed -n 's/^keys //p' "$root/proofs/bcc.cert")"
  alphas="$(awk '/^alphas /{split($2, a, "/"); split($3, b, "/"); printf "%.5f %.5f", a[1] / a[2], b[1] / b[2]}' "$root/proofs/bcc.cert")"
  # shellcheck disable=SC2086  # two words: alpha_long alpha_short
  "$build/prover/warpmesh-prove-bcc" --alphas $alphas --threads "$(nproc)" --keys "$(seq -s, 0 13 $((nbcc - 1)))" \
    --out "$fresh/bcc.sample" 2>"$fresh/bcc.sample.log" || { cat "$fresh/bcc.sample.log" >&2; exit 1; }
  if grep '^key ' "$fresh/bcc.sample" | grep -vxF -f "$root/proofs/bcc.cert" >&2; then
    echo "test: these proofs/bcc.cert keys differ from the prover's fresh output" >&2
    exit 1
  fi
  # The Delaunay face rule's certificate (format 5): its keys' lines depend on
  # the key alone too; a sample (every 7th key, six of them with quads) rerun
  # byte-identical.
  ndel="$(sed -n 's/^keys //p' "$root/proofs/bcc_delaunay.cert")"
  "$build/prover/warpmesh-prove-bcc" --face-rule delaunay --alphas 0.2675 0.39 --cap-min-deg 11.781 --cap-max-deg 161.253 \
    --threads "$(nproc)" --keys "$(seq -s, 0 7 $((ndel - 1)))" --out "$fresh/bcc_delaunay.sample" 2>"$fresh/bcc_delaunay.sample.log" ||
    { cat "$fresh/bcc_delaunay.sample.log" >&2; exit 1; }
  if grep '^key ' "$fresh/bcc_delaunay.sample" | grep -vxF -f "$root/proofs/bcc_delaunay.cert" >&2; then
    echo "test: these proofs/bcc_delaunay.cert keys differ from the prover's fresh output" >&2
    exit 1
  fi
  # The junction keys' certificate (multi-material meshes, proofs/README.md
  # "Junction keys (3D, bcc_junctions.cert)"): a key's five lines (its key
  # line and its four face lines) depend on the key alone; every 2nd key
  # rerun, its lines byte-identical to the certificate's.
  njun="$(sed -n 's/^keys //p' "$root/proofs/bcc_junctions.cert")"
  "$build/prover/warpmesh-prove-bcc" --junctions --threads "$(nproc)" --keys "$(seq -s, 0 2 $((njun - 1)))" \
    --out "$fresh/bcc_junctions.sample" 2>"$fresh/bcc_junctions.sample.log" || { cat "$fresh/bcc_junctions.sample.log" >&2; exit 1; }
  grep -E '^(key|face) ' "$fresh/bcc_junctions.sample" >"$fresh/bcc_junctions.sample.lines"
  awk 'NR == FNR { if ($1 == "key") want[$2] = 1; next } $1 == "key" { on = ($2 in want) } on && ($1 == "key" || $1 == "face")' \
    "$fresh/bcc_junctions.sample" "$root/proofs/bcc_junctions.cert" >"$fresh/bcc_junctions.committed.lines"
  if ! cmp -s "$fresh/bcc_junctions.sample.lines" "$fresh/bcc_junctions.committed.lines"; then
    echo "test: these proofs/bcc_junctions.cert keys differ from the prover's fresh output" >&2
    diff "$fresh/bcc_junctions.committed.lines" "$fresh/bcc_junctions.sample.lines" | cut -c1-200 >&2 || true
    exit 1
  fi
  # The 3D counter-example (the alpha = 1/2 closer-endpoint rule inverts a
  # tetrahedron) and the 3D ceiling (no thresholds reach 11.88 deg): their
  # writers are deterministic, the files byte-identical.
  same_as_writer() {  # same_as_writer NAME TOOL ARGS...: proofs/NAME.cert is TOOL ARGS's output
    local name=$1 tool=$2
    shift 2
    "$build/prover/$tool" "$@" >"$fresh/$name.cert"
    if ! cmp -s "$root/proofs/$name.cert" "$fresh/$name.cert"; then
      echo "test: $name.cert differs from $tool $*" >&2
      exit 1
    fi
  }
  same_as_writer bcc_half bcc_explore counterexample 0.5 0.5
  same_as_writer bcc_ceiling bcc_ceiling 11.88
  # The graded templates (issue 48): the prover's whole run (exact, under a
  # second), byte-identical.
  "$build/prover/warpmesh-prove-bcc" --graded --out "$fresh/bcc_graded.cert" 2>/dev/null
  if ! cmp -s "$root/proofs/bcc_graded.cert" "$fresh/bcc_graded.cert"; then
    echo "test: bcc_graded.cert differs from warpmesh-prove-bcc --graded" >&2
    exit 1
  fi
  stage "independent checkers on the committed certificates (one process per certificate)"
  pids=()
  for cert in "${certs2d[@]}"; do
    "$build/checker/warpmesh-check" "$cert" >"$fresh/$(basename "$cert").check" 2>&1 &
    pids+=($!)
  done
  "$build/checker/warpmesh-check-bcc" "$root/proofs/bcc.cert" >"$fresh/bcc.cert.check3d" 2>&1 &
  pids+=($!)
  "$build/checker/warpmesh-check-bcc" "$root/proofs/bcc_delaunay.cert" >"$fresh/bcc_delaunay.cert.check3d" 2>&1 &
  pids+=($!)
  "$build/checker/warpmesh-check-bcc" "$root/proofs/bcc_junctions.cert" >"$fresh/bcc_junctions.cert.check3d" 2>&1 &
  pids+=($!)
  "$build/checker/warpmesh-check-bcc" "$root/proofs/bcc_graded.cert" >"$fresh/bcc_graded.cert.check3d" 2>&1 &
  pids+=($!)
  no_bound=(bcc_half bcc_ceiling)  # a counter-example and a ceiling: NO BOUND statements
  no_bound_pids=()
  for c in "${no_bound[@]}"; do
    "$build/checker/warpmesh-check-bcc" "$root/proofs/$c.cert" >"$fresh/$c.cert.check3d" 2>&1 &
    no_bound_pids+=($!)
  done
  for i in "${!pids[@]}"; do
    wait "${pids[$i]}" || status=1
  done
  # They hold: exit 3 (verified, NO BOUND), never 0.
  for i in "${!no_bound[@]}"; do
    code=0
    wait "${no_bound_pids[$i]}" || code=$?
    [ "$code" -eq 3 ] || { echo "test: warpmesh-check-bcc proofs/${no_bound[$i]}.cert exited $code, not 3 (verified, NO BOUND)" >&2; status=1; }
  done
  cat "$fresh"/*.check "$fresh"/*.check3d
  [ "$status" -eq 0 ] || { echo "test: the checker rejected a certificate" >&2; exit 1; }
  # Every key of the three 3D bound certificates is tight (proofs/README.md):
  # the checker's counts read "N of N".
  for c in bcc bcc_delaunay bcc_junctions; do
    if grep -E '^  key (min|max|face) claims: ' "$fresh/$c.cert.check3d" | grep -vE ': ([0-9]+) of \1 within' >&2; then
      echo "test: proofs/$c.cert has keys whose claims are not tight (above)" >&2
      exit 1
    fi
  done
  stage "the tables of certified bounds (README.md, docs/guarantees.md) are the checker's"
  cat "$fresh"/*.check "$fresh"/*.check3d | "$root/scripts/bounds-table.sh" >"$fresh/table.md"
  for page in README.md docs/guarantees.md; do
    sed -n '/<!-- certified-bounds:begin -->/,/<!-- certified-bounds:end -->/p' "$root/$page" | sed '1d;$d' >"$fresh/page.md"
    if ! cmp -s "$fresh/table.md" "$fresh/page.md"; then
      echo "test: $page's certified-bounds table differs from the checker's output; regenerate it with" >&2
      echo "      { build/checker/warpmesh-check proofs/{fan,materials,materials_fan,maxmin,rhombic_maxmin,rhombic_separating,separating}.cert; build/checker/warpmesh-check-bcc proofs/bcc.cert; build/checker/warpmesh-check-bcc proofs/bcc_delaunay.cert; build/checker/warpmesh-check-bcc proofs/bcc_junctions.cert; build/checker/warpmesh-check-bcc proofs/bcc_graded.cert; build/checker/warpmesh-check-bcc proofs/bcc_half.cert; build/checker/warpmesh-check-bcc proofs/bcc_ceiling.cert; } | scripts/bounds-table.sh" >&2
      diff "$fresh/page.md" "$fresh/table.md" >&2 || true
      exit 1
    fi
  done
fi

stage "the readers', writers' and meshers' tests under AddressSanitizer + UndefinedBehaviorSanitizer"
"$root/scripts/sanitize.sh"

stage "fuzzing"
WARPMESH_FUZZ_BUILT=1 "$root/scripts/fuzz.sh" "${WARPMESH_FUZZ_SECONDS:-30}"
stage "done"
echo "test: all passed in $SECONDS s"
