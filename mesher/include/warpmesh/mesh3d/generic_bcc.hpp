// generic_bcc.hpp — the 3D generic cell: lattice warping on the BCC lattice
// (isosurface stuffing), written once.
//
// The single source of truth for the geometry of the 3D angle proof, as
// generic_square.hpp is in 2D.  The 3D mesher instantiates it with `double`,
// the 3D prover with outward-rounded intervals (prover/src/bcc/); the
// independent checker (checker/checker3d.cpp) re-derives what it needs on
// its own, on purpose.  Only + - * and ScalarOps<T>::from_int are used on
// the scalar, so every form below is a polynomial in the parameters and is
// exact on exact inputs (rationals).
//
// THE LATTICE.  Coordinates are *doubled*: at spacing s a lattice point with
// integer coordinates q sits at q * s/2.  Cube corners have all three
// coordinates even, cube centres all three odd.  Every lattice point has 14
// lattice edges (`neighbour_offsets`): 6 long (axis-parallel, length s,
// offset ±2 along one axis) and 8 short (corner–centre, length √3/2·s,
// offsets (±1, ±1, ±1)).
//
// THE BACKGROUND TETRAHEDRA.  Two cubes sharing a face F, and one edge of F,
// span a tetrahedron: the two cube centres (a long edge through F) and the
// edge's two corners (a long edge of F).  They tile space, 12 per cube, all
// congruent; each has 2 long edges (opposite, perpendicular) and 4 short
// ones.  A tetrahedron's *local order* is (k0, k1, c0, c1): k0 k1 the corners,
// c0 c1 the centres, positively oriented (det(k1-k0, c0-k0, c1-k0) > 0).  Its
// local edges are `tet_edges`: 0 = k0k1 and 1 = c0c1 (long), 2..5 short.  The
// reference tetrahedron `reference_tet` is the one with k0 at the origin:
// k0 (0,0,0), k1 (2,0,0), c0 (1,1,-1), c1 (1,1,1).  Every background
// tetrahedron is the image of the reference one, vertex for vertex, under an
// orientation-preserving lattice isometry that maps corners to corners (a
// signed permutation of the axes with determinant +1, plus an even
// translation).
//
// CUT POINTS AND WARPING (the mesher's contract; the prover's configuration
// space is a superset, proofs/README.md "The BCC space").  f < 0 inside.
//   1. Every lattice point gets the sign of f: -, 0, +.
//   2. A lattice edge is *cut* iff its endpoints have strictly opposite
//      signs; its cut point is a zero of f on it, strictly inside.
//   3. A cut point at fraction u of its edge's length from endpoint v
//      *violates* v iff u < α_e, with α_e = α_long on long edges and α_short on
//      short ones (`Alphas`; both < 1/2, so it violates at most one endpoint).
//   4. Violations are applied closest first (`warp_before`: smaller fraction
//      first; ties by the lattice coordinates of v, then by the edge's
//      direction index — a geometric order, independent of labels).  A
//      violation (v, e) is applied iff v is still unwarped and the other
//      endpoint of e is still unwarped (the cut point still exists); v then
//      moves to the cut point and its sign becomes 0.
//   5. After warping, a cut point exists on every lattice edge whose
//      endpoints have strictly opposite post-warp signs; both endpoints are
//      unwarped and it violates neither (else step 4 would have applied it),
//      so its fraction lies in [α_e, 1 − α_e].
//   6. Each background tetrahedron is split by `stencil` from its vertices'
//      post-warp signs and its parity bit (`tet_parity`); the output is the
//      part with f <= 0.  A tetrahedron without a - vertex outputs nothing,
//      so one whose four vertices are all zero ("all-zero") is never output:
//      its faces, all of whose vertices lie on f = 0, become boundary faces
//      where a neighbour's output shares them, so the boundary stays on the
//      level set, the mesh stays conforming, and every output tetrahedron
//      has a key with a - vertex (certified: proofs/README.md).  Its volume,
//      within the α-band of the surface, is left out.
//
// THE STENCILS.  Let n-, n0, n+ count the post-warp signs.  n- = 0: nothing
// (all zero included, above).  n+ = 0: the whole tetrahedron.  Otherwise the
// output polyhedron's vertices are the - and 0 vertices and the cut points of
// the (-, +) edges:
//   n- = 1: one tetrahedron (each + vertex replaced by its cut point);
//   n- = 2, n0 = 1, n+ = 1: a pyramid over the quadrilateral (a, b, cut(b,r),
//      cut(a,r)) of the face (a, b, r), split by that quad's diagonal;
//   n- = 2, n+ = 2: a triangular prism with two quads on background faces and
//      one inside, 3 tetrahedra;
//   n- = 3, n+ = 1: a prism with three quads on background faces, 3 tetrahedra.
// A quad on a background face (A, B, r) (A, B the - vertices, r the + one) is
// split by a rule of the face alone, so the two tetrahedra sharing the face
// agree (conformity):
//   - AB short: the face's long edge is Ar or Br; the diagonal joins the cut
//     point on that long edge to the opposite lattice vertex.
//   - AB long (the *parity rule*, Labelle–Shewchuk §3.3): X = 1 iff AB joins
//     corners; par = the number of coordinates in which A exceeds cut(B, r),
//     mod 2.  The diagonal is A–cut(B, r) iff X == par, else B–cut(A, r).
//     (Evaluated from B and r alone: each coordinate of A differs strictly
//     from every point strictly inside B–r, so the comparison is made at the
//     midpoint, 2A > B + r.  Symmetric: swapping A and B flips par, so both
//     ends name the same diagonal.)
// The prism's inside quad (n- = 2, n+ = 2) takes the only diagonal that does
// not close a cycle of diagonals (a prism whose three quad diagonals turn the
// same way has no triangulation); with the face rules above the two face
// quads always turn the same way, so it is forced (`prism_tets` asserts a
// non-cyclic set).  The Delaunay face rule ("The diagonal choices" below)
// replaces both face rules by a test of the quad's own points; it is
// certified on its own (proofs/README.md, "The Delaunay face rule").
//
// PARITY IN THE LOCAL FRAME.  A lattice isometry maps every coordinate
// comparison of the parity rule to one comparison, reversed on each reflected
// axis, and X is preserved (corners to corners).  So every parity decision of
// a background tetrahedron equals the reference tetrahedron's decision for
// the same local face, exclusive-or one bit per tetrahedron, `tet_parity`
// (tests/test_bcc_definition.cpp checks this on every tetrahedron of a
// block).  The stencil needs only the local signs and that bit.
//
// ANGLE FORMS.  No angle is computed on the proof path.  For an output
// tetrahedron (p0, p1, p2, p3) and its edge (a, b) with the other vertices
// c, d, let e = pb − pa, n_c = e × (pc − pa), n_d = e × (pd − pa).  The
// dihedral angle θ at the edge is the angle between n_c and n_d, so
//        cos θ = (n_c·n_d) / (|n_c| |n_d|),
// and, for thresholds 0 < θmin < 90° < θmax with C = cos²θ:
//        θ >= θmin  <=>  n_c·n_d <= 0  or  (n_c·n_d)² <= C(θmin) |n_c|²|n_d|²,
//        θ <= θmax  <=>  n_c·n_d >= 0  or  (n_c·n_d)² <= C(θmax) |n_c|²|n_d|².
// `dihedral_forms` returns n_c·n_d and |n_c|²|n_d|² per edge and six times the
// signed volume (positive orientation: volume > 0).
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cstdint>
#include <optional>
#include <string_view>

