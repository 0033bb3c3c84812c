#!/usr/bin/python3
"""Numeric exploration of warping-rule variants (sampling, NOT a proof; not
on the proof path: the certificates come from prover/src and checker).

Enumerates the configuration keys of proofs/README.md, samples each key's
t-box [0,1/2]^m on a grid and reports the worst minimum angle over the
triangles the mesher would *emit* (all corners inside: sign <= 0 or warped)
for a few candidate per-square rules.  Usage: /usr/bin/python3 explore_rules.py [n]   (grid points per warped corner;
threshold_study(n, H0) samples the fan rule as certified in proofs/fan.cert)
"""
import itertools, sys
import numpy as np

STATES = [(0, 0)] + [(-1 if st <= 5 else 1, (st - 1) % 5) for st in range(1, 11)]  # keys.cpp's state_of
DX = {0: 0, 1: 1, 2: -1, 3: 0, 4: 0}
DY = {0: 0, 1: 0, 2: 0, 3: 1, 4: -1}
A, B, C, D = 0, 1, 2, 3

def inward_target(c, w):
    x, y = (c & 1) + DX[w], (c >> 1) + DY[w]
    if w == 0 or x < 0 or x > 1 or y < 0 or y > 1: return -1
    return x + 2 * y

def consistent(k):
    for c in range(4):
        s, w = k[c]
        if s == 0 and w != 0: return False
        if w == 0: continue
        n = inward_target(c, w)
        if n >= 0:
            if k[n][0] != -s: return False
            if inward_target(n, k[n][1]) == c: return False
    for e0, e1 in ((A, B), (B, D), (D, C), (C, A)):
        a, b = k[e0], k[e1]
        if a[0] != 0 and b[0] == -a[0] and a[1] == 0 and b[1] == 0: return False
    return True

KEYS = [k for k in itertools.product(STATES, repeat=4) if consistent(k)]

def positions(k, T):  # T: (N,4) array of t per corner -> (N,4,2)
    N = T.shape[0]
    P = np.zeros((N, 4, 2))
    for c in range(4):
        P[:, c, 0] = (c & 1) + DX[k[c][1]] * T[:, c]
        P[:, c, 1] = (c >> 1) + DY[k[c][1]] * T[:, c]
    return P

def tri_maxcot(p0, p1, p2):
    """max cot over the triangle's angles; +inf if not ccw."""
    pts = [p0, p1, p2]
    cr = (p1[:, 0] - p0[:, 0]) * (p2[:, 1] - p0[:, 1]) - (p1[:, 1] - p0[:, 1]) * (p2[:, 0] - p0[:, 0])
    q = np.full(cr.shape, -np.inf)
    for i in range(3):
        o, a, b = pts[i], pts[(i + 1) % 3], pts[(i + 2) % 3]
        dot = (a[:, 0] - o[:, 0]) * (b[:, 0] - o[:, 0]) + (a[:, 1] - o[:, 1]) * (b[:, 1] - o[:, 1])
        with np.errstate(divide='ignore', invalid='ignore'):
            q = np.maximum(q, dot / cr)
    return np.where(cr > 1e-14, q, np.inf)

TRIS = {'AD': [(A, B, D), (A, D, C)], 'BC': [(A, B, C), (B, D, C)]}

def diag_q(P, d):
    return np.maximum(*[tri_maxcot(P[:, t[0]], P[:, t[1]], P[:, t[2]]) for t in TRIS[d]])

def fan_q(P, M):
    # ccw ring A B D C
    ring = [A, B, D, C]
    q = None
    for i in range(4):
        x = tri_maxcot(P[:, ring[i]], P[:, ring[(i + 1) % 4]], M)
        q = x if q is None else np.maximum(q, x)
    return q

def cot2deg(q):
    return np.degrees(np.arctan2(1, q))

ALPHA = 0.5  # largest warp t sampled (a warp threshold alpha < 1/2 would need split edges)

def grid(m, n):
    g = np.linspace(0, ALPHA, n)
    return np.array(list(itertools.product(g, repeat=m))) if m else np.zeros((1, 0))

def sampled(k, n):
    """Key k's square on the grid of its warped corners' t: T (N,4), positions (N,4,2)
    and which corners are inside (sign <= 0 or warped)."""
    vars_ = [c for c in range(4) if k[c][1] != 0]
    G = grid(len(vars_), n)
    T = np.zeros((G.shape[0], 4))
    for j, c in enumerate(vars_): T[:, c] = G[:, j]
    return T, positions(k, T), [k[c][1] != 0 or k[c][0] <= 0 for c in range(4)]

def evaluate(rule, n):
    worst = (np.inf, None, None)
    per_class = {}
    for k in KEYS:
        T, P, inside = sampled(k, n)
        q = rule(k, P, inside)
        if q is None: continue
        i = int(np.argmax(q))
        cls = sum(inside)
        if q[i] > per_class.get(cls, (-np.inf,))[0]: per_class[cls] = (q[i], k, T[i])
        if -q[i] < -worst[0] if False else q[i] > (worst[0] if worst[1] is not None else -np.inf):
            worst = (q[i], k, T[i])
    return worst, per_class

