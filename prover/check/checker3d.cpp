// warpmesh-check-bcc — independent checker of the 3D certificate proofs/bcc.cert.
//
// Shares no code with the prover or the mesher (no project header).  From
// the rules of proofs/README.md ("The BCC space") it re-derives the
// consistent configurations of the generic tetrahedron, their output
// tetrahedra (its own stencils and parity rule) and their canonical keys
// under the tetrahedron's 8 symmetries (matching the image's output
// tetrahedra to the original's, point for point); every canonical key must
// be in the certificate, with a root box containing its exact parameter box.
// It replays each key's bisection from its split string and re-verifies
// every leaf in exact dyadic interval arithmetic: positive orientation and
// both dihedral bounds of every output tetrahedron.  No global state.  Any
// failure: exit 1; exit 0 only when the printed theorem holds.
#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <boost/multiprecision/gmp.hpp>

// GMP through Boost.Multiprecision (the 2D checker's cpp_int is ~10x slower
// on the 3D forms' 300-500-bit numbers).
using Q = boost::multiprecision::mpq_rational;
using Z = boost::multiprecision::mpz_int;

struct Fail {
    std::string msg;
};
[[noreturn]] void fail(const std::string& m) { throw Fail{m}; }

// ---- parsing (hostile input: bounded sizes, digits only) ----------------------
Z parse_int(const std::string& s) {
    const std::size_t from = !s.empty() && s[0] == '-' ? 1 : 0;
    if (s.size() <= from || s.size() - from > 40) fail("bad integer '" + s.substr(0, 60) + "'");
    for (std::size_t i = from; i < s.size(); ++i)
        if (s[i] < '0' || s[i] > '9') fail("bad integer '" + s.substr(0, 60) + "'");
    return Z(s);
}
Q parse_q(const std::string& s) {
    const auto slash = s.find('/');
    if (slash == std::string::npos) return Q(parse_int(s));
    const Z d = parse_int(s.substr(slash + 1));
    if (d <= 0) fail("bad denominator in '" + s.substr(0, 60) + "'");
    return Q(parse_int(s.substr(0, slash)), d);
}

// ---- exact dyadic numbers m 2^e and their intervals, with derivatives -----------
struct N {
    Z m;
    long e = 0;
};
N num(long v) { return N{Z(v), 0}; }
N add(const N& a, const N& b) {
    if (a.e <= b.e) return N{a.m + (b.m << static_cast<unsigned>(b.e - a.e)), a.e};
    return N{(a.m << static_cast<unsigned>(a.e - b.e)) + b.m, b.e};
}
N neg(const N& a) { return N{-a.m, a.e}; }
N mul(const N& a, const N& b) {  // normalised: odd mantissa (keeps the numbers short)
    if (a.m == 0 || b.m == 0) return num(0);
    if (a.e + b.e < -4000) fail("number too small");
    N r{a.m * b.m, a.e + b.e};
    const auto z = lsb(abs(r.m));
    if (z) r.m >>= z, r.e += static_cast<long>(z);
    return r;
}
int sgn(const N& a) { return a.m > 0 ? 1 : a.m < 0 ? -1 : 0; }
bool less(const N& a, const N& b) { return sgn(add(a, neg(b))) < 0; }
N dyadic(const Q& q) {
    const Z d = denominator(q);
    if ((d & (d - 1)) != 0) fail("number is not dyadic");
    return N{numerator(q), -static_cast<long>(msb(d))};
}
N half(const N& a) { return N{a.m, a.e - 1}; }

