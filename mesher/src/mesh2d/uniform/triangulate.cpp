// triangulate.cpp — stage 5: one diagonal per square, the output triangles,
// compacted vertices and the boundary.
//
// Each square emits the triangles of its chosen diagonal whose three corners
// are inside (sign <= 0, or warped: a warped point lies on f = 0); under
// DiagonalRule::fan a square whose four corners are inside may instead emit
// the four triangles of its centroid fan, with a new vertex at the centroid
// (numbered after the lattice vertices, in square order).  A square
// with no warped and no zero-valued corner is the unit square in the generic
// frame with no separating pair on the level set, where both diagonals tie at
// 45 degrees and the rule takes the square's tie-break — the union-jack
// pattern, union_jack(i, j): AD where i + j is even, BC where it is odd, so the
// interior has no preferred direction; the fast path below takes it without
// evaluating the rule, which is exactly what choose_diagonal returns there
// (the unit square's corners are exact in floating point).  On the
// rhombic lattice (LatticeMetric::rhombic) the unwarped square
// is a rhombus and the rule takes its short diagonal BC everywhere
// (unwarped_diagonal).  Every other square
// — a warped corner, or a zero-valued one, which can make the separating rule
// force BC on an unwarped square — is handed, in the generic frame, to the
// same choose_diagonal that the prover certifies.
//
// Topology comes from the lattice alone: every triangle edge is a lattice edge
// or a square's diagonal, so two squares that share a side share its two
// endpoints and the mesh is conforming by construction.  Its geometric
// validity — every triangle counter-clockwise — is what the prover's
// orientation theorem certifies for every generic square.
//
// The work is four passes, each parallel over rows and each deterministic:
//   1. a code per square: its diagonal and which of its triangles it emits;
//   2. per point, whether an emitted triangle uses it → compact vertex ids;
//   3. the triangles, at row offsets from a prefix sum;
//   4. the boundary: edges covered by exactly one emitted triangle.
#include <algorithm>
#include <numeric>

#include "warpmesh/mesh2d/lattice.hpp"
#include "mesh2d/mesh_assembly.hpp"
#include "mesh2d/square_code.hpp"

