// warpmesh-check — independent checker of the angle certificates (proofs/*.cert).
//
// Shares no code with the prover or the mesher: it re-derives the consistent
// keys and their flatness, rebuilds every key's bisection tree from the leaves,
// re-verifies every leaf with exact rational interval arithmetic (including
// the margins that make the mesher's double-precision diagonal choice agree),
// checks the claims and witnesses, and prints the theorem table.  Junction
// keys (proofs/materials.cert and materials_fan.cert, `space junctions`: squares with
// 3 or 4 materials) are enumerated and decided here too, from their own
// rules (junction_consistent, forced).  No global
// state: every operation gets what it needs.  Format 4 adds a `metric` line:
// `metric rhombic` certificates (proofs/rhombic_*.cert) measure the angles of
// the 60-degree rhombic lattice in lattice coordinates, with this file's own
// copy of its forms (Key::tri) and a rational enclosure of sqrt 3 for the
// degrees (sqrt3_enclosure); unknown metrics are refused.  Exit status: 0 every
// certificate verified and every theorem an angle bound; 1 a certificate
// rejected (any failure); 3 verified, but a theorem states no bound (a key
// `inverted`, with an exact witness: a counter-example, not a proof); 2 usage.
// Format and semantics: proofs/README.md.
#include <algorithm>
#include <array>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <boost/multiprecision/cpp_int.hpp>

using Q = boost::multiprecision::cpp_rational;
using Z = boost::multiprecision::cpp_int;

struct Fail {
    std::string msg;
};
[[noreturn]] void fail(const std::string& m) { throw Fail{m}; }

// ---- parsing (hostile input: bounded sizes, digits only) ---------------------
bool digits(const std::string& s, std::size_t from) {
    if (s.size() <= from || s.size() - from > 40) return false;
    for (std::size_t i = from; i < s.size(); ++i)
        if (s[i] < '0' || s[i] > '9') return false;
    return true;
}
Z parse_int(const std::string& s) {
    if (!digits(s, s.size() && s[0] == '-' ? 1 : 0)) fail("bad integer '" + s.substr(0, 60) + "'");
    return Z(s);
}
Q parse_q(const std::string& s) {
    const auto slash = s.find('/');
    if (slash == std::string::npos) return Q(parse_int(s));
    const Z d = parse_int(s.substr(slash + 1));
    if (d <= 0) fail("bad denominator in '" + s.substr(0, 60) + "'");
    return Q(parse_int(s.substr(0, slash)), d);
}
long small_int(const std::string& s, long lo, long hi) {
    const Z z = parse_int(s);
    if (z < lo || z > hi) fail("integer out of range: '" + s.substr(0, 60) + "'");
    return z.convert_to<long>();
}

// ---- configurations ------------------------------------------------------------
// Corner c at (c%2, c/2); warp 0 stay, 1 +x, 2 -x, 3 +y, 4 -y.  Junction
// keys (multi-material squares with 3 or 4 materials, `space junctions`):
// letter = the corner's material class 0..3 (first appearance A..D), sign 0.
struct St {
    int sign, warp;
    int letter = -1;  // >= 0: a junction key
};
const int DX[5] = {0, 1, -1, 0, 0}, DY[5] = {0, 0, 0, 1, -1};
const char WCH[5] = {'s', 'R', 'L', 'U', 'D'};
int target_corner(int c, int w) {  // corner reached by an inward slide, else -1
    const int x = c % 2 + DX[w], y = c / 2 + DY[w];
    return (w == 0 || x < 0 || x > 1 || y < 0 || y > 1) ? -1 : x + 2 * y;
}
bool consistent(const std::array<St, 4>& k) {
    for (int c = 0; c < 4; ++c) {
        if (k[c].warp == 0) continue;
        if (k[c].sign == 0) return false;
        const int n = target_corner(c, k[c].warp);
        if (n >= 0 && (k[n].sign != -k[c].sign || target_corner(n, k[n].warp) == c)) return false;
    }
    const int E[4][2] = {{0, 1}, {1, 3}, {3, 2}, {2, 0}};
    for (auto& e : E)
        if (k[e[0]].sign != 0 && k[e[0]].sign == -k[e[1]].sign && !k[e[0]].warp && !k[e[1]].warp) return false;
    return true;
}
// The key code and the flatness test below are independent copies, on purpose:
// the untrusted side's single copies are key_code and stencil_admits_flat
// (mesher/include/warpmesh/certified.hpp), used by the mesher and the prover.
std::string code(const std::array<St, 4>& k) {
    std::string s;
    for (auto& x : k) s += std::string(1, x.letter >= 0 ? static_cast<char>('a' + x.letter) : "-0+"[x.sign + 1]) + WCH[x.warp];
    return s;
}
// Junction keys (proofs/README.md, "Junction keys"), from the multi-material
// mesher: a side is cut iff its ends' letters differ; one cut point and one
// mover per cut side; a corner slides only along a cut edge of its own (an
// outward slide's neighbour is outside the key: free); every cut side has a
// warped end.  Letters are in first-appearance order with >= 3 of them.
bool junction_consistent(const std::array<St, 4>& k) {
    int next = 0;
    for (auto& x : k) {
        if (x.letter > next) return false;
        next += x.letter == next;
    }
    if (next < 3) return false;
    for (int c = 0; c < 4; ++c) {
        const int n = target_corner(c, k[c].warp);
        if (n >= 0 && (k[n].letter == k[c].letter || target_corner(n, k[n].warp) == c)) return false;
    }
    const int E[4][2] = {{0, 1}, {1, 3}, {3, 2}, {2, 0}};
    for (auto& e : E)
        if (k[e[0]].letter != k[e[1]].letter && !k[e[0]].warp && !k[e[1]].warp) return false;
    return true;
}
// Flat-compatible: some a x + b y + c has the corner signs and the opposite
// sign at the outside neighbour of every outward slide.  By homogeneity, strict
// signs become s (a x + b y + c) >= 1; zeros stay = 0.  A non-empty polyhedron
// contains a point solving 3 independent rows taken among its constraints made
// tight and the coordinate rows w_j = 0, so trying all such 3x3 systems
// (Cramer, integers) decides feasibility exactly.
bool flat(const std::array<St, 4>& k) {
    std::vector<std::array<long, 4>> rows;  // r . w (>= if r[3] = 1, == if r[3] = 0) r[3]
    for (int c = 0; c < 4; ++c) {
        const long x = c % 2, y = c / 2, s = k[c].sign;
        rows.push_back(s != 0 ? std::array<long, 4>{s * x, s * y, s, 1} : std::array<long, 4>{x, y, 1, 0});
        if (k[c].warp && target_corner(c, k[c].warp) < 0)
            rows.push_back({-s * (x + DX[k[c].warp]), -s * (y + DY[k[c].warp]), -s, 1});
    }
    std::vector<std::array<long, 4>> cand = rows;
    cand.push_back({1, 0, 0, 0}), cand.push_back({0, 1, 0, 0}), cand.push_back({0, 0, 1, 0});
    auto det = [](const std::array<long, 4>& a, const std::array<long, 4>& b, const std::array<long, 4>& c, int col) {
        auto e = [&](const std::array<long, 4>& r, int j) { return j == col ? r[3] : r[j]; };
        return e(a, 0) * (e(b, 1) * e(c, 2) - e(b, 2) * e(c, 1)) - e(a, 1) * (e(b, 0) * e(c, 2) - e(b, 2) * e(c, 0)) +
               e(a, 2) * (e(b, 0) * e(c, 1) - e(b, 1) * e(c, 0));
    };
    for (std::size_t i = 0; i < cand.size(); ++i)
        for (std::size_t j = i + 1; j < cand.size(); ++j)
            for (std::size_t l = j + 1; l < cand.size(); ++l) {
                const long D = det(cand[i], cand[j], cand[l], -1);
                if (D == 0) continue;
                const long N[3] = {det(cand[i], cand[j], cand[l], 0), det(cand[i], cand[j], cand[l], 1),
                                   det(cand[i], cand[j], cand[l], 2)};
                bool ok = true;  // w = N / D
                for (auto& r : rows) {
                    const long v = r[0] * N[0] + r[1] * N[1] + r[2] * N[2];
                    ok = ok && (r[3] ? (D > 0 ? v >= D : v <= D) : v == 0);
                }
                if (ok) return true;
            }
    return false;
}
// Separating rule: opposite corners both staying with opposite non-zero signs
// force the other diagonal.  Returns 0 none, 1 AD, 2 BC.
int forced(const std::array<St, 4>& k) {
    if (k[0].letter >= 0) {  // junction keys: both staying with different materials
        if (!k[0].warp && !k[3].warp && k[0].letter != k[3].letter) return 2;
        if (!k[1].warp && !k[2].warp && k[1].letter != k[2].letter) return 1;
        return 0;
    }
    auto ss = [&](int c) { return k[c].warp == 0 && k[c].sign != 0; };
    if (ss(0) && ss(3) && k[0].sign == -k[3].sign) return 2;
    if (ss(1) && ss(2) && k[1].sign == -k[2].sign) return 1;
    return 0;
}

