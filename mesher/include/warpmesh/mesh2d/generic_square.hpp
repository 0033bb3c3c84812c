// generic_square.hpp — the generic square and the diagonal rules, written once.
//
// This header is the single source of truth for the geometry that the angle
// proof is about.  The mesher instantiates it with `double`; the prover
// instantiates it with outward-rounded intervals and certifies, box by box,
// exactly what this code decides.  Nothing here may depend on how the scalar
// is represented beyond the few operations of `ScalarOps<T>`
// (warpmesh/numerics/scalar.hpp).
//
// The generic square is the unit square with corners
//
//        C=(0,1) ------- D=(1,1)
//          |               |
//          |               |
//        A=(0,0) ------- B=(1,0)
//
// Corner c sits at (c & 1, c >> 1).  Each corner either stays, or has been
// warped onto a cut point: it slid a distance t in [0, 1/2] (in units of the
// lattice spacing) along +x, -x, +y or -y.  Two of those directions run along
// the square's own edges ("inward"), the other two leave the square towards a
// lattice neighbour ("outward").  The two diagonals are AD and BC; each splits
// the square into two triangles, listed counter-clockwise for the unwarped
// square:
//
//        AD:  (A, B, D) and (A, D, C)
//        BC:  (A, B, C) and (B, D, C)
//
// Angles are never computed.  For a triangle (p0, p1, p2) the angle at p_i with
// edge vectors u, v satisfies
//
//        cot(angle_i) = (u . v) / (u x v),
//
// and u x v is the same number for all three vertices of a triangle: twice its
// signed area.  So a triangle's smallest angle has the largest cotangent, and
// its *quality* `max_i (u_i . v_i) / (2 area)` orders triangles exactly as the
// minimum angle does (reversed) — a rational function of the coordinates, so
// the prover can enclose it and the checker can evaluate it exactly.
#pragma once

#include <array>
#include <cstdint>

#include "warpmesh/numerics/scalar.hpp"  // Truth, ScalarOps

#include "warpmesh/core/names.hpp"

