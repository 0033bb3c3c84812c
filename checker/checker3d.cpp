// warpmesh-check-bcc — independent checker of the 3D certificates (proofs/bcc.cert and its kin).
//
// Shares no code with the prover or the mesher (no project header).  From
// the rules of proofs/README.md ("The BCC space") it re-derives the
// consistent configurations of the generic tetrahedron, their output
// tetrahedra (its own stencils and parity rule) and their canonical keys
// under the tetrahedron's 8 symmetries (matching the image's output
// tetrahedra to the original's, point for point); every canonical key must
// be in the certificate, with a root box containing its exact parameter box.
// It replays each key's bisection from its split string (format 4: each split
// names its side) and re-verifies every leaf exactly: positive orientation,
// both dihedral bounds and the face-angle bound of every output tetrahedron.
// It evaluates every witness exactly and measures each claim's tightness.
// Format 5 is format 4 with one more header line, `face-rule delaunay`,
// right after the first: the quads are split by the Delaunay face rule
// (proofs/README.md, "The Delaunay face rule (certified)"), and each leaf
// is verified for every tetrahedron of every stencil that rule admits on it
// (delaunay_tets: its own forms, decided exactly where the sign is; both
// diagonals where a form's exact enclosure contains 0), each witness with
// the stencil the rule chooses there (ties: the parity rule's diagonal).
// A face-rule line in format 4, none or two in format 5, or another rule
// rejects the certificate.  The key space is the same in both formats.
// It also checks a counter-example certificate (proofs/bcc_half.cert,
// "warpmesh-bcc-counterexample 1", see check_counterexample): an exact point
// of a key's space where an output tetrahedron is not positively oriented.
// And a ceiling certificate (proofs/bcc_ceiling.cert, "warpmesh-bcc-ceiling
// 1", see check_ceiling): a quadtree over the threshold pairs, each box with
// an exact point of a single-tetrahedron key's space, valid at every pair of
// the box, where a dihedral angle is below the stated one.
// And the junction certificate (proofs/bcc_junctions.cert,
// "warpmesh-bcc-junctions 1", see check_junctions): the background
// tetrahedra of multi-material meshes where three or four materials meet,
// split by the cone stencil, re-derived here on their own (keys, stencils,
// symmetries, the 15 points), each key verified face by face.
// And the graded templates' certificate (proofs/bcc_graded.cert,
// "warpmesh-bcc-graded 1", see check_graded): the tetrahedra of a graded
// mesh's octree transitions, re-derived from the fan rule and checked exactly.
// And the A15 certificate (a15.cert, "warpmesh-a15-certificate 1",
// see check_a15): isosurface stuffing on the A15 lattice, whose sites,
// Delaunay tetrahedra, classes, symmetries, keys, parameter boxes and face
// rule are re-derived here from proofs/README.md ("The A15 space"); the
// stencils, leaves, witnesses and tightness are the BCC ones', on the A15
// reference tetrahedra (Frame).
// No global state.  Any failure: exit 1; exit 0 only when the printed
// theorem (an angle bound) holds; exit 3 when a counter-example or ceiling
// certificate holds (verified, NO BOUND), as warpmesh-check does for
// `inverted` categories, so that 0 never means "no bound".
//
// EXACT FIXED-POINT ARITHMETIC.  A leaf's box ends are dyadic, m / 2^e.  With
// K = 1 + the largest e of the leaf (so the box's centre is dyadic at 2^-K
// too), every parameter is an integer multiple of 2^-K and every point of
// the generic tetrahedron has coordinates X / 2^K with X an integer.  The
// forms are homogeneous in the coordinates — 6·volume of degree 3, d = n_c·n_d
// of degree 4, N = |n_c|²|n_d|² and d² of degree 8, a face angle's s = u·v of
// degree 2 and M = |u|²|v|² of degree 4 — so evaluated on the integers X they
// are the exact forms times 2^(3K), 2^(4K), 2^(8K) (2^(2K), 2^(4K)): the same
// signs.  A claim C = c / 2^40 enters as c·N − 2^40·d² (times 2^(8K+40)).
// Partial derivatives in a parameter t are carried at the value's scale (dX/dt
// = offset·2^K), and the mean-value form g(m) + Σ g_i [−r_i, r_i], with r_i =
// R_i / 2^K, is evaluated times 2^K: g(m)·2^K + Σ g_i [−R_i, R_i]; the
// second-order Taylor form times 2^(2K+1) (taylor2).  Integers
// are GMP's mpn digits in fixed arrays (no allocation); every result's size is
// checked and an overflow rejects the certificate.  Interval products are the
// plain interval products, + − × in the order of the prover's formulas
// (generic_bcc.hpp, dihedral_forms, face_angle_forms), so each exact enclosure is contained in
// the prover's outward-rounded one.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <tuple>
#include <sstream>
#include <string>
#include <type_traits>
#include <vector>

#include <gmp.h>
#include <unistd.h>

static_assert(GMP_NAIL_BITS == 0 && GMP_NUMB_BITS == 64, "64-bit GMP limbs");

struct Fail {
    std::string msg;
};
[[noreturn]] void fail(const std::string& m) { throw Fail{m}; }

// ---- exact integers of at most 12 limbs (768 bits) ---------------------------------
constexpr int LIMBS = 12;
struct Z {
    int n = 0;  // limbs in use (d[n-1] != 0), 0 for zero
    bool neg = false;
    mp_limb_t d[LIMBS];
};
Z zint(std::int64_t v) {
    Z r;
    if (v != 0) r.n = 1, r.neg = v < 0, r.d[0] = v < 0 ? 0 - static_cast<mp_limb_t>(v) : static_cast<mp_limb_t>(v);
    return r;
}
Z pow2(int k) {  // 2^k
    if (k < 0 || k >= 64 * LIMBS - 1) fail("exponent out of range");
    Z r;
    r.n = k / 64 + 1;
    for (int i = 0; i < r.n; ++i) r.d[i] = 0;
    r.d[k / 64] = mp_limb_t{1} << (k % 64);
    return r;
}
int sgn(const Z& a) { return a.n == 0 ? 0 : a.neg ? -1 : 1; }
int cmp_mag(const Z& a, const Z& b) { return a.n != b.n ? (a.n < b.n ? -1 : 1) : mpn_cmp(a.d, b.d, a.n); }
int cmp(const Z& a, const Z& b) {
    const int sa = sgn(a), sb = sgn(b);
    if (sa != sb) return sa < sb ? -1 : 1;
    return sa == 0 ? 0 : sa * cmp_mag(a, b);
}
void normalise(Z& r) {
    while (r.n > 0 && r.d[r.n - 1] == 0) --r.n;
    if (r.n == 0) r.neg = false;
}
Z add_mag(const Z& a, const Z& b) {  // |a| + |b|, |a| >= |b| in limbs, b != 0
    Z r;
    const mp_limb_t carry = mpn_add(r.d, a.d, a.n, b.d, b.n);
    r.n = a.n;
    if (carry) {
        if (r.n == LIMBS) fail("number too large");
        r.d[r.n++] = carry;
    }
    return r;
}
Z sub_mag(const Z& a, const Z& b) {  // |a| - |b| >= 0, b != 0
    Z r;
    mpn_sub(r.d, a.d, a.n, b.d, b.n);
    r.n = a.n;
    normalise(r);
    return r;
}
Z operator+(const Z& a, const Z& b) {
    if (a.n == 0) return b;
    if (b.n == 0) return a;
    Z r;
    if (a.neg == b.neg) {
        r = a.n >= b.n ? add_mag(a, b) : add_mag(b, a);
        r.neg = a.neg;
        return r;
    }
    const int c = cmp_mag(a, b);
    if (c == 0) return Z{};
    r = c > 0 ? sub_mag(a, b) : sub_mag(b, a);
    r.neg = c > 0 ? a.neg : b.neg;
    return r;
}
Z operator-(const Z& a) {
    Z r = a;
    if (r.n) r.neg = !r.neg;
    return r;
}
Z operator-(const Z& a, const Z& b) { return a + (-b); }
Z operator*(const Z& a, const Z& b) {
    Z r;
    if (a.n == 0 || b.n == 0) return r;
    if (a.n + b.n > LIMBS) fail("number too large");
    if (a.n >= b.n) mpn_mul(r.d, a.d, a.n, b.d, b.n);
    else mpn_mul(r.d, b.d, b.n, a.d, a.n);
    r.n = a.n + b.n;
    r.neg = a.neg != b.neg;
    normalise(r);
    return r;
}
Z half(const Z& a) {  // a / 2, a even
    if (a.n == 0) return a;
    if (a.d[0] & 1) fail("odd half");
    Z r = a;
    mpn_rshift(r.d, a.d, a.n, 1);
    normalise(r);
    return r;
}

