// lattice.hpp — the uniform lattice of squares and the per-point arrays the
// pipeline stages exchange.
//
//   lattice.cpp     → lattices over a box (Lattice: levelset.hpp), sampling f at its points
//   signs.cpp       → sign of f at each point
//   cut_points.cpp  → cut edges and their cut points
//   warp.cpp        → which endpoint of each cut edge moves, and where
//   triangulate.cpp → diagonal per square, output triangles, boundary
#pragma once

#include <chrono>
#include <cstdint>
#include <span>
#include <vector>

#include "warpmesh/core/buffer.hpp"
#include "warpmesh/mesh2d/generic_square.hpp"
#include "warpmesh/mesh2d/square_keys.hpp"  // stencil_offsets, off_lattice
#include "warpmesh/levelset/levelset.hpp"
#include "warpmesh/core/mesh.hpp"

namespace warpmesh {

// The lattice of spacing s whose points cover box: x0 = xmin, and as many
// whole squares as fit (at least one).
Lattice lattice_over(const Box& box, double s);

// The lattice of spacing s around a region contained in box, with at least
// one whole square of margin on every side.  Every lattice point on the
// lattice's border is then at distance >= s from the region, so it is the
// endpoint of no cut edge, never warps, and the mesh never reaches the border.
Lattice lattice_around(const Box& box, double s);

// Both throw InputError for a spacing that is not positive and finite or not
// within 1e-100 .. 1e100 (triangle areas would underflow or overflow), more
// than this many squares along an axis (callers bound the total first, e.g.
// the CLI's --max-squares), or coordinates beyond 2^32 spacings from the
// origin, where lattice points would round onto each other.
inline constexpr double max_lattice_squares_per_axis = 4294967296.0;  // 2^32

// f at all points (row-major).  Throws InputError on NaN or infinity.
Buffer<double> sample_values(const LevelSet& f, const Lattice& lattice);

// The InputError both front ends throw for a NaN or infinite value of f at
// lattice point p (an index i + j (nx + 1)), naming the point.
[[noreturn]] void throw_non_finite(const Lattice& lattice, std::int64_t p);

// Seconds since a time point, for the pipelines' phase times.
inline double seconds_since(std::chrono::steady_clock::time_point a) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}

// Signs of f: -1, 0 (exactly on the level set) or +1.
Buffer<std::int8_t> compute_signs(std::span<const double> values);

// A cut edge runs from point p to its neighbour in +x (axis 0) or +y (axis 1);
// its endpoints have strictly opposite signs; the cut point is at parameter u
// in (0, 1) from p.  sign is the sign of f at p (for the warp's tie rule).
struct CutEdge {
    std::int64_t p;
    std::int8_t axis;
    std::int8_t sign;
    double u;
};

// All cut edges, sorted by (p, axis).
std::vector<CutEdge> find_cut_edges(const LevelSet& f, const Lattice& lattice, std::span<const double> values,
                                    std::span<const std::int8_t> signs);

// The one test both front ends (find_cut_edges, tiles.cpp) make: appends the
// edge from point (i, j) to its neighbour along `axis` (0: +x, 1: +y) if their
// signs sp, sq are strictly opposite, with its cut point from the values fp, fq.
inline void append_cut_edge(const LevelSet& f, const Lattice& lattice, std::int64_t i, std::int64_t j, int axis,
                            std::int8_t sp, std::int8_t sq, double fp, double fq, std::vector<CutEdge>& out) {
    if (sp == 0 || sq != -sp) return;
    const Vec2 a = lattice.position(i, j), b = lattice.position(i + (axis == 0), j + (axis == 1));
    out.push_back({lattice.index(i, j), static_cast<std::int8_t>(axis), sp, f.cut_parameter(a, b, fp, fq)});
}

// A warped lattice point: it moved distance t (in units of s, 0 < t <= 1/2)
// along `dir` onto a cut point.
struct WarpedPoint {
    std::int64_t p;
    Warp dir;
    double t;
};

// For every cut edge the endpoint closer to the cut point warps onto it; at a
// tie (u = 1/2 exactly) the endpoint with f < 0 does.  A point that is the
// closer endpoint of several cut edges takes the nearest cut point; equal
// distances are broken in the order +x, -x, +y, -y.  Sorted by p.  The cut
// edges in (p, axis) order are cuts[order[k]], or cuts[k] if order is empty
// (a front end that finds them in another order passes the permutation
// rather than a sorted copy).
std::vector<WarpedPoint> warp_points(const Lattice& lattice, std::span<const CutEdge> cuts,
                                     std::span<const std::uint32_t> order = {});

