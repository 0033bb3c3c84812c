#!/usr/bin/python3
"""One quality evaluator for every mesher of scripts/bench-peers.sh.

usage: evaluate.py DOMAIN MESHFILE
  DOMAIN: ellipse:a,b | annulus:r1,r2 | flower:a,b,k   (centred at the origin)
  MESHFILE: anything meshio reads (.vtu, .msh, .off)

Prints one JSON object: triangles, min/max angle, mean minimum angle (degrees),
and the boundary distance: the largest distance from the mesh's boundary edges
(edges of exactly one triangle) to the exact curve, sampled at 9 points per
edge as |f| / |grad f| with the level set f of warpmesh's shapes and a
central-difference gradient — the measure warpmesh's own report uses
(one-sided: mesh boundary to curve).
"""
import json
import sys

import meshio
import numpy as np


def level_set(spec):
    kind, args = spec.split(":")
    v = [float(x) for x in args.split(",")]
    if kind == "ellipse":
        a, b = v
        return lambda x, y: min(a, b) * (np.sqrt((x / a) ** 2 + (y / b) ** 2) - 1)
    if kind == "annulus":
        r1, r2 = v
        return lambda x, y: np.maximum(r1 - np.hypot(x, y), np.hypot(x, y) - r2)
    if kind == "flower":
        a, b, k = v
        return lambda x, y: np.hypot(x, y) - (a + b * np.cos(k * np.arctan2(y, x)))
    raise SystemExit(f"unknown domain {spec}")


def main():
    spec, path = sys.argv[1], sys.argv[2]
    f = level_set(spec)
    m = meshio.read(path)
    pts = m.points[:, :2].astype(float)
    tris = np.concatenate([c.data for c in m.cells if c.type == "triangle"])
    # Drop vertices no triangle uses (gmsh keeps its geometry points).
    a, b, c = pts[tris[:, 0]], pts[tris[:, 1]], pts[tris[:, 2]]

    def angle(p, q, r):
        u, v = q - p, r - p
        cr = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
        return np.degrees(np.arctan2(cr, (u * v).sum(axis=1)))

    ang = np.stack([angle(a, b, c), angle(b, c, a), angle(c, a, b)], axis=1)
    mins, maxs = ang.min(axis=1), ang.max(axis=1)

    edges = np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]])
    key = np.sort(edges, axis=1)
    uniq, counts = np.unique(key, axis=0, return_counts=True)
    bnd = uniq[counts == 1]
    p, q = pts[bnd[:, 0]], pts[bnd[:, 1]]
    h = 1e-6
    worst = 0.0
    for s in np.linspace(0, 1, 9):
        x = p[:, 0] + s * (q[:, 0] - p[:, 0])
        y = p[:, 1] + s * (q[:, 1] - p[:, 1])
        v = f(x, y)
        gx = (f(x + h, y) - f(x - h, y)) / (2 * h)
        gy = (f(x, y + h) - f(x, y - h)) / (2 * h)
        worst = max(worst, float(np.max(np.abs(v) / np.hypot(gx, gy))))
    print(json.dumps({
        "triangles": int(len(tris)),
        "min_angle": float(mins.min()),
        "max_angle": float(maxs.max()),
        "mean_min_angle": float(mins.mean()),
        "boundary_distance": worst,
    }))


if __name__ == "__main__":
    main()