// ---- exact interval arithmetic with derivatives ---------------------------------
// Boxes and claims are dyadic, and the forms use only + - *, so they are
// evaluated exactly on dyadic numbers m 2^e (no gcd: fast); divisions (the
// rule's quality comparisons, witnesses, degrees) use rationals.
struct N {
    Z m;
    long e = 0;
    N() = default;
    N(int v) : m(v) {}
    N(Z mm, long ee) : m(std::move(mm)), e(ee) {}
};
N align(const N& a, long e) { return N(a.m << static_cast<unsigned>(a.e - e), e); }
N operator+(const N& a, const N& b) {
    if (a.e == b.e) return N(a.m + b.m, a.e);
    return a.e < b.e ? N(a.m + align(b, a.e).m, a.e) : N(align(a, b.e).m + b.m, b.e);
}
N operator-(const N& a) { return N(-a.m, a.e); }
N operator-(const N& a, const N& b) { return a + (-b); }
N operator*(const N& a, const N& b) {
    if (a.m == 0 || b.m == 0) return N(0);
    if (a.e + b.e < -4000) fail("number too small");
    return N(a.m * b.m, a.e + b.e);
}
int cmp(const N& a, const N& b) {
    const N d = a - b;
    return d.m > 0 ? 1 : d.m < 0 ? -1 : 0;
}
bool operator<(const N& a, const N& b) { return cmp(a, b) < 0; }
bool operator>(const N& a, const N& b) { return cmp(a, b) > 0; }
bool operator<=(const N& a, const N& b) { return cmp(a, b) <= 0; }
bool operator>=(const N& a, const N& b) { return cmp(a, b) >= 0; }
bool operator==(const N& a, const N& b) { return cmp(a, b) == 0; }
Q toQ(const N& a) {
    if (a.e >= 0) return Q(a.m << static_cast<unsigned>(a.e));
    return Q(a.m, Z(1) << static_cast<unsigned>(-a.e));
}
N dyadic(const Q& q) {  // exact, or rejected
    const Z d = denominator(q);
    if ((d & (d - 1)) != 0) fail("number is not dyadic");
    return N(numerator(q), -static_cast<long>(msb(d)));
}
struct RQ {
    Q lo, hi;
};
struct R {
    N lo, hi;
};
R operator+(const R& a, const R& b) { return {a.lo + b.lo, a.hi + b.hi}; }
R operator-(const R& a, const R& b) { return {a.lo - b.hi, a.hi - b.lo}; }
R operator*(const R& a, const R& b) {
    const N p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
    R r{p[0], p[0]};
    for (const N& x : p) r.lo = x < r.lo ? x : r.lo, r.hi = x > r.hi ? x : r.hi;
    return r;
}
RQ quot(const R& a, const R& b) {  // b > 0
    const Q al = toQ(a.lo), ah = toQ(a.hi), bl = toQ(b.lo), bh = toQ(b.hi);
    const Q p[4] = {al / bl, al / bh, ah / bl, ah / bh};
    RQ r{p[0], p[0]};
    for (const Q& x : p) r.lo = x < r.lo ? x : r.lo, r.hi = x > r.hi ? x : r.hi;
    return r;
}
struct D {  // value and partial derivatives in the key's variables
    R v;
    std::array<R, 4> d;  // d[i] for i < n; the others are 0 and never read
    int n = 0;           // partials carried: 0 for constants and value-only passes
};
D operator+(const D& a, const D& b) {
    D r{a.v + b.v, {}, std::max(a.n, b.n)};
    for (int i = 0; i < r.n; ++i) r.d[i] = a.d[i] + b.d[i];
    return r;
}
D operator-(const D& a, const D& b) {
    D r{a.v - b.v, {}, std::max(a.n, b.n)};
    for (int i = 0; i < r.n; ++i) r.d[i] = a.d[i] - b.d[i];
    return r;
}
D operator*(const D& a, const D& b) {
    D r{a.v * b.v, {}, std::max(a.n, b.n)};
    for (int i = 0; i < r.n; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
    return r;
}
D cst(const N& q) { return D{{q, q}, {R{0, 0}, R{0, 0}, R{0, 0}, R{0, 0}}, 0}; }

using Box = std::vector<R>;  // one interval per warped corner (in corner order)
struct Tri {
    D cross;
    std::array<D, 3> dot;
};
const int TRI[2][2][3] = {{{0, 1, 3}, {0, 3, 2}}, {{0, 1, 2}, {1, 3, 2}}};  // AD, BC

struct Key {
    std::array<St, 4> s;
    std::vector<int> vars;
    std::array<D, 2> pos[4];
    // The metric (format 4's `metric` line): false the square lattice, dot =
    // u . v; true the rhombic lattice measured in lattice coordinates,
    // G = [[1, 1/2], [1/2, 1]], dot = 2 u . G v = 2 (ux vx + uy vy) + ux vy + uy vx,
    // cross = ux vy - uy vx as on the square: dot / cross = sqrt(3) cot(angle).
    bool rhombic = false;
    // Corner positions on box b; with `partials`, their derivatives in the
    // key's variables as well (carried through every form computed from them).
    void positions(const Box& b, bool partials) {
        for (int c = 0; c < 4; ++c) {
            D t = cst(0);
            t.n = partials ? static_cast<int>(vars.size()) : 0;
            for (std::size_t j = 0; j < vars.size(); ++j)
                if (vars[j] == c) t.v = b[j], t.d[j] = partials ? R{1, 1} : R{0, 0};
            pos[c][0] = cst(c % 2), pos[c][1] = cst(c / 2);
            if (DX[s[c].warp]) pos[c][0] = pos[c][0] + cst(DX[s[c].warp]) * t;
            if (DY[s[c].warp]) pos[c][1] = pos[c][1] + cst(DY[s[c].warp]) * t;
        }
    }
    // diag 0 AD, 1 BC (triangle k = 0, 1); diag 2 the fan rule's centroid fan
    // (k = 0..3), computed on the corners scaled by 4 and the centre
    // A + B + C + D (cotangents are scale-invariant; no division needed).
    Tri tri(int diag, int k) const {
        std::array<std::array<D, 2>, 5> P;
        for (int c = 0; c < 4; ++c) P[c] = pos[c];
        int v[3];
        if (diag == 2) {
            for (int c = 0; c < 4; ++c) P[c] = {cst(4) * pos[c][0], cst(4) * pos[c][1]};
            for (int a = 0; a < 2; ++a) P[4][a] = pos[0][a] + pos[1][a] + pos[2][a] + pos[3][a];
            const int ring[4] = {0, 1, 3, 2};  // A B D C, counter-clockwise
            v[0] = ring[k], v[1] = ring[(k + 1) % 4], v[2] = 4;
        } else {
            for (int i = 0; i < 3; ++i) v[i] = TRI[diag][k][i];
        }
        Tri t;
        for (int i = 0; i < 3; ++i) {
            const auto &o = P[v[i]], &q = P[v[(i + 1) % 3]], &r = P[v[(i + 2) % 3]];
            const D ux = q[0] - o[0], uy = q[1] - o[1], vx = r[0] - o[0], vy = r[1] - o[1];
            t.dot[i] = ux * vx + uy * vy;
            if (rhombic) t.dot[i] = cst(2) * t.dot[i] + (ux * vy + uy * vx);
            if (i == 0) t.cross = ux * vy - uy * vx;
        }
        return t;
    }
};

// Form f of a triangle: 0 cross > 0; 1..3 qmin cross - dot >= 0; 4..6 dot - qmax cross >= 0.
D form(const Tri& t, int f, const N& qmin, const N& qmax) {
    if (f == 0) return t.cross;
    if (f <= 3) return cst(qmin) * t.cross - t.dot[f - 1];
    return t.dot[f - 4] - cst(qmax) * t.cross;
}
// g >= 0 (strict: g > 0) on box b, where g = eval(k) once k.positions is set.
// Tried in turn: the natural interval extension on b, and the mean-value form
// around the centre c of b, g(b) in g(c) + sum_j d_j g(b) [-r_j, r_j] (r_j the
// half-widths; mean-value theorem on the segment from c).  While neither
// proves it, every variable with a sign-definite partial derivative is fixed at
// the end where g is smallest, and both are tried on that face.
template <class F>
bool verify_poly(Key& k, Box b, bool strict, const F& eval) {
    for (;;) {
        k.positions(b, true);
        const D g = eval(k);
        if (strict ? g.v.lo > 0 : g.v.lo >= 0) return true;
        Box c = b;
        for (R& x : c) {
            N mid = x.lo + x.hi;
            mid.e -= 1;
            x = R{mid, mid};
        }
        k.positions(c, false);
        N lo = eval(k).v.lo;
        for (std::size_t j = 0; j < b.size(); ++j) {
            N r = b[j].hi - b[j].lo;
            r.e -= 1;
            const N mag = -g.d[j].lo > g.d[j].hi ? -g.d[j].lo : g.d[j].hi;
            if (r.m != 0) lo = lo - r * mag;
        }
        if (strict ? lo > 0 : lo >= 0) return true;
        bool fixed = false;
        for (std::size_t j = 0; j < b.size(); ++j) {
            if (b[j].lo == b[j].hi) continue;
            if (g.d[j].lo >= 0) b[j].hi = b[j].lo, fixed = true;
            else if (g.d[j].hi <= 0) b[j].lo = b[j].hi, fixed = true;
        }
        if (!fixed) return false;
    }
}
// Form f of triangle `tri` of `diag` on the box; `first`: its value on the
// whole box, already computed (a cheap first test without partials).
bool verify_form(Key& k, const Box& b, int diag, int tri, int f, const N& qmin, const N& qmax, const Tri* first) {
    if (first) {
        const D g = form(*first, f, qmin, qmax);
        if (f == 0 ? g.v.lo > 0 : g.v.lo >= 0) return true;
    }
    return verify_poly(k, b, f == 0, [&](Key& kk) { return form(kk.tri(diag, tri), f, qmin, qmax); });
}
// Switching leaves (tag S): for ratio k of diagonal d (3 t + i: vertex i of
// its triangle t) and ratio j of the other diagonal o,
// h = kappa dot_j(o) cross(d, t) - dot_k(d) cross(o, j / 3), kappa = 1 + 2^-30: where
// d is taken and o is valid, some h_j >= 0 (proofs/README.md, "Double
// agreement", item 6).  Positions must be set.
D ratio_h(const Key& k, int d, int kk, int j) {
    const Tri td = k.tri(d, kk / 3), to = k.tri(1 - d, j / 3);
    return cst(N(1) + N(Z(1), -30)) * to.dot[j % 3] * td.cross - td.dot[kk % 3] * to.cross;
}
// q(diag) = max over its triangles of max_i dot_i / cross (crosses > 0 required).
bool valid_q(Key& k, int diag, RQ& q) {
    for (int t = 0; t < 2; ++t) {
        const Tri tr = k.tri(diag, t);
        if (!(tr.cross.v.lo > 0)) return false;
        R m = tr.dot[0].v;
        for (int i = 1; i < 3; ++i)
            m.lo = std::max(m.lo, tr.dot[i].v.lo), m.hi = std::max(m.hi, tr.dot[i].v.hi);
        const RQ r = quot(m, tr.cross.v);
        if (t == 0) q = r;
        else q.lo = std::max(q.lo, r.lo), q.hi = std::max(q.hi, r.hi);
    }
    return true;
}
bool invalid(Key& k, int diag) { return !(k.tri(diag, 0).cross.v.hi > 0) || !(k.tri(diag, 1).cross.v.hi > 0); }
// The max-min rule takes `win` (0 AD, 1 BC) on the whole box, and the
// mesher's double evaluation takes it too.  Positions must be set.
// Agreement margins (proofs/README.md, "Double agreement"): a diagonal decided
// by comparing the qualities q must win by the relative margin 2^-30, i.e.
// q(winner) + 2^-30 M < q(loser) on the box, with M the largest |end| of the
// two enclosures (the prover demands 1e-9 of its outward-rounded enclosures,
// which contain these exact ones; 1e-9 - 2^-30 covers its round-to-nearest
// test).  A threshold H must exceed q(win) by the relative margin 2^-28:
// q(win) (1 + 2^-28) <= H.  Decisions by validity (a cross <= 0 on the whole
// box) carry no margin.  Ties: the mesher breaks an exact tie q(AD) = q(BC)
// by the square's position (either diagonal may be taken), so a comparison
// decides only where the winner is strictly better on the whole box (A:
// q(BC) > q(AD), B: q(BC) < q(AD)); a box where they may tie is undecided
// (X or S: bounded on both diagonals).  The margin implies strictness (M > 0:
// every valid triangle has q >= cot 60 deg > 0); it is tested on its own too.
enum Decision { undecided, without_margin, decided_with_margin };
Decision decided(Key& k, int win, bool threshold, const N& h) {
    const int other = 1 - win;
    if (threshold) {  // win valid, q(win) <= h, and some dot_i - h cross > 0 on the other diagonal
        Q qw = 0;
        bool first = true;
        for (int t = 0; t < 2; ++t) {
            const Tri tr = k.tri(win, t);
            if (!(tr.cross.v.lo > 0)) return undecided;
            for (auto& d : tr.dot) {
                const Q q = quot(d.v, tr.cross.v).hi;
                if (first || q > qw) qw = q;
                first = false;
            }
        }
        const Q H = toQ(h);
        if (qw > H) return undecided;
        for (int t = 0; t < 2; ++t) {
            const Tri tr = k.tri(other, t);
            for (auto& d : tr.dot)
                if ((d.v - R{h, h} * tr.cross.v).lo > 0)
                    return qw * (1 + Q(1, Z(1) << 28)) <= H ? decided_with_margin : without_margin;
        }
        return undecided;
    }
    RQ qa, qb;
    auto margin = [&]() -> Q {  // 2^-30 max |end| (a Q, not an expression template over locals)
        Q m = 0;
        for (const Q& x : {qa.lo, qa.hi, qb.lo, qb.hi}) m = std::max(m, Q(abs(x)));
        return m / (Z(1) << 30);
    };
    if (win == 0) {  // BC invalid, or both valid with q(BC) >= q(AD)
        if (invalid(k, 1)) return decided_with_margin;
        if (!valid_q(k, 0, qa) || !valid_q(k, 1, qb) || !(qb.lo > qa.hi)) return undecided;
        return qb.lo >= qa.hi + margin() ? decided_with_margin : without_margin;
    }
    if (!valid_q(k, 1, qb)) return undecided;  // BC valid, and AD invalid or q(BC) < q(AD)
    if (invalid(k, 0)) return decided_with_margin;
    if (!valid_q(k, 0, qa) || !(qb.hi < qa.lo)) return undecided;
    return qb.hi + margin() < qa.lo ? decided_with_margin : without_margin;
}

// The fan rule (proofs/README.md, "The fan rule"): H0 = 3 + 2^-20; a diagonal
// excluded at H0 (1 + 2^-28) does not qualify, in exact or double arithmetic;
// one verified at H0 (1 - 2^-28) qualifies in both; one the mesher lets
// qualify has exact q <= H0 (1 + 2^-30).
N fan_h0() { return N(3) + N(Z(1), -20); }
N fan_scaled(int sign, int e) { return fan_h0() + N(sign) * fan_h0() * N(Z(1), -e); }
// Every corner inside (sign <= 0, or warped onto the level set): the squares
// on which the fan rule may take the fan.  Junction keys (materials): the
// staying corners share one letter (the fan then takes that material).
bool all_inside(const std::array<St, 4>& k) {
    int letter = -1;
    for (auto& c : k) {
        if (c.warp != 0) continue;
        if (c.letter < 0 && c.sign > 0) return false;
        if (c.letter >= 0 && letter >= 0 && c.letter != letter) return false;
        if (c.letter >= 0) letter = c.letter;
    }
    return true;
}
// Diagonal d does not qualify anywhere on the box: some dot_i - h cross > 0.
bool excluded(Key& k, int d, const N& h) {
    for (int t = 0; t < 2; ++t) {
        const Tri tr = k.tri(d, t);
        for (auto& dt : tr.dot)
            if ((dt.v - R{h, h} * tr.cross.v).lo > 0) return true;
    }
    return false;
}

// ---- exact point evaluation (witnesses) -------------------------------------------
struct PointVal {
    bool valid;
    Q qmin, qmax;  // largest and smallest cot of the chosen triangles' angles
};
PointVal at_point(Key& k, bool separating, bool fanrule, const std::vector<Q>& t) {
    Box b;
    for (auto& x : t) b.push_back(R{dyadic(x), dyadic(x)});
    k.positions(b, false);
    int diag = separating && forced(k.s) ? forced(k.s) - 1 : -1;
    if (diag < 0) {
        RQ qa, qb;
        const bool va = valid_q(k, 0, qa), vb = valid_q(k, 1, qb);
        // AD on an exact tie: its value is attained there (by the squares
        // whose position-dependent tie-break is AD), which is all a witness says.
        diag = vb && (!va || qb.lo < qa.lo) ? 1 : 0;
        const Q h = toQ(fan_h0());
        if (fanrule && all_inside(k.s) && !(va && qa.lo <= h) && !(vb && qb.lo <= h)) diag = 2;  // the fan
    }
    PointVal p{true, 0, 0};
    bool first = true;
    for (int t = 0; t < (diag == 2 ? 4 : 2); ++t) {
        const Tri tr = k.tri(diag, t);
        if (tr.cross.v.lo <= 0) {
            p.valid = false;
            continue;
        }
        for (auto& d : tr.dot) {
            const Q c = toQ(d.v.lo) / toQ(tr.cross.v.lo);
            if (first || c > p.qmin) p.qmin = c;
            if (first || c < p.qmax) p.qmax = c;
            first = false;
        }
    }
    return p;
}

// ---- rigorous degrees for the report ------------------------------------------------
RQ atan_ser(const Q& z) {  // |z| <= 1/2, alternating series, error < next term
    Q s = 0, p = z;
    for (int n = 0; n < 40; ++n, p *= z * z) s += (n % 2 ? -p : p) / (2 * n + 1);
    const Q e = abs(p) / 81;
    return {s - e, s + e};
}
RQ deg(const Q& cot) {  // the angle in degrees whose cotangent is cot
    const RQ a5 = atan_ser(Q(1, 5)), a239 = atan_ser(Q(1, 239));
    const RQ pi{16 * a5.lo - 4 * a239.hi, 16 * a5.hi - 4 * a239.lo};
    if (cot == 0) return {90, 90};
    const Q y = 1 / abs(cot);
    RQ a;  // atan(y) / pi
    if (y <= Q(1, 2)) a = atan_ser(y), a = {a.lo / pi.hi, a.hi / pi.lo};
    else if (y <= 2) {
        const RQ s = atan_ser((y - 1) / (y + 1));
        a = {Q(1, 4) + std::min(s.lo / pi.hi, s.lo / pi.lo), Q(1, 4) + std::max(s.hi / pi.lo, s.hi / pi.hi)};
    } else {
        const RQ s = atan_ser(1 / y);
        a = {Q(1, 2) - s.hi / pi.lo, Q(1, 2) - s.lo / pi.hi};
    }
    return cot > 0 ? RQ{180 * a.lo, 180 * a.hi} : RQ{180 - 180 * a.hi, 180 - 180 * a.lo};
}
std::string dec(const Q& q, bool up, int digits = 10) {  // `digits` decimals, rounded outward
    Z scale = 1;
    for (int i = 0; i < digits; ++i) scale *= 10;
    const Q s = q * Q(scale);
    Z n = numerator(s) / denominator(s);
    if (Q(n) > s) n -= 1;
    if (up && Q(n) < s) n += 1;
    std::string d = (n < 0 ? -n : n).str();
    while (static_cast<int>(d.size()) <= digits) d = "0" + d;
    return std::string(n < 0 ? "-" : "") + d.substr(0, d.size() - digits) + "." + d.substr(d.size() - digits);
}
// sqrt 3 in [n, n + 1] / 10^20, n = isqrt(3 10^40), checked here exactly.
RQ sqrt3_enclosure() {
    const Z scale = boost::multiprecision::pow(Z(10), 20), three = 3 * scale * scale;
    const Z n = boost::multiprecision::sqrt(three);
    if (!(n * n < three && three < (n + 1) * (n + 1))) fail("internal: sqrt 3 enclosure");
    return {Q(n, scale), Q(n + 1, scale)};
}
// The angle in degrees whose ratio dot / cross is r: r is the cotangent on the
// square lattice; on the rhombic one r = sqrt(3) cot, so cot lies between
// r / hi and r / lo (sqrt 3 in [lo, hi]) and, the angle being monotone in
// cot, it lies in the union of the two enclosures (outward).
RQ deg_r(const Q& r, bool rhombic) {
    if (!rhombic) return deg(r);
    const RQ s = sqrt3_enclosure(), a = deg(r / s.lo), b = deg(r / s.hi);
    return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)};
}
std::string degs(const Q& r, bool rhombic) {
    const RQ d = deg_r(r, rhombic);
    return "[" + dec(d.lo, false) + ", " + dec(d.hi, true) + "] deg";
}