namespace warpmesh {
namespace {

// Per-point state bits.
constexpr std::uint8_t inside_bit = 1, warped_bit = 2, zero_bit = 4;

using namespace square_code;  // tri0_bit, …, triangle_of, emitted, uses_corner, square_boundary_edges

}  // namespace

// `flatten`: the rule's helpers (triangle_forms, diagonal_quality) are
// inlined here, for double only — left to itself the compiler calls them
// (about a third of the rule's time on this machine).  Inlining changes no
// operation and no order of operations: the same doubles come out.  The
// prover's interval instantiation is compiled as before.
[[gnu::flatten]] SquareSplit warped_square_split(DiagonalRule rule, const std::array<CornerState, 4>& cs,
                                                 const std::array<double, 4>& t, bool* forced, TieBreak tie,
                                                 LatticeMetric metric) {
    std::array<Warp, 4> w{};
    for (int k = 0; k < 4; ++k) w[static_cast<std::size_t>(k)] = cs[static_cast<std::size_t>(k)].warp;
    const Choice ch = choose_diagonal(rule, generic_positions(w, t), cs, tie, metric);
    if (forced) {
        Diagonal forced_d{};
        *forced = false;
        if (rule != DiagonalRule::maxmin && separating_diagonal(cs, forced_d)) {
            const Choice free = choose_diagonal(DiagonalRule::maxmin, generic_positions(w, t), cs, tie, metric);
            *forced = free.bc != ch.bc;
        }
    }
    return ch.fan ? SquareSplit::fan : ch.bc ? SquareSplit::bc : SquareSplit::ad;
}

Diagonal warped_square_diagonal(DiagonalRule rule, const std::array<CornerState, 4>& cs, const std::array<double, 4>& t,
                                bool* forced, TieBreak tie) {
    return warped_square_split(rule, cs, t, forced, tie) == SquareSplit::bc ? Diagonal::BC : Diagonal::AD;
}

namespace {

// Each point's state bits: inside (sign <= 0, or warped), warped, zero.
Buffer<std::uint8_t> point_states(const Lattice& lattice, std::span<const std::int8_t> signs, std::span<const WarpedPoint> warped) {
    const std::size_t npoints = static_cast<std::size_t>(lattice.point_count());
    Buffer<std::uint8_t> state(npoints);  // every element written by the loop below
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < static_cast<std::int64_t>(npoints); ++k)
        state[static_cast<std::size_t>(k)] = signs[static_cast<std::size_t>(k)] < 0    ? inside_bit
                                             : signs[static_cast<std::size_t>(k)] == 0 ? inside_bit | zero_bit
                                                                                       : 0;
    for (const WarpedPoint& w : warped) state[static_cast<std::size_t>(w.p)] = inside_bit | warped_bit;
    return state;
}

// The warp record of warped point p (warped: sorted by point).
const WarpedPoint& warp_of(std::span<const WarpedPoint> warped, std::int64_t p) {
    return *std::lower_bound(warped.begin(), warped.end(), p, [](const WarpedPoint& w, std::int64_t q) { return w.p < q; });
}

// Pass 1's results: a code per square; per row its triangles and its centroid
// fans (DiagonalRule::fan), prefix-summed (row j's first, [ny]: all); the
// warped squares and the diagonals the separating rule forced.
struct SquareCodes {
    Buffer<std::uint8_t> code;
    std::vector<std::int64_t> row_tris, row_fans;
    std::int64_t warped_squares = 0, forced = 0;
};

// Pass 1: a code per square — its diagonal and which of its triangles it emits.
SquareCodes square_codes(const Lattice& lattice, std::span<const std::int8_t> signs, const Buffer<std::uint8_t>& state,
                         std::span<const WarpedPoint> warped, DiagonalRule rule, LatticeMetric metric) {
    const std::int64_t nxp = lattice.points_x(), nx = lattice.nx, ny = lattice.ny;
    SquareCodes sc{Buffer<std::uint8_t>(static_cast<std::size_t>(nx * ny)),  // every element written below
                   std::vector<std::int64_t>(static_cast<std::size_t>(ny) + 1, 0),
                   std::vector<std::int64_t>(static_cast<std::size_t>(ny) + 1, 0), 0, 0};
    Buffer<std::uint8_t>& code = sc.code;
    std::vector<std::int64_t>& row_tris = sc.row_tris;
    std::vector<std::int64_t>& row_fans = sc.row_fans;
    std::int64_t warped_squares = 0, forced = 0;
#pragma omp parallel for schedule(dynamic, 8) reduction(+ : warped_squares, forced)
    for (std::int64_t j = 0; j < ny; ++j) {
        std::int64_t tris = 0, fans = 0;
        for (std::int64_t i = 0; i < nx; ++i) {
            const std::int64_t pa = lattice.index(i, j);
            const std::array<std::int64_t, 4> p{pa, pa + 1, pa + nxp, pa + nxp + 1};
            const std::array<std::uint8_t, 4> st{state[static_cast<std::size_t>(p[0])],
                                                 state[static_cast<std::size_t>(p[1])],
                                                 state[static_cast<std::size_t>(p[2])],
                                                 state[static_cast<std::size_t>(p[3])]};
            const int inside = (st[0] & inside_bit) | (st[1] & inside_bit) << 1 | (st[2] & inside_bit) << 2 |
                               (st[3] & inside_bit) << 3;
            const std::uint8_t any = st[0] | st[1] | st[2] | st[3];
            const TieBreak tie = union_jack(i, j);
            std::uint8_t c = 0;
            if (!(any & (warped_bit | zero_bit))) {
                // The unit square: its tie-break, or BC on the rhombic
                // lattice (only where it emits, so that
                // a square emitting nothing keeps bit 2 clear).
                if (inside == 15 && unwarped_diagonal(metric, tie) == Diagonal::BC) c = bc_bit;
            } else {
                warped_squares += (any & warped_bit) != 0;
                c = rule_bit;
                if (diagonal_matters(inside)) {  // else it emits nothing, whichever diagonal
                    const std::array<std::int8_t, 4> sg{signs[static_cast<std::size_t>(p[0])], signs[static_cast<std::size_t>(p[1])],
                                                        signs[static_cast<std::size_t>(p[2])], signs[static_cast<std::size_t>(p[3])]};
                    bool was_forced = false;
                    c |= rule_diagonal(rule, sg, [&](int k) {
                        return st[static_cast<std::size_t>(k)] & warped_bit ? &warp_of(warped, p[static_cast<std::size_t>(k)]) : nullptr;
                    }, &was_forced, tie, metric);
                    forced += was_forced;
                }
            }
            const std::uint8_t e = emitted[(c & bc_bit) != 0][inside];
            c |= e;
            tris += (c & fan_bit) ? 4 : (e & 1) + (e >> 1);
            fans += (c & fan_bit) != 0;
            code[static_cast<std::size_t>(i + j * nx)] = c;
        }
        row_tris[static_cast<std::size_t>(j) + 1] = tris;
        row_fans[static_cast<std::size_t>(j) + 1] = fans;
    }
    std::partial_sum(row_tris.begin(), row_tris.end(), row_tris.begin());
    std::partial_sum(row_fans.begin(), row_fans.end(), row_fans.begin());
    sc.warped_squares = warped_squares;
    sc.forced = forced;
    return sc;
}

// Pass 3: the triangles at their rows' offsets into mesh (sized by
// compact_vertices), the centroid fans' centres numbered from
// lattice_vertices on; with want_keyed, per row the squares through the rule
// with their triangles.
std::vector<std::vector<KeyedSquare>> fill_triangles(const Lattice& lattice, const SquareCodes& sc, const Buffer<std::int32_t>& vid,
                                                     std::int64_t lattice_vertices, bool want_keyed, Mesh& mesh) {
    const std::int64_t nxp = lattice.points_x(), nx = lattice.nx, ny = lattice.ny;
    const Buffer<std::uint8_t>& code = sc.code;
    std::vector<std::vector<KeyedSquare>> keyed_rows(want_keyed ? static_cast<std::size_t>(ny) : 0);
#pragma omp parallel for schedule(static)
    for (std::int64_t j = 0; j < ny; ++j) {
        std::int64_t next = sc.row_tris[static_cast<std::size_t>(j)];
        std::int64_t next_centre = lattice_vertices + sc.row_fans[static_cast<std::size_t>(j)];
        for (std::int64_t i = 0; i < nx; ++i) {
            const std::uint8_t c = code[static_cast<std::size_t>(i + j * nx)];
            if (!(c & (tri0_bit | tri1_bit))) continue;
            const std::int64_t pa = lattice.index(i, j);
            const std::array<std::int64_t, 4> p{pa, pa + 1, pa + nxp, pa + nxp + 1};
            if (c & fan_bit) {
                // The centroid fan: the centre at the mean of the four corners.
                if (want_keyed) keyed_rows[static_cast<std::size_t>(j)].push_back({i + j * nx, next, 4});
                const auto m = static_cast<std::int32_t>(next_centre++);
                std::array<Vec2, 4> x{};
                for (std::size_t q = 0; q < 4; ++q) x[q] = mesh.vertices[static_cast<std::size_t>(vid[static_cast<std::size_t>(p[q])])];
                mesh.vertices[static_cast<std::size_t>(m)] = fan_centre_position(x);
                for (const auto& tri : fan_triangles)
                    mesh.triangles[static_cast<std::size_t>(next++)] = {vid[static_cast<std::size_t>(p[static_cast<std::size_t>(tri[0])])],
                                                                        vid[static_cast<std::size_t>(p[static_cast<std::size_t>(tri[1])])], m};
                continue;
            }
            if (want_keyed && (c & rule_bit))
                keyed_rows[static_cast<std::size_t>(j)].push_back(
                    {i + j * nx, next, static_cast<std::int32_t>((c & tri0_bit ? 1 : 0) + (c & tri1_bit ? 1 : 0))});
            for (int k = 0; k < 2; ++k) {
                if (!(c & (1 << k))) continue;
                const auto tri = triangle_of(c, k);
                mesh.triangles[static_cast<std::size_t>(next++)] = {vid[static_cast<std::size_t>(p[tri[0]])],
                                                                    vid[static_cast<std::size_t>(p[tri[1]])],
                                                                    vid[static_cast<std::size_t>(p[tri[2]])]};
            }
        }
    }
    return keyed_rows;
}

// Each triangle's region: f.region_at its centroid if f tags regions, else 1.
void tag_regions(const LevelSet& f, Mesh& mesh) {
    const std::int64_t ntris = static_cast<std::int64_t>(mesh.triangles.size());
    mesh.region.resize(mesh.triangles.size());  // every element written below
    const bool tags = f.tags_regions();
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < ntris; ++k) {
        if (!tags) {
            mesh.region[static_cast<std::size_t>(k)] = 1;
            continue;
        }
        const auto& t = mesh.triangles[static_cast<std::size_t>(k)];
        const Vec2 &a = mesh.vertices[static_cast<std::size_t>(t[0])], &b = mesh.vertices[static_cast<std::size_t>(t[1])],
                   &c = mesh.vertices[static_cast<std::size_t>(t[2])];
        mesh.region[static_cast<std::size_t>(k)] = f.region_at((a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3);
    }
}

// Pass 4: the boundary edges, per row {from, to, tag}.
// A side of square (i, j) is covered when the triangle of the chosen
// diagonal that holds it is emitted.  It is a boundary edge when exactly
// one of the two squares sharing it covers it (the lattice's outer border
// has one square only), a diagonal when exactly one of the square's two
// triangles is emitted: square_boundary_edges (square_code.hpp), shared
// with the graded triangulation.
std::vector<std::vector<std::array<std::int32_t, 3>>> boundary_edges(const Lattice& lattice, const Buffer<std::uint8_t>& code,
                                                                     const Buffer<std::int32_t>& vid) {
    const std::int64_t nxp = lattice.points_x(), nx = lattice.nx, ny = lattice.ny;
    auto square_code = [&](std::int64_t i, std::int64_t j) -> std::uint8_t {
        return (i < 0 || j < 0 || i >= nx || j >= ny) ? 0 : code[static_cast<std::size_t>(i + j * nx)];
    };
    std::vector<std::vector<std::array<std::int32_t, 3>>> per_row(static_cast<std::size_t>(ny));
#pragma omp parallel for schedule(dynamic, 16)
    for (std::int64_t j = 0; j < ny; ++j) {
        auto& out = per_row[static_cast<std::size_t>(j)];
        for (std::int64_t i = 0; i < nx; ++i) {
            const std::uint8_t c = code[static_cast<std::size_t>(i + j * nx)];
            if (!(c & (tri0_bit | tri1_bit))) continue;
            // A full square whose four neighbours are full has no boundary edge.
            constexpr std::uint8_t full = tri0_bit | tri1_bit;
            if ((c & full) == full && i > 0 && j > 0 && i + 1 < nx && j + 1 < ny &&
                (code[static_cast<std::size_t>(i - 1 + j * nx)] & code[static_cast<std::size_t>(i + 1 + j * nx)] &
                 code[static_cast<std::size_t>(i + (j - 1) * nx)] & code[static_cast<std::size_t>(i + (j + 1) * nx)] &
                 full) == full)
                continue;
            const std::int64_t pa = lattice.index(i, j);
            const std::array<std::int64_t, 4> p{pa, pa + 1, pa + nxp, pa + nxp + 1};
            auto edge = [&](int from, int to, std::int32_t tag) {
                out.push_back({vid[static_cast<std::size_t>(p[from])], vid[static_cast<std::size_t>(p[to])], tag});
            };
            const std::array<bool, 4> border{j == 0, i == nx - 1, j == ny - 1, i == 0};  // below, right, above, left
            square_boundary_edges(
                c, [&](int sd) { return border[static_cast<std::size_t>(sd)]; },
                [&](int sd) {
                    const auto& d = side_step[static_cast<std::size_t>(sd)];
                    return square_code(i + d[0], j + d[1]);
                },
                edge);
        }
    }
    return per_row;
}

}  // namespace