struct R {  // [lo, hi]
    N lo, hi;
};
R operator+(const R& a, const R& b) { return {add(a.lo, b.lo), add(a.hi, b.hi)}; }
R operator-(const R& a, const R& b) { return {add(a.lo, neg(b.hi)), add(a.hi, neg(b.lo))}; }
R operator*(const R& a, const R& b) {
    const N p[4] = {mul(a.lo, b.lo), mul(a.lo, b.hi), mul(a.hi, b.lo), mul(a.hi, b.hi)};
    R r{p[0], p[0]};
    for (const N& x : p) r.lo = less(x, r.lo) ? x : r.lo, r.hi = less(r.hi, x) ? x : r.hi;
    return r;
}
struct D {  // value and partials in the key's parameters
    R v;
    std::array<R, 4> d;
    int n = 0;  // partials carried (0: a constant, or a value-only pass)
};
R zero() { return R{num(0), num(0)}; }
D cst(long v) { return D{{num(v), num(v)}, {zero(), zero(), zero(), zero()}, 0}; }
D operator+(const D& a, const D& b) {
    D r{a.v + b.v, {zero(), zero(), zero(), zero()}, std::max(a.n, b.n)};
    for (int i = 0; i < r.n; ++i) r.d[i] = a.d[i] + b.d[i];
    return r;
}
D operator-(const D& a, const D& b) {
    D r{a.v - b.v, {zero(), zero(), zero(), zero()}, std::max(a.n, b.n)};
    for (int i = 0; i < r.n; ++i) r.d[i] = a.d[i] - b.d[i];
    return r;
}
D operator*(const D& a, const D& b) {
    D r{a.v * b.v, {zero(), zero(), zero(), zero()}, std::max(a.n, b.n)};
    for (int i = 0; i < r.n; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
    return r;
}

// ---- the generic tetrahedron (doubled lattice coordinates) -----------------------
// Local vertices 0, 1 the corners, 2, 3 the centres; edges 0 = 01, 1 = 23 long.
const int REF[4][3] = {{0, 0, 0}, {2, 0, 0}, {1, 1, -1}, {1, 1, 1}};
const int OFF[14][3] = {{2, 0, 0},  {-2, 0, 0}, {0, 2, 0},   {0, -2, 0}, {0, 0, 2},   {0, 0, -2},  {1, 1, 1},
                        {-1, 1, 1}, {1, -1, 1}, {-1, -1, 1}, {1, 1, -1}, {-1, 1, -1}, {1, -1, -1}, {-1, -1, -1}};
const int EDGE[6][2] = {{0, 1}, {2, 3}, {0, 2}, {0, 3}, {1, 2}, {1, 3}};
const int STAY = 14;
int edge_of(int a, int b) {
    for (int e = 0; e < 6; ++e)
        if ((EDGE[e][0] == a && EDGE[e][1] == b) || (EDGE[e][0] == b && EDGE[e][1] == a)) return e;
    fail("no such edge");
}
struct Key {
    std::array<int, 4> sign{}, warp{STAY, STAY, STAY, STAY};
    int parity = 0;
    std::array<int, 9> enc() const {
        return {sign[0], warp[0], sign[1], warp[1], sign[2], warp[2], sign[3], warp[3], parity};
    }
};
int reached(int i, int w) {  // local vertex reached from i along w, or -1
    if (w == STAY) return -1;
    for (int j = 0; j < 4; ++j)
        if (REF[i][0] + OFF[w][0] == REF[j][0] && REF[i][1] + OFF[w][1] == REF[j][1] && REF[i][2] + OFF[w][2] == REF[j][2])
            return j;
    return -1;
}
bool parity_quad(const Key& k) {
    bool pos = false;
    for (int s : k.sign) pos = pos || s > 0;
    return pos && ((k.sign[0] < 0 && k.sign[1] < 0) || (k.sign[2] < 0 && k.sign[3] < 0));
}
// The consistency rules of proofs/README.md ("The BCC space").
bool consistent(const Key& k) {
    if (k.parity != 0 && !parity_quad(k)) return false;
    for (int i = 0; i < 4; ++i) {
        if (k.sign[i] != 0 && k.warp[i] != STAY) return false;
        const int j = reached(i, k.warp[i]);
        if (j >= 0 && (reached(j, k.warp[j]) == i || (k.sign[j] == 0 && k.warp[j] == STAY))) return false;
    }
    return true;
}
// Face (a, b, r), a and b the - vertices: true iff the quad's diagonal is
// a-cut(b, r).  Long ab: the parity rule (X = a is a corner, par = #coords
// with 2a > b + r, mod 2), reversed by the parity bit; else the diagonal
// leaves the cut point of the face's long edge.
bool diag_a(int a, int b, int r, int parity) {
    if (edge_of(a, b) < 2) {
        int par = 0;
        for (int i = 0; i < 3; ++i) par += 2 * REF[a][i] > REF[b][i] + REF[r][i];
        return ((a < 2) == (par % 2 == 1)) != (parity == 1);
    }
    return edge_of(b, r) < 2;
}
// Points: 0..3 the vertices, 4 + e the cut point of edge e.
int cut(int a, int b) { return 4 + edge_of(a, b); }
using Tet = std::array<int, 4>;
// The output tetrahedra, each positively oriented with cut points at the
// midpoints (orientation fixed below by the reference volume).
std::vector<Tet> stencil(const Key& k) {
    std::vector<int> ng, zr, ps;
    for (int i = 0; i < 4; ++i) (k.sign[i] < 0 ? ng : k.sign[i] == 0 ? zr : ps).push_back(i);
    std::vector<Tet> out;
    if (ng.empty()) return out;
    if (ps.empty()) return {{0, 1, 2, 3}};
    if (ng.size() == 1) {
        Tet t{0, 1, 2, 3};
        for (int p : ps) t[p] = cut(ng[0], p);
        return {t};
    }
    if (ng.size() == 2 && ps.size() == 1) {  // pyramid over the quad of face (a, b, r)
        const int a = ng[0], b = ng[1], r = ps[0], z = zr[0];
        if (diag_a(a, b, r, k.parity)) return {{z, a, b, cut(b, r)}, {z, a, cut(b, r), cut(a, r)}};
        return {{z, a, b, cut(a, r)}, {z, b, cut(b, r), cut(a, r)}};
    }
    // Prisms: bottom B, top T (T[i] = cut point of B[i]); lateral quad i joins
    // B[i], B[i+1]; its diagonal is B[i]-T[i+1] (f[i]) or B[i+1]-T[i].
    std::array<int, 3> B{}, T{};
    std::array<bool, 3> f{};
    if (ng.size() == 2) {  // two - two +: B = (a, cut(a,r0), cut(a,r1)), T likewise from b
        const int a = ng[0], b = ng[1];
        B = {a, cut(a, ps[0]), cut(a, ps[1])}, T = {b, cut(b, ps[0]), cut(b, ps[1])};
        f[0] = diag_a(a, b, ps[0], k.parity), f[2] = !diag_a(a, b, ps[1], k.parity);
        if (f[0] != f[2]) fail("prism: face quads turn differently");
        f[1] = !f[0];  // the inside quad: the only non-cyclic choice
    } else {
        for (int i = 0; i < 3; ++i) B[i] = ng[i], T[i] = cut(ng[i], ps[0]);
        for (int i = 0; i < 3; ++i) f[i] = diag_a(B[i], B[(i + 1) % 3], ps[0], k.parity);
        if (f[0] == f[1] && f[1] == f[2]) fail("prism: cyclic diagonals");
    }
    // B[i] with f[i] and not f[i-1] sees all of T; the rest is a pyramid on quad i+1.
    int i = 0;
    while (!(f[i] && !f[(i + 2) % 3])) ++i;
    const int j = (i + 1) % 3, l = (i + 2) % 3;
    out.push_back({B[i], T[0], T[1], T[2]});
    if (f[j]) out.push_back({B[i], B[j], B[l], T[l]}), out.push_back({B[i], B[j], T[l], T[j]});
    else out.push_back({B[i], B[j], B[l], T[j]}), out.push_back({B[i], B[l], T[l], T[j]});
    return out;
}
long ref_volume(const Tet& t) {  // 6 * volume, quadrupled coordinates
    long p[4][3];
    for (int v = 0; v < 4; ++v)
        for (int c = 0; c < 3; ++c)
            p[v][c] = t[v] < 4 ? 2 * REF[t[v]][c] : REF[EDGE[t[v] - 4][0]][c] + REF[EDGE[t[v] - 4][1]][c];
    long a[3], b[3], c[3];
    for (int x = 0; x < 3; ++x) a[x] = p[1][x] - p[0][x], b[x] = p[2][x] - p[0][x], c[x] = p[3][x] - p[0][x];
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}
std::vector<Tet> oriented(const Key& k) {
    std::vector<Tet> s = stencil(k);
    for (Tet& t : s) {
        const long v = ref_volume(t);
        if (v == 0) fail("flat stencil tetrahedron");
        if (v < 0) std::swap(t[2], t[3]);
    }
    return s;
}

// ---- symmetries and canonical keys -------------------------------------------------
// The 8 permutations p of the local vertices keeping the pairs {0,1}, {2,3},
// each with the signed permutation matrix L (found by search) for which
// L (REF[j] - REF[0]) = REF[p[j]] - REF[p[0]]: a lattice isometry.
struct Sym {
    std::array<int, 4> p;
    int L[3][3];
};
std::vector<Sym> symmetries() {
    std::vector<Sym> out;
    std::array<int, 4> p{0, 1, 2, 3};
    do {
        if (p[0] / 2 != p[1] / 2 || p[2] / 2 != p[3] / 2) continue;
        std::array<int, 3> ax{0, 1, 2};
        bool found = false;
        do
            for (int sg = 0; sg < 8 && !found; ++sg) {
                Sym s{p, {}};
                for (int r = 0; r < 3; ++r)
                    for (int c = 0; c < 3; ++c) s.L[r][c] = ax[c] == r ? ((sg >> c) & 1 ? -1 : 1) : 0;
                bool ok = true;
                for (int j = 1; j < 4; ++j)
                    for (int r = 0; r < 3; ++r) {
                        int v = 0;
                        for (int c = 0; c < 3; ++c) v += s.L[r][c] * (REF[j][c] - REF[0][c]);
                        ok = ok && v == REF[p[j]][r] - REF[p[0]][r];
                    }
                if (ok) out.push_back(s), found = true;
            }
        while (!found && std::next_permutation(ax.begin(), ax.end()));
        if (!found) fail("a pair-preserving permutation is not a lattice isometry");
    } while (std::next_permutation(p.begin(), p.end()));
    if (out.size() != 8) fail("symmetry group");
    return out;
}
std::set<std::array<int, 4>> mapped(const std::vector<Tet>& ts, const std::array<int, 4>& p) {
    std::set<std::array<int, 4>> s;
    for (const Tet& t : ts) {
        std::array<int, 4> q{};
        for (int v = 0; v < 4; ++v) q[v] = t[v] < 4 ? p[t[v]] : cut(p[EDGE[t[v] - 4][0]], p[EDGE[t[v] - 4][1]]);
        std::sort(q.begin(), q.end());
        s.insert(q);
    }
    return s;
}
// The image of k under s, its parity bit the one whose output is the image of k's output.
Key image(const Key& k, const Sym& s) {
    Key m;
    for (int i = 0; i < 4; ++i) {
        m.sign[s.p[i]] = k.sign[i];
        if (k.warp[i] == STAY) continue;
        int d[3] = {0, 0, 0};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) d[r] += s.L[r][c] * OFF[k.warp[i]][c];
        for (int w = 0; w < 14; ++w)
            if (OFF[w][0] == d[0] && OFF[w][1] == d[1] && OFF[w][2] == d[2]) m.warp[s.p[i]] = w;
    }
    const auto want = mapped(oriented(k), s.p);
    for (m.parity = 0; m.parity < (parity_quad(m) ? 2 : 1); ++m.parity)
        if (mapped(oriented(m), {0, 1, 2, 3}) == want) return m;
    fail("stencil does not commute with a symmetry");
}

