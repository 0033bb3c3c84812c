#!/usr/bin/env python3
"""Golden meshes: canonical outputs of the `warpmesh` CLI, pinned in tests/expected/.

    golden.py WARPMESH_EXE              compare every case with tests/expected/NAME.txt
    golden.py WARPMESH_EXE --regenerate rewrite tests/expected/ on purpose
                                        (scripts/regen-golden.sh; commit the diff
                                        with the reason the meshes changed)
    golden.py WARPMESH_EXE --only NAME  one case

Each case runs the CLI as a user would (`warpmesh mesh ARGS -o case.node
--report case.json`), reads the Triangle files back and writes a canonical
text form, independent of vertex numbering and triangle order:

  * vertices sorted by (x, y), written with Python's shortest round-trip repr,
    so equal text means bit-identical doubles;
  * triangles renumbered, each rotated to start at its smallest vertex (the
    orientation is kept: a flipped triangle is a change), then sorted, with
    the region tag;
  * boundary edges renumbered and sorted, with their tags (orientation kept);
  * multi-material meshes only (a .poly with interface segments, tags >= 3):
    the interface edges, each as its two renumbered vertices in increasing
    order with the region tags on its left and on its right, read from the
    two triangles that share it, sorted.  Reading them checks the segments:
    each must be an edge of exactly two triangles of different regions, and
    every edge between two triangles of different regions must be one;
  * the JSON report without timings, memory and the input path.  Report
    numbers are compared to a relative 1e-12 (sums such as the area may be
    reduced in a thread-dependent order); the mesh itself must match exactly.

Only the Python standard library is used.  Exit status 0 when every case
matches, 1 otherwise, with a diff summary per failing case.
"""
import json
import math
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXPECTED = os.path.join(ROOT, "tests", "expected")
DATA = "tests/data"
EX = "mesher/examples"

# name -> arguments to `warpmesh mesh` (paths relative to the repository root).
# Each case says what it pins; where a case pins a fixed bug it is named after it.
CASES = {
    # The basic shapes, the three rules, uniform (the default is the fan rule,
    # issue 50: circle_fan; the separating and maxmin rules by name).
    "circle_separating": ["--shape", "circle:0,0,10", "--diagonal", "separating"],
    "circle_fan": ["--shape", "circle:0,0,10"],
    "circle_maxmin": ["--shape", "circle:0,0,10", "--diagonal", "maxmin"],
    # Boolean shapes with a hole; the cut point of a corner shared by two cut
    # edges (coarse spacing: the boundary turns inside a square).
    "disc_with_hole_s05": ["--shape", "diff(circle:0,0,10;ellipse:2,0,4,2)", "--spacing", "0.5"],
    "annulus_coarse_s2": ["--shape", "annulus:0,0,4,11", "--spacing", "2"],
    # Lattice points exactly on the level set (f = 0 never moves) and a region
    # that is a union of lattice squares.
    "rect_on_lattice": ["--shape", "rect:0,0,10,7"],
    # Threshold mode on real images, both inside directions.
    "corpus_callosum_threshold": [f"{DATA}/CorpusCallosumMeanShape_phi16.pgm", "--iso", "128"],
    "horse_below_s8": [f"{DATA}/horse_binary.pgm", "--iso", "128", "--inside", "below", "--spacing", "8"],
    # Label mode on the atlas slices (the bundled example of scripts/run.sh).
    "brain_wm_label41_s2": [f"{EX}/brain_axial_s128_labels16.pgm", "--label", "41", "--spacing", "2"],
    "abdomen_kidneys_maxmin_s2": [f"{EX}/abdomen_axial_z040_labels16.pgm", "--label", "51,52",
                                  "--spacing", "2", "--diagonal", "maxmin"],
    # Graded meshes: shapes, a label image with a region touching the border
    # (domain_border tags), a cell-size limit, the max-min rule.
    "flower_graded": ["--shape", "flower:0,0,30,8,5", "--graded"],
    "flower_graded_maxmin": ["--shape", "flower:0,0,30,8,5", "--graded", "--diagonal", "maxmin"],
    "ventricle_graded_threshold": [f"{DATA}/VentricleModel.pgm", "--iso", "100", "--graded"],
    "abdomen_nonzero_graded_s2": [f"{DATA}/abdomen_axial_z024_labels16.pgm", "--label", "nonzero",
                                  "--graded", "--spacing", "2"],
    "circle_graded_maxcell4_wide": ["--shape", "circle:0,0,70", "--graded", "--max-cell", "4", "--spacing", "1"],
    # --guarantee flat refines the lattice until every warped square is flat;
    # here it stops at --min-spacing (16 / 16) with non-flat squares left.
    "k1_guarantee_flat_s16": [f"{DATA}/K1_small.pgm", "--iso", "128", "--spacing", "16", "--guarantee", "flat"],
    # Multi-material meshes (--materials, --shapes): every label of an atlas
    # slice with the background dropped; a list of labels (the rest merged into
    # the background); three analytic materials with triple points and the
    # background kept.
    "brain_all_materials_s2": [f"{EX}/brain_axial_s128_labels16.pgm", "--materials", "all", "--spacing", "2"],
    "abdomen_kidneys_materials_s2": [f"{EX}/abdomen_axial_z040_labels16.pgm", "--materials", "51,52",
                                     "--spacing", "2"],
    "three_shapes_materials": ["--shapes", "1=circle:0,0,10;2=circle:6,0,8;3=rect:-2,-2,2,12",
                               "--background", "keep", "--spacing", "0.75", "--diagonal", "separating"],
    # The fan rule with materials (issue 28), the default since issue 50: the
    # same three materials; its certified floor is the fan rule's 18.4349 deg,
    # junction squares included.
    "three_shapes_materials_fan": ["--shapes", "1=circle:0,0,10;2=circle:6,0,8;3=rect:-2,-2,2,12",
                                   "--background", "keep", "--spacing", "0.75"],
    # Graded multi-material meshes: the finest band along every interface,
    # coarse leaves inside each material — every label of the brain slice
    # (background dropped), and the three analytic materials with the
    # background kept and a cell-size limit.
    "brain_all_materials_graded_s2": [f"{EX}/brain_axial_s128_labels16.pgm", "--materials", "all", "--graded",
                                      "--spacing", "2"],
    "three_shapes_materials_graded": ["--shapes", "1=circle:0,0,10;2=circle:6,0,8;3=rect:-2,-2,2,12",
                                      "--background", "keep", "--spacing", "0.5", "--graded", "--max-cell", "8"],
    # Size control of graded multi-material meshes (issue 18: --max-size was
    # ignored there): a global bound (cells of at most 2 squares; 4 without)
    # and a per-material cap (material 1 all finest squares), the background
    # kept.
    "three_shapes_materials_graded_sizes": ["--shapes", "1=circle:0,0,10;2=circle:6,0,8;3=rect:-2,-2,2,12",
                                            "--background", "keep", "--spacing", "0.5", "--graded", "--max-size", "2.5",
                                            "--max-size-of", "1=1.2"],
}

