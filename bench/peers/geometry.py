#!/usr/bin/python3
"""Boundary curves of the benchmark domains for the peers of scripts/bench-peers.sh.

usage: geometry.py DOMAIN H POLY GEO
  DOMAIN: ellipse:a,b | annulus:r1,r2 | flower:a,b,k  (centred at the origin)
  POLY: for the CGAL driver: 'loop N' then N lines 'x y' per closed curve,
        'hole x y' for a point inside each hole; vertices on the exact curve,
        about H apart along it.
  GEO:  for gmsh: the same curves as closed splines through points H/4 apart
        (mesh size H), Frontal-Delaunay (Mesh.Algorithm 6), one thread.
"""
import math
import sys


def curves(spec):
    kind, args = spec.split(":")
    v = [float(x) for x in args.split(",")]
    if kind == "ellipse":
        a, b = v
        return [lambda t: (a * math.cos(t), b * math.sin(t))], []
    if kind == "annulus":
        r1, r2 = v
        return [lambda t: (r2 * math.cos(t), r2 * math.sin(t)),
                lambda t: (r1 * math.cos(t), r1 * math.sin(t))], [(0.0, 0.0)]
    if kind == "flower":
        a, b, k = v
        r = lambda t: a + b * math.cos(k * t)
        return [lambda t: (r(t) * math.cos(t), r(t) * math.sin(t))], []
    raise SystemExit(f"unknown domain {spec}")


def sample(c, step):
    """Points on curve c (t in [0, 2 pi)) about `step` apart in arc length."""
    fine = [c(2 * math.pi * i / 20000) for i in range(20001)]
    length = sum(math.dist(fine[i], fine[i + 1]) for i in range(20000))
    n = max(8, math.ceil(length / step))
    # Equal arc-length spacing by inverting the cumulative length.
    cum = [0.0]
    for i in range(20000):
        cum.append(cum[-1] + math.dist(fine[i], fine[i + 1]))
    out, j = [], 0
    for m in range(n):
        target = length * m / n
        while cum[j + 1] < target:
            j += 1
        u = (target - cum[j]) / (cum[j + 1] - cum[j])
        out.append(c(2 * math.pi * (j + u) / 20000))
    return out


def main():
    spec, h, poly, geo = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4]
    cs, holes = curves(spec)
    with open(poly, "w") as o:
        for c in cs:
            pts = sample(c, h)
            o.write(f"loop {len(pts)}\n")
            o.writelines(f"{x!r} {y!r}\n" for x, y in pts)
        for x, y in holes:
            o.write(f"hole {x!r} {y!r}\n")
    with open(geo, "w") as o:
        o.write(f"h = {h!r};\nMesh.Algorithm = 6;\nGeneral.NumThreads = 1;\nMesh.MeshSizeFromCurvature = 0;\n")
        p = 1
        loops = []
        for ci, c in enumerate(cs):
            pts = sample(c, h / 4)
            first = p
            for x, y in pts:
                o.write(f"Point({p}) = {{{x!r}, {y!r}, 0, h}};\n")
                p += 1
            ids = ", ".join(str(i) for i in range(first, p)) + f", {first}"
            o.write(f"Spline({ci + 1}) = {{{ids}}};\nCurve Loop({ci + 1}) = {{{ci + 1}}};\n")
            loops.append(str(ci + 1))
        o.write(f"Plane Surface(1) = {{{', '.join(loops)}}};\nPhysical Surface(1) = {{1}};\n")


if __name__ == "__main__":
    main()
