// quadtree.cpp — the graded mesher's balanced quadtree, as per-level arrays.
//
// Three passes, each a flat loop over one level's array (level 1 is computed
// straight from the signs: a point is critical when f = 0 there or a
// 4-neighbour has the strictly opposite sign — exactly the endpoints of cut
// edges) (parallel over rows,
// no pointers, no Morton codes — a node's parent is (i >> 1, j >> 1), its
// children (2i + a, 2j + b)):
//
//  1. the set of warped points (a bitset with ranks);
//  2. the coarsenability pyramid `sign` (see graded.hpp), bottom-up;
//  3. `split`, bottom-up: a node is split when it is not coarsenable, or when
//     2:1 balance demands it.
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
// is final once level l is.  Pass 3 evaluates it as a gather (each node reads
// the 4x4 block of level-l nodes around its children, minus the block's
// corners), which is race-free and independent of the thread count.
#include <algorithm>
#include <bit>
#include <cassert>
#include <cstring>
#include <stdexcept>
#include <string>

#include "warpmesh/graded.hpp"

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

// fn(i) for every split node i of row j of level l >= 1.
template <class Fn>
inline void for_each_split(const Quadtree& t, int l, std::int64_t j, Fn&& fn) {
    const std::size_t L = static_cast<std::size_t>(l);
    const std::int64_t mx = t.nodes_x[L];
    if (l == 1)
        for_each_byte<true>(t.sign[1].data() + j * mx, mx, fn);  // level 1: split iff not coarsenable
    else
        for_each_byte<false>(t.split[L].data() + j * mx, mx, fn);
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
    Quadtree t;
    const std::int64_t nx = lattice.nx, ny = lattice.ny, nxp = nx + 1;
    t.nx = nx, t.ny = ny;
    // Roots: the smallest power of two covering the lattice, capped by K.
    int cover = 0;
    while ((std::int64_t{1} << cover) < std::max(nx, ny)) ++cover;
    t.top = max_cell == 0 ? cover : std::min(cover, std::countr_zero(static_cast<std::uint64_t>(max_cell)));

    // ---- 1. the warped points ----------------------------------------------------
    t.warped = PointSet(nxp, ny + 1);
    for (const WarpedPoint& w : warped) t.warped.insert(w.p % nxp, w.p / nxp);
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

    // ---- 2. the coarsenability pyramid -----------------------------------------
    // Level 1 tile by tile (tiles.hpp).  A uniform tile's points are all
    // non-critical with its sign, so all its level-1 nodes are coarsenable
    // with it.  In a sampled tile each point's code is its sign if it is not
    // critical (not 0, no 4-neighbour of the opposite sign: the block's ring
    // holds the neighbours beyond the tile, 0 outside the lattice, which never
    // makes a point critical), else 0; a node takes the common code of its
    // 3 x 3 points.  Either way a node partly outside the lattice is never a
    // leaf, and an inside node on the lattice border is not coarsenable (its
    // border squares stay finest, as in the uniform mesh).
    {
        const std::int64_t mx = t.nodes_x[1], my = t.nodes_y[1], half = signs.size() / 2, S = signs.stride();
        auto& s1 = t.sign[1];
        s1.resize(static_cast<std::size_t>(mx * my));
        const std::int64_t ntiles = signs.tx * signs.ty;
#pragma omp parallel if (mx * my >= parallel_min)
        {
            std::vector<std::int8_t> code(static_cast<std::size_t>((signs.size() + 1) * (signs.size() + 1)));
#pragma omp for schedule(dynamic, 16)
            for (std::int64_t k = 0; k < ntiles; ++k) {
                const std::int64_t TI = k % signs.tx, TJ = k / signs.tx;
                const std::int32_t slot = signs.slot[static_cast<std::size_t>(k)];
                const std::int8_t* blk = slot >= 0 ? signs.block(slot) : nullptr;
                const std::int64_t i0 = TI << signs.tile_log, j0 = TJ << signs.tile_log;
                if (blk)
                    for (std::int64_t y = 0; y <= signs.size() && j0 + y <= ny; ++y)
                        for (std::int64_t x = 0; x <= signs.size() && i0 + x <= nx; ++x) {
                            const std::int8_t* c = blk + (y + 1) * S + x + 1;
                            const std::int8_t v = *c, o = static_cast<std::int8_t>(-v);
                            const bool critical = v == 0 || c[-1] == o || c[1] == o || c[-S] == o || c[S] == o;
                            code[static_cast<std::size_t>(y * (signs.size() + 1) + x)] = critical ? 0 : v;
                        }
                for (std::int64_t J = TJ * half; J < std::min((TJ + 1) * half, my); ++J)
                    for (std::int64_t I = TI * half; I < std::min((TI + 1) * half, mx); ++I) {
                        std::int8_t sg = 0;
                        if (2 * I + 2 <= nx && 2 * J + 2 <= ny) {
                            if (!blk) {
                                sg = signs.uniform[static_cast<std::size_t>(k)];
                            } else {
                                const std::int64_t x = 2 * I - i0, y = 2 * J - j0, w = signs.size() + 1;
                                const std::int8_t* c = code.data() + y * w + x;
                                sg = c[0];
                                for (std::int64_t dy = 0; dy < 3; ++dy)
                                    for (std::int64_t dx = 0; dx < 3; ++dx) sg = c[dy * w + dx] == sg ? sg : 0;
                            }
                            if (sg < 0 && (I == 0 || J == 0 || 2 * I + 2 == nx || 2 * J + 2 == ny)) sg = 0;
                        }
                        s1[static_cast<std::size_t>(I + J * mx)] = sg;
                    }
            }
        }
    }
    for (int l = 2; l <= t.top; ++l) {
        const std::int64_t mx = t.nodes_x[static_cast<std::size_t>(l)], my = t.nodes_y[static_cast<std::size_t>(l)];
        const std::int64_t cx = t.nodes_x[static_cast<std::size_t>(l) - 1], cy = t.nodes_y[static_cast<std::size_t>(l) - 1];
        const auto& child = t.sign[static_cast<std::size_t>(l) - 1];
        auto& s = t.sign[static_cast<std::size_t>(l)];
        s.assign(static_cast<std::size_t>(mx * my), 0);
#pragma omp parallel for schedule(static) if (mx * my >= parallel_min)
        for (std::int64_t J = 0; J < my; ++J) {
            if (2 * J + 1 >= cy) continue;
            for (std::int64_t I = 0; 2 * I + 1 < cx; ++I) {
                const std::size_t c = static_cast<std::size_t>(2 * I + 2 * J * cx);
                const std::int8_t v = child[c];
                const bool same = v != 0 && child[c + 1] == v && child[c + static_cast<std::size_t>(cx)] == v &&
                                  child[c + static_cast<std::size_t>(cx) + 1] == v;
                s[static_cast<std::size_t>(I + J * mx)] = same ? v : 0;
            }
        }
    }

    // ---- 3. split nodes, with 2:1 balance ---------------------------------------
    // Level 1: split iff not coarsenable (stored as sign 0).  Levels >= 2:
    for (int l = 2; l <= t.top; ++l) {
        const std::size_t L = static_cast<std::size_t>(l);
        const std::int64_t mx = t.nodes_x[L], my = t.nodes_y[L];
        auto& sp = t.split[L];
        sp.resize(static_cast<std::size_t>(mx * my));
        const auto& sg = t.sign[L];
#pragma omp parallel for schedule(static) if (mx * my >= parallel_min)
        for (std::int64_t k = 0; k < mx * my; ++k) sp[static_cast<std::size_t>(k)] = sg[static_cast<std::size_t>(k)] == 0;
        // Balance: for every split node (a, r) of level l - 1, split the parents
        // of its existing edge neighbours.  Row J of this level is written only
        // by iteration J, reading child rows 2J - 1 .. 2J + 2.
        const std::int64_t cx = t.nodes_x[L - 1], cy = t.nodes_y[L - 1];
#pragma omp parallel for schedule(static) if (mx * my >= parallel_min)
        for (std::int64_t J = 0; J < my; ++J) {
            std::uint8_t* out = sp.data() + J * mx;
            for (std::int64_t r = std::max<std::int64_t>(0, 2 * J - 1); r <= std::min(cy - 1, 2 * J + 2); ++r)
                for_each_split(t, l - 1, r, [&](std::int64_t a) {
                    if ((r >> 1) == J) {
                        out[a >> 1] = 1;  // (its own parent: split already)
                        if (a > 0) out[(a - 1) >> 1] = 1;
                        if (a + 1 < cx) out[(a + 1) >> 1] = 1;
                    }
                    if (r > 0 && ((r - 1) >> 1) == J) out[a >> 1] = 1;
                    if (r + 1 < cy && ((r + 1) >> 1) == J) out[a >> 1] = 1;
                });
        }
    }
#ifndef NDEBUG
    // The invariant the angle proof rests on (graded.hpp); O(lattice), debug only.
    {
        const QuadtreeCheck chk = check_quadtree(t, signs);
        assert(chk.ok());
    }
#endif
    return t;
}

