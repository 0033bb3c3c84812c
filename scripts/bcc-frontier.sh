#!/usr/bin/env bash
# The certified frontier of the 3D (BCC) proof: for each (alpha_long,
# alpha_short) pair given (default: a small grid), prove a certificate into
# a temporary directory, check it with the independent checker, and print
# the checker's theorem (the certified dihedral range) per pair.  Nothing is
# committed: each certificate is about 1-2 MB and is regenerated here.
#
#   scripts/bcc-frontier.sh                 # the default grid
#   scripts/bcc-frontier.sh 0.24999:0.41189 0.24999:0.39957:8.99:160.6
#
# A pair is L:S or L:S:CAPMIN:CAPMAX: the prover's --cap-min-deg and
# --cap-max-deg (defaults 9.31 and 161.7, the caps of proofs/bcc.cert).  A
# key whose own claim cannot be proved tight is proved at the caps, so they
# must lie below the pair's minimum and above its maximum (else "not
# proved"), and within 0.01 deg / 0.1 deg of them for the checker to accept
# the theorem as tight.
#
# Requires build/ (scripts/build.sh).  Each pair costs a full proof and a
# full check (proofs/README.md, "Frontier", gives the measured figures).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_BUILD_DIR:-$root/build}"
pairs=("$@")
[ "${#pairs[@]}" -gt 0 ] || pairs=(0.24999:0.41189 0.24999:0.39957:8.99:160.6 0.26:0.41189:9.31:162.8)
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
echo "| α_long | α_short | certified dihedral angles | min witness | max witness |"
echo "|---|---|---|---|---|"
for p in "${pairs[@]}"; do
  IFS=: read -r l s cmin cmax <<<"$p"
  if ! "$build/prover/warpmesh-prove-bcc" --alphas "$l" "$s" --cap-min-deg "${cmin:-9.31}" --cap-max-deg "${cmax:-161.7}" \
    --threads "$(nproc)" --out "$tmp/c.cert" 2>"$tmp/prove.log"; then
    echo "| $l | $s | not proved: $(tail -1 "$tmp/prove.log") | | |"
    continue
  fi
  if ! "$build/prover/warpmesh-check-bcc" "$tmp/c.cert" >"$tmp/check.log" 2>&1; then
    echo "| $l | $s | REJECTED by the checker: $(tail -1 "$tmp/check.log") | | |"
    continue
  fi
  range="$(sed -n 's/.*rounded outward: every dihedral angle in \(.*\) deg$/\1/p' "$tmp/check.log")"
  wmin="$(sed -n 's/^  3D witness min \([^:]*\): angle \([0-9.]*\) deg.*/`\1` \2°/p' "$tmp/check.log")"
  wmax="$(sed -n 's/^  3D witness max \([^:]*\): angle \([0-9.]*\) deg.*/`\1` \2°/p' "$tmp/check.log")"
  echo "| $l | $s | $range | $wmin | $wmax |"
done
