#!/usr/bin/python3
"""Numeric exploration of the 60-degree rhombic lattice's angles over the
generic square's configuration space (sampling in double precision, NOT a
proof; not on the proof path).

The rhombic lattice is the square lattice under P(x, y) = (x + y/2, (√3/2) y)
(mesher/src/mesh2d/uniform/rhombic.hpp).  P keeps every lattice edge's length, so
the configuration space of proofs/README.md ("Configuration space": signs,
slides t in [0, 1/2] along ±x, ±y, the consistency rules) is the same set of
keys and t-boxes, and so is flatness (an affine function of the physical
plane is affine in lattice coordinates).  Only the angles change: they are
measured after P.  This samples every consistent key's t-box (a grid of n
points per warped corner, plus `random` uniform points) and reports, for the
max-min rule and the separating rule in the rhombic metric, the worst minimum
and maximum angle over

  chosen:  both triangles of the chosen diagonal (what a certificate covers),
  emitted: the chosen triangles whose three corners are inside,

on U (every key) and F (the flat-compatible keys of proofs/key_table.txt),
with the worst keys and t.  Usage:

  /usr/bin/python3 prover/tools/explore_rhombic.py [n] [random] [--square | --third-direction]

--square measures the square lattice instead (a check against the certified
bounds: the sampled worst must lie inside them); --third-direction samples a
variant whose front end also warps along the short diagonal
(explore_third_direction).
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from explore_rules import KEYS, TRIS, A, B, C, D, code, grid, positions, sep_forced  # noqa: E402

H = np.sqrt(3) / 2


def to_physical(P, square):
    if square:
        return P
    Q = P.copy()
    Q[..., 0] = P[..., 0] + 0.5 * P[..., 1]
    Q[..., 1] = H * P[..., 1]
    return Q


def tri_cots(p0, p1, p2):
    """(max cot, min cot) over the triangle's angles, (inf, -inf) where not ccw
    (an inverted or degenerate triangle: angle 0 and 180)."""
    pts = [p0, p1, p2]
    cr = (p1[:, 0] - p0[:, 0]) * (p2[:, 1] - p0[:, 1]) - (p1[:, 1] - p0[:, 1]) * (p2[:, 0] - p0[:, 0])
    qmax = np.full(cr.shape, -np.inf)
    qmin = np.full(cr.shape, np.inf)
    ok = cr > 1e-14
    safe = np.where(ok, cr, 1.0)
    for i in range(3):
        o, a, b = pts[i], pts[(i + 1) % 3], pts[(i + 2) % 3]
        dot = (a[:, 0] - o[:, 0]) * (b[:, 0] - o[:, 0]) + (a[:, 1] - o[:, 1]) * (b[:, 1] - o[:, 1])
        qmax = np.maximum(qmax, dot / safe)
        qmin = np.minimum(qmin, dot / safe)
    return np.where(ok, qmax, np.inf), np.where(ok, qmin, -np.inf)


def diag_cots(Q, d):
    a = [tri_cots(Q[:, t[0]], Q[:, t[1]], Q[:, t[2]]) for t in TRIS[d]]
    return np.maximum(a[0][0], a[1][0]), np.minimum(a[0][1], a[1][1]), a


def deg(q):
    return np.degrees(np.arctan2(1, q))


def rule_cots(k, Q):
    """Per rule ("maxmin", "separating"), per triangle set ("chosen": both of
    the chosen diagonal; "emitted": those with three inside corners), the
    (max cot, min cot) at each sample of key k's physical positions Q."""
    inside = [k[c][1] != 0 or k[c][0] <= 0 for c in range(4)]
    qa_max, qa_min, ta = diag_cots(Q, "AD")
    qb_max, qb_min, tb = diag_cots(Q, "BC")
    f = sep_forced(k)
    out = {}
    for rule in ("maxmin", "separating"):
        if rule == "separating" and f is not None:
            bc = np.full(Q.shape[0], f == "BC")
        else:
            bc = qb_max < qa_max  # ties (measure zero off the unit square) to AD
        emax = np.full(Q.shape[0], -np.inf)
        emin = np.full(Q.shape[0], np.inf)
        for d, mask, tr in (("AD", ~bc, ta), ("BC", bc, tb)):
            for t, (tmax, tmin) in zip(TRIS[d], tr):
                if all(inside[c] for c in t):
                    emax = np.where(mask, np.maximum(emax, tmax), emax)
                    emin = np.where(mask, np.minimum(emin, tmin), emin)
        out[rule] = {"chosen": (np.where(bc, qb_max, qa_max), np.where(bc, qb_min, qa_min)), "emitted": (emax, emin)}
    return out


