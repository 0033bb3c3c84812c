#!/usr/bin/python3
"""Rotation sensitivity of the error (issue 33): the P1 Poisson errors of
accuracy.py on one warpmesh mesh of the unit disc, rotated about the origin
by angles spanning the lattice's period (square: 90°, rhombic: 60°) — the
disc is invariant, so this rotates the lattice against the solution.  Prints
per series and size the errors per angle and max/min over the angles.

usage: rotations.py --warpmesh EXE [--sizes 1e4,3e4] [--steps 8]
"""
import argparse
import logging
import math
import os
import sys
import tempfile

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import accuracy  # noqa: E402

PERIOD = {"warpmesh": 90, "warpmesh-rhombic": 60}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--warpmesh", required=True)
    ap.add_argument("--sizes", default="1e4,3e4")
    ap.add_argument("--steps", type=int, default=8)
    o = ap.parse_args(argv)
    logging.disable(logging.INFO)
    with tempfile.TemporaryDirectory() as work:
        for series, period in PERIOD.items():
            for n in (int(float(x)) for x in o.sizes.split(",")):
                pts, tris = accuracy.make_mesh(series, "disc", n, o, work)
                rows = []
                for k in range(o.steps + 1):
                    a = period * k / o.steps
                    c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
                    rows.append((a,) + accuracy.solve(pts @ np.array([[c, s], [-s, c]]), tris, 1))
                l2, h1 = [r[2] for r in rows], [r[3] for r in rows]
                print(f"{series} {rows[0][1]} unknowns: max/min over rotations L2 {max(l2) / min(l2):.3f} "
                      f"H1 {max(h1) / min(h1):.3f}; L2 at 0° {l2[0]:.4e}, largest at {rows[int(np.argmax(l2))][0]:g}°")
                print("   " + " ".join(f"{r[0]:g}°: {r[2]:.4e}/{r[3]:.4e}" for r in rows), flush=True)


if __name__ == "__main__":
    main()
