#!/usr/bin/env bash
# The table of certified angle bounds (README.md, docs/guarantees.md), made from what the independent
# checker printed — never typed by hand.
#
#   { build/checker/warpmesh-check proofs/{fan,materials,materials_fan,maxmin,rhombic_maxmin,rhombic_separating,separating}.cert;
#     build/checker/warpmesh-check-bcc proofs/bcc.cert; build/checker/warpmesh-check-bcc proofs/bcc_delaunay.cert;
#     build/checker/warpmesh-check-bcc proofs/bcc_junctions.cert; build/checker/warpmesh-check-bcc proofs/bcc_graded.cert;
#     build/checker/warpmesh-check-bcc proofs/bcc_half.cert; build/checker/warpmesh-check-bcc proofs/bcc_ceiling.cert; } | scripts/bounds-table.sh
#
# The 3D checker's theorems (dihedral angles of the BCC lattice warping, one
# row per certificate in input order: the parity face rule, the Delaunay face
# rule, the junction keys of multi-material meshes) come after the 2D rows,
# then the A15 lattice's (a15.cert, when its check is in the input: not
# yet in proofs/, proofs/README.md "The A15 space"),
# then the graded meshes' transition templates;
# its counter-example for the α = ½ closer-endpoint rule (no bound: an
# inverted tetrahedron) follows, and the
# ceiling (no thresholds, with any face rule, reach its angle) is the last.
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
  /^(BCC|A15) theorem \(alphas / {
    # BCC theorem (alphas A, B[, Delaunay face rule]): ... t in [LO, HI] deg ...
    # A15 theorem (alphas C, W, A, B (chain, ...), Delaunay face rule): ... (the A15 lattice)
    al = $0; sub(/^(BCC|A15) theorem \(alphas /, "", al); sub(/\):.*/, "", al)
    a15[n3 + 1] = $0 ~ /^A15/
    faces3[++n3] = al ~ /Delaunay face rule/ ? "Delaunay" : "parity"
    junction3[n3] = al ~ /junction keys/
    a3[n3] = al
    t3 = $0; sub(/.*: t in \[/, "", t3); sub(/\] deg.*/, "", t3); split(t3, tt, ", ")
    lo3[n3] = tt[1]; hi3[n3] = tt[2]
    next
  }
  /^BCC counter-example \(alphas / {
    # BCC counter-example (alphas A, B): key K at (P): output tetrahedron (...) has 6*volume V < 0 (inverted; ...
    ax = $0; sub(/^BCC counter-example \(alphas /, "", ax); sub(/\):.*/, "", ax)
    kx = $0; sub(/.*: key /, "", kx); sub(/ at .*/, "", kx)
    px = $0; sub(/.* at \(/, "", px); sub(/\):.*/, "", px)
    vx = $0; sub(/.* has 6\*volume /, "", vx); sub(/ .*/, "", vx)
    next
  }
  /^BCC graded templates: / {
    # BCC graded templates: the N tetrahedra of the 17 fan configurations (...) are ... in [LO, HI] deg and ...; witnesses A, B, C deg
    gn = $0; sub(/^BCC graded templates: the /, "", gn); sub(/ tetrahedra.*/, "", gn)
    gt = $0; sub(/.*dihedral angle in \[/, "", gt); sub(/\] deg.*/, "", gt); split(gt, gg, ", ")
    gw = $0; sub(/.*; witnesses /, "", gw); sub(/ deg$/, "", gw); split(gw, gv, ", ")
    glo = gg[1]; ghi = gg[2]
    next
  }
  /^BCC ceiling: / {
    # BCC ceiling: ... a dihedral angle below D deg (= X deg; cos^2 > C), of a key ...: N boxes (K n, ...); NO BOUND ...
    cx = $0; sub(/.* below /, "", cx); sub(/ deg \(= .*/, "", cx)
    dx = $0; sub(/.*deg \(= /, "", dx); sub(/ deg;.*/, "", dx)
    bx = $0; sub(/.*no face rule enters\): /, "", bx); sub(/\); NO BOUND.*/, ")", bx)
    next
  }
  /^  rounded outward: every dihedral angle in / { r = $0; sub(/.*angle in /, "", r); sub(/ deg$/, "", r); r3[n3] = r; next }
  /^  3D witness / {
    # 3D witness min KEY: angle A deg, claim C deg, gap G deg
    key = $4; sub(/:$/, "", key)
    w = $0; sub(/.*: angle /, "", w); sub(/ deg.*/, "", w)
    g = $0; sub(/.*gap /, "", g); sub(/ deg.*/, "", g)
    wit3[n3, $3] = "`" key "` " w "° (gap " g "°)"
    next
  }
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
    # keys)", claim U only), then the rhombic lattice (rule "maxmin (rhombic
    # lattice)") come last, whatever the order of the files.
    for (pass = 1; pass <= 3; ++pass)
      for (i = 1; i <= n; ++i) {
        r = order[i]
        if ((r ~ /junction/ ? 2 : r ~ /rhombic/ ? 3 : 1) != pass) continue
        for (s = 1; s <= 2; ++s) {
          set = s == 1 ? "U" : "F"
          if (!((r, set) in lo)) continue
          what = set == "U" ? (r ~ /junction/ ? "U: all junction keys" : "U: all consistent") : "F: flat stencils"
          printf "| %s | %s | %s° | %s° | %s | %s | %s |\n", r, what, lo[r, set], hi[r, set], rounded[r, set], wit[r, set, "min"], wit[r, set, "max"]
        }
      }
    for (i = 1; i <= n3; ++i) {
      if (a15[i]) continue
      split(a3[i], aa, ", "); split(aa[1], p, "/"); split(aa[2], q, "/")
      what3 = junction3[i] ? "BCC multi-material junctions (3 or 4 materials), " : "BCC closest-first, "
      conf3 = junction3[i] ? "all junction keys" : "all keys with output"
      printf "| %s%s faces (3D dihedral, α %.5f / %.5f) | %s | %s° | %s° | %s | %s | %s |\n", what3, faces3[i], p[1] / p[2], q[1] / q[2], conf3, lo3[i], hi3[i], r3[i], wit3[i, "min"], wit3[i, "max"]
    }
    for (i = 1; i <= n3; ++i) {  # the A15 lattice after BCC
      if (!a15[i]) continue
      split(a3[i], aa, ", "); split(aa[1], ac, "/"); split(aa[2], aw, "/"); split(aa[3], ax5, "/"); split(aa[4], ay, "/")
      printf "| A15 closest-first, %s faces (3D dihedral, α chain %.5f / wide %.5f / A end %.5f / B end %.5f) | all keys with output | %s° | %s° | %s | %s | %s |\n", faces3[i], ac[1] / ac[2], aw[1] / aw[2], ax5[1] / ax5[2], ay[1] / ay[2], lo3[i], hi3[i], r3[i], wit3[i, "min"], wit3[i, "max"]
    }
    if (glo != "")
      printf "| BCC graded transitions (3D dihedral, the templates of graded meshes, any α) | all 17 fan configurations (%s tetrahedra) | %s° | %s° | %s° … %s° | %s° (exact) | %s° (exact) |\n", gn, glo, ghi, glo, ghi, gv[1], gv[2]
    if (kx != "") {
      split(ax, aa, ", "); split(aa[1], p, "/"); split(aa[2], q, "/")
      printf "| BCC closer-endpoint (3D dihedral, α %.5f / %.5f) | all keys with output | no bound | no bound | inverted | `%s` at (%s): 6·volume %s (doubled coordinates) | — |\n", p[1] / p[2], q[1] / q[2], kx, px, vx
    }
    if (cx != "") {
      gsub(/-,/, "`-,", bx); gsub(/\/0 /, "/0` ", bx)
      printf "| BCC, any thresholds and face rule (3D dihedral ceiling, α in [0, ½]²) | keys with one output tetrahedron | no bound ≥ %s° | — | ceiling | below %s° at every pair: %s | — |\n", dx, cx, bx
    }
  }
'