def record(w, name, T, hi, lo):
    """Keeps in w = [max cot, key, t, min cot, key, t] the worst of the samples."""
    i, j = int(np.argmax(hi)), int(np.argmin(lo))
    if hi[i] > w[0]:
        w[0:3] = [hi[i], name, T[i]]
    if lo[j] < w[3]:
        w[3:6] = [lo[j], name, T[j]]
    return i, j


def samples(k, n, nrand, rng):
    vars_ = [c for c in range(4) if k[c][1] != 0]
    G = grid(len(vars_), n)
    if vars_ and nrand:
        G = np.vstack([G, rng.uniform(0, 0.5, (nrand, len(vars_)))])
    T = np.zeros((G.shape[0], 4))
    for j, c in enumerate(vars_):
        T[:, c] = G[:, j]
    return T


def flat_keys():
    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "proofs", "key_table.txt")
    with open(path) as f:
        return {w[1] for w in (line.split() for line in f if not line.startswith("#")) if w[0] == "separating" and w[2] == "flat"}


def explore(n, nrand, square, seed=1):
    rng = np.random.default_rng(seed)
    flat = flat_keys()
    # worst[(rule, which, set)] = [max cot, key, t, min cot, key, t]
    worst = {}
    inverted = {"maxmin": 0, "separating": 0}
    per_key = []
    for k in KEYS:
        T = samples(k, n, nrand, rng)
        cots = rule_cots(k, to_physical(positions(k, T), square))
        sets = ["U"] + (["F"] if code(k) in flat else [])
        for rule, by_set in cots.items():
            inverted[rule] += int(np.sum(~np.isfinite(by_set["chosen"][0])))
            for which, (hi, lo) in by_set.items():
                for s in sets:
                    i, j = record(worst.setdefault((rule, which, s), [-np.inf, None, None, np.inf, None, None]),
                                  code(k), T, hi, lo)
                if rule == "separating" and which == "chosen":
                    per_key.append((hi[i], lo[j], code(k), T[i], T[j], "F" in sets))
    return worst, inverted, per_key


# ---- a variant: warps along the third lattice direction too -------------------
# On the rhombic lattice the short diagonal BC (lattice vector (-1, 1), length 1
# after P) is an edge of the equilateral triangulation.  If the front end also
# cut and warped along it (a cut edge per sign change along (-1, 1), its
# closer endpoint warping, t in [0, 1/2]), two staying corners B, C of
# different signs would be impossible — the configuration that makes the
# separating rule force the long diagonal AD.  Warps: 5 = along (-1, +1),
# 6 = along (+1, -1).  The consistency rules of proofs/README.md, with BC a
# fifth edge of the square (no flatness: F is not computed for this variant).
DX3 = {0: 0, 1: 1, 2: -1, 3: 0, 4: 0, 5: -1, 6: 1}
DY3 = {0: 0, 1: 0, 2: 0, 3: 1, 4: -1, 5: 1, 6: -1}
STATES3 = [(0, 0)] + [(s, w) for s in (-1, 1) for w in range(1, 7)]
EDGES3 = ((A, B), (B, D), (D, C), (C, A), (B, C))


def inward_target3(c, w):
    x, y = (c & 1) + DX3[w], (c >> 1) + DY3[w]
    return -1 if w == 0 or not (0 <= x <= 1 and 0 <= y <= 1) else x + 2 * y


def consistent3(k):
    for c in range(4):
        s, w = k[c]
        if w == 0:
            continue
        n = inward_target3(c, w)
        if n >= 0 and (k[n][0] != -s or inward_target3(n, k[n][1]) == c):
            return False
    for e0, e1 in EDGES3:
        a, b = k[e0], k[e1]
        if a[0] != 0 and b[0] == -a[0] and a[1] == 0 and b[1] == 0:
            return False
    return True


def positions3(k, T):
    P = np.zeros((T.shape[0], 4, 2))
    for c in range(4):
        P[:, c, 0] = (c & 1) + DX3[k[c][1]] * T[:, c]
        P[:, c, 1] = (c >> 1) + DY3[k[c][1]] * T[:, c]
    return P


def code3(k):
    return "".join("-0+"[s + 1] + "sRLUDbc"[w] for s, w in k)


