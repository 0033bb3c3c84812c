// bound.cpp — branch and bound over a key's t-box: runs generic_square.hpp's
// own choose_diagonal with outward-rounded intervals and verifies the angle
// forms of the chosen triangles box by box (proofs/README.md, "Certificate
// format" and "How the prover decides").
#include <algorithm>
#include <cmath>

#include "warpmesh/numerics/dual.hpp"
#include "warpmesh/numerics/interval.hpp"
#include "warpmesh/prove.hpp"

namespace warpmesh {

// Outward-rounded intervals (numerics/interval.hpp: every entry point below
// holds a RoundUp guard) and dual numbers over them (numerics/dual.hpp):
// value and the partial derivatives with respect to the (at most 4) t
// variables.  Positions are affine in t, the angle forms quadratic.
using I = Interval;
using DI = Dual<Interval>;

namespace prover {
namespace {

// ---- boxes -----------------------------------------------------------------
struct Box {
    int m = 0;
    std::array<double, 4> lo{}, hi{};
};

std::array<Point<I>, 4> positions_i(const Key& k, const std::vector<int>& vars, const Box& b) {
    std::array<Warp, 4> w{};
    std::array<I, 4> t{I(0.), I(0.), I(0.), I(0.)};
    for (int c = 0; c < 4; ++c) w[c] = k.s[c].warp;
    for (int j = 0; j < b.m; ++j) t[vars[j]] = I(b.lo[j], b.hi[j]);
    return generic_positions<I>(w, t);
}

std::array<Point<DI>, 4> positions_d(const Key& k, const std::vector<int>& vars, const Box& b) {
    std::array<Warp, 4> w{};
    std::array<DI, 4> t{};
    for (int c = 0; c < 4; ++c) {
        w[c] = k.s[c].warp;
        t[c] = ScalarOps<DI>::from_int(0);
    }
    for (int j = 0; j < b.m; ++j) {
        t[vars[j]].v = I(b.lo[j], b.hi[j]);
        t[vars[j]].d[j] = I(1.);
    }
    return generic_positions<DI>(w, t);
}

// Form f of a triangle: 0 = cross (> 0), 1..3 = qmin*cross - dot_i (>= 0),
// 4..6 = dot_i - qmax*cross (>= 0).
DI form(const TriangleForms<DI>& tf, int f, double qmin, double qmax) {
    if (f == 0) return tf.cross;
    const DI qc = ScalarOps<DI>::from_int(0);
    DI c = tf.cross;
    if (f <= 3) {
        DI q = qc;
        q.v = I(qmin);
        return q * c - tf.dot[f - 1];
    }
    DI q = qc;
    q.v = I(qmax);
    return tf.dot[f - 4] - q * c;
}

// A form "g >= 0" (strict: g > 0) holds on box b.  Tests, in turn, the natural
// interval extension g(b) and the mean-value form around the centre c of b:
// g(t) = g(c) + sum_j d_j g(xi) (t_j - c_j) for some xi in b, so
// g(b) is contained in g(c) + sum_j d_j g(b) [-r_j, r_j] (r_j the half-width).
// While neither proves it, every variable whose partial derivative has a
// decided sign on the box is fixed at the end where g is smallest (all at
// once: each segment stays in the box) and both tests are repeated on that
// face.  `eval(box)` evaluates g with its partials on a box; `g` is eval(b).
// The checker applies the identical procedure with exact dyadic intervals.
template <class Eval>
bool verify_poly(Box b, DI g, bool strict, const Eval& eval) {
    for (;;) {
        if (strict ? g.v.lower() > 0 : g.v.lower() >= 0) return true;
        Box c = b;
        for (int j = 0; j < b.m; ++j) c.lo[j] = c.hi[j] = 0.5 * (b.lo[j] + b.hi[j]);
        I mv = eval(c).v;
        for (int j = 0; j < b.m; ++j)
            if (b.lo[j] != b.hi[j]) {
                const double r = 0.5 * (b.hi[j] - b.lo[j]);
                mv = mv + g.d[j] * I(-r, r);
            }
        if (strict ? mv.lower() > 0 : mv.lower() >= 0) return true;
        bool fixed = false;
        for (int j = 0; j < b.m; ++j) {
            if (b.lo[j] == b.hi[j]) continue;
            if (g.d[j].lower() >= 0) b.hi[j] = b.lo[j], fixed = true;
            else if (g.d[j].upper() <= 0) b.lo[j] = b.hi[j], fixed = true;
        }
        if (!fixed) return false;
        g = eval(b);
    }
}

// Form f of triangle `tri` (of the corners, or with `fan` of fan_points).
bool verify_form(const Key& k, const std::vector<int>& vars, const Box& b, const std::array<int, 3>& tri, int f,
                 double qmin, double qmax, const DI& g, bool fan = false) {
    return verify_poly(b, g, f == 0, [&](const Box& bx) {
        const auto p = positions_d(k, vars, bx);
        if (fan) {
            const auto q = fan_points(p);
            return form(triangle_forms(q[tri[0]], q[tri[1]], q[tri[2]], k.metric), f, qmin, qmax);
        }
        return form(triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]], k.metric), f, qmin, qmax);
    });
}