// ---- tightness of the key claims ----------------------------------------------------
// Upper bound, in degrees, of the angle between the angles whose cotangents
// are a and b: with a <= b these are arccot a >= arccot b, and
// tan(arccot a - arccot b) = (b - a)/(1 + a b); atan x <= x for x >= 0, and
// 180/pi < 180/(314159/100000).  Rational throughout; 180 if 1 + a b <= 0.
// Rhombic metric (a, b ratios r = sqrt(3) cot): the tangent is
// sqrt(3) (b - a) / (3 + a b), bounded with sqrt 3's upper end; 180 if 3 + a b <= 0.
Q gap_deg(const Q& a, const Q& b, bool rhombic) {
    const Q lo = a < b ? a : b, hi = a < b ? b : a;
    if (!rhombic) {
        if (1 + lo * hi <= 0) return 180;
        return (hi - lo) / (1 + lo * hi) * Q(18000000, 314159);
    }
    if (3 + lo * hi <= 0) return 180;
    return sqrt3_enclosure().hi * (hi - lo) / (3 + lo * hi) * Q(18000000, 314159);
}
struct Tightness {
    Q target;
    long keys = 0, within = 0, keys_flat = 0, within_flat = 0;
    Q worst = 0;
    std::string worst_key = "-";
    std::array<long, 4> over{};  // gaps in (target, 1], (1, 5], (5, 20], > 20 deg
    void add(const Q& g, const std::string& key, bool flat) {
        ++keys, keys_flat += flat;
        if (g <= target) ++within, within_flat += flat;
        else ++over[g <= 1 ? 0 : g <= 5 ? 1 : g <= 20 ? 2 : 3];
        if (g > worst) worst = g, worst_key = key;
    }
};

