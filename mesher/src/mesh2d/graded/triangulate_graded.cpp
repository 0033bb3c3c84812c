// triangulate_graded.cpp — the triangles of the quadtree's leaves, compacted
// vertices and the boundary (triangulate_graded.hpp).
//
// Finest leaves are lattice squares and are triangulated exactly as the
// uniform mesher does: the diagonal by the rule (warped_square_split, the
// code the prover certifies, wherever a corner is warped or zero-valued; the
// union-jack tie-break on the plain unit square, where both diagonals tie),
// and the triangles whose three
// corners are inside — or, under DiagonalRule::fan, the centroid fan of a
// square whose four corners are inside (fan_triangles: four triangles around
// a new vertex at the centroid of its corners, fan_centre_position).  By the
// quadtree's invariant (quadtree.hpp) every square with a warped corner is
// such a leaf, so every warped triangle of the graded mesh is a triangle of a
// generic square of the proof.  A fan square covers its four sides as a
// diagonal's two triangles do and its centre is interior to it, so the
// conformity and boundary arguments below see it as a full square.
//
// Coarse leaves (level l >= 1, side w = 2^l) are unwarped and, by the
// quadtree's construction, entirely inside (σ = -1: all their points have f < 0)
// or entirely outside (σ = +1: they emit nothing).  An inside coarse leaf with
// no split side is the square split by one diagonal — (A, B, D), (A, D, C) or
// (A, B, C), (B, D, C), by the union-jack pattern of its level
// (coarse_tie_break, quadtree.hpp) — angles 45, 45, 90.  With
// split sides it takes the centre template: the centre M joined to the ring
//
//        A → [mid AB] → B → [mid BD] → D → [mid DC] → C → [mid CA] → A,
//
// (midpoints only of split sides), one triangle (M, ring[k], ring[k+1]) per
// ring edge: 4 + (number of split sides) triangles, each a right isosceles
// triangle — the half-square (M, A, B) of legs w/√2 or the quarter-square
// (M, A, mid AB) of legs w/2 — so every angle is 45 or 90 degrees.
//
// Conformity.  Every triangle edge is a side of a leaf, a half side, or lies
// inside a leaf.  A side shared by two leaves of the same level is one edge on
// both sides (neither halves it).  A side shared by leaves of levels l and
// l - 1 (the only other case, by 2:1 edge balance) is halved on the coarse
// side, whose template puts a vertex at its midpoint; on the fine side that
// midpoint is the shared corner of the two finer leaves.  So every vertex on a
// leaf's side is one of the leaf's own vertices: no hanging vertex.
//
// Boundary.  A coarse inside leaf never carries a boundary edge: it does not
// touch the lattice border (quadtree.hpp), and a square across one of its sides
// shares two non-critical inside points, so its other two corners cannot be
// outside (an outside one would make a cut edge with a shared point, which
// would then be critical): all four are inside and the square covers the side.
// So boundary edges come from finest leaves only, and are found as in the
// uniform mesher: a side covered by exactly one of its two squares (a square
// inside a coarse leaf covers it iff the leaf is inside), or a diagonal with
// one emitted triangle.  Since the finest leaves emit what the uniform squares
// emit and the coarse leaves tile what the uniform inside squares tile, the
// graded mesh covers exactly the uniform mesh's region and has the same
// boundary edges.
//
// Passes, each a member function of GradedTriangulation below, over chunks
// of leaves (parallel, deterministic): the finest leaves by their level-1
// parents (Leaves, quadtree.hpp), in runs of row pairs, then the coarse
// leaves.
//   1. finest_codes: the finest leaves' codes, a parent's 2 x 2 squares at
//      once; count_and_mark_used: per chunk the triangle count, and the used
//      points;
//   2. place_vertices: compact vertex ids in lattice-point order (a point
//      set with ranks) and their positions; the fan centres follow, numbered
//      in chunk order (the finest leaves' canonical order), so the vertex
//      order does not depend on the thread count or the tile size;
//   3. emit_triangles: triangles at chunk offsets, fan centres' positions,
//      region tags;
//   4. boundary_edges: the boundary edges of the finest leaves.
#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <cmath>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "mesh2d/graded/triangulate_graded.hpp"
#include "mesh2d/mesh_assembly.hpp"
#include "mesh2d/square_code.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh {
namespace {

using namespace square_code;  // finest leaf codes: tri0_bit, …, triangle_of, emitted, sides, covers

constexpr std::int64_t chunk_size = 2048;

// A finest square whose four corners are unwarped with f < 0 (in its code,
// beside square_code's bits).  None of its sides is on the level-set
// boundary: the square across a side shares two such corners, and its other
// two corners are inside too — an outside one, unwarped with f > 0, would
// make a cut edge with a shared corner, and one of the two would warp.
constexpr std::uint8_t interior_bit = 16;
static_assert((interior_bit & (tri0_bit | tri1_bit | bc_bit | rule_bit | fan_bit)) == 0);

constexpr std::uint8_t both_triangles = tri0_bit | tri1_bit;

// Number of triangles a coarse inside leaf emits.
constexpr int coarse_triangles(std::uint8_t split) { return split ? 4 + std::popcount(split) : 2; }

// Region tags by centroid, asking the level set as rarely as it allows: the
// last cell region_in answered is kept (empty at first: holds nothing), and
// every box or centroid it holds takes its tag without a call.  One per chunk.
struct RegionTagger {
    const LevelSet& f;
    RegionCell cell{0, {INFINITY, INFINITY, -INFINITY, -INFINITY}};