// Forms f0 <= f < f1 of the four triangles of the centroid fan.
bool verify_fan(const Key& k, const std::vector<int>& vars, const Box& b, double qmin, double qmax, int* fail_kind,
                int f0 = 0, int f1 = 7) {
    const auto q = fan_points(positions_d(k, vars, b));
    for (const auto& tri : fan_triangles) {
        const TriangleForms<DI> tf = triangle_forms(q[tri[0]], q[tri[1]], q[tri[2]], k.metric);
        for (int f = f0; f < f1; ++f)
            if (!verify_form(k, vars, b, tri, f, qmin, qmax, form(tf, f, qmin, qmax), true)) {
                *fail_kind = f == 0 ? 0 : f <= 3 ? 1 : 2;
                return false;
            }
    }
    return true;
}

// Forms f0 <= f < f1 of both triangles of diagonal d.
bool verify_diag(const Key& k, const std::vector<int>& vars, const Box& b, Diagonal d, double qmin, double qmax,
                 int* fail_kind, int f0 = 0, int f1 = 7) {
    const auto p = positions_d(k, vars, b);
    for (const auto& tri : diagonal_triangles(d)) {
        const TriangleForms<DI> tf = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]], k.metric);
        for (int f = f0; f < f1; ++f)
            if (!verify_form(k, vars, b, tri, f, qmin, qmax, form(tf, f, qmin, qmax))) {
                *fail_kind = f == 0 ? 0 : f <= 3 ? 1 : 2;
                return false;
            }
    }
    return true;
}

// ---- switching leaves (tag S; proofs/README.md, "Certificate format") -------
// On a box where the max-min choice is undecided, diagonal d's max-angle forms
// need to hold only where d is taken.  There (with the other diagonal o
// exactly valid on the box) q(d) <= kappa q(o), kappa = 1 + 2^-30, for the exact rule
// and for the mesher's double evaluation ("Double agreement", item 6).  For a
// ratio r_k = dot_k / cross of d (index 3 t + i: vertex i of d's triangle t)
// and the six ratios s_j of o: r_k <= q(d) <= kappa max_j s_j, so some
// h_j = kappa dot_j(o) cross(d, t) - dot_k(d) cross(o, j / 3) >= 0.  The leaf
// names k and at most two ratios J of o such that h_j < 0 on the box for every
// other j; then wherever d is taken some named h_J >= 0, and each max-angle
// form g of d is verified outright or, for each named J, as g - lambda h_J >= 0
// with a dyadic lambda >= 0 (so g >= lambda h_J >= 0 where h_J >= 0).  With no
// J named, d is never taken on the box.
constexpr double switch_slack = 1 + 0x1p-30;  // kappa

DI ratio_h(const std::array<Point<DI>, 4>& p, Diagonal d, int k, int j, LatticeMetric metric) {
    const Diagonal o = d == Diagonal::AD ? Diagonal::BC : Diagonal::AD;
    const auto td = diagonal_triangles(d)[static_cast<std::size_t>(k / 3)];
    const auto to = diagonal_triangles(o)[static_cast<std::size_t>(j / 3)];
    const TriangleForms<DI> fd = triangle_forms(p[td[0]], p[td[1]], p[td[2]], metric);
    const TriangleForms<DI> fo = triangle_forms(p[to[0]], p[to[1]], p[to[2]], metric);
    DI e = ScalarOps<DI>::from_int(0);
    e.v = I(switch_slack);
    return e * fo.dot[j % 3] * fd.cross - fd.dot[k % 3] * fo.cross;
}