namespace warpmesh {

// ---------------------------------------------------------------------------
// Corners, warp states, diagonals.
enum Corner : int { A = 0, B = 1, C = 2, D = 3 };

enum class Warp : std::uint8_t { stay = 0, px = 1, mx = 2, py = 3, my = 4 };
inline constexpr int warp_count = 5;

constexpr int warp_dx(Warp w) { return w == Warp::px ? 1 : w == Warp::mx ? -1 : 0; }
constexpr int warp_dy(Warp w) { return w == Warp::py ? 1 : w == Warp::my ? -1 : 0; }

// True when sliding corner c along w runs along an edge of the square
// (towards another corner); false for `stay` and for outward slides.
constexpr bool warp_is_inward(int c, Warp w) {
    const int cx = c & 1, cy = c >> 1;
    return (warp_dx(w) != 0 && cx + warp_dx(w) == 1 - cx) ||
           (warp_dy(w) != 0 && cy + warp_dy(w) == 1 - cy);
}

enum class Diagonal : std::uint8_t { AD = 0, BC = 1 };
// maxmin and separating: one diagonal per square.  fan: the separating rule,
// except that a square whose four corners are all inside (corner_inside) and
// in which neither diagonal reaches the minimum angle atan(1/3) — precisely:
// no diagonal is valid with worst cotangent <= fan_threshold_cot — is split
// into four triangles around the centroid of its corners (choose_diagonal).
enum class DiagonalRule : std::uint8_t { maxmin = 0, separating = 1, fan = 2 };
// Their names (reports, certificates, --diagonal, Python's rule=), the
// default first; parse with value_of(diagonal_rule_names, name).
inline constexpr std::array<Named<DiagonalRule>, 3> diagonal_rule_names{
    {{DiagonalRule::separating, "separating"}, {DiagonalRule::maxmin, "maxmin"}, {DiagonalRule::fan, "fan"}}};

// The two triangles of each diagonal, counter-clockwise on the unwarped square.
inline constexpr std::array<std::array<int, 3>, 2> diagonal_triangles(Diagonal d) {
    if (d == Diagonal::AD) return {{{A, B, D}, {A, D, C}}};
    return {{{A, B, C}, {B, D, C}}};
}

template <class T>
struct Point {
    T x, y;
};

// Position of corner c of the unit square after sliding t along w.
template <class T>
Point<T> warped_corner(int c, Warp w, const T& t) {
    using O = ScalarOps<T>;
    Point<T> p{O::from_int(c & 1), O::from_int(c >> 1)};
    if (warp_dx(w) != 0) p.x = p.x + O::from_int(warp_dx(w)) * t;
    if (warp_dy(w) != 0) p.y = p.y + O::from_int(warp_dy(w)) * t;
    return p;
}

// A corner counts as inside the region for output when its value is <= 0:
// a warped corner lies on the level set, so it counts as 0.
constexpr bool corner_inside(int sign, Warp w) { return w != Warp::stay || sign <= 0; }

// ---------------------------------------------------------------------------
// The centroid fan (DiagonalRule::fan).  Its centre is M = (A + B + C + D) / 4,
// joined to the four corners: the triangles (A, B, M), (B, D, M), (D, C, M),
// (C, A, M), counter-clockwise on the unwarped square.  Since the angle forms
// are homogeneous (dot and cross both scale by k^2 when every point is scaled
// by k), the fan's forms are computed on the points scaled by 4 —
// fan_points() = {4A, 4B, 4C, 4D, A + B + C + D}, index 4 the centre — which
// needs no division, so intervals, dual numbers and rationals evaluate it as
// they evaluate the corners.  The mesher places the vertex at the centroid
// itself.
inline constexpr int fan_centre = 4;
inline constexpr std::array<std::array<int, 3>, 4> fan_triangles{
    {{A, B, fan_centre}, {B, D, fan_centre}, {D, C, fan_centre}, {C, A, fan_centre}}};

template <class T>
std::array<Point<T>, 5> fan_points(const std::array<Point<T>, 4>& p) {
    const T four = ScalarOps<T>::from_int(4);
    return {Point<T>{four * p[A].x, four * p[A].y}, Point<T>{four * p[B].x, four * p[B].y},
            Point<T>{four * p[C].x, four * p[C].y}, Point<T>{four * p[D].x, four * p[D].y},
            Point<T>{p[A].x + p[B].x + p[C].x + p[D].x, p[A].y + p[B].y + p[C].y + p[D].y}};
}

// The fan rule's threshold H0 = 3 + 2^-20 on a diagonal's worst cotangent:
// a diagonal with q <= H0 keeps every angle >= arccot(H0), 5.5e-6 deg below
// atan(1/3) = 18.4349488 deg (the slack lets the prover certify squares whose
// best diagonal is exactly atan(1/3), with the double-agreement margins of
// proofs/README.md).  Exactly representable in binary floating point.
template <class T>
T fan_threshold_cot() {
    using O = ScalarOps<T>;
    return O::from_int(3) + O::from_int(1) / O::from_int(1 << 20);
}

// ---------------------------------------------------------------------------
// Angle forms of one triangle.  dot[i] = u_i . v_i at vertex i, cross = u x v
// (equal at the three vertices).  The angle at vertex i is >= theta iff
// cross > 0 and dot[i] <= cot(theta) * cross; it is <= phi (phi > 90 deg) iff
// dot[i] >= cot(phi) * cross.  Only additions and multiplications are used, so
// with exact inputs these forms are exact.
template <class T>
struct TriangleForms {
    std::array<T, 3> dot;
    T cross;
};

// The lattice's metric: which physical lattice the generic square stands for.
// `square`: the square lattice, the generic square is the physical one
// (proofs/*.cert).  `rhombic` (its own certificates, proofs/rhombic_*.cert):
// the 60-degree rhombic lattice, the square lattice under the affine map
// P(x, y) = (x + y/2, (sqrt 3 / 2) y), whose unwarped squares are rhombi
// with a short diagonal BC that splits them into equilateral triangles.  P
// maps lattice edges to edges of the same length, so everything but the
// angles is computed in lattice coordinates unchanged; the angles are those
// of the metric G = [[1, 1/2], [1/2, 1]], u .G v = ux vx + uy vy + (ux vy + uy vx)/2,
// whose cross product is (sqrt 3 / 2)(ux vy - uy vx).  The forms below are
// scaled to stay polynomial with integer coefficients:
//
//        dot = 2 (u .G v),   cross = ux vy - uy vx,   dot / cross = sqrt(3) cot(angle),
//
// a common factor sqrt 3 for every angle, so comparisons of dot / cross
// (the max-min rule) are those of the physical cotangents; a bound on an angle
// is a bound dot <= sqrt(3) cot(theta) cross, with a rational outside
// sqrt(3) cot(theta).  The fan rule's threshold is in square-lattice
// cotangents: the fan is not defined on the rhombic metric (refused by the
// pipeline).
enum class LatticeMetric : std::uint8_t { square = 0, rhombic = 1 };
// Their names (certificates' metric line, --lattice, Python's lattice=).
inline constexpr std::array<Named<LatticeMetric>, 2> lattice_metric_names{
    {{LatticeMetric::square, "square"}, {LatticeMetric::rhombic, "rhombic"}}};

template <class T>
TriangleForms<T> triangle_forms(const Point<T>& p0, const Point<T>& p1, const Point<T>& p2,
                                LatticeMetric metric = LatticeMetric::square) {
    const std::array<Point<T>, 3> p{p0, p1, p2};
    TriangleForms<T> f{};
    for (int i = 0; i < 3; ++i) {
        const Point<T>& o = p[i];
        const Point<T>& q = p[(i + 1) % 3];
        const Point<T>& r = p[(i + 2) % 3];
        const T ux = q.x - o.x, uy = q.y - o.y, vx = r.x - o.x, vy = r.y - o.y;
        if (metric == LatticeMetric::square) {
            f.dot[i] = ux * vx + uy * vy;
        } else {
            const T e = ux * vx + uy * vy;  // doubled by an addition: no constant, any scalar type
            f.dot[i] = e + e + (ux * vy + uy * vx);
        }
        if (i == 0) f.cross = ux * vy - uy * vx;
    }
    return f;
}

// Quality of a diagonal: whether both of its triangles are positively
// oriented, and the largest cotangent among their six angles, i.e. the
// cotangent of the smallest angle.  `worst_cot` is meaningful only where
// `valid` is not `no` (an interval enclosure, where `valid` is `maybe`, may be
// unbounded).
template <class T>
struct DiagonalQuality {
    Truth valid;
    T worst_cot;
};

template <class T>
DiagonalQuality<T> diagonal_quality(const std::array<Point<T>, 4>& p, Diagonal d,
                                    LatticeMetric metric = LatticeMetric::square) {
    using O = ScalarOps<T>;
    DiagonalQuality<T> q{Truth::yes, O::from_int(0)};
    bool first = true;
    for (const auto& tri : diagonal_triangles(d)) {
        const TriangleForms<T> f = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]], metric);
        const Truth ok = O::positive(f.cross);
        q.valid = q.valid && ok;
        if (ok == Truth::no) continue;  // an inverted triangle: never wins
        const T worst = O::max(O::max(f.dot[0], f.dot[1]), f.dot[2]) / f.cross;
        q.worst_cot = first ? worst : O::max(q.worst_cot, worst);
        first = false;
    }
    return q;
}