    // The one tag of every triangle with vertices in `box`, if known.
    std::optional<std::int32_t> of_box(const Box& box) {
        if (!cell.holds(box)) {
            const std::optional<RegionCell> c = f.region_in(box);
            if (!c) return std::nullopt;  // the last cell stays, for the centroids
            cell = *c;
        }
        return cell.region;
    }
    std::int32_t of_triangle(const Vec2& a, const Vec2& b, const Vec2& c) const {
        const double x = (a.x + b.x + c.x) / 3, y = (a.y + b.y + c.y) / 3;
        return cell.holds({x, y, x, y}) ? cell.region : f.region_at(x, y);
    }
};

// A lattice point by its indices (the point sets take (i, j): no division).
struct Pt {
    std::int64_t i, j;
};

// Corners A, B, C, D of square (i, j).
inline std::array<Pt, 4> square_corners(std::int64_t i, std::int64_t j) {
    return {Pt{i, j}, Pt{i + 1, j}, Pt{i, j + 1}, Pt{i + 1, j + 1}};
}

// The vertex ids of a parent's 3 x 3 corners (i + c, j + r), [r][c].
using CornerIds = std::array<std::array<std::int32_t, 3>, 3>;

// A boundary edge (from, to, tag), as the passes collect them per chunk.
using TaggedEdge = std::array<std::int32_t, 3>;

// The chunks of leaves the passes run over.  Finest chunks are runs of whole
// row pairs with about chunk_size squares; then the coarse leaves, chunk_size
// per chunk.  Triangles are numbered in chunk order: finest leaves first, in
// canonical order (by parents, quadtree.hpp), then the coarse leaves.
struct Chunks {
    std::vector<std::int64_t> pair;  // finest chunk ch: row pairs pair[ch] .. pair[ch + 1] - 1
    std::int64_t finest = 0;         // finest chunks (the first ones)
    std::int64_t count = 0;          // all chunks
    std::int64_t ncoarse = 0;        // coarse leaves

    explicit Chunks(const Leaves& leaves) : pair{0}, ncoarse(static_cast<std::int64_t>(leaves.coarse.size())) {
        const std::int64_t npairs = leaves.row_pairs();
        for (std::int64_t R = 0, since = 0; R < npairs; ++R) {
            since += leaves.pair_start[static_cast<std::size_t>(R) + 1] - leaves.pair_start[static_cast<std::size_t>(R)];
            if (since >= chunk_size / 4 || R + 1 == npairs) pair.push_back(R + 1), since = 0;
        }
        finest = static_cast<std::int64_t>(pair.size()) - 1;
        count = finest + (ncoarse + chunk_size - 1) / chunk_size;
    }
    // The coarse leaves [k0, k1) of (coarse) chunk ch.
    std::pair<std::int64_t, std::int64_t> coarse_range(std::int64_t ch) const {
        const std::int64_t k0 = (ch - finest) * chunk_size;
        return {k0, std::min(ncoarse, k0 + chunk_size)};
    }
};

// The triangulation's inputs, its passes' results, and the passes.
struct GradedTriangulation {
    const LevelSet& f;
    const Lattice& lattice;
    const TiledSigns& signs;
    const Quadtree& tree;
    const Leaves& leaves;
    std::span<const WarpedPoint> warped;  // sorted by point: a warped point's record is at its rank in tree.warped
    DiagonalRule rule;
    std::int64_t nx, ny, nxp;
    Chunks chunks;
    bool parallel;

    // Pass 1: per parent k, the codes of its squares (2P + c, 2R + r) at
    // code[k][2r + c] (0, emitting nothing, for a child outside the lattice);
    // statistics; per chunk the triangle and fan counts, then (prefix sums)
    // the first triangle and the first fan of each chunk; the used points.
    std::vector<std::array<std::uint8_t, 4>> code;
    std::int64_t warped_squares = 0, forced = 0;
    std::vector<std::int64_t> chunk_tris, chunk_fans;
    PointSet used;
    std::int64_t lattice_vertices = 0;  // the used points' count: the first fan centre's id (pass 2)
    // Passes 2 - 4.
    Mesh mesh;