// Dyadic with 12 significant bits, at most x.
double dyadic12(double x) {
    int e = 0;
    std::frexp(x, &e);
    return std::ldexp(std::floor(std::ldexp(x, 12 - e)), e - 12);
}

// A multiplier lambda >= 0 with g - lambda h >= 0 on box b (g: max-angle form
// f of triangle tri, h = ratio_h(d, kd, jo)), or -1.  Candidates: the
// projection of g's gradient on h's (weighted by the half-widths) and the
// per-variable ratios of the partials; the one with the best approximate
// mean-value lower bound is verified.
double find_lambda(const Key& k, const std::vector<int>& vars, const Box& b, Diagonal d, int kd, int jo,
                   const std::array<int, 3>& tri, int f, double qmax) {
    auto combined = [&](const Box& bx, double lam) {
        const auto q = positions_d(k, vars, bx);
        DI lc = ScalarOps<DI>::from_int(0);
        lc.v = I(lam);
        return form(triangle_forms(q[tri[0]], q[tri[1]], q[tri[2]], k.metric), f, 0, qmax) - lc * ratio_h(q, d, kd, jo, k.metric);
    };
    Box c = b;
    for (int j = 0; j < b.m; ++j) c.lo[j] = c.hi[j] = 0.5 * (b.lo[j] + b.hi[j]);
    const DI g = combined(b, 0), gc = combined(c, 0);
    const auto pb = positions_d(k, vars, b), pc = positions_d(k, vars, c);
    const DI h = ratio_h(pb, d, kd, jo, k.metric), hc = ratio_h(pc, d, kd, jo, k.metric);
    std::vector<double> cand;
    double num = 0, den = 0;
    for (int j = 0; j < b.m; ++j) {
        const double r = 0.5 * (b.hi[j] - b.lo[j]), gd = boost::numeric::median(g.d[j]),
                     hd = boost::numeric::median(h.d[j]);
        num += gd * hd * r * r, den += hd * hd * r * r;
        if (hd != 0 && gd / hd > 0) cand.push_back(gd / hd);
    }
    if (den > 0 && num / den > 0) cand.push_back(num / den);
    double best = -1e300, best_lam = -1;
    for (double l : cand) {
        l = dyadic12(l);
        if (!(l > 0) || !std::isfinite(l)) continue;
        double est = boost::numeric::median(gc.v) - l * boost::numeric::median(hc.v);
        for (int j = 0; j < b.m; ++j)
            est -= 0.5 * (b.hi[j] - b.lo[j]) * boost::numeric::norm(g.d[j] - I(l) * h.d[j]);
        if (est > best) best = est, best_lam = l;
    }
    if (best_lam <= 0) return -1;
    const auto eval = [&](const Box& bx) { return combined(bx, best_lam); };
    return verify_poly(b, eval(b), false, eval) ? best_lam : -1;
}

// The switching certificate of diagonal d on box b with reference ratio kd
// (see above), into sw.
bool switch_diag_with(const Key& k, const std::vector<int>& vars, const Box& b, Diagonal d, int kd, double qmax,
                      Switch& sw) {
    const int di = d == Diagonal::AD ? 0 : 1;
    // The ratios of o not excluded on the box: at most two.
    const auto pd = positions_d(k, vars, b);
    std::vector<int> named;
    for (int j = 0; j < 6; ++j)
        if (!(ratio_h(pd, d, kd, j, k.metric).v.upper() < 0)) named.push_back(j);
    if (named.size() > 2) return false;
    sw.k[di] = static_cast<std::int8_t>(kd);
    for (std::size_t n = 0; n < 2; ++n) sw.j[2 * di + n] = static_cast<std::int8_t>(n < named.size() ? named[n] : -1);
    for (int t = 0; t < 2; ++t) {
        const auto tri = diagonal_triangles(d)[static_cast<std::size_t>(t)];
        const TriangleForms<DI> tf = triangle_forms(pd[tri[0]], pd[tri[1]], pd[tri[2]], k.metric);
        for (int i = 0; i < 3; ++i) {
            for (std::size_t n = 0; n < 2; ++n) sw.lambda[12 * di + 6 * n + 3 * t + i] = -1;  // '-'
            if (named.empty() || verify_form(k, vars, b, tri, 4 + i, 0, qmax, form(tf, 4 + i, 0, qmax))) continue;
            for (std::size_t n = 0; n < named.size(); ++n) {
                const double lam = find_lambda(k, vars, b, d, kd, named[n], tri, 4 + i, qmax);
                if (lam < 0) return false;
                sw.lambda[12 * di + 6 * n + 3 * t + i] = lam;
            }
        }
    }
    return true;
}

