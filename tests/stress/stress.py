#!/usr/bin/python3
"""Random stress of the warpmesh command with an independent validator.

usage: stress.py WARPMESH N SEED [--scaled] [--keep-failures DIR] [--quiet] [--case CASE_SEED]
                 [--focus-optimize | --focus-materials]

--scaled multiplies N by WARPMESH_TEST_SCALE (CTest: a quarter under the
sanitizers); --case reruns the one case of that seed (printed with a failure)
and keeps its files in the current directory; --focus-optimize draws only
label images with --optimize (saddles; where the optimiser's folds were);
--focus-materials draws only multi-material inputs (--materials, --shapes)
with --optimize.

Draws N random inputs over every option of `warpmesh mesh` (label images with
--label or --materials, grayscale fields with --iso, analytic shapes and CSG,
--shapes, --graded with --grading/--max-size/--max-cell/--max-size-of,
--optimize, --diagonal separating|maxmin|fan, non-dyadic spacings), runs the
command, reads the written .vtu back with meshio and checks it with code of its
own (nothing here comes from the mesher):

  * conformity: every edge in one or two triangles, traversed both ways when
    in two; every triangle counter-clockwise with positive area;
  * no overlaps: the angles at an interior vertex sum to 360 deg and at a
    boundary vertex to at most 360; no two boundary edges meet except at a
    shared end; no boundary vertex inside a triangle that does not have it;
  * boundary loops closed (in-degree = out-degree); interface chains (edges
    between different regions) end only on the boundary or at junctions;
  * tags: the regions are the requested labels / shape tags;
  * areas: within perimeter x (spacing-derived width) of the exact area —
    pixel counts for label images, the bilinear field's super-level set for
    grayscale images (sampled), the shapes' areas (closed forms, or a fine
    sampling of our own point-in-shape test for CSG and flowers);
  * sizes: longest edge <= --max-size, and per tag <= --max-size-of;
  * angles: every triangle's measured angles within the report's
    certified [min_angle_deg, max_angle_deg], and >= its certified_min_angle;
  * --optimize: the measured minimum angle is >= the unoptimised mesh's;
    with --materials, no label's area error against its pixel count is
    larger than the unoptimised mesh's.

A refusal (exit 1, a message on stderr, no output file) is accepted for
inputs the generator knows may be refused (empty regions, a --max-size below
sqrt(5) spacing); any other exit is a failure.
Exit status: 0 when every case passes, 1 otherwise; one line per failure.
"""
import json
import math
import os
import random
import shutil
import subprocess
import sys
import tempfile

import numpy as np
import meshio


# ----------------------------------------------------------------- inputs

def write_pgm(path, img, maxval):
    h, w = img.shape
    with open(path, "w") as f:
        f.write(f"P2\n{w} {h}\n{maxval}\n")
        for row in img:
            f.write(" ".join(str(int(v)) for v in row) + "\n")


def random_labels(rng, w, h):
    """A label image: a background 0 and a few blobs, with salt (saddles)."""
    nlab = rng.randint(1, 4)
    img = np.zeros((h, w), dtype=np.int64)
    yy, xx = np.mgrid[0:h, 0:w]
    for _ in range(rng.randint(1, 5)):
        cx, cy = rng.uniform(0, w), rng.uniform(0, h)
        rx, ry = rng.uniform(1.5, w / 1.5), rng.uniform(1.5, h / 1.5)
        img[((xx - cx) / rx) ** 2 + ((yy - cy) / ry) ** 2 <= 1] = rng.randint(1, nlab)
    salt = rng.choice([0.03, 0.1, 0.2] if FOCUS else [0, 0, 0.03, 0.1])
    if salt:
        m = np.array([[rng.random() < salt for _ in range(w)] for _ in range(h)])
        img[m] = [rng.randint(0, nlab) for _ in range(int(m.sum()))]
    if rng.random() < 0.15:  # a checkerboard patch: saddles everywhere
        x0, y0 = rng.randint(0, w - 3), rng.randint(0, h - 3)
        for y in range(y0, min(h, y0 + 4)):
            for x in range(x0, min(w, x0 + 4)):
                img[y, x] = nlab if (x + y) % 2 else 0
    return img