DROP = {"phase_seconds", "total_seconds", "peak_memory_mb", "input", "repeat"}


def run_case(exe, args, tmp):
    out = os.path.join(tmp, "m.node")
    rep = os.path.join(tmp, "m.json")
    cmd = [exe, "mesh", *args, "-o", out, "--report", rep, "--quiet", "--threads", "2"]
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=600)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)} exited {r.returncode}: {r.stderr.strip()}")
    return canonical(os.path.join(tmp, "m"), rep)


def rows(path):
    with open(path) as f:
        lines = [l.split() for l in f if l.strip() and not l.startswith("#")]
    return lines[0], lines[1:]


def canonical(stem, report_path):
    head, node = rows(stem + ".node")
    xy = [(float(r[1]), float(r[2])) for r in node[: int(head[0])]]
    order = sorted(range(len(xy)), key=lambda i: xy[i])
    for a, b in zip(order, order[1:]):
        if xy[a] == xy[b]:
            raise RuntimeError(f"two vertices at {xy[a]}")
    new = [0] * len(xy)
    for k, i in enumerate(order):
        new[i] = k
    head, ele = rows(stem + ".ele")
    tris = []
    for r in ele[: int(head[0])]:
        v = [new[int(x) - 1] for x in r[1:4]]
        s = v.index(min(v))
        v = v[s:] + v[:s]
        tris.append((*v, int(r[4])))
    tris.sort()
    _, poly = rows(stem + ".poly")
    nseg = int(poly[0][0])
    # The boundary edges (tags 1 = level set, 2 = domain border); the .poly's
    # interface segments of multi-material meshes (tags 3, ...) follow them.
    edges = sorted((new[int(r[1]) - 1], new[int(r[2]) - 1], int(r[3])) for r in poly[1 : 1 + nseg]
                   if int(r[3]) in (1, 2))
    segments = [(new[int(r[1]) - 1], new[int(r[2]) - 1]) for r in poly[1 : 1 + nseg] if int(r[3]) not in (1, 2)]
    interfaces = interface_edges(tris, segments) if segments else None
    with open(report_path) as f:
        report = {k: v for k, v in json.load(f).items() if k not in DROP}
    out = ["report " + json.dumps(report, sort_keys=True), f"vertices {len(xy)}"]
    out += [f"{xy[i][0]!r} {xy[i][1]!r}" for i in order]
    out.append(f"triangles {len(tris)}")
    out += [" ".join(map(str, t)) for t in tris]
    out.append(f"boundary {len(edges)}")
    out += [" ".join(map(str, e)) for e in edges]
    if interfaces is not None:
        out.append(f"interfaces {len(interfaces)}")
        out += [" ".join(map(str, e)) for e in interfaces]
    return "\n".join(out) + "\n"


