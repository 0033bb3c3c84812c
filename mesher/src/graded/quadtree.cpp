// quadtree.cpp — the graded mesher's balanced quadtree (graded.hpp).
//
// Passes, bottom-up, with no pointers and no Morton codes — a node's parent
// is (i >> 1, j >> 1), its children (2i + a, 2j + b):
//
//  1. the set of warped points (a bitset with ranks);
//  2. the active tiles (graded.hpp): tiles with sampled signs or on the
//     lattice border, and their eight neighbours;
//  3. the coarsenability pyramid `sign` (see graded.hpp): level 1 from the
//     signs (a point is critical when f = 0 there or a 4-neighbour has the
//     strictly opposite sign — exactly the endpoints of cut edges), then each
//     level from its children; per active tile below the tiles' level, dense
//     above;
//  4. `split`, bottom-up: a node is split when it is not coarsenable, or when
//     2:1 balance demands it;
// and, on demand, the leaf list (quadtree_leaves): the finest leaves as their
// split level-1 parents, the coarse leaves level by level.  On the per-tile
// levels, pass 4 and the leaf list work on a tile's rows of nodes as words of
// bits (tile_log <= 7: a row of level-1 nodes fits in 64 bits).
// Work and memory are proportional to the active tiles plus the dense levels'
// nodes (at most 4/3 per tile): O(boundary), not O(lattice), apart from a few
// bytes per tile and the warped points' block flags (PointSet).
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
// is final once level l is.  Pass 4 applies it level by level: on a per-tile
// level each active tile marks from its own split children (a mark only sets
// a byte to 1, so concurrent marks across a tile side commute: relaxed atomic
// stores); on a dense level row J of level l + 1 is written only by the
// iteration for J, which reads the split nodes of rows 2J - 1 .. 2J + 2 of
// level l.  Either way the result is independent of the thread count.
#include <algorithm>
#include <atomic>
#include <bit>
#include <cassert>
#include <cstring>
#include <stdexcept>
#include <numeric>
#include <string>

#include "graded/quadtree.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh {
namespace {

// Calls fn(i) for every i < n with row[i] != 0 (Zero = false) or == 0 (Zero =
// true), skipping eight uninteresting bytes at a time: split nodes are sparse
// (they follow the level set), so the scans cost a fraction of a pass.
template <bool Zero, class T, class Fn>
inline void for_each_byte(const T* row, std::int64_t n, Fn&& fn) {
    static_assert(sizeof(T) == 1);
    constexpr std::uint64_t ones = 0x0101010101010101ull, highs = 0x8080808080808080ull;
    std::int64_t i = 0;
    for (; i + 8 <= n; i += 8) {
        std::uint64_t word;
        std::memcpy(&word, row + i, 8);
        const bool any = Zero ? ((word - ones) & ~word & highs) != 0 : word != 0;  // a zero byte / a non-zero byte
        if (!any) continue;
        for (std::int64_t q = i; q < i + 8; ++q)
            if ((row[q] == 0) == Zero) fn(q);
    }
    for (; i < n; ++i)
        if ((row[i] == 0) == Zero) fn(i);
}

// fn(q) for every split node among n consecutive nodes of a row of per-tile
// level l >= 1 in slot s, the first at index `first` of local_sign: level 1
// is split where not coarsenable (code 0), higher levels by their flag.
template <class Fn>
inline void for_each_split_in_run(const Quadtree& t, int l, std::int64_t s, std::int64_t first, std::int64_t n, Fn&& fn) {
    if (l == 1)
        for_each_byte<true>(t.local_sign.data() + first, n, fn);
    else
        for_each_byte<false>(t.local_split.data() + t.split_of_local(s, first), n, fn);
}

// fn(i) for every split node i of row j of level l >= 1, in increasing i.
template <class Fn>
inline void for_each_split(const Quadtree& t, int l, std::int64_t j, Fn&& fn) {
    const std::size_t L = static_cast<std::size_t>(l);
    const std::int64_t mx = t.nodes_x[L];
    if (l > t.local_top) return for_each_byte<false>(t.split[L].data() + j * mx, mx, fn);
    // A per-tile level: only active tiles have split nodes; those of tile row
    // TJ are the slots row_start[TJ] .. row_start[TJ + 1] - 1, left to right.
    // Level 1 is split where not coarsenable (code 0).
    const int h = t.tile_log - l;
    const std::int64_t TJ = j >> h;
    for (std::int64_t s = t.row_start[static_cast<std::size_t>(TJ)]; s < t.row_start[static_cast<std::size_t>(TJ) + 1]; ++s) {
        const std::int64_t I0 = t.active_x[static_cast<std::size_t>(s)] << h;
        const std::int64_t base = t.local_index(l, s, I0, j), n = std::min(std::int64_t{1} << h, mx - I0);
        for_each_split_in_run(t, l, s, base, n, [&](std::int64_t q) { fn(I0 + q); });
    }
}

// The split flags of n (a power of two, <= 64) consecutive nodes of a row of
// per-tile level l in slot s, from index `first` of local_sign, as bits: level
// 1 is split where its code is 0, higher levels where their flag is not.  Eight
// bytes at a time: a byte's high bit, after adding 0x7f to its low seven bits
// and or-ing the byte itself, is set iff the byte is non-zero (no carry leaves
// the byte), and a multiply gathers the eight high bits.
inline std::uint64_t split_row(const Quadtree& t, int l, std::int64_t s, std::int64_t first, std::int64_t n) {
    if (n < 8) {
        std::uint64_t b = 0;
        for (std::int64_t x = 0; x < n; ++x) b |= static_cast<std::uint64_t>(t.local_is_split(l, s, first + x)) << x;
        return b;
    }
    const std::uint8_t* p = l == 1 ? reinterpret_cast<const std::uint8_t*>(t.local_sign.data()) + first
                                   : t.local_split.data() + t.split_of_local(s, first);
    constexpr std::uint64_t low7 = 0x7f7f7f7f7f7f7f7full, highs = 0x8080808080808080ull;
    std::uint64_t b = 0;
    for (std::int64_t x = 0; x < n; x += 8) {
        std::uint64_t w;
        std::memcpy(&w, p + x, 8);
        std::uint64_t nonzero = (((w & low7) + low7) | w) & highs;
        if (l == 1) nonzero ^= highs;  // split: code 0
        b |= ((nonzero >> 7) * 0x0102040810204080ull >> 56) << x;
    }
    return b;
}

// Bits 0 .. n - 1 set, 0 <= n <= 64 (a shift by 64 would be undefined).
inline std::uint64_t low_bits(std::int64_t n) { return n >= 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << n) - 1; }