// ---- certificate -----------------------------------------------------------------------
struct Reader {
    std::vector<std::vector<std::string>> lines;
    std::size_t at = 0;
    const std::vector<std::string>& next(const char* what) {
        if (at >= lines.size()) fail(std::string("truncated: expected ") + what);
        return lines[at++];
    }
};

// ---- leaves ------------------------------------------------------------------------------
struct Cover {  // rebuilds the bisection tree: widest side first (lowest index on ties), halves in order
    Key& k;
    bool sep;
    bool fan;  // fan rule and every corner inside
    N qmin, qmax;
    Reader& rd;
    long remaining;
    long leaves = 0;
    void leaf_or_split(const Box& b, int depth) {
        if (depth > 260) fail("key " + code(k.s) + ": leaves do not tile the box");
        if (remaining <= 0 || rd.at >= rd.lines.size()) fail("key " + code(k.s) + ": missing leaves");
        const auto& L = rd.lines[rd.at];
        const std::size_t m = k.vars.size();
        if (L.size() < 2 + 2 * m || L[0].size() != 1) fail("key " + code(k.s) + ": malformed leaf");
        const long e = small_int(L[1], 0, 62);
        Box lb(m);
        for (std::size_t j = 0; j < m; ++j)
            lb[j] = R{N(parse_int(L[2 + 2 * j]), -e), N(parse_int(L[3 + 2 * j]), -e)};
        bool equal = true, inside = true;
        for (std::size_t j = 0; j < m; ++j) {
            equal = equal && lb[j].lo == b[j].lo && lb[j].hi == b[j].hi;
            inside = inside && lb[j].lo >= b[j].lo && lb[j].hi <= b[j].hi && lb[j].lo < lb[j].hi;
        }
        if (equal) {
            ++rd.at, --remaining, ++leaves;
            verify_leaf(L, b);
            return;
        }
        if (!inside) fail("key " + code(k.s) + ": leaf " + std::to_string(leaves) + " does not tile the box");
        std::size_t s = 0;
        for (std::size_t j = 1; j < m; ++j)
            if (b[j].hi - b[j].lo > b[s].hi - b[s].lo) s = j;
        N mid = b[s].lo + b[s].hi;
        mid.e -= 1;
        Box l = b, r = b;
        l[s].hi = mid, r[s].lo = mid;
        leaf_or_split(l, depth + 1);
        leaf_or_split(r, depth + 1);
    }
    // Forms f0..f1-1 of the first `ntri` triangles of `diag` on box b, with the
    // min-angle bound `qmn`.
    bool forms_hold(const Box& b, int diag, int ntri, int f0, int f1, const N& qmn) {
        for (int t = 0; t < ntri; ++t) {
            k.positions(b, false);  // verify_form leaves the positions of a face or a point
            const Tri tr = k.tri(diag, t);
            for (int form = f0; form < f1; ++form)
                if (!verify_form(k, b, diag, t, form, qmn, qmax, &tr)) return false;
        }
        return true;
    }
    void verify_leaf(const std::vector<std::string>& L, const Box& b) {
        const char c = L[0][0];
        const std::size_t m = k.vars.size();
        const bool thr = c == 'a' || c == 'b';
        if (c == 'S' ? L.size() < 4 + 2 * m : L.size() != 2 + 2 * m + (thr ? 1 : 0)) fail("key " + code(k.s) + ": malformed leaf");
        if (c != 'A' && c != 'B' && c != 'X' && c != 'S' && !thr && !(fan && (c == 'F' || c == 'Y')))
            fail("key " + code(k.s) + ": bad diagonal tag");
        const std::string where = "key " + code(k.s) + " leaf " + std::to_string(leaves) + ": ";
        const int f = sep ? forced(k.s) : 0;
        k.positions(b, false);
        if (fan && (c == 'F' || c == 'Y')) return verify_fan_leaf(c, b, where);
        // On a fan square a diagonal leaf also shows that the fan is not taken:
        // the diagonal's min-angle forms hold with H0 (1 - 2^-28) (it qualifies).
        const N keep = fan_scaled(-1, 28);
        const N dmin = fan && keep < qmin ? keep : qmin;
        if (f && !(c == "?AB"[f])) fail(where + "separating rule forces the other diagonal");
        if (!f && c != 'X' && c != 'S') {
            const Decision d = decided(k, (c == 'B' || c == 'b') ? 1 : 0, thr, thr ? dyadic(parse_q(L.back())) : N(0));
            if (d == undecided) fail(where + "claimed diagonal is not decided on the box");
            if (d == without_margin) fail(where + "diagonal decided without the double-agreement margin");
        }
        if (c == 'X' || c == 'S') return verify_undecided_leaf(L, b, where, dmin);
        if (!forms_hold(b, (c == 'B' || c == 'b') ? 1 : 0, 2, 0, 7, dmin))
            fail(where + "angle or orientation inequality not verified");
    }
    // `F`: both diagonals excluded, the rule takes the fan.  `Y`: the fan or a
    // qualifying diagonal (q <= H0 (1 + 2^-30)); the max angle on each diagonal
    // not excluded on the box (an excluded one never qualifies, and the max-min
    // pick qualifies whenever some diagonal does).  Both: the fan whole.
    void verify_fan_leaf(char c, const Box& b, const std::string& where) {
        const N h = fan_scaled(1, 28);
        if (c == 'F') {
            if (!excluded(k, 0, h) || !excluded(k, 1, h)) fail(where + "fan not decided on the box");
        } else {
            if (qmin < fan_scaled(1, 30)) fail(where + "undecided fan leaf needs qmin >= H0 (1 + 2^-30)");
            for (int d = 0; d < 2; ++d) {
                k.positions(b, false);
                if (!excluded(k, d, h) && !forms_hold(b, d, 2, 4, 7, qmin)) fail(where + "max-angle inequality not verified");
            }
        }
        if (!forms_hold(b, 2, 4, 0, 7, qmin)) fail(where + "fan angle or orientation inequality not verified");
    }
    // `X` / `S`, undecided: one diagonal valid with the min-angle bound (the
    // rule takes a valid one at least as good), the max-angle bound on both
    // (S: on each diagonal where it is taken; per diagonal `-`, or
    // k:J:J2:mask and the multipliers).
    void verify_undecided_leaf(const std::vector<std::string>& L, const Box& b, const std::string& where, const N& dmin) {
        const char c = L[0][0];
        if (sep && forced(k.s)) fail(where + "undecided leaf on a forced key");
        if (!forms_hold(b, 0, 2, 0, 4, dmin) && !forms_hold(b, 1, 2, 0, 4, dmin))
            fail(where + "orientation/min-angle not verified");
        std::size_t at = 2 + 2 * k.vars.size();
        for (int d = 0; d < 2; ++d) {
            if (c == 'S' && at >= L.size()) fail(where + "malformed switching certificate");
            if (c == 'X' || L[at] == "-") {
                at += c == 'S';
                if (!forms_hold(b, d, 2, 4, 7, dmin)) fail(where + "max-angle inequality not verified");
                continue;
            }
            at = verify_switch(L, at, d, b, where, dmin);
        }
        if (at != L.size()) fail(where + "malformed switching certificate");
    }
    // One diagonal d's group `k:J:J2:mask` λ... of an `S` leaf at field `at`
    // (proofs/README.md, "Certificate format"); returns the field after it.
    std::size_t verify_switch(const std::vector<std::string>& L, std::size_t at, int d, const Box& b,
                              const std::string& where, const N& dmin) {
        std::vector<std::string> g(1);
        for (char ch : L[at]) {
            if (ch == ':') g.emplace_back();
            else g.back().push_back(ch);
        }
        if (g.size() != 4 || (g[1] == "-" && g[2] != "-")) fail(where + "malformed switching certificate");
        ++at;
        const int kk = static_cast<int>(small_int(g[0], 0, 5)), mask = static_cast<int>(small_int(g[3], 0, 63));
        std::vector<int> named;
        for (std::size_t n = 1; n <= 2; ++n)
            if (g[n] != "-") named.push_back(static_cast<int>(small_int(g[n], 0, 5)));
        k.positions(b, false);
        if (!(k.tri(1 - d, 0).cross.v.lo > 0) || !(k.tri(1 - d, 1).cross.v.lo > 0))
            fail(where + "switching leaf: the other diagonal is not valid on the box");
        for (int j = 0; j < 6; ++j)
            if (std::find(named.begin(), named.end(), j) == named.end() && !(ratio_h(k, d, kk, j).v.hi < 0))
                fail(where + "switching leaf: ratio " + std::to_string(j) + " not excluded");
        if (named.empty() && mask != 0) fail(where + "malformed switching certificate");
        for (int x = 0; x < 6 && !named.empty(); ++x) {  // forms outside the mask: outright
            const int t = x / 3, f = 4 + x % 3;
            k.positions(b, false);
            const Tri tr = k.tri(d, t);
            if (!(mask >> x & 1) && !verify_form(k, b, d, t, f, dmin, qmax, &tr))
                fail(where + "max-angle inequality not verified");
        }
        for (const int jj : named)
            for (int x = 0; x < 6; ++x) {
                if (!(mask >> x & 1)) continue;
                if (at >= L.size()) fail(where + "malformed switching certificate");
                const Q lq = parse_q(L[at++]);
                if (lq < 0) fail(where + "negative multiplier");
                const N lam = dyadic(lq);
                const int t = x / 3, f = 4 + x % 3;
                if (!verify_poly(k, b, false, [&](Key& kq) {
                        return form(kq.tri(d, t), f, dmin, qmax) - cst(lam) * ratio_h(kq, d, kk, jj);
                    }))
                    fail(where + "max-angle inequality not verified where the diagonal is taken");
            }
        return at;
    }
};