def code(k):
    return ''.join('-0+'[s + 1] + 'sRLUD'[w] for s, w in k)

def sep_forced(k):
    ph = [(1 if k[c][0] > 0 else 0) if (k[c][1] == 0 and k[c][0] != 0) else -1 for c in range(4)]
    if ph[A] >= 0 and ph[D] >= 0 and ph[A] != ph[D]: return 'BC'
    if ph[B] >= 0 and ph[C] >= 0 and ph[B] != ph[C]: return 'AD'
    return None

def maxmin_choice(P):
    qa, qb = diag_q(P, 'AD'), diag_q(P, 'BC')
    return np.where(qb < qa, qb, qa), qb < qa

def emitted_q(k, P, inside, d_is_bc):
    """max cot over emitted triangles given chosen diagonal per sample."""
    out = np.full(P.shape[0], -np.inf)
    for d, mask in (('AD', ~d_is_bc), ('BC', d_is_bc)):
        for t in TRIS[d]:
            if all(inside[c] for c in t):
                q = tri_maxcot(P[:, t[0]], P[:, t[1]], P[:, t[2]])
                out = np.where(mask, np.maximum(out, q), out)
    return out

def rule_separating_emitted(k, P, inside):
    f = sep_forced(k)
    qa, qb = diag_q(P, 'AD'), diag_q(P, 'BC')
    bc = (qb < qa) if f is None else np.full(P.shape[0], f == 'BC')
    return emitted_q(k, P, inside, bc)

def rule_separating_all(k, P, inside):
    f = sep_forced(k)
    qa, qb = diag_q(P, 'AD'), diag_q(P, 'BC')
    if f is None: return np.minimum(qa, qb)
    return qa if f == 'AD' else qb

def make_fan_rule(centre, only_all_inside=True, drop=True):
    def rule(k, P, inside):
        f = sep_forced(k)
        qa, qb = diag_q(P, 'AD'), diag_q(P, 'BC')
        bc = (qb < qa) if f is None else np.full(P.shape[0], f == 'BC')
        q = emitted_q(k, P, inside, bc)
        if all(inside):
            M = centre(P)
            q = np.minimum(q, fan_q(P, M))
        elif sum(inside) == 3 and drop:
            x = inside.index(False)
            opp = 3 - x
            if k[opp][1] != 0 or k[opp][0] == 0:  # opposite corner on the level set: the triangle may be dropped
                q = np.minimum(q, -np.inf)
        return q
    return rule

def centroid(P): return P.mean(axis=1)
def centre_sq(P): return np.full((P.shape[0], 2), 0.5)

if __name__ == '__main__':
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 9
    print(len(KEYS), 'keys')
    for name, rule in [('separating (all chosen)', rule_separating_all),
                       ('separating (emitted)', rule_separating_emitted),
                       ('sep + centroid fan + drop', make_fan_rule(centroid)),
                       ('sep + centre fan + drop', make_fan_rule(centre_sq)),
                       ('sep + centroid fan, no drop', make_fan_rule(centroid, drop=False))]:
        (q, k, t), pc = evaluate(rule, n)
        print(f'{name:32s} worst {cot2deg(q):8.4f} deg at {code(k)} t={np.round(t,4)}')
        for cls in sorted(pc):
            qq, kk, tt = pc[cls]
            print(f'    {cls} inside: {cot2deg(qq):8.4f} at {code(kk)} t={np.round(tt,4)}')

def threshold_study(n, H0=3.0 + 2**-20):
    """The threshold rule: all-inside squares take the separating rule's
    (max-min) diagonal if some diagonal is valid with q <= H0, else the
    centroid fan.  Prints per class the worst min angle and the worst max angle,
    and the worst fan q where the fan is taken."""
    worst = {}
    fanw = (-np.inf, None, None)
    for k in KEYS:
        T, P, inside = sampled(k, n)
        f = sep_forced(k)
        qa, qb = diag_q(P, 'AD'), diag_q(P, 'BC')
        q = rule_separating_all(k, P, inside)
        if all(inside):
            qf = fan_q(P, centroid(P))
            use_fan = np.minimum(qa, qb) > H0
            if use_fan.any():
                i = int(np.argmax(np.where(use_fan, qf, -np.inf)))
                if qf[i] > fanw[0]: fanw = (qf[i], k, T[i])
            q = np.where(use_fan, qf, q)
        cls = sum(inside)
        i = int(np.argmax(q))
        if q[i] > worst.get(cls, (-np.inf,))[0]: worst[cls] = (q[i], k, T[i])
    for cls in sorted(worst):
        qq, kk, tt = worst[cls]
        print(f'  class {cls} inside: worst {cot2deg(qq):8.4f} at {code(kk)} t={np.round(tt,4)}')
    if fanw[1] is None: print('  no fan taken')
    else: print(f'  fan where taken: worst {cot2deg(fanw[0]):8.4f} at {code(fanw[1])} t={np.round(fanw[2],4)}')