// Bit k of x < 2^32 to bits 2k and 2k + 1.
inline std::uint64_t spread_bits(std::uint64_t x) {
    x &= 0xffffffffull;
    x = (x | x << 16) & 0x0000ffff0000ffffull;
    x = (x | x << 8) & 0x00ff00ff00ff00ffull;
    x = (x | x << 4) & 0x0f0f0f0f0f0f0f0full;
    x = (x | x << 2) & 0x3333333333333333ull;
    x = (x | x << 1) & 0x5555555555555555ull;
    return x | x << 1;
}

// Bits 0, 2, 4, ... of x to bits 0, 1, 2, ... (the inverse of spread_bits).
inline std::uint64_t compress_even(std::uint64_t x) {
    x &= 0x5555555555555555ull;
    x = (x | x >> 1) & 0x3333333333333333ull;
    x = (x | x >> 2) & 0x0f0f0f0f0f0f0f0full;
    x = (x | x >> 4) & 0x00ff00ff00ff00ffull;
    x = (x | x >> 8) & 0x0000ffff0000ffffull;
    x = (x | x >> 16) & 0x00000000ffffffffull;
    return x;
}

// Below this many nodes a level is done by one thread: a parallel region costs
// more than the loop.
constexpr std::int64_t parallel_min = std::int64_t{1} << 16;

}  // namespace