Mesh triangulate(const LevelSet& f, const Lattice& lattice, std::span<const std::int8_t> signs,
                 std::span<const WarpedPoint> warped, DiagonalRule rule, TriangulateStats* stats, LatticeMetric metric) {
    const Buffer<std::uint8_t> state = point_states(lattice, signs, warped);
    const SquareCodes sc = square_codes(lattice, signs, state, warped, rule, metric);

    // ---- pass 2: compact vertex ids (inside points used by an emitted triangle) --
    Mesh mesh;
    Buffer<std::int32_t> vid;
    const std::int64_t ntris = sc.row_tris.back();
    compact_vertices(
        lattice, sc.code, ntris, [&](std::int64_t p) { return (state[static_cast<std::size_t>(p)] & inside_bit) != 0; },
        [&](std::int64_t p, std::int64_t i, std::int64_t j) {
            Vec2 x = lattice.position(i, j);
            if (state[static_cast<std::size_t>(p)] & warped_bit) {
                const WarpedPoint& wp = warp_of(warped, p);
                // The same affine map as generic_positions, scaled by s.
                x.x += warp_dx(wp.dir) * wp.t * lattice.s;
                x.y += warp_dy(wp.dir) * wp.t * lattice.s;
            }
            return x;
        },
        vid, mesh);
    // Fan centres follow the lattice vertices, in square order.
    const std::int64_t lattice_vertices = static_cast<std::int64_t>(mesh.vertices.size());
    if (lattice_vertices + sc.row_fans.back() > INT32_MAX) throw std::length_error("mesh too large for 32-bit vertex indices");
    mesh.vertices.resize(static_cast<std::size_t>(lattice_vertices + sc.row_fans.back()));  // centres written in pass 3

    // ---- pass 3: triangles, regions; pass 4: boundary --------------------------------
    // Squares through the rule, for the certification: per row, then joined.
    const auto keyed_rows = fill_triangles(lattice, sc, vid, lattice_vertices, stats && stats->keyed_squares, mesh);
    tag_regions(f, mesh);
    append_boundary(mesh, boundary_edges(lattice, sc.code, vid));
    record_stats(stats, sc.warped_squares, sc.forced, keyed_rows);
    return mesh;
}

}  // namespace warpmesh