def random_field(rng, w, h):
    yy, xx = np.mgrid[0:h, 0:w].astype(float)
    f = np.zeros((h, w))
    for _ in range(rng.randint(1, 5)):
        cx, cy, r = rng.uniform(0, w), rng.uniform(0, h), rng.uniform(1.5, max(w, h) / 2)
        f += rng.uniform(-1, 1) * np.exp(-((xx - cx) ** 2 + (yy - cy) ** 2) / (2 * r * r))
    f = (f - f.min()) / max(f.max() - f.min(), 1e-9)
    return np.round(f * 255).astype(np.int64)


class Shape:
    """Our own point-in-shape test (vectorised), area and box of a shape."""

    def __init__(self, kind, args=(), parts=()):
        self.kind, self.args, self.parts = kind, args, parts

    def spec(self):
        if self.parts:
            return f"{self.kind}({self.parts[0].spec()};{self.parts[1].spec()})"
        return self.kind + ":" + ",".join(repr(round(a, 5)) if isinstance(a, float) else str(a) for a in self.args)

    def inside(self, x, y):
        k, a = self.kind, [float(v) for v in self.args]
        if k == "circle":
            return (x - a[0]) ** 2 + (y - a[1]) ** 2 < a[2] ** 2
        if k == "ellipse":
            return ((x - a[0]) / a[2]) ** 2 + ((y - a[1]) / a[3]) ** 2 < 1
        if k == "annulus":
            d2 = (x - a[0]) ** 2 + (y - a[1]) ** 2
            return (d2 > a[2] ** 2) & (d2 < a[3] ** 2)
        if k == "rect":
            return (x > a[0]) & (x < a[2]) & (y > a[1]) & (y < a[3])
        if k == "flower":
            r = np.hypot(x - a[0], y - a[1])
            return r < a[2] + a[3] * np.cos(self.args[4] * np.arctan2(y - a[1], x - a[0]))
        p, q = self.parts[0].inside(x, y), self.parts[1].inside(x, y)
        return p | q if k == "union" else p & q if k == "intersect" else p & ~q

    def box(self):
        k, a = self.kind, self.args
        if k in ("circle", "annulus"):
            r = a[2] if k == "circle" else a[3]
            return (a[0] - r, a[1] - r, a[0] + r, a[1] + r)
        if k == "ellipse":
            return (a[0] - a[2], a[1] - a[3], a[0] + a[2], a[1] + a[3])
        if k == "flower":
            r = a[2] + abs(a[3])
            return (a[0] - r, a[1] - r, a[0] + r, a[1] + r)
        if k == "rect":
            return tuple(a)
        b1, b2 = self.parts[0].box(), self.parts[1].box()
        return (min(b1[0], b2[0]), min(b1[1], b2[1]), max(b1[2], b2[2]), max(b1[3], b2[3]))

    def exact_area(self):
        k, a = self.kind, self.args
        if k == "circle":
            return math.pi * a[2] ** 2
        if k == "ellipse":
            return math.pi * a[2] * a[3]
        if k == "annulus":
            return math.pi * (a[3] ** 2 - a[2] ** 2)
        if k == "rect":
            return (a[2] - a[0]) * (a[3] - a[1])
        if k == "flower":
            return math.pi * (a[2] ** 2 + a[3] ** 2 / 2)
        return None

    def perimeter(self):
        b = self.box()
        if self.parts:
            return self.parts[0].perimeter() + self.parts[1].perimeter()
        if self.kind == "annulus":
            return 2 * math.pi * (self.args[2] + self.args[3])
        if self.kind == "flower":
            return 2 * math.pi * (self.args[2] + abs(self.args[3]) * self.args[4])
        return 2 * ((b[2] - b[0]) + (b[3] - b[1])) * (math.pi / 4 if self.kind in ("circle", "ellipse") else 1)