Quadtree build_quadtree(const Lattice& lattice, const TiledSigns& signs, std::span<const WarpedPoint> warped,
                        std::int64_t max_cell) {
    if (max_cell < 0 || (max_cell != 0 && !std::has_single_bit(static_cast<std::uint64_t>(max_cell))))
        throw std::invalid_argument("max cell size must be 0 or a power of two, got " + std::to_string(max_cell));
    if (lattice.nx >= INT32_MAX || lattice.ny >= INT32_MAX)
        throw std::length_error("lattice too large for the graded mesher");
    if (signs.tile_log > 7)  // a row of a tile's level-1 nodes must fit in a 64-bit word
        throw std::invalid_argument("the quadtree needs tiles of at most 128 squares, got tile_log " + std::to_string(signs.tile_log));
    Quadtree t;
    const std::int64_t nx = lattice.nx, ny = lattice.ny, nxp = nx + 1;
    t.nx = nx, t.ny = ny;
    // Roots: the smallest power of two covering the lattice, capped by K.
    int cover = 0;
    while ((std::int64_t{1} << cover) < std::max(nx, ny)) ++cover;
    t.top = max_cell == 0 ? cover : std::min(cover, std::countr_zero(static_cast<std::uint64_t>(max_cell)));

    // ---- 1. the warped points ----------------------------------------------------
    t.warped = PointSet(nxp, ny + 1);
    // `warped` is sorted by point, so the row only advances: no division per
    // point (a 64-bit divide costs tens of cycles, and this ran at one per point).
    {
        std::int64_t j = 0, row0 = 0;  // row0 = j * nxp
        for (const WarpedPoint& w : warped) {
            assert(w.p >= row0);
            while (w.p - row0 >= nxp) ++j, row0 += nxp;
            t.warped.insert(w.p - row0, j);
        }
    }
    t.warped.finish();

    t.nodes_x.assign(static_cast<std::size_t>(t.top) + 1, 0);
    t.nodes_y.assign(static_cast<std::size_t>(t.top) + 1, 0);
    t.sign.resize(static_cast<std::size_t>(t.top) + 1);
    t.split.resize(static_cast<std::size_t>(t.top) + 1);
    t.nodes_x[0] = nx, t.nodes_y[0] = ny;
    for (int l = 1; l <= t.top; ++l) {
        t.nodes_x[static_cast<std::size_t>(l)] = (nx + (std::int64_t{1} << l) - 1) >> l;
        t.nodes_y[static_cast<std::size_t>(l)] = (ny + (std::int64_t{1} << l) - 1) >> l;
    }
    if (t.top == 0) return t;
    // ---- 2. the active tiles ------------------------------------------------------
    const std::int64_t TX = signs.tx, TY = signs.ty, ntiles = TX * TY, T = signs.size();
    t.tile_log = signs.tile_log, t.tiles_x = TX;
    t.local_top = std::min(signs.tile_log - 1, t.top);
    t.tile_sign = signs.uniform;
    {
        // Seeds, then their 3 x 3 dilation: along rows, then across.
        std::vector<std::uint8_t> seed(static_cast<std::size_t>(ntiles)), wide(static_cast<std::size_t>(ntiles));
        for (std::int64_t TJ = 0; TJ < TY; ++TJ)
            for (std::int64_t TI = 0; TI < TX; ++TI)
                seed[static_cast<std::size_t>(TI + TJ * TX)] = signs.slot[static_cast<std::size_t>(TI + TJ * TX)] >= 0 ||
                                                               TI == 0 || TJ == 0 || TI == TX - 1 || TJ == TY - 1;
        for (std::int64_t TJ = 0; TJ < TY; ++TJ) {
            const std::uint8_t* r = seed.data() + TJ * TX;
            std::uint8_t* o = wide.data() + TJ * TX;
            for (std::int64_t TI = 0; TI < TX; ++TI)
                o[TI] = r[TI] | (TI > 0 ? r[TI - 1] : 0) | (TI + 1 < TX ? r[TI + 1] : 0);
        }
        t.tile_slot.assign(static_cast<std::size_t>(ntiles), -1);
        t.row_start.assign(static_cast<std::size_t>(TY) + 1, 0);
        for (std::int64_t TJ = 0; TJ < TY; ++TJ) {
            t.row_start[static_cast<std::size_t>(TJ)] = static_cast<std::int64_t>(t.active.size());
            const std::uint8_t* mid = wide.data() + TJ * TX;
            const std::uint8_t* below = TJ > 0 ? mid - TX : mid;
            const std::uint8_t* above = TJ + 1 < TY ? mid + TX : mid;
            for (std::int64_t TI = 0; TI < TX; ++TI) {
                if (!(below[TI] | mid[TI] | above[TI])) continue;
                t.tile_slot[static_cast<std::size_t>(TI + TJ * TX)] = static_cast<std::int32_t>(t.active.size());
                t.active.push_back(TI + TJ * TX);
                t.active_x.push_back(TI);
            }
        }
        t.row_start[static_cast<std::size_t>(TY)] = static_cast<std::int64_t>(t.active.size());
        t.local_offset.assign(static_cast<std::size_t>(t.local_top) + 1, 0);
        t.local_size = 0;
        for (int l = 1; l <= t.local_top; ++l) {
            t.local_offset[static_cast<std::size_t>(l)] = t.local_size;
            t.local_size += (T >> l) * (T >> l);
        }
        const std::size_t n = t.active.size() * static_cast<std::size_t>(t.local_size);
        t.local_sign.resize(n);
        t.level1 = t.local_top >= 1 ? (T >> 1) * (T >> 1) : 0;
        t.local_split.resize(t.active.size() * static_cast<std::size_t>(t.local_size - t.level1));  // written in pass 4
    }
    const std::int64_t nslots = static_cast<std::int64_t>(t.active.size());
    // ---- 3. the coarsenability pyramid -------------------------------------------
    // Per active tile, level 1 from the tile's points: their signs if sampled
    // (a point's code is its sign if it is not critical — not 0, no
    // 4-neighbour of the opposite sign: the signs' ring holds the neighbours
    // beyond the tile, 0 outside the lattice, which never makes a point
    // critical — else 0), or the tile's σ for every point; a node takes the
    // common code of its 3 x 3 points.  A node partly outside the lattice is
    // never a leaf, and an inside node on the lattice border is not
    // coarsenable (its border squares stay finest, as in the uniform mesh).
    // Then levels 2 .. local_top, each node from its four children (in the
    // same tile; a child outside the lattice's nodes counts as 0).
#pragma omp parallel if (nslots >= 256)
    {
        // Per thread: the codes of a tile's (T + 1)^2 points, and per row of
        // points the common code of each horizontal triple (2x, 2x + 1, 2x + 2)
        // (0 if they differ): a node's 3 x 3 points agree iff the triples of
        // its three rows do.
        std::vector<std::int8_t> code(static_cast<std::size_t>((T + 1) * (T + 1))), triple(static_cast<std::size_t>((T + 1) * (T / 2)));
        const std::int64_t w = T + 1, S = signs.stride();
#pragma omp for schedule(dynamic, 16)
        for (std::int64_t s = 0; s < nslots; ++s) {
            const std::int64_t k = t.active[static_cast<std::size_t>(s)], TI = k % TX, TJ = k / TX;
            const std::int32_t sslot = signs.slot[static_cast<std::size_t>(k)];
            const std::int8_t* blk = sslot >= 0 ? signs.block(sslot) : nullptr;
            const std::int64_t i0 = TI * T, j0 = TJ * T;
            const std::int64_t half = T / 2;
            std::int8_t* out = t.local_sign.data() + s * t.local_size + t.local_offset[1];
            const bool border = TI == 0 || TJ == 0 || TI == TX - 1 || TJ == TY - 1;
            const std::int8_t sigma = signs.uniform[static_cast<std::size_t>(k)];
            if (!blk && !border) {  // every point non-critical with σ: every node coarsenable with σ
                std::fill(out, out + t.local_size - t.local_offset[1], sigma);
                continue;
            }
            // Points of the tile inside the lattice: wx x wy.
            const std::int64_t wx = std::min(w, nx - i0 + 1), wy = std::min(w, ny - j0 + 1);
            if (blk) {
                for (std::int64_t y = 0; y < wy; ++y) {
                    const std::int8_t* c = blk + (y + 1) * S + 1;
                    std::int8_t* o = code.data() + y * w;
#pragma omp simd
                    for (std::int64_t x = 0; x < wx; ++x) {
                        const std::int8_t v = c[x], opp = static_cast<std::int8_t>(-v);
                        const bool critical = (v == 0) | (c[x - 1] == opp) | (c[x + 1] == opp) | (c[x - S] == opp) | (c[x + S] == opp);
                        o[x] = critical ? std::int8_t{0} : v;
                    }
                }
            } else {
                for (std::int64_t y = 0; y < wy; ++y) std::fill_n(code.data() + y * w, wx, sigma);
            }
            for (std::int64_t y = 0; y < wy; ++y) {
                const std::int8_t* c = code.data() + y * w;
                std::int8_t* o = triple.data() + y * half;
                for (std::int64_t x = 0; x < half; ++x)  // & and a select, not && (which kept the loop scalar)
                    o[x] = static_cast<std::int8_t>(c[2 * x] * ((c[2 * x] == c[2 * x + 1]) & (c[2 * x + 1] == c[2 * x + 2])));
            }
            for (std::int64_t y = 0; y < half; ++y) {
                const std::int64_t J = TJ * half + y;
                const std::int8_t* c = triple.data() + 2 * y * half;  // rows 2y, 2y + 1, 2y + 2 of triples
                for (std::int64_t x = 0; x < half; ++x) {  // selects, not branches: a loop the compiler vectorises
                    const std::int64_t I = TI * half + x;
                    // Only a node whose points are all in the lattice (then all
                    // computed; the others' triples are stale and ignored);
                    // an inside one on the lattice border is not coarsenable.
                    const bool in = (2 * I + 2 <= nx) & (2 * J + 2 <= ny);
                    const bool edge = (I == 0) | (J == 0) | (2 * I + 2 == nx) | (2 * J + 2 == ny);
                    const std::int8_t sg = static_cast<std::int8_t>(c[x] * ((c[x] == c[x + half]) & (c[x + half] == c[x + 2 * half])));
                    out[y * half + x] = static_cast<std::int8_t>(sg * (in & !(edge & (sg < 0))));
                }
            }
            for (int l = 2; l <= t.local_top; ++l) {
                const std::int64_t n = T >> l, cx = t.nodes_x[static_cast<std::size_t>(l) - 1],
                                   cy = t.nodes_y[static_cast<std::size_t>(l) - 1];
                const std::int8_t* child = t.local_sign.data() + s * t.local_size + t.local_offset[static_cast<std::size_t>(l) - 1];
                std::int8_t* o = t.local_sign.data() + s * t.local_size + t.local_offset[static_cast<std::size_t>(l)];
                for (std::int64_t y = 0; y < n; ++y)
                    for (std::int64_t x = 0; x < n; ++x) {
                        const std::int64_t I = TI * n + x, J = TJ * n + y;
                        const std::int8_t* c = child + 2 * y * (2 * n) + 2 * x;
                        const std::int8_t v = c[0];
                        const bool same = 2 * I + 1 < cx && 2 * J + 1 < cy && v != 0 && c[1] == v && c[2 * n] == v &&
                                          c[2 * n + 1] == v;
                        o[y * n + x] = same ? v : 0;
                    }
            }
        }
    }
    // Dense levels: at most about one node per tile, read through node_sign.
    for (int l = t.local_top + 1; l <= t.top; ++l) {
        const std::size_t L = static_cast<std::size_t>(l);
        const std::int64_t mx = t.nodes_x[L], my = t.nodes_y[L], cx = t.nodes_x[L - 1], cy = t.nodes_y[L - 1];
        auto& sg = t.sign[L];
        sg.assign(static_cast<std::size_t>(mx * my), 0);
        assert(l != t.tile_log || (mx == TX && my == TY));
#pragma omp parallel for schedule(static) if (mx * my >= parallel_min)
        for (std::int64_t J = 0; J < my; ++J) {
            if (2 * J + 1 >= cy) continue;
            for (std::int64_t I = 0; 2 * I + 1 < cx; ++I) {
                if (l == t.tile_log) {
                    // One node per tile: its children are the 2 x 2 nodes of the
                    // slot's last level, or, in an inactive tile, all σ (never 0).
                    const std::int32_t s = t.tile_slot[static_cast<std::size_t>(I + J * TX)];
                    std::int8_t v = t.tile_sign[static_cast<std::size_t>(I + J * TX)];
                    if (s >= 0) {
                        const std::int8_t* c = t.local_sign.data() + s * t.local_size + t.local_offset[L - 1];
                        v = c[0] != 0 && c[1] == c[0] && c[2] == c[0] && c[3] == c[0] ? c[0] : 0;
                    }
                    sg[static_cast<std::size_t>(I + J * mx)] = v;
                    continue;
                }
                const std::int8_t v = t.node_sign(l - 1, 2 * I, 2 * J);
                const bool same = v != 0 && t.node_sign(l - 1, 2 * I + 1, 2 * J) == v &&
                                  t.node_sign(l - 1, 2 * I, 2 * J + 1) == v && t.node_sign(l - 1, 2 * I + 1, 2 * J + 1) == v;
                sg[static_cast<std::size_t>(I + J * mx)] = same ? v : 0;
            }
        }
    }
    // ---- 4. split nodes, with 2:1 balance ---------------------------------------
    // Level 1: split iff not coarsenable (code 0).  Levels >= 2: first split
    // iff not coarsenable, then, for every split node (a, r) of level l - 1,
    // split its parent and the parents of its existing edge neighbours.  Level
    // l is final once level l - 1 is, so the levels go in order; within a
    // level the marks only set bytes to 1, so their order does not matter.
    // A parent in an inactive tile would contradict the reach of balance
    // (graded.hpp): checked, not assumed.
    std::int64_t outside_active = 0;
    for (int l = 2; l <= t.top; ++l) {
        const std::size_t L = static_cast<std::size_t>(l);
        const std::int64_t mx = t.nodes_x[L], my = t.nodes_y[L], cx = t.nodes_x[L - 1], cy = t.nodes_y[L - 1];
        if (l <= t.local_top) {
            // Per-tile level: per active tile, its own split children of level
            // l - 1 (2n x 2n of them, n = T >> l, 2n <= 64: tile_log <= 7).
            // A mark lands in the same tile unless the neighbour is across the
            // tile's side; several threads may then mark one byte (relaxed
            // atomic stores of 1).
            const int h = t.tile_log - l;
            const std::int64_t n = std::int64_t{1} << h, cn = 2 * n;
            for (std::int64_t s = 0; s < nslots; ++s) {
                const std::int64_t base = s * t.local_size + t.local_offset[L];
                const std::int64_t sbase = t.split_of_local(s, base);
                for (std::int64_t q = 0; q < n * n; ++q)
                    t.local_split[static_cast<std::size_t>(sbase + q)] = t.local_sign[static_cast<std::size_t>(base + q)] == 0;
            }
#pragma omp parallel for schedule(static) reduction(+ : outside_active) if (nslots >= 256)
            for (std::int64_t s = 0; s < nslots; ++s) {
                const std::int64_t TI = t.active_x[static_cast<std::size_t>(s)], TJ = t.active[static_cast<std::size_t>(s)] / TX;
                std::uint8_t* own = t.local_split.data() + t.split_of_local(s, s * t.local_size + t.local_offset[L]);
                auto mark = [&](std::int64_t I, std::int64_t J) {  // node (I, J) of level l, in another tile
                    const std::int32_t o = t.tile_slot[static_cast<std::size_t>((I >> h) + (J >> h) * TX)];
                    if (o < 0) return void(++outside_active);
                    std::atomic_ref<std::uint8_t>(t.local_split[static_cast<std::size_t>(t.split_index(l, o, I, J))])
                        .store(1, std::memory_order_relaxed);
                };
                // The tile's children of level l - 1 that exist (columns A <
                // cx, rows B < cy), a row of them per word.  Their marks inside
                // the tile by shifts: node (X, Y) is marked by a split child in
                // rows 2Y, 2Y + 1 and columns 2X - 1 .. 2X + 2 (its own
                // children and the children beside them that mark it as their
                // parent's edge neighbour), or in rows 2Y - 1, 2Y + 2 and
                // columns 2X, 2X + 1.  Marks across the tile's sides, from its
                // border children, one by one.
                const std::int64_t A0 = TI * cn, B0 = TJ * cn, wa = std::min(cn, cx - A0), hb = std::min(cn, cy - B0);
                const std::uint64_t cexist = low_bits(wa);
                std::array<std::uint64_t, 66> C;  // child row b at C[b + 1]; rows -1 and hb .. cn are 0
                std::uint64_t any = 0;
                for (std::int64_t b = 0; b < hb; ++b)
                    any |= C[static_cast<std::size_t>(b) + 1] =
                        split_row(t, l - 1, s, s * t.local_size + t.local_offset[L - 1] + b * cn, cn) & cexist;
                if (!any) continue;
                C[0] = 0;
                std::fill(C.begin() + hb + 1, C.begin() + cn + 2, 0);
                const std::uint64_t row_nodes = low_bits(n);
                for (std::int64_t Y = 0; Y < n; ++Y) {
                    const std::size_t y0 = static_cast<std::size_t>(2 * Y) + 1;  // C index of row 2Y
                    const std::uint64_t H = C[y0] | C[y0 + 1], V = C[y0 - 1] | C[y0 + 2];
                    // Bit 2X: columns 2X - 1 .. 2X + 2 of H, columns 2X, 2X + 1 of V.
                    std::uint64_t marked = compress_even(H | H >> 1 | H << 1 | H >> 2 | V | V >> 1) & row_nodes;
                    for (; marked; marked &= marked - 1) {
                        std::uint8_t& b = own[static_cast<std::size_t>((Y << h) + std::countr_zero(marked))];
                        if (!b) std::atomic_ref<std::uint8_t>(b).store(1, std::memory_order_relaxed);
                    }
                }
                for (std::int64_t b = 0; b < hb; ++b) {
                    const std::uint64_t r = C[static_cast<std::size_t>(b) + 1];
                    if ((r & 1) && A0 > 0) mark((A0 - 1) >> 1, (B0 + b) >> 1);
                    if (((r >> (wa - 1)) & 1) && A0 + wa < cx) mark((A0 + wa) >> 1, (B0 + b) >> 1);
                }
                for (std::uint64_t r = B0 > 0 ? C[1] : 0; r; r &= r - 1) mark((A0 + std::countr_zero(r)) >> 1, (B0 - 1) >> 1);
                for (std::uint64_t r = B0 + hb < cy ? C[static_cast<std::size_t>(hb)] : 0; r; r &= r - 1)
                    mark((A0 + std::countr_zero(r)) >> 1, (B0 + hb) >> 1);
            }
            continue;
        }
        // Dense level: row J of level l is written only by iteration J, which
        // reads child rows 2J - 1 .. 2J + 2 (race-free).
        auto& sp = t.split[L];
        const auto& sg = t.sign[L];
        sp.resize(static_cast<std::size_t>(mx * my));
        for (std::int64_t k = 0; k < mx * my; ++k) sp[static_cast<std::size_t>(k)] = sg[static_cast<std::size_t>(k)] == 0;
#pragma omp parallel for schedule(static) if (t.nodes(l) >= parallel_min)
        for (std::int64_t J = 0; J < my; ++J) {
            for (std::int64_t r = std::max<std::int64_t>(0, 2 * J - 1); r <= std::min(cy - 1, 2 * J + 2); ++r)
                for_each_split(t, l - 1, r, [&](std::int64_t a) {
                    auto mark = [&](std::int64_t I) { sp[static_cast<std::size_t>(I + J * mx)] = 1; };
                    if ((r >> 1) == J) {
                        mark(a >> 1);  // (its own parent: not a leaf either)
                        if (a > 0) mark((a - 1) >> 1);
                        if (a + 1 < cx) mark((a + 1) >> 1);
                    }
                    if (r > 0 && ((r - 1) >> 1) == J) mark(a >> 1);
                    if (r + 1 < cy && ((r + 1) >> 1) == J) mark(a >> 1);
                });
        }
    }
    if (outside_active) throw std::logic_error("quadtree: 2:1 balance reached an inactive tile");
#ifndef NDEBUG
    // The invariant the angle proof rests on (graded.hpp); O(lattice), debug only.
    {
        const QuadtreeCheck chk = check_quadtree(t, signs);
        assert(chk.ok());
    }
#endif
    return t;
}

