#!/usr/bin/env bash
# Reruns every proof whole — the 2D certificates, the 3D proofs/bcc.cert,
# proofs/bcc_delaunay.cert (the Delaunay face rule), proofs/bcc_junctions.cert
# (the junction keys of multi-material meshes), proofs/bcc_graded.cert (the
# graded meshes' transition templates), the 3D
# counter-example proofs/bcc_half.cert and the 3D ceiling proofs/bcc_ceiling.cert
# (scripts/test.sh reruns the 3D ones on samples of their keys) — into OUTDIR
# (default: a temporary directory) and compares each with proofs/ byte for
# byte.  Exit 1 if any differs.
#
#   scripts/prove-all.sh [OUTDIR]
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_BUILD_DIR:-$root/build}"
out="${1:-$(mktemp -d)}"
mkdir -p "$out"
SECONDS=0
"$build/mesher/warpmesh" prove --out "$out" --threads "$(nproc)"
echo "== [$SECONDS s] 2D proofs done"
alphas="$(awk '/^alphas /{split($2, a, "/"); split($3, b, "/"); printf "%.5f %.5f", a[1] / a[2], b[1] / b[2]}' "$root/proofs/bcc.cert")"
# shellcheck disable=SC2086  # two words: alpha_long alpha_short
"$build/prover/warpmesh-prove-bcc" --alphas $alphas --threads "$(nproc)" --out "$out/bcc.cert"
"$build/prover/warpmesh-prove-bcc" --face-rule delaunay --alphas 0.2675 0.39 --cap-min-deg 11.781 --cap-max-deg 161.253 \
  --threads "$(nproc)" --out "$out/bcc_delaunay.cert"  # proofs/README.md, "The Delaunay face rule (certified)"
"$build/prover/warpmesh-prove-bcc" --junctions --threads "$(nproc)" --out "$out/bcc_junctions.cert"  # multi-material junctions
"$build/prover/warpmesh-prove-bcc" --graded --out "$out/bcc_graded.cert"  # the graded meshes' transition templates
echo "== [$SECONDS s] 3D proofs done"
"$build/prover/bcc_explore" counterexample 0.5 0.5 >"$out/bcc_half.cert"  # the alpha = 1/2 counter-example
"$build/prover/bcc_ceiling" 11.88 >"$out/bcc_ceiling.cert"  # no thresholds reach 11.88 deg
status=0
for cert in "$root"/proofs/{maxmin,separating,materials,fan,bcc,bcc_delaunay,bcc_junctions,bcc_graded,bcc_half,bcc_ceiling}.cert "$root"/proofs/key_table.txt; do
  if ! cmp -s "$cert" "$out/$(basename "$cert")"; then
    echo "prove-all: $(basename "$cert") differs from the prover's fresh output ($out)" >&2
    status=1
  fi
done
exit "$status"
