#!/usr/bin/env bash
# Speed and memory of the mesher, as measured on this machine.
#
# For each case and thread count: output triangles, meshing time (the sum of
# the pipeline phases, excluding file output and the quality report; the
# fastest of five runs, each a fresh process — and for the graded mesher also
# the fastest of ten runs in one process, "warm"), triangles per second, and peak resident memory of the whole process in bytes
# per output triangle.  No mesh file is written (the cost of .vtu/.msh output
# is a separate, I/O-bound matter).
#
#   scripts/bench.sh            all cases: uniform, graded, the fan rule against
#                               the separating rule, cost of certification
#   scripts/bench.sh --quick    the atlas slice only (with each rule)
#   scripts/bench.sh --3d       the 3D mesher (issue 30): a sphere and the SPL brain
#                               atlas through warpmesh-bench3d (library only, no
#                               file); the fastest of three runs each
#   scripts/bench.sh --writers  end to end with file output (issues 32, 49): whole-
#                               process wall time and peak RSS from /usr/bin/time -v
#                               against the meshing time, per format, triangles (the
#                               4096² disc) and tetrahedra (the SPL brain atlas at
#                               1 mm, WARPMESH_BRAIN_NRRD), each with a no-output row
#   scripts/bench.sh --cgal3d   warpmesh mesh3d against CGAL Mesh_3 on the SPL brain
#                               atlas (--label nonzero), one thread each, in one run:
#                               tetrahedra, time, min/max dihedral angle; installs
#                               libcgal-dev (benchmark-only) and builds
#                               bench/peers/cgal_mesh3.cpp.  The atlas NRRD is
#                               WARPMESH_BRAIN_NRRD or /work/shared/data/*/orig/hncma-atlas.nrrd
#   scripts/bench.sh --graded3d graded against uniform warpmesh and CGAL Mesh_3 on the SPL
#                               brain atlas (--label nonzero) at 2, 1.4 and 1 mm
#                               (WARPMESH_BENCH_GRADED_SPACINGS), one thread each, in one
#                               run (issue 48): tetrahedra, boundary faces, CPU s,
#                               tets/CPU s, tets per boundary face, measured and
#                               certified dihedral extremes.
#                               CGAL gets the surface size of the spacing (facet size S,
#                               facet distance S / 2) and no cell size (cells free to
#                               grow inside); WARPMESH_BENCH_GRADED_CGAL lists the
#                               spacings CGAL runs at (default all).
#   scripts/bench.sh --cgal3d-whole
#                               the whole process of both, in one run (issue 49, item 7):
#                               read + mesh + write a Medit .mesh, one thread each,
#                               wall, CPU (user + system) and peak RSS from
#                               /usr/bin/time -v, at the pairs WARPMESH_BENCH_PAIRS
#                               (warpmesh spacing:CGAL size, default "5:5 2.5:2.5 1.4:1.4");
#                               warpmesh reads the gzip'd NRRD (--label nonzero), CGAL
#                               the region as raw bytes (written before, not timed)
#   scripts/bench.sh --cgal3d-materials
#                               every label of the SPL brain and abdomen atlases
#                               (--materials all) against CGAL Mesh_3 on the same
#                               labelled volumes (renumbered 1..N, 16-bit), one
#                               thread each, in one run: tetrahedra, CPU seconds
#                               (warpmesh: the whole mesh3d call through
#                               warpmesh-bench3d; CGAL: make_mesh_3), tetrahedra per
#                               CPU second, bytes per tetrahedron, min/max dihedral
#                               angle, labels kept, certified bounds and per-label
#                               volume errors, CGAL with refinement only and with
#                               perturb + exude, and the ratio to CGAL's refinement
#                               at the warpmesh spacing of the nearest count
#                               (WARPMESH_BENCH_{BRAIN,ABDOMEN}_{SPACINGS,CGAL}).
#                               Atlases: WARPMESH_BRAIN_NRRD, WARPMESH_ABDOMEN_NRRD
#                               (default /work/shared/data/*/orig/{hncma-atlas,seg}.nrrd)
#   scripts/bench.sh --accuracy [--before EXE] [--cgal]
#                               accuracy per unknown (issue 33): FEniCSx Poisson,
#                               P1 and P2, on the disc and the flower, warpmesh
#                               (plain, --optimize, --graded --max-size) against
#                               Gmsh Frontal-Delaunay, 10^3 - 3.10^5 vertices
#                               (bench/accuracy/accuracy.py, under nice -n 10);
#                               --before: another warpmesh build as a series;
#                               --cgal: installs libcgal-dev (benchmark-only) and
#                               adds CGAL Mesh_2 (bench/peers/cgal_mesh2.cpp)
#   scripts/bench.sh --accuracy3d [--rates H,H,...]
#                               3D accuracy (issue 48): FEniCSx P1 Poisson on the
#                               unit ball, warpmesh uniform and --graded --max-size 4h
#                               against Gmsh's Delaunay ball, L² error against
#                               vertices (bench/accuracy/accuracy3d.py --compare);
#                               --rates: the graded series' rates at these spacings
#                               (0.00625: 13.8 M tetrahedra, 6.6 GB, 6 CPU min)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/setup.sh" >/dev/null
"$root/scripts/build.sh" >/dev/null
exe="${WARPMESH_BUILD_DIR:-$root/build}/mesher/warpmesh"
tmp="$(mktemp -d)"
# CGAL is benchmark-only: installed here (the CGAL sections), never by setup.sh.
install_cgal() {
  if ! dpkg -s libcgal-dev >/dev/null 2>&1; then
    SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
    $SUDO apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends libcgal-dev >/dev/null
  fi
}
trap 'rm -rf "$tmp"' EXIT
# The region warpmesh meshes with --label nonzero, as bytes for CGAL's Image_3
# (the SPL atlas NRRD is gzip'd shorts, x fastest, 1 mm voxels): brain_bytes NRRD RAW.
brain_bytes() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import gzip, sys, numpy as np
raw = open(sys.argv[1], "rb").read()
at = raw.index(b"\n\n")
assert b"sizes: 256 256 256" in raw[:at] and b"type: short" in raw[:at] and b"encoding: gzip" in raw[:at]
(np.frombuffer(gzip.decompress(raw[at + 2:]), "<i2") != 0).astype(np.uint8).tofile(sys.argv[2])
PY
}
# The CGAL sections on the brain: CGAL installed, the peer built ($tmp/cgal_mesh3),
# the atlas found ($nrrd) and binarised ($tmp/brain.raw).
cgal_and_brain() {
  install_cgal
  nrrd="${WARPMESH_BRAIN_NRRD:-$(ls /work/shared/data/*/orig/hncma-atlas.nrrd 2>/dev/null | head -1)}"
  [ -f "$nrrd" ] || { echo "the SPL brain atlas NRRD was not found: set WARPMESH_BRAIN_NRRD" >&2; exit 1; }
  g++ -O3 -DNDEBUG -std=c++17 "$root/bench/peers/cgal_mesh3.cpp" -o "$tmp/cgal_mesh3" -lgmp -lmpfr
  brain_bytes "$nrrd" "$tmp/brain.raw"
}
brain="$root/mesher/examples/brain_axial_s128_labels16.pgm"

