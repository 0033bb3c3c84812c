// quadtree.cpp — building the graded mesher's balanced quadtree
// (quadtree.hpp), bottom-up, in passes over the Quadtree:
//
//  1. warped_points: the set of warped points (a bitset with ranks);
//  2. choose_active_tiles: the tiles whose levels are stored (quadtree.hpp);
//  3. the coarsening codes, level by level: tiled_codes per active tile
//     (level 1 from the signs: a point is critical when f = 0 there or a
//     4-neighbour has the strictly opposite sign — exactly the endpoints of
//     cut edges; then each level from its children), dense_codes above;
//  4. with inside classes (per-material size caps), cap_codes: the nodes of a
//     class above its level made non-coarsenable;
//  5. with a grading buffer n >= 1 (--grading G < 2), widen_codes: the
//     non-coarsenable inside nodes of each level widened by n nodes;
//  6. the split flags with 2:1 balance, level by level upward:
//     balance_tiled_level, balance_dense_level.
//
// The leaf list is leaves.cpp; the checks, check_quadtree.cpp.
//
// 2:1 balance, edge neighbours only.  Leaves that share an edge (a segment of
// positive length) differ by at most one level; leaves that only touch at a
// corner are not balanced.  The centre template needs no more: its only
// vertices besides the leaf's corners are the centre and the midpoints of
// sides halved by an edge neighbour one level finer, so a leaf's triangles
// depend on its four edge neighbours alone, and a corner neighbour never puts
// a vertex on the leaf's boundary (it meets the leaf in a corner, which is a
// vertex already).
//
// Balance as a rule on split nodes.  The tree is edge-balanced iff
//
//     for every split node P of level m, the parents of P's edge neighbours
//     of level m are split (P's neighbours are not inside a coarser leaf).
//
// Necessity: P split means its four children have leaves of level <= m - 1
// along every side of P; a neighbour inside a leaf of level >= m + 1 would
// differ from them by >= 2.  Sufficiency: if leaves L (level l) and L' (level
// <= l - 2) share an edge, the level l - 1 ancestor P of L' is split and its
// neighbour across that edge lies inside L, whose level is l: its parent is
// the leaf L, not split.  Splitting a node of level m + 1 to satisfy the rule
// creates leaves of level m (no new split node of level m), so the rule
// propagates strictly upward and one bottom-up pass enforces it: level l + 1
// is final once level l is.  On a tiled level each active tile marks from its
// own split children (a mark only sets a byte to 1, so concurrent marks
// across a tile side commute: relaxed atomic stores); on a dense level row J
// of level l + 1 is written only by the iteration for J, which reads the split
// nodes of rows 2J - 1 .. 2J + 2 of level l.  Either way the result is
// independent of the thread count.
#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <stdexcept>
#include <string>

#include "mesh2d/graded/quadtree.hpp"
#include "warpmesh/mesh2d/graded.hpp"