Leaves quadtree_leaves(const Quadtree& t, std::vector<std::int64_t>* per_level, bool drop_outside) {
    // Per level, rows (or, on the lower per-tile levels, tiles) in order; with
    // several threads, chunks of them in parallel, each chunk's leaves in
    // order, then joined.
    bool parallel = false;
#ifdef _OPENMP
    parallel = omp_get_max_threads() > 1;
#endif
    constexpr std::int64_t rows_per_chunk = 32;
    // Rows (or tiles) [0, rows) by emit(R0, R1, out) -> dropped, in chunks;
    // the chunks' outputs joined in order.
    auto by_chunks = [&](std::int64_t rows, std::int64_t work, auto& all, auto&& emit) {
        const std::int64_t nchunks = (rows + rows_per_chunk - 1) / rows_per_chunk;
        if (!parallel || nchunks < 2 || work < parallel_min) return emit(0, rows, all);
        std::vector<std::remove_reference_t<decltype(all)>> parts(static_cast<std::size_t>(nchunks));
        std::int64_t dropped = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : dropped)
        for (std::int64_t ch = 0; ch < nchunks; ++ch)
            dropped += emit(ch * rows_per_chunk, std::min(rows, (ch + 1) * rows_per_chunk), parts[static_cast<std::size_t>(ch)]);
        std::size_t add = 0;
        for (const auto& c : parts) add += c.size();
        all.reserve(all.size() + add);
        for (const auto& c : parts) all.insert(all.end(), c.begin(), c.end());
        return dropped;
    };
    Leaves out;
    out.nx = t.nx, out.ny = t.ny;
    if (per_level) per_level->clear();

    // ---- finest leaves: the split level-1 nodes, by row pairs --------------------
    // Reserved for the most there can be (only the pages written are ever
    // touched, and no growth copies them): below the tiles' level only in
    // active tiles, above it one per node; with top = 0, every column.
    const std::int64_t pairs = (t.ny + 1) / 2, px = (t.nx + 1) / 2;
    out.parents.reserve(static_cast<std::size_t>(t.top == 0 ? px * pairs
                                                 : t.local_top >= 1 ? static_cast<std::int64_t>(t.active.size()) << (2 * t.tile_log - 2)
                                                                    : t.nodes(1)));
    out.pair_start.assign(static_cast<std::size_t>(pairs) + 1, 0);
    by_chunks(pairs, px * pairs, out.parents, [&](std::int64_t R0, std::int64_t R1, std::vector<std::int32_t>& o) {
        for (std::int64_t R = R0; R < R1; ++R) {
            const std::size_t before = o.size();
            if (t.top == 0)
                for (std::int64_t P = 0; P < px; ++P) o.push_back(static_cast<std::int32_t>(P));
            else
                for_each_split(t, 1, R, [&](std::int64_t P) { o.push_back(static_cast<std::int32_t>(P)); });
            out.pair_start[static_cast<std::size_t>(R) + 1] = static_cast<std::int64_t>(o.size() - before);  // a count until summed
        }
        return std::int64_t{0};
    });
    std::partial_sum(out.pair_start.begin(), out.pair_start.end(), out.pair_start.begin());
    // Two columns per parent, but one for a parent at an odd lattice's last column.
    for (std::int64_t R = 0; R < pairs; ++R) {
        const std::int64_t k0 = out.pair_start[static_cast<std::size_t>(R)], k1 = out.pair_start[static_cast<std::size_t>(R) + 1];
        if (k1 > k0) out.finest += out.rows(R) * (2 * (k1 - k0) - (2 - out.columns(out.parents[static_cast<std::size_t>(k1) - 1])));
    }
    if (per_level) per_level->push_back(out.finest);

    // ---- coarse leaves, level by level -------------------------------------------
    std::size_t bound = t.active.size() << (2 * t.tile_log);
    for (int l = t.local_top + 1; l <= t.top; ++l) bound += static_cast<std::size_t>(t.nodes(l));  // the dense levels
    if (t.top > 0 && t.local_top == t.top) bound += static_cast<std::size_t>(t.nodes(t.top));      // roots below the tiles' level
    out.coarse.reserve(bound);
    for (int l = 1; l <= t.top; ++l) {
        const std::size_t L = static_cast<std::size_t>(l);
        const std::int64_t mx = t.nodes_x[L], my = t.nodes_y[L];
        // Node (I, J) of level l, with sign σ, is a leaf: only counted when it
        // is outside and dropped (before its sides are looked up), else
        // appended with its split sides, asked of split(a, b) for its four
        // edge neighbours — by balance a split edge neighbour's two children
        // along the shared side are leaves one level finer: the side is halved.
        auto put = [&](std::vector<Leaf>& o, std::int64_t& dropped, std::int64_t I, std::int64_t J, std::int8_t sign,
                       auto&& split) {
            if (drop_outside && sign > 0) return void(++dropped);
            const std::uint8_t sides = static_cast<std::uint8_t>(
                (split(I, J - 1) ? side_bottom : 0) | (split(I + 1, J) ? side_right : 0) | (split(I, J + 1) ? side_top : 0) |
                (split(I - 1, J) ? side_left : 0));
            o.push_back({static_cast<std::int32_t>(I << l), static_cast<std::int32_t>(J << l), static_cast<std::int8_t>(l), sign, sides});
        };
        auto is_split = [&](std::int64_t a, std::int64_t b) { return t.is_split(l, a, b); };
        // The leaves of level l are the unsplit nodes among the children of the
        // split nodes of level l + 1 (all unsplit nodes at the top); a row R of
        // level l + 1 gives rows 2R and 2R + 1 of level l, in order.
        const bool roots = l == t.top;
        const std::int64_t rows = roots ? my : t.nodes_y[L + 1];
        // put() for the unsplit nodes among (2P, J), (2P + 1, J) of a per-tile
        // level l, which lie in one tile: its slot is looked up once, and
        // neighbours inside the tile are read from it; only those across its
        // sides go through is_split.  An inactive tile has no split node of
        // level l.
        const int h = l <= t.local_top ? t.tile_log - l : 0;  // (only used on per-tile levels)
        auto local_children = [&](std::int64_t P, std::int64_t J, std::vector<Leaf>& o, std::int64_t& dropped) {
            const std::int64_t k = t.tile_of(l, 2 * P, J);
            const std::int32_t s = t.tile_slot[static_cast<std::size_t>(k)];
            const std::int64_t first = s < 0 ? 0 : t.local_index(l, s, 2 * P, J);  // node (2P, J) in local_sign
            auto split_at = [&](std::int64_t d) { return t.local_is_split(l, s, first + d); };  // node at offset d of (2P, J), in the tile
            for (std::int64_t q = 0; q < 2 && 2 * P + q < mx; ++q) {
                if (s >= 0 && split_at(q)) continue;
                const std::int64_t I = 2 * P + q;
                put(o, dropped, I, J, s < 0 ? t.tile_sign[static_cast<std::size_t>(k)] : t.local_sign[static_cast<std::size_t>(first + q)],
                    [&](std::int64_t a, std::int64_t b) {
                        // Across the tile's side, or no node: as is_split.  Else
                        // the same answer from the slot found above.
                        if (a < 0 || b < 0 || a >= mx || b >= my || ((a ^ I) | (b ^ J)) >> h) return t.is_split(l, a, b);
                        return s >= 0 && split_at((a - 2 * P) + ((b - J) << h));
                    });
            }
        };
        auto emit_rows = [&](std::int64_t R0, std::int64_t R1, std::vector<Leaf>& o) {
            std::int64_t dropped = 0;
            auto keep = [&](std::int64_t I, std::int64_t J) { put(o, dropped, I, J, t.node_sign(l, I, J), is_split); };
            for (std::int64_t R = R0; R < R1; ++R) {
                if (roots && l <= t.local_top) {
                    for (std::int64_t P = 0; 2 * P < mx; ++P) local_children(P, R, o, dropped);
                    continue;
                }
                if (roots) {
                    for (std::int64_t I = 0; I < mx; ++I)
                        if (!t.is_split(l, I, R)) keep(I, R);
                    continue;
                }
                for (std::int64_t J = 2 * R; J < std::min(2 * R + 2, my); ++J)
                    for_each_split(t, l + 1, R, [&](std::int64_t P) {
                        if (l <= t.local_top) return local_children(P, J, o, dropped);
                        for (std::int64_t I = 2 * P; I < std::min(2 * P + 2, mx); ++I)
                            if (!t.is_split(l, I, J)) keep(I, J);
                    });
            }
            return dropped;
        };
        // Per-tile levels below local_top, tile by tile: a leaf's parent is
        // then a node of the same tile (so only active tiles have leaves), and
        // a row of the tile's n = 2^h <= 64 nodes is one word of split bits.
        // A row's leaves are its unsplit nodes under split parents, and their
        // split sides come from shifts of the row and the rows above and
        // below — the tile's own, or those of the neighbouring tiles.
        auto tile_leaves = [&](std::int64_t s0, std::int64_t s1, std::vector<Leaf>& o) {
            std::int64_t dropped = 0;
            const std::int64_t n = std::int64_t{1} << h;
            std::array<std::uint64_t, 66> S;       // split bits of rows -1 .. n of the tile, at S[y + 1]
            std::array<std::uint64_t, 32> parent;  // split bits of the parents' rows, doubled
            for (std::int64_t s = s0; s < s1; ++s) {
                const std::int64_t I0 = t.active_x[static_cast<std::size_t>(s)] << h,
                                   J0 = (t.active[static_cast<std::size_t>(s)] / t.tiles_x) << h;
                const std::int64_t ex = std::min(n, mx - I0), ey = std::min(n, my - J0);  // the tile's nodes that exist
                const std::uint64_t exist = low_bits(ex);
                // Split parents first: a tile without any has no leaf of level l.
                const std::int64_t pfirst = t.local_index(l + 1, s, I0, J0);
                std::uint64_t any = 0;
                for (std::int64_t yp = 0; 2 * yp < ey; ++yp)
                    any |= parent[static_cast<std::size_t>(yp)] = spread_bits(split_row(t, l + 1, s, pfirst + (yp << (h - 1)), n / 2)) & exist;
                if (!any) continue;
                const std::int64_t first = t.local_index(l, s, I0, J0);
                for (std::int64_t y = 0; y < ey; ++y) S[static_cast<std::size_t>(y) + 1] = split_row(t, l, s, first + (y << h), n) & exist;
                // Split bits beyond the tile's side (di, dj), once per side if
                // asked: the row of nodes below or above the tile (bit x:
                // column I0 + x) or the column left or right of it (bit y: row
                // J0 + y), read in the neighbouring tile and answered as
                // is_split does: no node (outside the level's nodes), not
                // split; an inactive tile splits nothing but, on level 1,
                // everything if its σ is 0.
                auto beyond = [&](std::int64_t di, std::int64_t dj) -> std::uint64_t {
                    if ((di < 0 && I0 == 0) || (di > 0 && I0 + ex >= mx) || (dj < 0 && J0 == 0) || (dj > 0 && J0 + ey >= my)) return 0;
                    const std::size_t k = static_cast<std::size_t>(t.active[static_cast<std::size_t>(s)] + di + dj * t.tiles_x);
                    const std::int32_t o = t.tile_slot[k];
                    if (o < 0) return l == 1 && t.tile_sign[k] == 0 ? (di ? low_bits(ey) : exist) : 0;
                    if (dj) return split_row(t, l, o, t.local_index(l, o, I0, dj < 0 ? J0 - 1 : J0 + n), n) & exist;
                    const std::int64_t I = di < 0 ? I0 - 1 : I0 + n;  // (a right neighbour exists only if the tile is full)
                    std::uint64_t m = 0;
                    for (std::int64_t y = 0; y < ey; ++y)
                        m |= static_cast<std::uint64_t>(t.local_is_split(l, o, t.local_index(l, o, I, J0 + y))) << y;
                    return m;
                };
                std::uint64_t left = 0, right = 0;
                bool have_columns = false;
                for (std::int64_t y = 0; y < ey; ++y) {
                    const std::uint64_t cur = S[static_cast<std::size_t>(y) + 1];
                    std::uint64_t leaves = ~cur & parent[static_cast<std::size_t>(y >> 1)];
                    if (!leaves) continue;
                    if (y == 0) S[0] = beyond(0, -1);
                    if (y == ey - 1) S[static_cast<std::size_t>(ey) + 1] = beyond(0, 1);
                    if (!have_columns && (leaves & (1 | std::uint64_t{1} << (ex - 1)))) {
                        left = beyond(-1, 0), right = beyond(1, 0);
                        have_columns = true;
                    }
                    const std::uint64_t below = S[static_cast<std::size_t>(y)], above = S[static_cast<std::size_t>(y) + 2];
                    const std::uint64_t to_left = cur << 1 | ((left >> y) & 1), to_right = cur >> 1 | ((right >> y) & 1) << (ex - 1);
                    for (; leaves; leaves &= leaves - 1) {
                        const int x = std::countr_zero(leaves);
                        const std::int8_t sign = t.local_sign[static_cast<std::size_t>(first + (y << h) + x)];
                        if (drop_outside && sign > 0) {
                            ++dropped;
                            continue;
                        }
                        const std::uint8_t sides = static_cast<std::uint8_t>(
                            ((below >> x) & 1) * side_bottom | ((to_right >> x) & 1) * side_right | ((above >> x) & 1) * side_top |
                            ((to_left >> x) & 1) * side_left);
                        o.push_back({static_cast<std::int32_t>((I0 + x) << l), static_cast<std::int32_t>((J0 + y) << l),
                                     static_cast<std::int8_t>(l), sign, sides});
                    }
                }
            }
            return dropped;
        };
        const std::size_t before = out.coarse.size();
        const std::int64_t dropped = l < t.local_top
                                         ? by_chunks(static_cast<std::int64_t>(t.active.size()), mx * my, out.coarse, tile_leaves)
                                         : by_chunks(rows, mx * my, out.coarse, emit_rows);
        if (per_level) per_level->push_back(static_cast<std::int64_t>(out.coarse.size() - before) + dropped);
    }
    return out;
}