field() { sed -n "s/^  \"$1\": \\([^,]*\\),*$/\\1/p" "$2"; }

run_case() {  # name threads args...
  local name="$1" threads="$2"
  shift 2
  # Fastest of five runs: on this shared 2-core VM a fresh process's figures
  # vary by up to 2x from run to run (the warm in-process ones by ±5 %); the
  # minimum is the run least disturbed.
  local best="" s
  for _ in 1 2 3 4 5; do
    OMP_NUM_THREADS="$threads" "$exe" mesh "$@" --quiet --report "$tmp/run.json"
    s=$(field total_seconds "$tmp/run.json")
    if [ -z "$best" ] || awk -v a="$s" -v b="$best" 'BEGIN { exit !(a < b) }'; then
      best="$s"
      cp "$tmp/run.json" "$tmp/r.json"
    fi
  done
  print_case "$name" "$threads"
}

warm_case() {  # name threads args...: ten runs in one process (--repeat), the fastest
  local name="$1" threads="$2"
  shift 2
  OMP_NUM_THREADS="$threads" "$exe" mesh "$@" --repeat 10 --quiet --report "$tmp/r.json"
  print_case "$name" "$threads"
}

print_case() {  # name threads, from $tmp/r.json
  local name="$1" threads="$2"
  local tris secs mem
  tris=$(field triangles "$tmp/r.json")
  secs=$(field total_seconds "$tmp/r.json")
  mem=$(field peak_memory_mb "$tmp/r.json")
  awk -v n="$name" -v th="$threads" -v t="$tris" -v s="$secs" -v m="$mem" 'BEGIN {
    printf "%-34s %2d  %11d  %8.3f  %8.2f  %9.1f  %6.1f\n", n, th, t, s, t / s / 1e6, m, m * 1048576 / t }'
  sed -n 's/^  "phase_seconds": /      phases: /p' "$tmp/r.json"
}

