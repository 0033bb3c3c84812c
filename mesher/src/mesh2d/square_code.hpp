// square_code.hpp — the one-byte code of a finest lattice square, shared by
// the uniform (triangulate.cpp) and graded (triangulate_graded.cpp)
// triangulations, so that both emit, and find the boundary of, a square in
// exactly the same way.  Private to mesher/src.
//
// Bit 0 = the chosen diagonal's first triangle is emitted, bit 1 = its second,
// bit 2 = the diagonal is BC (else AD), bit 3 = the square goes through the
// rule (a warped or zero-valued corner: the square has a key in the
// certificates) — asked only where the diagonal matters (diagonal_matters
// below; a square that emits nothing keeps bit 2 clear).  Corners A, B, C, D
// and diagonal_triangles are from generic_square.hpp.
#pragma once

#include <array>
#include <cstdint>
#include <numeric>
#include <span>
#include <stdexcept>
#include <vector>

#include "warpmesh/mesh2d/generic_square.hpp"
#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh::square_code {

constexpr std::uint8_t tri0_bit = 1, tri1_bit = 2, bc_bit = 4, rule_bit = 8;
// Bit 5: the square is the centroid fan (DiagonalRule::fan; its four corners
// are inside, so both bits 0 and 1 are set too and it covers its four sides
// as a diagonal's two triangles do; it emits 4 triangles and one centre
// vertex).  Bit 4 is the graded triangulation's interior_bit.
constexpr std::uint8_t fan_bit = 32;

// The position of a fan's centre vertex: the centroid of its (warped) corner
// positions x[A], x[B], x[C], x[D], summed in that order — one expression for
// the uniform and graded triangulations, so that their centres agree to the bit.
inline Vec2 fan_centre_position(const std::array<Vec2, 4>& x) {
    Vec2 m{0, 0};
    for (const Vec2& v : x) m.x += v.x, m.y += v.y;
    return {0.25 * m.x, 0.25 * m.y};
}

// Corners of triangle k (0 or 1) of the code's diagonal.
constexpr std::array<int, 3> triangle_of(std::uint8_t code, int k) {
    return diagonal_triangles((code & bc_bit) ? Diagonal::BC : Diagonal::AD)[static_cast<std::size_t>(k)];
}

// Which triangles a square emits, given its diagonal (bc_bit or 0) and the
// mask of its inside corners (bit c = corner c): emitted[diagonal][mask].
constexpr std::array<std::array<std::uint8_t, 16>, 2> emitted = [] {
    std::array<std::array<std::uint8_t, 16>, 2> e{};
    for (int d = 0; d < 2; ++d)
        for (int mask = 0; mask < 16; ++mask)
            for (int k = 0; k < 2; ++k) {
                bool all = true;
                for (int v : triangle_of(static_cast<std::uint8_t>(d ? bc_bit : 0), k)) all = all && ((mask >> v) & 1);
                if (all) e[d][mask] |= static_cast<std::uint8_t>(1 << k);
            }
    return e;
}();

// Whether the diagonal changes what a square with these inside corners emits.
// Only with three or four inside corners: with two or fewer, no triangle of
// either diagonal has three inside corners, and the square emits nothing
// whichever diagonal it takes.  The meshers ask the rule only where it
// matters (a fifth to a half of the squares with a warped corner are on the
// outer side of the boundary and emit nothing).
constexpr bool diagonal_matters(int inside_mask) {
    return (emitted[0][static_cast<std::size_t>(inside_mask)] | emitted[1][static_cast<std::size_t>(inside_mask)]) != 0;
}

// bc_bit if the rule takes BC on the square whose corners A, B, C, D have these
// signs and warps — record(q): corner q's warp record, null if it stays — as
// the generic square the prover certifies (warped_square_split), with the
// square's tie-break `tie` (union_jack); fan_bit if it takes the centroid fan;
// else 0.
template <class Record>
std::uint8_t rule_diagonal(DiagonalRule rule, const std::array<std::int8_t, 4>& sign, Record&& record, bool* forced,
                           TieBreak tie, LatticeMetric metric = LatticeMetric::square) {
    std::array<CornerState, 4> cs{};
    std::array<double, 4> t{};
    for (std::size_t q = 0; q < 4; ++q) {
        cs[q].sign = sign[q];
        if (const WarpedPoint* w = record(static_cast<int>(q))) cs[q].warp = w->dir, t[q] = w->t;
    }
    const SquareSplit s = warped_square_split(rule, cs, t, forced, tie, metric);
    return s == SquareSplit::bc ? bc_bit : s == SquareSplit::fan ? fan_bit : 0;
}

// Whether the emitted triangles of a square with this code use corner c, as a
// table: bit c of corner_mask[code].
constexpr std::array<std::uint8_t, 8> corner_mask = [] {
    std::array<std::uint8_t, 8> m{};
    for (int code = 0; code < 8; ++code)
        for (int k = 0; k < 2; ++k)
            if (code & (1 << k))
                for (int v : triangle_of(static_cast<std::uint8_t>(code), k)) m[code] |= static_cast<std::uint8_t>(1 << v);
    return m;
}();
constexpr bool uses_corner(std::uint8_t code, int c) { return (corner_mask[code & 7] >> c) & 1; }

// Sides of a square: bottom A→B, right B→D, top D→C, left C→A (counter-
// clockwise, the direction each has inside its triangle), and which triangle
// (0 or 1) of each diagonal holds the side.
struct Side {
    int from, to;
    int tri_ad, tri_bc;
};
constexpr std::array<Side, 4> sides{{{A, B, 0, 0}, {B, D, 0, 1}, {D, C, 1, 1}, {C, A, 1, 0}}};