// ---- the certificate's lines, by kind ----------------------------------------------------
// One line into `line` (without its newline); false at the end of the input.
// A line longer than `max` bytes fails before more of it is read, so a stream
// without newlines is never held whole.
bool bounded_line(std::istream& in, std::string& line, std::size_t max) {
    line.clear();
    std::streambuf* sb = in.rdbuf();
    for (int c = sb->sbumpc(); c != std::char_traits<char>::eof(); c = sb->sbumpc()) {
        if (c == '\n') return true;
        if (line.size() == max) fail("certificate too large");
        line.push_back(static_cast<char>(c));
    }
    return !line.empty();
}

// The lines as whitespace-separated fields ('#' comments and blank lines
// dropped).  Hostile input is bounded: 256 MB, 2000000 lines (proofs/ has at
// most 363017), 4096 bytes and 40 fields a line.
Reader read_certificate(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("cannot read " + path);
    Reader rd;
    std::string line;
    std::size_t bytes = 0;
    while (bounded_line(in, line, 4096)) {
        bytes += line.size() + 1;
        if (bytes > (std::size_t(256) << 20) || rd.lines.size() >= 2000000) fail("certificate too large");
        if (line.empty() || line[0] == '#') continue;
        const auto blank = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
        // Fields counted first, so each line's vector is allocated once (the
        // tamper tests read whole certificates many times under ASan).
        std::size_t n = 0;
        for (std::size_t i = 0; i < line.size(); ++i) n += !blank(line[i]) && (i == 0 || blank(line[i - 1]));
        if (n > 40) fail("line too long");
        if (n == 0) continue;
        std::vector<std::string> tok;
        tok.reserve(n);
        for (std::size_t i = 0; i < line.size();) {
            if (blank(line[i])) { ++i; continue; }
            std::size_t j = i;
            while (j < line.size() && !blank(line[j])) ++j;
            tok.emplace_back(line, i, j - i);
            i = j;
        }
        rd.lines.push_back(std::move(tok));
    }
    if (rd.lines.empty()) fail("empty certificate");
    return rd;
}
void expect(const std::vector<std::string>& l, const std::string& w, std::size_t n) {
    if (l.empty() || l[0] != w || l.size() != n) fail("expected '" + w + "' line");
}