    GradedTriangulation(const LevelSet& f_, const Lattice& lattice_, const TiledSigns& signs_, const Quadtree& tree_,
                        const Leaves& leaves_, std::span<const WarpedPoint> warped_, DiagonalRule rule_)
        : f(f_),
          lattice(lattice_),
          signs(signs_),
          tree(tree_),
          leaves(leaves_),
          warped(warped_),
          rule(rule_),
          nx(lattice_.nx),
          ny(lattice_.ny),
          nxp(lattice_.points_x()),
          chunks(leaves_),
          parallel(false),
          code(leaves_.parents.size(), std::array<std::uint8_t, 4>{}),
          chunk_tris(static_cast<std::size_t>(chunks.count) + 1, 0),
          chunk_fans(static_cast<std::size_t>(chunks.count) + 1, 0),
          used(nxp, ny + 1) {
#ifdef _OPENMP
        parallel = chunks.count > 1 && omp_get_max_threads() > 1;
#endif
    }

    // ---- helpers ------------------------------------------------------------------
    const WarpedPoint& warp_of(Pt p) const {
        const WarpedPoint& w = warped[static_cast<std::size_t>(tree.warped.rank(p.i, p.j))];
        assert(w.p == p.i + p.j * nxp);
        return w;
    }

    // The position of lattice point (i, j) as a mesh vertex: warped points
    // moved by the same affine map as generic_positions, scaled by s — the
    // same expression as triangulate.cpp, so the coordinates agree with the
    // uniform mesh's to the bit.  `wp`: the point's warp record, or null.
    Vec2 position(std::int64_t i, std::int64_t j, const WarpedPoint* wp) const {
        Vec2 x = lattice.position(i, j);
        if (wp) {
            assert(wp->p == i + j * nxp);
            x.x += warp_dx(wp->dir) * wp->t * lattice.s;
            x.y += warp_dy(wp->dir) * wp->t * lattice.s;
        }
        return x;
    }

    std::int64_t pair_start(std::int64_t R) const { return leaves.pair_start[static_cast<std::size_t>(R)]; }

    // fn(k, i, j, cols, rows) for the parents of finest chunk ch, in order:
    // parent k, its lower-left square (i, j) = (2P, 2R), its squares' columns
    // and rows (1 or 2).
    template <class Fn>
    void for_each_parent(std::int64_t ch, Fn&& fn) const {
        for (std::int64_t R = chunks.pair[static_cast<std::size_t>(ch)]; R < chunks.pair[static_cast<std::size_t>(ch) + 1]; ++R)
            for (std::int64_t k = pair_start(R); k < pair_start(R + 1); ++k) {
                const std::int64_t P = leaves.parents[static_cast<std::size_t>(k)];
                fn(k, 2 * P, 2 * R, leaves.columns(P), leaves.rows(R));
            }
    }

    // The code of finest square (i, j), as in triangulate.cpp: its diagonal
    // (or fan) and emitted triangles.  `sg`, `wp`: the signs and warped flags of its
    // corners A, B, C, D.  `warped_corner` / `forced_diag` report, for the
    // stats, whether a corner is warped and whether the separating rule
    // overrode max-min (asked only where the diagonal matters).
    std::uint8_t finest_code(std::int64_t i, std::int64_t j, const std::array<std::int8_t, 4>& sg, const std::array<bool, 4>& wp,
                             bool* warped_corner, bool* forced_diag) const {
        std::array<bool, 4> in{};
        for (std::size_t q = 0; q < 4; ++q) in[q] = wp[q] || sg[q] <= 0;  // inside: f <= 0, or warped onto the level set
        std::uint8_t c = 0;
        *warped_corner = wp[0] || wp[1] || wp[2] || wp[3];
        // As in triangulate.cpp: a warped or zero-valued corner (where the
        // separating rule may force BC even on the unwarped square) goes to the
        // certified rule; the plain unit square takes its tie-break, the
        // union-jack pattern of the lattice (union_jack(i, j)).
        const bool zero_corner = sg[0] == 0 || sg[1] == 0 || sg[2] == 0 || sg[3] == 0;
        const int mask = in[0] | in[1] << 1 | in[2] << 2 | in[3] << 3;
        const TieBreak tie = union_jack(i, j);
        if (*warped_corner || zero_corner) {
            c = rule_bit;
            if (diagonal_matters(mask)) {
                const auto p = square_corners(i, j);
                c |= rule_diagonal(rule, sg, [&](int q) {
                    const std::size_t Q = static_cast<std::size_t>(q);
                    return wp[Q] ? &warp_of(p[Q]) : nullptr;
                }, forced_diag, tie);
            }
        } else if (sg[0] < 0 && sg[1] < 0 && sg[2] < 0 && sg[3] < 0) {
            c = interior_bit | (tie == TieBreak::bc ? bc_bit : 0);
        }
        return static_cast<std::uint8_t>(c | emitted[(c & bc_bit) != 0][mask]);
    }