# One whole-process run writing `out`: file size (all files it makes), wall
# time and peak RSS (/usr/bin/time -v), the meshing time (the report's
# total_seconds) and wall / meshing; the fastest wall time of three runs.
# OUT "-": no mesh output (the report only: the process's fixed costs beyond
# the meshing, e.g. the quality report).  A first argument mesh3d meshes
# tetrahedra.
write_case() {  # name threads out [mesh3d] args...
  local name="$1" threads="$2" out="$3" sub=mesh
  shift 3
  if [ "${1:-}" = mesh3d ]; then sub=mesh3d; shift; fi
  local best="" w o=()
  [ "$out" != - ] && o=(-o "$tmp/o/$out")
  for _ in 1 2 3; do
    rm -rf "$tmp/o" && mkdir "$tmp/o"
    /usr/bin/time -v "$exe" "$sub" "$@" --threads "$threads" "${o[@]}" --quiet --report "$tmp/w.json" 2>"$tmp/time.txt"
    w=$(sed -n 's/.*Elapsed (wall clock) time (h:mm:ss or m:ss): //p' "$tmp/time.txt" | awk -F: '{ print ($1 * 60) + $2 }')
    if [ -z "$best" ] || awk -v a="$w" -v b="$best" 'BEGIN { exit !(a < b) }'; then
      best="$w"
      cp "$tmp/w.json" "$tmp/wb.json"
      cp "$tmp/time.txt" "$tmp/timeb.txt"
      du -cb "$tmp"/o | tail -1 | cut -f1 >"$tmp/size.txt"
    fi
  done
  local mesh rss size
  mesh=$(field total_seconds "$tmp/wb.json")
  [ -n "$mesh" ] || mesh=$(field seconds "$tmp/wb.json")  # mesh3d's report
  rss=$(sed -n 's/.*Maximum resident set size (kbytes): //p' "$tmp/timeb.txt")
  size=$(cat "$tmp/size.txt")
  awk -v n="$name" -v th="$threads" -v s="$size" -v w="$best" -v m="$mesh" -v r="$rss" 'BEGIN {
    printf "| %s | %d | %.2f GB | %.2f s | %.2f s | %.1fx | %.0f MB |\n", n, th, s / 1e9, w, m, w / m, r / 1024 }'
}

if [ "${1:-}" = "--accuracy" ]; then
  shift
  extra=()
  while [ $# -gt 0 ]; do
    case "$1" in
      --before) extra+=(--before "$2"); shift 2 ;;
      --cgal)
        install_cgal
        g++ -O3 -DNDEBUG -std=c++17 "$root/bench/peers/cgal_mesh2.cpp" -o "$tmp/cgal_mesh2" -lgmp -lmpfr
        extra+=(--cgal "$tmp/cgal_mesh2"); shift ;;
      *) echo "usage: $0 --accuracy [--before EXE] [--cgal]" >&2; exit 2 ;;
    esac
  done
  echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); load: $(cut -d' ' -f1-3 /proc/loadavg)"
  OMP_NUM_THREADS=1 nice -n 10 /usr/bin/python3 "$root/bench/accuracy/accuracy.py" --warpmesh "$exe" \
    --json "${WARPMESH_ACCURACY_JSON:-$tmp/accuracy.json}" ${extra[@]+"${extra[@]}"}
  exit 0
fi

if [ "${1:-}" = "--accuracy3d" ]; then
  shift
  mode=(--compare)
  case "${1:-}" in
    --rates) mode=(--rates "${2:?usage: $0 --accuracy3d [--rates H,H,...]}") ;;
    "") ;;
    *) echo "usage: $0 --accuracy3d [--rates H,H,...]" >&2; exit 2 ;;
  esac
  echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); load: $(cut -d' ' -f1-3 /proc/loadavg)"
  OMP_NUM_THREADS=1 nice -n 10 /usr/bin/python3 "$root/bench/accuracy/accuracy3d.py" --warpmesh "$exe" "${mode[@]}" \
    --json "${WARPMESH_ACCURACY_JSON:-$tmp/accuracy3d.json}"
  exit 0
fi

if [ "${1:-}" = "--writers" ]; then
  echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); load: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "| output | threads | files | wall | meshing | wall / meshing | peak RSS |"
  echo "|---|---:|---:|---:|---:|---:|---:|"
  disc=(--shape circle:0,0,2047 --spacing 1)
  write_case "disc 4096², no mesh output (report only)" 1 - "${disc[@]}"
  write_case "disc 4096², binary .vtu" 1 d.vtu "${disc[@]}"
  write_case "disc 4096², zlib .vtu (--compress)" 1 d.vtu "${disc[@]}" --compress
  write_case "disc 4096², binary .msh 4.1" 1 d.msh "${disc[@]}"
  write_case "disc 4096², .xdmf + .h5" 1 d.xdmf "${disc[@]}"
  write_case "disc 4096², ASCII .vtu (--ascii)" 1 d.vtu "${disc[@]}" --ascii
  write_case "disc 4096², ASCII .inp" 2 d.inp "${disc[@]}"
  write_case "disc 4096², ASCII .node/.ele" 2 d.node "${disc[@]}"
  write_case "brain slice ¼ px, every label, binary .vtu" 1 b.vtu "$brain" --materials all --spacing 0.25
  write_case "brain slice ¼ px, every label, binary .vtu" 2 b.vtu "$brain" --materials all --spacing 0.25
  # Tetrahedra: the SPL brain atlas at 1 mm (--label nonzero, 22 M tetrahedra).
  nrrd="${WARPMESH_BRAIN_NRRD:-$(ls /work/shared/data/*/orig/hncma-atlas.nrrd 2>/dev/null | head -1)}"
  if [ -f "$nrrd" ]; then
    atlas=(mesh3d "$nrrd" --label nonzero --spacing 1)
    write_case "SPL brain 1 mm, no mesh output (report only)" 1 - "${atlas[@]}"
    write_case "SPL brain 1 mm, binary .vtu" 1 t.vtu "${atlas[@]}"
    write_case "SPL brain 1 mm, binary .msh 4.1" 1 t.msh "${atlas[@]}"
    write_case "SPL brain 1 mm, .xdmf + .h5" 1 t.xdmf "${atlas[@]}"
    write_case "SPL brain 1 mm, ASCII .inp" 2 t.inp "${atlas[@]}"
  else
    echo "(the SPL brain atlas NRRD was not found: set WARPMESH_BRAIN_NRRD for the tetrahedral cases)"
  fi
  echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
  exit 0
