#!/usr/bin/env bash
# The table of certified angle bounds (README.md, docs/guarantees.md), made from what the independent
# checker printed — never typed by hand.
#
#   build/prover/warpmesh-check proofs/*.cert | scripts/bounds-table.sh
#
# scripts/test.sh runs the checker, pipes its output through this script and
# fails if README.md or docs/guarantees.md does not contain the result verbatim (between the markers
# <!-- certified-bounds:begin --> and <!-- certified-bounds:end -->).
set -euo pipefail
awk '
  /^[^ ].*: rule / { rule = $0; sub(/.*: rule /, "", rule); sub(/,.*/, "", rule); next }
  /^  [UF] \(/ {
    set = substr($0, 3, 1)
    line = $0
    sub(/.*every angle >= /, "", line); split(line, a, " ")
    lo[rule, set] = a[1]
    line = $0
    sub(/.* and <= /, "", line); split(line, b, " ")
    hi[rule, set] = b[1]
    next
  }
  /^    rounded outward/ { r = $0; sub(/.*every angle in /, "", r); sub(/ deg$/, "", r); rounded[rule, set] = r; next }
  /^  witness / {
    # witness U min KEY: angle [LO, HI] deg (...), claim [...] deg, gap <= G deg
    kind = $3; key = $4; sub(/:$/, "", key)
    w = $0; sub(/.*angle \[/, "", w); sub(/,.*/, "", w)
    g = $0; sub(/.*gap <= /, "", g); sub(/ deg.*/, "", g)
    wit[rule, $2, kind] = "`" key "` " w "° (gap " g "°)"
    if (!(rule in seen)) { seen[rule] = 1; order[++n] = rule }
    next
  }
  END {
    print "| rule | configurations | every angle ≥ | every angle ≤ | to 4 decimals | min-angle witness | max-angle witness |"
    print "|---|---|---:|---:|---|---|---|"
    # The junction keys (proofs/materials.cert: rule "separating (junction
    # keys)", claim U only) come last, whatever the order of the files.
    for (pass = 1; pass <= 2; ++pass)
      for (i = 1; i <= n; ++i) {
        r = order[i]
        if ((r ~ /junction/) != (pass == 2)) continue
        for (s = 1; s <= 2; ++s) {
          set = s == 1 ? "U" : "F"
          if (!((r, set) in lo)) continue
          what = set == "U" ? (r ~ /junction/ ? "U: all junction keys" : "U: all consistent") : "F: flat stencils"
          printf "| %s | %s | %s° | %s° | %s | %s | %s |\n", r, what, lo[r, set], hi[r, set], rounded[r, set], wit[r, set, "min"], wit[r, set, "max"]
        }
      }
  }
'