// Whether a square with this code covers side `side` (the triangle holding it
// is emitted).
constexpr bool covers(std::uint8_t code, int side) {
    const Side& s = sides[static_cast<std::size_t>(side)];
    return (code >> ((code & bc_bit) ? s.tri_bc : s.tri_ad)) & 1;
}

// Pass 2 of the uniform triangulations (triangulate.cpp, the multi-material
// mesh_materials.cpp): compact vertex ids.  A point is a vertex iff
// candidate(p) and one of its (up to four) squares emits a triangle that uses
// it (the point's corner role in square (i - di, j - dj) is di + 2 dj).
// Fills vid (the vertex id, or -1) and mesh.vertices (position(p, i, j)) in
// point order, and sizes mesh.triangles for ntris triangles.  Throws
// std::length_error beyond 32-bit indices.
template <class Candidate, class Position>
void compact_vertices(const Lattice& lattice, std::span<const std::uint8_t> code, std::int64_t ntris,
                      Candidate&& candidate, Position&& position, Buffer<std::int32_t>& vid, Mesh& mesh) {
    const std::int64_t nx = lattice.nx, ny = lattice.ny, nxp = lattice.points_x();
    auto square_code = [&](std::int64_t i, std::int64_t j) -> std::uint8_t {
        return (i < 0 || j < 0 || i >= nx || j >= ny) ? 0 : code[static_cast<std::size_t>(i + j * nx)];
    };
    vid.resize(static_cast<std::size_t>(lattice.point_count()));  // every element written: 0 (used) or -1 just below
    std::vector<std::int64_t> row_verts(static_cast<std::size_t>(ny) + 2, 0);
#pragma omp parallel for schedule(static)
    for (std::int64_t j = 0; j <= ny; ++j) {
        std::int64_t count = 0;
        for (std::int64_t i = 0; i < nxp; ++i) {
            const bool used = candidate(lattice.index(i, j)) &&
                              (uses_corner(square_code(i, j), A) || uses_corner(square_code(i - 1, j), B) ||
                               uses_corner(square_code(i, j - 1), C) || uses_corner(square_code(i - 1, j - 1), D));
            vid[static_cast<std::size_t>(lattice.index(i, j))] = used ? 0 : -1;
            count += used;
        }
        row_verts[static_cast<std::size_t>(j) + 1] = count;
    }
    std::partial_sum(row_verts.begin(), row_verts.end(), row_verts.begin());
    const std::int64_t nverts = row_verts.back();
    if (nverts > INT32_MAX || ntris > INT32_MAX)
        throw std::length_error("mesh too large for 32-bit vertex and triangle indices");
    mesh.vertices.resize(static_cast<std::size_t>(nverts));  // written by the loop below, one per used point
    mesh.triangles.resize(static_cast<std::size_t>(ntris));  // written by the caller's pass 3
#pragma omp parallel for schedule(static)
    for (std::int64_t j = 0; j <= ny; ++j) {
        std::int64_t next = row_verts[static_cast<std::size_t>(j)];
        for (std::int64_t i = 0; i < nxp; ++i) {
            const std::int64_t p = lattice.index(i, j);
            if (vid[static_cast<std::size_t>(p)] < 0) continue;
            vid[static_cast<std::size_t>(p)] = static_cast<std::int32_t>(next);
            mesh.vertices[static_cast<std::size_t>(next++)] = position(p, i, j);
        }
    }
}

// The square across each side (bottom, right, top, left) of square (i, j):
// (i + side_step[side][0], j + side_step[side][1]); it sees the side as its
// side (side + 2) % 4.
constexpr std::array<std::array<int, 2>, 4> side_step{{{0, -1}, {1, 0}, {0, 1}, {-1, 0}}};

// The boundary edges of a square with code c, as edge(from, to, tag) from
// corner `from` to corner `to` (A, B, C, D), oriented with the square's
// triangles on their left.  A side the square covers is a boundary edge when
// it lies on the lattice's outer border (on_border(side): tag
// boundary_domain) or the square across it does not cover it (across(side):
// that square's code, asked only for covered sides off the border; tag
// boundary_level_set).  The diagonal is a boundary edge when exactly one of
// the square's two triangles is emitted.  Since a side's two squares see it
// in opposite directions, each boundary edge is found once, by the square
// that covers it.
template <class OnBorder, class Across, class Edge>
void square_boundary_edges(std::uint8_t c, OnBorder&& on_border, Across&& across, Edge&& edge) {
    for (int sd = 0; sd < 4; ++sd) {
        if (!covers(c, sd)) continue;
        const Side& s = sides[static_cast<std::size_t>(sd)];
        if (on_border(sd))
            edge(s.from, s.to, boundary_domain);
        else if (!covers(across(sd), (sd + 2) % 4))  // the opposite side, seen from across
            edge(s.from, s.to, boundary_level_set);
    }
    if (((c & tri0_bit) != 0) != ((c & tri1_bit) != 0)) {
        // The diagonal's direction inside the emitted triangle:
        // ABD: D→A, ADC: A→D, ABC: B→C, BDC: C→B.
        const bool bc = c & bc_bit, first = c & tri0_bit;
        if (!bc) first ? edge(D, A, boundary_level_set) : edge(A, D, boundary_level_set);
        else first ? edge(B, C, boundary_level_set) : edge(C, B, boundary_level_set);
    }
}

}  // namespace warpmesh::square_code