fi

if [ "${1:-}" = "--cgal3d" ]; then
  cgal_and_brain
  echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); load before: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "SPL brain atlas 256^3, 1 mm, --label nonzero; one thread each; wall s: the meshing alone (warpmesh: its report, CGAL: make_mesh_3); CPU s: user CPU of the whole process"
  printf "%-38s %10s %9s %9s %9s %9s %8s\n" mesher tetrahedra "wall s" "CPU s" "min dih" "max dih" "peak MB"
  for s in ${WARPMESH_BENCH_SPACINGS:-3 2}; do
    /usr/bin/time -f "%e %U %M" -o "$tmp/t" "$exe" mesh3d "$nrrd" --label nonzero --spacing "$s" --threads 1 \
      --report "$tmp/w.json" --quiet 2>/dev/null
    read -r _ user rss < "$tmp/t"
    printf "%-38s %10s %9.2f %9.2f %9.3f %9.3f %8d\n" "warpmesh mesh3d, spacing $s" "$(field tetrahedra "$tmp/w.json")" \
      "$(field seconds "$tmp/w.json")" "$user" "$(field min_dihedral_deg "$tmp/w.json")" \
      "$(field max_dihedral_deg "$tmp/w.json")" $((rss / 1024))
  done
  /usr/bin/python3 -c "import json,sys; c=json.load(open(sys.argv[1]))['certified']; print('  (warpmesh certified: every tetrahedron in [%.2f, %.2f] deg, %s)' % (c['min_dihedral_deg'], c['max_dihedral_deg'], c['certificate']))" "$tmp/w.json"
  for h in ${WARPMESH_BENCH_CGAL_SIZES:-2}; do
    /usr/bin/time -f "%e %U %M" -o "$tmp/t" "$tmp/cgal_mesh3" "$tmp/brain.raw" 256 256 256 1 1 1 "$h" > "$tmp/c.json"
    read -r _ user rss < "$tmp/t"
    /usr/bin/python3 -c "import json,sys; c=json.load(open(sys.argv[1])); print('%-38s %10d %9.2f %9.2f %9.3f %9.3f %8d' % ('CGAL Mesh_3, facet/cell size ' + sys.argv[2], c['tetrahedra'], c['seconds'], float(sys.argv[3]), c['min_dihedral_deg'], c['max_dihedral_deg'], int(sys.argv[4]) // 1024))" \
      "$tmp/c.json" "$h" "$user" "$rss"
  done
  echo "  (CGAL: wall s = make_mesh_3 only; CPU s = the whole process, reading and the image domain included)"
  echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
  exit 0
fi

if [ "${1:-}" = "--graded3d" ]; then
  bench3d="${WARPMESH_BUILD_DIR:-$root/build}/mesher/warpmesh-bench3d"
  cgal_and_brain
  echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); load before: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "SPL brain atlas 256^3, 1 mm, --label nonzero; one thread each.  CPU s: warpmesh, the whole mesh3d call (warpmesh-bench3d,"
  echo "no file, no quality pass); CGAL, make_mesh_3 alone.  Angles, boundary faces and certified bounds from a separate report run."
  printf "%-44s %10s %9s %9s %8s %11s %9s %9s  %s\n" mesher tetrahedra "bdry fcs" "tets/fc" "CPU s" "tets/CPU s" "min dih" "max dih" certified
  cgal_at=" ${WARPMESH_BENCH_GRADED_CGAL:-${WARPMESH_BENCH_GRADED_SPACINGS:-2 1.4 1}} "
  for s in ${WARPMESH_BENCH_GRADED_SPACINGS:-2 1.4 1}; do
    for mode in "" --graded; do
      # shellcheck disable=SC2086
      out=$("$bench3d" --volume "$nrrd" --label nonzero --spacing "$s" --threads 1 $mode 2>/dev/null)
      # shellcheck disable=SC2086
      "$exe" mesh3d "$nrrd" --label nonzero --spacing "$s" --threads 1 $mode --report "$tmp/w.json" --quiet 2>/dev/null
      /usr/bin/python3 - "$tmp/w.json" "$s" "$mode" "$out" <<'PY'
import json, sys
w = json.load(open(sys.argv[1])); kv = dict(x.split("=", 1) for x in sys.argv[4].split())
tets, cpu, c = int(kv["tets"]), float(kv["cpu_seconds"]), w["certified"]
print("%-44s %10d %9d %9.2f %8.2f %11.0f %9.3f %9.3f  [%.2f, %.2f]" % ("warpmesh mesh3d %s, spacing %s" % ("graded" if sys.argv[3] else "uniform", sys.argv[2]),
      tets, w["boundary_faces"], tets / w["boundary_faces"], cpu, tets / cpu, w["min_dihedral_deg"], w["max_dihedral_deg"], c["min_dihedral_deg"], c["max_dihedral_deg"]))