// The diagonal of a square with at least one warped corner: choose_diagonal
// on the square in the generic frame — exactly what the prover certifies.
// `forced`, if given, is set to whether the separating rule overrode max-min.
// `tie`: the diagonal taken where both are equally good, by the square's
// position (union_jack, generic_square.hpp).  (Squares with no warped corner
// take the tie-break, which is what the rule returns on the unit square.)
// Shared by the uniform and the graded triangulations.
Diagonal warped_square_diagonal(DiagonalRule rule, const std::array<CornerState, 4>& corners,
                                const std::array<double, 4>& t, bool* forced = nullptr, TieBreak tie = TieBreak::ad);

// How such a square is triangulated: one of its diagonals, or (DiagonalRule::
// fan only, on a square whose four corners are inside) the centroid fan of
// generic_square.hpp.  warped_square_diagonal is this with the fan reported as
// AD; the meshers use this one.
enum class SquareSplit : std::uint8_t { ad, bc, fan };
// `metric`: the lattice's (generic_square.hpp, LatticeMetric).
SquareSplit warped_square_split(DiagonalRule rule, const std::array<CornerState, 4>& corners,
                                const std::array<double, 4>& t, bool* forced = nullptr, TieBreak tie = TieBreak::ad,
                                LatticeMetric metric = LatticeMetric::square);

// A finest lattice square i + j nx whose diagonal went through the rule, and
// its output triangles first .. first + count - 1 (count 1 or 2; 4 for a fan).
struct KeyedSquare {
    std::int64_t square;
    std::int64_t first;
    std::int32_t count;
};

// What certification reads of a 2D mesh (certify/certified.hpp: certify_keys),
// recorded by the meshers when asked (KeyOptions::keys): the squares through
// the rule with their output triangles, in the mesher's order, and per square
// what its key is made of — the signs the certificate sees at its 12 stencil
// points (stencil_offsets order; off_lattice for a point outside the
// lattice, which makes the stencil non-flat) and its corners' warps; for a
// junction square (a multi-material square whose corners carry 3 or 4
// materials) signs[0..3] are its corners' material classes (junction_letters:
// 0..3) and the square is keyed by its junction key.  The metric is the
// lattice's the squares were meshed in (rhombic: lattice coordinates, before
// the map by P).  A few entries per boundary square, nothing per triangle.
struct KeyedStencil {
    std::array<std::int8_t, 12> signs{};
    std::array<Warp, 4> warps{};  // corners A, B, C, D (Warp::stay: not warped)
    bool junction = false;
};
struct SquareKeys {
    std::vector<KeyedSquare> squares;
    std::vector<KeyedStencil> stencils;  // one per square
    LatticeMetric metric = LatticeMetric::square;
    double seconds = 0;  // gathering the stencils (part of the report's "certify" phase)
};

// What a 2D mesher records besides the mesh, for the certification that
// follows it (the pipeline's, pipeline/mesh2d.cpp): `keys`, its SquareKeys;
// `check_invariant` (graded meshers), the quadtree's invariant that the
// certificates rest on, checked on the leaves (graded/quadtree.hpp,
// check_critical_squares_finest; std::logic_error if violated) — the
// pipeline asks for it with --verify.
struct KeyOptions {
    bool keys = false;
    bool check_invariant = false;
};

struct TriangulateStats {
    std::int64_t warped_squares = 0;
    // Squares that emit triangles and whose diagonal the separating rule took
    // against max-min (a square that emits nothing has no diagonal in the mesh).
    std::int64_t forced_diagonals = 0;
    // If set (input), filled with the squares "through the rule" (a warped or
    // zero-valued corner) that emit triangles, in increasing square order, with
    // their output triangles: a few per boundary square, nothing per triangle.
    std::vector<KeyedSquare>* keyed_squares = nullptr;
};

// Build the output mesh: per square, the diagonal by `rule`; the triangles
// whose three corners are inside (sign <= 0 or warped); vertices compacted in
// point order; boundary edges oriented with the region on their left.
// `metric`: the diagonal rule's angles (LatticeMetric::rhombic: the mesh is
// in lattice coordinates, its vertices to be mapped by rhombic_map, rhombic.hpp).
Mesh triangulate(const LevelSet& f, const Lattice& lattice, std::span<const std::int8_t> signs,
                 std::span<const WarpedPoint> warped, DiagonalRule rule, TriangulateStats* stats = nullptr,
                 LatticeMetric metric = LatticeMetric::square);

}  // namespace warpmesh