void PointSet::finish() {
    prefix.resize(words.size());  // written for the non-zero words, the only ones rank() reads
    std::int64_t n = 0;
    std::vector<std::int64_t> band;  // the flagged blocks of a band of rows
    for (std::int64_t j = 0; j < rows; ++j) {
        if ((j & 127) == 0) {
            band.clear();
            for (std::int64_t bx = 0; bx < blocks_x; ++bx)
                if (flagged[static_cast<std::size_t>((j >> 7) * blocks_x + bx)]) band.push_back(bx);
        }
        for (const std::int64_t bx : band) {
            const std::size_t base = static_cast<std::size_t>(((j >> 7) * blocks_x + bx) * (block_words * block_rows) + ((j & 127) << 2));
            for (std::size_t q = 0; q < static_cast<std::size_t>(block_words); ++q)
                if (const std::uint64_t w = words[base + q]) {
                    if (n > static_cast<std::int64_t>(UINT32_MAX) - 64)
                        throw std::length_error("more lattice points in a point set than 32-bit ranks allow");
                    prefix[base + q] = static_cast<std::uint32_t>(n);
                    n += std::popcount(w);
                }
        }
    }
    count = n;
}

QuadtreeCheck check_quadtree(const Quadtree& t, const TiledSigns& signs) {
    QuadtreeCheck r;
    auto note = [&r](std::string m) {
        if (r.messages.size() < 10) r.messages.push_back(std::move(m));
    };
    const std::int64_t nx = t.nx, ny = t.ny;
    auto sgn = [&](std::int64_t i, std::int64_t j) { return signs(i, j); };
    // Leaf level of every square, by painting the leaves.
    std::vector<std::int8_t> level(static_cast<std::size_t>(nx * ny), -1);
    const Leaves leaves = quadtree_leaves(t);
    for_each_finest(leaves, [&](std::int64_t i, std::int64_t j) {
        if (i >= nx || j >= ny) {
            ++r.untiled;
            note("finest leaf (" + std::to_string(i) + ", " + std::to_string(j) + ") outside the lattice");
            return;
        }
        auto& v = level[static_cast<std::size_t>(i + j * nx)];
        if (v >= 0) ++r.untiled;
        v = 0;
    });
    for (const Leaf& leaf : leaves.coarse) {
        const std::int64_t w = std::int64_t{1} << leaf.level;
        if (leaf.i + w > nx || leaf.j + w > ny) {
            ++r.untiled;
            note("leaf at (" + std::to_string(leaf.i) + ", " + std::to_string(leaf.j) + ") leaves the lattice");
            continue;
        }
        for (std::int64_t j = leaf.j; j < leaf.j + w; ++j)
            for (std::int64_t i = leaf.i; i < leaf.i + w; ++i) {
                auto& v = level[static_cast<std::size_t>(i + j * nx)];
                if (v >= 0) ++r.untiled;
                v = leaf.level;
            }
        bool good = leaf.level >= 1 && leaf.sign != 0;
        for (std::int64_t j = leaf.j; j <= leaf.j + w; ++j)
            for (std::int64_t i = leaf.i; i <= leaf.i + w; ++i) good = good && sgn(i, j) == leaf.sign;
        if (!good) {
            ++r.bad_sign;
            note("coarse leaf at (" + std::to_string(leaf.i) + ", " + std::to_string(leaf.j) + ") has a point of another sign");
        }
    }
    auto lv = [&](std::int64_t i, std::int64_t j) { return level[static_cast<std::size_t>(i + j * nx)]; };
    for (std::int64_t j = 0; j < ny; ++j)
        for (std::int64_t i = 0; i < nx; ++i) {
            const int l = lv(i, j);
            if (l < 0) {
                ++r.untiled;
                continue;
            }
            if ((i + 1 < nx && std::abs(l - lv(i + 1, j)) >= 2) || (j + 1 < ny && std::abs(l - lv(i, j + 1)) >= 2)) {
                ++r.unbalanced;
                note("leaves at square (" + std::to_string(i) + ", " + std::to_string(j) + ") are not 2:1 balanced");
            }
            if (l == 0) continue;
            bool critical = false, inside = false;
            for (int c = 0; c < 4; ++c) {
                const std::int64_t pi = i + (c & 1), pj = j + (c >> 1);
                const int s = sgn(pi, pj);
                inside = inside || s <= 0;
                critical = critical || s == 0 || (pi > 0 && sgn(pi - 1, pj) == -s) || (pi < nx && sgn(pi + 1, pj) == -s) ||
                           (pj > 0 && sgn(pi, pj - 1) == -s) || (pj < ny && sgn(pi, pj + 1) == -s);
            }
            if (critical) {
                ++r.coarse_critical;
                note("square (" + std::to_string(i) + ", " + std::to_string(j) + ") has a critical corner but is in a leaf of level " +
                     std::to_string(l));
            }
            if (inside && (i == 0 || j == 0 || i == nx - 1 || j == ny - 1)) {
                ++r.coarse_border;
                note("inside border square (" + std::to_string(i) + ", " + std::to_string(j) + ") is in a coarse leaf");
            }
        }
    return r;
}

}  // namespace warpmesh