// ---- intervals [lo, hi] and dual numbers (value and partials) --------------------
struct I {
    Z lo, hi;
};
I point(const Z& z) { return I{z, z}; }
I operator+(const I& a, const I& b) { return {a.lo + b.lo, a.hi + b.hi}; }
I operator-(const I& a, const I& b) { return {a.lo - b.hi, a.hi - b.lo}; }
// The product's range: where neither factor's interval contains numbers of
// both signs its ends are two of the four end products (both >= 0: lo·lo and
// hi·hi; both <= 0: hi·hi and lo·lo; a >= 0 >= b: hi·lo and lo·hi; a <= 0 <=
// b: lo·hi and hi·lo), and a point times a point is one product; otherwise the
// smallest and largest of all four.
I operator*(const I& a, const I& b) {
    const bool a_pos = sgn(a.lo) >= 0, a_neg = sgn(a.hi) <= 0, b_pos = sgn(b.lo) >= 0, b_neg = sgn(b.hi) <= 0;
    if (cmp(a.lo, a.hi) == 0 && cmp(b.lo, b.hi) == 0) return point(a.lo * b.lo);
    if (a_pos && b_pos) return {a.lo * b.lo, a.hi * b.hi};
    if (a_neg && b_neg) return {a.hi * b.hi, a.lo * b.lo};
    if (a_pos && b_neg) return {a.hi * b.lo, a.lo * b.hi};
    if (a_neg && b_pos) return {a.lo * b.hi, a.hi * b.lo};
    const Z p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
    I r{p[0], p[0]};
    for (const Z& x : p) {
        if (cmp(x, r.lo) < 0) r.lo = x;
        if (cmp(x, r.hi) > 0) r.hi = x;
    }
    return r;
}
struct D {
    I v;
    std::array<I, 4> d;
    int n = 0;  // partials carried
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
// Second order: value, partials and second partials h[i][j] (i <= j < n).
struct D2 {
    I v;
    std::array<I, 4> d;
    std::array<std::array<I, 4>, 4> h;
    int n = 0;
};
D2 operator+(const D2& a, const D2& b) {
    D2 r{a.v + b.v, {}, {}, std::max(a.n, b.n)};
    for (int i = 0; i < r.n; ++i) {
        r.d[i] = a.d[i] + b.d[i];
        for (int j = i; j < r.n; ++j) r.h[i][j] = a.h[i][j] + b.h[i][j];
    }
    return r;
}
D2 operator-(const D2& a, const D2& b) {
    D2 r{a.v - b.v, {}, {}, std::max(a.n, b.n)};
    for (int i = 0; i < r.n; ++i) {
        r.d[i] = a.d[i] - b.d[i];
        for (int j = i; j < r.n; ++j) r.h[i][j] = a.h[i][j] - b.h[i][j];
    }
    return r;
}
D2 operator*(const D2& a, const D2& b) {
    D2 r{a.v * b.v, {}, {}, std::max(a.n, b.n)};
    for (int i = 0; i < r.n; ++i) {
        r.d[i] = a.d[i] * b.v + a.v * b.d[i];
        for (int j = i; j < r.n; ++j) r.h[i][j] = a.h[i][j] * b.v + a.v * b.h[i][j] + a.d[i] * b.d[j] + a.d[j] * b.d[i];
    }
    return r;
}
const I& val(const I& x) { return x; }
const I& val(const D& x) { return x.v; }

// ---- dyadic numbers m / 2^e (box ends) and parsing (hostile input) -----------------
struct Dy {
    std::int64_t m = 0;
    int e = 0;
};
constexpr int MAX_E = 60;  // box ends finer than 2^-60 are rejected
Dy at(const Dy& a, int e) {  // the same number with exponent e >= a.e
    return Dy{a.m * (std::int64_t{1} << (e - a.e)), e};
}
Dy mid(const Dy& a, const Dy& b) {
    const int e = std::max(a.e, b.e);
    if (e + 1 > MAX_E) fail("box too deep");
    return Dy{at(a, e).m + at(b, e).m, e + 1};
}
int cmp(const Dy& a, const Dy& b) {
    const int e = std::max(a.e, b.e);
    const std::int64_t x = at(a, e).m, y = at(b, e).m;
    return x < y ? -1 : x > y ? 1 : 0;
}
Dy width(const Dy& lo, const Dy& hi) {
    const int e = std::max(lo.e, hi.e);
    return Dy{at(hi, e).m - at(lo, e).m, e};
}
std::int64_t parse_int(const std::string& s) {
    const std::size_t from = !s.empty() && s[0] == '-' ? 1 : 0;
    if (s.size() <= from || s.size() - from > 18) fail("bad integer '" + s.substr(0, 60) + "'");
    for (std::size_t i = from; i < s.size(); ++i)
        if (s[i] < '0' || s[i] > '9') fail("bad integer '" + s.substr(0, 60) + "'");
    return std::stoll(s);
}
// "p/q" (or "p"): numerator and denominator, q > 0.
std::pair<std::int64_t, std::int64_t> parse_q(const std::string& s) {
    const auto slash = s.find('/');
    if (slash == std::string::npos) return {parse_int(s), 1};
    const std::int64_t d = parse_int(s.substr(slash + 1));
    if (d <= 0) fail("bad denominator in '" + s.substr(0, 60) + "'");
    return {parse_int(s.substr(0, slash)), d};
}
// A dyadic p / 2^e with |p / 2^e| <= 2 and e <= 40 (root boxes, claims).
Dy parse_dyadic(const std::string& s) {
    const auto [p, q] = parse_q(s);
    if ((q & (q - 1)) != 0) fail("number is not dyadic");
    int e = 0;
    while ((std::int64_t{1} << e) != q) ++e;
    if (e > 40 || p > (std::int64_t{2} << e) || p < -(std::int64_t{2} << e)) fail("number out of range: " + s.substr(0, 60));
    return Dy{p, e};
}
// a <= n / d (d > 0, |n|, d < 2^31), exactly.
bool le(const Dy& a, std::int64_t n, std::int64_t d) {
    return static_cast<__int128>(a.m) * d <= static_cast<__int128>(n) * (static_cast<__int128>(1) << a.e);
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
// The diagonals of a stencil's quads.  face[f], f the vertex off the face
// (a, b, r) with a < b its - vertices and r its + vertex: true iff the quad
// is split by a-cut(b, r).  inside: the inside quad of the n- = 2, n+ = 2
// prism where its face quads leave it free: 1 cut(a,r0)-cut(b,r1), 0
// cut(a,r1)-cut(b,r0), -1 the choice against the face (a, b, r0).
struct Diag {
    std::array<bool, 4> face{};
    int inside = -1;
};
// The face (a, b, r) without vertex f, a < b its - vertices, r its + vertex;
// false if the face has no quad.
bool quad_face(const Key& k, int f, int& a, int& b, int& r) {
    a = b = r = -1;
    for (int i = 0; i < 4; ++i) {
        if (i == f || k.sign[i] == 0) continue;
        if (k.sign[i] > 0) r = i;
        else (a < 0 ? a : b) = i;
    }
    return b >= 0 && r >= 0;
}
Diag parity_diag(const Key& k) {
    Diag d;
    for (int f = 0, a, b, r; f < 4; ++f)
        if (quad_face(k, f, a, b, r)) d.face[f] = diag_a(a, b, r, k.parity);
    return d;
}
// Whether the quad of face (x, y, r) (x, y its - vertices, any order) is
// split by x-cut(y, r).
bool takes(const Diag& d, int x, int y, int r) { return x < y ? d.face[6 - x - y - r] : !d.face[6 - x - y - r]; }
// The output tetrahedra, each positively oriented with cut points at the
// midpoints (orientation fixed below by the reference volume), the quads
// split as d says.
std::vector<Tet> stencil(const Key& k, const Diag& d) {
    std::vector<int> ng, zr, ps;
    for (int i = 0; i < 4; ++i) (k.sign[i] < 0 ? ng : k.sign[i] == 0 ? zr : ps).push_back(i);
    std::vector<Tet> out;
    if (ng.empty()) return out;  // no - vertex (all-zero included): never output, so no key
    if (ps.empty()) return {{0, 1, 2, 3}};
    if (ng.size() == 1) {
        Tet t{0, 1, 2, 3};
        for (int p : ps) t[p] = cut(ng[0], p);
        return {t};
    }
    if (ng.size() == 2 && ps.size() == 1) {  // pyramid over the quad of face (a, b, r)
        const int a = ng[0], b = ng[1], r = ps[0], z = zr[0];
        if (takes(d, a, b, r)) return {{z, a, b, cut(b, r)}, {z, a, cut(b, r), cut(a, r)}};
        return {{z, a, b, cut(a, r)}, {z, b, cut(b, r), cut(a, r)}};
    }
    // Prisms: bottom B, top T (T[i] = cut point of B[i]); lateral quad i joins
    // B[i], B[i+1]; its diagonal is B[i]-T[i+1] (f[i]) or B[i+1]-T[i].
    std::array<int, 3> B{}, T{};
    std::array<bool, 3> f{};
    if (ng.size() == 2) {  // two - two +: B = (a, cut(a,r0), cut(a,r1)), T likewise from b
        const int a = ng[0], b = ng[1];
        B = {a, cut(a, ps[0]), cut(a, ps[1])}, T = {b, cut(b, ps[0]), cut(b, ps[1])};
        f[0] = takes(d, a, b, ps[0]), f[2] = !takes(d, a, b, ps[1]);
        // The inside quad: forced (the only non-cyclic choice) where the face
        // quads turn the same way (the parity rule's always do), else d's.
        f[1] = f[0] == f[2] || d.inside < 0 ? !f[0] : d.inside == 1;
    } else {
        for (int i = 0; i < 3; ++i) B[i] = ng[i], T[i] = cut(ng[i], ps[0]);
        for (int i = 0; i < 3; ++i) f[i] = takes(d, B[i], B[(i + 1) % 3], ps[0]);
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
std::vector<Tet> stencil(const Key& k) { return stencil(k, parity_diag(k)); }
// The geometry of a key's generic tetrahedron: its reference vertices and
// each vertex's warp offset (zero for one that stays), integer lattice
// coordinates (BCC doubled, A15 quadrupled).
struct Frame {
    std::array<std::array<int, 3>, 4> ref{}, off{};
};
Frame bcc_frame(const Key& k) {
    Frame f;
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) f.ref[i][c] = REF[i][c], f.off[i][c] = k.warp[i] == STAY ? 0 : OFF[k.warp[i]][c];
    return f;
}
long ref_volume(const Tet& t, const Frame& fr) {  // 6 * volume at the reference with cut points at the midpoints, doubled
    long p[4][3];
    for (int v = 0; v < 4; ++v)
        for (int c = 0; c < 3; ++c)
            p[v][c] = t[v] < 4 ? 2 * fr.ref[t[v]][c] : fr.ref[EDGE[t[v] - 4][0]][c] + fr.ref[EDGE[t[v] - 4][1]][c];
    long a[3], b[3], c[3];
    for (int x = 0; x < 3; ++x) a[x] = p[1][x] - p[0][x], b[x] = p[2][x] - p[0][x], c[x] = p[3][x] - p[0][x];
    return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}
std::vector<Tet> oriented(const Key& k, const Diag& d, const Frame& fr) {
    std::vector<Tet> s = stencil(k, d);
    for (Tet& t : s) {
        const long v = ref_volume(t, fr);
        if (v == 0) fail("flat stencil tetrahedron");
        if (v < 0) std::swap(t[2], t[3]);
    }
    return s;
}
std::vector<Tet> oriented(const Key& k, const Diag& d) { return oriented(k, d, bcc_frame(k)); }
std::vector<Tet> oriented(const Key& k) { return oriented(k, parity_diag(k)); }

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
// The image of warp direction w under s's linear part (STAY stays).
int map_dir(int w, const Sym& s) {
    if (w == STAY) return STAY;
    int d[3] = {0, 0, 0};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) d[r] += s.L[r][c] * OFF[w][c];
    for (int v = 0; v < 14; ++v)
        if (OFF[v][0] == d[0] && OFF[v][1] == d[1] && OFF[v][2] == d[2]) return v;
    fail("a symmetry maps a lattice direction to none");
}
// The image of k under s, its parity bit the one whose output is the image of k's output.
Key image(const Key& k, const Sym& s) {
    Key m;
    for (int i = 0; i < 4; ++i) m.sign[s.p[i]] = k.sign[i], m.warp[s.p[i]] = map_dir(k.warp[i], s);
    const auto want = mapped(oriented(k), s.p);
    for (m.parity = 0; m.parity < (parity_quad(m) ? 2 : 1); ++m.parity)
        if (mapped(oriented(m), {0, 1, 2, 3}) == want) return m;
    fail("stencil does not commute with a symmetry");
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


// ---- verification of one leaf ------------------------------------------------------
struct Param {
    int index;  // 0..3: t of vertex index; 4 + e: u of edge e
    std::int64_t lo_num, hi_num, den;  // the exact box [lo_num/den, hi_num/den]
};
std::vector<Param> params(const Key& k, std::int64_t along, std::int64_t ashort, std::int64_t den) {
    std::vector<Param> ps;
    for (int i = 0; i < 4; ++i)
        if (k.sign[i] == 0 && k.warp[i] != STAY) ps.push_back({i, 0, k.warp[i] < 6 ? along : ashort, den});
    for (int e = 0; e < 6; ++e)
        if (k.sign[EDGE[e][0]] * k.sign[EDGE[e][1]] < 0) {
            const std::int64_t a = e < 2 ? along : ashort;
            ps.push_back({4 + e, a, den - a, den});
        }
    return ps;
}
struct Side {
    Dy lo, hi;
};
using Box = std::vector<Side>;
// The claim: cos^2 thresholds c / 2^40 (dihedral min and max, face angle min).
struct Claim {
    Z cmin, cmax, cface;
};

// The scaled integer 2^K · x of a box end (K >= x.e).
Z scaled(const Dy& x, int K) { return zint(x.m) * pow2(K - x.e); }

// The ten points of the generic tetrahedron of frame fr, times S, where the
// parameters ps take the scaled values val (val[i] = S times parameter i's
// interval; T = I: values only; T = D: with partials in the parameters, at
// the value's scale S; T = D2: and second partials).
template <class T>
std::array<std::array<T, 3>, 10> scaled_points(const Frame& fr, const std::vector<Param>& ps, const std::vector<I>& val, const Z& S) {
    std::array<T, 10> var{};
    for (std::size_t i = 0; i < ps.size(); ++i) {
        if constexpr (!std::is_same_v<T, I>) {
            var[ps[i].index] = T{};
            var[ps[i].index].v = val[i], var[ps[i].index].n = static_cast<int>(ps.size());
            var[ps[i].index].d[i] = point(S);  // dt/dt, at the value's scale S
        } else {
            var[ps[i].index] = val[i];
        }
    }
    const auto cst = [&](int v) {
        T c{};
        if constexpr (!std::is_same_v<T, I>) c.v = point(zint(v) * S);
        else c = point(zint(v) * S);
        return c;
    };
    const auto times = [&](int c, const T& x) {  // c · x, c a small integer
        T r{};
        if constexpr (!std::is_same_v<T, I>) {
            r = x;
            r.v = point(zint(c)) * x.v;
            for (int i = 0; i < r.n; ++i) r.d[i] = point(zint(c)) * x.d[i];  // second partials: 0 (t is linear)
        } else {
            r = point(zint(c)) * x;
        }
        return r;
    };
    std::array<std::array<T, 3>, 10> pt{};
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c) {
            pt[i][c] = cst(fr.ref[i][c]);
            if (fr.off[i][c] != 0) pt[i][c] = pt[i][c] + times(fr.off[i][c], var[i]);
        }
    for (int e = 0; e < 6; ++e)
        for (int c = 0; c < 3; ++c) {
            const int a = fr.ref[EDGE[e][0]][c], d = fr.ref[EDGE[e][1]][c] - a;
            pt[4 + e][c] = cst(a);
            if (d != 0) pt[4 + e][c] = pt[4 + e][c] + times(d, var[4 + e]);
        }
    return pt;
}
// The ten points on box b, times 2^K (K >= every end's exponent).
template <class T>
std::array<std::array<T, 3>, 10> points(const Frame& fr, const std::vector<Param>& ps, const Box& b, int K) {
    std::vector<I> val;
    for (const Side& s : b) val.push_back(I{scaled(s.lo, K), scaled(s.hi, K)});
    return scaled_points<T>(fr, ps, val, pow2(K));
}
template <class T>
std::array<std::array<T, 3>, 10> points(const Key& k, const std::vector<Param>& ps, const Box& b, int K) {
    return points<T>(bcc_frame(k), ps, b, K);
}

template <class T>
using P3 = std::array<T, 3>;
template <class T>
P3<T> sub3(const P3<T>& a, const P3<T>& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <class T>
P3<T> cross3(const P3<T>& a, const P3<T>& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <class T>
T dot3(const P3<T>& a, const P3<T>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
// The 25 forms of one output tetrahedron (scaled as in the header comment):
// 0: 6·volume (> 0); per edge e: 1 + 2e: −d, 2 + 2e: c_min N − 2^40 d² (one
// of them >= 0: θ >= θmin); 13 + 2e: d, 14 + 2e: c_max N − 2^40 d² (one >= 0:
// θ <= θmax).  Edge e = (a, b) of the tetrahedron's own vertex order, faces
// through the other two vertices c < d: n_c = (p_b − p_a) × (p_c − p_a).
// d = n_c·n_d and N = |n_c|²|n_d|² of edge e = (a, b) of tetrahedron t (its
// own vertex order), faces through the other two vertices c < d:
// n_c = (p_b − p_a) × (p_c − p_a).
template <class T, std::size_t N>
void edge_forms(const std::array<P3<T>, N>& pt, const Tet& t, int e, T& dt, T& nn) {
    const int a = EDGE[e][0], bb = EDGE[e][1];
    int c = 0;
    while (c == a || c == bb) ++c;
    const int d = 6 - a - bb - c;
    const P3<T> ev = sub3(pt[t[bb]], pt[t[a]]);
    const P3<T> nc = cross3(ev, sub3(pt[t[c]], pt[t[a]])), nd = cross3(ev, sub3(pt[t[d]], pt[t[a]]));
    dt = dot3(nc, nd), nn = dot3(nc, nc) * dot3(nd, nd);
}
// s = u·v and M = |u|²|v|² of face angle q of tetrahedron t: at vertex a =
// q / 3 of the face without vertex o (the (q % 3)-th other vertex), u, v to
// its other two vertices b < c.
template <class T, std::size_t N>
void angle_forms(const std::array<P3<T>, N>& pt, const Tet& t, int q, T& s, T& M) {
    const int a = q / 3, o = q % 3 < a ? q % 3 : q % 3 + 1;
    int b = 0;
    while (b == a || b == o) ++b;
    const int c = 6 - a - o - b;
    const P3<T> u = sub3(pt[t[b]], pt[t[a]]), v = sub3(pt[t[c]], pt[t[a]]);
    s = dot3(u, v), M = dot3(u, u) * dot3(v, v);
}
// The 49 forms of one output tetrahedron (scaled as in the header comment):
// 0: 6·volume (> 0); per edge e: 1 + 2e: −d, 2 + 2e: c_min N − 2^40 d² (one
// of them >= 0: θ >= θmin); 13 + 2e: d, 14 + 2e: c_max N − 2^40 d² (one >= 0:
// θ <= θmax); per face angle q: 25 + 2q: −s, 26 + 2q: c_face M − 2^40 s²
// (one >= 0: φ >= φmin; s degree 2, M degree 4).
template <class T, std::size_t N>
std::array<T, 49> tet_forms(const std::array<P3<T>, N>& pt, const Tet& t, const Claim& cl) {
    std::array<T, 49> f{};
    const P3<T>&p0 = pt[t[0]], &p1 = pt[t[1]], &p2 = pt[t[2]], &p3 = pt[t[3]];
    f[0] = dot3(sub3(p1, p0), cross3(sub3(p2, p0), sub3(p3, p0)));
    T cmin{}, cmax{}, cface{}, two40{};
    if constexpr (!std::is_same_v<T, I>)
        cmin.v = point(cl.cmin), cmax.v = point(cl.cmax), cface.v = point(cl.cface), two40.v = point(pow2(40));
    else cmin = point(cl.cmin), cmax = point(cl.cmax), cface = point(cl.cface), two40 = point(pow2(40));
    for (int e = 0; e < 6; ++e) {
        T dt{}, nn{};
        edge_forms(pt, t, e, dt, nn);
        const T dd = two40 * (dt * dt);
        f[1 + 2 * e] = T{} - dt, f[2 + 2 * e] = cmin * nn - dd;
        f[13 + 2 * e] = dt, f[14 + 2 * e] = cmax * nn - dd;
    }
    for (int q = 0; q < 12; ++q) {
        T sq{}, M{};
        angle_forms(pt, t, q, sq, M);
        f[25 + 2 * q] = T{} - sq, f[26 + 2 * q] = cface * M - two40 * (sq * sq);
    }
    return f;
}
// Form f alone (as tet_forms(pt, t, cl)[f], in the same order).
template <class T, std::size_t N>
T form_at(const std::array<P3<T>, N>& pt, const Tet& t, int f, const Claim& cl) {
    if (f == 0) return dot3(sub3(pt[t[1]], pt[t[0]]), cross3(sub3(pt[t[2]], pt[t[0]]), sub3(pt[t[3]], pt[t[0]])));
    const auto constant = [](const Z& z) {  // z with no partials
        T c{};
        if constexpr (std::is_same_v<T, I>) c = point(z);
        else c.v = point(z);
        return c;
    };
    T dt{}, nn{};
    const T two40 = constant(pow2(40));
    if (f >= 25) {
        angle_forms(pt, t, (f - 25) / 2, dt, nn);
        if ((f - 25) % 2 == 0) return T{} - dt;
        return constant(cl.cface) * nn - two40 * (dt * dt);
    }
    const int g = (f - 1) % 12, e = g / 2;
    edge_forms(pt, t, e, dt, nn);
    if (g % 2 == 0) return f < 13 ? T{} - dt : dt;
    return constant(f < 13 ? cl.cmin : cl.cmax) * nn - two40 * (dt * dt);
}
// ---- what a leaf is verified on ---------------------------------------------------
// A one-region key's ten points (points) or a junction face's fifteen
// (jpoints, below: times 12), over the parameters ps (for a junction face,
// only those its tetrahedra depend on).
struct Model {
    Key k;  // the warps (one region: and the signs)
    std::vector<Param> ps;
    bool junction = false;
    std::optional<Frame> a15;  // an A15 key's frame (its warps: fr.off; k.warp unused), else BCC's
    Frame frame() const { return a15 ? *a15 : bcc_frame(k); }
};
template <class T>
std::array<P3<T>, 15> jpoints(const Model& m, const Box& b, int K);
// f(the model's points on b, times 2^K) for T = I, D, D2; one region keeps
// its ten points (no cost for the five it does not have).
template <class T, class F>
auto on_points(const Model& m, const Box& b, int K, F&& f) {
    if (m.junction) return f(jpoints<T>(m, b, K));
    return f(points<T>(m.frame(), m.ps, b, K));
}

// ---- the Delaunay face rule (format 5) -------------------------------------------
// Its own forms, from the points (times 2^K).  The quad (a, b, cut(b,r),
// cut(a,r)) of a face (a, b, r) lies in a lattice face (a, b, r unmoved).
// The circle through a, b, cut(b,r) meets the line r-a again at distance
// P_b / |ra| from r, by the power of r, with P_x = (r - x)·(r - cut(x,r))
// = |xr| |r cut(x,r)|; so a-cut(b,r) is the Delaunay diagonal iff cut(a,r)
// lies outside that circle iff P_b - P_a > 0 (a tie: cocircular).  Each
// term of P_x is (r - x)_c² (1 - u) times a positive constant, all
// monotone the same way in the one cut fraction u, so the interval sum is
// P_x's exact range, and P_b - P_a (two cut fractions) is exact too.
I power(const std::array<P3<I>, 10>& pt, int x, int r) { return dot3(sub3(pt[r], pt[x]), sub3(pt[r], pt[cut(x, r)])); }
// The prism's inside quad takes the shorter diagonal: |cut(a,r0) cut(b,r1)|²
// - |cut(a,r1) cut(b,r0)|² < 0 iff cut(a,r0)-cut(b,r1).  Each coordinate
// difference is exact (one cut fraction per point); squares and sums in
// generic_bcc.hpp's order (inside_form), so this exact enclosure lies
// inside the prover's outward-rounded one.
I inside(const std::array<P3<I>, 10>& pt, int a, int b, int r0, int r1) {
    const P3<I> p = sub3(pt[cut(a, r0)], pt[cut(b, r1)]), q = sub3(pt[cut(a, r1)], pt[cut(b, r0)]);
    return dot3(p, p) - dot3(q, q);
}
// The signs an enclosure admits: both where it contains 0 on a box (either
// side may hold there), 0 where it is exactly 0 (a tie).
std::vector<int> admits(const I& x) {
    if (sgn(x.lo) > 0) return {1};
    if (sgn(x.hi) < 0) return {-1};
    if (sgn(x.lo) == 0 && sgn(x.hi) == 0) return {0};
    return {-1, 1};
}
// The output tetrahedra of every stencil the Delaunay rule admits where the
// points pt are (a leaf box, or an exact point: one stencil), each once.
// Ties, BCC: a face quad takes the parity rule's diagonal, the inside quad
// the choice against the face (a, b, r0).  A15 (m.a15): the tie of a face
// quad goes by the face's global order, which the key does not know, so a
// box admits both diagonals; an exact point (at_point: a witness) is the
// configuration on the reference tetrahedron itself, where a face quad's tie
// goes to a iff a's reference coordinates precede b's lexicographically and
// the inside quad's against the face (a, b, r0), as on BCC (a box admits
// both there too: another tetrahedron of the class may hold the key in
// another vertex order).  An n- = 3 prism's three face quads never all turn
// the same way at a point (P_a < P_b < P_c < P_a; a tie breaks no order),
// so such combinations are skipped.
std::vector<Tet> delaunay_tets(const Model& m, const std::array<P3<I>, 10>& pt, bool at_point) {
    const Key& k = m.k;
    const Frame fr = m.frame();
    std::array<std::vector<int>, 5> opt;  // per face (the vertex off it), then the inside quad
    std::vector<int> ng, ps;
    for (int i = 0; i < 4; ++i) {
        if (k.sign[i] < 0) ng.push_back(i);
        if (k.sign[i] > 0) ps.push_back(i);
    }
    const auto tie = [&](std::vector<int> o) { return m.a15 && !at_point && o == std::vector<int>{0} ? std::vector<int>{-1, 1} : o; };
    for (int f = 0, a, b, r; f < 4; ++f)
        opt[f] = quad_face(k, f, a, b, r) ? tie(admits(power(pt, b, r) - power(pt, a, r))) : std::vector<int>{1};
    opt[4] = ng.size() == 2 && ps.size() == 2 ? tie(admits(inside(pt, ng[0], ng[1], ps[0], ps[1]))) : std::vector<int>{0};
    Diag par = parity_diag(k);
    if (m.a15)
        for (int f = 0, a, b, r; f < 4; ++f)
            if (quad_face(k, f, a, b, r)) par.face[f] = fr.ref[a] < fr.ref[b];
    std::vector<Tet> out;
    for (int c = 0, n = 1; c < n; ++c) {
        Diag d;
        int rest = c;
        n = 1;
        for (int q = 0; q < 5; ++q) {
            const int s = opt[q][static_cast<std::size_t>(rest) % opt[q].size()];
            rest /= static_cast<int>(opt[q].size()), n *= static_cast<int>(opt[q].size());
            if (q < 4) d.face[q] = s == 0 ? par.face[q] : s > 0;
            else d.inside = s == 0 ? -1 : s < 0;
        }
        if (ng.size() == 3 && ps.size() == 1) {
            const bool f0 = takes(d, ng[0], ng[1], ps[0]);
            if (takes(d, ng[1], ng[2], ps[0]) == f0 && takes(d, ng[2], ng[0], ps[0]) == f0) continue;
        }
        for (const Tet& t : oriented(k, d, fr))
            if (std::find(out.begin(), out.end(), t) == out.end()) out.push_back(t);
    }
    return out;
}

int leaf_exponent(const Box& b) {
    int K = 0;
    for (const Side& s : b) K = std::max({K, s.lo.e, s.hi.e});
    return K + 1;
}
Box centre(const Box& b) {
    Box m = b;
    for (Side& s : m) s.lo = s.hi = mid(s.lo, s.hi);
    return m;
}
// The second-order Taylor form of form f of t on b around its centre m,
// times 2^(2K+1): 2^(2K+1) g(m) + 2^(K+1) sum_i g_i(m) [-R_i, R_i]
// + sum_i g_ii(b) [0, R_i²] + 2 sum_{i<l} g_il(b) [-R_i R_l, R_i R_l]
// (R_i = 2^K r_i, the half-widths; the partials at the point m, the second
// partials on the box; g is the scaled form, its partials in t).
I taylor2(const Model& m, const Tet& t, const Box& b, int K, int f, const Claim& cl) {
    const D g = on_points<D>(m, centre(b), K, [&](const auto& pt) { return form_at(pt, t, f, cl); });
    const D2 h = on_points<D2>(m, b, K, [&](const auto& pt) { return form_at(pt, t, f, cl); });
    std::vector<Z> R;
    for (const Side& s : b) R.push_back(half(scaled(width(s.lo, s.hi), K)));
    I sum = g.v * point(pow2(2 * K + 1));
    for (std::size_t i = 0; i < b.size(); ++i) {
        if (sgn(R[i]) == 0) continue;
        sum = sum + g.d[i] * point(pow2(K + 1)) * I{-R[i], R[i]} + h.h[i][i] * I{Z{}, R[i] * R[i]};
        for (std::size_t l = i + 1; l < b.size(); ++l)
            if (sgn(R[l]) != 0) sum = sum + h.h[i][l] * point(zint(2) * R[i] * R[l]) * I{zint(-1), zint(1)};
    }
    return sum;
}
// Form f of tetrahedron t >= 0 (> 0 if strict) on b: the natural enclosure
// g, then the mean-value form around the centre (mid: the form's value
// there), then the face where every variable whose partial has a decided
// sign is fixed at its worse end, again (re-evaluated there); where none is,
// the second-order Taylor form on that face.  K: b's scale.
bool holds(const Model& m, const Tet& t, Box b, int K, int f, bool strict, const Claim& cl, D g, I mid_value) {
    for (bool first = true;; first = false) {
        const auto pos = [&](const Z& x) { return strict ? sgn(x) > 0 : sgn(x) >= 0; };
        if (pos(g.v.lo)) return true;
        I mv = (first ? mid_value : on_points<I>(m, centre(b), K, [&](const auto& pt) { return form_at(pt, t, f, cl); })) * point(pow2(K));
        for (std::size_t i = 0; i < b.size(); ++i) {
            const Dy w = width(b[i].lo, b[i].hi);
            if (w.m == 0) continue;
            const Z r = half(scaled(w, K));
            mv = mv + g.d[i] * I{-r, r};
        }
        if (pos(mv.lo)) return true;
        bool fixed = false;
        for (std::size_t i = 0; i < b.size(); ++i) {
            if (cmp(b[i].lo, b[i].hi) == 0) continue;
            if (sgn(g.d[i].lo) >= 0) b[i].hi = b[i].lo, fixed = true;
            else if (sgn(g.d[i].hi) <= 0) b[i].lo = b[i].hi, fixed = true;
        }
        if (!fixed) return pos(taylor2(m, t, b, K, f, cl).lo);
        g = on_points<D>(m, b, K, [&](const auto& pt) { return form_at(pt, t, f, cl); });
    }
}
bool verify_leaf(const Model& m, const std::vector<Tet>& tets, const Box& b, const Claim& cl) {
    const int K = leaf_exponent(b);
    // The natural enclosures alone, without partials, often suffice.
    const bool all = on_points<I>(m, b, K, [&](const auto& pv) {
        for (const Tet& t : tets) {
            const auto f = tet_forms(pv, t, cl);
            const auto P = [&](int x) { return sgn(f[x].lo) >= 0; };
            if (sgn(f[0].lo) <= 0) return false;
            for (int e = 0; e < 6; ++e)
                if (!((P(1 + 2 * e) || P(2 + 2 * e)) && (P(13 + 2 * e) || P(14 + 2 * e)))) return false;
            for (int q = 0; q < 12; ++q)
                if (!(P(25 + 2 * q) || P(26 + 2 * q))) return false;
        }
        return true;
    });
    if (all) return true;
    const auto each = [&](const auto& pd, const auto& pm) {
        for (const Tet& t : tets) {
            const auto fb = tet_forms(pd, t, cl);
            const auto fm = tet_forms(pm, t, cl);
            const auto H = [&](int f, bool strict) { return holds(m, t, b, K, f, strict, cl, fb[f], fm[f]); };
            if (!H(0, true)) return false;
            // Either alternative proves a bound; the one matching the sign of d at
            // the centre is tried first (only the cost depends on the order).
            for (int e = 0; e < 6; ++e) {
                const bool acute = sgn(fm[13 + 2 * e].lo) > 0;
                const int s1 = 1 + 2 * e, q1 = 2 + 2 * e, s2 = 13 + 2 * e, q2 = 14 + 2 * e;
                if (!(acute ? H(q1, false) || H(s1, false) : H(s1, false) || H(q1, false))) return false;
                if (!(acute ? H(s2, false) || H(q2, false) : H(q2, false) || H(s2, false))) return false;
            }
            for (int q = 0; q < 12; ++q) {  // face angles: as the minimum, s in place of d
                const bool acute = sgn(fm[25 + 2 * q].hi) < 0;
                const int s1 = 25 + 2 * q, q1 = 26 + 2 * q;
                if (!(acute ? H(q1, false) || H(s1, false) : H(s1, false) || H(q1, false))) return false;
            }
        }
        return true;
    };
    return on_points<D>(m, b, K, [&](const auto& pd) { return on_points<I>(m, centre(b), K, [&](const auto& pm) { return each(pd, pm); }); });
}
// Replays the bisection: '1' + j splits side j at its midpoint, lower half
// first; '0' is a leaf, verified (Delaunay: every tetrahedron the rule
// admits on the leaf).
long replay(const Model& m, const std::vector<Tet>& tets, const Box& root, const std::string& splits, const Claim& cl, bool delaunay) {
    delaunay = delaunay && !m.junction && tets.size() > 1;  // a single output tetrahedron: no quad, nothing to choose
    std::vector<Box> stack{root};
    std::size_t at = 0;
    long leaves = 0;
    while (!stack.empty()) {
        const Box b = stack.back();
        stack.pop_back();
        if (at >= splits.size()) fail("split string too short");
        const char c = splits[at++];
        if (c == '0') {
            const auto at = [&] { return delaunay_tets(m, points<I>(m.frame(), m.ps, b, leaf_exponent(b)), false); };
            if (!verify_leaf(m, delaunay ? at() : tets, b, cl)) fail("leaf not verified");
            ++leaves;
            continue;
        }
        const std::size_t s = static_cast<std::size_t>(c - '1');
        if (c < '1' || s >= b.size() || stack.size() > 200) fail("bad split string");
        const Dy m = mid(b[s].lo, b[s].hi);
        Box lo = b, hi = b;
        lo[s].hi = m, hi[s].lo = m;
        stack.push_back(hi), stack.push_back(lo);
    }
    if (at != splits.size()) fail("split string too long");
    return leaves;
}


// ---- witnesses and tightness ---------------------------------------------------
// An exact cos² p / q of an angle, acute or (right or) obtuse.
struct Cos2 {
    Z p, q;
    bool acute = false;
};
double to_double(const Z& z) {  // for messages only
    double x = 0;
    for (int i = z.n - 1; i >= 0; --i) x = x * 18446744073709551616.0 + static_cast<double>(z.d[i]);
    return z.neg ? -x : x;
}
double degrees(const Cos2& c) {  // for messages only
    const double a = std::acos(std::sqrt(to_double(c.p) / to_double(c.q))) * 180 / M_PI;
    return c.acute ? a : 180 - a;
}
// Whether angle a is larger than angle b.
bool larger(const Cos2& a, const Cos2& b) {
    if (a.acute != b.acute) return b.acute;
    const int c = cmp(a.p * b.q, b.p * a.q);
    return a.acute ? c < 0 : c > 0;
}
// The extreme over `tets` at the exact points pt (witness_cos2's, by kind);
// found: whether some angle qualified.
template <std::size_t N>
int extreme_cos2(const std::vector<Tet>& tets, const std::array<P3<I>, N>& pt, int kind, bool& found, Cos2& best) {
    for (const Tet& t : tets)
        for (int e = 0; e < (kind == 2 ? 12 : 6); ++e) {
            I dt, nn;
            if (kind == 2) angle_forms(pt, t, e, dt, nn);
            else edge_forms(pt, t, e, dt, nn);  // points: exact, dt.lo == dt.hi
            const Cos2 c{dt.lo * dt.lo, nn.lo, sgn(dt.lo) > 0};
            if (kind != 1 ? c.acute && (!found || larger(best, c)) : !found || larger(c, best)) best = c, found = true;
        }
    return 0;
}
// The exact cos² of the extreme angle of the key's output at the witness w
// (dyadic, inside the exact box), by kind: 0 the smallest dihedral angle
// (the largest d²/N over the edges with d > 0), 1 the largest (the largest
// d²/N over the edges with d <= 0; if every angle is acute, the smallest
// d²/N), 2 the smallest face angle (the largest s²/M with s > 0).
// Delaunay: the stencil the rule chooses at the witness.
Cos2 witness_cos2(const Model& m, const std::vector<Tet>& tets, const std::vector<Dy>& w, int kind, bool delaunay) {
    Box b;
    int K = 0;
    for (const Dy& x : w) b.push_back(Side{x, x}), K = std::max(K, x.e);
    bool found = false;
    Cos2 best;
    on_points<I>(m, b, K, [&](const auto& pt) {
        if constexpr (std::tuple_size_v<std::decay_t<decltype(pt)>> == 10)
            if (delaunay) return extreme_cos2(delaunay_tets(m, pt, true), pt, kind, found, best);
        return extreme_cos2(tets, pt, kind, found, best);
    });
    if (!found) fail("min witness without an acute angle");
    return best;
}
// Whether the witness's angle (cos² c = p/q) is at most tol degrees beyond the
// claim's (cos² C = cm / 2^40), given c <= C, both angles acute (minimum) or
// both obtuse (maximum).  |dθ/dc| = 1 / |sin 2θ|, and |sin 2θ| = 2 sqrt(c (1 − c))
// is concave in θ on each side of 90°, so the gap is at most (C − c) / the
// smaller |sin 2θ| of the two ends; with δ = tol · 3.14159 / 180 (below tol
// in radians): (C − c)² <= 4 δ² min(c (1 − c), C (1 − C)).  δ = 314159 / den
// (den = 18000000000 / tol·100...: 1800000000 for 0.01°, 180000000 for 0.1°).
// Near 90° the ends' |sin 2θ| vanish: obtuse angles with C <= 3·10^-6 <
// sin²(0.0993°) both lie in [90°, 90.0993°].  An acute max witness (every
// angle there acute) against the claim's θ >= 90°: the gap is
// arcsin √c + arcsin √C <= (π/3)(√c + √C) (arcsin is convex on [0, 1] and
// arcsin ½ = π/6), at most 60 (√c + √C) degrees; tight if √c + √C <= 1/S,
// S = 60 / tol = den / 300000, i.e. Y = 1/S² − c − C >= 0 and 4 c C <= Y²
// (scaled by S² q 2^40).
bool tight(const Z& cm, const Cos2& w, std::int64_t den, bool obtuse) {
    if (obtuse && w.acute) {
        const Z S2 = zint(den / 300000) * zint(den / 300000);
        const Z Y = w.q * pow2(40) - S2 * w.p * pow2(40) - S2 * cm * w.q;
        return sgn(Y) >= 0 && cmp(zint(4) * w.p * cm * S2 * S2 * w.q * pow2(40), Y * Y) <= 0;
    }
    if (obtuse && cmp(cm * zint(1000000), zint(3) * pow2(40)) <= 0) return true;
    const Z X = cm * w.q - w.p * pow2(40);
    const Z lhs = X * X * zint(den) * zint(den);
    const Z k4 = zint(4) * zint(314159) * zint(314159);
    if (cmp(lhs, k4 * pow2(80) * w.p * (w.q - w.p)) <= 0 && cmp(lhs, k4 * cm * (pow2(40) - cm) * w.q * w.q) <= 0) return true;
    // Near 90° |sin 2θ| vanishes and the bound above fails; there use
    // |θ − 90°| = arcsin y (y = √x, x = cos² θ), whose slope 1/√(1 − y²) =
    // 1/√(1 − x) is at most 1/√(1 − C) for x in [c, C]: the gap is at most
    // (√C − √c)/√(1 − C),
    // within δ if √C − √c <= δ √(1 − C), i.e. with L = C + c − δ²(1 − C):
    // L <= 0 or L² <= 4 c C.  Scaled by 2^40 q den²: L' = cm q den² +
    // p 2^40 den² − 314159² (2^40 − cm) q, and L'² <= 4 p cm 2^40 q den⁴.
    if (w.q.n > 4) return false;  // q < 2^256 keeps L'² (< 2^720) within the 768 bits
    const Z d2 = zint(den) * zint(den);
    const Z L = cm * w.q * d2 + w.p * pow2(40) * d2 - zint(314159) * zint(314159) * (pow2(40) - cm) * w.q;
    return sgn(L) <= 0 || cmp(L * L, zint(4) * w.p * cm * pow2(40) * w.q * d2 * d2) <= 0;
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

// A claim's threshold as c with C = c / 2^40, 0 < C < 1.
Z claim_threshold(const std::string& s) {
    const Dy x = parse_dyadic(s);
    if (x.m <= 0 || x.m >= (std::int64_t{1} << x.e)) fail("claim out of (0, 1)");
    return zint(x.m) * pow2(40 - x.e);
}

struct Entry {
    std::string code;
    Key k;
    std::vector<Param> ps;
    Box root;
    Claim claim;
    std::array<std::vector<Dy>, 3> w;  // witnesses: min, max (dihedral), face
    std::string splits;
};
// Claim j: 0 dihedral min, 1 dihedral max, 2 face angle min.
const Z& claim_of(const Claim& c, int j) { return j == 0 ? c.cmin : j == 1 ? c.cmax : c.cface; }
// One key line: "key CODE m lo_0 hi_0 .. CMIN CMAX CFACE WMIN_0 .. WMAX_0 ..
// WFACE_0 .. SPLITS":
// the root box containing the exact box, the key's claim, its witnesses
// inside the exact box, and a complete preorder bisection.
// x >= n / d (d > 0), exactly.
bool ge(const Dy& a, std::int64_t n, std::int64_t d) {
    return static_cast<__int128>(a.m) * d >= static_cast<__int128>(n) * (static_cast<__int128>(1) << a.e);
}
// The root box of parameters ps from `in`: dyadic ends containing each exact
// parameter box, each side narrower than 1.
Box parse_root(std::istream& in, const std::vector<Param>& ps, const std::string& code) {
    Box root;
    std::string lo, hi;
    for (const Param& p : ps) {
        if (!(in >> lo >> hi)) fail("bad root box for " + code);
        const Dy l = parse_dyadic(lo), h = parse_dyadic(hi);
        if (!(le(l, p.lo_num, p.den) && ge(h, p.hi_num, p.den) && cmp(width(l, h), Dy{1, 0}) < 0))
            fail("root box does not contain the parameter box of " + code);
        root.push_back(Side{l, h});
    }
    return root;
}
// The three witnesses (min, max, face) from `in`, each a point of the exact box.
std::array<std::vector<Dy>, 3> parse_witnesses(std::istream& in, const std::vector<Param>& ps, const std::string& code) {
    std::array<std::vector<Dy>, 3> out;
    std::string x;
    for (std::vector<Dy>& w : out)
        for (const Param& p : ps) {
            if (!(in >> x)) fail("bad witness for " + code);
            const Dy v = parse_dyadic(x);
            if (!(ge(v, p.lo_num, p.den) && le(v, p.hi_num, p.den))) fail("witness outside the parameter box of " + code);
            w.push_back(v);
        }
    return out;
}
// The split string, the line's last word: a complete preorder bisection of
// an m-parameter box.
std::string parse_splits(std::istream& in, int m, const std::string& code) {
    std::string splits, word;
    if (!(in >> splits) || splits.size() > 50000000 || (in >> word)) fail("bad split string for " + code);
    long open = 1;  // a preorder bisection: every '1' opens two subtrees, every '0' closes one
    for (const char ch : splits) {
        if (open == 0) fail("split string too long for " + code);
        if (ch < '0' || ch >= '1' + m) fail("bad split string for " + code);
        open += ch == '0' ? -1 : 1;
    }
    if (open != 0) fail("split string too short for " + code);
    return splits;
}
Entry parse_key_line(const std::string& line, std::int64_t along, std::int64_t ashort, std::int64_t den,
                     const std::set<std::array<int, 9>>& expected, std::set<std::array<int, 9>>& seen) {
    std::istringstream ks(line);
    std::string word, code;
    int m = -1;
    if (!(ks >> word >> code >> m) || word != "key") fail("bad key line");
    Entry en{code, parse_code(code), {}, {}, {}, {}, {}};
    if (!expected.count(en.k.enc()) || !seen.insert(en.k.enc()).second) fail("unexpected or repeated key " + code);
    en.ps = params(en.k, along, ashort, den);
    if (m != static_cast<int>(en.ps.size())) fail("wrong parameter count for " + code);
    en.root = parse_root(ks, en.ps, code);
    std::string lo, hi, fa;
    if (!(ks >> lo >> hi >> fa)) fail("bad claim for " + code);
    en.claim = Claim{claim_threshold(lo), claim_threshold(hi), claim_threshold(fa)};
    en.w = parse_witnesses(ks, en.ps, code);
    en.splits = parse_splits(ks, m, code);
    return en;
}

// The key's witnesses agree with its claim (c <= C: else the claim is false;
// an acute max witness agrees with every claim, which is >= 90°).
// Returns the witnesses' cos² and whether each is tight: within 0.01° of the
// claim (minima), 0.1° (maximum).
struct Witnessed {
    std::array<Cos2, 3> c;
    std::array<bool, 3> tight;
};
std::int64_t tol_den(int j) { return j == 1 ? 180000000 : 1800000000; }  // 0.1°, 0.01° (see tight)
Witnessed check_witnesses(const Entry& en, bool delaunay) {
    const std::vector<Tet> tets = oriented(en.k);
    Witnessed w{};
    for (int j = 0; j < 3; ++j) {
        w.c[j] = witness_cos2(Model{en.k, en.ps, false, std::nullopt}, tets, en.w[j], j, delaunay);
        const Z& c = claim_of(en.claim, j);
        if ((j != 1 || !w.c[j].acute) && cmp(w.c[j].p * pow2(40), c * w.c[j].q) > 0) fail("the witness of " + en.code + " contradicts its claim");
        w.tight[j] = tight(c, w.c[j], tol_den(j), j == 1);
    }
    return w;
}

const char* const KIND[3] = {"min", "max", "face"};
const char* const TOL[3] = {"0.01", "0.1", "0.01"};

// The claim is the keys' extremes (largest C_min, C_max, C_face) and tight:
// its most extreme witness per kind (ext: that key) lies within 0.01° /
// 0.1° of it, as check's.
void theorem_extremes(const Claim& claim, const std::vector<Entry>& entries, const std::vector<Witnessed>& wit, std::size_t* ext) {
    for (int j = 0; j < 3; ++j) {
        Z worst = zint(0);
        for (std::size_t i = 0; i < entries.size(); ++i) {
            if (cmp(claim_of(entries[i].claim, j), worst) > 0) worst = claim_of(entries[i].claim, j);
            if (j != 1 ? larger(wit[ext[j]].c[j], wit[i].c[j]) : larger(wit[i].c[j], wit[ext[j]].c[j])) ext[j] = i;
        }
        if (cmp(worst, claim_of(claim, j)) != 0) fail("the claim is not the keys' extremes");
        if (!tight(claim_of(claim, j), wit[ext[j]].c[j], tol_den(j), j == 1))
            fail(std::string("the theorem's ") + KIND[j] + " witness (" + entries[ext[j]].code + ") is not within " + TOL[j] +
                 " deg of the claim");
    }
}

// Prints the theorem (checked), its witnesses (ext: the most extreme key per
// kind) and the keys' tightness; degrees by arccos in double, messages only:
// the theorem is the exact statement of the first line.
void print_theorem(const std::string& setting, const std::array<std::string, 3>& text, const Claim& claim,
                   const std::vector<Entry>& entries, const std::vector<Witnessed>& wit, const std::size_t* ext, long leaves,
                   const char* lattice = "BCC") {
    double deg[3];
    for (int j = 0; j < 3; ++j) deg[j] = degrees(Cos2{claim_of(claim, j), pow2(40), j != 1});
    std::cout << std::fixed << std::setprecision(10) << lattice << " theorem (alphas " << setting
              << "): every output tetrahedron of the " << entries.size()
              << " keys is positively oriented, and every dihedral angle t has cos t <= 0 or cos^2 t <= " << text[0]
              << ", and cos t >= 0 or cos^2 t <= " << text[1] << ": t in [" << deg[0] << ", " << deg[1] << "] deg (" << leaves
              << " leaves)\n";
    std::cout << std::setprecision(4) << "  rounded outward: every dihedral angle in [" << std::floor(deg[0] * 1e4) / 1e4 << ", "
              << std::ceil(deg[1] * 1e4) / 1e4 << "] deg\n";
    std::cout << std::setprecision(10) << "  face angles: every face angle t of every output tetrahedron has cos t <= 0 or cos^2 t <= "
              << text[2] << ": t >= " << deg[2] << " deg (rounded down: " << std::setprecision(4) << std::floor(deg[2] * 1e4) / 1e4
              << ")\n";
    for (int j = 0; j < 3; ++j) {
        const double w = degrees(wit[ext[j]].c[j]);
        std::cout << std::setprecision(10) << (j < 2 ? "  3D witness " : "  face witness ") << (j < 2 ? KIND[j] : "min") << " "
                  << entries[ext[j]].code << ": angle " << w << " deg, claim " << deg[j] << " deg, gap " << std::fabs(w - deg[j])
                  << " deg\n";
    }
    for (int j = 0; j < 3; ++j) {  // per-key tightness: counts, and the largest gaps
        long tight = 0;
        double gap = 0;
        std::size_t gk = 0;
        for (std::size_t i = 0; i < entries.size(); ++i) {
            tight += wit[i].tight[j];
            const double g = std::fabs(degrees(wit[i].c[j]) - degrees(Cos2{claim_of(entries[i].claim, j), pow2(40), j != 1}));
            if (g > gap) gap = g, gk = i;
        }
        std::cout << std::setprecision(4) << "  key " << KIND[j] << " claims: " << tight << " of " << entries.size() << " within "
                  << TOL[j] << " deg of their witnesses; largest gap " << gap << " deg (" << entries[gk].code << ")\n";
    }
}

// ---- the counter-example certificate (proofs/bcc_half.cert) ---------------------------
// Format (proofs/README.md, "The α = ½ rule: a counter-example"):
//   warpmesh-bcc-counterexample 1
//   alphas L S            exact rationals with one denominator, 0 < α <= 1/2
//   key CODE              a canonical consistent key with output
//   point x_0 .. x_{m-1}  dyadic, inside the key's exact parameter box at the alphas
//   inverted P0 P1 P2 P3  an output tetrahedron of the key's stencil (points
//                         0..3 the vertices, 4 + e the cut point of edge e)
// The statement: at that configuration of the key's space the tetrahedron,
// in the stencil's positive orientation (positive at the reference
// configuration), has 6·volume <= 0; and at the same point with every warp
// t set to 0 (in the box: t ∈ [0, α]) it has 6·volume > 0.  Both exactly
// (points times 2^K with integer coordinates; 6·volume of degree 3, so its
// sign is the exact one).  So the space contains a flat output tetrahedron
// (6·volume is a polynomial on the segment between the two points, and the
// box is convex), and no theorem of bcc.cert's form (every output tetrahedron
// positively oriented) holds at these alphas.
// The same denominator for both alphas, below 2^31; 0 < α <= 1/2 (at α = 1/2
// a cut point violates at most one endpoint, since the violation is u < α,
// so the consistency rules still hold and the space is still a superset).
std::pair<std::int64_t, std::int64_t> counterexample_alphas(const std::string& line, std::int64_t& den) {
    std::istringstream a(line);
    std::string word, al, as;
    if (!(a >> word >> al >> as) || word != "alphas" || (a >> word)) fail("bad alphas line");
    const auto [ln, ld] = parse_q(al);
    const auto [sn, sd] = parse_q(as);
    if (ld != sd || ld >= (std::int64_t{1} << 31)) fail("alphas need one denominator below 2^31");
    if (!(ln > 0 && 2 * ln <= ld && sn > 0 && 2 * sn <= sd)) fail("alphas out of (0, 1/2]");
    den = ld;
    return {ln, sn};
}
// The key of CODE: consistent, with output, canonical.
Key checked_key(const std::string& code) {
    const Key k = parse_code(code);
    if (!consistent(k) || stencil(k).empty()) fail("key " + code + " is not a consistent key with output");
    std::array<int, 9> best = k.enc();
    for (const Sym& s : symmetries()) best = std::min(best, image(k, s).enc());
    if (best != k.enc()) fail("key " + code + " is not canonical");
    return k;
}
// The key of the "key CODE" line.
Key counterexample_key(const std::string& line, std::string& code) {
    std::istringstream ks(line);
    std::string word;
    if (!(ks >> word >> code) || word != "key" || (ks >> word)) fail("bad key line");
    return checked_key(code);
}
// The rest of ps_in: one dyadic per parameter, each inside the exact box.
Box exact_point(std::istringstream& ps_in, const std::vector<Param>& ps, const std::string& code) {
    std::string x;
    Box b;
    for (const Param& p : ps) {
        if (!(ps_in >> x)) fail("too few parameters for " + code);
        const Dy v = parse_dyadic(x);
        const bool ge = static_cast<__int128>(v.m) * p.den >= static_cast<__int128>(p.lo_num) * (static_cast<__int128>(1) << v.e);
        if (!(ge && le(v, p.hi_num, p.den))) fail("point outside the parameter box of " + code);
        b.push_back(Side{v, v});
    }
    if (ps_in >> x) fail("too many parameters for " + code);
    return b;
}
// The "point" line.
Box counterexample_point(const std::string& line, const std::vector<Param>& ps, const std::string& code) {
    std::istringstream ps_in(line);
    std::string word;
    if (!(ps_in >> word) || word != "point") fail("bad point line");
    return exact_point(ps_in, ps, code);
}
// The "inverted" line's tetrahedron, as the stencil orients it.
Tet counterexample_tet(const std::string& line, const Key& k, const std::string& code) {
    std::istringstream ts(line);
    std::string word;
    Tet want{};
    if (!(ts >> word) || word != "inverted") fail("bad inverted line");
    for (int& v : want)
        if (!(ts >> v) || v < 0 || v > 9) fail("bad inverted line");
    if (ts >> word) fail("bad inverted line");
    std::sort(want.begin(), want.end());
    for (const Tet& t : oriented(k)) {
        Tet s = t;
        std::sort(s.begin(), s.end());
        if (s == want) return t;
    }
    fail("the inverted tetrahedron is not an output tetrahedron of " + code);
}
// The finest exponent of a point's coordinates (its points are integers times 2^-K).
int finest_exponent(const Box& b) {
    int K = 0;
    for (const Side& s : b) K = std::max(K, s.lo.e);
    return K;
}
// 6·volume of t at the point b, times 2^(3K) (K = finest_exponent(b)): exact.
Z volume6_at(const Key& k, const std::vector<Param>& ps, const Box& b, const Tet& t) {
    const auto pt = points<I>(k, ps, b, finest_exponent(b));
    const I v = dot3(sub3(pt[t[1]], pt[t[0]]), cross3(sub3(pt[t[2]], pt[t[0]]), sub3(pt[t[3]], pt[t[0]])));
    if (cmp(v.lo, v.hi) != 0) fail("internal: a point's volume is not exact");
    return v.lo;
}
int check_counterexample(const std::vector<std::string>& body) {
    if (body.size() != 5) fail("a counter-example has five lines");
    std::int64_t den = 0;
    const auto [ln, sn] = counterexample_alphas(body[1], den);
    std::string code;
    const Key k = counterexample_key(body[2], code);
    const std::vector<Param> ps = params(k, ln, sn, den);
    const Box b = counterexample_point(body[3], ps, code);
    const Tet t = counterexample_tet(body[4], k, code);
    const Z v = volume6_at(k, ps, b, t);
    if (sgn(v) > 0) fail("the tetrahedron of " + code + " is positively oriented at the point (6*volume > 0)");
    Box unwarped = b;  // every t_i = 0, the cut points as given
    for (std::size_t i = 0; i < ps.size(); ++i)
        if (ps[i].index < 4) unwarped[i] = Side{Dy{0, 0}, Dy{0, 0}};
    if (sgn(volume6_at(k, ps, unwarped, t)) <= 0) fail("the tetrahedron of " + code + " is not positively oriented without its warps");
    const int K = finest_exponent(b);
    std::string at = body[3].substr(body[3].find(' ') + 1);  // the point as written (exact dyadics)
    std::replace(at.begin(), at.end(), ' ', ',');
    // 6·volume = v / 2^(3K) in doubled coordinates; the double is for the message only.
    std::cout << std::setprecision(10) << "BCC counter-example (alphas " << ln << "/" << den << ", " << sn << "/" << den
              << "): key " << code << " at (" << at << "): output tetrahedron (" << t[0] << " " << t[1] << " " << t[2] << " "
              << t[3] << ") has 6*volume " << to_double(v) / std::ldexp(1.0, 3 * K) << (sgn(v) < 0 ? " < 0 (inverted" : " = 0 (flat")
              << "; doubled lattice coordinates), > 0 with every warp t = 0: the key's space contains a flat output "
                 "tetrahedron, NO BOUND on the dihedral angles at these alphas\n";
    return 3;  // verified, but the statement is a counter-example, not a bound
}

// ---- the ceiling certificate (proofs/bcc_ceiling.cert) ------------------------------
// Format (proofs/README.md, "A ceiling: no thresholds reach 12°"):
//   warpmesh-bcc-ceiling 1
//   below DEG C          DEG = p/q degrees (0 < DEG <= 60), C an integer with
//                        cos²(DEG°) <= C / 2^40 < 1
//   then a quadtree over the square [0, 1/2]² of (α_long, α_short), depth
//   first from the whole square: `split` (the box's four quadrants follow,
//   (low, low), (high, low), (low, high), (high, high) in (α_long, α_short))
//   or `witness CODE x_0 .. x_{m-1}` for the box [L0, L1] × [S0, S1].
// A witness holds when CODE is a canonical consistent key whose stencil is a
// single tetrahedron (no quad: no face rule enters), the point lies in the
// key's exact parameter box at every pair of the box (a warp t in [0, L0] or
// [0, S0] by its edge's type, a cut fraction u in [L1, 1 − L1] or
// [S1, 1 − S1]: those boxes are the intersections over the pairs), and
// there the tetrahedron has 6·volume > 0 and a dihedral angle θ with d > 0
// and 2^40 d² > C N (cos θ = d / √N > 0, cos²θ > C / 2^40 >= cos²(DEG°): θ <
// DEG°), all exact.  The statement: for every pair (α_long, α_short) in
// [0, 1/2]² the key space at that pair contains a positively oriented output
// tetrahedron with a dihedral angle below DEG° — no thresholds, with any
// face rule, give θmin >= DEG° over the space.
//
// C against DEG without a transcendental function: x = π·DEG/180 <= π/3;
// cos x <= P(x) = 1 − x²/2 + x⁴/24 for |x| < π/2 (the Taylor remainder
// −cos(ξ) x⁶/720 <= 0), P decreases on (0, √6) and x_lo = 3.14159·DEG/180 <
// x, so cos²(DEG°) <= P(x_lo)², a rational; the check is C / 2^40 >= P(x_lo)².
// With x_lo = X / Dn, X = 314159 p, Dn = 18000000 q: P(x_lo) = (24 Dn⁴ − 12 X²
// Dn² + X⁴) / (24 Dn⁴), so C (24 Dn⁴)² >= 2^40 (24 Dn⁴ − 12 X² Dn² + X⁴)².
constexpr int CEILING_DEPTH = 39;  // box ends k / 2^40 at most
struct Ceiling {
    Z c;
    double deg = 0;  // for the message only
    long boxes = 0;
    std::map<std::string, long> keys;  // witnesses per key
};
Ceiling ceiling_claim(const std::string& line, std::string& deg) {
    std::istringstream in(line);
    std::string word, c;
    if (!(in >> word >> deg >> c) || word != "below" || (in >> word)) fail("bad below line");
    const auto [p, q] = parse_q(deg);
    if (q > 1000000 || p <= 0 || p > 60 * q) fail("below: degrees out of (0, 60] or denominator above 10^6");
    const std::int64_t cc = parse_int(c);
    if (cc <= 0 || cc >= (std::int64_t{1} << 40)) fail("below: C out of (0, 2^40)");
    const Z X = zint(314159) * zint(p), Dn = zint(18000000) * zint(q);
    const Z D2 = Dn * Dn, D4 = D2 * D2, X2 = X * X;
    const Z num = zint(24) * D4 - zint(12) * X2 * D2 + X2 * X2, den = zint(24) * D4;
    if (sgn(num) <= 0 || cmp(zint(cc) * den * den, pow2(40) * num * num) < 0) fail("below: C / 2^40 is not >= cos^2 of the angle");
    Ceiling cl;
    cl.c = zint(cc);
    cl.deg = static_cast<double>(p) / static_cast<double>(q);
    return cl;
}
// One witness line for the box [i, i + 1] × [j, j + 1] / 2^e.
void ceiling_witness(const std::string& line, std::int64_t i, std::int64_t j, int e, Ceiling& cl) {
    std::istringstream in(line);
    std::string word, code;
    if (!(in >> word >> code) || word != "witness") fail("bad quadtree line '" + line.substr(0, 60) + "'");
    const Key k = checked_key(code);
    const std::vector<Tet> tets = oriented(k);
    if (tets.size() != 1) fail("key " + code + " has more than one output tetrahedron (a face rule would enter)");
    const std::int64_t den = std::int64_t{1} << e;
    std::vector<Param> ps = params(k, i, j, den);  // warps: t in [0, α_lo]
    const std::vector<Param> hi = params(k, i + 1, j + 1, den);  // cuts: u in [α_hi, 1 − α_hi]
    for (std::size_t n = 0; n < ps.size(); ++n)
        if (ps[n].index >= 4) ps[n] = hi[n];
    const Box b = exact_point(in, ps, code);
    if (sgn(volume6_at(k, ps, b, tets[0])) <= 0) fail("the tetrahedron of " + code + " is not positively oriented at the point");
    const auto pt = points<I>(k, ps, b, finest_exponent(b));
    for (int edge = 0; edge < 6; ++edge) {
        I dt{}, nn{};
        edge_forms(pt, tets[0], edge, dt, nn);
        if (sgn(dt.lo) > 0 && cmp(pow2(40) * dt.lo * dt.lo, cl.c * nn.lo) > 0) {
            ++cl.boxes, ++cl.keys[code];
            return;
        }
    }
    fail("no dihedral angle of " + code + " below the ceiling at the point (box " + std::to_string(i) + ", " + std::to_string(j) +
         " / 2^" + std::to_string(e) + ")");
}
// The quadtree from line `at` for the box (i, j) at depth d (side 2^-(d+1)).
void ceiling_box(const std::vector<std::string>& body, std::size_t& at, std::int64_t i, std::int64_t j, int d, Ceiling& cl) {
    if (at >= body.size()) fail("the quadtree ends before every box is settled");
    if (body[at] != "split") return ceiling_witness(body[at++], i, j, d + 1, cl);
    if (d == CEILING_DEPTH) fail("quadtree deeper than " + std::to_string(CEILING_DEPTH));
    ++at;
    for (const auto& [di, dj] : {std::pair{0, 0}, {1, 0}, {0, 1}, {1, 1}}) ceiling_box(body, at, 2 * i + di, 2 * j + dj, d + 1, cl);
}
int check_ceiling(const std::vector<std::string>& body) {
    if (body.size() < 3) fail("a ceiling has a below line and a quadtree");
    std::string deg;
    Ceiling cl = ceiling_claim(body[1], deg);
    std::size_t at = 2;
    ceiling_box(body, at, 0, 0, 0, cl);
    if (at != body.size()) fail("lines after the quadtree");
    std::cout << "BCC ceiling: for every (alpha_long, alpha_short) in [0, 1/2]^2 the space contains a positively oriented "
                 "output tetrahedron with a dihedral angle below "
              << deg << " deg (= " << std::setprecision(6) << cl.deg << " deg; cos^2 > " << to_double(cl.c) / std::ldexp(1.0, 40)
              << "), of a key whose stencil is one tetrahedron (no face rule enters): " << cl.boxes << " boxes (";
    const char* sep = "";
    for (const auto& [code, n] : cl.keys) std::cout << sep << code << " " << n, sep = ", ";
    std::cout << "); NO BOUND theta_min >= " << deg << " deg at any thresholds\n";
    return 3;  // verified, but the statement is a limit, not a bound
}

// ---- the graded templates (proofs/bcc_graded.cert) ----------------------------------
// Format (proofs/README.md, "Graded transitions (3D, bcc_graded.cert)"):
//   warpmesh-bcc-graded 1
//   claim CMIN CMAX CFACE        dyadic p/2^40: cos² bounds of the smallest and the
//                                largest dihedral angle and of the smallest face angle
//   configs 17
//   config K N                   then N lines, the fan of configuration K:
//   tet x0 y0 z0 .. x3 y3 z3 WMIN WMAX WFACE
// The octree's fan rule is re-derived here on its own (not read from the
// certificate): a face piece between the centres cx, cy of two leaves, its
// ring the square's corners with the midpoints of its split sides in cyclic
// order, and the fan (cx, cy, ring[i], ring[i+1]), the last two swapped where
// the orientation is negative.  Configuration K < 16: two equal leaves,
// X = [0,4]³ above the piece [0,4]² × {0}, Y = [0,4]² × [-4,0], side k split
// iff bit k of K; K = 16: Y = [0,8]² × [-8,0] twice X's size.  The listed
// tetrahedra must be exactly those, in that order.  Each is verified exactly
// (integers): 6·volume > 0, per edge d <= 0 or d²·2^40 <= CMIN·N and d >= 0
// or d²·2^40 <= CMAX·N, per face angle s <= 0 or s²·2^40 <= CFACE·M; its
// witnesses must be its own exact extremes ("-" where it has no such angle:
// no obtuse dihedral angle), and the claim within 0.01° of the extreme
// witness.  Beyond the 17, every placement the octree makes — the piece
// normal to each axis, Y below or above X, and for K = 16 X's face in each
// quadrant of Y's — is derived and checked against the claim too, so the
// theorem does not rest on the symmetry argument.
using G3 = std::array<std::int64_t, 3>;
using GTet = std::array<G3, 4>;
G3 gsub(const G3& a, const G3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
std::array<Z, 3> gcross(const G3& a, const G3& b) {
    return {zint(a[1]) * zint(b[2]) - zint(a[2]) * zint(b[1]), zint(a[2]) * zint(b[0]) - zint(a[0]) * zint(b[2]),
            zint(a[0]) * zint(b[1]) - zint(a[1]) * zint(b[0])};
}
Z gdot(const std::array<Z, 3>& a, const std::array<Z, 3>& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
std::array<Z, 3> gz(const G3& a) { return {zint(a[0]), zint(a[1]), zint(a[2])}; }
Z gvolume6(const GTet& t) { return gdot(gz(gsub(t[1], t[0])), gcross(gsub(t[2], t[0]), gsub(t[3], t[0]))); }
// The fan of the piece: face with lowest corner f0 normal to axis a, side d.
std::vector<GTet> graded_fan(const G3& cx, const G3& cy, const G3& f0, int a, std::int64_t d, unsigned split) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    const std::int64_t ub[5] = {0, 1, 1, 0, 0}, uc[5] = {0, 0, 1, 1, 0};
    std::vector<G3> ring;
    for (int k = 0; k < 4; ++k) {
        G3 q = f0;
        q[b] += d * ub[k], q[c] += d * uc[k];
        ring.push_back(q);
        if (split >> k & 1u) {
            G3 m = f0;
            m[b] += d * (ub[k] + ub[k + 1]) / 2, m[c] += d * (uc[k] + uc[k + 1]) / 2;
            ring.push_back(m);
        }
    }
    std::vector<GTet> fan;
    for (std::size_t i = 0; i < ring.size(); ++i) {
        GTet t{cx, cy, ring[i], ring[(i + 1) % ring.size()]};
        const int s = sgn(gvolume6(t));
        if (s == 0) fail("a fan tetrahedron is flat");
        if (s < 0) std::swap(t[2], t[3]);
        fan.push_back(t);
    }
    return fan;
}
// Configuration k in the frame of the certificate.
std::vector<GTet> graded_config(int k) {
    if (k < 16) return graded_fan({2, 2, 2}, {2, 2, -2}, {0, 0, 0}, 2, 4, static_cast<unsigned>(k));
    return graded_fan({2, 2, 2}, {4, 4, -4}, {0, 0, 0}, 2, 4, 0);
}
// The exact extremes of one tetrahedron: kind 0 the largest d²/N with d > 0,
// 1 the largest with d < 0, 2 the largest s²/M with s > 0 (found[kind]:
// whether it has one); and whether it meets the claim.
struct GradedAngles {
    std::array<Cos2, 3> w;
    std::array<bool, 3> found{false, false, false};
    bool within = true;
};
GradedAngles graded_angles(const GTet& t, const Claim& cl) {
    GradedAngles g;
    const auto keep = [&](int kind, const Z& x, const Z& n) {
        const Cos2 c{x * x, n, kind != 1};
        if (!g.found[kind] || cmp(c.p * g.w[kind].q, g.w[kind].p * c.q) > 0) g.w[kind] = c, g.found[kind] = true;
    };
    for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) {
            int c = 0;
            while (c == i || c == j) ++c;
            const int d = 6 - i - j - c;
            const G3 e = gsub(t[j], t[i]);
            const std::array<Z, 3> nc = gcross(e, gsub(t[c], t[i])), nd = gcross(e, gsub(t[d], t[i]));
            const Z x = gdot(nc, nd), n = gdot(nc, nc) * gdot(nd, nd);
            if (sgn(x) == 0) continue;
            const int kind = sgn(x) > 0 ? 0 : 1;
            g.within = g.within && cmp(pow2(40) * x * x, (kind == 0 ? cl.cmin : cl.cmax) * n) <= 0;
            keep(kind, x, n);
        }
    for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
            for (int c = b + 1; c < 4; ++c) {
                if (b == a || c == a) continue;
                const std::array<Z, 3> u = gz(gsub(t[b], t[a])), v = gz(gsub(t[c], t[a]));
                const Z s = gdot(u, v), m = gdot(u, u) * gdot(v, v);
                if (sgn(s) <= 0) continue;
                g.within = g.within && cmp(pow2(40) * s * s, cl.cface * m) <= 0;
                keep(2, s, m);
            }
    return g;
}
// One tet line against the derived tetrahedron; returns its angles.
GradedAngles graded_tet_line(const std::string& line, const GTet& t, const Claim& cl, int k) {
    std::istringstream in(line);
    std::string word;
    if (!(in >> word) || word != "tet") fail("configuration " + std::to_string(k) + ": bad tet line '" + line.substr(0, 60) + "'");
    for (const G3& v : t)
        for (const std::int64_t x : v) {
            std::string s;
            if (!(in >> s) || parse_int(s) != x) fail("configuration " + std::to_string(k) + ": a tetrahedron is not the fan's");
        }
    if (sgn(gvolume6(t)) <= 0) fail("configuration " + std::to_string(k) + ": a tetrahedron is not positively oriented");
    const GradedAngles g = graded_angles(t, cl);
    if (!g.within) fail("configuration " + std::to_string(k) + ": a tetrahedron is outside the claim");
    for (int kind = 0; kind < 3; ++kind) {
        std::string s;
        if (!(in >> s)) fail("configuration " + std::to_string(k) + ": a tet line without its witnesses");
        if (s == "-" ? g.found[kind] : !g.found[kind]) fail("configuration " + std::to_string(k) + ": a witness is not the tetrahedron's");
        if (s == "-") continue;
        const auto [p, q] = parse_q(s);
        if (cmp(zint(p) * g.w[kind].q, g.w[kind].p * zint(q)) != 0)
            fail("configuration " + std::to_string(k) + ": a witness is not the tetrahedron's extreme");
    }
    if (in >> word) fail("configuration " + std::to_string(k) + ": trailing fields on a tet line");
    return g;
}
// Every placement of every configuration (above) within the claim; the count.
long graded_placements(const Claim& cl) {
    long n = 0;
    for (int a = 0; a < 3; ++a)
        for (int side = 0; side < 2; ++side) {
            G3 cx{2, 2, 2}, f0{0, 0, 0};
            if (side) f0[a] = 4;
            const std::int64_t s = side ? 1 : -1;
            std::vector<std::vector<GTet>> fans;
            for (unsigned split = 0; split < 16; ++split) {
                G3 cy = cx;
                cy[a] += 4 * s;
                fans.push_back(graded_fan(cx, cy, f0, a, 4, split));
            }
            for (int qb = 0; qb < 2; ++qb)
                for (int qc = 0; qc < 2; ++qc) {
                    G3 cy{};  // Y: side 8, X's face its quadrant (qb, qc)
                    cy[a] = side ? 8 : -4;
                    cy[(a + 1) % 3] = 4 - 4 * qb;
                    cy[(a + 2) % 3] = 4 - 4 * qc;
                    fans.push_back(graded_fan(cx, cy, f0, a, 4, 0));
                }
            for (const auto& fan : fans)
                for (const GTet& t : fan) {
                    if (sgn(gvolume6(t)) <= 0 || !graded_angles(t, cl).within) fail("a placement of a configuration is outside the claim");
                    ++n;
                }
        }
    return n;
}
int check_graded(const std::vector<std::string>& body) {
    if (body.size() < 3) fail("a graded certificate has a claim, a configs line and configurations");
    std::istringstream c(body[1]), n(body[2]);
    std::string word;
    std::array<std::string, 3> text;
    long configs = -1;
    if (!(c >> word >> text[0] >> text[1] >> text[2]) || word != "claim" || (c >> word)) fail("bad claim line");
    if (!(n >> word >> configs) || word != "configs" || (n >> word)) fail("bad configs line");
    if (configs != 17) fail("the certificate does not list the 17 configurations");
    const Claim cl{claim_threshold(text[0]), claim_threshold(text[1]), claim_threshold(text[2])};
    std::size_t at = 3;
    std::array<Cos2, 3> worst;
    std::array<bool, 3> found{false, false, false};
    long tets = 0;
    for (int k = 0; k < 17; ++k) {
        const std::vector<GTet> fan = graded_config(k);
        std::istringstream h(at < body.size() ? body[at] : std::string());
        long kk = -1, count = -1;
        if (!(h >> word >> kk >> count) || word != "config" || kk != k || (h >> word)) fail("configuration " + std::to_string(k) + ": bad config line");
        if (count != static_cast<long>(fan.size())) fail("configuration " + std::to_string(k) + ": not the fan's tetrahedron count");
        ++at;
        for (const GTet& t : fan) {
            if (at >= body.size()) fail("the certificate ends inside configuration " + std::to_string(k));
            const GradedAngles g = graded_tet_line(body[at++], t, cl, k);
            for (int kind = 0; kind < 3; ++kind)
                if (g.found[kind] && (!found[kind] || cmp(g.w[kind].p * worst[kind].q, worst[kind].p * g.w[kind].q) > 0))
                    worst[kind] = g.w[kind], found[kind] = true;
            ++tets;
        }
    }
    if (at != body.size()) fail("lines after the configurations");
    for (int kind = 0; kind < 3; ++kind)
        if (!found[kind] || !tight(claim_of(cl, kind), worst[kind], 1800000000, kind == 1))
            fail("the claim is not within 0.01 deg of its witness (kind " + std::to_string(kind) + ")");
    const long placements = graded_placements(cl);
    // Degrees for the message only, the claim's rounded outward to 4 decimals.
    const auto down = [](double x) { return std::floor(x * 1e4) / 1e4; };
    const auto up = [](double x) { return std::ceil(x * 1e4) / 1e4; };
    std::cout << std::fixed << std::setprecision(4) << "BCC graded templates: the " << tets
              << " tetrahedra of the 17 fan configurations (re-derived, " << placements
              << " placements checked) are positively oriented with every dihedral angle in ["
              << down(degrees(Cos2{cl.cmin, pow2(40), true})) << ", " << up(degrees(Cos2{cl.cmax, pow2(40), false}))
              << "] deg and every face angle >= " << down(degrees(Cos2{cl.cface, pow2(40), true}))
              << " deg (rounded outward); witnesses " << degrees(worst[0]) << ", " << degrees(worst[1]) << ", "
              << degrees(worst[2]) << " deg\n";
    return 0;
}

// The alphas of a bound certificate ("alphas L S"): exact rationals with one
// denominator below 2^31 (returned in den), both in (0, 1/2).
std::pair<std::int64_t, std::int64_t> bound_alphas(const std::string& al, const std::string& as, std::int64_t& den) {
    const auto [ln, ld] = parse_q(al);
    const auto [sn, sd] = parse_q(as);
    if (ld != sd || ld >= (std::int64_t{1} << 31)) fail("alphas need one denominator below 2^31");
    if (!(ln > 0 && 2 * ln < ld && sn > 0 && 2 * sn < sd)) fail("alphas out of (0, 1/2)");
    den = ld;
    return {ln, sn};
}

// ---- the junction certificate (proofs/bcc_junctions.cert) ---------------------------
// Format (proofs/README.md, "Junction keys (3D, bcc_junctions.cert)"):
//   warpmesh-bcc-junctions 1
//   alphas L S                 as in a bound certificate (one denominator, in (0, 1/2))
//   claim CMIN CMAX CFACE      the keys' extremes
//   keys N                     every canonical junction key
//   then per key, in any order: `key CODE CMIN CMAX CFACE` and its four face
//   lines `face F m lo_0 hi_0 .. WMIN_0 .. WMAX_0 .. WFACE_0 .. SPLITS`, F = 0..3.
// A junction background tetrahedron has three or four materials among its
// unwarped vertices (letters by first appearance, -1 the warped vertex);
// its output is the cone stencil: every face subdivided by a rule of the
// face alone, each triangle joined to the centre.  Its points, times 12 so
// that they are integers times 2^K: vertices and cut points as one region's
// (times 12), face point f 4 (sum of the face's three cut points), the
// centre 3 (sum of the four vertices).  A face's tetrahedra use the face's
// points and the centre only, so they depend only on the face's cut
// fractions and on the warp (the centre moves with the warped vertex): each
// face is verified on its own box (its parameters: the warp t, then the
// cut edges of the face by local edge index), every leaf against its key's
// claim.  The key's claim is the extremes of nothing but itself: each face's
// witnesses must agree with it, and its tightness is measured against the
// most extreme of its faces' witnesses.
struct JKey {
    std::array<int, 4> letter{}, warp{STAY, STAY, STAY, STAY};
    int parity = 0;
    std::array<int, 9> enc() const { return {letter[0], warp[0], letter[1], warp[1], letter[2], warp[2], letter[3], warp[3], parity}; }
};
// Letters renamed by first appearance in local order (-1 kept).
std::array<int, 4> relettered(const std::array<int, 4>& l) {
    std::map<int, int> name;
    std::array<int, 4> out{};
    for (int i = 0; i < 4; ++i) out[i] = l[i] < 0 ? -1 : name.emplace(l[i], static_cast<int>(name.size())).first->second;
    return out;
}
int letter_count(const JKey& k) {
    std::set<int> s;
    for (int l : k.letter)
        if (l >= 0) s.insert(l);
    return static_cast<int>(s.size());
}
// The three vertices of the face without vertex f, ascending.
std::array<int, 3> face_of(int f) {
    std::array<int, 3> v{};
    for (int i = 0, n = 0; i < 4; ++i)
        if (i != f) v[n++] = i;
    return v;
}
bool cut_edge(const JKey& k, int a, int b) { return k.letter[a] >= 0 && k.letter[b] >= 0 && k.letter[a] != k.letter[b]; }
// Whether the stencil splits a quad by the parity rule: a face of three
// unwarped vertices and two letters whose equal pair is a long edge.
bool jparity_matters(const JKey& k) {
    for (int f = 0; f < 4; ++f) {
        const auto [a, b, c] = face_of(f);
        if (k.letter[a] < 0 || k.letter[b] < 0 || k.letter[c] < 0) continue;
        const int cuts = cut_edge(k, a, b) + cut_edge(k, b, c) + cut_edge(k, a, c);
        if (cuts == 2 && ((!cut_edge(k, a, b) && edge_of(a, b) < 2) || (!cut_edge(k, b, c) && edge_of(b, c) < 2) ||
                          (!cut_edge(k, a, c) && edge_of(a, c) < 2)))
            return true;
    }
    return false;
}
bool jconsistent(const JKey& k) {
    for (int i = 0; i < 4; ++i) {
        if (k.letter[i] < -1 || k.letter[i] > 3) return false;
        if ((k.letter[i] < 0) != (k.warp[i] != STAY) || k.warp[i] < 0 || k.warp[i] > STAY) return false;
    }
    if (relettered(k.letter) != k.letter || letter_count(k) < 3) return false;
    return k.parity == 0 || (k.parity == 1 && jparity_matters(k));
}
// Points: 0..3 the vertices, 4 + e the cut points, 10 + f the face points, 14 the centre.
const int CENTRE = 14;
// Face f's cone tetrahedra (point indices; orientation fixed by jorient).
std::vector<Tet> jface_tets(const JKey& k, int f) {
    const auto [a, b, c] = face_of(f);
    const auto L = [&](int v) { return k.letter[v]; };
    const int cuts = cut_edge(k, a, b) + cut_edge(k, b, c) + cut_edge(k, a, c);
    std::vector<Tet> out;
    if (cuts == 0) return {{a, b, c, CENTRE}};  // one letter, a vertex warped
    if (cuts == 3) {                           // three letters: around the face point
        for (int x : {a, b, c})
            for (int y : {a, b, c})
                if (x != y) out.push_back({x, cut(x, y), 10 + f, CENTRE});
        return out;
    }
    if (L(a) < 0 || L(b) < 0 || L(c) < 0) {  // two letters x, y and the warped z: the cut edge's halves
        const int z = L(a) < 0 ? a : L(b) < 0 ? b : c, x = z == a ? b : a, y = a + b + c - x - z;
        return {{x, cut(x, y), z, CENTRE}, {cut(x, y), y, z, CENTRE}};
    }
    // Two letters, none warped: the odd vertex y's triangle, and the quad of
    // the equal pair x1 < x2, split as the parity rule says.
    const int y = !cut_edge(k, a, b) ? c : !cut_edge(k, b, c) ? a : b;
    const int x1 = y == a ? b : a, x2 = y == c ? b : c;
    const int c1 = cut(x1, y), c2 = cut(x2, y);
    out.push_back({y, c1, c2, CENTRE});
    if (diag_a(x1, x2, y, k.parity)) out.push_back({x1, x2, c2, CENTRE}), out.push_back({x1, c2, c1, CENTRE});
    else out.push_back({x1, x2, c1, CENTRE}), out.push_back({x2, c2, c1, CENTRE});
    return out;
}
// Reference positions times 12: vertices 12 REF, cut points 6 (sum of the
// ends), face points 4 (sum of the face's vertices), the centre 3 (sum of all).
std::array<long, 3> jref(int q) {
    std::array<long, 3> p{};
    for (int c = 0; c < 3; ++c) {
        if (q < 4) p[c] = 12L * REF[q][c];
        else if (q < 10) p[c] = 6L * (REF[EDGE[q - 4][0]][c] + REF[EDGE[q - 4][1]][c]);
        else
            for (int i = 0; i < 4; ++i) p[c] += (q == CENTRE ? 3L : i == q - 10 ? 0L : 4L) * REF[i][c];
    }
    return p;
}
// The tetrahedra positively oriented in the reference configuration.
std::vector<Tet> jorient(std::vector<Tet> ts) {
    for (Tet& t : ts) {
        std::array<long, 3> d[3];
        const auto p0 = jref(t[0]);
        for (int v = 1; v < 4; ++v) {
            const auto pv = jref(t[v]);
            for (int c = 0; c < 3; ++c) d[v - 1][c] = pv[c] - p0[c];
        }
        const long vol = d[0][0] * (d[1][1] * d[2][2] - d[1][2] * d[2][1]) - d[0][1] * (d[1][0] * d[2][2] - d[1][2] * d[2][0]) +
                         d[0][2] * (d[1][0] * d[2][1] - d[1][1] * d[2][0]);
        if (vol == 0) fail("flat junction stencil tetrahedron");
        if (vol < 0) std::swap(t[2], t[3]);
    }
    return ts;
}
std::vector<Tet> jstencil(const JKey& k) {
    std::vector<Tet> all;
    for (int f = 0; f < 4; ++f)
        for (const Tet& t : jface_tets(k, f)) all.push_back(t);
    return jorient(all);
}
// The image of a point index under the vertex permutation p.
int jmap(int q, const std::array<int, 4>& p) {
    if (q < 4) return p[q];
    if (q < 10) return cut(p[EDGE[q - 4][0]], p[EDGE[q - 4][1]]);
    return q == CENTRE ? CENTRE : 10 + p[q - 10];
}
std::set<std::array<int, 4>> jmapped(const std::vector<Tet>& ts, const std::array<int, 4>& p) {
    std::set<std::array<int, 4>> s;
    for (const Tet& t : ts) {
        std::array<int, 4> q{jmap(t[0], p), jmap(t[1], p), jmap(t[2], p), jmap(t[3], p)};
        std::sort(q.begin(), q.end());
        s.insert(q);
    }
    return s;
}
// The image of k under s: letters and warps moved, re-lettered by first
// appearance, the parity bit the one whose stencil is the image of k's.
JKey jimage(const JKey& k, const Sym& s) {
    JKey m;
    std::array<int, 4> letter{};
    for (int i = 0; i < 4; ++i) letter[s.p[i]] = k.letter[i], m.warp[s.p[i]] = map_dir(k.warp[i], s);
    m.letter = relettered(letter);
    const auto want = jmapped(jstencil(k), s.p);
    for (m.parity = 0; m.parity < (jparity_matters(m) ? 2 : 1); ++m.parity)
        if (jmapped(jstencil(m), {0, 1, 2, 3}) == want) return m;
    fail("junction stencil does not commute with a symmetry");
}
// Every canonical consistent junction key (the smallest image of each).
std::set<std::array<int, 9>> junction_keys(const std::vector<Sym>& syms) {
    std::set<std::array<int, 9>> out;
    std::array<int, 4> st{};
    for (st[0] = 0; st[0] < 18; ++st[0])
        for (st[1] = 0; st[1] < 18; ++st[1])
            for (st[2] = 0; st[2] < 18; ++st[2])
                for (st[3] = 0; st[3] < 18; ++st[3])
                    for (int par = 0; par < 2; ++par) {
                        JKey k;
                        for (int i = 0; i < 4; ++i) k.letter[i] = st[i] < 4 ? st[i] : -1, k.warp[i] = st[i] < 4 ? STAY : st[i] - 4;
                        k.parity = par;
                        if (!jconsistent(k)) continue;
                        std::array<int, 9> best = jimage(k, syms[0]).enc();
                        for (const Sym& s : syms) best = std::min(best, jimage(k, s).enc());
                        out.insert(best);
                    }
    return out;
}
// "a,b,0h,c/0": per vertex a letter a..d, or 0 and a warp direction a..n; the parity bit.
JKey parse_jcode(const std::string& s) {
    JKey k;
    std::size_t at = 0;
    const auto bad = [&] { fail("bad junction key code " + s.substr(0, 40)); };
    for (int i = 0; i < 4; ++i) {
        if (at >= s.size()) bad();
        const char c = s[at++];
        if (c >= 'a' && c <= 'd') k.letter[i] = c - 'a';
        else if (c == '0' && at < s.size() && s[at] >= 'a' && s[at] <= 'n') k.letter[i] = -1, k.warp[i] = s[at++] - 'a';
        else bad();
        if (at >= s.size() || s[at++] != (i < 3 ? ',' : '/')) bad();
    }
    if (at + 1 != s.size() || (s[at] != '0' && s[at] != '1')) bad();
    k.parity = s[at] - '0';
    return k;
}
// Face f's parameters: t of the warped vertex (the centre moves with it),
// then u of each cut edge of the face (both ends unwarped, letters differ)
// by local edge index.
std::vector<Param> jface_params(const JKey& k, int f, std::int64_t along, std::int64_t ashort, std::int64_t den) {
    std::vector<Param> ps;
    for (int i = 0; i < 4; ++i)
        if (k.warp[i] != STAY) ps.push_back({i, 0, k.warp[i] < 6 ? along : ashort, den});
    for (int e = 0; e < 6; ++e)
        if (EDGE[e][0] != f && EDGE[e][1] != f && cut_edge(k, EDGE[e][0], EDGE[e][1])) {
            const std::int64_t a = e < 2 ? along : ashort;
            ps.push_back({4 + e, a, den - a, den});
        }
    return ps;
}
// The parameters point q depends on (bit i: t of vertex i; bit 4 + e: u of edge e).
unsigned depends(const JKey& k, int q) {
    unsigned d = 0;
    if (q < 4) return k.warp[q] != STAY ? 1u << q : 0u;
    if (q < 10) return 1u << q;
    for (int i = 0; i < 4; ++i) {
        if (q == CENTRE && k.warp[i] != STAY) d |= 1u << i;
        for (int j = i + 1; j < 4; ++j)
            if (q != CENTRE && i != q - 10 && j != q - 10) d |= 1u << (4 + edge_of(i, j));
    }
    return d;
}
template <class T>
T times(int c, const T& x) {  // c · x, c a small integer
    if constexpr (std::is_same_v<T, I>) return point(zint(c)) * x;
    else {
        T r{};
        r.v = point(zint(c));
        return r * x;
    }
}
// The 15 points times 12, times 2^K (see above), from one region's ten.
template <class T>
std::array<P3<T>, 15> jpoints(const Model& m, const Box& b, int K) {
    const auto g = points<T>(m.k, m.ps, b, K);
    std::array<P3<T>, 15> p{};
    for (int c = 0; c < 3; ++c) {
        for (int q = 0; q < 10; ++q) p[q][c] = times(12, g[q][c]);
        for (int f = 0; f < 4; ++f) {
            const auto [a, bb, cc] = face_of(f);
            p[10 + f][c] = times(4, g[cut(a, bb)][c] + g[cut(bb, cc)][c] + g[cut(cc, a)][c]);
        }
        p[CENTRE][c] = times(3, g[0][c] + g[1][c] + g[2][c] + g[3][c]);
    }
    return p;
}
struct JFace {
    Model m;
    std::vector<Tet> tets;
    Box root;
    std::array<std::vector<Dy>, 3> w;
    std::string splits;
};
struct JEntry {
    Entry key;  // its code, key and claim (the rest unused)
    std::array<JFace, 4> face;
};
// One face line, "face F m lo_0 hi_0 .. WMIN_0 .. WMAX_0 .. WFACE_0 .. SPLITS",
// of key k (F must be `f`): its tetrahedra, parameters (their count must be
// m), root box, witnesses and split string.
JFace parse_face_line(const std::string& line, const JKey& k, const std::string& code, int f, std::int64_t along, std::int64_t ashort,
                      std::int64_t den) {
    std::istringstream in(line);
    std::string word;
    int F = -1, m = -1;
    const std::string name = code + " face " + std::to_string(f);
    if (!(in >> word >> F >> m) || word != "face" || F != f) fail("expected face line " + std::to_string(f) + " of " + code);
    JFace face;
    face.m = Model{Key{}, jface_params(k, f, along, ashort, den), true, std::nullopt};
    for (int i = 0; i < 4; ++i) face.m.k.warp[i] = k.warp[i];
    if (m != static_cast<int>(face.m.ps.size())) fail("wrong parameter count for " + name);
    face.tets = jorient(jface_tets(k, f));
    unsigned have = 0;  // the parameters of the face; every point of its tetrahedra depends on these only
    for (const Param& p : face.m.ps) have |= 1u << p.index;
    for (const Tet& t : face.tets)
        for (int q : t)
            if ((depends(k, q) & ~have) != 0) fail("a point of " + name + " depends on a parameter outside the face");
    face.root = parse_root(in, face.m.ps, name);
    face.w = parse_witnesses(in, face.m.ps, name);
    face.splits = parse_splits(in, m, name);
    return face;
}
// "key CODE CMIN CMAX CFACE" and its four face lines from body[at].
JEntry parse_junction(const std::vector<std::string>& body, std::size_t at, std::int64_t along, std::int64_t ashort, std::int64_t den,
                      const std::set<std::array<int, 9>>& expected, std::set<std::array<int, 9>>& seen) {
    std::istringstream ks(body[at]);
    std::string word, code, lo, hi, fa;
    if (!(ks >> word >> code >> lo >> hi >> fa) || word != "key" || (ks >> word)) fail("bad junction key line");
    const JKey k = parse_jcode(code);
    if (!expected.count(k.enc()) || !seen.insert(k.enc()).second) fail("unexpected or repeated junction key " + code);
    JEntry en;
    en.key.code = code;
    en.key.claim = Claim{claim_threshold(lo), claim_threshold(hi), claim_threshold(fa)};
    for (int f = 0; f < 4; ++f) en.face[f] = parse_face_line(body[at + 1 + f], k, code, f, along, ashort, den);
    return en;
}
// Every face witness agrees with its key's claim (as check_witnesses); the
// key's witness of each kind is its faces' most extreme, tight or not
// against the key's claim.
Witnessed junction_witnesses(const JEntry& en) {
    Witnessed w{};
    for (int j = 0; j < 3; ++j) {
        const Z& c = claim_of(en.key.claim, j);
        for (int f = 0; f < 4; ++f) {
            const Cos2 x = witness_cos2(en.face[f].m, en.face[f].tets, en.face[f].w[j], j, false);
            if ((j != 1 || !x.acute) && cmp(x.p * pow2(40), c * x.q) > 0)
                fail("a witness of " + en.key.code + " face " + std::to_string(f) + " contradicts its key's claim");
            if (f == 0 || (j != 1 ? larger(w.c[j], x) : larger(x, w.c[j]))) w.c[j] = x;
        }
        w.tight[j] = tight(c, w.c[j], tol_den(j), j == 1);
    }
    return w;
}
int check_junctions(const std::vector<std::string>& body, bool progress) {
    if (body.size() < 4) fail("a junction certificate has alphas, claim and keys lines");
    std::istringstream a(body[1]), c(body[2]), n(body[3]);
    std::string word, al, as;
    std::array<std::string, 3> text;
    long nkeys = -1;
    if (!(a >> word >> al >> as) || word != "alphas" || (a >> word)) fail("bad alphas line");
    if (!(c >> word >> text[0] >> text[1] >> text[2]) || word != "claim" || (c >> word)) fail("bad claim line");
    if (!(n >> word >> nkeys) || word != "keys" || nkeys < 0 || nkeys > 100000 || (n >> word)) fail("bad keys line");
    std::int64_t den = 0;
    const auto [ln, sn] = bound_alphas(al, as, den);
    const Claim claim{claim_threshold(text[0]), claim_threshold(text[1]), claim_threshold(text[2])};
    if (static_cast<long>(body.size()) != 4 + 5 * nkeys) fail("junction key count mismatch (a key line and four face lines per key)");
    const auto expected = junction_keys(symmetries());
    if (static_cast<long>(expected.size()) != nkeys) fail("the certificate does not list every junction key");
    std::vector<JEntry> keys;
    std::vector<Entry> entries;
    std::vector<Witnessed> wit;
    std::set<std::array<int, 9>> seen;
    for (long i = 0; i < nkeys; ++i) {
        keys.push_back(parse_junction(body, 4 + 5 * static_cast<std::size_t>(i), ln, sn, den, expected, seen));
        entries.push_back(keys.back().key);
        wit.push_back(junction_witnesses(keys.back()));
    }
    std::size_t ext[3] = {0, 0, 0};
    theorem_extremes(claim, entries, wit, ext);
    long leaves = 0;
    const bool terminal = ::isatty(STDERR_FILENO) == 1;
    for (std::size_t i = 0; i < keys.size(); ++i) {  // a progress line per key, rewritten in place on a terminal
        for (const JFace& f : keys[i].face) leaves += replay(f.m, f.tets, f.root, f.splits, entries[i].claim, false);
        if (progress)
            std::cerr << (terminal ? "\r" : "") << "checked " << i + 1 << " of " << keys.size() << " junction keys, " << leaves << " leaves"
                      << (terminal ? "\033[K" : "\n") << std::flush;
    }
    if (progress && terminal) std::cerr << "\r\033[K";
    print_theorem(al + ", " + as + ", junction keys", text, claim, entries, wit, ext, leaves);
    return 0;
}

// ---- the A15 certificate (a15.cert) ------------------------------------------------
// Format (proofs/README.md, "The A15 certificate"):
//   warpmesh-a15-certificate 1
//   alphas CHAIN WIDE A B   exact rationals, one denominator below 2^31, each in (0, 1/2):
//                           the thresholds of chain and wide B–B edges, and of mixed
//                           A–B edges at their A end and at their B end
//   claim CMIN CMAX CFACE   exactly the keys' extremes, tight
//   keys N                  every canonical A15 key with output, in any order
//   key CODE m lo_0 hi_0 .. CMIN CMAX CFACE WMIN_0 .. WMAX_0 .. WFACE_0 .. SPLITS
// as a BCC key line, with an A15 code ("1:+,-,0c,-": the class, then per
// vertex of the class's reference its sign and, for a zero vertex, its warp
// letter a.. (an index into its site's lattice edges, by |d|² then
// lexicographically) or s), and witness coordinates p/q with q a power of 2
// up to 2^24 or the alphas' denominator (an exact end of the box).
// Everything else is re-derived here from the definition of proofs/README.md
// ("The A15 space"): the sites, the lattice edges, the Delaunay
// tetrahedra of a cell (every 4-clique of lattice edges whose circumsphere
// holds no other lattice point, exactly; their volumes must fill the cell,
// so none is missing), each tetrahedron the image of its class's reference
// under a lattice symmetry (so a configuration of any background
// tetrahedron is one of its reference's, with the same angles), the
// reference's own symmetries, the consistent keys and their canonical forms,
// the parameter boxes, the stencils (BCC's, oriented at the A15 reference)
// and the Delaunay rule with A15's ties (delaunay_tets).
using V3 = std::array<int, 3>;
// The sites of a cubic cell, quadrupled coordinates: A (Si) then B (Cr).
const V3 A15_SITE[8] = {{0, 0, 0}, {2, 2, 2}, {1, 0, 2}, {3, 0, 2}, {2, 1, 0}, {2, 3, 0}, {0, 2, 1}, {0, 2, 3}};
// The references (the codes' local vertex orders): class 0 (B, B', A, B'')
// with BB' a chain edge, class 1 (A, B, B', B''), class 2 (B0, B1, B2, B3)
// with B0B1 and B2B3 chain edges.
const V3 A15_REF[3][4] = {{{-1, 0, 2}, {1, 0, 2}, {0, 0, 0}, {0, 2, 1}},
                          {{0, 0, 0}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}},
                          {{-1, 0, 2}, {1, 0, 2}, {0, 2, 1}, {0, 2, 3}}};
int a15_site(const V3& q) {
    V3 r{};
    for (int c = 0; c < 3; ++c) r[c] = ((q[c] % 4) + 4) % 4;
    for (int s = 0; s < 8; ++s)
        if (A15_SITE[s] == r) return s;
    return -1;
}
V3 add3(const V3& a, const V3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V3 diff3(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
int norm2(const V3& d) { return d[0] * d[0] + d[1] * d[1] + d[2] * d[2]; }
long long det3(const V3& a, const V3& b, const V3& c) {
    return static_cast<long long>(a[0]) * (b[1] * c[2] - b[2] * c[1]) - static_cast<long long>(a[1]) * (b[0] * c[2] - b[2] * c[0]) +
           static_cast<long long>(a[2]) * (b[0] * c[1] - b[1] * c[0]);
}
long long vol6(const std::array<V3, 4>& t) { return det3(diff3(t[1], t[0]), diff3(t[2], t[0]), diff3(t[3], t[0])); }
// x ↦ L x, L a signed permutation matrix.
struct Lin {
    int L[3][3];
    V3 operator()(const V3& x) const {
        V3 y{};
        for (int r = 0; r < 3; ++r) y[r] = L[r][0] * x[0] + L[r][1] * x[1] + L[r][2] * x[2];
        return y;
    }
};
std::vector<Lin> signed_permutations() {
    std::vector<Lin> out;
    std::array<int, 3> ax{0, 1, 2};
    do
        for (int sg = 0; sg < 8; ++sg) {
            Lin m{};
            for (int r = 0; r < 3; ++r) m.L[r][ax[r]] = (sg >> r) & 1 ? -1 : 1;
            out.push_back(m);
        }
    while (std::next_permutation(ax.begin(), ax.end()));
    return out;
}
// Whether x ↦ L x + t maps the lattice onto itself (the 8 sites onto 8
// distinct sites modulo the cell).
bool lattice_map(const Lin& L, const V3& t) {
    std::set<int> img;
    for (const V3& s : A15_SITE) {
        const int i = a15_site(add3(L(s), t));
        if (i < 0) return false;
        img.insert(i);
    }
    return img.size() == 8;
}
// A lattice symmetry mapping tetrahedron `from` onto `to` vertex for vertex
// through the permutation p (from[i] ↦ to[p[i]]): its linear part, if any.
std::optional<Lin> maps_onto(const std::array<V3, 4>& from, const std::array<V3, 4>& to, const std::array<int, 4>& p,
                             const std::vector<Lin>& lins) {
    for (const Lin& L : lins) {
        const V3 t = diff3(to[p[0]], L(from[0]));
        bool ok = true;
        for (int i = 1; i < 4 && ok; ++i) ok = add3(L(from[i]), t) == to[p[i]];
        if (ok && lattice_map(L, t)) return L;
    }
    return std::nullopt;
}
// Where q lies against the circumsphere of t (6·volume != 0): +1 strictly
// inside, 0 on it, -1 outside.  The lifted determinant, coordinates times 4
// so that the centroid (an interior point) is integral: q is inside iff its
// determinant has the centroid's sign.
int sphere_side(const std::array<V3, 4>& t, const V3& q) {
    const auto lifted = [&](const V3& x4) {
        __int128 m[4][4];
        for (int i = 0; i < 4; ++i) {
            const V3 d = diff3({4 * t[i][0], 4 * t[i][1], 4 * t[i][2]}, x4);
            for (int c = 0; c < 3; ++c) m[i][c] = d[c];
            m[i][3] = static_cast<__int128>(d[0]) * d[0] + static_cast<__int128>(d[1]) * d[1] + static_cast<__int128>(d[2]) * d[2];
        }
        const auto minor3 = [&](const int* r) {  // the rows r, columns 0..2
            return m[r[0]][0] * (m[r[1]][1] * m[r[2]][2] - m[r[1]][2] * m[r[2]][1]) -
                   m[r[0]][1] * (m[r[1]][0] * m[r[2]][2] - m[r[1]][2] * m[r[2]][0]) +
                   m[r[0]][2] * (m[r[1]][0] * m[r[2]][1] - m[r[1]][1] * m[r[2]][0]);
        };
        __int128 det = 0;  // expansion along the last column
        for (int i = 0; i < 4; ++i) {
            int r[3], n = 0;
            for (int j = 0; j < 4; ++j)
                if (j != i) r[n++] = j;
            det += (i % 2 == 0 ? -1 : 1) * m[i][3] * minor3(r);
        }
        return det;
    };
    const __int128 dc = lifted(add3(add3(t[0], t[1]), add3(t[2], t[3])));
    const __int128 dq = lifted({4 * q[0], 4 * q[1], 4 * q[2]});
    if (dc == 0) fail("internal: a centroid on its circumsphere");
    return dq == 0 ? 0 : (dq > 0) == (dc > 0) ? 1 : -1;
}
// The lattice as re-derived: each site's lattice edges (offsets, by |d|²
// then lexicographically: the warp letters' order), and each class's
// reference symmetries (vertex permutation and linear part).
struct A15 {
    std::array<std::vector<V3>, 8> nb;
    struct Sym15 {
        std::array<int, 4> p;
        Lin L;
    };
    std::array<std::vector<Sym15>, 3> sym;
    std::array<int, 3> per_class{};  // Delaunay tetrahedra per cell, by class
};
std::array<V3, 4> a15_ref(int c) { return {A15_REF[c][0], A15_REF[c][1], A15_REF[c][2], A15_REF[c][3]}; }
// Every lattice point with coordinates in [lo, hi).
std::vector<V3> lattice_points(int lo, int hi) {
    std::vector<V3> out;
    for (int x = lo; x < hi; ++x)
        for (int y = lo; y < hi; ++y)
            for (int z = lo; z < hi; ++z)
                if (a15_site({x, y, z}) >= 0) out.push_back({x, y, z});
    return out;
}
// The lattice edges: no two lattice points closer than |d|² = 4; an A site
// has 12 edges of |d|² <= 6, a B site 14.
void derive_edges(A15& g) {
    for (int s = 0; s < 8; ++s) {
        for (int x = -3; x <= 3; ++x)
            for (int y = -3; y <= 3; ++y)
                for (int z = -3; z <= 3; ++z) {
                    const V3 d{x, y, z};
                    if (norm2(d) == 0 || norm2(d) > 6 || a15_site(add3(A15_SITE[s], d)) < 0) continue;
                    if (norm2(d) < 4) fail("A15: two lattice points closer than an edge");
                    g.nb[s].push_back(d);
                }
        std::sort(g.nb[s].begin(), g.nb[s].end(), [](const V3& a, const V3& b) { return std::pair{norm2(a), a} < std::pair{norm2(b), b}; });
        if (static_cast<int>(g.nb[s].size()) != (s < 2 ? 12 : 14)) fail("A15: a site's edge count");
    }
}
bool adjacent(const V3& a, const V3& b) {
    const int n = norm2(diff3(a, b));
    return n >= 4 && n <= 6;
}
// The Delaunay tetrahedra with their centroid in cell 0 (coordinate sums in
// [0, 16)³): every 4-clique of lattice edges whose circumsphere has every
// other lattice point strictly outside.  Their 6·volumes must add up to the
// cell's, 6·4³: the Delaunay tetrahedra tile space, so none is missing (and,
// no point being on a sphere, the tiling is unique).  Each must be the image
// of one reference under a lattice symmetry, every reference positively
// oriented and Delaunay.
void derive_tetrahedra(A15& g, const std::vector<Lin>& lins) {
    const std::vector<V3> verts = lattice_points(-3, 7), probe = lattice_points(-6, 11);
    long long volume = 0;
    for (std::size_t a = 0; a < verts.size(); ++a)
        for (std::size_t b = a + 1; b < verts.size(); ++b)
            for (std::size_t c = b + 1; c < verts.size(); ++c)
                for (std::size_t d = c + 1; d < verts.size(); ++d) {
                    const std::array<V3, 4> t{verts[a], verts[b], verts[c], verts[d]};
                    bool clique = true;
                    for (int i = 0; i < 4 && clique; ++i)
                        for (int j = i + 1; j < 4 && clique; ++j) clique = adjacent(t[i], t[j]);
                    if (!clique) continue;
                    const V3 sum = add3(add3(t[0], t[1]), add3(t[2], t[3]));
                    if (!(sum[0] >= 0 && sum[0] < 16 && sum[1] >= 0 && sum[1] < 16 && sum[2] >= 0 && sum[2] < 16) || vol6(t) == 0) continue;
                    bool empty = true;
                    for (const V3& q : probe)
                        if (q != t[0] && q != t[1] && q != t[2] && q != t[3]) {
                            const int side = sphere_side(t, q);
                            if (side == 0) fail("A15: five lattice points on one sphere (the Delaunay tetrahedra are not unique)");
                            empty = empty && side < 0;
                        }
                    if (!empty) continue;
                    volume += std::llabs(vol6(t));
                    int cls = -1;
                    std::array<int, 4> p{0, 1, 2, 3};
                    for (int k = 0; k < 3 && cls < 0; ++k) {
                        std::sort(p.begin(), p.end());
                        do
                            if (maps_onto(a15_ref(k), t, p, lins)) cls = k;
                        while (cls < 0 && std::next_permutation(p.begin(), p.end()));
                    }
                    if (cls < 0) fail("A15: a Delaunay tetrahedron is the image of no reference");
                    ++g.per_class[cls];
                }
    if (volume != 6 * 64) fail("A15: the Delaunay tetrahedra found do not fill the cell");
    for (int k = 0; k < 3; ++k) {
        const std::array<V3, 4> r = a15_ref(k);
        if (vol6(r) <= 0) fail("A15: a reference is not positively oriented");
        for (const V3& q : probe)
            if (q != r[0] && q != r[1] && q != r[2] && q != r[3] && sphere_side(r, q) >= 0) fail("A15: a reference is not Delaunay");
    }
}
// Each reference's lattice symmetries: the permutations p and linear parts L
// with L r_i + t = r_{p[i]} for a lattice symmetry x ↦ L x + t.
void derive_symmetries(A15& g, const std::vector<Lin>& lins) {
    for (int k = 0; k < 3; ++k) {
        std::array<int, 4> p{0, 1, 2, 3};
        do
            for (const Lin& L : lins) {
                const V3 t = diff3(A15_REF[k][p[0]], L(A15_REF[k][0]));
                bool ok = true;
                for (int i = 1; i < 4 && ok; ++i) ok = add3(L(A15_REF[k][i]), t) == A15_REF[k][p[i]];
                if (ok && lattice_map(L, t)) g.sym[k].push_back({p, L});
            }
        while (std::next_permutation(p.begin(), p.end()));
    }
}
A15 derive_a15() {
    A15 g;
    const std::vector<Lin> lins = signed_permutations();
    derive_edges(g);
    derive_tetrahedra(g, lins);
    derive_symmetries(g, lins);
    return g;
}

// ---- A15 keys ---------------------------------------------------------------------------
int site_of_vertex(int cls, int i) { return a15_site(A15_REF[cls][i]); }
int a15_dir(const A15& g, int site, const V3& d) {
    for (std::size_t i = 0; i < g.nb[site].size(); ++i)
        if (g.nb[site][i] == d) return static_cast<int>(i);
    return -1;
}
// The local vertex vertex i of class cls reaches along its warp w, or -1.
int a15_reached(const A15& g, int cls, int i, int w) {
    if (w == STAY) return -1;
    const V3 q = add3(A15_REF[cls][i], g.nb[site_of_vertex(cls, i)][w]);
    for (int j = 0; j < 4; ++j)
        if (A15_REF[cls][j] == q) return j;
    return -1;
}
// The consistency rules of proofs/README.md ("The A15 space"): only zero
// vertices warp; no two warp towards each other; a vertex warped along an
// edge of the tetrahedron found its other end unwarped, so that end, if
// zero, warped later (not `s`).
bool a15_consistent(const A15& g, int cls, const Key& k) {
    for (int i = 0; i < 4; ++i) {
        const int w = k.warp[i];
        if (w == STAY) continue;
        if (k.sign[i] != 0 || w >= static_cast<int>(g.nb[site_of_vertex(cls, i)].size())) return false;
        const int j = a15_reached(g, cls, i, w);
        if (j >= 0 && (a15_reached(g, cls, j, k.warp[j]) == i || (k.sign[j] == 0 && k.warp[j] == STAY))) return false;
    }
    return true;
}
using Enc15 = std::array<int, 9>;  // class, then sign and warp of each vertex
Enc15 enc15(int cls, const Key& k) { return {cls, k.sign[0], k.warp[0], k.sign[1], k.warp[1], k.sign[2], k.warp[2], k.sign[3], k.warp[3]}; }
Key a15_image(const A15& g, int cls, const Key& k, const A15::Sym15& s) {
    Key m;
    for (int i = 0; i < 4; ++i) {
        const int to = s.p[i];
        m.sign[to] = k.sign[i];
        m.warp[to] = k.warp[i] == STAY ? STAY : a15_dir(g, site_of_vertex(cls, to), s.L(g.nb[site_of_vertex(cls, i)][k.warp[i]]));
        if (m.warp[to] < 0) fail("A15: a symmetry maps a lattice edge to none");
    }
    return m;
}
// Every canonical consistent key with a - vertex: the smallest image.
std::set<Enc15> a15_keys(const A15& g) {
    std::set<Enc15> out;
    for (int cls = 0; cls < 3; ++cls)
        for (int code = 0; code < 81; ++code) {
            Key k;
            for (int i = 0, c = code; i < 4; ++i, c /= 3) k.sign[i] = c % 3 - 1;
            if (std::none_of(k.sign.begin(), k.sign.end(), [](int v) { return v < 0; })) continue;
            std::array<int, 4> n{};
            for (int i = 0; i < 4; ++i) n[i] = k.sign[i] == 0 ? static_cast<int>(g.nb[site_of_vertex(cls, i)].size()) + 1 : 1;
            for (int w = 0; w < n[0] * n[1] * n[2] * n[3]; ++w) {
                for (int i = 0, r = w; i < 4; ++i, r /= n[i - 1]) k.warp[i] = k.sign[i] != 0 || r % n[i] == n[i] - 1 ? STAY : r % n[i];
                if (!a15_consistent(g, cls, k)) continue;
                Enc15 best = enc15(cls, k);
                for (const A15::Sym15& s : g.sym[cls]) best = std::min(best, enc15(cls, a15_image(g, cls, k, s)));
                out.insert(best);
            }
        }
    return out;
}
// "C:v,v,v,v", v one of -, +, 0x (x a warp letter a.. or s).
std::pair<int, Key> a15_parse_code(const std::string& s) {
    const auto bad = [&] { fail("bad A15 key code " + s.substr(0, 40)); };
    if (s.size() < 2 || s[0] < '0' || s[0] > '2' || s[1] != ':') bad();
    Key k;
    std::size_t at = 2;
    for (int i = 0; i < 4; ++i) {
        if (at >= s.size()) bad();
        const char c = s[at++];
        if (c == '-' || c == '+') k.sign[i] = c == '-' ? -1 : 1;
        else if (c == '0' && at < s.size() && (s[at] == 's' || (s[at] >= 'a' && s[at] <= 'n')))
            k.sign[i] = 0, k.warp[i] = s[at] == 's' ? STAY : s[at] - 'a', ++at;
        else bad();
        if (i < 3 && (at >= s.size() || s[at++] != ',')) bad();
    }
    if (at != s.size()) bad();
    return {s[0] - '0', k};
}
// The thresholds: chain, wide, mixed at the A end, mixed at the B end (over den).
struct Alphas15 {
    std::array<std::int64_t, 4> num{};
    std::int64_t den = 1;
    std::int64_t at(int len2, bool end_is_a) const { return len2 == 4 ? num[0] : len2 == 6 ? num[1] : end_is_a ? num[2] : num[3]; }
};
// The key's parameters (warped vertices, then cut edges, by local index):
// t of vertex i in [0, α of its warp edge at i], u of a (-, +) edge e =
// (i, j) in [α at i, 1 − α at j].
std::vector<Param> a15_params(const A15& g, int cls, const Key& k, const Alphas15& al) {
    std::vector<Param> ps;
    for (int i = 0; i < 4; ++i)
        if (k.warp[i] != STAY)
            ps.push_back({i, 0, al.at(norm2(g.nb[site_of_vertex(cls, i)][k.warp[i]]), site_of_vertex(cls, i) < 2), al.den});
    for (int e = 0; e < 6; ++e) {
        const int i = EDGE[e][0], j = EDGE[e][1];
        if (k.sign[i] * k.sign[j] >= 0) continue;
        const int len2 = norm2(diff3(A15_REF[cls][j], A15_REF[cls][i]));
        ps.push_back({4 + e, al.at(len2, site_of_vertex(cls, i) < 2), al.den - al.at(len2, site_of_vertex(cls, j) < 2), al.den});
    }
    return ps;
}
Frame a15_frame(const A15& g, int cls, const Key& k) {
    Frame f;
    for (int i = 0; i < 4; ++i)
        for (int c = 0; c < 3; ++c)
            f.ref[i][c] = A15_REF[cls][i][c], f.off[i][c] = k.warp[i] == STAY ? 0 : g.nb[site_of_vertex(cls, i)][k.warp[i]][c];
    return f;
}

// ---- the A15 certificate's lines -----------------------------------------------------
struct Entry15 {
    Entry e;  // its witnesses are wq's
    int cls = 0;
    Frame fr;
    std::array<std::vector<std::pair<std::int64_t, std::int64_t>>, 3> wq;  // p/q in lowest terms
};
std::int64_t gcd64(std::int64_t a, std::int64_t b) {
    a = a < 0 ? -a : a;
    while (b != 0) a %= b, std::swap(a, b);
    return a;
}
// The three witnesses (min, max, face): per parameter p/q with q a power of
// 2 up to 2^24 or the alphas' denominator, inside the exact box.
std::array<std::vector<std::pair<std::int64_t, std::int64_t>>, 3> parse_witnesses15(std::istream& in, const std::vector<Param>& ps,
                                                                                       const std::string& code) {
    std::array<std::vector<std::pair<std::int64_t, std::int64_t>>, 3> out;
    std::string x;
    for (auto& w : out)
        for (const Param& p : ps) {
            if (!(in >> x)) fail("bad witness for " + code);
            auto [n, q] = parse_q(x);
            if (!(q == p.den || ((q & (q - 1)) == 0 && q <= (std::int64_t{1} << 24)))) fail("bad witness denominator for " + code);
            const __int128 lo = static_cast<__int128>(p.lo_num) * q, hi = static_cast<__int128>(p.hi_num) * q, v = static_cast<__int128>(n) * p.den;
            if (v < lo || v > hi) fail("witness outside the parameter box of " + code);
            const std::int64_t g = gcd64(n, q);
            w.push_back({n / g, q / g});
        }
    return out;
}
// The exact cos² of the extreme angle (witness_cos2's kinds) of the rule's
// output at the rational point w: coordinates times S, the least common
// denominator (the point's scale; every form is homogeneous).
Cos2 witness15(const Model& m, const std::vector<std::pair<std::int64_t, std::int64_t>>& w, int kind) {
    std::int64_t S = 1;
    for (const auto& [n, q] : w) {
        S = S / gcd64(S, q) * q;
        if (S > (std::int64_t{1} << 56)) fail("witness denominators too large");
    }
    std::vector<I> val;
    for (const auto& [n, q] : w) val.push_back(point(zint(n * (S / q))));
    const auto pt = scaled_points<I>(m.frame(), m.ps, val, zint(S));
    bool found = false;
    Cos2 best;
    extreme_cos2(delaunay_tets(m, pt, true), pt, kind, found, best);
    if (!found) fail("min witness without an acute angle");
    return best;
}
Entry15 parse_key_line15(const A15& g, const std::string& line, const Alphas15& al, const std::set<Enc15>& expected, std::set<Enc15>& seen) {
    std::istringstream ks(line);
    std::string word, code;
    int m = -1;
    if (!(ks >> word >> code >> m) || word != "key") fail("bad key line");
    Entry15 en;
    std::tie(en.cls, en.e.k) = a15_parse_code(code);
    en.e.code = code;
    const Enc15 enc = enc15(en.cls, en.e.k);
    if (!expected.count(enc) || !seen.insert(enc).second) fail("unexpected or repeated key " + code);
    en.fr = a15_frame(g, en.cls, en.e.k);
    en.e.ps = a15_params(g, en.cls, en.e.k, al);
    if (m != static_cast<int>(en.e.ps.size())) fail("wrong parameter count for " + code);
    en.e.root = parse_root(ks, en.e.ps, code);
    std::string lo, hi, fa;
    if (!(ks >> lo >> hi >> fa)) fail("bad claim for " + code);
    en.e.claim = Claim{claim_threshold(lo), claim_threshold(hi), claim_threshold(fa)};
    en.wq = parse_witnesses15(ks, en.e.ps, code);
    en.e.splits = parse_splits(ks, m, code);
    return en;
}
Witnessed check_witnesses15(const Entry15& en) {
    Witnessed w{};
    const Model m{en.e.k, en.e.ps, false, en.fr};
    for (int j = 0; j < 3; ++j) {
        w.c[j] = witness15(m, en.wq[j], j);
        const Z& c = claim_of(en.e.claim, j);
        if ((j != 1 || !w.c[j].acute) && cmp(w.c[j].p * pow2(40), c * w.c[j].q) > 0) fail("the witness of " + en.e.code + " contradicts its claim");
        w.tight[j] = tight(c, w.c[j], tol_den(j), j == 1);
    }
    return w;
}
Alphas15 a15_alphas(const std::string& line) {
    std::istringstream a(line);
    std::string word, x[4];
    if (!(a >> word >> x[0] >> x[1] >> x[2] >> x[3]) || word != "alphas" || (a >> word)) fail("bad alphas line");
    Alphas15 al;
    for (int i = 0; i < 4; ++i) {
        const auto [n, d] = parse_q(x[i]);
        if ((i > 0 && d != al.den) || d >= (std::int64_t{1} << 31)) fail("alphas need one denominator below 2^31");
        if (!(n > 0 && 2 * n < d)) fail("alphas out of (0, 1/2)");
        al.num[i] = n, al.den = d;
    }
    return al;
}
// The A15 certificate: the lattice re-derived, the header, every key line
// and witness (cheap), the theorem's tightness, then every leaf.
int check_a15(const std::vector<std::string>& body, bool progress) {
    if (body.size() < 4) fail("an A15 certificate has alphas, claim and keys lines");
    const A15 g = derive_a15();
    const Alphas15 al = a15_alphas(body[1]);
    std::istringstream c(body[2]), n(body[3]);
    std::string word;
    std::array<std::string, 3> text;
    long nkeys = -1;
    if (!(c >> word >> text[0] >> text[1] >> text[2]) || word != "claim" || (c >> word)) fail("bad claim line");
    if (!(n >> word >> nkeys) || word != "keys" || nkeys < 0 || nkeys > 1000000 || (n >> word)) fail("bad keys line");
    const Claim claim{claim_threshold(text[0]), claim_threshold(text[1]), claim_threshold(text[2])};
    if (static_cast<long>(body.size()) != 4 + nkeys) fail("key count mismatch");
    const std::set<Enc15> expected = a15_keys(g);
    if (static_cast<long>(expected.size()) != nkeys)
        fail("the certificate does not list every key (" + std::to_string(expected.size()) + " canonical A15 keys)");
    std::vector<Entry15> keys;
    std::vector<Entry> entries;
    std::vector<Witnessed> wit;
    std::set<Enc15> seen;
    for (long i = 0; i < nkeys; ++i) {
        keys.push_back(parse_key_line15(g, body[4 + static_cast<std::size_t>(i)], al, expected, seen));
        entries.push_back(keys.back().e);
        wit.push_back(check_witnesses15(keys.back()));
    }
    std::size_t ext[3] = {0, 0, 0};
    theorem_extremes(claim, entries, wit, ext);
    // Every leaf, the keys on all threads (OpenMP, where built with it: the
    // keys are independent and the checker has no global state); a failure
    // is reported for the first failing key in the certificate's order.
    const bool terminal = ::isatty(STDERR_FILENO) == 1;
    std::vector<long> key_leaves(keys.size(), 0);
    std::vector<std::string> failure(keys.size());
    long done = 0, leaves = 0;
#pragma omp parallel for schedule(dynamic, 4)
    for (long i = 0; i < static_cast<long>(keys.size()); ++i) {
        const Entry15& en = keys[static_cast<std::size_t>(i)];
        try {
            const Model m{en.e.k, en.e.ps, false, en.fr};
            key_leaves[static_cast<std::size_t>(i)] = replay(m, oriented(en.e.k, parity_diag(en.e.k), en.fr), en.e.root, en.e.splits, en.e.claim, true);
        } catch (const Fail& e) {
            failure[static_cast<std::size_t>(i)] = en.e.code + ": " + e.msg;
        }
#pragma omp critical
        {
            leaves += key_leaves[static_cast<std::size_t>(i)];
            if (progress && (++done % 50 == 0 || done == static_cast<long>(keys.size())))
                std::cerr << (terminal ? "\r" : "") << "checked " << done << " of " << keys.size() << " A15 keys, " << leaves << " leaves"
                          << (terminal ? "\033[K" : "\n") << std::flush;
        }
    }
    if (progress && terminal) std::cerr << "\r\033[K";
    for (const std::string& f : failure)
        if (!f.empty()) fail(f);
    std::cout << "A15 lattice (re-derived): 8 sites per cell, " << g.per_class[0] + g.per_class[1] + g.per_class[2]
              << " Delaunay tetrahedra per cell (" << g.per_class[0] << " / " << g.per_class[1] << " / " << g.per_class[2]
              << " by class, each the image of its class's reference), reference symmetries " << g.sym[0].size() << " / "
              << g.sym[1].size() << " / " << g.sym[2].size() << "\n";
    std::string setting;
    for (int i = 0; i < 4; ++i) setting += (i ? ", " : "") + std::to_string(al.num[i]) + "/" + std::to_string(al.den);
    print_theorem(setting + " (chain, wide, mixed at A, mixed at B), Delaunay face rule", text, claim, entries, wit, ext, leaves, "A15");
    return 0;
}

// Parses the header, every key line and witness (cheap), then verifies the
// leaves; prints the theorem.
// The certificate's lines, '#' comments and blank lines dropped.  Hostile
// input is bounded: at most 256 MB are read (proofs/ holds 1.2 MB), counted
// byte by byte so that a stream without newlines is never held whole, a line
// has at most 16 MB (the longest key line there has 37 kB), and at most
// 1000010 lines are kept (a certificate has its key count, at most 1000000,
// and 5 more).
std::vector<std::string> read_body(std::istream& in) {
    constexpr std::size_t max_bytes = std::size_t{256} << 20, max_line = std::size_t{16} << 20, max_lines = 1000010;
    std::vector<std::string> body;
    std::string line;
    std::size_t bytes = 0;
    std::streambuf* sb = in.rdbuf();
    for (;;) {
        const int c = sb->sbumpc();
        const bool end = c == std::char_traits<char>::eof();
        if (!end && ++bytes > max_bytes) fail("larger than 256 MB: not a certificate");
        if (!end && c != '\n') {
            if (line.size() == max_line) fail("a line longer than 16 MB: not a certificate");
            line.push_back(static_cast<char>(c));
            continue;
        }
        if (!line.empty() && line[0] != '#') body.push_back(std::move(line));
        if (body.size() > max_lines) fail("more than 1000010 lines: not a certificate");
        line.clear();
        if (end) return body;
    }
}

// progress: a line per 50 keys on stderr, rewritten in place on a terminal.
int check(std::istream& in, bool progress) {
    const bool terminal = ::isatty(STDERR_FILENO) == 1;
    std::string word;
    const std::vector<std::string> body = read_body(in);
    if (!body.empty() && body[0] == "warpmesh-bcc-counterexample 1") return check_counterexample(body);
    if (!body.empty() && body[0] == "warpmesh-bcc-ceiling 1") return check_ceiling(body);
    if (!body.empty() && body[0] == "warpmesh-bcc-junctions 1") return check_junctions(body, progress);
    if (!body.empty() && body[0] == "warpmesh-bcc-graded 1") return check_graded(body);
    if (!body.empty() && body[0] == "warpmesh-a15-certificate 1") return check_a15(body, progress);
    const bool delaunay = !body.empty() && body[0] == "warpmesh-bcc-certificate 5";
    if (body.size() < 4 || (body[0] != "warpmesh-bcc-certificate 4" && !delaunay))
        fail("not a BCC certificate (format 4 or 5), counter-example, ceiling, junction or graded certificate (format 1)");
    // Format 5: one face-rule line, right after the header; format 4: none.
    long rules = 0;
    for (const std::string& l : body) rules += l.rfind("face-rule", 0) == 0;
    if (!delaunay && rules > 0) fail("a face-rule line in a format 4 certificate");
    if (delaunay && (rules != 1 || body[1].rfind("face-rule", 0) != 0)) fail("format 5 needs one face-rule line, after the header");
    if (delaunay && body[1] != "face-rule delaunay") fail("unknown face rule: " + body[1].substr(0, 60));
    const std::size_t h = delaunay ? 2 : 1;  // the alphas line
    std::istringstream a(body[h]), c(body[h + 1]), n(body[h + 2]);
    std::string al, as;
    std::array<std::string, 3> text;
    long nkeys = -1;
    if (!(a >> word >> al >> as) || word != "alphas") fail("bad alphas line");
    if (!(c >> word >> text[0] >> text[1] >> text[2]) || word != "claim" || (c >> word)) fail("bad claim line");
    if (!(n >> word >> nkeys) || word != "keys" || nkeys < 0 || nkeys > 1000000) fail("bad keys line");
    std::int64_t ld = 0;
    const auto [ln, sn] = bound_alphas(al, as, ld);
    const Claim claim{claim_threshold(text[0]), claim_threshold(text[1]), claim_threshold(text[2])};
    if (static_cast<long>(body.size()) != static_cast<long>(h) + 3 + nkeys) fail("key count mismatch");
    const auto expected = canonical_keys(symmetries());
    if (static_cast<long>(expected.size()) != nkeys) fail("the certificate does not list every key");
    // First pass, no leaf: keys, root boxes, claims, witnesses, split strings.
    std::vector<Entry> entries;
    std::set<std::array<int, 9>> seen;
    Z worst[3] = {zint(0), zint(0), zint(0)};
    std::vector<Witnessed> wit;
    for (long i = 0; i < nkeys; ++i) {
        entries.push_back(parse_key_line(body[h + 3 + static_cast<std::size_t>(i)], ln, sn, ld, expected, seen));
        wit.push_back(check_witnesses(entries.back(), delaunay));
        for (int j = 0; j < 3; ++j)
            if (cmp(claim_of(entries.back().claim, j), worst[j]) > 0) worst[j] = claim_of(entries.back().claim, j);
    }
    for (int j = 0; j < 3; ++j)
        if (cmp(worst[j], claim_of(claim, j)) != 0) fail("the claim is not the keys' extremes");
    // The theorem is tight: its most extreme witness (the smallest angle over
    // the keys' min (face) witnesses, resp. the largest over their max
    // witnesses) lies within 0.01° / 0.1° of it.  (A key's own claim may be
    // looser: counted below.)
    std::size_t ext[3] = {0, 0, 0};
    for (int j = 0; j < 3; ++j) {
        for (std::size_t i = 1; i < wit.size(); ++i)
            if (j != 1 ? larger(wit[ext[j]].c[j], wit[i].c[j]) : larger(wit[i].c[j], wit[ext[j]].c[j])) ext[j] = i;
        if (!tight(claim_of(claim, j), wit[ext[j]].c[j], tol_den(j), j == 1))
            fail(std::string("the theorem's ") + KIND[j] + " witness (" + entries[ext[j]].code + ") is not within " + TOL[j] +
                 " deg of the claim");
    }
    // Second pass: every leaf verified against its key's claim.
    long leaves = 0;
    for (std::size_t i = 0; i < entries.size(); ++i) {
        leaves += replay(Model{entries[i].k, entries[i].ps, false, std::nullopt}, oriented(entries[i].k), entries[i].root, entries[i].splits, entries[i].claim,
                         delaunay);
        if (progress && ((i + 1) % 50 == 0 || i + 1 == entries.size()))
            std::cerr << (terminal ? "\r" : "") << "checked " << i + 1 << " of " << entries.size() << " keys, " << leaves
                      << " leaves" << (terminal ? "\033[K" : "\n") << std::flush;
    }
    if (progress && terminal) std::cerr << "\r\033[K";  // the line erased: the theorem follows on stdout
    print_theorem(al + ", " + as + (delaunay ? ", Delaunay face rule" : ""), text, claim, entries, wit, ext, leaves);
    return 0;
}

int main(int argc, char** argv) {
    // Progress is shown on a terminal, or anywhere with --progress.
    const bool flag = argc == 3 && std::string(argv[1]) == "--progress";
    const bool progress = flag || ::isatty(STDERR_FILENO) == 1;
    if (argc != 2 && !flag) {
        std::cerr << "usage: warpmesh-check-bcc [--progress] CERTIFICATE\n"
                     "exit status: 0 the angle bound holds, 3 a counter-example or ceiling holds (NO BOUND),\n"
                     "1 rejected or unreadable, 2 usage\n";
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