// `warpmesh-certificate 3` (the square lattice) or `warpmesh-certificate 4`
// followed by `metric square|rhombic`, then `rule maxmin|separating|fan` and,
// for the junction keys, `space junctions` (separating or fan rule; no flat
// category).  The rhombic metric is defined for the maxmin and separating
// rules on the sign keys only (the fan rule's threshold is a square-lattice
// cotangent; the rhombic mesher has no junctions).
struct Header {
    std::string rule;
    bool fanrule = false, sep = false, junctions = false, rhombic = false;
    int ncat() const { return junctions ? 1 : 2; }  // U, and F on sign keys
};
Header read_header(Reader& rd) {
    expect(rd.next("header"), "warpmesh-certificate", 2);
    const std::string version = rd.lines[0][1];
    if (version != "3" && version != "4") fail("unknown version");
    Header h;
    if (version == "4") {
        const auto& ml = rd.next("metric");
        expect(ml, "metric", 2);
        if (ml[1] != "square" && ml[1] != "rhombic") fail("unknown metric '" + ml[1].substr(0, 40) + "'");
        h.rhombic = ml[1] == "rhombic";
    }
    const auto& rl = rd.next("rule");
    expect(rl, "rule", 2);
    h.rule = rl[1];
    if (h.rule != "maxmin" && h.rule != "separating" && h.rule != "fan") fail("unknown rule");
    h.fanrule = h.rule == "fan";
    h.sep = h.rule == "separating" || h.fanrule;  // the fan rule forces as the separating rule does
    h.junctions = rd.at < rd.lines.size() && rd.lines[rd.at][0] == "space";
    if (h.junctions) {
        const auto& sl = rd.next("space");
        expect(sl, "space", 2);
        if (sl[1] != "junctions" || h.rule == "maxmin") fail("unknown key space (only 'junctions', separating or fan rule)");
    }
    if (h.rhombic && (h.fanrule || h.junctions)) fail("the rhombic metric has the maxmin and separating rules on sign keys only");
    return h;
}

// Own enumeration of the consistent keys, in canonical order (junction keys:
// a corner's state is letter * 5 + warp, corner A most significant).
std::vector<std::array<St, 4>> enumerate_keys(bool junctions) {
    std::vector<std::array<St, 4>> keys;
    for (int i = 0; i < (junctions ? 160000 : 14641); ++i) {
        std::array<St, 4> k;
        if (junctions) {
            for (int c = 3, r = i; c >= 0; --c, r /= 20) k[c] = St{0, r % 5, r % 20 / 5};
            if (junction_consistent(k)) keys.push_back(k);
            continue;
        }
        for (int c = 3, r = i; c >= 0; --c, r /= 11) k[c] = r % 11 == 0 ? St{0, 0} : St{r % 11 <= 5 ? -1 : 1, (r % 11 - 1) % 5};
        if (consistent(k)) keys.push_back(k);
    }
    return keys;
}
Key make_key(const std::array<St, 4>& s, const Header& hd) {
    Key k{s, {}, {}, hd.rhombic};
    for (int c = 0; c < 4; ++c)
        if (k.s[c].warp) k.vars.push_back(c);
    return k;
}
// A configuration of key k: one dyadic t in [0, 1/2] per warped corner, the
// fields [from, from + m) of l.
std::vector<Q> read_t(const std::vector<std::string>& l, std::size_t from, const Key& k, const std::string& what) {
    if (l.size() < from + k.vars.size()) fail(what + ": wrong number of t values");
    std::vector<Q> t;
    for (std::size_t j = 0; j < k.vars.size(); ++j) {
        t.push_back(parse_q(l[from + j]));
        if (t.back() < 0 || t.back() > Q(1, 2)) fail(what + ": witness t outside [0, 1/2]");
    }
    return t;
}

// `claim C <qmin> <qmax>` (a bound: qmax <= cot a <= qmin for every angle a
// of the category C's chosen triangles, all positively oriented) or
// `claim C inverted` (no bound: some configuration of C has a chosen triangle
// with cross <= 0), then the category's witnesses, `witness C min|max <key>
// <t...> <value>` or `witness C inverted <key> <t...>`.
struct Claim {
    bool present = false, inverted = false;
    Q qmin, qmax;
};
struct Wit {
    int cat;
    std::string kind, code;
    std::vector<std::string> fields;  // the witness line
};
struct Claims {
    Claim claim[2];
    std::vector<Wit> wits;
};
Claims read_claims(Reader& rd, const Header& hd) {
    Claims cl;
    while (rd.at < rd.lines.size() && (rd.lines[rd.at][0] == "claim" || rd.lines[rd.at][0] == "witness")) {
        const auto& l = rd.next("claim");
        if (l.size() < 3 || (l[1] != "U" && l[1] != "F")) fail("bad claim/witness line");
        const int c = l[1] == "F";
        if (l[0] == "witness") {
            if (l.size() < 4 || (l[2] != "min" && l[2] != "max" && l[2] != "inverted")) fail("bad witness line");
            cl.wits.push_back(Wit{c, l[2], l[3], l});
            continue;
        }
        Claim& k = cl.claim[c];
        if (k.present) fail("duplicate claim");
        k.present = true;
        if (l.size() == 3 && l[2] == "inverted") k.inverted = true;
        else if (l.size() == 4) k.qmin = parse_q(l[2]), k.qmax = parse_q(l[3]);
        else fail("bad claim line");
    }
    if (!cl.claim[0].present || cl.claim[1].present != !hd.junctions)
        fail(hd.junctions ? "junction keys: claim U only" : "missing claims");
    return cl;
}

// A key line's claim: `key <i> <code> <flat> <m> <qmin> <qmax> <leaves>` (a
// bound) or `key <i> <code> <flat> <m> inverted`.
struct KeyClaim {
    std::string code;
    bool flat = false, inverted = false;
    Q qmin, qmax;
};
// The fields every key line has: the enumeration's i-th key (none missing,
// none repeated), its flatness and its dimension.
void check_key_head(const std::vector<std::string>& h, const std::array<St, 4>& s, std::size_t i, const Header& hd) {
    if (h.size() < 6 || h[0] != "key") fail("expected key line");
    if (small_int(h[1], 0, 160000) != static_cast<long>(i) || h[2] != code(s)) fail("key " + std::to_string(i) + " is not " + code(s));
    if (small_int(h[3], 0, 1) != (!hd.junctions && flat(s))) fail("key " + code(s) + ": flatness flag differs");
    if (small_int(h[4], 0, 4) != static_cast<long>(make_key(s, hd).vars.size())) fail("key " + code(s) + ": dimension");
}
// An inverted key's witness line `winv <t_1> ... <t_m>` (wl, null if the
// certificate ends): a configuration of the key's box at which a chosen
// triangle has cross <= 0, in exact arithmetic.
void check_inverted_key(const std::vector<std::string>* wl, const std::array<St, 4>& s, const Header& hd) {
    Key k = make_key(s, hd);
    const std::string name = "key " + code(s);
    if (!wl || (*wl)[0] != "winv") fail(name + ": inverted without its exact witness ('winv' line)");
    if (wl->size() != k.vars.size() + 1) fail(name + ": 'winv' has the wrong number of t values");
    if (at_point(k, hd.sep, hd.fanrule, read_t(*wl, 1, k, name)).valid)
        fail(name + ": inverted witness is not inverted (exact evaluation: every chosen triangle has cross > 0)");
}
// The claims of the key lines from rd.at on, read ahead of their verification
// (no leaf is looked at) so that a claim contradicting them is rejected at
// once; inverted keys (no leaves) are checked here whole.  Malformed key lines
// are skipped here and rejected by read_key.
std::vector<KeyClaim> scan_key_lines(const Reader& rd, const std::vector<std::array<St, 4>>& keys, const Header& hd) {
    std::vector<KeyClaim> out;
    for (std::size_t j = rd.at; j < rd.lines.size(); ++j) {
        const auto& h = rd.lines[j];
        if (h[0] != "key" || h.size() < 6 || !digits(h[1], 0) || Z(h[1]) >= keys.size()) continue;
        const std::array<St, 4>& s = keys[Z(h[1]).convert_to<std::size_t>()];
        const bool fl = !hd.junctions && flat(s);
        if (h.size() == 6 && h[5] == "inverted") {
            check_key_head(h, s, Z(h[1]).convert_to<std::size_t>(), hd);
            check_inverted_key(j + 1 < rd.lines.size() ? &rd.lines[j + 1] : nullptr, s, hd);
            out.push_back({h[2], fl, true, 0, 0});
        } else if (h.size() == 8) {
            out.push_back({h[2], fl, false, parse_q(h[5]), parse_q(h[6])});
        }
    }
    return out;
}

