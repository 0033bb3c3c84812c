#!/usr/bin/python3
"""Accuracy of 3D meshes (issue 48, item 4): FEniCSx P1 Poisson on the unit ball,

    -Δu = f in the ball,  u = 0 on the mesh's boundary,  u = (1 − r²) cos(x) e^(y/2)

(the problem of tests/python/test_poisson3d.py; Debian's dolfinx 0.5), on

  warpmesh          warpmesh mesh3d --shape sphere:0,0,0,1 --spacing h
  warpmesh-graded   ... --graded --max-size 4h (cells capped at 4h cubes)
  gmsh              Gmsh's Python API: an OpenCASCADE sphere, Delaunay 3D
                    (Mesh.Algorithm3D 1), Mesh.MeshSizeMin = Max = h

Every mesh covers the polyhedron whose boundary vertices lie on the sphere, so
the boundary's approximation is part of the error for every mesher alike; the
error is integrated at quadrature degree 4 (degree 6 gives the same digits).

Two reports:
  --rates H,H,...   the graded series at these spacings: vertices, tetrahedra,
                    L² error, the rate between neighbouring spacings, and the
                    share of the ball's volume in capped cells (longest edge
                    above 3h, i.e. cells of 4h cubes) — why the rate is below 2
                    until that share is close to 1 (docs/3d.md).
  --compare         every series at its --spacings-SERIES; the L² error against
                    the number of vertices, and warpmesh ÷ Gmsh at equal
                    vertices (log-log interpolation at Gmsh's vertex counts inside
                    the overlap, bench/accuracy/accuracy.py's rule).

usage: accuracy3d.py --warpmesh EXE (--rates H,... | --compare) [--json OUT] [--workdir DIR]
"""
import argparse
import json
import logging
import math
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "..", "..", "tests", "python"))

from accuracy import gmsh_cells, ratio_at_equal_unknowns  # noqa: E402
from conftest import ball_error, read_xdmf  # noqa: E402

SERIES = ("warpmesh", "warpmesh-graded", "gmsh")
# Spacings of --compare, chosen so that the warpmesh series cover Gmsh's
# vertex counts (about 4 000 … 250 000).
SPACINGS = {"warpmesh": [0.15, 0.1, 0.07, 0.05, 0.035, 0.03],
            "warpmesh-graded": [0.141, 0.1, 0.07, 0.05, 0.035, 0.025, 0.0177],
            "gmsh": [0.1, 0.07, 0.05, 0.035, 0.025]}


def warpmesh_ball(exe, h, graded, workdir):
    """(dolfinx mesh, its boundary facets) of warpmesh's ball at spacing h, read
    from XDMF as the tests read it."""
    stem = os.path.join(workdir, f"ball-{h:.6g}{'-graded' if graded else ''}")
    extra = ["--graded", "--max-size", repr(4 * h)] if graded else []
    subprocess.run([exe, "mesh3d", "--shape", "sphere:0,0,0,1", "--spacing", repr(h), "-o", stem + ".xdmf",
                    "--quiet", *extra], check=True)
    mesh, _, facets = read_xdmf(stem)
    for suffix in (".xdmf", ".h5", "_facets.xdmf", "_facets.h5"):
        os.remove(stem + suffix)
    return mesh, facets.indices[facets.values == 1]


def gmsh_ball(h):
    """(dolfinx mesh, its boundary facets) of Gmsh's Delaunay ball of size h."""
    import gmsh
    import ufl
    from dolfinx import mesh as dmesh
    from mpi4py import MPI
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        for name, value in (("General.Terminal", 0), ("General.NumThreads", 1), ("Mesh.Algorithm3D", 1),
                            ("Mesh.MeshSizeFromCurvature", 0), ("Mesh.MeshSizeExtendFromBoundary", 0),
                            ("Mesh.MeshSizeMin", h), ("Mesh.MeshSizeMax", h)):
            gmsh.option.setNumber(name, value)
        gmsh.model.add("ball")
        gmsh.model.occ.addSphere(0, 0, 0, 1)
        gmsh.model.occ.synchronize()
        gmsh.model.mesh.generate(3)
        points, tets = gmsh_cells(4, 4)
    finally:
        gmsh.finalize()
    mesh = dmesh.create_mesh(MPI.COMM_SELF, tets, points, ufl.Mesh(ufl.VectorElement("Lagrange", "tetrahedron", 1)))
    mesh.topology.create_connectivity(2, 3)
    return mesh, dmesh.exterior_facet_indices(mesh.topology)