std::vector<Leaf> quadtree_leaves(const Quadtree& t, std::vector<std::int64_t>* per_level) {
    std::vector<std::vector<Leaf>> levels(static_cast<std::size_t>(t.top) + 1);
    for (int l = 0; l <= t.top; ++l) {
        const std::size_t L = static_cast<std::size_t>(l);
        const std::int64_t mx = t.nodes_x[L], my = t.nodes_y[L];
        auto leaf = [&](std::int64_t I, std::int64_t J) -> Leaf {
            std::uint8_t sides = 0;
            if (l > 0)
                // By balance a split edge neighbour's two children along the
                // shared side are leaves one level finer: the side is halved.
                sides = static_cast<std::uint8_t>(
                    (t.is_split(l, I, J - 1) ? side_bottom : 0) | (t.is_split(l, I + 1, J) ? side_right : 0) |
                    (t.is_split(l, I, J + 1) ? side_top : 0) | (t.is_split(l, I - 1, J) ? side_left : 0));
            return {static_cast<std::int32_t>(I << l), static_cast<std::int32_t>(J << l), static_cast<std::int8_t>(l),
                    l > 0 ? t.sign[L][static_cast<std::size_t>(I + J * mx)] : std::int8_t{0}, sides};
        };
        auto is_leaf_node = [&](std::int64_t I, std::int64_t J) { return !t.is_split(l, I, J); };
        // The leaves of level l are the unsplit nodes among the children of the
        // split nodes of level l + 1 (all unsplit nodes at the top).  Rows of
        // level l + 1 in parallel, each giving two rows of level l in order.
        const bool roots = l == t.top;
        const std::int64_t rows = roots ? my : t.nodes_y[L + 1];
        std::vector<std::vector<Leaf>> per_row(static_cast<std::size_t>(rows));
#pragma omp parallel for schedule(dynamic, 16) if (mx * my >= parallel_min)
        for (std::int64_t R = 0; R < rows; ++R) {
            auto& out = per_row[static_cast<std::size_t>(R)];
            if (roots) {
                for (std::int64_t I = 0; I < mx; ++I)
                    if (is_leaf_node(I, R)) out.push_back(leaf(I, R));
                continue;
            }
            for (std::int64_t J = 2 * R; J < std::min(2 * R + 2, my); ++J)
                for_each_split(t, l + 1, R, [&](std::int64_t P) {
                    for (std::int64_t I = 2 * P; I < std::min(2 * P + 2, mx); ++I)
                        if (is_leaf_node(I, J)) out.push_back(leaf(I, J));
                });
        }
        for (auto& r : per_row) levels[L].insert(levels[L].end(), r.begin(), r.end());
    }
    std::vector<Leaf> all;
    std::size_t total = 0;
    for (const auto& v : levels) total += v.size();
    all.reserve(total);
    if (per_level) per_level->clear();
    for (const auto& v : levels) {
        all.insert(all.end(), v.begin(), v.end());
        if (per_level) per_level->push_back(static_cast<std::int64_t>(v.size()));
    }
    return all;
}