PY
    done
    case "$cgal_at" in *" $s "*) ;; *) continue ;; esac
    "$tmp/cgal_mesh3" "$tmp/brain.raw" 256 256 256 1 1 1 "$s" cell=0 "distance=$(awk -v s="$s" 'BEGIN { print s / 2 }')" > "$tmp/c.json"
    /usr/bin/python3 - "$tmp/c.json" "$s" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
print("%-44s %10d %9d %9.2f %8.2f %11.0f %9.3f %9.3f  none" % ("CGAL Mesh_3, facet size %s, no cell size" % sys.argv[2], c["tetrahedra"], c["facets"],
      c["tetrahedra"] / c["facets"], c["cpu_seconds"], c["tetrahedra"] / c["cpu_seconds"], c["min_dihedral_deg"], c["max_dihedral_deg"]))
PY
  done
  echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
  exit 0
fi

if [ "${1:-}" = "--cgal3d-whole" ]; then
  cgal_and_brain
  # wall s, CPU s (user + system) and peak MB of the last command, from /usr/bin/time -v's report in $1.
  timed() { awk -F': ' '/Elapsed/ { n = split($2, t, ":"); w = t[n] + (n > 1 ? 60 * t[n - 1] : 0) } /User time/ { u = $2 }
                        /System time/ { s = $2 } /Maximum resident/ { m = $2 } END { printf "%.2f %.2f %d", w, u + s, m / 1024 }' "$1"; }
  echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); $(uptime)"
  echo "SPL brain atlas 256^3 int16 (33.5 MB of voxels, 0.47 MB gzip'd), --label nonzero; one thread each; the whole process:"
  echo "read + mesh + write a Medit .mesh (warpmesh: the gzip'd NRRD, its default report with the quality pass; CGAL: the raw region bytes)"
  printf "%-34s %10s %8s %8s %8s %11s %9s %9s\n" mesher tetrahedra "wall s" "CPU s" "peak MB" "tets/CPU s" "min dih" "max dih"
  for pair in ${WARPMESH_BENCH_PAIRS:-5:5 2.5:2.5 1.4:1.4}; do
    s=${pair%%:*} h=${pair##*:}
    /usr/bin/time -v -o "$tmp/t" "$exe" mesh3d "$nrrd" --label nonzero --spacing "$s" --threads 1 -o "$tmp/w.mesh" \
      --report "$tmp/w.json" --quiet 2>/dev/null
    read -r wall cpu mb <<<"$(timed "$tmp/t")"
    wt=$(field tetrahedra "$tmp/w.json")
    printf "%-34s %10s %8s %8s %8s %11.0f %9.3f %9.3f\n" "warpmesh mesh3d --spacing $s" "$wt" "$wall" "$cpu" "$mb" \
      "$(awk -v t="$wt" -v c="$cpu" 'BEGIN { print t / c }')" "$(field min_dihedral_deg "$tmp/w.json")" "$(field max_dihedral_deg "$tmp/w.json")"
    /usr/bin/time -v -o "$tmp/t" "$tmp/cgal_mesh3" "$tmp/brain.raw" 256 256 256 1 1 1 "$h" "out=$tmp/c.mesh" > "$tmp/c.json"
    read -r cwall ccpu cmb <<<"$(timed "$tmp/t")"
    /usr/bin/python3 -c "import json,sys; c=json.load(open(sys.argv[1])); print('%-34s %10d %8s %8s %8s %11.0f %9.3f %9.3f' % ('CGAL Mesh_3, size ' + sys.argv[2], c['tetrahedra'], sys.argv[3], sys.argv[4], sys.argv[5], c['tetrahedra'] / float(sys.argv[4]), c['min_dihedral_deg'], c['max_dihedral_deg']))" \
      "$tmp/c.json" "$h" "$cwall" "$ccpu" "$cmb"
    awk -v a="$ccpu" -v b="$cpu" 'BEGIN { printf "  CGAL CPU / warpmesh CPU: %.1fx\n", a / b }'
  done
  echo "$(uptime)"
  exit 0
fi

if [ "${1:-}" = "--cgal3d-materials" ]; then
  install_cgal
  bench3d="${WARPMESH_BUILD_DIR:-$root/build}/mesher/warpmesh-bench3d"
  brain="${WARPMESH_BRAIN_NRRD:-$(ls /work/shared/data/*/orig/hncma-atlas.nrrd 2>/dev/null | head -1)}"
  abdomen="${WARPMESH_ABDOMEN_NRRD:-$(ls /work/shared/data/spl_abdomen/orig/seg.nrrd 2>/dev/null | head -1)}"
  g++ -O3 -DNDEBUG -std=c++17 "$root/bench/peers/cgal_mesh3.cpp" -o "$tmp/cgal_mesh3" -lgmp -lmpfr
  echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); load before: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "every label; one thread each.  CPU s: warpmesh, the whole mesh3d call (warpmesh-bench3d: the material field"
  echo "built from the volume, lattice, meshing, boundary and interfaces, certification counts, per-material figures;"
  echo "not reading the file, not the quality pass, no file written); CGAL, make_mesh_3 alone.  tets/CPU s from it."
  echo "B/tet: warpmesh's peak resident memory of the call beyond what the process held before (the volume read) per tetrahedron."
  echo "Then, per warpmesh spacing, from a separate report run (not timed): measured dihedral extremes, certified bounds,"
  echo "and the labels of >= 1000 voxels whose mesh volume is within 5 % of their voxels'."
  printf "%-46s %10s %8s %11s %6s %9s %9s %7s\n" mesher tetrahedra "CPU s" "tets/CPU s" "B/tet" "min dih" "max dih" labels
  for case in "brain:$brain:${WARPMESH_BENCH_BRAIN_SPACINGS:-1 2.9}:${WARPMESH_BENCH_BRAIN_CGAL:-4}" \
              "abdomen:$abdomen:${WARPMESH_BENCH_ABDOMEN_SPACINGS:-0.9375 3.4}:${WARPMESH_BENCH_ABDOMEN_CGAL:-3.3}"; do
    IFS=: read -r name nrrd spacings sizes <<<"$case"
    [ -f "$nrrd" ] || { echo "$name: the atlas NRRD was not found (set WARPMESH_${name^^}_NRRD)" >&2; continue; }
    # The labels renumbered 1..N as little-endian 16-bit voxels for CGAL's Image_3.
    geometry=$(/usr/bin/python3 - "$nrrd" "$tmp/$name.raw" <<'PY'
import gzip, re, sys, numpy as np
raw = open(sys.argv[1], "rb").read()
at = raw.index(b"\n\n")
head = raw[:at].decode()
sizes = [int(x) for x in re.search(r"sizes: (\d+) (\d+) (\d+)", head).groups()]
dirs = re.search(r"space directions: (.*)", head).group(1)
spacing = [max(abs(float(v)) for v in d.strip("()").split(",")) for d in dirs.split()]
kind = {"short": "<i2", "unsigned short": "<u2", "unsigned char": "u1", "uchar": "u1", "int": "<i4"}[re.search(r"type: (.*)", head).group(1).strip()]
data = raw[at + 2:]
a = np.frombuffer(gzip.decompress(data) if "gzip" in head else data, kind).astype(np.int64)
labels = np.unique(a); labels = labels[labels != 0]
lut = np.zeros(int(a.max()) + 1, np.uint16); lut[labels] = np.arange(1, len(labels) + 1)
lut[a].astype("<u2").tofile(sys.argv[2])
print(*sizes, *spacing)
PY
)
    : > "$tmp/$name.rows"
    for s in $spacings; do
      out=$("$bench3d" --volume "$nrrd" --materials all --spacing "$s" --threads 1 2>/dev/null)
      "$exe" mesh3d "$nrrd" --materials all --spacing "$s" --threads 1 --report "$tmp/w.json" --quiet 2>/dev/null
      /usr/bin/python3 - "$tmp/w.json" "$name" "$s" "$out" "$tmp/$name.rows" <<'PY'
