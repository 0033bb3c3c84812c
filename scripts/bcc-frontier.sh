#!/usr/bin/env bash
# The certified frontier of the 3D (BCC) proof: for each (alpha_long,
# alpha_short) pair given (default: the grid of proofs/README.md,
# "Certified frontier"), choose the caps, prove a certificate into a
# temporary directory (or KEEP_DIR), check it with the independent checker,
# and print one table row per pair.  Nothing is committed: each certificate
# is about 2 MB and is regenerated here; its sha256 is in the row.
#
#   scripts/bcc-frontier.sh                         # the default grid
#   scripts/bcc-frontier.sh 0.24999:0.41189 0.22:0.38
#   scripts/bcc-frontier.sh 0.24999:0.39957:8.99:160.6   # explicit caps
#   WARPMESH_THREADS=2 KEEP_DIR=/tmp/certs scripts/bcc-frontier.sh 0.2:0.35
#
# The caps (the prover's --cap-min-deg, --cap-max-deg; a key whose claim
# cannot be proved at its witness's margin is proved at the caps) must lie
# at or below the pair's true minimum and at or above its maximum (else a key
# is "not proved") and within 0.01 deg / 0.1 deg of them (else the checker
# rejects the theorem as not tight).  They are chosen from the prover's own
# witness search (`warpmesh-prove-bcc --extremes`, the deterministic double
# search that also picks each key's claim): the smallest witness angle minus
# 0.005 deg rounded down to 0.001 deg, the largest plus 0.05 deg rounded up
# to 0.001 deg.  If the search missed a configuration more extreme than
# that, the prover reports the key as not proved: the row says so.
#
# A pair the prover refuses (alphas outside (0, 0.5), more than 5 digits)
# is an error (exit 2).  A pair that fails prints "no bound" (the search
# finds flat tetrahedra), "prover failed" (with the prover's reason) or
# "REJECTED" (the checker's reason): never skipped.  Columns: caps, certified range, the theorem's
# witnesses, keys, leaves, prove and check user seconds, sha256.
#
# Requires build/ (scripts/build.sh).  Each pair costs a full proof and a
# full check (proofs/README.md gives the measured figures).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${WARPMESH_BUILD_DIR:-$root/build}"
threads="${WARPMESH_THREADS:-$(nproc)}"
pairs=("$@")
[ "${#pairs[@]}" -gt 0 ] || pairs=(0.285:0.3985 0.28:0.40 0.27:0.39957 0.24999:0.41189 0.22:0.38 0.20:0.35 0.27:0.43 0.24999:0.35
  0.30:0.41189 0.24999:0.38 0.20:0.41189 0.22:0.41189 0.27:0.35 0.26:0.39957 0.285:0.38 0.29:0.3985 0.35:0.41189)
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
keep="${KEEP_DIR:-}"
[ -z "$keep" ] || mkdir -p "$keep"
prove="$build/prover/warpmesh-prove-bcc"
check="$build/checker/warpmesh-check-bcc"
for exe in "$prove" "$check"; do
  [ -x "$exe" ] || { echo "bcc-frontier: $exe missing (run scripts/build.sh)" >&2; exit 2; }
done

for p in "${pairs[@]}"; do
  IFS=: read -r l s _ <<<"$p"
  if [ -z "${l:-}" ] || [ -z "${s:-}" ]; then
    echo "bcc-frontier: a pair is L:S or L:S:CAPMIN:CAPMAX, not '$p'" >&2
    exit 2
  fi
done
row() { echo "| $1 | $2 | $3 | $4 | $5 | $6 | $7 | $8 | $9 | ${10} | ${11} |"; }
echo "| α_long | α_short | caps (deg) | certified dihedral angles | min witness | max witness | keys | leaves | prove user s | check user s | sha256 |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for p in "${pairs[@]}"; do
  IFS=: read -r l s cmin cmax <<<"$p"
  if [ -z "${cmin:-}" ]; then
    if ! ext="$("$prove" --alphas "$l" "$s" --extremes --threads "$threads" 2>"$tmp/ext.log")"; then
      echo "bcc-frontier: pair '$p': $(tail -1 "$tmp/ext.log")" >&2
      exit 2
    fi
    read -r _ wmin kmin wmax kmax _ <<<"$ext"
    cmin="$(awk -v w="$wmin" 'BEGIN { printf "%.3f", int((w - 0.005) * 1000) / 1000 }')"
    cmax="$(awk -v w="$wmax" 'BEGIN { c = (w + 0.05) * 1000; i = int(c); if (i < c) i++; printf "%.3f", i / 1000 }')"
    if ! awk -v a="$cmin" -v b="$cmax" 'BEGIN { exit !(a > 0 && b < 180) }'; then
      row "$l" "$s" "" "no bound: search finds flat tetrahedra ($wmin° at \`$kmin\`, $wmax° at \`$kmax\`)" "" "" "" "" "" "" ""
      continue
    fi
  fi
  cert="$tmp/c.cert"
  if ! /usr/bin/time -f %U -o "$tmp/prove.time" "$prove" --alphas "$l" "$s" --cap-min-deg "$cmin" \
    --cap-max-deg "$cmax" --threads "$threads" --out "$cert" 2>"$tmp/prove.log"; then
    why="$(grep -c 'not proved' "$tmp/prove.log" || true) keys not proved, first: $(grep -m1 'not proved' "$tmp/prove.log" | cut -c1-120)"
    row "$l" "$s" "[$cmin, $cmax]" "prover failed: $why" "" "" "" "" "$(tail -1 "$tmp/prove.time")" "" ""
    continue
  fi
  ptime="$(tail -1 "$tmp/prove.time")"
  sum="$(sha256sum "$cert" | cut -d' ' -f1)"
  [ -z "$keep" ] || cp "$cert" "$keep/bcc-$l-$s.cert"
  if ! /usr/bin/time -f %U -o "$tmp/check.time" "$check" "$cert" >"$tmp/check.log" 2>&1; then
    row "$l" "$s" "[$cmin, $cmax]" "REJECTED by the checker: $(grep -v '^[0-9.]*$' "$tmp/check.log" | tail -1 | sed "s|$cert: ||")" "" "" "" "" "$ptime" "$(tail -1 "$tmp/check.time")" "$sum"
    continue
  fi
  range="$(sed -n 's/.*rounded outward: every dihedral angle in \(.*\) deg$/\1/p' "$tmp/check.log")"
  # shellcheck disable=SC2016  # the backquotes are Markdown, not expansions
  wmin="$(sed -n 's/^  3D witness min \([^:]*\): angle \([0-9.]*\) deg.*/`\1` \2°/p' "$tmp/check.log")"
  # shellcheck disable=SC2016
  wmax="$(sed -n 's/^  3D witness max \([^:]*\): angle \([0-9.]*\) deg.*/`\1` \2°/p' "$tmp/check.log")"
  nkeys="$(sed -n 's/.* of the \([0-9]*\) keys is.*/\1/p' "$tmp/check.log")"
  leaves="$(sed -n 's/.*deg (\([0-9]*\) leaves)$/\1/p' "$tmp/check.log")"
  row "$l" "$s" "[$cmin, $cmax]" "$range" "$wmin" "$wmax" "$nkeys" "$leaves" "$ptime" "$(tail -1 "$tmp/check.time")" "$sum"
done
