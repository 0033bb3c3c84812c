#!/usr/bin/python3
"""Accuracy per unknown: FEniCSx Poisson with a smooth manufactured solution on
warpmesh meshes and on Gmsh Frontal-Delaunay meshes of the same domains.

    -Δu = f in Ω,  u = u_ex on ∂Ω,   u_ex = sin(3x + 1) cos(2y − 1/2) + x y / 2

on the unit disc (`circle:0,0,1`) and a five-petal flower (`flower:0,0,0.8,0.25,5`,
r = 0.8 + 0.25 cos 5θ), P1 and P2 Lagrange elements (Debian's dolfinx 0.5).
Every mesh covers the polygon whose boundary vertices lie on the curve; the
errors ‖u_h − u_ex‖ (L²) and |u_h − u_ex| (H¹ seminorm) are measured on that
polygon with a quadrature of degree 2p + 3, so the boundary's approximation is
part of the error for every mesher alike.

Meshers ("series"):
  warpmesh            warpmesh mesh --shape S --spacing h
  warpmesh-optimize   ... --optimize
  warpmesh-graded     ... --graded --max-size 4h
  warpmesh-rhombic    ... --lattice rhombic (certified by proofs/rhombic_*.cert: the
                      60° rhombic lattice, equilateral interior, edge h)
  warpmesh-rhombic-optimize  ... --lattice rhombic --optimize
  warpmesh-rhombic-maxmin    ... --lattice rhombic --diagonal maxmin
  gmsh-frontal        Gmsh (python API) Frontal-Delaunay (Mesh.Algorithm 6),
                      the curve as a spline through points h/4 apart, size h
  warpmesh-before     (--before EXE) another warpmesh executable, e.g. the
                      build before the union-jack interior
  cgal                (--cgal EXE) bench/peers/cgal_mesh2.cpp, criteria
                      B = 0.125 and size √2·h on the polyline of the curve
                      (points h apart)

The comparison is at equal unknowns: log(error) against log(unknowns) is
interpolated linearly between a series' sizes, evaluated at the reference
series' (Gmsh's) unknowns inside the overlap, and the ratio warpmesh ÷ Gmsh is
reported as its range and its geometric mean over those points.  Fitted
constants: error ≈ C · N^(−r) at the nominal rate r (P1: L² 1, H¹ 1/2; P2:
L² 3/2, H¹ 1 — in unknowns N, i.e. h², h, h³, h²), C the geometric mean of
error · N^r; and the free least-squares slope.

usage: accuracy.py --warpmesh EXE [--sizes 1e3,3e3,...] [--domains disc,flower]
                   [--degrees 1,2] [--series a,b,...] [--before EXE] [--cgal EXE]
                   [--json OUT] [--workdir DIR]
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

DOMAINS = {
    "disc": {"shape": "circle:0,0,1", "area": math.pi,
             "curve": lambda t: (math.cos(t), math.sin(t))},
    "flower": {"shape": "flower:0,0,0.8,0.25,5", "area": math.pi * (0.8 ** 2 + 0.25 ** 2 / 2),
               "curve": lambda t: ((0.8 + 0.25 * math.cos(5 * t)) * math.cos(t),
                                   (0.8 + 0.25 * math.cos(5 * t)) * math.sin(t))},
}
NOMINAL = {(1, "L2"): 1.0, (1, "H1"): 0.5, (2, "L2"): 1.5, (2, "H1"): 1.0}
REFERENCE = "gmsh-frontal"


def exact_numpy(x):
    return np.sin(3 * x[0] + 1) * np.cos(2 * x[1] - 0.5) + 0.5 * x[0] * x[1]


def exact_ufl(x):
    import ufl
    return ufl.sin(3 * x[0] + 1) * ufl.cos(2 * x[1] - 0.5) + 0.5 * x[0] * x[1]


# ---- meshes: (points (n, 2), triangles (m, 3)) ----------------------------------
def warpmesh_mesh(exe, domain, h, extra, workdir):
    import meshio
    out = os.path.join(workdir, f"w-{domain}-{h:.6g}-{abs(hash(tuple(extra))) % 10**8}.vtu")
    subprocess.run([exe, "mesh", "--shape", DOMAINS[domain]["shape"], "--spacing", repr(h), "-o", out, "--quiet"] + extra,
                   check=True)
    m = meshio.read(out)
    os.remove(out)
    return m.points[:, :2].astype(np.float64), m.get_cells_type("triangle").astype(np.int64)


def curve_points(curve, step):
    """Points on the closed curve about `step` apart in arc length."""
    n_fine = 20000
    fine = np.array([curve(2 * math.pi * i / n_fine) for i in range(n_fine + 1)])
    seg = np.hypot(*np.diff(fine, axis=0).T)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    n = max(8, math.ceil(cum[-1] / step))
    s = cum[-1] * np.arange(n) / n
    t = np.interp(s, cum, 2 * math.pi * np.arange(n_fine + 1) / n_fine)
    return [curve(v) for v in t]


def gmsh_mesh(domain, h):
    import gmsh
    gmsh.initialize(["-noenv"], readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NumThreads", 1)
        gmsh.option.setNumber("Mesh.Algorithm", 6)  # Frontal-Delaunay
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.model.add(domain)
        pts = [gmsh.model.geo.addPoint(x, y, 0, h) for x, y in curve_points(DOMAINS[domain]["curve"], h / 4)]
        spline = gmsh.model.geo.addSpline(pts + [pts[0]])
        surface = gmsh.model.geo.addPlaneSurface([gmsh.model.geo.addCurveLoop([spline])])
        gmsh.model.geo.synchronize()
        gmsh.model.addPhysicalGroup(2, [surface], 1)
        gmsh.model.mesh.generate(2)
        points, tris = gmsh_cells(2, 3)
    finally:
        gmsh.finalize()
    return points[:, :2].copy(), tris


def gmsh_cells(element_type, corners):
    """(points (n, 3), cells (m, corners) 0-based) of the current Gmsh model's
    elements of `element_type` (2: triangles, 4: tetrahedra), only the nodes
    they use (Gmsh's geometry points are left out)."""
    import gmsh
    tags, coords, _ = gmsh.model.mesh.getNodes()
    _, elem_nodes = gmsh.model.mesh.getElementsByType(element_type)
    index = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    cells = index[elem_nodes.astype(np.int64)].reshape(-1, corners)
    used = np.unique(cells)
    remap = np.full(len(tags), -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return coords.reshape(-1, 3)[used].copy(), remap[cells]


def cgal_mesh(exe, domain, h, workdir):
    poly = os.path.join(workdir, f"c-{domain}-{h:.6g}.poly")
    with open(poly, "w") as o:
        pts = curve_points(DOMAINS[domain]["curve"], h)
        o.write(f"loop {len(pts)}\n")
        o.writelines(f"{x!r} {y!r}\n" for x, y in pts)
    out = os.path.join(workdir, f"c-{domain}-{h:.6g}.off")
    subprocess.run([exe, poly, repr(h), out], check=True, stdout=subprocess.DEVNULL)
    with open(out) as f:
        words = f.read().split()
    assert words[0] == "OFF"
    nv, nt = int(words[1]), int(words[2])
    v = np.array(words[4:4 + 3 * nv], dtype=np.float64).reshape(nv, 3)[:, :2]
    t = np.array(words[4 + 3 * nv:4 + 3 * nv + 4 * nt], dtype=np.int64).reshape(nt, 4)[:, 1:]
    return v, t


def spacing_for(series, domain, n):
    """The mesh size that gives about n vertices: the lattice spacing (n ≈ A/h²),
    the equilateral edge (n ≈ 2A/(√3 h²): other meshers and the rhombic
    lattice, whose edges are h); graded meshes are sized by their
    finest spacing, which they share with the plain series."""
    area = DOMAINS[domain]["area"]
    if series.startswith("warpmesh") and "rhombic" not in series:
        return math.sqrt(area / n)
    return math.sqrt(2 * area / (math.sqrt(3) * n))


def make_mesh(series, domain, n, opts, workdir):
    h = spacing_for(series, domain, n)
    if series == "warpmesh":
        return warpmesh_mesh(opts.warpmesh, domain, h, [], workdir)
    if series == "warpmesh-optimize":
        return warpmesh_mesh(opts.warpmesh, domain, h, ["--optimize"], workdir)
    if series == "warpmesh-graded":
        return warpmesh_mesh(opts.warpmesh, domain, h, ["--graded", "--max-size", repr(4 * h)], workdir)
    if series == "warpmesh-rhombic":
        return warpmesh_mesh(opts.warpmesh, domain, h, ["--lattice", "rhombic"], workdir)
    if series == "warpmesh-rhombic-optimize":
        return warpmesh_mesh(opts.warpmesh, domain, h, ["--lattice", "rhombic", "--optimize"], workdir)
    if series == "warpmesh-rhombic-maxmin":
        return warpmesh_mesh(opts.warpmesh, domain, h, ["--lattice", "rhombic", "--diagonal", "maxmin"], workdir)
    if series == "warpmesh-before":
        return warpmesh_mesh(opts.before, domain, h, [], workdir)
    if series == REFERENCE:
        return gmsh_mesh(domain, h)
    if series == "cgal":
        return cgal_mesh(opts.cgal, domain, h, workdir)
    raise SystemExit(f"unknown series {series}")


# ---- the solve --------------------------------------------------------------------
def solve(points, triangles, degree):
    """(unknowns, L² error, H¹ seminorm error) of the P`degree` solution."""
    import ufl
    from dolfinx import fem
    from dolfinx import mesh as dmesh
    from dolfinx.fem.petsc import LinearProblem
    from mpi4py import MPI

    domain = dmesh.create_mesh(MPI.COMM_SELF, triangles, points, ufl.Mesh(ufl.VectorElement("Lagrange", "triangle", 1)))
    V = fem.FunctionSpace(domain, ("Lagrange", degree))
    x = ufl.SpatialCoordinate(domain)
    u_ex = exact_ufl(x)
    u, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    f = -ufl.div(ufl.grad(u_ex))
    domain.topology.create_connectivity(1, 2)
    facets = dmesh.exterior_facet_indices(domain.topology)
    u_bc = fem.Function(V)
    u_bc.interpolate(exact_numpy)
    bc = fem.dirichletbc(u_bc, fem.locate_dofs_topological(V, 1, facets))
    dx = ufl.dx(metadata={"quadrature_degree": 2 * degree + 3})
    problem = LinearProblem(ufl.inner(ufl.grad(u), ufl.grad(v)) * dx, f * v * dx, bcs=[bc],
                            petsc_options={"ksp_type": "cg", "pc_type": "hypre", "ksp_rtol": 1e-12, "ksp_max_it": 2000})
    uh = problem.solve()
    e = uh - u_ex
    l2 = fem.assemble_scalar(fem.form(e * e * dx))
    h1 = fem.assemble_scalar(fem.form(ufl.inner(ufl.grad(e), ufl.grad(e)) * dx))
    unknowns = V.dofmap.index_map.size_global * V.dofmap.index_map_bs
    return unknowns, math.sqrt(l2), math.sqrt(h1)


# ---- comparison --------------------------------------------------------------------
def ratio_at_equal_unknowns(series, reference):
    """warpmesh ÷ reference at the reference's unknowns inside the overlap:
    (min, geometric mean, max, number of points), or None.  Arguments: lists
    of (unknowns, error), log-log interpolated."""
    xs = np.log([n for n, _ in series])
    ys = np.log([e for _, e in series])
    order = np.argsort(xs)
    xs, ys = xs[order], ys[order]
    r = [math.exp(np.interp(math.log(n), xs, ys) - math.log(e))
         for n, e in reference if xs[0] - 1e-12 <= math.log(n) <= xs[-1] + 1e-12]
    if not r:
        return None
    return min(r), math.exp(np.mean(np.log(r))), max(r), len(r)


def fitted(rows, degree, norm):
    n = np.array([r[0] for r in rows], dtype=float)
    e = np.array([r[1] for r in rows], dtype=float)
    rate = NOMINAL[(degree, norm)]
    c = math.exp(np.mean(np.log(e * n ** rate)))
    slope = -np.polyfit(np.log(n), np.log(e), 1)[0] if len(n) > 1 else float("nan")
    return c, slope


def run(opts, log=sys.stderr):
    results = {}  # (domain, series, degree) -> list of [vertices, unknowns, L2, H1, seconds]
    with tempfile.TemporaryDirectory(dir=opts.workdir) as work:
        for domain in opts.domains:
            for series in opts.series:
                for n in opts.sizes:
                    t0 = time.time()
                    pts, tris = make_mesh(series, domain, n, opts, work)
                    for degree in opts.degrees:
                        t1 = time.time()
                        unknowns, l2, h1 = solve(pts, tris, degree)
                        row = [len(pts), unknowns, l2, h1, round(time.time() - t1, 2)]
                        results.setdefault((domain, series, degree), []).append(row)
                        print(f"{domain:7s} {series:18s} P{degree} vertices {len(pts):7d} unknowns {unknowns:8d} "
                              f"L2 {l2:.4e} H1 {h1:.4e} ({time.time() - t0:.1f} s)", file=log, flush=True)
    return results


def summary(results, opts):
    """The ratios to the reference and the fitted constants, as a dict."""
    out = {"ratios": [], "fits": []}
    for domain in opts.domains:
        for degree in opts.degrees:
            ref = results.get((domain, REFERENCE, degree))
            for series in opts.series:
                rows = results[(domain, series, degree)]
                for k, norm in ((2, "L2"), (3, "H1")):
                    c, slope = fitted([(r[1], r[k]) for r in rows], degree, norm)
                    out["fits"].append({"domain": domain, "series": series, "degree": degree, "norm": norm,
                                        "C": c, "slope": slope})
                    if ref is None or series == REFERENCE:
                        continue
                    rr = ratio_at_equal_unknowns([(r[1], r[k]) for r in rows], [(r[1], r[k]) for r in ref])
                    if rr:
                        out["ratios"].append({"domain": domain, "series": series, "degree": degree, "norm": norm,
                                              "min": rr[0], "mean": rr[1], "max": rr[2], "points": rr[3]})
    return out


def print_tables(s, file=sys.stdout):
    print(f"\nerror ratio at equal unknowns, ÷ {REFERENCE} (min – max, geometric mean; points):", file=file)
    print("| domain | series | P | L² | H¹ |\n|---|---|---|---|---|", file=file)
    key = {}
    for r in s["ratios"]:
        key.setdefault((r["domain"], r["series"], r["degree"]), {})[r["norm"]] = r
    for (d, se, p), v in key.items():
        cell = lambda r: f"{r['min']:.3f}–{r['max']:.3f} ({r['mean']:.3f}; {r['points']})" if r else "—"
        print(f"| {d} | {se} | {p} | {cell(v.get('L2'))} | {cell(v.get('H1'))} |", file=file)
    print("\nfitted constants, error ≈ C·N^(−r) at the nominal rate r (free slope in parentheses):", file=file)
    print("| domain | series | P | C (L²) | C (H¹) |\n|---|---|---|---|---|", file=file)
    key = {}
    for r in s["fits"]:
        key.setdefault((r["domain"], r["series"], r["degree"]), {})[r["norm"]] = r
    for (d, se, p), v in key.items():
        print(f"| {d} | {se} | {p} | {v['L2']['C']:.4g} ({v['L2']['slope']:.3f}) | {v['H1']['C']:.4g} ({v['H1']['slope']:.3f}) |",
              file=file)


def parse(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--warpmesh", default=os.environ.get("WARPMESH_EXE", "warpmesh"))
    ap.add_argument("--sizes", default="1e3,3e3,1e4,3e4,1e5,3e5")
    ap.add_argument("--domains", default="disc,flower")
    ap.add_argument("--degrees", default="1,2")
    ap.add_argument("--series", default=None)
    ap.add_argument("--before", default=None, help="another warpmesh executable: the series warpmesh-before")
    ap.add_argument("--cgal", default=None, help="the CGAL driver (bench/peers/cgal_mesh2.cpp): the series cgal")
    ap.add_argument("--json", default=None)
    ap.add_argument("--workdir", default=None)
    o = ap.parse_args(argv)
    o.sizes = [int(float(x)) for x in o.sizes.split(",")]
    o.domains = o.domains.split(",")
    o.degrees = [int(x) for x in o.degrees.split(",")]
    if o.series is None:
        o.series = ["warpmesh", "warpmesh-optimize", "warpmesh-graded", REFERENCE]
        if o.before:
            o.series.insert(0, "warpmesh-before")
        if o.cgal:
            o.series.append("cgal")
    else:
        o.series = o.series.split(",")
    return o


def main(argv=None):
    logging.disable(logging.INFO)  # the form compiler's build log
    opts = parse(sys.argv[1:] if argv is None else argv)
    results = run(opts)
    s = summary(results, opts)
    print_tables(s)
    if opts.json:
        with open(opts.json, "w") as f:
            json.dump({"results": {"|".join(map(str, k)): v for k, v in results.items()}, **s}, f, indent=1)


if __name__ == "__main__":
    main()
