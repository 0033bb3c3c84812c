// generic_a15.hpp — the A15 generic cell: lattice warping (isosurface
// stuffing) on the A15 lattice, written once (issue 51).
//
// The A15 analogue of generic_bcc.hpp: one definition of the lattice, its
// background tetrahedra, edge classes, thresholds, warping order, stencils
// and face rule, templated on the scalar (only + - * and
// ScalarOps<T>::from_int touch it), for the mesher (double) and a prover
// (outward-rounded intervals).  The stencils and the diagonal bookkeeping
// (`bcc::Diagonals`, `bcc::stencil_with`, local edge numbering
// `bcc::tet_edges`) are those of generic_bcc.hpp: they depend only on the
// local order of a positively oriented tetrahedron, not on the lattice.
//
// THE LATTICE (Cr₃Si, the β-tungsten structure).  Coordinates are
// *quadrupled*: at cell size s a point with integer coordinates q sits at
// q · s/4.  A cubic cell (lowest corner 4m) holds 8 sites (`sites`):
//   type A (Si): (0,0,0), (2,2,2)            [cell coordinates 0, ½·(1,1,1)]
//   type B (Cr): (1,0,2), (3,0,2), (2,1,0), (2,3,0), (0,2,1), (0,2,3)
//                [(¼,0,½), (¾,0,½), (½,¼,0), (½,¾,0), (0,½,¼), (0,½,¾)]
// The B sites form chains along the three axes (x at y = 0, z = ½; y at
// z = 0, x = ½; z at x = 0, y = ½).  The lattice's symmetries (the space
// group Pm-3n) are, modulo translations by 4 Z³, 48 maps x ↦ M x + t, M a
// signed permutation matrix (`LatticeOp`), half of them proper.
//
// THE BACKGROUND TETRAHEDRA: the Delaunay tetrahedralization of the sites,
// unique (no five sites are cospherical), 46 tetrahedra per cell
// (`cell_tets`; a tetrahedron belongs to the cell holding its centroid) in
// three classes up to the lattice's symmetries:
//   class 0  A + 3 B, edges (|d|², quadrupled) 4, 5, 5, 5, 6, 6   24 per cell
//   class 1  A + 3 B, edges 5, 5, 5, 6, 6, 6                       16 per cell
//   class 2  4 B,     edges 4, 4, 6, 6, 6, 6                        6 per cell
// Every dihedral angle lies in [arccos(3/5), arccos(1/5)] = [53.130°,
// 78.463°] (Eppstein, Sullivan and Üngör 2004): the tiling is acute.
// tests/test_a15_definition.cpp proves all of this in exact integer
// arithmetic (orientation, tiling, empty spheres, dihedral forms).
//
// THE EDGES: three classes (`EdgeClass`), by squared length in quadrupled
// coordinates: chain 4 (B–B along a chain, length s/2), mixed 5 (A–B,
// √5/4·s ≈ 0.559 s, the only edges joining different kinds of site), wide 6
// (B–B across chains, √6/4·s ≈ 0.612 s).  An A site has 12 edges (all
// mixed: its icosahedron), a B site 14 (2 chain, 4 mixed, 8 wide):
// `neighbours`, in a fixed order whose index is the *direction* of a warp.
//
// THE LOCAL FRAME.  Each class has a reference tetrahedron
// (`reference_tets`, positively oriented): class 0 (B, B', A, B'') with BB'
// the chain edge; class 1 (A, B, B', B''); class 2 (B0, B1, B2, B3) with
// B0B1 and B2B3 the chain edges.  Cell tetrahedron j is the image of its
// class's reference, vertex for vertex, under a lattice symmetry
// `cell_tets[j].op` (then translated by 4m for cell m).  Classes 0 and 2
// are reached by proper symmetries; half of class 1 is the mirror image of
// the other half (its reference has only its three rotations as lattice
// symmetries), reached by improper ones: its local order is then
// negatively oriented (`det(op) = -1`), and the mesher orients its output
// tetrahedra by swapping two vertices.  Angles, the face rule's forms and
// the configuration's parameters are invariant under the symmetry, so a
// prover works in the reference frame alone; a global warp direction D of
// local vertex i is the reference direction M⁻¹ D (`to_local`), one of the
// reference vertex's site's `neighbours`.
//
// CUT POINTS AND WARPING (the mesher's contract).  f < 0 inside.
//   1. Every site gets the sign of f: -, 0, +.
//   2. A lattice edge is *cut* iff its endpoints have strictly opposite
//      signs; its cut point is a zero of f strictly inside it.
//   3. A cut point at fraction u of its edge's length from endpoint v
//      *violates* v iff u < α(class, kind of v) (`Alphas`, `threshold`):
//      α_chain, α_wide on B–B edges; on mixed edges α_A at the A end and
//      α_B at the B end (the ends differ).  Every α lies in (0, ½), so a cut
//      point violates at most one endpoint.
//   4. Violations are applied closest first: smaller fraction first, ties by
//      the lattice coordinates of v, then by the direction's index in v's
//      `neighbours` (`bcc::warp_before`: a geometric order, independent of
//      labels).  A violation (v, e) is applied iff v and the other endpoint
//      of e are both still unwarped; v moves to the cut point, sign 0.
//   5. A cut point remains on every lattice edge whose endpoints have
//      strictly opposite post-warp signs (both unwarped; fraction in
//      [α at that end, 1 − α at the other end]).
//   6. Each background tetrahedron is split by `bcc::stencil_with` from its
//      post-warp signs in the local order and the Delaunay face rule's
//      choices (`delaunay_diagonals`); nothing without a - vertex (all-zero
//      tetrahedra included), exactly as on BCC.
//
// THE FACE RULE (Delaunay).  A quad on a background face (a, b, r), a, b
// the - vertices and r the + one (all unwarped lattice sites, so the quad
// (a, b, cut(b,r), cut(a,r)) lies in the face and is convex), is split by
// its Delaunay diagonal.  By the power of the point r (generic_bcc.hpp,
// "The diagonal choices"), with P_x = |xr|² (1 − u_x), u_x the cut point's
// fraction of xr from x, a–cut(b, r) is the Delaunay diagonal iff
// P_a < P_b (`face_form` = P_b − P_a > 0).  A tie (cocircular quad) goes to
// the endpoint with the lexicographically smaller global coordinates: a
// takes the diagonal iff (P_a, a) < (P_b, b) lexicographically
// (`face_takes`).  This is a function of the face's global data alone, so
// both tetrahedra sharing the face agree (conformity, ties included); and
// it is a strict total order on the - vertices of an n- = 3, n+ = 1 prism
// (all three faces share r), so its three diagonals never turn the same way
// (no cyclic prism).  The n- = 2, n+ = 2 prism's inside quad lies in one
// tetrahedron; where free it takes the shorter diagonal (`inside_form` <
// 0: cut(a,r0)–cut(b,r1)), a tie turning against the face (a, b, r0), as
// on BCC.
//
// ORIENTATION OF THE STENCILS.  bcc::stencil_with orients its output
// tetrahedra at BCC's reference tetrahedron with cut points at the
// midpoints.  Any positively oriented tetrahedron with its edge midpoints
// is the image of that configuration under an orientation-preserving
// affine map, so the same outputs are positively oriented at the midpoints
// of every A15 reference tetrahedron (the test checks it for every class,
// sign pattern and choice of diagonals).
#pragma once