// The switching certificate of diagonal d on box b: requires the other
// diagonal valid on the box; the reference ratio k is tried among d's largest
// ratios at the centre of the box (near the switching surface d's largest
// ratio may change, and k must be the largest where d is not taken).
bool switch_diag(const Key& k, const std::vector<int>& vars, const Box& b, Diagonal d, double qmax, Switch& sw) {
    const Diagonal o = d == Diagonal::AD ? Diagonal::BC : Diagonal::AD;
    const auto pi = positions_i(k, vars, b);
    for (const auto& tri : diagonal_triangles(o))
        if (!(triangle_forms(pi[tri[0]], pi[tri[1]], pi[tri[2]], k.metric).cross.lower() > 0)) return false;
    Box c = b;
    for (int j = 0; j < b.m; ++j) c.lo[j] = c.hi[j] = 0.5 * (b.lo[j] + b.hi[j]);
    const auto pc = positions_i(k, vars, c);
    std::array<std::pair<double, int>, 6> r;
    for (int t = 0; t < 2; ++t) {
        const auto tri = diagonal_triangles(d)[static_cast<std::size_t>(t)];
        const auto tf = triangle_forms(pc[tri[0]], pc[tri[1]], pc[tri[2]], k.metric);
        if (!(tf.cross.lower() > 0)) return false;
        for (int i = 0; i < 3; ++i)
            r[static_cast<std::size_t>(3 * t + i)] = {
                -boost::numeric::median(tf.dot[i]) / boost::numeric::median(tf.cross), 3 * t + i};
    }
    std::sort(r.begin(), r.end());  // largest ratio first
    for (std::size_t n = 0; n < 3; ++n) {
        if (n > 0 && -r[n].first < -r[0].first - 0.125 * (1 + std::fabs(r[0].first))) break;
        if (switch_diag_with(k, vars, b, d, r[n].second, qmax, sw)) return true;
    }
    return false;
}

// A second, division-free decision of the max-min rule, used where the header's
// interval evaluation cannot decide because the losing diagonal degenerates
// (its cross product's enclosure contains 0).  `win` is taken on the whole box
// if `win` is valid there and, for some triangle T of the other diagonal and
// some vertex i, dot_i(T) - H cross(T) > 0 on the box (>= 0 when win = AD, the
// tie-break) with H >= q(win): where cross(T) > 0 this gives
// q(other) >= dot_i/cross > H >= q(win) (so the rule takes win), and where
// cross(T) <= 0 the other diagonal is invalid.  H is q(win)'s upper bound
// times (1 + 2^-28), a dyadic recorded in the certificate: the relative margin
// that lets the mesher's double evaluation agree.  Returns H in `thr`.
bool threshold_decides(const Key& k, const std::vector<int>& vars, const Box& b, Diagonal win, double& thr) {
    const auto p = positions_i(k, vars, b);
    double h = -1e300;
    for (const auto& tri : diagonal_triangles(win)) {
        const auto tf = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]], k.metric);
        if (!(tf.cross.lower() > 0)) return false;
        for (const I& dot : tf.dot) h = std::max(h, (dot / tf.cross).upper());
    }
    if (!(h > 0) || !std::isfinite(h)) return false;
    {
        int e = 0;
        std::frexp(h, &e);
        h = std::ldexp(std::ceil(std::ldexp(h, 24 - e) * (1 + std::ldexp(1.0, -28))) + 1, e - 24);
    }
    const Diagonal other = win == Diagonal::AD ? Diagonal::BC : Diagonal::AD;
    for (const auto& tri : diagonal_triangles(other)) {
        const auto tf = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]], k.metric);
        for (const I& dot : tf.dot) {
            const I g = dot - I(h) * tf.cross;
            if (g.lower() > 0) {
                thr = h;
                return true;
            }
        }
    }
    return false;
}