def explore_third_direction(n, nrand, seed=1):
    """Worst (min, max) angle of the chosen and emitted triangles, max-min and
    separating rules in the rhombic metric, over every consistent key."""
    import itertools
    rng = np.random.default_rng(seed)
    keys = [k for k in itertools.product(STATES3, repeat=4) if consistent3(k)]
    worst = {}
    for k in keys:
        T = samples(k, n, nrand, rng)
        for rule, by_set in rule_cots(k, to_physical(positions3(k, T), False)).items():
            for which, (hi, lo) in by_set.items():
                record(worst.setdefault((rule, which), [-np.inf, None, None, np.inf, None, None]), code3(k), T, hi, lo)
    print(f"\nvariant: warps along the short diagonal too (b: along (-1, 1), c: along (1, -1)); {len(keys)} consistent keys, U only")
    print("| rule | triangles | worst min angle | at key, t | worst max angle | at key, t |")
    print("|---|---|---|---|---|---|")
    for (rule, which), w in sorted(worst.items()):
        t1 = ",".join(f"{v:.3g}" for v in w[2])
        t2 = ",".join(f"{v:.3g}" for v in w[5])
        print(f"| {rule} | {which} | {deg(w[0]):.4f}° | `{w[1]}` ({t1}) | {deg(w[3]):.4f}° | `{w[4]}` ({t2}) |")


def chosen_cots(k, T, rule, square):
    """(max cot, min cot) over the chosen triangles of key k at the t rows T."""
    return rule_cots(k, to_physical(positions(k, T), square))[rule]["chosen"]


def refine(k, t0, rule, square, largest):
    """Local search (Nelder-Mead, t clipped to [0, 1/2]) from t0 for the
    smallest minimum angle (largest=False) or the largest maximum angle."""
    from scipy.optimize import minimize
    vars_ = [c for c in range(4) if k[c][1] != 0]
    if not vars_:
        return t0, chosen_cots(k, t0[None, :], rule, square)[1 if largest else 0][0]

    def obj(x):
        T = np.zeros((1, 4))
        T[0, vars_] = np.clip(x, 0, 0.5)
        hi, lo = chosen_cots(k, T, rule, square)
        return lo[0] if largest else -hi[0]
    r = minimize(obj, t0[vars_], method="Nelder-Mead", options={"xatol": 1e-10, "fatol": 1e-13, "maxiter": 4000})
    t = t0.copy()
    t[vars_] = np.clip(r.x, 0, 0.5)
    return t, (r.fun if largest else -r.fun)


def main(argv):
    square = "--square" in argv
    args = [a for a in argv if not a.startswith("--")]
    n = int(args[0]) if args else 7
    nrand = int(args[1]) if len(args) > 1 else 0
    if "--third-direction" in argv:
        return explore_third_direction(n, nrand)
    worst, inverted, per_key = explore(n, nrand, square)
    lattice = "square" if square else "rhombic"
    print(f"{lattice} lattice, {len(KEYS)} keys, grid {n} per warped corner + {nrand} random points per key")
    print("| rule | triangles | set | worst min angle | at key, t | worst max angle | at key, t |")
    print("|---|---|---|---|---|---|---|")
    for (rule, which, s), w in sorted(worst.items()):
        t1 = ",".join(f"{v:.3g}" for v in w[2])
        t2 = ",".join(f"{v:.3g}" for v in w[5])
        print(f"| {rule} | {which} | {s} | {deg(w[0]):.4f}° | `{w[1]}` ({t1}) | {deg(w[3]):.4f}° | `{w[4]}` ({t2}) |")
    print("configurations with an inverted chosen triangle:", inverted)
    print("\nlocal refinement (Nelder-Mead) from every (rule, set)'s worst sample, chosen triangles:")
    for (rule, which, s), w in sorted(worst.items()):
        if which != "chosen":
            continue
        k = next(k for k in KEYS if code(k) == w[1])
        t, q = refine(k, np.array(w[2]), rule, square, False)
        k2 = next(k for k in KEYS if code(k) == w[4])
        t2, q2 = refine(k2, np.array(w[5]), rule, square, True)
        print(f"  {rule} {s}: min {deg(q):.4f}° at {w[1]} t = {np.round(t, 6)}; max {deg(q2):.4f}° at {w[4]} t = {np.round(t2, 6)}")
    print("\nseparating, chosen: the 12 keys with the smallest minimum angle (F = flat-compatible)")
    for q, _, c, t, _, f in sorted(per_key, key=lambda r: -r[0])[:12]:
        print(f"  {c} {'F' if f else 'U'} min {deg(q):.4f}° at t = {np.round(t, 4)}")
    print("separating, chosen: the 12 keys with the largest maximum angle")
    for _, q, c, _, t, f in sorted(per_key, key=lambda r: r[1])[:12]:
        print(f"  {c} {'F' if f else 'U'} max {deg(q):.4f}° at t = {np.round(t, 4)}")


if __name__ == "__main__":
    main(sys.argv[1:])