import json, sys
w = json.load(open(sys.argv[1])); kv = dict(x.split("=", 1) for x in sys.argv[4].split())
tets, cpu = int(kv["tets"]), float(kv["cpu_seconds"])
print("%-46s %10d %8.2f %11.0f %6.1f %9.3f %9.3f %7s" % ("warpmesh mesh3d " + sys.argv[2] + ", spacing " + sys.argv[3], tets, cpu, tets / cpu,
      float(kv["call_peak_bytes_per_tet"]), w["min_dihedral_deg"], w["max_dihedral_deg"], kv["kept"]))
err = lambda m: m["relative_error"] if m.get("relative_error") is not None else -1.0
big = [m for m in w["materials"] if (m.get("voxels") or 0) >= 1000]
within = [m for m in big if abs(err(m)) <= 0.05]
worst = max(big, key=lambda m: abs(err(m)))
j, c = w["junctions"], w["certified"]
print("    certified: %d of %d tetrahedra in [%.2f, %.2f] deg (junctions: %d tetrahedra, %s); labels >= 1000 voxels: %d of %d within 5 %%"
      " (worst %s, %+.1f %%); labels kept %s of %d" % (c["certified_tetrahedra"], tets, c["min_dihedral_deg"], c["max_dihedral_deg"],
      j["tetrahedra"], "certified" if j["certified"] else "not certified", len(within), len(big), worst["name"], 100 * err(worst),
      kv["kept"], len(w["materials"])))
open(sys.argv[5], "a").write("%d %f\n" % (tets, tets / cpu))
PY
    done
    for h in $sizes; do
      for mode in "" optimise; do
        # shellcheck disable=SC2086
        "$tmp/cgal_mesh3" "$tmp/$name.raw" $geometry "$h" u16 $mode > "$tmp/c.json"
        /usr/bin/python3 - "$tmp/c.json" "$name" "$h" "$mode" "$tmp/$name.rows" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
