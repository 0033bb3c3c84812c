#!/usr/bin/env bash
# Reruns the 2D proofs on a deterministic sample of their keys and compares
# the result with the committed certificates (scripts/test.sh; the whole rerun
# is scripts/prove-all.sh).
#
#   scripts/sample-2d-proofs.sh OUTDIR [STEP]
#
# Why a sample reproduces the certificate's lines.  A 2D key's block (its key
# line and the lines up to the next key) is a function of the key and of its
# category's targets (prover/src/run_proof.cpp, set_targets); the targets are
# a function of the category's worst witnesses, i.e. of the keys named on the
# certificate's `witness` lines.  So the sample is every STEP-th key (default
# 8) plus those witness keys: the prover's fresh output on it must equal the
# committed certificate's claim and witness lines and the sampled keys'
# blocks, byte for byte.  proofs/key_table.txt is a function of the five
# square-lattice certificates' key lines; it is rebuilt from them and compared.
# The independent checker (scripts/test.sh, next stage) checks every
# certificate whole.  Exit 1 on any difference.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_BUILD_DIR:-$root/build}"
out="$1"
step="${2:-8}"
mkdir -p "$out"
status=0

# sample CERT: every step-th key index, the witness keys' indices, and for
# each claim value the first key whose own claim attains it (a category's
# claim is the weakest of its keys' claims; category F holds the flat keys),
# comma-separated.
sample() {
  awk -v step="$step" '
    $1 == "claim" { cmin[$2] = $3; cmax[$2] = $4 }
    $1 == "witness" { want[$4] = 1 }
    $1 == "key" {
      take = $2 % step == 0 || ($3 in want)
      for (c in cmin) {
        if (c == "F" && $4 != "1") continue
        if ($6 == cmin[c] && !(c "min" in got)) { got[c "min"] = 1; take = 1 }
        if ($7 == cmax[c] && !(c "max" in got)) { got[c "max"] = 1; take = 1 }
      }
      if (take) ids[++n] = $2
    }
    END { for (i = 1; i <= n; ++i) printf "%s%s", ids[i], (i < n ? "," : "\n") }' "$1"
}
# lines CERT [IDS_FROM]: the claim and witness lines, then the blocks of the
# keys that IDS_FROM (default CERT itself) lists.
lines() {
  awk '
    NR == FNR { if ($1 == "key") want[$2] = 1; next }
    $1 == "claim" || $1 == "witness" { print; next }
    $1 == "key" { on = ($2 in want) }
    $1 == "end" { on = 0 }
    on' "${2:-$1}" "$1"
}

# name rule key-option lattice
for spec in "maxmin maxmin --keys square" "separating separating --keys square" \
  "materials separating --junction-keys square" "fan fan --keys square" "materials_fan fan --junction-keys square" \
  "rhombic_maxmin maxmin --keys rhombic" "rhombic_separating separating --keys rhombic"; do
  read -r name rule opt lattice <<<"$spec"
  committed="$root/proofs/$name.cert"
  dir="$out/$name"
  mkdir -p "$dir"
  keys="$(sample "$committed")"
  if ! "$build/mesher/warpmesh" prove --rule "$rule" --lattice "$lattice" "$opt" "$keys" --threads "$(nproc)" --out "$dir" \
    >"$dir/log" 2>&1; then
    cat "$dir/log" >&2
    echo "test: warpmesh prove failed on the sample of $name.cert" >&2
    status=1
    continue
  fi
  if ! cmp -s <(lines "$dir/$name.cert") <(lines "$committed" "$dir/$name.cert"); then
    echo "test: proofs/$name.cert differs from the prover's fresh output on its sample of keys:" >&2
    diff <(lines "$committed" "$dir/$name.cert") <(lines "$dir/$name.cert") | cut -c1-200 | head -20 >&2 || true
    status=1
  else
    echo "$name.cert: $(grep -c '^key ' "$dir/$name.cert") of $(sed -n 's/^keys //p' "$committed") keys rerun, byte-identical"
  fi
done

# proofs/key_table.txt: the square lattice's five certificates' key lines
# (prove_main.cpp, write_key_table), in the prover's order.
{
  echo "# rule key flat min_cot max_cot   (see proofs/README.md; every angle a of the chosen triangles"
  echo "# of every configuration of the key has max_cot <= cot(a) <= min_cot)"
  for name in maxmin separating materials fan materials_fan; do
    awk '$1 == "rule" { rule = $2 }
      $1 == "key" { print rule, $3, ($4 == "1" ? "flat" : "any"), $6, ($6 == "inverted" ? "-" : $7) }' "$root/proofs/$name.cert"
  done
} >"$out/key_table.txt"
if ! cmp -s "$out/key_table.txt" "$root/proofs/key_table.txt"; then
  echo "test: proofs/key_table.txt is not the committed certificates' key lines" >&2
  status=1
fi
exit "$status"