void PointSet::finish() {
    prefix.resize(words.size());
    std::int64_t n = 0;
    for (std::size_t w = 0; w < words.size(); ++w) {
        prefix[w] = n;
        n += std::popcount(words[w]);
    }
}

QuadtreeCheck check_quadtree(const Quadtree& t, const TiledSigns& signs) {
    QuadtreeCheck r;
    auto note = [&r](std::string m) {
        if (r.messages.size() < 10) r.messages.push_back(std::move(m));
    };
    const std::int64_t nx = t.nx, ny = t.ny, nxp = nx + 1;
    auto sgn = [&](std::int64_t i, std::int64_t j) { return signs(i, j); };
    // Leaf level of every square, by painting the leaves.
    std::vector<std::int8_t> level(static_cast<std::size_t>(nx * ny), -1);
    for (const Leaf& leaf : quadtree_leaves(t)) {
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
        if (leaf.level > 0) {
            bool good = leaf.sign != 0;
            for (std::int64_t j = leaf.j; j <= leaf.j + w; ++j)
                for (std::int64_t i = leaf.i; i <= leaf.i + w; ++i) good = good && sgn(i, j) == leaf.sign;
            if (!good) {
                ++r.bad_sign;
                note("coarse leaf at (" + std::to_string(leaf.i) + ", " + std::to_string(leaf.j) +
                     ") has a point of another sign");
            }
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
