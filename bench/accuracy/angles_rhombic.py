#!/usr/bin/python3
"""Angles of the rhombic lattice on random level sets (sampling in
double precision, NOT a proof): random smooth shapes at random offsets, meshed
with `warpmesh mesh --lattice rhombic` and, for comparison, on the square
lattice, under the separating and the max-min rule; per (lattice, rule) the
worst minimum and maximum angle over all meshes, the worst shapes, and the
same restricted to shapes whose smallest feature is at least `--resolved`
spacings (radius of curvature), where the flat theorem's 12-point stencils
are flat in practice.

usage: angles_rhombic.py --warpmesh EXE [--count N] [--seed S] [--resolved R]
"""
import argparse
import json
import math
import os
import random
import subprocess
import sys
import tempfile


def random_shape(rng):
    """(shape spec, smallest radius of curvature in spacings) at spacing 1."""
    cx, cy = rng.uniform(-50, 50), rng.uniform(-50, 50)
    kind = rng.choice(["circle", "ellipse", "flower", "annulus"])
    if kind == "circle":
        r = math.exp(rng.uniform(math.log(1.5), math.log(40)))
        return f"circle:{cx:.6f},{cy:.6f},{r:.6f}", r
    if kind == "ellipse":
        a, b = (math.exp(rng.uniform(math.log(2), math.log(40))) for _ in range(2))
        return f"ellipse:{cx:.6f},{cy:.6f},{a:.6f},{b:.6f}", min(a, b) ** 2 / max(a, b)
    if kind == "annulus":
        r1 = math.exp(rng.uniform(math.log(2), math.log(30)))
        r2 = r1 + math.exp(rng.uniform(math.log(2), math.log(30)))
        return f"annulus:{cx:.6f},{cy:.6f},{r1:.6f},{r2:.6f}", min(r1, (r2 - r1) / 2)
    a = math.exp(rng.uniform(math.log(6), math.log(40)))
    k = rng.randint(3, 7)
    b = a * rng.uniform(0.05, 0.25)
    # r = a + b cos kθ: smallest radius of curvature at a petal tip or a trough, roughly (a - b)... bounded below by
    # the tip's (a + b)^2 / (a + b + b k^2) (the curvature of the polar curve at θ = 0)
    rc = (a + b) ** 2 / (a + b + b * k * k)
    return f"flower:{cx:.6f},{cy:.6f},{a:.6f},{b:.6f},{k}", rc


def run(exe, shape, lattice, rule, work):
    rep = os.path.join(work, "r.json")
    cmd = [exe, "mesh", "--shape", shape, "--spacing", "1", "--diagonal", rule, "--report", rep, "--quiet", "--no-certify"]
    if lattice == "rhombic":
        cmd += ["--lattice", "rhombic"]
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        return None
    with open(rep) as f:
        d = json.load(f)
    return d["min_angle_deg"], d["max_angle_deg"], d["triangles"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--warpmesh", required=True)
    ap.add_argument("--count", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=33)
    ap.add_argument("--resolved", type=float, default=4.0)
    o = ap.parse_args(argv)
    rng = random.Random(o.seed)
    shapes = [random_shape(rng) for _ in range(o.count)]
    res = {}
    with tempfile.TemporaryDirectory() as work:
        for lattice in ("square", "rhombic"):
            for rule in ("separating", "maxmin"):
                rows = []
                for spec, rc in shapes:
                    r = run(o.warpmesh, spec, lattice, rule, work)
                    if r:
                        rows.append((r[0], r[1], r[2], spec, rc))
                res[(lattice, rule)] = rows
    print(f"{o.count} random shapes (seed {o.seed}), spacing 1; resolved: smallest radius of curvature >= {o.resolved}")
    print("| lattice | rule | meshes | triangles | worst min angle (all / resolved) | worst max angle (all / resolved) | "
          "meshes with min < 18.43° (all / resolved) | meshes with max > 143.13° (all / resolved) |")
    print("|---|---|---:|---:|---|---|---|---|")
    for (lattice, rule), rows in res.items():
        good = [r for r in rows if r[4] >= o.resolved]
        tri = sum(r[2] for r in rows)
        mn = lambda rs: min((r[0] for r in rs), default=float("nan"))
        mx = lambda rs: max((r[1] for r in rs), default=float("nan"))
        lo = lambda rs: sum(r[0] < 18.4349 for r in rs)
        hi = lambda rs: sum(r[1] > 143.1302 for r in rs)
        print(f"| {lattice} | {rule} | {len(rows)} | {tri} | {mn(rows):.3f}° / {mn(good):.3f}° | {mx(rows):.3f}° / {mx(good):.3f}° | "
              f"{lo(rows)} / {lo(good)} | {hi(rows)} / {hi(good)} |")
    for (lattice, rule), rows in res.items():
        if lattice != "rhombic":
            continue
        print(f"\nrhombic, {rule}: worst minimum angles")
        for r in sorted(rows)[:5]:
            print(f"  {r[0]:.3f}° (max {r[1]:.3f}°)  {r[3]}  (radius of curvature {r[4]:.2f})")
        print(f"rhombic, {rule}: worst maximum angles")
        for r in sorted(rows, key=lambda r: -r[1])[:5]:
            print(f"  {r[1]:.3f}° (min {r[0]:.3f}°)  {r[3]}  (radius of curvature {r[4]:.2f})")


if __name__ == "__main__":
    main()