// ---------------------------------------------------------------------------
// The separating rule's combinatorial test, for corners that carry a *phase*:
// the sign of f (two materials: inside, outside) or a material (multi-material
// meshes).  `phase(c)` is -1 for a corner that does not take part — it warped,
// or (signs) it is zero-valued — else the corner's phase.  If two opposite
// corners both stay with different phases, every path between them along the
// square's edges crosses an edge whose endpoints differ, i.e. a cut edge; its
// closer endpoint warped, and the two staying ends did not, so each of the
// other two corners warped (or is zero-valued): both lie on the interface.
// Taking the diagonal through them keeps the interface on mesh edges.  At most
// one pair can qualify: if A, D both stay with different phases, C warped (or
// is zero), so B, C do not both take part.
//
// Consequence (multi-material meshes): no triangle of the chosen diagonal has
// two staying corners of different materials.  Two of a triangle's corners are
// either ends of a square side — if both stayed with different materials the
// side would be cut and one of them would have warped — or the ends of the
// chosen diagonal — which the rule never chooses between two staying corners
// of different materials.
template <class Phase>
constexpr bool separating_pair(Phase&& phase, Diagonal& forced) {
    const int a = phase(A), b = phase(B), c = phase(C), d = phase(D);
    if (a >= 0 && d >= 0 && a != d) {
        forced = Diagonal::BC;
        return true;
    }
    if (b >= 0 && c >= 0 && b != c) {
        forced = Diagonal::AD;
        return true;
    }
    return false;
}

// Signs (two materials): a corner takes part when it stays with a non-zero
// sign; two such corners differ exactly when their signs are opposite.
struct CornerState {
    std::int8_t sign;  // sign of f at the lattice point: -1, 0, +1
    Warp warp;
};