def interface_edges(tris, segments):
    """The interface segments as (a, b, left region, right region), a < b, sorted;
    raises unless they are exactly the edges between triangles of different regions."""
    side = {}  # directed edge (u, v) of a counter-clockwise triangle -> its region (on the left of u -> v)
    for a, b, c, region in tris:
        for u, v in ((a, b), (b, c), (c, a)):
            if (u, v) in side:
                raise RuntimeError(f"edge {u}-{v} in two triangles with the same orientation")
            side[(u, v)] = region
    between = {(u, v) for (u, v), r in side.items() if u < v and (v, u) in side and side[(v, u)] != r}
    got = set()
    for u, v in segments:
        a, b = min(u, v), max(u, v)
        if (a, b) not in between:
            raise RuntimeError(f"interface segment {a}-{b} is not an edge between two triangles of different regions")
        got.add((a, b, side[(a, b)], side[(b, a)]))
    if len(got) != len(segments) or len(got) != len(between):
        raise RuntimeError(f"{len(segments)} interface segments ({len(got)} distinct) for {len(between)} edges "
                           "between triangles of different regions")
    return sorted(got)


def close(a, b):
    """Report values: exact for everything but floats, which agree to 1e-12 relative."""
    if isinstance(a, dict) and isinstance(b, dict):
        return a.keys() == b.keys() and all(close(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(close(x, y) for x, y in zip(a, b))
    if isinstance(a, float) or isinstance(b, float):
        if isinstance(a, bool) or isinstance(b, bool):
            return a == b
        return math.isclose(float(a), float(b), rel_tol=1e-12, abs_tol=1e-300)
    return a == b


def compare(name, got, want):
    """None if equal, else a short description of the first differences."""
    g, w = got.splitlines(), want.splitlines()
    problems = []
    rg, rw = json.loads(g[0][7:]), json.loads(w[0][7:])
    if not close(rg, rw):
        keys = sorted(set(rg) | set(rw))
        diff = [k for k in keys if not close(rg.get(k), rw.get(k))]
        problems.append("report differs in " + ", ".join(f"{k}: {rw.get(k)} -> {rg.get(k)}" for k in diff[:6]))
    if g[1:] != w[1:]:
        n = sum(1 for a, b in zip(g[1:], w[1:]) if a != b) + abs(len(g) - len(w))
        first = next((i for i, (a, b) in enumerate(zip(g, w)) if i and a != b), min(len(g), len(w)))
        problems.append(f"mesh differs in {n} line(s); first at line {first + 1}: "
                        f"expected '{w[first] if first < len(w) else '<end>'}', got '{g[first] if first < len(g) else '<end>'}'")
    return "; ".join(problems) or None


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    exe, rest = os.path.abspath(argv[1]), argv[2:]
    regenerate = "--regenerate" in rest
    names = list(CASES)
    if "--only" in rest:
        names = [rest[rest.index("--only") + 1]]
    failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for name in names:
            path = os.path.join(EXPECTED, name + ".txt")
            try:
                got = run_case(exe, CASES[name], tmp)
            except Exception as e:  # a case that does not run is a failure, never a skip
                print(f"golden: {name}: FAILED to run: {e}")
                failed += 1
                continue
            if regenerate:
                with open(path, "w") as f:
                    f.write(got)
                print(f"golden: {name}: written ({got.count(chr(10))} lines)")
                continue
            if not os.path.exists(path):
                print(f"golden: {name}: FAILED: no {os.path.relpath(path, ROOT)} (scripts/regen-golden.sh)")
                failed += 1
                continue
            with open(path) as f:
                problem = compare(name, got, f.read())
            print(f"golden: {name}: " + ("ok" if problem is None else "FAILED: " + problem))
            failed += problem is not None
    if not regenerate:
        print(f"golden: {len(names) - failed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