def random_shape(rng, depth=0):
    if depth < 2 and rng.random() < 0.3:
        op = rng.choice(["union", "intersect", "diff"])
        a = random_shape(rng, depth + 1)
        b = random_shape(rng, depth + 1)
        return Shape(op, parts=(a, b))
    k = rng.choice(["circle", "circle", "ellipse", "annulus", "rect", "rect", "flower"])
    cx, cy = rng.uniform(-10, 10), rng.uniform(-10, 10)
    if k == "circle":
        return Shape(k, (cx, cy, rng.uniform(2, 9)))
    if k == "ellipse":
        return Shape(k, (cx, cy, rng.uniform(2, 9), rng.uniform(2, 9)))
    if k == "annulus":
        r1 = rng.uniform(1.5, 5)
        return Shape(k, (cx, cy, r1, r1 + rng.uniform(2, 5)))
    if k == "flower":
        a = rng.uniform(3, 8)
        return Shape(k, (cx, cy, a, rng.uniform(-0.3, 0.3) * a, rng.randint(1, 6)))
    w, h = rng.uniform(3, 16), rng.uniform(3, 16)
    return Shape(k, (cx, cy, cx + w, cy + h))


def sampled_area(inside, box, n=700):
    x0, y0, x1, y1 = box
    xs = np.linspace(x0, x1, n, endpoint=False) + (x1 - x0) / (2 * n)
    ys = np.linspace(y0, y1, n, endpoint=False) + (y1 - y0) / (2 * n)
    X, Y = np.meshgrid(xs, ys)
    return float(inside(X, Y).mean()) * (x1 - x0) * (y1 - y0)


def bilinear_above(img, iso, below, sub=6):
    """Area of {bilinear image > iso} (or < iso) over [0, w-1] x [0, h-1], sampled."""
    h, w = img.shape
    f = img.astype(float)
    u = (np.arange(sub) + 0.5) / sub
    U, V = np.meshgrid(u, u)
    total = 0.0
    a, b, c, d = f[:-1, :-1], f[:-1, 1:], f[1:, :-1], f[1:, 1:]
    for du, dv in zip(U.ravel(), V.ravel()):
        val = a * (1 - du) * (1 - dv) + b * du * (1 - dv) + c * (1 - du) * dv + d * du * dv
        total += float(((val < iso) if below else (val > iso)).sum())
    return total / (sub * sub)


# ----------------------------------------------------------------- cases

def spacing_of(rng, lo, hi):
    s = rng.uniform(lo, hi)
    return round(s, 4) if abs(math.log2(round(s, 4))) % 1 > 1e-9 else s + 0.0137


def graded_opts(rng, s, materials):
    """--graded and its size options; returns (args, max_size or None, max_size_of dict)."""
    if rng.random() < 0.55:
        return [], None, {}
    args, ms, mso = ["--graded"], None, {}
    if rng.random() < 0.4:
        args += ["--grading", f"{rng.uniform(1.1, 2.0):.4g}"]
    if rng.random() < 0.4:
        ms = round(rng.uniform(2.3, 14) * s, 4)
        args += ["--max-size", repr(ms)]
    if rng.random() < 0.15:
        args += ["--max-cell", str(rng.choice([1, 2, 4, 8]))]
    return args, ms, mso


FOCUS = None  # --focus-optimize: label images with --optimize only (where folds were found)
FOCUS_MATERIALS = None  # --focus-materials: --materials and --shapes with --optimize only