// ---- verification of one leaf ------------------------------------------------------
struct Param {
    int index;  // 0..3: t of vertex index; 4 + e: u of edge e
    Q lo, hi;   // the exact box
};
std::vector<Param> params(const Key& k, const Q& along, const Q& ashort) {
    std::vector<Param> ps;
    for (int i = 0; i < 4; ++i)
        if (k.sign[i] == 0 && k.warp[i] != STAY) ps.push_back({i, Q(0), k.warp[i] < 6 ? along : ashort});
    for (int e = 0; e < 6; ++e)
        if (k.sign[EDGE[e][0]] * k.sign[EDGE[e][1]] < 0) {
            const Q a = e < 2 ? along : ashort;
            ps.push_back({4 + e, a, 1 - a});
        }
    return ps;
}
using Box = std::vector<R>;
using P3 = std::array<D, 3>;
P3 sub3(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
P3 cross3(const P3& a, const P3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
D dot3(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
// The 25 forms of every output tetrahedron on box b (see verify_leaf).
// (`only` >= 0: that tetrahedron's forms only, the others left empty;
// `partials` false: values only, the partials left 0.)
std::vector<std::array<D, 25>> forms(const Key& k, const std::vector<Param>& ps, const std::vector<Tet>& tets,
                                     const Box& b, const N& cmin, const N& cmax, int only = -1, bool partials = true) {
    std::array<D, 10> var;
    for (D& x : var) x = cst(0);
    for (std::size_t i = 0; i < ps.size(); ++i) {
        var[ps[i].index] = D{b[i], {zero(), zero(), zero(), zero()}, partials ? static_cast<int>(ps.size()) : 0};
        if (partials) var[ps[i].index].d[i] = R{num(1), num(1)};
    }
    std::array<P3, 10> pt;
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) {
            pt[i][c] = cst(REF[i][c]);
            if (k.warp[i] != STAY && OFF[k.warp[i]][c] != 0) pt[i][c] = pt[i][c] + cst(OFF[k.warp[i]][c]) * var[i];
        }
    for (int e = 0; e < 6; ++e)
        for (int c = 0; c < 3; ++c) {
            const int a = REF[EDGE[e][0]][c], d = REF[EDGE[e][1]][c] - a;
            pt[4 + e][c] = cst(a);
            if (d != 0) pt[4 + e][c] = pt[4 + e][c] + cst(d) * var[4 + e];
        }
    std::vector<std::array<D, 25>> out;
    const D Cmin{{cmin, cmin}, {zero(), zero(), zero(), zero()}}, Cmax{{cmax, cmax}, {zero(), zero(), zero(), zero()}};
    for (const Tet& t : tets) {
        std::array<D, 25> f;
        if (only >= 0 && &t != &tets[static_cast<std::size_t>(only)]) {
            out.push_back(f);
            continue;
        }
        const P3 &p0 = pt[t[0]], &p1 = pt[t[1]], &p2 = pt[t[2]], &p3 = pt[t[3]];
        f[0] = dot3(sub3(p1, p0), cross3(sub3(p2, p0), sub3(p3, p0)));
        for (int e = 0; e < 6; ++e) {
            const int a = EDGE[e][0], bb = EDGE[e][1];
            int c = 0;
            while (c == a || c == bb) ++c;
            const int d = 6 - a - bb - c;
            const P3 ev = sub3(pt[t[bb]], pt[t[a]]);
            const P3 nc = cross3(ev, sub3(pt[t[c]], pt[t[a]])), nd = cross3(ev, sub3(pt[t[d]], pt[t[a]]));
            const D dt = dot3(nc, nd), nn = dot3(nc, nc) * dot3(nd, nd);
            f[1 + 2 * e] = cst(0) - dt, f[2 + 2 * e] = Cmin * nn - dt * dt;
            f[13 + 2 * e] = dt, f[14 + 2 * e] = Cmax * nn - dt * dt;
        }
        out.push_back(f);
    }
    return out;
}
Box centre(const Box& b) {
    Box m = b;
    for (R& x : m) x.lo = x.hi = half(add(x.lo, x.hi));
    return m;
}
// Form f of tetrahedron j >= 0 (> 0 if strict) on b: the natural enclosure
// g, then the mean-value form around the centre (mid: the form's value
// there), then the face where every variable whose partial has a decided
// sign is fixed at its worse end, again (re-evaluated there).
bool holds(const Key& k, const std::vector<Param>& ps, const std::vector<Tet>& tets, Box b, int j, int f, bool strict,
           const N& cmin, const N& cmax, D g, R mid) {
    for (bool first = true;; first = false) {
        const auto pos = [&](const N& x) { return strict ? sgn(x) > 0 : sgn(x) >= 0; };
        if (pos(g.v.lo)) return true;
        R mv = first ? mid : forms(k, ps, tets, centre(b), cmin, cmax, j)[j][f].v;
        for (std::size_t i = 0; i < b.size(); ++i) {
            const N r = half(add(b[i].hi, neg(b[i].lo)));
            if (sgn(r) != 0) mv = mv + g.d[i] * R{neg(r), r};
        }
        if (pos(mv.lo)) return true;
        bool fixed = false;
        for (std::size_t i = 0; i < b.size(); ++i) {
            if (sgn(add(b[i].hi, neg(b[i].lo))) == 0) continue;
            if (sgn(g.d[i].lo) >= 0) b[i].hi = b[i].lo, fixed = true;
            else if (sgn(g.d[i].hi) <= 0) b[i].lo = b[i].hi, fixed = true;
        }
        if (!fixed) return false;
        g = forms(k, ps, tets, b, cmin, cmax, j)[j][f];
    }
}
bool verify_leaf(const Key& k, const std::vector<Param>& ps, const std::vector<Tet>& tets, const Box& b, const N& cmin,
                 const N& cmax) {
    {  // the natural enclosures alone, without partials, often suffice
        const auto fv = forms(k, ps, tets, b, cmin, cmax, -1, false);
        bool all = true;
        for (const auto& f : fv) {
            const auto P = [&](int x) { return sgn(f[x].v.lo) >= 0; };
            all = all && sgn(f[0].v.lo) > 0;
            for (int e = 0; e < 6 && all; ++e) all = (P(1 + 2 * e) || P(2 + 2 * e)) && (P(13 + 2 * e) || P(14 + 2 * e));
        }
        if (all) return true;
    }
    const auto fb = forms(k, ps, tets, b, cmin, cmax), fm = forms(k, ps, tets, centre(b), cmin, cmax);
    for (int j = 0; j < static_cast<int>(tets.size()); ++j) {
        const auto H = [&](int f, bool strict) { return holds(k, ps, tets, b, j, f, strict, cmin, cmax, fb[j][f], fm[j][f].v); };
        if (!H(0, true)) return false;
        // Either alternative proves a bound; the one matching the sign of d at
        // the centre is tried first (only the cost depends on the order).
        for (int e = 0; e < 6; ++e) {
            const bool acute = sgn(fm[j][13 + 2 * e].v.lo) > 0;
            const int s1 = 1 + 2 * e, q1 = 2 + 2 * e, s2 = 13 + 2 * e, q2 = 14 + 2 * e;
            if (!(acute ? H(q1, false) || H(s1, false) : H(s1, false) || H(q1, false))) return false;
            if (!(acute ? H(s2, false) || H(q2, false) : H(q2, false) || H(s2, false))) return false;
        }
    }
    return true;
}
// Replays the bisection: '1' splits the widest side (the first on ties) at its
// midpoint, lower half first; '0' is a leaf, verified.
long replay(const Key& k, const std::vector<Param>& ps, const Box& root, const std::string& splits, const N& cmin,
            const N& cmax) {
    const std::vector<Tet> tets = oriented(k);
    std::vector<Box> stack{root};
    std::size_t at = 0;
    long leaves = 0;
    while (!stack.empty()) {
        const Box b = stack.back();
        stack.pop_back();
        if (at >= splits.size()) fail("split string too short");
        const char c = splits[at++];
        if (c == '0') {
            if (!verify_leaf(k, ps, tets, b, cmin, cmax)) fail("leaf not verified");
            ++leaves;
            continue;
        }
        if (c != '1' || b.empty() || stack.size() > 200) fail("bad split string");
        std::size_t s = 0;
        for (std::size_t i = 1; i < b.size(); ++i)
            if (less(add(b[s].hi, neg(b[s].lo)), add(b[i].hi, neg(b[i].lo)))) s = i;
        const N mid = half(add(b[s].lo, b[s].hi));
        Box lo = b, hi = b;
        lo[s].hi = mid, hi[s].lo = mid;
        stack.push_back(hi), stack.push_back(lo);
    }
    if (at != splits.size()) fail("split string too long");
    return leaves;
}

// ---- the certificate ------------------------------------------------------------------
Key parse_code(const std::string& s) {
    Key k;
    std::size_t at = 0;
    for (int i = 0; i < 4; ++i) {
        if (at >= s.size()) fail("bad key code " + s.substr(0, 40));
        const char c = s[at++];
        if (c == '-' || c == '+') k.sign[i] = c == '-' ? -1 : 1;
        else if (c == '0' && at < s.size() && (s[at] == 's' || (s[at] >= 'a' && s[at] <= 'n')))
            k.sign[i] = 0, k.warp[i] = s[at] == 's' ? STAY : s[at] - 'a', ++at;
        else fail("bad key code " + s.substr(0, 40));
        if (at >= s.size() || s[at++] != (i < 3 ? ',' : '/')) fail("bad key code " + s.substr(0, 40));
    }
    if (at + 1 != s.size() || (s[at] != '0' && s[at] != '1')) fail("bad key code " + s.substr(0, 40));
    k.parity = s[at] - '0';
    return k;
}

// All canonical keys with output: the smallest image of every consistent
// configuration with a - vertex.
std::set<std::array<int, 9>> canonical_keys(const std::vector<Sym>& syms) {
    std::set<std::array<int, 9>> out;
    std::array<int, 4> st{};
    for (st[0] = 0; st[0] < 17; ++st[0])
        for (st[1] = 0; st[1] < 17; ++st[1])
            for (st[2] = 0; st[2] < 17; ++st[2])
                for (st[3] = 0; st[3] < 17; ++st[3])
                    for (int par = 0; par < 2; ++par) {
                        Key k;
                        bool any_neg = false;
                        for (int i = 0; i < 4; ++i) {
                            k.sign[i] = st[i] == 0 ? -1 : st[i] == 1 ? 1 : 0;
                            k.warp[i] = st[i] >= 2 ? st[i] - 2 : STAY;
                            any_neg = any_neg || k.sign[i] < 0;
                        }
                        k.parity = par;
                        if (!any_neg || !consistent(k)) continue;
                        std::array<int, 9> best = image(k, syms[0]).enc();
                        for (const Sym& s : syms) best = std::min(best, image(k, s).enc());
                        out.insert(best);
                    }
    return out;
}

int check(std::istream& in, bool progress) {
    std::string line, word;
    std::vector<std::string> body;
    while (std::getline(in, line))
        if (!line.empty() && line[0] != '#') body.push_back(line);
    if (body.size() < 4 || body[0] != "warpmesh-bcc-certificate 1") fail("not a BCC certificate (format 1)");
    std::istringstream a(body[1]), c(body[2]), n(body[3]);
    std::string al, as, cn, cx, kw;
    long nkeys = -1;
    if (!(a >> word >> al >> as) || word != "alphas") fail("bad alphas line");
    if (!(c >> word >> cn >> cx) || word != "claim") fail("bad claim line");
    if (!(n >> word >> nkeys) || word != "keys" || nkeys < 0 || nkeys > 1000000) fail("bad keys line");
    const Q along = parse_q(al), ashort = parse_q(as), qmin = parse_q(cn), qmax = parse_q(cx);
    if (!(along > 0 && along < Q(1, 2) && ashort > 0 && ashort < Q(1, 2))) fail("alphas out of (0, 1/2)");
    if (!(qmin > 0 && qmin < 1 && qmax > 0 && qmax < 1)) fail("claim out of (0, 1)");
    const N cmin = dyadic(qmin), cmax = dyadic(qmax);
    if (static_cast<long>(body.size()) != 4 + nkeys) fail("key count mismatch");
    const std::vector<Sym> syms = symmetries();
    const auto expected = canonical_keys(syms);
    if (static_cast<long>(expected.size()) != nkeys) fail("the certificate does not list every key");
    // First pass, structure only (cheap): keys, root boxes, split strings.
    struct Entry {
        Key k;
        std::vector<Param> ps;
        Box root;
        std::string splits;
    };
    std::vector<Entry> entries;
    std::set<std::array<int, 9>> seen;
    for (long i = 0; i < nkeys; ++i) {
        std::istringstream ks(body[static_cast<std::size_t>(4 + i)]);
        std::string code;
        int m = -1;
        if (!(ks >> word >> code >> m) || word != "key") fail("bad key line");
        Entry en{parse_code(code), {}, {}, {}};
        if (!expected.count(en.k.enc()) || !seen.insert(en.k.enc()).second) fail("unexpected or repeated key " + code);
        en.ps = params(en.k, along, ashort);
        if (m != static_cast<int>(en.ps.size())) fail("wrong parameter count for " + code);
        for (int j = 0; j < m; ++j) {
            std::string lo, hi;
            if (!(ks >> lo >> hi)) fail("bad root box for " + code);
            const Q l = parse_q(lo), h = parse_q(hi);
            if (!(l <= en.ps[static_cast<std::size_t>(j)].lo && h >= en.ps[static_cast<std::size_t>(j)].hi && h - l < 1))
                fail("root box does not contain the parameter box of " + code);
            en.root.push_back(R{dyadic(l), dyadic(h)});
        }
        if (!(ks >> en.splits) || en.splits.size() > 50000000 || (ks >> word)) fail("bad split string for " + code);
        long open = 1;  // a preorder bisection: every '1' opens two subtrees, every '0' closes one
        for (const char ch : en.splits) {
            if (open == 0) fail("split string too long for " + code);
            if (ch != '0' && ch != '1') fail("bad split string for " + code);
            open += ch == '1' ? 1 : -1;
        }
        if (open != 0) fail("split string too short for " + code);
        entries.push_back(std::move(en));
    }
    // Second pass: every leaf verified.
    long leaves = 0;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        leaves += replay(entries[i].k, entries[i].ps, entries[i].root, entries[i].splits, cmin, cmax);
        if (progress && (i + 1) % 50 == 0) std::cerr << "checked " << i + 1 << " keys, " << leaves << " leaves\n";
    }
    const double dmin = std::acos(std::sqrt(qmin.convert_to<double>())) * 180 / M_PI;
    const double dmax = 180 - std::acos(std::sqrt(qmax.convert_to<double>())) * 180 / M_PI;
    std::cout << "BCC theorem (alphas " << al << ", " << as << "): every output tetrahedron of the " << nkeys
              << " keys is positively oriented, and every dihedral angle t has cos t <= 0 or cos^2 t <= " << cn
              << ", and cos t >= 0 or cos^2 t <= " << cx << ": t in [" << dmin << ", " << dmax << "] deg (" << leaves
              << " leaves)\n";
    return 0;
}

int main(int argc, char** argv) {
    const bool progress = argc == 3 && std::string(argv[1]) == "--progress";
    if (argc != 2 && !progress) {
        std::cerr << "usage: warpmesh-check-bcc [--progress] CERTIFICATE\n";
        return 2;
    }
    std::ifstream f(argv[argc - 1]);
    if (!f) {
        std::cerr << "warpmesh-check-bcc: cannot read " << argv[argc - 1] << "\n";
        return 1;
    }
    try {
        return check(f, progress);
    } catch (const Fail& e) {
        std::cerr << "warpmesh-check-bcc: " << argv[argc - 1] << ": " << e.msg << "\n";
        return 1;
    }
}