namespace warpmesh {
namespace {

// Below this many nodes a level is done by one thread: a parallel region costs
// more than the loop.
constexpr std::int64_t parallel_min = std::int64_t{1} << 16;
// Below this many active tiles, the per-tile passes run on one thread.
constexpr std::int64_t parallel_min_tiles = 256;

// The largest tiles the tiled levels support: a row of a tile's level-1
// nodes, T / 2 of them, is one word of bits.
constexpr int max_tile_log = bits::word_log + 1;

// ---- 1. the warped points ----------------------------------------------------
// `warped` is sorted by point, so the row only advances: no division per point.
PointSet warped_points(const Lattice& lattice, std::span<const WarpedPoint> warped) {
    const std::int64_t nxp = lattice.points_x();
    PointSet set(nxp, lattice.ny + 1);
    std::int64_t j = 0, row0 = 0;  // row0 = j * nxp
    for (const WarpedPoint& w : warped) {
        assert(w.p >= row0);
        while (w.p - row0 >= nxp) ++j, row0 += nxp;
        set.insert(w.p - row0, j);
    }
    set.finish();
    return set;
}

// ---- 2. the active tiles -------------------------------------------------------
// Seeds (sampled tiles, tiles on the lattice border, and tiles of an inside
// class whose level is below the tiles' level), then their (2 radius + 1)^2
// dilation: along rows, then across (radius 1 without a grading buffer,
// quadtree.hpp).  Lays out the slots of the tiled levels
// 1 .. top and allocates them.
void choose_active_tiles(TileLevels& tl, const TiledSigns& signs, int top, std::int64_t radius) {
    const std::int64_t TX = signs.tx, TY = signs.ty, ntiles = TX * TY, T = signs.size();
    tl.tile_log = signs.tile_log, tl.tiles_x = TX;
    tl.top = std::min(signs.tile_log - 1, top);
    tl.tile_code = signs.uniform;
    std::vector<std::uint8_t> seed(static_cast<std::size_t>(ntiles)), wide(static_cast<std::size_t>(ntiles));
    for (std::int64_t TJ = 0; TJ < TY; ++TJ)
        for (std::int64_t TI = 0; TI < TX; ++TI)
            seed[static_cast<std::size_t>(TI + TJ * TX)] = signs.slot[static_cast<std::size_t>(TI + TJ * TX)] >= 0 || TI == 0 ||
                                                           TJ == 0 || TI == TX - 1 || TJ == TY - 1 ||
                                                           cap_level(signs.uniform[static_cast<std::size_t>(TI + TJ * TX)]) < tl.top;
    for (std::int64_t TJ = 0; TJ < TY; ++TJ) {
        const std::uint8_t* r = seed.data() + TJ * TX;
        std::uint8_t* o = wide.data() + TJ * TX;
        for (std::int64_t TI = 0; TI < TX; ++TI) {
            std::uint8_t v = 0;
            for (std::int64_t d = std::max<std::int64_t>(0, TI - radius); d <= std::min(TX - 1, TI + radius); ++d) v |= r[d];
            o[TI] = v;
        }
    }
    tl.slot_of_tile.assign(static_cast<std::size_t>(ntiles), -1);
    tl.row_start.assign(static_cast<std::size_t>(TY) + 1, 0);
    for (std::int64_t TJ = 0; TJ < TY; ++TJ) {
        tl.row_start[static_cast<std::size_t>(TJ)] = tl.slots();
        const std::int64_t J0 = std::max<std::int64_t>(0, TJ - radius), J1 = std::min(TY - 1, TJ + radius);
        for (std::int64_t TI = 0; TI < TX; ++TI) {
            std::uint8_t v = 0;
            for (std::int64_t d = J0; d <= J1; ++d) v |= wide[static_cast<std::size_t>(TI + d * TX)];
            if (!v) continue;
            // An inactive tile is not sampled, so its σ is not 0 (tiles.hpp).
            tl.slot_of_tile[static_cast<std::size_t>(TI + TJ * TX)] = static_cast<std::int32_t>(tl.slots());
            tl.tile_of_slot.push_back(TI + TJ * TX);
            tl.column_of_slot.push_back(TI);
        }
    }
    tl.row_start[static_cast<std::size_t>(TY)] = tl.slots();
    tl.level_offset.assign(static_cast<std::size_t>(tl.top) + 1, 0);
    tl.slot_nodes = 0;
    for (int l = 1; l <= tl.top; ++l) {
        tl.level_offset[static_cast<std::size_t>(l)] = tl.slot_nodes;
        tl.slot_nodes += (T >> l) * (T >> l);
    }
    tl.level1_nodes = tl.top >= 1 ? (T >> 1) * (T >> 1) : 0;
    tl.codes.resize(static_cast<std::size_t>(tl.slots() * tl.slot_nodes));
    tl.split.resize(static_cast<std::size_t>(tl.slots() * (tl.slot_nodes - tl.level1_nodes)));  // written in pass 6
}

// ---- 3. coarsening codes -------------------------------------------------------
// Per-thread scratch of tiled_codes for tiles of T squares: the codes of a
// tile's (T + 1)^2 points, and per row of points the common code of each
// horizontal triple (2x, 2x + 1, 2x + 2) (0 if they differ): a level-1
// node's 3 x 3 points agree iff the triples of its three rows do.
struct TileScratch {
    std::vector<CoarseningCode> point, triple;
    explicit TileScratch(std::int64_t T)
        : point(static_cast<std::size_t>((T + 1) * (T + 1))), triple(static_cast<std::size_t>((T + 1) * (T / 2))) {}
};

// The code of each point of tile (TI, TJ) inside the lattice (wx x wy of
// them, row stride T + 1): its sign if it is not critical — not 0, no
// 4-neighbour of the opposite sign (the block's ring holds the neighbours
// beyond the tile, 0 outside the lattice, which never makes a point critical)
// — else 0.
void point_codes(const TiledSigns& signs, const std::int8_t* block, std::int64_t wx, std::int64_t wy, CoarseningCode* out) {
    const std::int64_t w = signs.size() + 1, S = signs.stride();
    for (std::int64_t y = 0; y < wy; ++y) {
        const std::int8_t* c = block + (y + 1) * S + 1;
        CoarseningCode* o = out + y * w;
#pragma omp simd
        for (std::int64_t x = 0; x < wx; ++x) {
            const std::int8_t v = c[x], opp = static_cast<std::int8_t>(-v);
            const bool critical = (v == 0) | (c[x - 1] == opp) | (c[x + 1] == opp) | (c[x - S] == opp) | (c[x + S] == opp);
            o[x] = critical ? std::int8_t{0} : v;
        }
    }
}

// Level 1 of tile (TI, TJ) from the codes of its points (wy rows of them
// inside the lattice): a node takes the common code of its 3 x 3 points.  A
// node partly outside the lattice is never a leaf, and an inside node on the
// lattice border is not coarsenable (its border squares stay finest, as in
// the uniform mesh).
void level1_codes(const Quadtree& t, std::int64_t T, std::int64_t TI, std::int64_t TJ, std::int64_t wy, TileScratch& scratch,
                  CoarseningCode* out) {
    const std::int64_t half = T / 2, w = T + 1, nx = t.nx, ny = t.ny;
    for (std::int64_t y = 0; y < wy; ++y) {
        const CoarseningCode* c = scratch.point.data() + y * w;
        CoarseningCode* o = scratch.triple.data() + y * half;
        for (std::int64_t x = 0; x < half; ++x)  // & and a select, not && (which kept the loop scalar)
            o[x] = static_cast<CoarseningCode>(c[2 * x] * ((c[2 * x] == c[2 * x + 1]) & (c[2 * x + 1] == c[2 * x + 2])));
    }
    for (std::int64_t y = 0; y < half; ++y) {
        const std::int64_t J = TJ * half + y;
        const CoarseningCode* c = scratch.triple.data() + 2 * y * half;  // rows 2y, 2y + 1, 2y + 2 of triples
        for (std::int64_t x = 0; x < half; ++x) {  // selects, not branches: a loop the compiler vectorises
            const std::int64_t I = TI * half + x;
            // Only a node whose points are all in the lattice (then all
            // computed; the others' triples are stale and ignored).
            const bool in = (2 * I + 2 <= nx) & (2 * J + 2 <= ny);
            const bool edge = (I == 0) | (J == 0) | (2 * I + 2 == nx) | (2 * J + 2 == ny);
            const CoarseningCode sg = static_cast<CoarseningCode>(c[x] * ((c[x] == c[x + half]) & (c[x + half] == c[x + 2 * half])));
            out[y * half + x] = static_cast<CoarseningCode>(sg * (in & !(edge & (sg < 0))));
        }
    }
}

// Levels 2 .. tiled.top of slot s (tile (TI, TJ)), each node from its four
// children in the same tile; a child outside the lattice's nodes counts as 0.
void coarser_tiled_codes(Quadtree& t, std::int64_t s, std::int64_t TI, std::int64_t TJ) {
    TileLevels& tl = t.tiled;
    for (int l = 2; l <= tl.top; ++l) {
        const std::size_t L = static_cast<std::size_t>(l);
        const std::int64_t n = std::int64_t{1} << tl.nodes_log(l), cx = t.nodes_x[L - 1], cy = t.nodes_y[L - 1];
        const CoarseningCode* child = tl.codes.data() + s * tl.slot_nodes + tl.level_offset[L - 1];
        CoarseningCode* o = tl.codes.data() + s * tl.slot_nodes + tl.level_offset[L];
        for (std::int64_t y = 0; y < n; ++y)
            for (std::int64_t x = 0; x < n; ++x) {
                const std::int64_t I = TI * n + x, J = TJ * n + y;
                const CoarseningCode* c = child + 2 * y * (2 * n) + 2 * x;
                const CoarseningCode v = c[0];
                const bool same = 2 * I + 1 < cx && 2 * J + 1 < cy && v != 0 && c[1] == v && c[2 * n] == v && c[2 * n + 1] == v;
                o[y * n + x] = same ? v : 0;
            }
    }
}

// The codes of every tiled level, tile by tile.  A tile with no sampled sign
// off the lattice border has every point non-critical with its σ: every node
// coarsenable with σ.
void tiled_codes(Quadtree& t, const TiledSigns& signs) {
    TileLevels& tl = t.tiled;
    const std::int64_t nslots = tl.slots(), TX = signs.tx, TY = signs.ty, T = signs.size();
#pragma omp parallel if (nslots >= parallel_min_tiles)
    {
        TileScratch scratch(T);
#pragma omp for schedule(dynamic, 16)
        for (std::int64_t s = 0; s < nslots; ++s) {
            const std::int64_t k = tl.tile_of_slot[static_cast<std::size_t>(s)], TI = k % TX, TJ = k / TX;
            const std::int32_t sampled = signs.slot[static_cast<std::size_t>(k)];
            CoarseningCode* level1 = tl.codes.data() + s * tl.slot_nodes + tl.level_offset[1];
            const bool border = TI == 0 || TJ == 0 || TI == TX - 1 || TJ == TY - 1;
            const CoarseningCode sigma = signs.uniform[static_cast<std::size_t>(k)];
            if (sampled < 0 && !border) {
                std::fill(level1, level1 + tl.slot_nodes - tl.level_offset[1], sigma);
                continue;
            }
            // Points of the tile inside the lattice: wx x wy.
            const std::int64_t w = T + 1, wx = std::min(w, t.nx - TI * T + 1), wy = std::min(w, t.ny - TJ * T + 1);
            if (sampled >= 0)
                point_codes(signs, signs.block(sampled), wx, wy, scratch.point.data());
            else
                for (std::int64_t y = 0; y < wy; ++y) std::fill_n(scratch.point.data() + y * w, wx, sigma);
            level1_codes(t, T, TI, TJ, wy, scratch, level1);
            coarser_tiled_codes(t, s, TI, TJ);
        }
    }
}

// The codes of the dense levels, each node from its four children (at most
// about one node per tile).  The first dense level above the tiles' level
// has one node per tile: its children are the 2 x 2 nodes of the slot's top
// level, or, in an inactive tile, all σ (never 0).
void dense_codes(Quadtree& t) {
    for (int l = t.tiled.top + 1; l <= t.top; ++l) {
        const std::size_t L = static_cast<std::size_t>(l);
        DenseLevel& level = t.dense[L];
        level.nodes_x = t.nodes_x[L], level.nodes_y = t.nodes_y[L];
        const std::int64_t mx = level.nodes_x, my = level.nodes_y, cx = t.nodes_x[L - 1], cy = t.nodes_y[L - 1];
        level.codes.assign(static_cast<std::size_t>(mx * my), 0);
        const bool tile_level = l == t.tiled.tile_log;
        assert(!tile_level || (mx * my == static_cast<std::int64_t>(t.tiled.slot_of_tile.size())));
#pragma omp parallel for schedule(static) if (mx * my >= parallel_min)
        for (std::int64_t J = 0; J < my; ++J) {
            if (2 * J + 1 >= cy) continue;
            for (std::int64_t I = 0; 2 * I + 1 < cx; ++I) {
                CoarseningCode v;
                if (tile_level) {
                    const std::size_t k = static_cast<std::size_t>(I + J * mx);
                    const std::int32_t s = t.tiled.slot_of_tile[k];
                    v = t.tiled.tile_code[k];
                    if (s >= 0) {
                        const CoarseningCode* c = t.tiled.codes.data() + s * t.tiled.slot_nodes + t.tiled.level_offset[L - 1];
                        v = c[0] != 0 && c[1] == c[0] && c[2] == c[0] && c[3] == c[0] ? c[0] : 0;
                    }
                } else {
                    v = t.code(l - 1, 2 * I, 2 * J);
                    const bool same = v != 0 && t.code(l - 1, 2 * I + 1, 2 * J) == v && t.code(l - 1, 2 * I, 2 * J + 1) == v &&
                                      t.code(l - 1, 2 * I + 1, 2 * J + 1) == v;
                    v = same ? v : 0;
                }
                level.codes[level.index(I, J)] = v;
            }
        }
    }
}

// ---- 4. inside classes: a class's nodes above its level -------------------------
// A node of level l with code c, cap_level(c) < l, becomes non-coarsenable
// (quadtree.hpp: the pyramid is kept).  Only active tiles are visited: an
// inactive tile's class has cap_level >= tiled.top (choose_active_tiles), so
// none of its stored levels is above it.
void cap_codes(Quadtree& t) {
    TileLevels& tl = t.tiled;
    const std::int64_t nslots = tl.slots();
#pragma omp parallel for schedule(static) if (nslots >= parallel_min_tiles)
    for (std::int64_t s = 0; s < nslots; ++s)
        for (int l = 1; l <= tl.top; ++l) {
            const std::int64_t n = std::int64_t{1} << tl.nodes_log(l);
            CoarseningCode* c = tl.codes.data() + s * tl.slot_nodes + tl.level_offset[static_cast<std::size_t>(l)];
            for (std::int64_t q = 0; q < n * n; ++q)
                if (cap_level(c[q]) < l) c[q] = 0;
        }
    for (int l = tl.top + 1; l <= t.top; ++l)
        for (CoarseningCode& c : t.dense[static_cast<std::size_t>(l)].codes)
            if (cap_level(c) < l) c = 0;
}

// ---- 5. grading: the non-coarsenable set widened -----------------------------
// With a buffer of n >= 1 nodes, an inside node (code -1, or an inside
// class) of level l becomes non-coarsenable (code 0) when a node of level l
// at Chebyshev distance <= n (in nodes of level l, nodes outside the
// lattice's nodes ignored) is not coarsenable in the codes of passes 3 and 4
// (a capped class's zeros included: sizes grow by at most G away from a
// capped material's small cells too).  Each level is widened from its own
// codes of pass 3, so the codes stay a pyramid (a coarsenable node's
// children are coarsenable with its sign): if a child's n-neighbourhood
// holds a non-coarsenable node N, N's parent is non-coarsenable and lies in
// the parent's n-neighbourhood.  Only zeros are added, so every coarse leaf
// still contains only non-critical points of its sign (the proof's
// invariant), and a coarse leaf of level l is farther than n 2^l squares
// (max-norm) from every critical point and every inside border square.
// Outside nodes (code +1) emit no triangle and are left as they are.
//
// The nodes of an inactive tile cannot change (they are not stored): with
// the tiles activated up to radius grading_tile_radius(n) around the seeds
// (non-coarsenable nodes of the tiled levels lie in seed tiles or next to
// them, and the widening reaches n 2^l <= n T / 2 squares), none needs to;
// returns the number of inactive inside tiles within reach of a widened node
// (0, or the radius is wrong).
// z: a (w + 2n) x (h + 2n) window of 0/1 flags, row-major; out[y w + x] = 1
// iff a flag is set within max-norm distance n of window cell (x + n, y + n).
// Separable, with running counts: O(window) work whatever n.
void dilate(const std::vector<std::uint8_t>& z, std::int64_t w, std::int64_t h, std::int64_t n, std::vector<std::int32_t>& rows,
            std::vector<std::uint8_t>& out) {
    const std::int64_t W = w + 2 * n, H = h + 2 * n;
    rows.assign(static_cast<std::size_t>(w * H), 0);  // rows[y w + x]: flags in row y, columns x .. x + 2n
    for (std::int64_t y = 0; y < H; ++y) {
        const std::uint8_t* r = z.data() + y * W;
        std::int32_t c = 0;
        for (std::int64_t d = 0; d < 2 * n; ++d) c += r[d];
        for (std::int64_t x = 0; x < w; ++x) {
            c += r[x + 2 * n];
            rows[static_cast<std::size_t>(y * w + x)] = c;
            c -= r[x];
        }
    }
    out.assign(static_cast<std::size_t>(w * h), 0);
    for (std::int64_t x = 0; x < w; ++x) {
        std::int32_t c = 0;
        for (std::int64_t d = 0; d < 2 * n; ++d) c += rows[static_cast<std::size_t>(d * w + x)];
        for (std::int64_t y = 0; y < h; ++y) {
            c += rows[static_cast<std::size_t>((y + 2 * n) * w + x)];
            out[static_cast<std::size_t>(y * w + x)] = c > 0;
            c -= rows[static_cast<std::size_t>(y * w + x)];
        }
    }
}

std::int64_t widen_codes(Quadtree& t, int n) {
    TileLevels& tl = t.tiled;
    const std::vector<CoarseningCode> before = tl.codes;  // pass 3's codes, read while tl.codes is written
    const std::int64_t T = std::int64_t{1} << tl.tile_log, TX = tl.tiles_x, TY = TX ? static_cast<std::int64_t>(tl.slot_of_tile.size()) / TX : 0;
    std::int64_t unreachable = 0;
    for (int l = 1; l <= tl.top; ++l) {
        const std::size_t L = static_cast<std::size_t>(l);
        const std::int64_t mx = t.nodes_x[L], my = t.nodes_y[L], m = std::int64_t{1} << tl.nodes_log(l), W = m + 2 * n;
        const std::int64_t reach = (n * (std::int64_t{1} << l) + T - 1) / T;  // in tiles
        // Whether node (I, J) of level l was non-coarsenable (nodes outside the lattice's nodes: no).
        auto zero = [&](std::int64_t I, std::int64_t J) -> std::uint8_t {
            if (I < 0 || J < 0 || I >= mx || J >= my) return 0;
            const std::int64_t k = tl.tile_of(l, I, J);
            const std::int32_t s = tl.slot_of_tile[static_cast<std::size_t>(k)];
            return (s < 0 ? tl.tile_code[static_cast<std::size_t>(k)] : before[static_cast<std::size_t>(tl.index(l, s, I, J))]) == 0;
        };
#pragma omp parallel if (tl.slots() >= parallel_min_tiles)
        {
            std::vector<std::uint8_t> window(static_cast<std::size_t>(W * W)), near;
            std::vector<std::int32_t> rows;
#pragma omp for schedule(dynamic, 16) reduction(+ : unreachable)
            for (std::int64_t s = 0; s < tl.slots(); ++s) {
                const std::int64_t k = tl.tile_of_slot[static_cast<std::size_t>(s)], TI = k % TX, TJ = k / TX;
                for (std::int64_t y = 0; y < W; ++y)
                    for (std::int64_t x = 0; x < W; ++x)
                        window[static_cast<std::size_t>(y * W + x)] = zero(TI * m - n + x, TJ * m - n + y);
                dilate(window, m, m, n, rows, near);
                bool has_zero = false;
                for (std::int64_t y = 0; y < m; ++y)
                    for (std::int64_t x = 0; x < m; ++x) {
                        const std::int64_t I = TI * m + x, J = TJ * m + y;
                        if (I >= mx || J >= my) continue;
                        const std::size_t at = static_cast<std::size_t>(tl.index(l, s, I, J));
                        has_zero = has_zero || before[at] == 0;
                        if (before[at] < 0 && near[static_cast<std::size_t>(y * m + x)]) tl.codes[at] = 0;
                    }
                if (!has_zero) continue;
                for (std::int64_t b = std::max<std::int64_t>(0, TJ - reach); b <= std::min(TY - 1, TJ + reach); ++b)
                    for (std::int64_t a = std::max<std::int64_t>(0, TI - reach); a <= std::min(TX - 1, TI + reach); ++a) {
                        const std::size_t q = static_cast<std::size_t>(a + b * TX);
                        unreachable += tl.slot_of_tile[q] < 0 && tl.tile_code[q] < 0;
                    }
            }
        }
    }
    for (int l = tl.top + 1; l <= t.top; ++l) {
        DenseLevel& level = t.dense[static_cast<std::size_t>(l)];
        const std::int64_t mx = level.nodes_x, my = level.nodes_y, W = mx + 2 * n;
        std::vector<std::uint8_t> window(static_cast<std::size_t>(W * (my + 2 * n)), 0), near;
        std::vector<std::int32_t> rows;
        for (std::int64_t J = 0; J < my; ++J)
            for (std::int64_t I = 0; I < mx; ++I)
                window[static_cast<std::size_t>((J + n) * W + I + n)] = level.codes[level.index(I, J)] == 0;
        dilate(window, mx, my, n, rows, near);
        for (std::int64_t J = 0; J < my; ++J)
            for (std::int64_t I = 0; I < mx; ++I)
                if (level.codes[level.index(I, J)] < 0 && near[static_cast<std::size_t>(J * mx + I)]) level.codes[level.index(I, J)] = 0;
    }
    return unreachable;
}

// ---- 6. split nodes, with 2:1 balance ----------------------------------------
// A node of level l >= 2 is split if it is not coarsenable, or if a split
// node of level l - 1 is its child or an edge neighbour of its child (the
// rule above).  Level 1 needs no pass (split iff code 0).

// Tiled level l: per active tile, its own split children of level l - 1
// (2n x 2n of them, n = T >> l, 2n <= 64: tile_log <= max_tile_log), a row of
// them per word.  A mark lands in the same tile unless the neighbour is
// across the tile's side; several threads may then mark one byte (relaxed
// atomic stores of 1).  Returns the number of marks that would land in an
// inactive tile (0, or the reach of balance is wrong).
std::int64_t balance_tiled_level(Quadtree& t, int l) {
    TileLevels& tl = t.tiled;
    const std::size_t L = static_cast<std::size_t>(l);
    const std::int64_t nslots = tl.slots(), TX = tl.tiles_x, cx = t.nodes_x[L - 1], cy = t.nodes_y[L - 1];
    const int h = tl.nodes_log(l);
    const std::int64_t n = std::int64_t{1} << h, cn = 2 * n;
    for (std::int64_t s = 0; s < nslots; ++s) {  // split where not coarsenable
        const std::int64_t base = s * tl.slot_nodes + tl.level_offset[L], sbase = tl.split_index(s, base);
        for (std::int64_t q = 0; q < n * n; ++q)
            tl.split[static_cast<std::size_t>(sbase + q)] = tl.codes[static_cast<std::size_t>(base + q)] == 0;
    }
    std::int64_t outside_active = 0;
#pragma omp parallel for schedule(static) reduction(+ : outside_active) if (nslots >= parallel_min_tiles)
    for (std::int64_t s = 0; s < nslots; ++s) {
        const std::int64_t TI = tl.column_of_slot[static_cast<std::size_t>(s)], TJ = tl.tile_of_slot[static_cast<std::size_t>(s)] / TX;
        std::uint8_t* own = tl.split.data() + tl.split_index(s, s * tl.slot_nodes + tl.level_offset[L]);
        auto mark = [&](std::int64_t I, std::int64_t J) {  // node (I, J) of level l, in another tile
            const std::int32_t o = tl.slot_of_tile[static_cast<std::size_t>((I >> h) + (J >> h) * TX)];
            if (o < 0) return void(++outside_active);
            std::atomic_ref<std::uint8_t>(tl.split[static_cast<std::size_t>(tl.split_index(o, tl.index(l, o, I, J)))])
                .store(1, std::memory_order_relaxed);
        };
        // The tile's children that exist (columns A < cx, rows B < cy).
        const std::int64_t A0 = TI * cn, B0 = TJ * cn, wa = std::min(cn, cx - A0), hb = std::min(cn, cy - B0);
        const std::uint64_t cexist = bits::low_bits(wa);
        std::array<std::uint64_t, bits::word_bits + 2> C;  // child row b at C[b + 1]; rows -1 and hb .. cn are 0
        std::uint64_t any = 0;
        for (std::int64_t b = 0; b < hb; ++b)
            any |= C[static_cast<std::size_t>(b) + 1] = tl.split_bits(l - 1, s, s * tl.slot_nodes + tl.level_offset[L - 1] + b * cn, cn) & cexist;
        if (!any) continue;
        C[0] = 0;
        std::fill(C.begin() + hb + 1, C.begin() + cn + 2, 0);
        // Marks inside the tile, by shifts: node (X, Y) is marked by a split
        // child in rows 2Y, 2Y + 1 and columns 2X - 1 .. 2X + 2 (its own
        // children and the children beside them, which mark it as their
        // parent's edge neighbour), or in rows 2Y - 1, 2Y + 2 and columns 2X,
        // 2X + 1.
        const std::uint64_t row_nodes = bits::low_bits(n);
        for (std::int64_t Y = 0; Y < n; ++Y) {
            const std::size_t y0 = static_cast<std::size_t>(2 * Y) + 1;  // C index of row 2Y
            const std::uint64_t H = C[y0] | C[y0 + 1], V = C[y0 - 1] | C[y0 + 2];
            // Bit 2X: columns 2X - 1 .. 2X + 2 of H, columns 2X, 2X + 1 of V.
            bits::for_each_bit(bits::even_bits(H | H >> 1 | H << 1 | H >> 2 | V | V >> 1) & row_nodes, [&](int X) {
                std::uint8_t& b = own[static_cast<std::size_t>((Y << h) + X)];
                if (!b) std::atomic_ref<std::uint8_t>(b).store(1, std::memory_order_relaxed);
            });
        }
        // Marks across the tile's sides, from its border children, one by one.
        for (std::int64_t b = 0; b < hb; ++b) {
            const std::uint64_t r = C[static_cast<std::size_t>(b) + 1];
            if ((r & 1) && A0 > 0) mark((A0 - 1) >> 1, (B0 + b) >> 1);
            if (((r >> (wa - 1)) & 1) && A0 + wa < cx) mark((A0 + wa) >> 1, (B0 + b) >> 1);
        }
        if (B0 > 0) bits::for_each_bit(C[1], [&](int a) { mark((A0 + a) >> 1, (B0 - 1) >> 1); });
        if (B0 + hb < cy) bits::for_each_bit(C[static_cast<std::size_t>(hb)], [&](int a) { mark((A0 + a) >> 1, (B0 + hb) >> 1); });
    }
    return outside_active;
}

// Dense level l: row J is written only by iteration J, which reads child
// rows 2J - 1 .. 2J + 2 (race-free).
void balance_dense_level(Quadtree& t, int l) {
    const std::size_t L = static_cast<std::size_t>(l);
    DenseLevel& level = t.dense[L];
    const std::int64_t mx = level.nodes_x, my = level.nodes_y, cx = t.nodes_x[L - 1], cy = t.nodes_y[L - 1];
    level.split.resize(static_cast<std::size_t>(mx * my));
    for (std::size_t k = 0; k < level.split.size(); ++k) level.split[k] = level.codes[k] == 0;
#pragma omp parallel for schedule(static) if (mx * my >= parallel_min)
    for (std::int64_t J = 0; J < my; ++J) {
        auto mark = [&](std::int64_t I) { level.split[level.index(I, J)] = 1; };
        for (std::int64_t r = std::max<std::int64_t>(0, 2 * J - 1); r <= std::min(cy - 1, 2 * J + 2); ++r)
            t.visit(l - 1, [&](const auto& children) {
                children.for_each_split(r, [&](std::int64_t a) {
                    if ((r >> 1) == J) {
                        mark(a >> 1);  // (its own parent: not a leaf either)
                        if (a > 0) mark((a - 1) >> 1);
                        if (a + 1 < cx) mark((a + 1) >> 1);
                    }
                    if (r > 0 && ((r - 1) >> 1) == J) mark(a >> 1);
                    if (r + 1 < cy && ((r + 1) >> 1) == J) mark(a >> 1);
                });
            });
    }
}

}  // namespace

std::int64_t grading_tile_radius(int buffer) { return buffer == 0 ? 1 : 2 + (buffer + 1) / 2; }

Quadtree build_quadtree(const Lattice& lattice, const TiledSigns& signs, std::span<const WarpedPoint> warped,
                        std::int64_t max_cell, int buffer, bool classes) {
    if (max_cell < 0 || (max_cell != 0 && !std::has_single_bit(static_cast<std::uint64_t>(max_cell))))
        throw std::invalid_argument("max cell size must be 0 or a power of two, got " + std::to_string(max_cell));
    if (buffer < 0 || buffer > max_grading_buffer)
        throw std::invalid_argument("grading buffer must be 0 to " + std::to_string(max_grading_buffer) + ", got " +
                                    std::to_string(buffer));
    if (lattice.nx >= INT32_MAX || lattice.ny >= INT32_MAX)
        throw std::length_error("lattice too large for the graded mesher");
    if (signs.tile_log > max_tile_log)
        throw std::invalid_argument("the quadtree needs tiles of at most " + std::to_string(1 << max_tile_log) +
                                    " squares, got tile_log " + std::to_string(signs.tile_log));
    Quadtree t;
    const std::int64_t nx = lattice.nx, ny = lattice.ny;
    t.nx = nx, t.ny = ny;
    // Roots: the smallest power of two covering the lattice, capped by K.
    int cover = 0;
    while ((std::int64_t{1} << cover) < std::max(nx, ny)) ++cover;
    t.top = max_cell == 0 ? cover : std::min(cover, std::countr_zero(static_cast<std::uint64_t>(max_cell)));
    t.nodes_x.resize(static_cast<std::size_t>(t.top) + 1);
    t.nodes_y.resize(static_cast<std::size_t>(t.top) + 1);
    for (int l = 0; l <= t.top; ++l) {
        t.nodes_x[static_cast<std::size_t>(l)] = (nx + (std::int64_t{1} << l) - 1) >> l;
        t.nodes_y[static_cast<std::size_t>(l)] = (ny + (std::int64_t{1} << l) - 1) >> l;
    }
    t.dense.resize(static_cast<std::size_t>(t.top) + 1);

    t.warped = warped_points(lattice, warped);
    if (t.top == 0) return t;
    choose_active_tiles(t.tiled, signs, t.top, grading_tile_radius(buffer));
    tiled_codes(t, signs);
    dense_codes(t);
    if (classes) cap_codes(t);
    if (buffer > 0 && widen_codes(t, buffer) != 0)
        throw std::logic_error("quadtree: the grading buffer reached an inactive tile");
    std::int64_t outside_active = 0;
    for (int l = 2; l <= t.top; ++l) {  // level l is final once level l - 1 is
        if (t.is_tiled(l))
            outside_active += balance_tiled_level(t, l);
        else
            balance_dense_level(t, l);
    }
    if (outside_active) throw std::logic_error("quadtree: 2:1 balance reached an inactive tile");
#ifndef NDEBUG
    // The invariant the angle proof rests on (quadtree.hpp); O(lattice), debug only.
    {
        const QuadtreeCheck chk = check_quadtree(t, signs);
        assert(chk.ok());
    }
#endif
    return t;
}

}  // namespace warpmesh