// The fan rule's exclusion of diagonal d on the whole box: for some triangle T
// of d and vertex i, dot_i(T) - h cross(T) > 0 (h = fan_exclusion_cot below):
// where cross(T) > 0, q(d) > h; elsewhere d is invalid.  Either way d does not
// qualify (q <= H0), also in the mesher's double evaluation (margin 2^-28).
bool excludes(const Key& k, const std::vector<int>& vars, const Box& b, Diagonal d, double h) {
    const auto p = positions_i(k, vars, b);
    for (const auto& tri : diagonal_triangles(d)) {
        const auto tf = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]], k.metric);
        for (const I& dot : tf.dot)
            if ((dot - I(h) * tf.cross).lower() > 0) return true;
    }
    return false;
}

Leaf make_leaf(const Box& b, int diag) {
    Leaf l;
    l.diag = static_cast<std::uint8_t>(diag);
    int k = 0;
    for (int j = 0; j < b.m; ++j)
        for (double x : {b.lo[j], b.hi[j]}) {
            int e = 0;
            while (x * std::ldexp(1.0, e) != std::floor(x * std::ldexp(1.0, e))) ++e;
            k = std::max(k, e);
        }
    l.k = k;
    for (int j = 0; j < b.m; ++j) {
        l.num[2 * j] = static_cast<std::int64_t>(std::ldexp(b.lo[j], k));
        l.num[2 * j + 1] = static_cast<std::int64_t>(std::ldexp(b.hi[j], k));
    }
    return l;
}

}  // namespace

int interval_choice(DiagonalRule rule, const Key& key, const std::array<double, 4>& lo,
                    const std::array<double, 4>& hi) {
    const RoundUp guard;
    const auto vars = key_vars(key);
    Box b;
    b.m = static_cast<int>(vars.size());
    b.lo = lo, b.hi = hi;
    const Choice ch = choose_key_diagonal<I>(rule, positions_i(key, vars, b), key, TieBreak::either);
    return (ch.ad ? 1 : 0) | (ch.bc ? 2 : 0);
}