rate = c["tetrahedra"] / c["cpu_seconds"]
print("%-46s %10d %8.2f %11.0f %6s %9.3f %9.3f %7d" % ("CGAL Mesh_3 " + sys.argv[2] + ", size " + sys.argv[3] + (", perturb+exude" if sys.argv[4] else ""),
      c["tetrahedra"], c["cpu_seconds"], rate, "", c["min_dihedral_deg"], c["max_dihedral_deg"], c["labels"]))
if not sys.argv[4]:  # the ratio against the refinement alone, at the warpmesh run of the nearest count
    rows = [tuple(map(float, l.split())) for l in open(sys.argv[5])]
    tets, ours = min(rows, key=lambda r: abs(r[0] - c["tetrahedra"]) / c["tetrahedra"])
    print("    ratio at equal count: warpmesh %d tets at %.0f tets/CPU s, CGAL %d at %.0f: %.1fx" % (tets, ours, c["tetrahedra"], rate, ours / rate))
PY
      done
    done
  done
  echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
  exit 0
fi

if [ "${1:-}" = "--3d" ]; then
  # warpmesh-bench3d prints key=value figures; CPU seconds (user + system of
  # the mesh3d call, all threads) are the comparable figure on a shared VM.
  bench3d="${WARPMESH_BUILD_DIR:-$root/build}/mesher/warpmesh-bench3d"
  atlas="${WARPMESH_SPL_BRAIN:-/work/shared/data/spl_brain/orig/hncma-atlas.nrrd}"
  kv() { tr ' ' '\n' <<<"$2" | sed -n "s/^$1=//p"; }
  case3d() {  # name threads args...
    local name="$1" threads="$2" best="" line out
    shift 2
    for _ in 1 2 3; do
      out=$("$bench3d" "$@" --threads "$threads" 2>/dev/null)
      if [ -z "$best" ] || awk -v a="$(kv cpu_seconds "$out")" -v b="$(kv cpu_seconds "$best")" 'BEGIN { exit !(a < b) }'; then best="$out"; fi
    done
    line="| $name | $threads | $(kv tets "$best") | $(kv seconds "$best") | $(kv cpu_seconds "$best") | $(kv tets_per_cpu_second "$best") | $(kv peak_bytes_per_tet "$best") |"
    echo "$line"
  }
  echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1); load: $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "| case | threads | tetrahedra | wall s | CPU s | tets / CPU s | peak bytes / tet |"
  echo "|---|---:|---:|---:|---:|---:|---:|"
  case3d "sphere r = 1, s = 0.02 (104³ cubes)" 1 --shape sphere:0,0,0,1 --spacing 0.02
  case3d "sphere r = 1, s = 0.02 (104³ cubes)" 2 --shape sphere:0,0,0,1 --spacing 0.02
  case3d "sphere r = 1, s = 0.0078 (260³ cubes)" 2 --shape sphere:0,0,0,1 --spacing 0.0078125 --max-memory 8192
  if [ -f "$atlas" ]; then
    case3d "SPL brain atlas, --label nonzero, s = 1 mm" 1 --volume "$atlas" --label nonzero --spacing 1
    case3d "SPL brain atlas, --label nonzero, s = 1 mm" 2 --volume "$atlas" --label nonzero --spacing 1
  else
    echo "(no SPL brain atlas at $atlas: set WARPMESH_SPL_BRAIN)"
  fi
  echo "load after: $(cut -d' ' -f1-3 /proc/loadavg)"
  exit 0
fi

echo "machine: $(nproc) cores, $(sed -n 's/^model name\s*: //p' /proc/cpuinfo | head -1)"
echo "time = sum of the pipeline phases (no file output); certification off (--no-certify) unless stated"
printf "%-44s %2s  %11s  %8s  %8s  %9s  %6s\n" case thr triangles seconds "Mtri/s" "peak MB" "B/tri"
quick=0
[ "${1:-}" = "--quick" ] && quick=1
for th in 1 2; do
  run_case "atlas slice 256x256, s=1" "$th" "$brain" --label nonzero --spacing 1 --no-certify
  if [ "$quick" = 0 ]; then
    run_case "disc, 4096x4096 lattice" "$th" --shape circle:0,0,2047 --spacing 1 --no-certify
    run_case "atlas upscaled, 4096x4096 lattice" "$th" "$brain" --label nonzero --spacing 0.062255859375 --no-certify
    # Multi-material: every label its own material, interfaces as mesh edges
    # (the background's triangles are not output).
    run_case "atlas upscaled, 4096^2, --materials all" "$th" "$brain" --materials all --spacing 0.062255859375 --no-certify
  fi
done