// The claims against the keys: a category's claim is `inverted` iff one of its
// keys is, and a bound follows from its keys' claims (no key has a larger
// qmin or a smaller qmax: else the theorem would be false) and, once all keys
// are in (`complete`), is exactly their aggregate (no weaker theorem than the
// one the keys prove).
void check_claims(const Claims& cl, const std::vector<KeyClaim>& keys, const Header& hd, bool complete) {
    for (int c = 0; c < hd.ncat(); ++c) {
        bool any = false, inv = false;
        Q qmin, qmax;
        for (const KeyClaim& e : keys) {
            if (c == 1 && !e.flat) continue;
            inv = inv || e.inverted;
            if (e.inverted) continue;
            qmin = any ? std::max(qmin, e.qmin) : e.qmin, qmax = any ? std::min(qmax, e.qmax) : e.qmax, any = true;
        }
        const std::string name = std::string("claim ") + "UF"[c];
        if (cl.claim[c].inverted != inv && (complete || inv))
            fail(name + (inv ? " is a bound, but a key is inverted" : " is 'inverted', but no key is inverted"));
        if (inv || !any) continue;
        if (cl.claim[c].qmin < qmin || cl.claim[c].qmax > qmax) fail(name + " does not follow from the key claims");
        if (complete && (cl.claim[c].qmin != qmin || cl.claim[c].qmax != qmax)) fail(name + " is weaker than its keys give");
    }
}

// The category witnesses: for a bound, one `min` and one `max` witness (exact
// configurations near the claim: its tightness); for `inverted`, one
// `inverted` witness on a key marked inverted.  Returns the report's lines.
std::string check_theorem_witnesses(const Claims& cl, const std::vector<std::array<St, 4>>& keys,
                                    const std::vector<KeyClaim>& lines, const Header& hd) {
    for (int c = 0; c < hd.ncat(); ++c)
        for (const std::string kind : {"min", "max", "inverted"}) {
            const long n = std::count_if(cl.wits.begin(), cl.wits.end(), [&](const Wit& w) { return w.cat == c && w.kind == kind; });
            if (n != ((kind == "inverted") == cl.claim[c].inverted ? 1 : 0))
                fail(std::string("claim ") + "UF"[c] + (cl.claim[c].inverted ? " inverted" : " (a bound)") + ": has " +
                     std::to_string(n) + " '" + kind + "' witnesses");
        }
    std::ostringstream out;
    for (const Wit& w : cl.wits) {
        const auto it = std::find_if(keys.begin(), keys.end(), [&](const std::array<St, 4>& s) { return code(s) == w.code; });
        if (it == keys.end()) fail("witness key " + w.code.substr(0, 20) + " is not a consistent key");
        if (w.cat == 1 && (hd.junctions || !flat(*it))) fail("flat witness on a key that is not flat-compatible");
        Key k = make_key(*it, hd);
        const bool inv = w.kind == "inverted";
        if (w.fields.size() != 4 + k.vars.size() + (inv ? 0 : 1)) fail("witness has the wrong number of t values");
        const PointVal p = at_point(k, hd.sep, hd.fanrule, read_t(w.fields, 4, k, "witness " + w.code));
        out << "  witness " << "UF"[w.cat] << " " << w.kind << " " << w.code << ": ";
        if (inv) {
            const bool marked = std::any_of(lines.begin(), lines.end(), [&](const KeyClaim& e) { return e.code == w.code && e.inverted; });
            if (p.valid || !marked) fail("inverted witness is not inverted");
            out << "the chosen diagonal has a triangle with cross <= 0 (exact)\n";
            continue;
        }
        if (!p.valid) fail("witness is inverted");
        const Q v = w.kind == "min" ? p.qmin : p.qmax;
        if (v != parse_q(w.fields.back())) fail("witness value differs from exact evaluation");
        const Q bound = w.kind == "min" ? cl.claim[w.cat].qmin : cl.claim[w.cat].qmax;
        const RQ a = deg_r(v, hd.rhombic), bd = deg_r(bound, hd.rhombic);
        out << "angle " << degs(v, hd.rhombic) << " (" << (hd.rhombic ? "r " : "cot ") << v.convert_to<double>() << "), claim "
            << degs(bound, hd.rhombic)
            << ", gap <= " << dec(w.kind == "min" ? a.hi - bd.lo : bd.hi - a.lo, true) << " deg\n";
    }
    return out.str();
}

// One key line and its witnesses (its leaves follow; verify_leaves):
//   key <i> <code> <flat> <m> <qmin> <qmax> <leaves>, `wmin`, `wmax`; or
//   key <i> <code> <flat> <m> inverted, then `winv <t_1> ... <t_m>`: an exact
//   configuration of the key's box at which a chosen triangle has cross <= 0.
// Checked: index and code (the enumeration's i-th key: none missing, none
// repeated), flatness flag, dimension, the witnesses' exact values against the
// key's claim (their tightness goes to `tight`).
KeyClaim read_key(Reader& rd, const Header& hd, const std::array<St, 4>& s, std::size_t i, Tightness tight[2]) {
    const auto& h = rd.next("key");
    check_key_head(h, s, i, hd);
    KeyClaim e{code(s), !hd.junctions && flat(s), false, 0, 0};
    Key k = make_key(s, hd);
    const std::string name = "key " + e.code;
    if (h.size() == 6 && h[5] == "inverted") {
        e.inverted = true;
        check_inverted_key(rd.at < rd.lines.size() ? &rd.next("winv") : nullptr, s, hd);
        return e;
    }
    if (h.size() != 8) fail("malformed key line");
    e.qmin = parse_q(h[5]), e.qmax = parse_q(h[6]);
    // Premise of the double-agreement argument (proofs/README.md, "Double
    // agreement"): a diagonal the double evaluation wrongly deems valid has
    // quality above 2^40, far above every key's bound.
    if (e.qmin > 256) fail(name + ": min-angle cot bound above 256");
    // The key's witnesses: exact configurations whose extreme angles are
    // within the key's claim (else the claim is false) and, measured, close
    // to it (the tightness of the claim, reported).
    for (int w = 0; w < 2; ++w) {
        const auto& wl = rd.next("key witness");
        if (wl.size() != k.vars.size() + 2 || wl[0] != (w ? "wmax" : "wmin"))
            fail(name + ": expected '" + (w ? "wmax" : "wmin") + "' line");
        const PointVal p = at_point(k, hd.sep, hd.fanrule, read_t(wl, 1, k, name));
        const Q v = w ? p.qmax : p.qmin;
        if (!p.valid || v != parse_q(wl.back())) fail(name + ": witness value differs from exact evaluation");
        if (w ? v < e.qmax : v > e.qmin) fail(name + ": claim contradicted by its witness");
        tight[w].add(gap_deg(v, w ? e.qmax : e.qmin, hd.rhombic), e.code, e.flat);
    }
    return e;
}

// The leaves of a bounded key (line h, at rd.at): the bisection tree rebuilt
// and every leaf verified (Cover).  Verification is a function of the rule,
// the warps, the forcing (separating and fan rules), whether the fan may be
// taken (fan rule, every corner inside), the two bounds and the leaf lines
// only: a key whose text of these equals that of a key verified before is
// verified by it (`verified`, the memo).  Returns the number of leaves.
long verify_leaves(Reader& rd, const Header& hd, const std::array<St, 4>& s, const std::vector<std::string>& h,
                   std::set<std::string>& verified) {
    Key k = make_key(s, hd);
    const bool fan = hd.fanrule && all_inside(s);  // the fan rule's fan needs every corner inside
    Cover cv{k, hd.sep, fan, dyadic(parse_q(h[5])), dyadic(parse_q(h[6])), rd, small_int(h[7], 1, 50000000)};
    std::string memo = hd.rule + " " + std::to_string(hd.sep ? forced(s) : 0) + " " + (fan ? "fan" : "nofan") + " " + h[5] +
                       " " + h[6] + " " + h[7] + ":";
    for (int c = 0; c < 4; ++c) memo += WCH[s[c].warp];
    for (long j = 0; j < cv.remaining && rd.at + static_cast<std::size_t>(j) < rd.lines.size(); ++j) {
        memo += " |";
        for (const std::string& t : rd.lines[rd.at + static_cast<std::size_t>(j)]) memo += " " + t;
    }
    if (verified.count(memo)) {
        rd.at += static_cast<std::size_t>(cv.remaining);
        return cv.remaining;
    }
    Box root(k.vars.size(), R{N(0), N(Z(1), -1)});
    cv.leaf_or_split(root, 0);
    if (cv.remaining != 0) fail("key " + code(s) + ": extra leaves");
    verified.insert(memo);
    return cv.leaves;
}