    // Vertex id of a used point (after pass 2).
    std::int32_t vid(Pt p) const {
        assert(used.contains(p.i, p.j));
        return static_cast<std::int32_t>(used.rank(p.i, p.j));
    }
    // The vertex ids of a parent's 3 x 3 corners (i + c, j + r), c <= cols,
    // r <= rows, valid for the used ones: one rank per row (after pass 2).
    CornerIds corner_ids(std::int64_t i, std::int64_t j, int cols, int rows) const {
        CornerIds id;
        for (int r = 0; r <= rows; ++r) {
            const auto rk = used.rank_run(i, j + r, cols + 1);
            for (std::size_t c = 0; c < 3; ++c) id[static_cast<std::size_t>(r)][c] = static_cast<std::int32_t>(rk[c]);
        }
        return id;
    }

    // ---- pass 1 ---------------------------------------------------------------------
    // The finest leaves' codes, a parent's 2 x 2 squares at once.  A parent's
    // (up to) 2 x 2 squares share their 3 x 3 corners, whose signs lie in one
    // tile's block (the tile of its lower-left square: T is even, so the
    // corners reach at most the tile's last point) and whose warped flags lie
    // in three rows of the warped set: looked up once per parent.
    void finest_codes() {
        std::int64_t ws = 0, fd = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : ws, fd) if (parallel)
        for (std::int64_t ch = 0; ch < chunks.finest; ++ch)
            for_each_parent(ch, [&](std::int64_t k, std::int64_t i, std::int64_t j, int cols, int rows) {
                std::array<std::array<std::int8_t, 3>, 3> sg{};  // [row][column] of the corners (i + c, j + r)
                const std::int64_t I = i >> signs.tile_log, J = j >> signs.tile_log;
                const std::int32_t slot = signs.slot[static_cast<std::size_t>(I + J * signs.tx)];
                const std::int8_t* c0 = slot < 0 ? nullptr : signs.at(slot, I, J, i, j);
                std::array<unsigned, 3> wb{};
                for (int r = 0; r <= rows; ++r) {
                    for (int c = 0; c <= cols; ++c)
                        sg[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)] =
                            c0 ? c0[r * signs.stride() + c] : signs.uniform[static_cast<std::size_t>(I + J * signs.tx)];
                    wb[static_cast<std::size_t>(r)] = static_cast<unsigned>(tree.warped.members(i, j + r, cols + 1));
                }
                for (int r = 0; r < rows; ++r)
                    for (int c = 0; c < cols; ++c) {
                        const std::size_t R0 = static_cast<std::size_t>(r), C0 = static_cast<std::size_t>(c);
                        const std::array<std::int8_t, 4> s4{sg[R0][C0], sg[R0][C0 + 1], sg[R0 + 1][C0], sg[R0 + 1][C0 + 1]};
                        const std::array<bool, 4> w4{((wb[R0] >> c) & 1) != 0, ((wb[R0] >> (c + 1)) & 1) != 0,
                                                     ((wb[R0 + 1] >> c) & 1) != 0, ((wb[R0 + 1] >> (c + 1)) & 1) != 0};
                        assert(s4 == signs.square(i + c, j + r));
                        bool warped_corner = false, was_forced = false;
                        code[static_cast<std::size_t>(k)][2 * R0 + C0] = finest_code(i + c, j + r, s4, w4, &warped_corner, &was_forced);
                        ws += warped_corner;
                        fd += was_forced;
                    }
            });
        warped_squares = ws, forced = fd;
    }

    // Points (i + k, j) for the bits k of rel (several in one or two words).
    // Several leaves may mark one point: relaxed atomic or-s when chunks run
    // in parallel (plain ones with one thread).
    void mark_used(std::int64_t i, std::int64_t j, std::uint64_t rel) {
        if (!rel) return;
        if (parallel)
            used.insert_bits<true>(i, j, rel);
        else
            used.insert_bits<false>(i, j, rel);
    }

    // Per chunk, its triangle and fan counts and its leaves' used points;
    // then the chunks' first triangles and first fans.
    void count_and_mark_used() {
#pragma omp parallel for schedule(dynamic, 1) if (parallel)
        for (std::int64_t ch = 0; ch < chunks.count; ++ch)
            chunk_tris[static_cast<std::size_t>(ch) + 1] =
                ch < chunks.finest ? mark_finest_chunk(ch, chunk_fans[static_cast<std::size_t>(ch) + 1]) : mark_coarse_chunk(ch);
        std::partial_sum(chunk_tris.begin(), chunk_tris.end(), chunk_tris.begin());
        std::partial_sum(chunk_fans.begin(), chunk_fans.end(), chunk_fans.begin());
    }
    // A parent's used corners (corner_mask: bit q for corner q = A, B, C, D of
    // a square; a fan square has both triangle bits, so all four) as its three
    // rows of three points.  Returns the chunk's triangles (4 per fan), its
    // fans in `fans`.
    std::int64_t mark_finest_chunk(std::int64_t ch, std::int64_t& fans) {
        std::int64_t tris = 0;
        fans = 0;
        for_each_parent(ch, [&](std::int64_t k, std::int64_t i, std::int64_t j, int, int) {
            const auto& q = code[static_cast<std::size_t>(k)];
            std::array<unsigned, 4> m{};
            for (std::size_t s = 0; s < 4; ++s) {
                const bool fan = q[s] & fan_bit;
                tris += fan ? 4 : (q[s] & tri0_bit ? 1 : 0) + (q[s] & tri1_bit ? 1 : 0);
                fans += fan;
                m[s] = corner_mask[q[s] & 7];
            }
            mark_used(i, j, (m[0] & 3) | (m[1] & 3) << 1);
            mark_used(i, j + 1, (m[0] >> 2) | (m[1] >> 2) << 1 | (m[2] & 3) | (m[3] & 3) << 1);
            mark_used(i, j + 2, (m[2] >> 2) | (m[3] >> 2) << 1);
        });
        return tris;
    }
    // A coarse inside leaf uses its ring and, with a split side, its centre.
    std::int64_t mark_coarse_chunk(std::int64_t ch) {
        std::int64_t tris = 0;
        const auto [k0, k1] = chunks.coarse_range(ch);
        for (std::int64_t k = k0; k < k1; ++k) {
            const Leaf& leaf = leaves.coarse[static_cast<std::size_t>(k)];
            if (leaf.sign > 0) continue;
            const std::uint8_t split = leaf.split_sides;
            const std::int64_t w = std::int64_t{1} << leaf.level, h = w / 2, i = leaf.i, j = leaf.j;
            if (w < bits::word_bits) {  // the ring and centre (coarse_ring) by rows: j, j + h, j + w
                auto at = [](bool on, std::int64_t b) { return on ? std::uint64_t{1} << b : 0; };
                mark_used(i, j, 1 | at(split & side_bottom, h) | std::uint64_t{1} << w);
                mark_used(i, j + h, at(split & side_left, 0) | at(split != 0, h) | at(split & side_right, w));
                mark_used(i, j + w, 1 | at(split & side_top, h) | std::uint64_t{1} << w);
            } else {
                std::array<Pt, 8> ring{};
                Pt centre{};
                const int n = coarse_ring(leaf, ring, centre);
                for (int r = 0; r < n; ++r) mark_used(ring[static_cast<std::size_t>(r)].i, ring[static_cast<std::size_t>(r)].j, 1);
                if (split) mark_used(centre.i, centre.j, 1);
            }
            tris += coarse_triangles(split);
        }
        return tris;
    }

    // ---- pass 2 ---------------------------------------------------------------------
    // Compact vertex ids in lattice-point order: the ranks of the used points
    // are the vertex ids; positions by rows in parallel, word by word: `used`
    // and the tree's warped set have the same dimensions, hence the same word
    // layout, so a word's warped members are one AND away and their records
    // at the warped set's ranks (no per-point lookups).  The fan centres get
    // the ids after them (positions written by pass 3).
    void place_vertices() {
        used.finish();
        lattice_vertices = used.count;
        const std::int64_t nverts = used.count + chunk_fans.back(), ntris = chunk_tris.back();
        if (nverts > INT32_MAX || ntris > INT32_MAX) throw std::length_error("mesh too large for 32-bit vertex and triangle indices");
        mesh.vertices.resize(static_cast<std::size_t>(nverts));
        mesh.triangles.resize(static_cast<std::size_t>(ntris));
        const PointSet& moved_set = tree.warped;
        assert(used.words.size() == moved_set.words.size());
#pragma omp parallel for schedule(static) if (parallel && nverts >= 4096)
        for (std::int64_t j = 0; j <= ny; ++j)
            used.for_each_word_in_row(j, [&](std::size_t w, std::int64_t i0, std::uint64_t members, std::int64_t r0) {
                const std::uint64_t moved = moved_set.words[w];
                for (std::int64_t r = r0; members; members &= members - 1, ++r) {
                    const int b = std::countr_zero(members);
                    const WarpedPoint* wp = nullptr;
                    if ((moved >> b) & 1) wp = &warped[static_cast<std::size_t>(moved_set.rank_in_word(w, b))];
                    mesh.vertices[static_cast<std::size_t>(r)] = position(i0 + b, j, wp);
                }
            });
    }

    // ---- pass 3 ---------------------------------------------------------------------
    // The triangles, at their chunks' offsets, with region tags (label
    // images) from their centroids.  Where the level set knows a box around a
    // square or a coarse leaf to be one region (region_in), all its triangles
    // take that tag, and so do the next leaves in the same box (one call for a
    // run of squares in one pixel cell).  Else per triangle: a finest square's
    // corners read back from the vertices of pass 2, a coarse leaf's
    // (unwarped) as lattice positions, the same doubles as pass 2's.  Warped
    // corners stay in their square (they slide along its sides), so its box
    // holds every centroid (a fan's centre too: the centroid of its corners).
    // A fan square's centre is placed here, at the chunk's next fan id.  The
    // finest leaves through the rule are collected per chunk in `keyed`, if
    // asked (for the certification).
    struct Emitter {
        GradedTriangulation& g;
        std::int64_t next;         // the next triangle
        std::int64_t next_centre;  // the next fan centre's vertex id
        RegionTagger tagger;
        bool tags;

        // The one tag of the w x h squares from (i, j), if known.
        std::optional<std::int32_t> region_of_box(std::int64_t i, std::int64_t j, std::int64_t w, std::int64_t h) {
            if (!tags) return 1;
            const Vec2 lo = g.lattice.position(i, j), hi = g.lattice.position(i + w, j + h);
            return tagger.of_box({lo.x, lo.y, hi.x, hi.y});
        }
        void emit(std::int32_t a, std::int32_t b, std::int32_t c, std::int32_t region) {
            g.mesh.region[static_cast<std::size_t>(next)] = region;
            g.mesh.triangles[static_cast<std::size_t>(next++)] = {a, b, c};
        }
    };

    void emit_triangles(std::vector<std::vector<KeyedSquare>>* keyed) {
        const bool tags = f.tags_regions();
        mesh.region.resize(mesh.triangles.size());  // every element written below
#pragma omp parallel for schedule(dynamic, 1) if (chunks.count > 1)
        for (std::int64_t ch = 0; ch < chunks.count; ++ch) {
            Emitter e{*this, chunk_tris[static_cast<std::size_t>(ch)],
                      lattice_vertices + chunk_fans[static_cast<std::size_t>(ch)], RegionTagger{f}, tags};
            if (ch < chunks.finest)
                emit_finest_chunk(ch, e, keyed ? &(*keyed)[static_cast<std::size_t>(ch)] : nullptr);
            else
                emit_coarse_chunk(ch, e);
            assert(e.next == chunk_tris[static_cast<std::size_t>(ch) + 1]);
            assert(e.next_centre == lattice_vertices + chunk_fans[static_cast<std::size_t>(ch) + 1]);
        }
    }
    // Vertex ids and positions are looked up once per parent, not per triangle.
    void emit_finest_chunk(std::int64_t ch, Emitter& e, std::vector<KeyedSquare>* keyed) {
        for_each_parent(ch, [&](std::int64_t k, std::int64_t i0, std::int64_t j0, int cols, int rows) {
            const auto& q4 = code[static_cast<std::size_t>(k)];
            if (!((q4[0] | q4[1] | q4[2] | q4[3]) & both_triangles)) return;
            const CornerIds id = corner_ids(i0, j0, cols, rows);
            const std::optional<std::int32_t> all = e.region_of_box(i0, j0, cols, rows);  // else per square
            for (int r = 0; r < rows; ++r)
                for (int cc = 0; cc < cols; ++cc) {
                    const std::uint8_t c = q4[static_cast<std::size_t>(2 * r + cc)];
                    if (!(c & both_triangles)) continue;
                    const std::int64_t i = i0 + cc, j = j0 + r;
                    if (keyed && (c & rule_bit))
                        keyed->push_back({i + j * nx, e.next,
                                          static_cast<std::int32_t>((c & fan_bit) ? 4 : (c & tri0_bit ? 1 : 0) + (c & tri1_bit ? 1 : 0))});
                    const std::size_t R0 = static_cast<std::size_t>(r), C0 = static_cast<std::size_t>(cc);
                    const std::array<std::int32_t, 4> v{id[R0][C0], id[R0][C0 + 1], id[R0 + 1][C0], id[R0 + 1][C0 + 1]};
#ifndef NDEBUG
                    for (std::size_t q = 0; q < 4; ++q) {
                        const Pt pq = square_corners(i, j)[q];
                        assert(!uses_corner(c, static_cast<int>(q)) || (used.contains(pq.i, pq.j) && v[q] == vid(pq)));
                    }
#endif
                    const std::optional<std::int32_t> one = all ? all : e.region_of_box(i, j, 1, 1);
                    std::array<Vec2, 4> x{};
                    if (c & fan_bit) {  // the centroid fan (its four corners are used)
                        for (std::size_t q = 0; q < 4; ++q) x[q] = mesh.vertices[static_cast<std::size_t>(v[q])];
                        const auto m = static_cast<std::int32_t>(e.next_centre++);
                        const Vec2 xm = fan_centre_position(x);
                        mesh.vertices[static_cast<std::size_t>(m)] = xm;
                        for (const auto& tri : fan_triangles) {
                            const std::size_t a = static_cast<std::size_t>(tri[0]), b = static_cast<std::size_t>(tri[1]);
                            e.emit(v[a], v[b], m, one ? *one : e.tagger.of_triangle(x[a], x[b], xm));
                        }
                        continue;
                    }
                    if (!one)
                        for (std::size_t q = 0; q < 4; ++q)
                            if (uses_corner(c, static_cast<int>(q))) x[q] = mesh.vertices[static_cast<std::size_t>(v[q])];
                    for (int q = 0; q < 2; ++q) {
                        if (!(c & (1 << q))) continue;
                        const auto tri = triangle_of(c, q);
                        const std::size_t a = static_cast<std::size_t>(tri[0]), b = static_cast<std::size_t>(tri[1]),
                                          d = static_cast<std::size_t>(tri[2]);
                        e.emit(v[a], v[b], v[d], one ? *one : e.tagger.of_triangle(x[a], x[b], x[d]));
                    }
                }
        });
    }
    void emit_coarse_chunk(std::int64_t ch, Emitter& e) const {
        const auto [k0, k1] = chunks.coarse_range(ch);
        for (std::int64_t k = k0; k < k1; ++k) {
            const Leaf& leaf = leaves.coarse[static_cast<std::size_t>(k)];
            if (leaf.sign > 0) continue;
            const std::int64_t w = std::int64_t{1} << leaf.level;
            const std::optional<std::int32_t> one = e.region_of_box(leaf.i, leaf.j, w, w);
            // Filled for the ring's n points below (x only when tagging per
            // triangle, and only then read): not zeroed first.
            std::array<Pt, 8> ring;
            std::array<std::int32_t, 8> v;
            std::array<Vec2, 8> x;
            Pt centre;
            const int n = coarse_ring(leaf, ring, centre);
            for (std::size_t r = 0; r < static_cast<std::size_t>(n); ++r) {
                v[r] = vid(ring[r]);
                if (!one) x[r] = lattice.position(ring[r].i, ring[r].j);  // coarse leaves are unwarped
            }
            if (!leaf.split_sides) {  // ring = A, B, D, C; the diagonal by coarse_tie_break
                const auto& tris = coarse_diagonal_ring[coarse_tie_break(leaf) == TieBreak::bc];
                for (const auto& t : tris) {
                    const auto a = static_cast<std::size_t>(t[0]), b = static_cast<std::size_t>(t[1]), d = static_cast<std::size_t>(t[2]);
                    e.emit(v[a], v[b], v[d], one ? *one : e.tagger.of_triangle(x[a], x[b], x[d]));
                }
                continue;
            }
            const std::int32_t vm = vid(centre);
            const Vec2 xm = one ? Vec2{} : lattice.position(centre.i, centre.j);
            for (int r = 0; r < n; ++r) {
                const std::size_t r0 = static_cast<std::size_t>(r), r1 = static_cast<std::size_t>((r + 1) % n);
                e.emit(vm, v[r0], v[r1], one ? *one : e.tagger.of_triangle(xm, x[r0], x[r1]));
            }
        }
    }

    // ---- pass 4 ---------------------------------------------------------------------
    // The boundary edges of the finest leaves (see the head comment), by the
    // rule of square_boundary_edges (square_code.hpp).  The square across a
    // side is either outside the lattice (domain border), a finest square — a
    // child of the same parent, of the parent beside it in the row pair (the
    // previous or next listed, if it is the adjacent column), or of the
    // parent with the same column in the row pair below or above — or, if
    // its parent is not listed, inside a coarse leaf: all its corners then
    // have the leaf's sign, and it covers every side iff that sign is -1
    // (both AD triangles).
    std::uint8_t coarse_code(std::int64_t a, std::int64_t b) const {
        assert(!tree.is_finest(a, b));
        return signs(a, b) < 0 ? both_triangles : 0;
    }
    // Parent of column P in row pair Rn, or -1: `cursor` only moves forward
    // while the queries' P increase (the sweep over a row pair's parents), and
    // restarts otherwise.
    std::int64_t parent_in_pair(std::int64_t Rn, std::int64_t P, std::int64_t& cursor) const {
        const std::int64_t k0 = pair_start(Rn), k1 = pair_start(Rn + 1);
        const auto& parents = leaves.parents;
        if (cursor < k0 || cursor > k1 || (cursor > k0 && parents[static_cast<std::size_t>(cursor) - 1] >= P)) cursor = k0;
        while (cursor < k1 && parents[static_cast<std::size_t>(cursor)] < P) ++cursor;
        return cursor < k1 && parents[static_cast<std::size_t>(cursor)] == P ? cursor : -1;
    }
    // The code of the square across side sd of square (cc, r) of parent k
    // (lower-left square (i0, j0)), inside the lattice.
    std::uint8_t code_across(std::int64_t k, std::int64_t i0, std::int64_t j0, int cc, int r, int sd, std::int64_t& below,
                             std::int64_t& above) const {
        const auto& parents = leaves.parents;
        const std::int64_t R = j0 >> 1, P = i0 >> 1;
        const std::size_t r2 = static_cast<std::size_t>(2 * r);
        std::int64_t kn = -1;  // the neighbour's parent, if finest
        std::size_t qn = 0;    // and its place in it
        switch (sd) {
            case 0:  // below: the same parent's row 0, or row 1 of the pair below
                kn = r ? k : parent_in_pair(R - 1, P, below), qn = static_cast<std::size_t>(cc) + (r ? 0 : 2);
                break;
            case 2:  // above
                kn = r ? parent_in_pair(R + 1, P, above) : k, qn = static_cast<std::size_t>(cc) + (r ? 0 : 2);
                break;
            case 1:  // right: the same parent's column 1, or column 0 of the next parent
                kn = !cc ? k : k + 1 < pair_start(R + 1) && parents[static_cast<std::size_t>(k) + 1] == P + 1 ? k + 1 : -1;
                qn = r2 + (cc ? 0 : 1);
                break;
            default:  // left
                kn = cc ? k : k > pair_start(R) && parents[static_cast<std::size_t>(k) - 1] == P - 1 ? k - 1 : -1;
                qn = r2 + (cc ? 0 : 1);
        }
        const std::array<std::int64_t, 4> ni{i0 + cc, i0 + cc + 1, i0 + cc, i0 + cc - 1}, nj{j0 + r - 1, j0 + r, j0 + r + 1, j0 + r};
        return kn >= 0 ? code[static_cast<std::size_t>(kn)][qn]
                       : coarse_code(ni[static_cast<std::size_t>(sd)], nj[static_cast<std::size_t>(sd)]);
    }
    std::vector<TaggedEdge> boundary_of_chunk(std::int64_t ch) const {
        std::vector<TaggedEdge> out;
        out.reserve(chunk_size / 4);  // about what a chunk along the boundary has: few regrowths
        std::int64_t below = -1, above = -1;  // cursors into the row pairs below and above
        for_each_parent(ch, [&](std::int64_t k, std::int64_t i0, std::int64_t j0, int cols, int rows) {
            const auto& q4 = code[static_cast<std::size_t>(k)];
            std::optional<CornerIds> id;  // looked up at the parent's first boundary edge
            for (int r = 0; r < rows; ++r)
                for (int cc = 0; cc < cols; ++cc) {
                    const std::uint8_t c = q4[static_cast<std::size_t>(2 * r + cc)];
                    if (!(c & both_triangles)) continue;
                    const std::int64_t i = i0 + cc, j = j0 + r;
                    const bool interior = c & interior_bit;
                    const std::array<bool, 4> border{j == 0, i + 1 == nx, j + 1 == ny, i == 0};  // below, right, above, left
                    if (interior && !(border[0] || border[1] || border[2] || border[3])) continue;
                    square_boundary_edges(
                        c, [&](int sd) { return border[static_cast<std::size_t>(sd)]; },
                        [&](int sd) { return interior ? both_triangles : code_across(k, i0, j0, cc, r, sd, below, above); },
                        [&](int from, int to, std::int32_t tag) {
                            if (!id) id = corner_ids(i0, j0, cols, rows);
                            const auto& v = *id;
                            out.push_back({v[static_cast<std::size_t>(r + (from >> 1))][static_cast<std::size_t>(cc + (from & 1))],
                                           v[static_cast<std::size_t>(r + (to >> 1))][static_cast<std::size_t>(cc + (to & 1))], tag});
                        });
                }
        });
        return out;
    }
    void boundary_edges() {
        std::vector<std::vector<TaggedEdge>> per_chunk(static_cast<std::size_t>(chunks.finest));
#pragma omp parallel for schedule(dynamic, 1) if (chunks.finest > 1)
        for (std::int64_t ch = 0; ch < chunks.finest; ++ch) per_chunk[static_cast<std::size_t>(ch)] = boundary_of_chunk(ch);
        append_boundary(mesh, per_chunk);
    }
};

}  // namespace

Mesh triangulate_graded(const LevelSet& f, const Lattice& lattice, const TiledSigns& signs, const Quadtree& tree,
                        const Leaves& leaves, std::span<const WarpedPoint> warped, DiagonalRule rule, TriangulateStats* stats) {
    GradedTriangulation g(f, lattice, signs, tree, leaves, warped, rule);
    g.finest_codes();
    g.count_and_mark_used();
    g.place_vertices();
    const bool want_keyed = stats && stats->keyed_squares;
    std::vector<std::vector<KeyedSquare>> keyed(want_keyed ? static_cast<std::size_t>(g.chunks.finest) : 0);
    g.emit_triangles(want_keyed ? &keyed : nullptr);
    g.boundary_edges();
    record_stats(stats, g.warped_squares, g.forced, keyed);
    return std::move(g.mesh);
}

}  // namespace warpmesh
