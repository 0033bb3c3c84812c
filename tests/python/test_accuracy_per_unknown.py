"""Accuracy per unknown (issue 33), the small version of
bench/accuracy/accuracy.py (`scripts/bench.sh --accuracy` runs the full one):
FEniCSx P1 Poisson with a smooth manufactured solution on the unit disc and
the five-petal flower, on warpmesh meshes and on Gmsh Frontal-Delaunay meshes,
compared at equal unknowns (log-log interpolation of the error against the
unknowns, at Gmsh's sizes).

What it pins: the union-jack interior (generic_square.hpp, union_jack).  With
every interior square split along the same diagonal the P1 L² error at equal
unknowns was 1.55–1.63× Gmsh's and H¹ 1.20–1.21× (the issue's figures); the
asserted bounds below are the measured ratios of this test's sizes plus a
margin of about 3 % (docs/performance.md, "Accuracy per unknown").
"""
import os
import sys

import pytest

from conftest import require

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "bench", "accuracy"))

# Gmsh at these vertex counts; warpmesh over a slightly wider range, so that
# every Gmsh size is inside warpmesh's interpolation range.
GMSH_SIZES = [2000, 6000, 18000]
WARPMESH_SIZES = [1500, 4500, 13500, 24000]

# Upper bounds on warpmesh ÷ Gmsh Frontal-Delaunay, P1, the largest ratio over
# the compared sizes: measured (2026-12-03) disc L² 1.400–1.408, H¹
# 1.211–1.213; flower L² 1.278–1.321, H¹ 1.179–1.185; bounds about 3 % above.
# Issue 33's targets (L² ≤ 1.3, H¹ ≤ 1.12) are not reached: see
# docs/performance.md, "Accuracy per unknown".  With the old AD interior the
# same sizes give disc L² ≈ 1.6 and H¹ ≈ 1.27 (above these bounds).
BOUNDS = {"disc": {"L2": 1.45, "H1": 1.25}, "flower": {"L2": 1.36, "H1": 1.22}}
# The rhombic lattice (`--lattice rhombic`, certified by proofs/rhombic_*.cert:
# equilateral interior), the same sizes: measured (2026-12-04) disc L²
# 1.006–1.018, H¹ 1.002–1.007; flower L² 1.039–1.061, H¹ 1.003–1.009 —
# issue 33's targets and near parity; bounds about 3 % above.
RHOMBIC_BOUNDS = {"disc": {"L2": 1.05, "H1": 1.04}, "flower": {"L2": 1.09, "H1": 1.04}}


class Opts:
    warpmesh = os.environ.get("WARPMESH_EXE", "warpmesh")


@pytest.fixture(scope="module")
def errors(tmp_path_factory):
    require("dolfinx", "python3-dolfinx")
    require("gmsh", "python3-gmsh")
    import accuracy
    work = str(tmp_path_factory.mktemp("accuracy"))
    out = {}
    for domain in BOUNDS:
        for series, sizes in (("warpmesh", WARPMESH_SIZES), ("warpmesh-rhombic", WARPMESH_SIZES),
                              (accuracy.REFERENCE, GMSH_SIZES)):
            rows = []
            for n in sizes:
                pts, tris = accuracy.make_mesh(series, domain, n, Opts, work)
                rows.append(accuracy.solve(pts, tris, 1))
            out[(domain, series)] = rows
    return out


@pytest.mark.parametrize("series", ["warpmesh", "warpmesh-rhombic"])
@pytest.mark.parametrize("domain", sorted(BOUNDS))
@pytest.mark.parametrize("norm", ["L2", "H1"])
def test_p1_error_at_equal_unknowns_against_gmsh_frontal_delaunay(errors, domain, norm, series):
    import accuracy
    k = 1 if norm == "L2" else 2
    ours = [(r[0], r[k]) for r in errors[(domain, series)]]
    ref = [(r[0], r[k]) for r in errors[(domain, accuracy.REFERENCE)]]
    ratio = accuracy.ratio_at_equal_unknowns(ours, ref)
    assert ratio is not None and ratio[3] == len(GMSH_SIZES), (ours, ref)
    print(f"{domain} P1 {norm}: {series} / gmsh-frontal {ratio[0]:.3f}-{ratio[2]:.3f}")
    bounds = RHOMBIC_BOUNDS if series == "warpmesh-rhombic" else BOUNDS
    assert ratio[2] <= bounds[domain][norm], (ratio, ours, ref)


def hypotenuse_directions(path):
    """Per hypotenuse length (rounded), the number of right isosceles
    triangles whose hypotenuse runs along (1, 1) and along (1, -1)."""
    meshio = require("meshio", "python3-meshio")
    import numpy as np
    m = meshio.read(path)
    p, t = m.points[:, :2], m.get_cells_type("triangle")
    counts = {}
    for tri in t:
        x = p[tri]
        e = [x[(k + 1) % 3] - x[k] for k in range(3)]
        n = [float(np.hypot(*v)) for v in e]
        k = int(np.argmax(n))
        dx, dy = e[k]
        legs = sorted(n)[:2]
        if abs(abs(dx) - abs(dy)) > 1e-9 * n[k] or abs(legs[0] - legs[1]) > 1e-9 * n[k]:
            continue  # not an unwarped right isosceles triangle of the lattice's axes
        c = counts.setdefault(round(n[k], 6), [0, 0])
        c[0 if dx * dy > 0 else 1] += 1
    return counts


@pytest.mark.parametrize("graded", [False, True])
def test_interior_has_no_preferred_direction(tmp_path, graded):
    """The failure of issue 33: every interior square split along AD, every
    interior hypotenuse along (1, 1).  With the union-jack pattern both
    directions occur equally often (up to the boundary), among the finest
    squares and, in graded meshes, among the coarse leaves of every level."""
    from conftest import run_warpmesh
    out = tmp_path / "m.vtu"
    args = ["--shape", "circle:0,0,40", "--spacing", "1", "-o", out]
    if graded:
        args += ["--graded", "--max-size", "16"]
    run_warpmesh(args, tmp_path)
    counts = hypotenuse_directions(str(out))
    sizes = [h for h, c in counts.items() if sum(c) >= 40]
    assert len(sizes) >= (3 if graded else 1), counts
    for h in sizes:
        a, b = counts[h]
        assert min(a, b) >= 0.4 * (a + b), (h, counts[h])