// What was proved, per category: the bound (rigorous degrees), or no bound.
std::string theorem_text(const Claims& cl, const Header& hd) {
    const char* cname[2] = {"U (all consistent configurations)", "F (flat stencils)"};
    std::ostringstream out;
    for (int c = 0; c < hd.ncat(); ++c) {
        const Claim& k = cl.claim[c];
        if (k.inverted) {
            out << "  " << cname[c] << ": NO BOUND: NOT all triangles positively oriented (exact counter-example below)\n";
            continue;
        }
        const RQ lo = deg_r(k.qmin, hd.rhombic), hi = deg_r(k.qmax, hd.rhombic);
        const char* r = hd.rhombic ? "r" : "cot";
        out << "  " << cname[c] << ": every angle >= " << dec(lo.lo, false) << " deg and <= " << dec(hi.hi, true) << " deg ("
            << r << " <= " << k.qmin << ", " << r << " >= " << k.qmax << (hd.rhombic ? ", r = sqrt(3) cot" : "") << "); "
            << (hd.fanrule ? "every chosen triangle (a diagonal's two, or the fan's four)" : "both triangles")
            << " positively oriented\n"
            << "    rounded outward to 4 decimals: every angle in [" << dec(lo.lo, false, 4) << ", " << dec(hi.hi, true, 4)
            << "] deg\n";
    }
    return out.str();
}
std::string tightness_text(const Tightness tight[2]) {
    std::ostringstream out;
    for (int w = 0; w < 2; ++w) {
        const Tightness& t = tight[w];
        out << "  per-key " << (w ? "max" : "min") << " angle claims vs witnesses: gap <= " << dec(t.target, true, 2) << " deg on "
            << t.within << " of " << t.keys << " keys (flat: " << t.within_flat << " of " << t.keys_flat
            << "); largest gap <= " << dec(t.worst, true, 4) << " deg (key " << t.worst_key << ")\n"
            << "    keys above: gap <= 1 deg " << t.over[0] << ", <= 5 deg " << t.over[1] << ", <= 20 deg " << t.over[2]
            << ", > 20 deg " << t.over[3] << "\n";
    }
    return out.str();
}

// Checks one certificate; prints what it proves.  Returns true if every
// category's theorem is an angle bound, false if a category states no bound
// (an exact counter-example to orientation, verified); throws Fail if the
// certificate is wrong.  The claims are checked against the key lines and the
// category witnesses first (cheap), then every key in order with its leaves,
// then the claims against the keys as verified.
bool check_file(const std::string& path) {
    Reader rd = read_certificate(path);
    // A line `end` before the last one: data after the end, refused before
    // any leaf is verified.  (A certificate cut short has no `end` at all; it
    // is read up to its cut, where the reader reports what it expected.)
    for (std::size_t i = 0; i + 1 < rd.lines.size(); ++i)
        if (rd.lines[i].size() == 1 && rd.lines[i][0] == "end") fail("data after end");
    const Header hd = read_header(rd);
    const Claims cl = read_claims(rd, hd);
    const auto keys = enumerate_keys(hd.junctions);
    const auto& kl = rd.next("keys");
    expect(kl, "keys", 2);
    if (small_int(kl[1], 0, 1000000) != static_cast<long>(keys.size())) fail("key count differs from the enumeration");
    const std::vector<KeyClaim> ahead = scan_key_lines(rd, keys, hd);
    check_claims(cl, ahead, hd, ahead.size() == keys.size());
    const std::string witnesses = check_theorem_witnesses(cl, keys, ahead, hd);
    Tightness tight[2] = {{Q(1, 100)}, {Q(1, 10)}};  // min angle: 0.01 deg, max angle: 0.1 deg
    std::vector<KeyClaim> verified_keys;
    std::set<std::string> memo;
    long leaves = 0;
    for (std::size_t i = 0; i < keys.size(); ++i) {
        const auto& h = rd.lines[std::min(rd.at, rd.lines.size() - 1)];
        verified_keys.push_back(read_key(rd, hd, keys[i], i, tight));
        if (!verified_keys.back().inverted) leaves += verify_leaves(rd, hd, keys[i], h, memo);
    }
    expect(rd.next("end"), "end", 1);
    if (rd.at != rd.lines.size()) fail("data after end");
    check_claims(cl, verified_keys, hd, true);
    const long nflat = std::count_if(verified_keys.begin(), verified_keys.end(), [](const KeyClaim& e) { return e.flat; });
    std::cout << path << ": rule " << hd.rule << (hd.junctions ? " (junction keys)" : "")
              << (hd.rhombic ? " (rhombic lattice)" : "") << ", " << keys.size() << " keys ("
              << nflat << " flat-compatible), " << leaves << " leaves verified\n"
              << theorem_text(cl, hd) << tightness_text(tight) << witnesses;
    return !cl.claim[0].inverted && !cl.claim[1].inverted;
}

// ---- graded-mesh templates (not in the certificates: a finite, exact check) --
// The graded mesher (issue: quadtree) triangulates an unwarped leaf, scaled to
// [0,2]^2, in one of two ways: no split side → one diagonal (either one);
// otherwise the centre (1,1) is joined to the 4 corners and to the midpoint of
// every split side, i.e. each side gives the triangle (centre, corner, corner),
// or, split, (centre, corner, midpoint) and (centre, midpoint, corner).  All 16
// split patterns are enumerated; every triangle must be positively oriented
// with every angle in [45°, 90°]: cross > 0 and 0 <= dot <= cross (cot in
// [0, 1]).  Integer coordinates: the test is exact.
int check_templates() {
    using P = std::array<long, 2>;
    const P corner[4] = {{0, 0}, {2, 0}, {2, 2}, {0, 2}}, mid[4] = {{1, 0}, {2, 1}, {1, 2}, {0, 1}}, centre{1, 1};
    auto ok = [](const P& a, const P& b, const P& c) {
        const P v[3] = {a, b, c};
        for (int i = 0; i < 3; ++i) {
            const P &o = v[i], &p = v[(i + 1) % 3], &q = v[(i + 2) % 3];
            const long ux = p[0] - o[0], uy = p[1] - o[1], wx = q[0] - o[0], wy = q[1] - o[1];
            const long cross = ux * wy - uy * wx, dot = ux * wx + uy * wy;
            if (cross <= 0 || dot < 0 || dot > cross) return false;
        }
        return true;
    };
    int triangles = 0;
    for (int pattern = 0; pattern < 16; ++pattern) {
        std::vector<std::array<P, 3>> tris;
        if (pattern == 0) {
            tris = {{corner[0], corner[1], corner[2]}, {corner[0], corner[2], corner[3]},   // diagonal (0,0)-(2,2)
                    {corner[0], corner[1], corner[3]}, {corner[1], corner[2], corner[3]}};  // diagonal (2,0)-(0,2)
        } else {
            for (int side = 0; side < 4; ++side) {
                const P &a = corner[side], &b = corner[(side + 1) % 4];
                if (pattern >> side & 1) tris.push_back({centre, a, mid[side]}), tris.push_back({centre, mid[side], b});
                else tris.push_back({centre, a, b});
            }
        }
        for (const auto& t : tris)
            if (!ok(t[0], t[1], t[2])) fail("graded template " + std::to_string(pattern) + ": a triangle leaves [45, 90] deg");
        triangles += static_cast<int>(tris.size());
    }
    return triangles;
}

int main(int argc, char** argv) {
    if (argc < 2) {
        std::cerr << "usage: warpmesh-check FILE.cert...\n";
        return 2;
    }
    try {
        const int n = check_templates();
        std::cout << "graded templates: 16 split patterns, " << n
                  << " triangles, every angle in [45, 90] deg and positively oriented (exact)\n";
    } catch (const Fail& f) {
        std::cerr << "REJECTED: " << f.msg << "\n";
        return 1;
    }
    // Exit status: 0 every certificate verified and every theorem an angle
    // bound; 1 a certificate rejected; 3 all verified, but some category
    // states no bound (an exact counter-example to orientation): not a proof.
    bool rejected = false;
    std::vector<std::string> no_bound;
    for (int i = 1; i < argc; ++i) {
        try {
            if (!check_file(argv[i])) no_bound.push_back(argv[i]);
        } catch (const Fail& f) {
            std::cerr << argv[i] << ": REJECTED: " << f.msg << "\n";
            rejected = true;
        } catch (const std::exception& e) {
            std::cerr << argv[i] << ": REJECTED: " << e.what() << "\n";
            rejected = true;
        }
    }
    for (const std::string& p : no_bound)
        std::cerr << p << ": NO BOUND: verified, but a theorem is a counter-example (an inverted or degenerate triangle), not an angle bound\n";
    if (rejected) return 1;
    if (!no_bound.empty()) return 3;
    std::cout << "all certificates verified\n";
    return 0;
}