def make_case(rng, work):
    """(argv after the input, expectation dict)."""
    kind = rng.choices(["label", "materials", "gray", "shape", "shapes"], [30, 15, 15, 30, 10])[0]
    if FOCUS:
        kind = "label"
    if FOCUS_MATERIALS:
        kind = rng.choices(["materials", "shapes"], [75, 25])[0]
    e = {"kind": kind, "may_refuse": True}
    argv = []
    if kind in ("label", "materials", "gray"):
        w, h = rng.randint(6, 26), rng.randint(6, 26)
        path = os.path.join(work, "in.pgm")
        if kind == "gray":
            img = random_field(rng, w, h)
            write_pgm(path, img, 255)
            iso = rng.uniform(40, 215)
            below = rng.random() < 0.3
            argv = [path, "--iso", f"{iso:.3f}"] + (["--inside", "below"] if below else [])
            e["area"] = bilinear_above(img, iso, below)
            e["perimeter"] = 2 * (w + h) + 4 * math.sqrt(w * h)
            e["tags"] = {1}
            e["domain"] = (0, 0, w - 1, h - 1)
        else:
            img = random_labels(rng, w, h)
            write_pgm(path, img, max(int(img.max()), 1))
            labels = sorted(set(int(v) for v in img.ravel()))
            argv = [path]
            if kind == "label":
                pick = rng.choice(["nonzero", "one", "two"])
                chosen = [l for l in labels if l] if pick == "nonzero" else rng.sample(labels, min(len(labels), 1 if pick == "one" else 2))
                argv += ["--label", "nonzero" if pick == "nonzero" else ",".join(map(str, chosen))]
                mask = np.isin(img, chosen)
                e["areas"] = {None: float(mask.sum())}
                e["tags"] = set(chosen) | {1}  # the label value when one, else 1
                e["mask_perimeter"] = {None: perimeter_px(mask)}
            else:
                mats = [l for l in labels if l]
                if not mats:
                    mats = [1]
                pick = rng.random() < 0.5
                chosen = mats if pick else rng.sample(mats, rng.randint(1, len(mats)))
                argv += ["--materials", "all" if pick else ",".join(map(str, chosen))]
                keep = rng.random() < 0.4
                argv += ["--background", "keep" if keep else "drop"]
                e["areas"] = {l: float((img == l).sum()) for l in chosen}
                e["mask_perimeter"] = {l: perimeter_px(img == l) for l in chosen}
                e["tags"] = set(chosen) | ({0} if keep else set())
                e["materials"] = True
            e["domain"] = (0, 0, w - 1, h - 1)
        s = 1.0 if (FOCUS or FOCUS_MATERIALS) and rng.random() < 0.5 else spacing_of(rng, 0.35, 1.6)
    elif kind == "shape":
        sh = random_shape(rng)
        argv = ["--shape", sh.spec()]
        e["area"] = sh.exact_area()
        if e["area"] is None:
            b = sh.box()
            e["area"] = sampled_area(sh.inside, b)
        e["perimeter"] = sh.perimeter()
        e["tags"] = {1}
        b = sh.box()
        s = spacing_of(rng, 0.15, 0.03 * max(b[2] - b[0], b[3] - b[1]) + 0.2)
    else:
        n = rng.randint(1, 3)
        shapes = [random_shape(rng, 2) for _ in range(n)]
        tags = rng.sample(range(1, 9), n)
        argv = ["--shapes", ";".join(f"{t}={sh.spec()}" for t, sh in zip(tags, shapes))]
        keep = rng.random() < 0.3
        argv += ["--background", "keep" if keep else "drop"]
        e["tags"] = set(tags) | ({0} if keep else set())
        e["materials"] = True
        # A later shape wins: tag t's region is its shape minus the later ones.
        b = shapes[0].box()
        for sh in shapes[1:]:
            c = sh.box()
            b = (min(b[0], c[0]), min(b[1], c[1]), max(b[2], c[2]), max(b[3], c[3]))
        e["areas"], e["mask_perimeter"] = {}, {}
        for i, t in enumerate(tags):
            later = shapes[i + 1:]
            e["areas"][t] = sampled_area(lambda x, y, i=i, later=later: shapes[i].inside(x, y) & ~np.any([l.inside(x, y) for l in later] or [np.zeros_like(x, dtype=bool)], axis=0), b)
            e["mask_perimeter"][t] = sum(sh.perimeter() for sh in shapes)
        s = spacing_of(rng, 0.2, 0.03 * max(b[2] - b[0], b[3] - b[1]) + 0.25)
    e["spacing"] = s
    argv += ["--spacing", repr(s)]
    g, ms, mso = graded_opts(rng, s, e.get("materials"))
    argv += g
    e["max_size"] = ms
    if e.get("materials") and g and rng.random() < 0.4:
        t = rng.choice(sorted(e["tags"] - {0}) or [1])
        h = round(rng.uniform(2.3, 10) * s, 4)
        argv += ["--max-size-of", f"{t}={h!r}"]
        e["max_size_of"] = {t: h}
    rule = rng.choices(["separating", "maxmin", "fan"], [60, 20, 20])[0]
    argv += ["--diagonal", rule]
    if FOCUS or FOCUS_MATERIALS or rng.random() < 0.5:
        argv.append("--optimize")
        e["optimize"] = True
    return argv, e