#include <array>
#include <cstdint>
#include <optional>

#include "warpmesh/mesh3d/generic_bcc.hpp"

namespace warpmesh::a15 {

using bcc::Ivec;
template <class T>
using Vec = bcc::Vec<T>;

// ---------------------------------------------------------------------------
// The sites (quadrupled coordinates).  Sites 0, 1 are of type A, 2..7 of
// type B.
inline constexpr int site_count = 8;
inline constexpr std::array<Ivec, site_count> sites{
    {{0, 0, 0}, {2, 2, 2}, {1, 0, 2}, {3, 0, 2}, {2, 1, 0}, {2, 3, 0}, {0, 2, 1}, {0, 2, 3}}};
constexpr bool site_is_a(int s) { return s < 2; }
constexpr int floor_mod4(int x) { return ((x % 4) + 4) % 4; }
constexpr int floor_div4(int x) { return (x - floor_mod4(x)) / 4; }
// The site of lattice point q (its position modulo the cell), or -1 if q is
// no lattice point.
constexpr int site_of(const Ivec& q) {
    const Ivec r{floor_mod4(q[0]), floor_mod4(q[1]), floor_mod4(q[2])};
    for (int s = 0; s < site_count; ++s)
        if (sites[static_cast<std::size_t>(s)] == r) return s;
    return -1;
}
// The cell m holding q (q = 4m + its site).
constexpr Ivec cell_of(const Ivec& q) { return {floor_div4(q[0]), floor_div4(q[1]), floor_div4(q[2])}; }

// ---------------------------------------------------------------------------
// The edges.
enum class EdgeClass : int { chain = 0, mixed = 1, wide = 2 };
constexpr int norm2(const Ivec& d) { return d[0] * d[0] + d[1] * d[1] + d[2] * d[2]; }
// The class of a lattice edge with offset d (|d|² = 4, 5 or 6).
constexpr EdgeClass edge_class(const Ivec& d) { return static_cast<EdgeClass>(norm2(d) - 4); }

// Each site's lattice edges (offsets), by squared length then
// lexicographically; A sites use the first 12 entries.
struct Neighbours {
    int count;
    std::array<Ivec, 14> offset;
};
inline constexpr std::array<Neighbours, site_count> neighbours{{
    {12, {{{-2, -1, 0}, {-2, 1, 0}, {-1, 0, -2}, {-1, 0, 2}, {0, -2, -1}, {0, -2, 1}, {0, 2, -1}, {0, 2, 1}, {1, 0, -2}, {1, 0, 2}, {2, -1, 0}, {2, 1, 0}}}},
    {12, {{{-2, 0, -1}, {-2, 0, 1}, {-1, -2, 0}, {-1, 2, 0}, {0, -1, -2}, {0, -1, 2}, {0, 1, -2}, {0, 1, 2}, {1, -2, 0}, {1, 2, 0}, {2, 0, -1}, {2, 0, 1}}}},
    {14, {{{-2, 0, 0}, {2, 0, 0}, {-1, 0, -2}, {-1, 0, 2}, {1, -2, 0}, {1, 2, 0}, {-1, -2, -1}, {-1, -2, 1}, {-1, 2, -1}, {-1, 2, 1}, {1, -1, -2}, {1, -1, 2}, {1, 1, -2}, {1, 1, 2}}}},
    {14, {{{-2, 0, 0}, {2, 0, 0}, {-1, -2, 0}, {-1, 2, 0}, {1, 0, -2}, {1, 0, 2}, {-1, -1, -2}, {-1, -1, 2}, {-1, 1, -2}, {-1, 1, 2}, {1, -2, -1}, {1, -2, 1}, {1, 2, -1}, {1, 2, 1}}}},
    {14, {{{0, -2, 0}, {0, 2, 0}, {-2, -1, 0}, {0, 1, -2}, {0, 1, 2}, {2, -1, 0}, {-2, 1, -1}, {-2, 1, 1}, {-1, -1, -2}, {-1, -1, 2}, {1, -1, -2}, {1, -1, 2}, {2, 1, -1}, {2, 1, 1}}}},
    {14, {{{0, -2, 0}, {0, 2, 0}, {-2, 1, 0}, {0, -1, -2}, {0, -1, 2}, {2, 1, 0}, {-2, -1, -1}, {-2, -1, 1}, {-1, 1, -2}, {-1, 1, 2}, {1, 1, -2}, {1, 1, 2}, {2, -1, -1}, {2, -1, 1}}}},
    {14, {{{0, 0, -2}, {0, 0, 2}, {-2, 0, 1}, {0, -2, -1}, {0, 2, -1}, {2, 0, 1}, {-2, -1, -1}, {-2, 1, -1}, {-1, -2, 1}, {-1, 2, 1}, {1, -2, 1}, {1, 2, 1}, {2, -1, -1}, {2, 1, -1}}}},
    {14, {{{0, 0, -2}, {0, 0, 2}, {-2, 0, -1}, {0, -2, 1}, {0, 2, 1}, {2, 0, -1}, {-2, -1, 1}, {-2, 1, 1}, {-1, -2, -1}, {-1, 2, -1}, {1, -2, -1}, {1, 2, -1}, {2, -1, 1}, {2, 1, 1}}}},
}};
// The warp state of a vertex that did not move.
inline constexpr int stay = 14;
// The index of offset d among site s's neighbours, or -1.
constexpr int direction_of(int s, const Ivec& d) {
    const Neighbours& n = neighbours[static_cast<std::size_t>(s)];
    for (int i = 0; i < n.count; ++i)
        if (n.offset[static_cast<std::size_t>(i)] == d) return i;
    return -1;
}

// ---------------------------------------------------------------------------
// The violation thresholds (rationals num/den in (0, ½)): per edge class and,
// on mixed edges, per end.
struct Fraction {
    std::int64_t num, den;
};
struct Alphas {
    Fraction chain, wide, mixed_at_a, mixed_at_b;
};
constexpr bool valid(const Fraction& f) { return f.den > 0 && f.num > 0 && 2 * f.num < f.den; }
constexpr bool valid(const Alphas& a) {
    return valid(a.chain) && valid(a.wide) && valid(a.mixed_at_a) && valid(a.mixed_at_b);
}
// The threshold of an edge of class c at an endpoint of type A (end_is_a)
// or B: a cut point at fraction u < threshold from that endpoint violates it.
constexpr Fraction threshold(const Alphas& a, EdgeClass c, bool end_is_a) {
    switch (c) {
        case EdgeClass::chain: return a.chain;
        case EdgeClass::wide: return a.wide;
        case EdgeClass::mixed: break;
    }
    return end_is_a ? a.mixed_at_a : a.mixed_at_b;
}
template <class T>
T to_scalar(const Fraction& f) {
    using O = ScalarOps<T>;
    return O::from_int(static_cast<int>(f.num)) / O::from_int(static_cast<int>(f.den));
}
// Whether a cut point at fraction u from an endpoint of type A (end_is_a)
// or B violates it (step 3), for exact or double u.
template <class T>
bool violates(const Alphas& a, EdgeClass c, bool end_is_a, const T& u) {
    const Fraction f = threshold(a, c, end_is_a);
    return u * ScalarOps<T>::from_int(static_cast<int>(f.den)) < ScalarOps<T>::from_int(static_cast<int>(f.num));
}

// ---------------------------------------------------------------------------
// The lattice symmetries: x ↦ M x + shift, (M x)_k = sign(axis[k]) ·
// x_{|axis[k]| − 1}.
struct LatticeOp {
    std::array<int, 3> axis;
    Ivec shift;
};
constexpr int axis_sign(int a) { return a < 0 ? -1 : 1; }
constexpr int axis_index(int a) { return (a < 0 ? -a : a) - 1; }
constexpr Ivec apply_linear(const LatticeOp& g, const Ivec& x) {
    Ivec y{};
    for (int k = 0; k < 3; ++k)
        y[static_cast<std::size_t>(k)] = axis_sign(g.axis[static_cast<std::size_t>(k)]) *
                                         x[static_cast<std::size_t>(axis_index(g.axis[static_cast<std::size_t>(k)]))];
    return y;
}
constexpr Ivec apply(const LatticeOp& g, const Ivec& x) { return bcc::add(apply_linear(g, x), g.shift); }
// M⁻¹ d (M is orthogonal: its inverse is its transpose).
constexpr Ivec to_local(const LatticeOp& g, const Ivec& d) {
    Ivec x{};
    for (int k = 0; k < 3; ++k)
        x[static_cast<std::size_t>(axis_index(g.axis[static_cast<std::size_t>(k)]))] =
            axis_sign(g.axis[static_cast<std::size_t>(k)]) * d[static_cast<std::size_t>(k)];
    return x;
}
// det M: +1 proper, −1 improper.
constexpr int det(const LatticeOp& g) {
    int s = axis_sign(g.axis[0]) * axis_sign(g.axis[1]) * axis_sign(g.axis[2]);
    const int i = axis_index(g.axis[0]), j = axis_index(g.axis[1]), k = axis_index(g.axis[2]);
    const int inversions = (i > j) + (i > k) + (j > k);
    return inversions % 2 == 0 ? s : -s;
}

// ---------------------------------------------------------------------------
// The background tetrahedra.  `cell_tets[j]`: class, vertices (cell 0's
// tetrahedron; cell m's is translated by 4m) in the local order, and the
// symmetry mapping the class's reference onto it vertex for vertex.
inline constexpr int class_count = 3;
inline constexpr int tets_per_cell = 46;
inline constexpr std::array<int, class_count> class_size{24, 16, 6};
struct CellTet {
    int cls;
    std::array<Ivec, 4> v;
    LatticeOp op;
};
inline constexpr std::array<CellTet, tets_per_cell> cell_tets{{
    {0, {{{-1, 0, 2}, {1, 0, 2}, {0, 0, 0}, {0, 2, 1}}}, {{1, 2, 3}, {0, 0, 0}}},
    {0, {{{-1, 4, 2}, {1, 4, 2}, {0, 4, 4}, {0, 2, 3}}}, {{1, -2, -3}, {0, 4, 4}}},
    {0, {{{0, 2, -1}, {0, 2, 1}, {0, 0, 0}, {2, 1, 0}}}, {{2, 3, 1}, {0, 0, 0}}},
    {0, {{{0, 2, 1}, {0, 2, -1}, {0, 4, 0}, {2, 3, 0}}}, {{2, -3, -1}, {0, 4, 0}}},
    {0, {{{0, 2, 1}, {0, 2, 3}, {2, 2, 2}, {1, 4, 2}}}, {{-3, 2, 1}, {2, 2, 2}}},
    {0, {{{0, 2, 3}, {0, 2, 1}, {2, 2, 2}, {1, 0, 2}}}, {{-3, -2, -1}, {2, 2, 2}}},
    {0, {{{1, 0, 2}, {-1, 0, 2}, {0, 0, 4}, {0, 2, 3}}}, {{-1, 2, -3}, {0, 0, 4}}},
    {0, {{{1, 0, 2}, {3, 0, 2}, {2, 2, 2}, {2, 1, 4}}}, {{1, -3, 2}, {2, 2, 2}}},
    {0, {{{1, 4, 2}, {-1, 4, 2}, {0, 4, 0}, {0, 2, 1}}}, {{-1, -2, 3}, {0, 4, 0}}},
    {0, {{{1, 4, 2}, {3, 4, 2}, {2, 2, 2}, {2, 3, 0}}}, {{1, 3, -2}, {2, 2, 2}}},
    {0, {{{2, -1, 0}, {2, 1, 0}, {0, 0, 0}, {1, 0, 2}}}, {{3, 1, 2}, {0, 0, 0}}},
    {0, {{{2, -1, 4}, {2, 1, 4}, {4, 0, 4}, {3, 0, 2}}}, {{-3, 1, -2}, {4, 0, 4}}},
    {0, {{{2, 1, 0}, {2, -1, 0}, {4, 0, 0}, {3, 0, 2}}}, {{-3, -1, 2}, {4, 0, 0}}},
    {0, {{{2, 1, 0}, {2, 3, 0}, {2, 2, 2}, {4, 2, 1}}}, {{2, 1, -3}, {2, 2, 2}}},
    {0, {{{2, 1, 4}, {2, -1, 4}, {0, 0, 4}, {1, 0, 2}}}, {{3, -1, -2}, {0, 0, 4}}},
    {0, {{{2, 1, 4}, {2, 3, 4}, {2, 2, 2}, {0, 2, 3}}}, {{-2, 1, 3}, {2, 2, 2}}},
    {0, {{{2, 3, 0}, {2, 1, 0}, {2, 2, 2}, {0, 2, 1}}}, {{-2, -1, -3}, {2, 2, 2}}},
    {0, {{{2, 3, 4}, {2, 1, 4}, {2, 2, 2}, {4, 2, 3}}}, {{2, -1, 3}, {2, 2, 2}}},
    {0, {{{3, 0, 2}, {1, 0, 2}, {2, 2, 2}, {2, 1, 0}}}, {{-1, -3, -2}, {2, 2, 2}}},
    {0, {{{3, 4, 2}, {1, 4, 2}, {2, 2, 2}, {2, 3, 4}}}, {{-1, 3, 2}, {2, 2, 2}}},
    {0, {{{4, 2, -1}, {4, 2, 1}, {4, 4, 0}, {2, 3, 0}}}, {{-2, -3, 1}, {4, 4, 0}}},
    {0, {{{4, 2, 1}, {4, 2, -1}, {4, 0, 0}, {2, 1, 0}}}, {{-2, 3, -1}, {4, 0, 0}}},
    {0, {{{4, 2, 1}, {4, 2, 3}, {2, 2, 2}, {3, 0, 2}}}, {{3, -2, 1}, {2, 2, 2}}},
    {0, {{{4, 2, 3}, {4, 2, 1}, {2, 2, 2}, {3, 4, 2}}}, {{3, 2, -1}, {2, 2, 2}}},
    {1, {{{0, 0, 0}, {0, 2, 1}, {1, 0, 2}, {2, 1, 0}}}, {{1, 2, 3}, {0, 0, 0}}},
    {1, {{{0, 0, 4}, {0, 2, 3}, {1, 0, 2}, {2, 1, 4}}}, {{1, 2, -3}, {0, 0, 4}}},
    {1, {{{0, 4, 0}, {0, 2, 1}, {1, 4, 2}, {2, 3, 0}}}, {{1, -2, 3}, {0, 4, 0}}},
    {1, {{{0, 4, 4}, {0, 2, 3}, {1, 4, 2}, {2, 3, 4}}}, {{1, -2, -3}, {0, 4, 4}}},
    {1, {{{2, 2, 2}, {2, 1, 0}, {1, 0, 2}, {0, 2, 1}}}, {{-1, -3, -2}, {2, 2, 2}}},
    {1, {{{2, 2, 2}, {2, 1, 0}, {3, 0, 2}, {4, 2, 1}}}, {{1, -3, -2}, {2, 2, 2}}},
    {1, {{{2, 2, 2}, {2, 1, 4}, {1, 0, 2}, {0, 2, 3}}}, {{-1, -3, 2}, {2, 2, 2}}},
    {1, {{{2, 2, 2}, {2, 1, 4}, {3, 0, 2}, {4, 2, 3}}}, {{1, -3, 2}, {2, 2, 2}}},
    {1, {{{2, 2, 2}, {2, 3, 0}, {1, 4, 2}, {0, 2, 1}}}, {{-1, 3, -2}, {2, 2, 2}}},
    {1, {{{2, 2, 2}, {2, 3, 0}, {3, 4, 2}, {4, 2, 1}}}, {{1, 3, -2}, {2, 2, 2}}},
    {1, {{{2, 2, 2}, {2, 3, 4}, {1, 4, 2}, {0, 2, 3}}}, {{-1, 3, 2}, {2, 2, 2}}},
    {1, {{{2, 2, 2}, {2, 3, 4}, {3, 4, 2}, {4, 2, 3}}}, {{1, 3, 2}, {2, 2, 2}}},
    {1, {{{4, 0, 0}, {4, 2, 1}, {3, 0, 2}, {2, 1, 0}}}, {{-1, 2, 3}, {4, 0, 0}}},
    {1, {{{4, 0, 4}, {4, 2, 3}, {3, 0, 2}, {2, 1, 4}}}, {{-1, 2, -3}, {4, 0, 4}}},
    {1, {{{4, 4, 0}, {4, 2, 1}, {3, 4, 2}, {2, 3, 0}}}, {{-1, -2, 3}, {4, 4, 0}}},
    {1, {{{4, 4, 4}, {4, 2, 3}, {3, 4, 2}, {2, 3, 4}}}, {{-1, -2, -3}, {4, 4, 4}}},
    {2, {{{-1, 0, 2}, {1, 0, 2}, {0, 2, 1}, {0, 2, 3}}}, {{1, 2, 3}, {0, 0, 0}}},
    {2, {{{-1, 4, 2}, {1, 4, 2}, {0, 2, 3}, {0, 2, 1}}}, {{1, -2, -3}, {0, 4, 4}}},
    {2, {{{1, 0, 2}, {3, 0, 2}, {2, -1, 0}, {2, 1, 0}}}, {{1, 3, -2}, {2, -2, 2}}},
    {2, {{{1, 0, 2}, {3, 0, 2}, {2, 1, 4}, {2, -1, 4}}}, {{1, -3, 2}, {2, 2, 2}}},
    {2, {{{2, 1, 0}, {2, 3, 0}, {0, 2, -1}, {0, 2, 1}}}, {{-2, 1, 3}, {2, 2, -2}}},
    {2, {{{2, 1, 0}, {2, 3, 0}, {4, 2, 1}, {4, 2, -1}}}, {{2, 1, -3}, {2, 2, 2}}},
}};
inline constexpr std::array<std::array<Ivec, 4>, class_count> reference_tets{
    {cell_tets[0].v, cell_tets[24].v, cell_tets[40].v}};
// The reference tetrahedron's lattice symmetries: vertex i goes to vertex
// to[i], and the symmetry's linear part is `axis` (as in LatticeOp; its
// translation is whatever maps the vertices, unused): class 0 the mirror
// swapping its chain ends; class 1 the three rotations about its A vertex's
// threefold axis; class 2 the 8 symmetries keeping the two chain pairs.  A
// configuration's image under one moves vertex i's sign and warp to to[i],
// the warp direction mapped by the linear part (`transform`).
struct VertexMap {
    std::array<int, 4> to;
    std::array<int, 3> axis;
};
struct ClassSymmetries {
    int count;
    std::array<VertexMap, 8> map;
};
inline constexpr std::array<ClassSymmetries, class_count> symmetries{{
    {2, {{{{0, 1, 2, 3}, {1, 2, 3}}, {{1, 0, 2, 3}, {-1, 2, 3}}}}},
    {3, {{{{0, 1, 2, 3}, {1, 2, 3}}, {{0, 2, 3, 1}, {3, 1, 2}}, {{0, 3, 1, 2}, {2, 3, 1}}}}},
    {8,
     {{{{0, 1, 2, 3}, {1, 2, 3}},
       {{0, 1, 3, 2}, {1, 2, -3}},
       {{1, 0, 2, 3}, {-1, 2, 3}},
       {{1, 0, 3, 2}, {-1, 2, -3}},
       {{2, 3, 0, 1}, {3, -2, 1}},
       {{2, 3, 1, 0}, {-3, -2, 1}},
       {{3, 2, 0, 1}, {3, -2, -1}},
       {{3, 2, 1, 0}, {-3, -2, -1}}}}},
}};
// The site of local vertex i of a class's reference (its warp directions
// index that site's neighbours).
constexpr int reference_site(int cls, int i) {
    return site_of(reference_tets[static_cast<std::size_t>(cls)][static_cast<std::size_t>(i)]);
}
// The class of local edge e of a class's reference.
constexpr EdgeClass local_edge_class(int cls, int e) {
    const auto& r = reference_tets[static_cast<std::size_t>(cls)];
    const auto& te = bcc::tet_edges[static_cast<std::size_t>(e)];
    return edge_class(bcc::sub(r[static_cast<std::size_t>(te[1])], r[static_cast<std::size_t>(te[0])]));
}
// |xr|² of the local edge (x, r) of a class's reference (4, 5 or 6).
constexpr int local_len2(int cls, int x, int r) {
    const auto& t = reference_tets[static_cast<std::size_t>(cls)];
    return norm2(bcc::sub(t[static_cast<std::size_t>(r)], t[static_cast<std::size_t>(x)]));
}

// ---------------------------------------------------------------------------
// The Delaunay face rule (see "The face rule").  u[e] is the cut fraction of
// local edge e from bcc::tet_edges[e][0].

// P_b − P_a on the face (a, b, r) of class cls: > 0 iff a–cut(b, r) is the
// Delaunay diagonal.  Linear in the cut fractions; antisymmetric in a, b.
template <class T>
T face_form(int cls, int a, int b, int r, const std::array<T, 6>& u) {
    using O = ScalarOps<T>;
    const auto power = [&](int x) {
        return O::from_int(local_len2(cls, x, r)) * (O::from_int(1) - bcc::cut_fraction(x, r, u));
    };
    return power(b) - power(a);
}

// |cut(a,r0) cut(b,r1)|² − |cut(a,r1) cut(b,r0)|² of class cls (quadrupled
// coordinates): < 0 iff cut(a,r0)–cut(b,r1) is the shorter diagonal of the
// prism's inside quad.
template <class T>
T inside_form(int cls, int a, int b, int r0, int r1, const std::array<T, 6>& u) {
    return bcc::inside_form_of(reference_tets[static_cast<std::size_t>(cls)], a, b, r0, r1, u);
}

// The rule on one lattice face, from its global data alone: the - sites A, B,
// the + site R, and the cut fractions uA of A–R from A and uB of B–R from B
// (exact or double).  True iff the quad's diagonal is A–cut(B, R), that is
// iff (P_A, A) < (P_B, B) lexicographically.
template <class T>
bool face_takes(const Ivec& A, const Ivec& B, const Ivec& R, const T& uA, const T& uB) {
    using O = ScalarOps<T>;
    const T pa = O::from_int(norm2(bcc::sub(R, A))) * (O::from_int(1) - uA);
    const T pb = O::from_int(norm2(bcc::sub(R, B))) * (O::from_int(1) - uB);
    const int s = decided_sign(pb - pa).value();
    return s > 0 || (s == 0 && A < B);
}

// Resolve the rule in the local frame from the signs (-1, 0, +1) of its
// forms: face_sign[f] that of face_form(a, b, r) on the face without f (a <
// b; ignored where the face holds no quad), tie_a[f] whether a precedes b
// globally (read where face_sign[f] = 0), inside_sign that of inside_form
// (ignored unless n- = 2, n+ = 2).  A prover calls it for every sign and tie
// its enclosures and the local frame admit; the mesher with exact signs and
// the global order (`delaunay_diagonals`).
constexpr bcc::Diagonals resolve_delaunay(const std::array<int, 4>& sign, const std::array<int, 4>& face_sign,
                                          const std::array<bool, 4>& tie_a, int inside_sign) {
    bcc::Diagonals d;
    for (int f = 0; f < 4; ++f) {
        int a = -1, b = -1, r = -1;
        if (!bcc::quad_face(sign, f, a, b, r)) continue;
        const int s = face_sign[static_cast<std::size_t>(f)];
        if (s > 0 || (s == 0 && tie_a[static_cast<std::size_t>(f)])) d.face |= 1u << f;
    }
    int a = -1, b = -1, r0 = -1, r1 = -1;
    if (bcc::inside_quad(sign, a, b, r0, r1))
        d.inside = inside_sign < 0 || (inside_sign == 0 && !bcc::takes(d, a, b, r0));
    return d;
}

// The rule's choices for a background tetrahedron of class cls: post-warp
// signs and cut fractions in the local order, and its vertices' global
// positions (`global`, for ties).  Exact or double scalars only (every sign
// decided).
template <class T>
bcc::Diagonals delaunay_diagonals(int cls, const std::array<int, 4>& sign, const std::array<T, 6>& u,
                                  const std::array<Ivec, 4>& global) {
    std::array<int, 4> fs{};
    std::array<bool, 4> tie{};
    for (int f = 0; f < 4; ++f) {
        int a = -1, b = -1, r = -1;
        if (!bcc::quad_face(sign, f, a, b, r)) continue;
        fs[static_cast<std::size_t>(f)] = decided_sign(face_form(cls, a, b, r, u)).value();
        tie[static_cast<std::size_t>(f)] = global[static_cast<std::size_t>(a)] < global[static_cast<std::size_t>(b)];
    }
    int a = -1, b = -1, r0 = -1, r1 = -1, is = 0;
    if (bcc::inside_quad(sign, a, b, r0, r1)) is = decided_sign(inside_form(cls, a, b, r0, r1, u)).value();
    return resolve_delaunay(sign, fs, tie, is);
}

// ---------------------------------------------------------------------------
// A configuration of the generic tetrahedron in its class's reference frame:
// per vertex its post-warp sign and, for a zero vertex, its warp direction
// (an index into its reference site's `neighbours`) or `stay`.
struct Config {
    int cls = 0;
    std::array<int, 4> sign{};
    std::array<int, 4> warp{stay, stay, stay, stay};
};

// The ten points (quadrupled coordinates): vertex i at ref[i] + t[i] ·
// offset(warp[i]) (t[i] in [0, threshold of that edge at vertex i]; ignored
// for `stay`), cut point 4 + e at ref[i] + u[e] (ref[j] − ref[i]) for local
// edge e = (i, j) (u[e] in [threshold at i, 1 − threshold at j]; meaningful
// only on (-, +) edges).
template <class T>
std::array<Vec<T>, 10> generic_points(const Config& c, const std::array<T, 4>& t, const std::array<T, 6>& u) {
    using O = ScalarOps<T>;
    const auto& ref = reference_tets[static_cast<std::size_t>(c.cls)];
    std::array<Vec<T>, 10> p{};
    for (std::size_t i = 0; i < 4; ++i) {
        const int w = c.warp[i];
        const Ivec d = w == stay ? Ivec{0, 0, 0}
                                 : neighbours[static_cast<std::size_t>(reference_site(c.cls, static_cast<int>(i)))]
                                       .offset[static_cast<std::size_t>(w)];
        for (std::size_t k = 0; k < 3; ++k)
            p[i][k] = d[k] == 0 ? O::from_int(ref[i][k]) : O::from_int(ref[i][k]) + O::from_int(d[k]) * t[i];
    }
    for (std::size_t e = 0; e < 6; ++e) {
        const Ivec& a = ref[static_cast<std::size_t>(bcc::tet_edges[e][0])];
        const Ivec& b = ref[static_cast<std::size_t>(bcc::tet_edges[e][1])];
        for (std::size_t k = 0; k < 3; ++k) {
            const int d = b[k] - a[k];
            p[4 + e][k] = d == 0 ? O::from_int(a[k]) : O::from_int(a[k]) + O::from_int(d) * u[e];
        }
    }
    return p;
}

}  // namespace warpmesh::a15