echo "== graded (--graded, --max-cell default)"
for th in 1 2; do
  run_case "graded atlas slice 256x256, s=1" "$th" "$brain" --label nonzero --spacing 1 --graded --no-certify
  if [ "$quick" = 0 ]; then
    run_case "graded disc, 4096x4096 lattice" "$th" --shape circle:0,0,2047 --spacing 1 --graded --no-certify
    run_case "graded atlas upscaled, 4096x4096" "$th" "$brain" --label nonzero --spacing 0.062255859375 --graded --no-certify
    run_case "graded flower, 4096x4096 lattice" "$th" --shape flower:0,0,1500,500,40 --spacing 1 --graded --no-certify
    # Multi-material graded: the finest band along every interface; the
    # materials are sampled at every lattice point, as uniform.
    run_case "graded atlas 4096^2, --materials all" "$th" "$brain" --materials all --spacing 0.062255859375 --graded --no-certify
    # 16 times the lattice area, 4 times the boundary: the graded mesher's
    # work follows the boundary (the uniform mesh would have 540 M triangles).
    run_case "graded disc, 16384x16384 lattice" "$th" --shape circle:0,0,8191 --spacing 1 --graded --no-certify
  fi
done
echo "== the fan rule (--diagonal fan) against the separating rule (certified floor 18.4349 deg against 15 deg)"
for th in 1 2; do
  for rule in separating fan; do
    run_case "atlas slice s=1, $rule" "$th" "$brain" --label nonzero --spacing 1 --diagonal "$rule" --no-certify
    run_case "graded atlas slice, $rule" "$th" "$brain" --label nonzero --spacing 1 --graded --diagonal "$rule" --no-certify
    if [ "$quick" = 0 ]; then
      run_case "atlas 4096^2, $rule" "$th" "$brain" --label nonzero --spacing 0.062255859375 --diagonal "$rule" --no-certify
      run_case "graded atlas 4096^2, $rule" "$th" "$brain" --label nonzero --spacing 0.062255859375 --graded --diagonal "$rule" --no-certify
    fi
  done
done

if [ "$quick" = 0 ]; then
  # The same meshing repeated in one process (library use): memory freed by
  # one run is reused by the next, so these exclude the first-touch page
  # faults that a fresh process pays (~2 us a page on this VM) — the
  # difference between the two blocks is mostly that.  Peak memory here is
  # the process's over all ten runs (the heap keeps freed pages, and
  # fragmentation can hold up to two runs' worth).
  echo "== graded, warm: ten runs in one process (--repeat 10), the fastest"
  warm_case "graded disc, 4096x4096, warm" 1 --shape circle:0,0,2047 --spacing 1 --graded --no-certify
  warm_case "graded atlas upscaled, warm" 1 "$brain" --label nonzero --spacing 0.062255859375 --graded --no-certify
  warm_case "graded flower, 4096x4096, warm" 1 --shape flower:0,0,1500,500,40 --spacing 1 --graded --no-certify
  warm_case "graded disc, 16384x16384, warm" 1 --shape circle:0,0,8191 --spacing 1 --graded --no-certify
fi

if [ "$quick" = 0 ]; then
  echo "== triangle counts, uniform and graded (separating rule, --max-cell default), markdown"
  abdomen="$root/mesher/examples/abdomen_axial_z040_labels16.pgm"
  count() { "$exe" mesh "$@" --quiet --no-certify --report "$tmp/c.json" && field triangles "$tmp/c.json"; }
  echo "| case | uniform | graded | uniform / graded |"
  echo "|---|---:|---:|---:|"
  while IFS='|' read -r name args; do
    # shellcheck disable=SC2086
    u=$(count $args)
    # shellcheck disable=SC2086
    g=$(count $args --graded)
    awk -v n="$name" -v u="$u" -v g="$g" 'BEGIN { printf "| %s | %d | %d | %.1f |\n", n, u, g, u / g }'
  done <<EOF_CASES
brain slice (all labels), s = 1|$brain --label nonzero --spacing 1
brain slice (all labels), s = 2|$brain --label nonzero --spacing 2
brain slice (all labels), s = 4|$brain --label nonzero --spacing 4
abdomen slice (all labels), s = 1|$abdomen --label nonzero --spacing 1
abdomen slice (all labels), s = 2|$abdomen --label nonzero --spacing 2
abdomen slice (all labels), s = 4|$abdomen --label nonzero --spacing 4
ellipse 400 x 250, s = 1|--shape ellipse:0,0,400,250 --spacing 1
annulus 200 / 400, s = 1|--shape annulus:0,0,200,400 --spacing 1
flower r = 300 + 100 cos 5θ, s = 1|--shape flower:0,0,300,100,5 --spacing 1
disc on a 1024 x 1024 lattice|--shape circle:0,0,511 --spacing 1
EOF_CASES

  echo "== cost of the certification (per-square bounds, certified_min_angle, --verify), 1 thread"
  run_case "disc 4096, --no-certify" 1 --shape circle:0,0,2047 --spacing 1 --no-certify
  run_case "disc 4096, certified, --no-verify" 1 --shape circle:0,0,2047 --spacing 1 --no-verify
  run_case "disc 4096, certified and verified (default)" 1 --shape circle:0,0,2047 --spacing 1
  run_case "atlas upscaled, --no-certify" 1 "$brain" --label nonzero --spacing 0.062255859375 --no-certify
  run_case "atlas upscaled, certified and verified" 1 "$brain" --label nonzero --spacing 0.062255859375
fi