constexpr bool stays_signed(const CornerState& s) { return s.warp == Warp::stay && s.sign != 0; }

// Returns the forced diagonal in `forced` and true, or false if no pair qualifies.
constexpr bool separating_diagonal(const std::array<CornerState, 4>& s, Diagonal& forced) {
    return separating_pair([&](int c) { return stays_signed(s[static_cast<std::size_t>(c)]) ? int{s[static_cast<std::size_t>(c)].sign > 0} : -1; },
                           forced);
}

// Materials (multi-material meshes): every lattice point has one material (no
// zero-valued points); a corner takes part when it stays.  On a square whose
// corners carry two materials this is the rule above for the signs obtained by
// mapping one material to '-' and the other to '+' (either way round: the
// test only asks whether two phases differ).
struct MaterialCorner {
    std::uint16_t material;
    Warp warp;
};

constexpr bool separating_diagonal(const std::array<MaterialCorner, 4>& s, Diagonal& forced) {
    return separating_pair(
        [&](int c) { return s[static_cast<std::size_t>(c)].warp == Warp::stay ? int{s[static_cast<std::size_t>(c)].material} : -1; },
        forced);
}

// ---------------------------------------------------------------------------
// The diagonal rule.  Max-min: take the diagonal whose smaller angle is larger;
// an inverted or degenerate triangle never wins; if both diagonals are equally
// good (in particular on the unwarped square) take the *tie-break* diagonal,
// which the mesher chooses by the square's position (`TieBreak`: AD or BC, a
// union-jack pattern, so that the unwarped interior has no preferred
// direction); if both are invalid, take AD.  In three-valued form:
//
//        tie-break AD:  BC is taken  <=>  valid(BC) and (not valid(AD) or q(BC) <  q(AD)),
//        tie-break BC:  BC is taken  <=>  valid(BC) and (not valid(AD) or q(BC) <= q(AD)),
//
// where q is the worst cotangent (smaller q = larger minimum angle).  The
// prover asks with `TieBreak::either`: BC is taken where both tie-breaks take
// it, not taken where neither does, and undecided (`maybe`) where they differ,
// i.e. wherever an exact tie is possible on the box — so every certified
// decision holds for both tie-breaks, and an undecided box is bounded on both
// diagonals (proofs/README.md, "Ties").
//
// `Choice` says which diagonals the rule may take.  With exact scalars exactly
// one flag is set.  With intervals both may be set: the rule is undecided on
// the box and the prover must bound both diagonals there.
enum class TieBreak : std::uint8_t { ad = 0, bc = 1, either = 2 };

// The union-jack pattern: the tie-break of lattice square (i, j) (its lower-left
// corner), AD where i + j is even, BC where it is odd.  Every other lattice
// point then joins its eight neighbours and the rest their four: the
// diagonals alternate, so no direction is preferred.  One definition for the
// uniform, graded and multi-material meshers (graded coarse leaves use their
// position at their level).
constexpr TieBreak union_jack(std::int64_t i, std::int64_t j) { return ((i + j) & 1) ? TieBreak::bc : TieBreak::ad; }

// The diagonal the rule takes on an unwarped square with no zero-valued
// corner (no separating pair): the tie-break on the square lattice (both
// diagonals give 45-degree right triangles); on the rhombic lattice always the
// short diagonal BC (equilateral triangles, against 30-30-120 for AD), which
// is what choose_diagonal returns there.  The meshers' fast path.
constexpr Diagonal unwarped_diagonal(LatticeMetric metric, TieBreak tie) {
    return metric == LatticeMetric::rhombic || tie == TieBreak::bc ? Diagonal::BC : Diagonal::AD;
}

struct Choice {
    bool ad = false;
    bool bc = false;
    bool fan = false;  // DiagonalRule::fan only: the centroid fan (fan_triangles)
};