def perimeter_px(mask):
    m = mask.astype(np.int8)
    return float(np.abs(np.diff(m, axis=0)).sum() + np.abs(np.diff(m, axis=1)).sum() +
                 m[0].sum() + m[-1].sum() + m[:, 0].sum() + m[:, -1].sum())


# ----------------------------------------------------------------- validator

def read_vtu(path):
    m = meshio.read(path)
    tri = None
    for block in m.cells:
        if block.type == "triangle":
            tri = block.data if tri is None else np.vstack([tri, block.data])
    region = np.concatenate([d for d in m.cell_data["region"]]).astype(int)
    cert = None
    if "certified_min_angle" in m.cell_data:
        cert = np.concatenate(m.cell_data["certified_min_angle"]).astype(float)
    return m.points[:, :2].astype(float), tri.astype(np.int64), region, cert


def tri_areas(P, T):
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    return 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))


def angles_deg(P, T):
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]

    def ang(p, q, r):
        u, v = q - p, r - p
        return np.degrees(np.arctan2(np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]), (u * v).sum(1)))

    return np.stack([ang(a, b, c), ang(b, c, a), ang(c, a, b)], axis=1)


def segs_meet(p, q, r, s):
    def o(a, b, c):
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])

    def on(a, b, c):
        return min(a[0], b[0]) <= c[0] <= max(a[0], b[0]) and min(a[1], b[1]) <= c[1] <= max(a[1], b[1])

    o1, o2, o3, o4 = o(p, q, r), o(p, q, s), o(r, s, p), o(r, s, q)
    if ((o1 > 0 > o2) or (o1 < 0 < o2)) and ((o3 > 0 > o4) or (o3 < 0 < o4)):
        return True
    return (o1 == 0 and on(p, q, r)) or (o2 == 0 and on(p, q, s)) or (o3 == 0 and on(r, s, p)) or (o4 == 0 and on(r, s, q))