def cell_sizes(mesh, h):
    """(the share of the mesh's volume in tetrahedra whose longest edge is above
    3h: the cells of 4h cubes of a graded mesh with --max-size 4h; the longest
    edge of the mesh)."""
    x, cells = mesh.geometry.x, mesh.geometry.dofmap.array.reshape(-1, 4)
    capped = total = longest_edge = 0.0
    for start in range(0, len(cells), 1 << 20):  # in chunks: the finest meshes have ~10 M tetrahedra
        p = x[cells[start:start + (1 << 20)]]
        longest = np.max([np.linalg.norm(p[:, i] - p[:, j], axis=1) for i in range(4) for j in range(i + 1, 4)], axis=0)
        volume = np.abs(np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])) / 6
        capped += volume[longest > 3 * h].sum()
        total += volume.sum()
        longest_edge = max(longest_edge, longest.max())
    return capped / total, longest_edge


def measure(series, h, opts, work):
    """{series, h, vertices, tetrahedra, L2, capped, seconds} of one mesh."""
    t0 = time.time()
    if series == "gmsh":
        mesh, boundary = gmsh_ball(h)
    else:
        mesh, boundary = warpmesh_ball(opts.warpmesh, h, series == "warpmesh-graded", work)
    row = {"series": series, "h": h, "vertices": int(mesh.geometry.x.shape[0]),
           "tetrahedra": int(mesh.topology.index_map(3).size_global), "L2": float(ball_error(mesh, boundary)),
           "capped": float(cell_sizes(mesh, h)[0]) if series == "warpmesh-graded" else None}
    row["seconds"] = round(time.time() - t0, 1)
    print(f"{series:16s} h {h:<8.5g} vertices {row['vertices']:8d} tetrahedra {row['tetrahedra']:9d} "
          f"L2 {row['L2']:.4e} ({row['seconds']} s)", file=sys.stderr, flush=True)
    return row


def print_rates(rows, file=sys.stdout):
    print("\n| h | vertices | tetrahedra | L² error | rate from the previous h | volume in 4h cells |", file=file)
    print("|---:|---:|---:|---:|---:|---:|", file=file)
    for i, r in enumerate(rows):
        rate = "" if i == 0 else f"{math.log(rows[i - 1]['L2'] / r['L2']) / math.log(rows[i - 1]['h'] / r['h']):.2f}"
        print(f"| {r['h']:g} | {r['vertices']} | {r['tetrahedra']} | {r['L2']:.3e} | {rate} | "
              f"{100 * r['capped']:.0f} % |", file=file)


def print_comparison(rows, file=sys.stdout):
    by = {s: [(r["vertices"], r["L2"]) for r in rows if r["series"] == s] for s in SERIES}
    print("\n| series | h | vertices | tetrahedra | L² error |\n|---|---:|---:|---:|---:|", file=file)
    for r in rows:
        print(f"| {r['series']} | {r['h']:g} | {r['vertices']} | {r['tetrahedra']} | {r['L2']:.3e} |", file=file)
    print("\nL² error ratio at equal vertices (min – max, geometric mean; points):", file=file)
    for s, reference in (("warpmesh", "gmsh"), ("warpmesh-graded", "gmsh"), ("warpmesh-graded", "warpmesh")):
        rr = ratio_at_equal_unknowns(by[s], by[reference])
        print(f"  {s} ÷ {reference}: " + (f"{rr[0]:.3f}–{rr[2]:.3f} ({rr[1]:.3f}; {rr[3]})" if rr else "no overlap"),
              file=file)

def main(argv=None):
    logging.disable(logging.INFO)  # the form compiler's build log
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--warpmesh", default=os.environ.get("WARPMESH_EXE", "warpmesh"))
    ap.add_argument("--rates", default=None, help="spacings of the graded series, e.g. 0.05,0.035,0.025")
    ap.add_argument("--compare", action="store_true")
    ap.add_argument("--json", default=None)
    ap.add_argument("--workdir", default=None)
    opts = ap.parse_args(sys.argv[1:] if argv is None else argv)
    if not opts.rates and not opts.compare:
        ap.error("give --rates H,... or --compare")
    out = {}
    with tempfile.TemporaryDirectory(dir=opts.workdir) as work:
        if opts.rates:
            out["rates"] = [measure("warpmesh-graded", float(h), opts, work) for h in opts.rates.split(",")]
            print_rates(out["rates"])
        if opts.compare:
            out["compare"] = [measure(s, h, opts, work) for s in SERIES for h in SPACINGS[s]]
            print_comparison(out["compare"])
    if opts.json:
        with open(opts.json, "w") as f:
            json.dump(out, f, indent=1)


if __name__ == "__main__":
    main()