// `Corners` is std::array<CornerState, 4> (the certified two-material rule)
// or std::array<MaterialCorner, 4> (multi-material meshes): the same rule, the
// separating test reading signs or materials (separating_diagonal above).
//
// The fan rule: the separating rule's forced diagonal if a pair qualifies
// (then some corner stays outside, so the square is not all inside); else, on
// a square whose four corners are inside,
//
//        the fan is taken  <=>  not (some diagonal is valid with q <= H0),
//
// H0 = fan_threshold_cot; otherwise the max-min diagonal.  Where a diagonal
// qualifies, the max-min one qualifies too (it is valid and at least as good),
// so the rule never takes a diagonal with an angle below arccot(H0) when the
// fan is available.  The fan is only for squares whose four corners are
// inside: all its triangles are emitted, so its centre is never a boundary
// vertex and the square's sides are covered exactly as by a diagonal — the
// neighbours see the same four corners and the same sides (conforming).
inline bool all_inside(const std::array<CornerState, 4>& s) {
    for (const CornerState& c : s)
        if (!corner_inside(c.sign, c.warp)) return false;
    return true;
}
// Multi-material squares (materials.hpp): every triangle is emitted (each
// takes a material), and "inside" is relative to the square: the fan is
// available when the corners that stay share one material (or none stays).
// Then all four fan triangles take that material (or, none staying, the
// material at the centre), so no triangle has two staying corners of
// different materials and the centre is never on an interface.  Otherwise
// two staying corners differ; they are opposite (adjacent ones would bound a
// cut side with no warped end), so the separating test forces a diagonal
// first.  On a square with one or two materials this is the sign test above
// with the staying corners' material as '-' (the mesher's key mapping), so
// sign keys and junction keys see the same rule.
inline bool all_inside(const std::array<MaterialCorner, 4>& s) {
    int m = -1;
    for (const MaterialCorner& c : s) {
        if (c.warp != Warp::stay) continue;
        if (m >= 0 && m != c.material) return false;
        m = c.material;
    }
    return true;
}

// `metric` (LatticeMetric above): the angles compared by max-min; the
// separating test is combinatorial and the same on both lattices.
template <class T, class Corners>
Choice choose_diagonal(DiagonalRule rule, const std::array<Point<T>, 4>& p, const Corners& s, TieBreak tie = TieBreak::ad,
                       LatticeMetric metric = LatticeMetric::square) {
    if (rule == DiagonalRule::separating || rule == DiagonalRule::fan) {
        Diagonal forced{};
        if (separating_diagonal(s, forced)) return Choice{forced == Diagonal::AD, forced == Diagonal::BC};
    }
    const DiagonalQuality<T> ad = diagonal_quality(p, Diagonal::AD, metric);
    const DiagonalQuality<T> bc = diagonal_quality(p, Diagonal::BC, metric);
    // "q(BC) < q(AD)" (tie-break AD) or "q(BC) <= q(AD)" (tie-break BC),
    // evaluated only where it matters; TieBreak::either: decided only where
    // both agree.
    Truth better = Truth::no;
    if (bc.valid != Truth::no && ad.valid != Truth::no) {
        const Truth strict = tie == TieBreak::bc ? Truth::no : ScalarOps<T>::less(bc.worst_cot, ad.worst_cot);
        const Truth weak = tie == TieBreak::ad ? Truth::no : !ScalarOps<T>::less(ad.worst_cot, bc.worst_cot);
        better = tie == TieBreak::ad ? strict
                 : tie == TieBreak::bc ? weak
                 : strict == Truth::yes ? Truth::yes
                 : weak == Truth::no ? Truth::no
                                     : Truth::maybe;
    }
    const Truth take_bc = bc.valid && (!ad.valid || better);
    Choice ch{take_bc != Truth::yes, take_bc != Truth::no};
    if (rule == DiagonalRule::fan && all_inside(s)) {
        const T h = fan_threshold_cot<T>();
        // "q <= H0" is "not (H0 < q)"; evaluated only where the diagonal may be valid.
        const Truth ok_ad = ad.valid == Truth::no ? Truth::no : ad.valid && !ScalarOps<T>::less(h, ad.worst_cot);
        const Truth ok_bc = bc.valid == Truth::no ? Truth::no : bc.valid && !ScalarOps<T>::less(h, bc.worst_cot);
        const Truth take_diagonal = ok_ad || ok_bc;
        if (take_diagonal == Truth::no) return Choice{false, false, true};
        ch.fan = take_diagonal == Truth::maybe;
    }
    return ch;
}

// The corner positions of a square of the mesher in the unit square's frame.
template <class T>
std::array<Point<T>, 4> generic_positions(const std::array<Warp, 4>& w, const std::array<T, 4>& t) {
    return {warped_corner(A, w[A], t[A]), warped_corner(B, w[B], t[B]), warped_corner(C, w[C], t[C]),
            warped_corner(D, w[D], t[D])};
}

}  // namespace warpmesh