def validate(P, T, R, cert, report, e):
    errs = []
    nt = len(T)
    if nt == 0:
        return ["no triangles"]
    a, b, c = P[T[:, 0]], P[T[:, 1]], P[T[:, 2]]
    area2 = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    if (area2 <= 0).any():
        errs.append(f"{int((area2 <= 0).sum())} triangles not counter-clockwise")
    # conformity and orientation
    d = np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]])
    tri_of = np.concatenate([np.arange(nt)] * 3)
    und = np.sort(d, axis=1)
    key = und[:, 0] * (len(P) + 1) + und[:, 1]
    uniq, inv, cnt = np.unique(key, return_inverse=True, return_counts=True)
    if (cnt > 2).any():
        errs.append(f"{int((cnt > 2).sum())} edges in more than two triangles")
    fwd = d[:, 0] < d[:, 1]
    fsum = np.bincount(inv, weights=fwd.astype(float))
    two = cnt == 2
    if (two & (fsum != 1)).any():
        errs.append("interior edges traversed the same way twice")
    bmask = cnt[inv] == 1
    bd = d[bmask]
    outdeg = np.bincount(bd[:, 0], minlength=len(P))
    indeg = np.bincount(bd[:, 1], minlength=len(P))
    if (outdeg != indeg).any():
        errs.append("open boundary loops")
    if len(np.unique(T)) != len(P):
        errs.append("vertices in no triangle")
    if errs:
        return errs
    # angle sums
    ang = angles_deg(P, T)
    asum = np.bincount(T.ravel(), weights=ang.ravel(), minlength=len(P))
    onb = np.zeros(len(P), bool)
    onb[bd.ravel()] = True
    if (np.abs(asum[~onb] - 360) > 1e-6).any():
        errs.append(f"fold: interior vertex angle sums {asum[~onb][np.abs(asum[~onb] - 360) > 1e-6][:3]}")
    if (asum[onb] > 360 + 1e-6).any():
        errs.append("fold: a boundary vertex's angles exceed 360")
    # boundary edges pairwise, boundary vertices in triangles (grid buckets)
    h = float(np.median(np.hypot(*(P[bd[:, 1]] - P[bd[:, 0]]).T))) or 1.0
    buckets = {}
    for k, (u, v) in enumerate(bd):
        x0, x1 = sorted((P[u, 0], P[v, 0]))
        y0, y1 = sorted((P[u, 1], P[v, 1]))
        for i in range(int(math.floor(x0 / h)), int(math.floor(x1 / h)) + 1):
            for j in range(int(math.floor(y0 / h)), int(math.floor(y1 / h)) + 1):
                buckets.setdefault((i, j), []).append(k)
    bad = 0
    for cell, ks in buckets.items():
        for x in range(len(ks)):
            for y in range(x + 1, len(ks)):
                u, v = bd[ks[x]]
                w, z = bd[ks[y]]
                shared = {u, v} & {w, z}
                if len(shared) == 2:
                    bad += 1  # the same boundary edge twice
                elif len(shared) == 1:
                    p = shared.pop()
                    q1 = v if u == p else u
                    q2 = z if w == p else w
                    cr = (P[q1, 0] - P[p, 0]) * (P[q2, 1] - P[p, 1]) - (P[q1, 1] - P[p, 1]) * (P[q2, 0] - P[p, 0])
                    if cr == 0 and np.dot(P[q1] - P[p], P[q2] - P[p]) > 0:
                        bad += 1
                elif segs_meet(P[u], P[v], P[w], P[z]):
                    bad += 1
    if bad:
        errs.append(f"{bad} pairs of boundary edges meet (boundary not simple)")
    bverts = np.unique(bd.ravel())
    cell_of = {}
    for v in bverts:
        cell_of.setdefault((int(math.floor(P[v, 0] / h)), int(math.floor(P[v, 1] / h))), []).append(v)
    lo = np.minimum(np.minimum(a, b), c)
    hi = np.maximum(np.maximum(a, b), c)
    inside = 0
    for t in range(nt):
        i0, j0 = int(math.floor(lo[t, 0] / h)), int(math.floor(lo[t, 1] / h))
        i1, j1 = int(math.floor(hi[t, 0] / h)), int(math.floor(hi[t, 1] / h))
        if (i1 - i0 + 1) * (j1 - j0 + 1) > 400:
            continue
        for i in range(i0, i1 + 1):
            for j in range(j0, j1 + 1):
                for v in cell_of.get((i, j), ()):
                    if v in T[t]:
                        continue
                    x = P[v]
                    A, B, C = P[T[t, 0]], P[T[t, 1]], P[T[t, 2]]
                    o1 = (B[0] - A[0]) * (x[1] - A[1]) - (B[1] - A[1]) * (x[0] - A[0])
                    o2 = (C[0] - B[0]) * (x[1] - B[1]) - (C[1] - B[1]) * (x[0] - B[0])
                    o3 = (A[0] - C[0]) * (x[1] - C[1]) - (A[1] - C[1]) * (x[0] - C[0])
                    if o1 >= 0 and o2 >= 0 and o3 >= 0:
                        inside += 1
    if inside:
        errs.append(f"fold: {inside} boundary vertices inside triangles that do not have them")
    # interface chains: end on the boundary or at a junction
    rdiff = two & True
    rf = np.zeros(len(uniq), np.int64) - 1
    rb = np.zeros(len(uniq), np.int64) - 1
    rf[inv[fwd]] = R[tri_of[fwd]]
    rb[inv[~fwd]] = R[tri_of[~fwd]]
    iface = two & (rf != rb)
    if iface.any():
        ie = np.stack([uniq[iface] // (len(P) + 1), uniq[iface] % (len(P) + 1)], axis=1)
        deg = np.bincount(ie.ravel(), minlength=len(P))
        dangling = (deg == 1) & ~onb
        if dangling.any():
            errs.append(f"{int(dangling.sum())} interface chains end inside the mesh")
    # tags
    tags = set(int(t) for t in np.unique(R))
    if not tags <= e["tags"]:
        errs.append(f"regions {sorted(tags)} not within the expected {sorted(e['tags'])}")
    # areas
    s = e["spacing"]
    tri_area = area2 / 2
    if "areas" in e:
        for lab, want in e["areas"].items():
            got = float(tri_area.sum()) if lab is None else float(tri_area[R == lab].sum())
            per = e["mask_perimeter"][lab]
            tol = per * (s + 0.5) + 4 * s * s + 1.0
            if abs(got - want) > tol:
                errs.append(f"area of {lab}: {got:.4f}, expected {want:.4f} +- {tol:.3f}")
    elif "area" in e:
        got = float(tri_area.sum())
        tol = e["perimeter"] * s + 4 * s * s + (1.0 if e["kind"] == "gray" else 0.0)
        if e["kind"] == "gray":
            tol += e["perimeter"] * 0.5
        if abs(got - e["area"]) > tol:
            errs.append(f"area {got:.4f}, expected {e['area']:.4f} +- {tol:.3f}")
    # sizes
    L = np.sqrt(np.stack([((b - a) ** 2).sum(1), ((c - b) ** 2).sum(1), ((a - c) ** 2).sum(1)], 1).max(1))
    if e.get("max_size") and (L > e["max_size"] * (1 + 1e-9)).any():
        errs.append(f"longest edge {L.max():.5g} > --max-size {e['max_size']}")
    for t, hmax in (e.get("max_size_of") or {}).items():
        if (L[R == t] > hmax * (1 + 1e-9)).any():
            errs.append(f"longest edge of tag {t}: {L[R == t].max():.5g} > --max-size-of {hmax}")
    # certified bounds
    cb = report.get("certified") if report else None
    tol = 1e-7
    mn, mx = ang.min(1), ang.max(1)
    if cb:
        if mn.min() < cb["min_angle_deg"] - tol:
            errs.append(f"false certified.min_angle_deg {cb['min_angle_deg']}: measured {mn.min():.6f}")
        if mx.max() > cb["max_angle_deg"] + tol:
            errs.append(f"false certified.max_angle_deg {cb['max_angle_deg']}: measured {mx.max():.6f}")
    if cert is not None and (mn < cert - tol).any():
        errs.append(f"{int((mn < cert - tol).sum())} triangles below their certified_min_angle")
    return errs


# ----------------------------------------------------------------- driver

def run(warpmesh, argv, out, report):
    cmd = [warpmesh, "mesh"] + argv + ["-o", out, "--report", report, "--quiet", "--threads", "1"]
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    return p.returncode, p.stderr


def one_case(warpmesh, rng, work, i):
    argv, e = make_case(rng, work)
    out, rep = os.path.join(work, "out.vtu"), os.path.join(work, "report.json")
    for f in (out, rep):
        if os.path.exists(f):
            os.remove(f)
    code, err = run(warpmesh, argv, out, rep)
    if code != 0:
        if code in (1, 2) and e["may_refuse"] and err.strip() and not os.path.exists(out):
            return "refused", argv, [err.strip().splitlines()[-1][:90]]
        return "fail", argv, [f"exit {code}: {err.strip()[:300]}"]
    report = json.load(open(rep))
    P, T, R, cert = read_vtu(out)
    errs = validate(P, T, R, cert, report, e)
    if e.get("optimize") and not errs:
        plain = [a for a in argv if a != "--optimize"]
        code2, err2 = run(warpmesh, plain, out, rep)
        if code2 == 0:
            P2, T2, R2, _ = read_vtu(out)
            before, after = angles_deg(P2, T2).min(), angles_deg(P, T).min()
            if after < before - 1e-9:
                errs.append(f"--optimize lowered the minimum angle {before:.6f} -> {after:.6f}")
            if e["kind"] == "materials":  # no label's area error grows (pixel counts)
                for lab, want in e["areas"].items():
                    err_before = abs(tri_areas(P2, T2)[R2 == lab].sum() - want)
                    err_after = abs(tri_areas(P, T)[R == lab].sum() - want)
                    if err_after > err_before + 1e-9 * max(want, 1):
                        errs.append(f"--optimize made label {lab}'s area error {err_before:.6g} -> {err_after:.6g}")
        else:
            errs.append(f"without --optimize: exit {code2}: {err2.strip()[:200]}")
    return ("fail" if errs else "ok"), argv, errs


def main():
    args = sys.argv[1:]
    if len(args) < 3:
        print(__doc__)
        return 2
    warpmesh, n, seed = args[0], int(args[1]), int(args[2])
    if "--scaled" in args:  # WARPMESH_TEST_SCALE, as tests/support.hpp reads it
        try:
            scale = float(os.environ.get("WARPMESH_TEST_SCALE", "1"))
        except ValueError:
            scale = 1.0
        n = max(1, int(n * (scale if 0 < scale <= 1 else 1.0) + 0.5))
    keep = args[args.index("--keep-failures") + 1] if "--keep-failures" in args else None
    quiet = "--quiet" in args
    global FOCUS, FOCUS_MATERIALS
    FOCUS = "--focus-optimize" in args
    FOCUS_MATERIALS = "--focus-materials" in args
    if "--case" in args:  # one case, its files kept here
        case_seed = int(args[args.index("--case") + 1])
        status, argv, errs = one_case(warpmesh, random.Random(case_seed), os.getcwd(), 0)
        print(status, "warpmesh mesh " + " ".join(argv))
        for m in errs:
            print("    " + m)
        return 0 if status != "fail" else 1
    rng = random.Random(seed)
    counts = {"ok": 0, "refused": 0, "fail": 0}
    reasons = {}  # refusal message -> count
    work = tempfile.mkdtemp(prefix="warpmesh-stress-")
    try:
        for i in range(n):
            case_seed = rng.randrange(1 << 30)
            status, argv, errs = one_case(warpmesh, random.Random(case_seed), work, i)
            counts[status] += 1
            if status == "refused":
                reasons[errs[0]] = reasons.get(errs[0], 0) + 1
            if status == "fail":
                print(f"FAIL case {i} (seed {case_seed}): warpmesh mesh {' '.join(argv)}", flush=True)
                for m in errs:
                    print("    " + m, flush=True)
                if keep:
                    os.makedirs(keep, exist_ok=True)
                    if os.path.exists(os.path.join(work, "in.pgm")):
                        shutil.copy(os.path.join(work, "in.pgm"), os.path.join(keep, f"case{case_seed}.pgm"))
            elif not quiet and (i + 1) % 100 == 0:
                print(f"{i + 1} cases: {counts}", flush=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    for why, k in sorted(reasons.items(), key=lambda x: -x[1])[:8]:
        print(f"  refused {k:5d}: {why}")
    print(f"stress: {n} cases, seed {seed}: {counts['ok']} valid, {counts['refused']} refused cleanly, "
          f"{counts['fail']} failures", flush=True)
    return 1 if counts["fail"] else 0


if __name__ == "__main__":
    sys.exit(main())