KeyProof prove_key(DiagonalRule rule, const Key& key, double qmin, double qmax, std::size_t max_leaves) {
    const RoundUp guard;  // upward rounding: also the scalar margins below round away from the decision
    KeyProof out;
    const auto vars = key_vars(key);
    Box root;
    root.m = static_cast<int>(vars.size());
    for (int j = 0; j < root.m; ++j) root.lo[j] = 0, root.hi[j] = 0.5;
    // Depth-first, left half first: the checker rebuilds the same bisection tree
    // (split the widest side, the first one on ties, at its midpoint).
    // The fan rule on a square whose corners are all inside (generic_square.hpp):
    // leaves `F` (fan decided: both diagonals excluded), `Y` (undecided between
    // the fan and a diagonal), or diagonal leaves whose diagonal is verified
    // with q <= fan_keep_cot (so it qualifies and the fan is not taken).
    const bool fan_square = fan_key(rule, key);
    std::vector<Box> stack{root};
    auto split_or_fail = [&](const Box& b, int kind) {
        int s = -1;
        for (int j = 0; j < b.m; ++j)
            if (s < 0 || b.hi[j] - b.lo[j] > b.hi[s] - b.lo[s]) s = j;
        if (s < 0 || b.hi[s] - b.lo[s] < std::ldexp(1.0, -44) || out.leaves.size() > max_leaves) {
            for (int j = 0; j < b.m; ++j) out.fail_point[vars[j]] = 0.5 * (b.lo[j] + b.hi[j]);
            out.fail_kind = kind;
            return false;
        }
        const double mid = 0.5 * (b.lo[s] + b.hi[s]);
        Box l = b, r = b;
        l.hi[s] = mid, r.lo[s] = mid;
        stack.push_back(r);
        stack.push_back(l);
        return true;
    };
    while (!stack.empty()) {
        const Box b = stack.back();
        stack.pop_back();
        if (fan_square && excludes(key, vars, b, Diagonal::AD, fan_exclusion_cot) &&
            excludes(key, vars, b, Diagonal::BC, fan_exclusion_cot)) {
            int kind = 0;
            if (verify_fan(key, vars, b, qmin, qmax, &kind)) {
                out.leaves.push_back(make_leaf(b, 4));
                continue;
            }
            if (!split_or_fail(b, kind)) return out;
            continue;
        }
        const double dmin = fan_square ? std::min(qmin, fan_keep_cot) : qmin;
        Choice ch = choose_key_diagonal<I>(fan_square ? DiagonalRule::maxmin : rule, positions_i(key, vars, b), key, TieBreak::either);
        double thr = 0;
        if (ch.ad && ch.bc) {
            if (threshold_decides(key, vars, b, Diagonal::BC, thr)) ch.ad = false;
            else if (threshold_decides(key, vars, b, Diagonal::AD, thr)) ch.bc = false;
        }
        bool ok = true;
        int kind = 0;
        Switch sw;
        bool use_sw = false;
        if (ch.ad && ch.bc) {
            // Undecided (max-min rule): if one diagonal X is valid with q(X) <= qmin
            // on the box, the rule takes a valid diagonal Y with q(Y) <= q(X) at
            // every point, so orientation and the min angle hold; the max angle is
            // needed on both diagonals (the one taken is valid there).
            ok = verify_diag(key, vars, b, Diagonal::AD, dmin, qmax, &kind, 0, 4) ||
                 verify_diag(key, vars, b, Diagonal::BC, dmin, qmax, &kind, 0, 4);
            // A diagonal whose max-angle forms fail on the box may still hold
            // where it is taken: a switching certificate (leaf S).
            for (const Diagonal d : {Diagonal::AD, Diagonal::BC}) {
                if (!ok) break;
                if (verify_diag(key, vars, b, d, qmin, qmax, &kind, 4, 7)) continue;
                if (!switch_diag(key, vars, b, d, qmax, sw)) ok = false;
                else use_sw = true;
            }
        } else if (ch.ad) {
            ok = verify_diag(key, vars, b, Diagonal::AD, dmin, qmax, &kind);
        } else {
            ok = verify_diag(key, vars, b, Diagonal::BC, dmin, qmax, &kind);
        }
        if (ok) {
            out.leaves.push_back(make_leaf(b, (ch.ad ? 1 : 0) | (ch.bc ? 2 : 0)));
            out.leaves.back().threshold = (ch.ad && ch.bc) ? 0 : thr;
            if (use_sw) {
                out.leaves.back().sw = static_cast<int>(out.switches.size());
                out.switches.push_back(sw);
            }
            continue;
        }
        // Fan rule, undecided between the fan and a diagonal: the fan verified
        // whole; a diagonal the rule takes here qualifies (q <= H0; the max-min
        // pick among the diagonals qualifies whenever one does), which the claim
        // covers: qmin >= fan_taken_cot; the max-angle forms on each diagonal
        // that is not excluded on the box (an excluded one never qualifies).
        if (fan_square && qmin >= fan_taken_cot) {
            int k2 = 0;
            if (verify_fan(key, vars, b, qmin, qmax, &k2) &&
                (excludes(key, vars, b, Diagonal::AD, fan_exclusion_cot) ||
                 verify_diag(key, vars, b, Diagonal::AD, qmin, qmax, &k2, 4, 7)) &&
                (excludes(key, vars, b, Diagonal::BC, fan_exclusion_cot) ||
                 verify_diag(key, vars, b, Diagonal::BC, qmin, qmax, &k2, 4, 7))) {
                out.leaves.push_back(make_leaf(b, 5));
                continue;
            }
        }
        if (!split_or_fail(b, kind)) return out;
    }
    out.ok = true;
    return out;
}

}  // namespace prover
}  // namespace warpmesh
