#!/usr/bin/env bash
# warpmesh against its peers on the same domains and spacings, one thread each:
#   warpmesh (plain and --optimize), CGAL Mesh_2 (Delaunay refinement, criteria
#   B = 0.125 and size sqrt(2) h) and Gmsh (Frontal-Delaunay, mesh size h).
# Every tool's output is read back with meshio and measured by the same code
# (bench/peers/evaluate.py): triangles, minimum / maximum / mean minimum angle,
# and the largest distance from the mesh boundary to the exact curve.
#
# usage: scripts/bench-peers.sh [--spacings "1 0.5"] [--out DIR]
# The peers are benchmark-only: this script installs them (libcgal-dev, gmsh,
# python3-meshio) and builds the CGAL driver under DIR; warpmesh, its library
# and its tests never need them.
#
# Time: warpmesh's meshing phases from its report (sampling to triangulation,
# certification and verification, and the optimisation when asked; no file
# output), the fastest of 3 runs; CGAL: constraint insertion and refinement,
# timed inside the driver (fastest of 3); Gmsh: its own "Done meshing 2D" wall
# time (one run: Gmsh is slow).  The peers' boundary follows polylines through
# points on the exact curve (CGAL: about h apart; Gmsh: splines through points
# h/4 apart), so their boundary distance is the sagitta of their chords.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
spacings="1 0.5"
out="$root/bench-peers-out"
while [ $# -gt 0 ]; do
  case "$1" in
    --spacings) spacings="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    *) echo "usage: $0 [--spacings \"1 0.5\"] [--out DIR]" >&2; exit 2 ;;
  esac
done
mkdir -p "$out"

need=()
dpkg -s libcgal-dev >/dev/null 2>&1 || need+=(libcgal-dev)
command -v gmsh >/dev/null 2>&1 || need+=(gmsh)
/usr/bin/python3 -c "import meshio, numpy" >/dev/null 2>&1 || need+=(python3-meshio python3-numpy)
if [ ${#need[@]} -gt 0 ]; then
  echo "installing the benchmark-only packages: ${need[*]}" >&2
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi

if [ -z "${WARPMESH_EXE:-}" ]; then
  "$root/scripts/build.sh" >/dev/null
  WARPMESH_EXE="$root/build/mesher/warpmesh"
fi
g++ -O3 -DNDEBUG -std=c++17 "$root/bench/peers/cgal_mesh2.cpp" -o "$out/cgal_mesh2" -lgmp -lmpfr
py=/usr/bin/python3
eval_py="$root/bench/peers/evaluate.py"

# name | warpmesh shape | evaluator domain
domains=(
  "ellipse 100 x 60|ellipse:0,0,100,60|ellipse:100,60"
  "annulus 40 / 100|annulus:0,0,40,100|annulus:40,100"
  "flower 80 + 25 cos 5θ|flower:0,0,80,25,5|flower:80,25,5"
)

fastest() {  # the smallest of the numbers on stdin
  sort -g | head -n1
}

row() {  # tool domain h seconds evaluator-json
  "$py" - "$@" <<'EOF'
import json, sys
tool, dom, h, sec, js = sys.argv[1:6]
q = json.loads(js)
sec = float(sec)
print(f"| {dom} | {h} | {tool} | {q['triangles']} | {sec:.4f} | {q['triangles'] / sec / 1e6:.3f} | "
      f"{q['min_angle']:.2f} | {q['max_angle']:.2f} | {q['mean_min_angle']:.2f} | {q['boundary_distance']:.2e} |")
EOF
}

echo "| domain | h | tool | triangles | seconds | M triangles/s | min angle | max angle | mean min angle | boundary distance |"
echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|"
for d in "${domains[@]}"; do
  IFS='|' read -r name shape dom <<<"$d"
  for h in $spacings; do
    tag="$(echo "$dom" | tr ':,' '__')_h$h"
    for variant in plain optimize; do
      flag=(); [ "$variant" = optimize ] && flag=(--optimize)
      secs=$(for k in 1 2 3; do
        "$WARPMESH_EXE" mesh --shape "$shape" --spacing "$h" --threads 1 "${flag[@]}" \
          -o "$out/$tag-warpmesh-$variant.vtu" --report "$out/$tag-$variant.json" --quiet
        "$py" -c "import json,sys; print(json.load(open(sys.argv[1]))['total_seconds'])" "$out/$tag-$variant.json"
      done | fastest)
      tool="warpmesh"; [ "$variant" = optimize ] && tool="warpmesh --optimize"
      row "$tool" "$name" "$h" "$secs" "$("$py" "$eval_py" "$dom" "$out/$tag-warpmesh-$variant.vtu")"
    done

    "$py" "$root/bench/peers/geometry.py" "$dom" "$h" "$out/$tag.poly" "$out/$tag.geo"
    secs=$(for k in 1 2 3; do "$out/cgal_mesh2" "$out/$tag.poly" "$h" "$out/$tag-cgal.off"; done | fastest)
    row "CGAL Mesh_2" "$name" "$h" "$secs" "$("$py" "$eval_py" "$dom" "$out/$tag-cgal.off")"

    log=$(OMP_NUM_THREADS=1 gmsh "$out/$tag.geo" -2 -nt 1 -format msh41 -o "$out/$tag-gmsh.msh" 2>&1)
    secs=$(printf '%s\n' "$log" | sed -n 's/.*Done meshing 2D (Wall \([0-9.e+-]*\)s.*/\1/p' | tail -n1)
    row "Gmsh" "$name" "$h" "$secs" "$("$py" "$eval_py" "$dom" "$out/$tag-gmsh.msh")"
  done
done