#include "warpmesh/core/names.hpp"
#include "warpmesh/numerics/scalar.hpp"  // ScalarOps, decided_sign

namespace warpmesh::bcc {

using Ivec = std::array<int, 3>;
template <class T>
using Vec = std::array<T, 3>;

// ---------------------------------------------------------------------------
// The lattice (doubled coordinates).
inline constexpr std::array<Ivec, 14> neighbour_offsets{{{2, 0, 0},
                                                         {-2, 0, 0},
                                                         {0, 2, 0},
                                                         {0, -2, 0},
                                                         {0, 0, 2},
                                                         {0, 0, -2},
                                                         {1, 1, 1},
                                                         {-1, 1, 1},
                                                         {1, -1, 1},
                                                         {-1, -1, 1},
                                                         {1, 1, -1},
                                                         {-1, 1, -1},
                                                         {1, -1, -1},
                                                         {-1, -1, -1}}};
inline constexpr int direction_count = 14;
// Warp state of a vertex that did not move (a - or + vertex, or a zero vertex
// with f = 0 exactly at the lattice point).
inline constexpr int stay = 14;

constexpr bool is_long_direction(int d) { return d < 6; }
constexpr bool is_corner(const Ivec& p) { return (p[0] & 1) == 0; }
constexpr Ivec add(const Ivec& a, const Ivec& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
constexpr Ivec sub(const Ivec& a, const Ivec& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
// Index of offset d in neighbour_offsets, or -1.
constexpr int direction_of(const Ivec& d) {
    for (int i = 0; i < direction_count; ++i)
        if (neighbour_offsets[static_cast<std::size_t>(i)] == d) return i;
    return -1;
}

// Violation thresholds (rationals num/den, 0 < α < 1/2).
struct Alphas {
    std::int64_t long_num, long_den, short_num, short_den;
};
// Labelle and Shewchuk's pair (0.24999, 0.41189).
inline constexpr Alphas labelle_shewchuk_alphas{24999, 100000, 41189, 100000};
// The parity rule's pair (0.285, 0.3985), chosen from the certified frontier
// (proofs/README.md, "The certified frontier (3D)"): the largest certified
// minimum dihedral angle with a certified maximum <= 165 deg; proofs/bcc.cert
// is proved at it.
inline constexpr Alphas parity_alphas{28500, 100000, 39850, 100000};
// The Delaunay face rule's pair (0.2675, 0.39), the best of its sampled table
// (proofs/README.md, "Towards θmin ≥ 12°" (e)); proofs/bcc_delaunay.cert is
// proved at it.
inline constexpr Alphas delaunay_alphas{26750, 100000, 39000, 100000};

// ---------------------------------------------------------------------------
// The background tetrahedra and the local frame.
inline constexpr std::array<std::array<int, 2>, 6> tet_edges{{{0, 1}, {2, 3}, {0, 2}, {0, 3}, {1, 2}, {1, 3}}};
constexpr bool edge_is_long(int e) { return e < 2; }
constexpr int edge_index(int i, int j) {
    for (int e = 0; e < 6; ++e)
        if ((tet_edges[static_cast<std::size_t>(e)][0] == i && tet_edges[static_cast<std::size_t>(e)][1] == j) ||
            (tet_edges[static_cast<std::size_t>(e)][0] == j && tet_edges[static_cast<std::size_t>(e)][1] == i))
            return e;
    return -1;
}
inline constexpr std::array<Ivec, 4> reference_tet{{{0, 0, 0}, {2, 0, 0}, {1, 1, -1}, {1, 1, 1}}};

constexpr long det3(const Ivec& a, const Ivec& b, const Ivec& c) {
    return static_cast<long>(a[0]) * (b[1] * c[2] - b[2] * c[1]) - static_cast<long>(a[1]) * (b[0] * c[2] - b[2] * c[0]) +
           static_cast<long>(a[2]) * (b[0] * c[1] - b[1] * c[0]);
}
constexpr long orientation(const std::array<Ivec, 4>& p) {
    return det3(sub(p[1], p[0]), sub(p[2], p[0]), sub(p[3], p[0]));
}

// Background tetrahedron `index` (0..11) owned by the cube whose lowest corner
// is m (all even): the face of that cube at its low side along axis a =
// index / 4, the centres c = m + (1,1,1) and c − 2 e_a; the face's edge along
// axis b (the ((index / 2) % 2)-th of the two other axes), at offset 0 or 2
// (index % 2) along the remaining axis.  Local order, positively oriented.
// Every background tetrahedron is owned by exactly one cube.
constexpr std::array<Ivec, 4> background_tet(const Ivec& m, int index) {
    const int a = index / 4;
    const int b = (a + 1 + (index / 2) % 2) % 3;
    const int c = 3 - a - b;
    Ivec c0 = add(m, Ivec{1, 1, 1});
    Ivec c1 = c0;
    c1[static_cast<std::size_t>(a)] -= 2;
    Ivec k0 = m;
    k0[static_cast<std::size_t>(c)] += 2 * (index % 2);
    Ivec k1 = k0;
    k1[static_cast<std::size_t>(b)] += 2;
    std::array<Ivec, 4> t{k0, k1, c0, c1};
    if (orientation(t) < 0) std::swap(t[2], t[3]);
    return t;
}

// ---------------------------------------------------------------------------
// The parity rule on the lattice face (A, B, r), AB long: true iff the
// diagonal is A–cut(B, r).
constexpr bool parity_takes_a(const Ivec& A, const Ivec& B, const Ivec& r) {
    int par = 0;
    for (int i = 0; i < 3; ++i) par += 2 * A[static_cast<std::size_t>(i)] > B[static_cast<std::size_t>(i)] + r[static_cast<std::size_t>(i)] ? 1 : 0;
    return (is_corner(A) ? 1 : 0) == par % 2;
}

// The tetrahedron's parity bit: whether its decisions are the reference
// tetrahedron's, reversed (see "Parity in the local frame").
constexpr int tet_parity(const std::array<Ivec, 4>& p) {
    return parity_takes_a(p[0], p[1], p[2]) != parity_takes_a(reference_tet[0], reference_tet[1], reference_tet[2]) ? 1 : 0;
}

// The face rule in the local frame: on the face (a, b, r) of local vertices
// with a, b the - vertices, true iff the quad's diagonal is a–cut(b, r).
constexpr bool face_takes_a(int a, int b, int r, int parity) {
    if (edge_is_long(edge_index(a, b)))
        return parity_takes_a(reference_tet[static_cast<std::size_t>(a)], reference_tet[static_cast<std::size_t>(b)],
                              reference_tet[static_cast<std::size_t>(r)]) != (parity != 0);
    return !edge_is_long(edge_index(a, r));  // the long edge is br: a–cut(b, r)
}

// ---------------------------------------------------------------------------
// The stencils.  Points of the generic tetrahedron: 0..3 its vertices, 4 + e
// the cut point on local edge e.  Output tetrahedra are positively oriented
// in the reference configuration (vertices at their lattice points, cut
// points at the midpoints).
inline constexpr int cut_point(int i, int j) { return 4 + edge_index(i, j); }
using OutTet = std::array<std::uint8_t, 4>;
struct Stencil {
    int count = 0;
    std::array<OutTet, 3> tet{};
};

// Reference positions (quadrupled coordinates: exact integers).
constexpr Ivec reference_point(int q) {
    if (q < 4) {
        const Ivec& p = reference_tet[static_cast<std::size_t>(q)];
        return {2 * p[0], 2 * p[1], 2 * p[2]};
    }
    const auto& e = tet_edges[static_cast<std::size_t>(q - 4)];
    return add(reference_tet[static_cast<std::size_t>(e[0])], reference_tet[static_cast<std::size_t>(e[1])]);
}

constexpr void push_oriented(Stencil& s, int p0, int p1, int p2, int p3) {
    OutTet t{static_cast<std::uint8_t>(p0), static_cast<std::uint8_t>(p1), static_cast<std::uint8_t>(p2),
             static_cast<std::uint8_t>(p3)};
    const long o = orientation({reference_point(p0), reference_point(p1), reference_point(p2), reference_point(p3)});
    assert(o != 0);
    if (o < 0) std::swap(t[2], t[3]);
    s.tet[static_cast<std::size_t>(s.count++)] = t;
}

// The prism with triangles bot[0..2], top[0..2] (bot[i] and top[i] joined by
// an edge) and lateral quads i = (bot[i], bot[i+1], top[i+1], top[i]), split
// by fwd[i] ? bot[i]–top[i+1] : bot[i+1]–top[i].  Not all fwd equal.  Some
// bot[i] carries two diagonals (fwd[i] and not fwd[i-1]); it sees the whole
// top triangle, and the rest is a pyramid over quad i+1 with apex bot[i].
constexpr void prism_tets(Stencil& s, const std::array<int, 3>& bot, const std::array<int, 3>& top,
                          const std::array<bool, 3>& fwd) {
    assert(!(fwd[0] == fwd[1] && fwd[1] == fwd[2]));
    int i = 0;
    while (!(fwd[static_cast<std::size_t>(i)] && !fwd[static_cast<std::size_t>((i + 2) % 3)])) ++i;
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    const auto B = [&](int x) { return bot[static_cast<std::size_t>(x)]; };
    const auto T = [&](int x) { return top[static_cast<std::size_t>(x)]; };
    push_oriented(s, B(i), T(0), T(1), T(2));
    if (fwd[static_cast<std::size_t>(j)]) {  // quad j split by bot[j]–top[k]
        push_oriented(s, B(i), B(j), B(k), T(k));
        push_oriented(s, B(i), B(j), T(k), T(j));
    } else {  // split by bot[k]–top[j]
        push_oriented(s, B(i), B(j), B(k), T(j));
        push_oriented(s, B(i), B(k), T(k), T(j));
    }
}

// ---------------------------------------------------------------------------
// THE DIAGONAL CHOICES.  A stencil is fixed by the post-warp signs and, for
// the quads it splits, which diagonal each takes.  `Diagonals` records them
// resolved, whichever rule chose them:
//   face    bit f (f = the local vertex off the face) set iff that face's
//           quad — the face has two - vertices a < b and one + vertex r —
//           is split by a–cut(b, r); otherwise by b–cut(a, r).  Read only
//           on faces that hold a quad.
//   inside  the n- = 2, n+ = 2 prism (- vertices a < b, + vertices r0 < r1):
//           its inside quad, where free, is split by cut(a, r0)–cut(b, r1)
//           iff set, else by cut(a, r1)–cut(b, r0).  It is free iff the two
//           face quads' diagonals do not force it (a cycle of three
//           diagonals turning the same way has no triangulation).
// Two rules fill them in:
//   parity    (`parity_diagonals`) the faces by `face_takes_a` (the parity
//             rule on long-AB faces, the long edge's cut point on short-AB
//             faces); the inside quad turns against the prism's face
//             (a, b, r0).  The mesher's rule and proofs/bcc.cert's.
//   delaunay  (`delaunay_diagonals`) each face quad by the empty-circle test.
//             The quad (a, b, cut(b,r), cut(a,r)) lies in the lattice face
//             (a, b, r are unwarped lattice points) and is convex.  By the
//             power of the point r, the circle through a, b, cut(b,r) meets
//             the line r–a again at distance P_b / |ra| from r, with
//                 P_x = |xr| · |cut(x,r) r| = |xr|² (1 − u_x),
//             u_x the cut point's fraction of xr from x.  So a–cut(b,r) is
//             the Delaunay diagonal iff cut(a,r) lies outside that circle iff
//                 face_form(a, b, r) = P_b − P_a > 0,
//             linear in the cut fractions (|xr|² = 4 on long edges, 3 on short
//             ones, in doubled coordinates).  P = 0: cocircular, the parity
//             rule decides.  Both tetrahedra sharing the face see the same
//             a, b, r and cut points, so they agree (conformity).  Around the
//             n- = 3 prism the three comparisons of P_a, P_b, P_c cannot turn
//             the same way, so no prism is cyclic.  The inside quad (free)
//             takes the shorter diagonal: cut(a,r0)–cut(b,r1) iff
//                 inside_form = |cut(a,r0) cut(b,r1)|² − |cut(a,r1) cut(b,r0)|² < 0
//             (quadratic in the cut fractions; a tie turns against the face
//             (a, b, r0), as parity does).  It lies in one tetrahedron only,
//             so any choice is conforming.
// `stencil_with` builds the stencil of any resolved choice; `stencil(sign,
// parity)` is `stencil_with(sign, parity_diagonals(sign, parity))`.
struct Diagonals {
    unsigned face = 0;
    bool inside = false;
};

// The face quad split by x–cut(y, r)?  (x, y the face's - vertices, any order.)
constexpr bool takes(const Diagonals& d, int x, int y, int r) {
    const int f = 6 - x - y - r;
    const bool low = (d.face >> f & 1u) != 0;
    return x < y ? low : !low;
}

// The quad of the face without local vertex f, if it holds one: its two -
// vertices a < b and its + vertex r (false, and -1s, otherwise).
constexpr bool quad_face(const std::array<int, 4>& sign, int f, int& a, int& b, int& r) {
    a = b = r = -1;
    for (int i = 0; i < 4; ++i) {
        if (i == f) continue;
        const int v = sign[static_cast<std::size_t>(i)];
        if (v < 0) (a < 0 ? a : b) = i;
        else if (v > 0) r = i;
    }
    return b >= 0 && r >= 0;
}

// The n- = 2, n+ = 2 prism's inside quad: its - vertices a < b and its +
// vertices r0 < r1 (false, and -1s, for every other sign pattern).
constexpr bool inside_quad(const std::array<int, 4>& sign, int& a, int& b, int& r0, int& r1) {
    a = b = r0 = r1 = -1;
    int nn = 0, np = 0;
    for (int i = 0; i < 4; ++i) {
        const int v = sign[static_cast<std::size_t>(i)];
        if (v < 0 && nn++ < 2) (a < 0 ? a : b) = i;
        if (v > 0 && np++ < 2) (r0 < 0 ? r0 : r1) = i;
    }
    if (nn == 2 && np == 2) return true;
    a = b = r0 = r1 = -1;
    return false;
}

// Whether `d` turns the three face quads of an n- = 3, n+ = 1 prism the same
// way (a cycle, which no stencil cuts; never under either rule with exact
// signs, but a union over admissible signs can name one).
constexpr bool is_cyclic(const std::array<int, 4>& sign, const Diagonals& d) {
    std::array<int, 3> neg{};
    int nn = 0, r = -1;
    for (int i = 0; i < 4; ++i) {
        if (sign[static_cast<std::size_t>(i)] < 0 && nn < 3) neg[static_cast<std::size_t>(nn++)] = i;
        if (sign[static_cast<std::size_t>(i)] > 0) r = i;
    }
    if (nn != 3 || r < 0) return false;
    const bool f0 = takes(d, neg[0], neg[1], r);
    return takes(d, neg[1], neg[2], r) == f0 && takes(d, neg[2], neg[0], r) == f0;
}

// The parity rule's choices (see above).
constexpr Diagonals parity_diagonals(const std::array<int, 4>& sign, int parity) {
    Diagonals d;
    for (int f = 0; f < 4; ++f) {  // the faces with two - vertices and one + vertex
        int a = -1, b = -1, r = -1;
        if (quad_face(sign, f, a, b, r) && face_takes_a(a, b, r, parity)) d.face |= 1u << f;
    }
    int a = -1, b = -1, r0 = -1, r1 = -1;
    if (inside_quad(sign, a, b, r0, r1)) d.inside = !face_takes_a(a, b, r0, parity);
    return d;
}

// The fraction of the cut point on local edge (x, y) from x (u[e] is from
// tet_edges[e][0]).
template <class T>
T cut_fraction(int x, int y, const std::array<T, 6>& u) {
    const int e = edge_index(x, y);
    const T& f = u[static_cast<std::size_t>(e)];
    return tet_edges[static_cast<std::size_t>(e)][0] == x ? f : ScalarOps<T>::from_int(1) - f;
}

// The Delaunay face form P_b − P_a of the face (a, b, r) (see above): > 0
// iff a–cut(b, r) is the Delaunay diagonal.  Antisymmetric in a, b.
template <class T>
T face_form(int a, int b, int r, const std::array<T, 6>& u) {
    using O = ScalarOps<T>;
    const auto power = [&](int x) {
        const T len2 = O::from_int(edge_is_long(edge_index(x, r)) ? 4 : 3);
        return len2 * (O::from_int(1) - cut_fraction(x, r, u));
    };
    return power(b) - power(a);
}

// The prism's inside form of a tetrahedron with integer corners ref[0..3]:
// |cut(a,r0) cut(b,r1)|² − |cut(a,r1) cut(b,r0)|², < 0 iff cut(a,r0)–cut(b,r1)
// is the shorter diagonal (one definition for every lattice: BCC's reference
// tetrahedron here, A15's classes in generic_a15.hpp).
template <class T, class Ref>
T inside_form_of(const Ref& ref, int a, int b, int r0, int r1, const std::array<T, 6>& u) {
    using O = ScalarOps<T>;
    const auto at = [&](int x, int r, int k) {
        const T base = O::from_int(ref[static_cast<std::size_t>(x)][static_cast<std::size_t>(k)]);
        const int d = ref[static_cast<std::size_t>(r)][static_cast<std::size_t>(k)] - ref[static_cast<std::size_t>(x)][static_cast<std::size_t>(k)];
        return d == 0 ? base : base + O::from_int(d) * cut_fraction(x, r, u);
    };
    const auto dist2 = [&](int x, int rx, int y, int ry) {
        T s = O::from_int(0);
        for (int k = 0; k < 3; ++k) {
            const T c = at(x, rx, k) - at(y, ry, k);
            s = s + c * c;
        }
        return s;
    };
    return dist2(a, r0, b, r1) - dist2(a, r1, b, r0);
}

// BCC's (doubled coordinates).
template <class T>
T inside_form(int a, int b, int r0, int r1, const std::array<T, 6>& u) {
    return inside_form_of(reference_tet, a, b, r0, r1, u);
}

// Resolve the Delaunay rule from the signs (-1, 0, +1) of its forms:
// face_sign[f] the sign of face_form(a, b, r) on the face without f (a < b;
// ignored where the face holds no quad), inside_sign that of inside_form
// (ignored unless n- = 2, n+ = 2).  Zeros fall back to `parity_diagonals`.
// The prover calls it for every sign its intervals admit, the mesher with
// exact signs.
constexpr Diagonals resolve_delaunay(const std::array<int, 4>& sign, int parity, const std::array<int, 4>& face_sign,
                                     int inside_sign) {
    const Diagonals p = parity_diagonals(sign, parity);
    Diagonals d = p;
    for (int f = 0; f < 4; ++f) {
        const int s = face_sign[static_cast<std::size_t>(f)];
        if (s > 0) d.face |= 1u << f;
        if (s < 0) d.face &= ~(1u << f);
    }
    if (inside_sign < 0) d.inside = true;
    if (inside_sign > 0) d.inside = false;
    if (inside_sign == 0) {  // a tie turns against the face (a, b, r0), as parity does
        int a = -1, b = -1, r0 = -1;
        for (int i = 0; i < 4; ++i) {
            const int v = sign[static_cast<std::size_t>(i)];
            if (v < 0) (a < 0 ? a : b) = i;
            if (v > 0 && r0 < 0) r0 = i;
        }
        if (b >= 0 && r0 >= 0) d.inside = !takes(d, a, b, r0);
    }
    return d;
}

// The signs of the Delaunay forms at cut fractions u, where the scalar
// decides them (decided_sign: the three-valued comparison with zero):
// face[f] that of face_form on the face without vertex f, inside that of
// inside_form; 0 where the face holds no quad, or there is no inside quad
// (read off `sign`).  Exact scalars decide every sign; an enclosure (the
// prover's intervals, the mesher's filtered doubles) leaves std::nullopt
// where it cannot tell.
struct DelaunaySigns {
    std::array<std::optional<int>, 4> face{0, 0, 0, 0};
    std::optional<int> inside = 0;
};
template <class T>
DelaunaySigns delaunay_signs(const std::array<int, 4>& sign, const std::array<T, 6>& u) {
    DelaunaySigns s;
    for (int f = 0; f < 4; ++f) {
        int a = -1, b = -1, r = -1;
        if (quad_face(sign, f, a, b, r)) s.face[static_cast<std::size_t>(f)] = decided_sign(face_form(a, b, r, u));
    }
    int a = -1, b = -1, r0 = -1, r1 = -1;
    if (inside_quad(sign, a, b, r0, r1)) s.inside = decided_sign(inside_form(a, b, r0, r1, u));
    return s;
}

// The Delaunay rule's choices at cut fractions u, or std::nullopt where the
// scalar leaves a sign undecided (never for exact scalars, double included).
template <class T>
std::optional<Diagonals> decided_delaunay_diagonals(const std::array<int, 4>& sign, int parity, const std::array<T, 6>& u) {
    const DelaunaySigns s = delaunay_signs(sign, u);
    std::array<int, 4> fs{};
    for (std::size_t f = 0; f < 4; ++f) {
        if (!s.face[f]) return std::nullopt;
        fs[f] = *s.face[f];
    }
    if (!s.inside) return std::nullopt;
    return resolve_delaunay(sign, parity, fs, *s.inside);
}

// The Delaunay rule's choices at exact (or double) cut fractions u.
template <class T>
Diagonals delaunay_diagonals(const std::array<int, 4>& sign, int parity, const std::array<T, 6>& u) {
    return decided_delaunay_diagonals(sign, parity, u).value();
}

// The output tetrahedra of a background tetrahedron with post-warp signs
// `sign` (local order), its quads split as `d` says; none without a - vertex.
constexpr Stencil stencil_with(const std::array<int, 4>& sign, const Diagonals& d) {
    Stencil s;
    std::array<int, 4> neg{}, zer{}, pos{};
    int nn = 0, nz = 0, np = 0;
    for (int i = 0; i < 4; ++i) {
        const int v = sign[static_cast<std::size_t>(i)];
        if (v < 0) neg[static_cast<std::size_t>(nn++)] = i;
        else if (v == 0) zer[static_cast<std::size_t>(nz++)] = i;
        else pos[static_cast<std::size_t>(np++)] = i;
    }
    if (nn == 0) return s;  // all zero included: never output (step 6)
    if (np == 0) {
        push_oriented(s, 0, 1, 2, 3);
        return s;
    }
    if (nn == 1) {
        std::array<int, 4> q{0, 1, 2, 3};
        for (int i = 0; i < 4; ++i)
            if (sign[static_cast<std::size_t>(i)] > 0) q[static_cast<std::size_t>(i)] = cut_point(neg[0], i);
        push_oriented(s, q[0], q[1], q[2], q[3]);
        return s;
    }
    if (nn == 2 && np == 1) {  // pyramid: apex the zero vertex over the quad of face (a, b, r)
        const int a = neg[0], b = neg[1], r = pos[0], z = zer[0];
        const int ca = cut_point(a, r), cb = cut_point(b, r);
        if (takes(d, a, b, r)) {
            push_oriented(s, z, a, b, cb);
            push_oriented(s, z, a, cb, ca);
        } else {
            push_oriented(s, z, a, b, ca);
            push_oriented(s, z, b, cb, ca);
        }
        return s;
    }
    if (nn == 2) {  // prism: bottom (a, cut(a,r0), cut(a,r1)), top (b, cut(b,r0), cut(b,r1))
        const int a = neg[0], b = neg[1], r0 = pos[0], r1 = pos[1];
        const std::array<int, 3> bot{a, cut_point(a, r0), cut_point(a, r1)};
        const std::array<int, 3> top{b, cut_point(b, r0), cut_point(b, r1)};
        // quad 0 = face (a, b, r0): forward = a–cut(b, r0); quad 2 = face (a, b, r1)
        // read backwards: forward = bot[2]–top[0] = cut(a, r1)–b; quad 1 = the
        // inside quad: forward = bot[1]–top[2] = cut(a, r0)–cut(b, r1).
        const bool f0 = takes(d, a, b, r0);
        const bool f2 = !takes(d, a, b, r1);
        const bool f1 = f0 == f2 ? !f0 : d.inside;  // forced unless free
        prism_tets(s, bot, top, {f0, f1, f2});
        return s;
    }
    // nn == 3, np == 1: bottom (a, b, c), top their cut points towards r.
    const int r = pos[0];
    const std::array<int, 3> bot{neg[0], neg[1], neg[2]};
    const std::array<int, 3> top{cut_point(neg[0], r), cut_point(neg[1], r), cut_point(neg[2], r)};
    std::array<bool, 3> fwd{};
    for (int i = 0; i < 3; ++i)
        fwd[static_cast<std::size_t>(i)] = takes(d, bot[static_cast<std::size_t>(i)], bot[static_cast<std::size_t>((i + 1) % 3)], r);
    prism_tets(s, bot, top, fwd);
    return s;
}

// The parity rule's stencil (the mesher's and proofs/bcc.cert's).
constexpr Stencil stencil(const std::array<int, 4>& sign, int parity) {
    return stencil_with(sign, parity_diagonals(sign, parity));
}

}  // namespace warpmesh::bcc

namespace warpmesh {

// The rule that fills in the diagonal choices of a mesh (above): parity
// (`parity_diagonals`) or the Delaunay face rule (`delaunay_diagonals`).
// Its names (reports, the certificates' face-rule line, the options'
// face_rule), one table read both ways: face_rule_name, and the one parser
// of names, parse_face_rule ("parity", "delaunay"; nothing for any other).
enum class FaceRule { parity, delaunay };
inline constexpr std::array<Named<FaceRule>, 2> face_rule_names{
    {{FaceRule::parity, "parity"}, {FaceRule::delaunay, "delaunay"}}};
inline constexpr std::array<FaceRule, 2> face_rules{FaceRule::parity, FaceRule::delaunay};
constexpr const char* face_rule_name(FaceRule rule) { return name_of(face_rule_names, rule).data(); }
constexpr std::optional<FaceRule> parse_face_rule(std::string_view name) { return value_of(face_rule_names, name); }

}  // namespace warpmesh

namespace warpmesh::bcc {

// ---------------------------------------------------------------------------
// A configuration of the generic tetrahedron (the prover's key, the mesher's
// background tetrahedron in its local frame): per vertex its post-warp sign
// and, for a zero vertex, the direction (index into neighbour_offsets, in the
// local frame) along which it was warped, or `stay`; and the parity bit.
struct Config {
    std::array<int, 4> sign{};
    std::array<int, 4> warp{stay, stay, stay, stay};
    int parity = 0;
};

template <class T>
T alpha(const Alphas& a, bool long_edge) {
    using O = ScalarOps<T>;
    return long_edge ? O::from_int(static_cast<int>(a.long_num)) / O::from_int(static_cast<int>(a.long_den))
                     : O::from_int(static_cast<int>(a.short_num)) / O::from_int(static_cast<int>(a.short_den));
}

// The ten points of the generic tetrahedron in the reference frame (doubled
// coordinates): vertex i at reference_tet[i] + t[i] · neighbour_offsets[warp[i]]
// (t[i] the fraction of that lattice edge, in [0, α_e]; ignored for `stay`),
// cut point e = (i, j) at reference_tet[i] + u[e] (reference_tet[j] −
// reference_tet[i]) (u[e] in [α_e, 1 − α_e]; meaningful only on (-, +) edges).
template <class T>
std::array<Vec<T>, 10> generic_points(const Config& c, const std::array<T, 4>& t, const std::array<T, 6>& u) {
    using O = ScalarOps<T>;
    std::array<Vec<T>, 10> p{};
    for (int i = 0; i < 4; ++i) {
        const Ivec& r = reference_tet[static_cast<std::size_t>(i)];
        const int w = c.warp[static_cast<std::size_t>(i)];
        for (int k = 0; k < 3; ++k) {
            p[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] = O::from_int(r[static_cast<std::size_t>(k)]);
            if (w != stay) {
                const int d = neighbour_offsets[static_cast<std::size_t>(w)][static_cast<std::size_t>(k)];
                if (d != 0)
                    p[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] =
                        p[static_cast<std::size_t>(i)][static_cast<std::size_t>(k)] + O::from_int(d) * t[static_cast<std::size_t>(i)];
            }
        }
    }
    for (int e = 0; e < 6; ++e) {
        const Ivec& a = reference_tet[static_cast<std::size_t>(tet_edges[static_cast<std::size_t>(e)][0])];
        const Ivec& b = reference_tet[static_cast<std::size_t>(tet_edges[static_cast<std::size_t>(e)][1])];
        for (int k = 0; k < 3; ++k) {
            const int d = b[static_cast<std::size_t>(k)] - a[static_cast<std::size_t>(k)];
            T x = O::from_int(a[static_cast<std::size_t>(k)]);
            if (d != 0) x = x + O::from_int(d) * u[static_cast<std::size_t>(e)];
            p[static_cast<std::size_t>(4 + e)][static_cast<std::size_t>(k)] = x;
        }
    }
    return p;
}

// ---------------------------------------------------------------------------
// Angle forms of one tetrahedron (see "Angle forms" above).  Edge k of the
// tetrahedron is (tet_edges[k]) in the output tetrahedron's own vertex order.
template <class T>
struct DihedralForms {
    std::array<T, 6> dot;  // n_c · n_d
    std::array<T, 6> nn;   // |n_c|² |n_d|²
    T volume6;             // det(p1 − p0, p2 − p0, p3 − p0)
};

template <class T>
Vec<T> vsub(const Vec<T>& a, const Vec<T>& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
}
template <class T>
Vec<T> cross(const Vec<T>& a, const Vec<T>& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
template <class T>
T dot(const Vec<T>& a, const Vec<T>& b) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

// Six times the signed volume.
template <class T>
T volume6_form(const std::array<Vec<T>, 4>& p) {
    return dot(vsub(p[1], p[0]), cross(vsub(p[2], p[0]), vsub(p[3], p[0])));
}
// The forms of edge k alone (dihedral_forms' dot[k] and nn[k], computed alike).
template <class T>
void dihedral_form(const std::array<Vec<T>, 4>& p, int k, T& d_out, T& nn_out) {
    const int a = tet_edges[static_cast<std::size_t>(k)][0], b = tet_edges[static_cast<std::size_t>(k)][1];
    int c = 0;
    while (c == a || c == b) ++c;
    const int d = 6 - a - b - c;
    const Vec<T> e = vsub(p[static_cast<std::size_t>(b)], p[static_cast<std::size_t>(a)]);
    const Vec<T> nc = cross(e, vsub(p[static_cast<std::size_t>(c)], p[static_cast<std::size_t>(a)]));
    const Vec<T> nd = cross(e, vsub(p[static_cast<std::size_t>(d)], p[static_cast<std::size_t>(a)]));
    d_out = dot(nc, nd);
    nn_out = dot(nc, nc) * dot(nd, nd);
}
template <class T>
DihedralForms<T> dihedral_forms(const std::array<Vec<T>, 4>& p) {
    DihedralForms<T> f{};
    f.volume6 = volume6_form(p);
    for (int k = 0; k < 6; ++k) dihedral_form(p, k, f.dot[static_cast<std::size_t>(k)], f.nn[static_cast<std::size_t>(k)]);
    return f;
}

// Face angles: at vertex a of the face without vertex o, q = 3a + the rank of
// o among the three others; b < c the face's other two vertices, u = pb − pa,
// v = pc − pa: cos φ = u·v / (|u| |v|), so with F = cos²φmin,
//        φ >= φmin  <=>  u·v <= 0  or  (u·v)² <= F |u|²|v|².
template <class T>
struct FaceAngleForms {
    std::array<T, 12> dot;  // u · v
    std::array<T, 12> nn;   // |u|² |v|²
};
// The forms of face angle q = 3a + k alone (face_angle_forms' dot[q], nn[q]).
template <class T>
void face_angle_form(const std::array<Vec<T>, 4>& p, int q, T& s_out, T& m_out) {
    const int a = q / 3, k = q % 3;
    const int o = k < a ? k : k + 1;  // the vertex off the face
    int b = 0;
    while (b == a || b == o) ++b;
    const int c = 6 - a - o - b;
    const Vec<T> u = vsub(p[static_cast<std::size_t>(b)], p[static_cast<std::size_t>(a)]);
    const Vec<T> v = vsub(p[static_cast<std::size_t>(c)], p[static_cast<std::size_t>(a)]);
    s_out = dot(u, v);
    m_out = dot(u, u) * dot(v, v);
}
template <class T>
FaceAngleForms<T> face_angle_forms(const std::array<Vec<T>, 4>& p) {
    FaceAngleForms<T> f{};
    for (int q = 0; q < 12; ++q) face_angle_form(p, q, f.dot[static_cast<std::size_t>(q)], f.nn[static_cast<std::size_t>(q)]);
    return f;
}

// ---------------------------------------------------------------------------
// The warping order (step 4 of the contract): violation a before b.  `frac`
// is the cut point's fraction of the edge from the violated vertex.
struct Violation {
    double frac;
    Ivec vertex;
    int direction;
};
inline bool warp_before(const Violation& a, const Violation& b) {
    if (a.frac != b.frac) return a.frac < b.frac;
    if (a.vertex != b.vertex) return a.vertex < b.vertex;
    return a.direction < b.direction;
}

}  // namespace warpmesh::bcc
