// quadtree.hpp — the graded mesher's 2:1-balanced quadtree and its leaves.
// Private to mesher/src (the public entry point is warpmesh/mesh2d/graded.hpp).
//
// Levels and nodes.  A node of level l covers the 2^l x 2^l block of lattice
// squares [I 2^l, (I+1) 2^l) x [J 2^l, (J+1) 2^l); level 0 nodes are the
// lattice squares.  A node's parent is (I >> 1, J >> 1), its children
// (2I + a, 2J + b): no pointers.  The tree is conceptually padded to a
// power-of-two root; nodes that do not lie entirely inside the lattice are
// never leaves (they are always split), and parts outside the lattice do not
// exist.  The roots are the nodes of level `top`, with 2^top = K (max_cell)
// or, for K = 0, the smallest power of two covering the lattice.
//
// Which nodes may be leaves.  A lattice point is *critical* when f is 0 there
// or it is an endpoint of a cut edge (a 4-neighbour has the strictly opposite
// sign): exactly the points that lie on the level set or could warp.  A node of
// level l >= 1 is *coarsenable* with sign σ in {-1, +1} when every lattice point
// in it (interior and boundary) is non-critical with sign σ — computed
// bottom-up as a pyramid: a node is coarsenable iff its 4 children are
// coarsenable with the same sign (their points cover the parent's).  This is
// exact: a single critical point anywhere in a big block, e.g. a tiny hole,
// keeps it from coarsening.  In addition an inside node (σ = -1) touching the
// lattice's outer border is not coarsenable, so the border squares that are
// meshed are finest squares and the domain-border boundary edges are those of
// the uniform mesh.  Outside nodes (σ = +1) coarsen too; they emit nothing.
// A node's *coarsening code* is σ if it is coarsenable, else 0.
//
// Grading (`--grading G < 2`, a buffer of n = grading_buffer(G) >= 2 nodes,
// graded.hpp): an inside node of level l is coarsenable only if, in addition,
// every node of level l within n nodes of it (max-norm) is coarsenable.  So a
// coarse inside leaf of width w = 2^l squares is farther than n w from every
// critical point, and on any straight path from the boundary to a leaf of
// width 2w lie at least n leaves of width <= w: sizes grow by at most a
// factor 2^(1/n) <= G per leaf on average.  Only zeros are added: the
// invariant below is untouched, and the coarse leaves stay the same
// templates.  n = 0 (G = 2) is the plain tree: 2:1 balance alone puts at
// least one leaf of width w before one of width 2w.
//
// Inside classes (per-material size caps, `--max-size-of`): the signs may
// also carry codes -2 - L (L >= 0), inside points whose cells are at most 2^L
// squares wide (cap_level; plain inside points, -1, only obey the roots'
// level).  A class is coarsenable like -1 — every point of the node
// non-critical with that same code — and in addition only up to its level L:
// cap_codes zeroes every node of level > L with code -2 - L, after the
// pyramid is built.  That keeps the pyramid (a node of level l > L of the
// class has a parent of level l + 1 > L of it, zeroed too), adds only zeros
// (the invariant below is untouched, coarse leaves stay the same templates),
// and a coarse leaf of a class is at most 2^L squares wide.  A tile whose
// points all carry a class of level L < tiled.top is active (a seed), since
// an inactive tile's nodes are all coarsenable up to the tiles' level;
// balance and the grading buffer then spread from its zeros as from any
// seed's.  Classes are distinct from the material numbers: the multi-material
// mesher gives every capped material the class of its own largest cell
// (mesh_materials_graded.cpp), so materials with the same cap share one.
//
// The invariant that makes the angle proof apply: every lattice square that
// has a critical corner (in particular every square with a warped corner) is a
// finest leaf with no split side.  Proof: a coarse leaf contains only
// non-critical points, so a square with a critical corner lies in no coarse
// leaf and is a level-0 leaf; and a level-0 leaf never has a split side, since
// a side is split only by a neighbour strictly finer than the leaf, and
// nothing is finer than level 0.  Conversely every vertex a coarse leaf uses
// (corners, side midpoints, centre) is one of its own non-critical points, so
// it never warps: coarse triangles are exact template shapes.  So no extra
// band is needed beyond "squares with a critical corner are finest" — the
// coarsenability test already yields it, and balance only ever splits.
//
// Storage: one interface, two schemes.  Level 0 stores nothing: a square is a
// finest leaf iff its level-1 parent is split (or top = 0).  Every level
// l >= 1 answers, for its nodes (I, J) (0 <= I < nodes_x[l], 0 <= J <
// nodes_y[l]):
//
//     code(I, J)             the node's coarsening code
//     is_split(I, J)         whether the node is split
//     for_each_split(J, fn)  fn(I) for the split nodes of row J, I increasing
//
// and is stored one of two ways (Quadtree::visit picks it):
//
//   * TiledLevel, levels 1 .. tiled.top (tiled.top = min(tile_log - 1, top)):
//     per tile of the signs (tiles.hpp), and only for *active* tiles — tiles
//     with sampled signs or on the lattice border, and their eight
//     neighbours.  In any other tile every point is non-critical with the
//     tile's sign σ, so all its nodes below the tile's level are coarsenable
//     with σ and none is split: a split can only come from a non-coarsenable
//     node, all of which lie in tiles with sampled signs or on the border, and
//     2:1 balance carries a split from level m to level m + 1 at most 2^(m+1)
//     squares further, which sums to less than one tile (T = 2^tile_log)
//     below the tiles' level (checked while balancing, not assumed).  A
//     grading buffer of n nodes widens the non-coarsenable set by at most
//     n T / 2 squares below the tiles' level, so the tiles are then activated
//     up to grading_tile_radius(n) = 2 + ceil(n / 2) tiles around the seeds
//     (also checked).
//   * DenseLevel, levels tiled.top + 1 .. top: row-major arrays, at most one
//     node per tile.
//
// Level 1 stores no split flags: nothing is split below it, so it has no
// balance constraint, and its nodes are split iff not coarsenable (code 0).
//
// Cost.  The work follows the boundary, not the lattice's area: the tiled
// levels exist only in active tiles, the dense ones have at most 4/3 node per
// tile.  What remains proportional to the area is small: a few bytes per tile,
// and the block flags of the point sets (point_set.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "mesh2d/graded/bits.hpp"
#include "mesh2d/graded/point_set.hpp"
#include "mesh2d/graded/tiles.hpp"
#include "warpmesh/core/buffer.hpp"
#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh {

// σ in {-1, +1} if the node is coarsenable with sign σ, 0 if it is not.
using CoarseningCode = std::int8_t;

// The largest level of a coarse leaf with code c: L for an inside class
// c = -2 - L, else no limit (no_cap_level); inside_class(L) is the code
// (0 <= L <= 62, the levels of 64-bit cell widths: codes down to -64).
inline constexpr int no_cap_level = 127;
constexpr int cap_level(CoarseningCode c) { return c < -1 ? -2 - c : no_cap_level; }
constexpr CoarseningCode inside_class(int level) { return static_cast<CoarseningCode>(-2 - level); }

// A level stored densely: nodes_x x nodes_y nodes, row-major.
struct DenseLevel {
    std::int64_t nodes_x = 0, nodes_y = 0;
    std::vector<CoarseningCode> codes;
    std::vector<std::uint8_t> split;  // 1 if split (balance included)

    std::size_t index(std::int64_t I, std::int64_t J) const { return static_cast<std::size_t>(I + J * nodes_x); }
    CoarseningCode code(std::int64_t I, std::int64_t J) const { return codes[index(I, J)]; }
    bool is_split(std::int64_t I, std::int64_t J) const { return split[index(I, J)] != 0; }
    template <class Fn>
    void for_each_split(std::int64_t J, Fn&& fn) const {
        bits::for_each_byte<false>(split.data() + J * nodes_x, nodes_x, fn);
    }
};

// The per-tile levels 1 .. top of the active tiles.  Each active tile has a
// *slot*; a slot holds, level after level, the (T >> l)^2 nodes of each
// level, row-major: their codes, and the split flags of levels >= 2.
struct TileLevels {
    int tile_log = 1;                         // tiles of T = 2^tile_log squares a side
    int top = 0;                              // the highest per-tile level, min(tile_log - 1, the tree's top)
    std::int64_t tiles_x = 0;                 // tiles a row
    std::vector<std::int32_t> slot_of_tile;   // per tile: its slot if active, else -1
    std::vector<CoarseningCode> tile_code;    // per tile: the code of every node of an inactive tile (its σ, never 0)
    std::vector<std::int64_t> tile_of_slot;   // per slot: its tile (slots in row-major tile order)
    std::vector<std::int64_t> column_of_slot; // per slot: its tile's column
    std::vector<std::int64_t> row_start;      // per tile row: its first slot; one more entry at the end
    std::vector<std::int64_t> level_offset;   // per level: the index of its first node in a slot
    std::int64_t slot_nodes = 0;              // nodes a slot holds, levels 1 .. top
    std::int64_t level1_nodes = 0;            // of which on level 1: (T / 2)^2 (0 if top = 0)
    std::vector<CoarseningCode> codes;        // slot_nodes per slot
    Buffer<std::uint8_t> split;               // levels 2 .. top: slot_nodes - level1_nodes per slot, every byte written

    std::int64_t slots() const { return static_cast<std::int64_t>(tile_of_slot.size()); }
    // A tile holds 2^h x 2^h nodes of level l, h = nodes_log(l).
    int nodes_log(int l) const { return tile_log - l; }
    // The tile of node (I, J) of level l.
    std::int64_t tile_of(int l, std::int64_t I, std::int64_t J) const {
        const int h = nodes_log(l);
        return (I >> h) + (J >> h) * tiles_x;
    }
    // Index in `codes` of node (I, J) of level l in slot s (its tile's).
    std::int64_t index(int l, std::int64_t s, std::int64_t I, std::int64_t J) const {
        const int h = nodes_log(l);
        const std::int64_t m = (std::int64_t{1} << h) - 1;
        return s * slot_nodes + level_offset[static_cast<std::size_t>(l)] + ((J & m) << h) + (I & m);
    }
    // Index in `split` of the node at `index` of slot s (levels >= 2).
    std::int64_t split_index(std::int64_t s, std::int64_t index) const { return index - (s + 1) * level1_nodes; }
    // Whether the node at `index` of slot s, level l, is split: on level 1
    // where not coarsenable, above by its flag.
    bool is_split_at(int l, std::int64_t s, std::int64_t index) const {
        return l == 1 ? codes[static_cast<std::size_t>(index)] == 0 : split[static_cast<std::size_t>(split_index(s, index))] != 0;
    }
    // The split flags of n consecutive nodes of a row of level l from `index`
    // of slot s, as bits (bit x: the node at index + x); n <= 64 and, if
    // n >= 8, a multiple of 8.
    std::uint64_t split_bits(int l, std::int64_t s, std::int64_t index, std::int64_t n) const {
        if (n < 8) {
            std::uint64_t b = 0;
            for (std::int64_t x = 0; x < n; ++x) b |= static_cast<std::uint64_t>(is_split_at(l, s, index + x)) << x;
            return b;
        }
        std::uint64_t b = 0;
        if (l == 1) {  // split: code 0
            for (std::int64_t x = 0; x < n; x += 8) b |= (~bits::nonzero_bytes(bits::load8(codes.data() + index + x)) & 0xff) << x;
        } else {
            const std::uint8_t* p = split.data() + split_index(s, index);
            for (std::int64_t x = 0; x < n; x += 8) b |= bits::nonzero_bytes(bits::load8(p + x)) << x;
        }
        return b;
    }
};

// A level stored per tile: a view of level l of TileLevels, with the level's
// nodes_x (rows of nodes end there).
struct TiledLevel {
    const TileLevels* tiles;
    int l;
    std::int64_t nodes_x;

    CoarseningCode code(std::int64_t I, std::int64_t J) const {
        const std::int64_t k = tiles->tile_of(l, I, J);
        const std::int32_t s = tiles->slot_of_tile[static_cast<std::size_t>(k)];
        return s < 0 ? tiles->tile_code[static_cast<std::size_t>(k)] : tiles->codes[static_cast<std::size_t>(tiles->index(l, s, I, J))];
    }
    // An inactive tile splits nothing (see above).
    bool is_split(std::int64_t I, std::int64_t J) const {
        const std::int32_t s = tiles->slot_of_tile[static_cast<std::size_t>(tiles->tile_of(l, I, J))];
        return s >= 0 && tiles->is_split_at(l, s, tiles->index(l, s, I, J));
    }
    // Only active tiles have split nodes; those of the tile row of J are the
    // slots row_start[TJ] .. row_start[TJ + 1] - 1, left to right.
    template <class Fn>
    void for_each_split(std::int64_t J, Fn&& fn) const {
        const int h = tiles->nodes_log(l);
        const std::int64_t TJ = J >> h;
        for (std::int64_t s = tiles->row_start[static_cast<std::size_t>(TJ)]; s < tiles->row_start[static_cast<std::size_t>(TJ) + 1]; ++s) {
            const std::int64_t I0 = tiles->column_of_slot[static_cast<std::size_t>(s)] << h;
            const std::int64_t first = tiles->index(l, s, I0, J), n = std::min(std::int64_t{1} << h, nodes_x - I0);
            auto at = [&](std::int64_t q) { fn(I0 + q); };
            if (l == 1)
                bits::for_each_byte<true>(tiles->codes.data() + first, n, at);
            else
                bits::for_each_byte<false>(tiles->split.data() + tiles->split_index(s, first), n, at);
        }
    }
};

// The balanced quadtree.
struct Quadtree {
    std::int64_t nx = 0, ny = 0;                 // lattice squares
    int top = 0;                                 // level of the roots
    PointSet warped;                             // the warped points (warped[k] has rank k)
    std::vector<std::int64_t> nodes_x, nodes_y;  // per level: ceil(n / 2^l)
    TileLevels tiled;                            // levels 1 .. tiled.top
    std::vector<DenseLevel> dense;               // levels tiled.top + 1 .. top, at their index (the others empty)

    std::int64_t nodes(int l) const { return nodes_x[static_cast<std::size_t>(l)] * nodes_y[static_cast<std::size_t>(l)]; }
    bool is_tiled(int l) const { return l <= tiled.top; }
    TiledLevel tiled_level(int l) const { return {&tiled, l, nodes_x[static_cast<std::size_t>(l)]}; }
    // fn(level) with level l, 1 <= l <= top, as its storage holds it.
    template <class Fn>
    decltype(auto) visit(int l, Fn&& fn) const {
        return is_tiled(l) ? fn(tiled_level(l)) : fn(dense[static_cast<std::size_t>(l)]);
    }
    // The code of node (I, J) of level 1 <= l <= top, (I, J) among its nodes.
    CoarseningCode code(int l, std::int64_t I, std::int64_t J) const {
        return visit(l, [&](const auto& level) { return level.code(I, J); });
    }
    // Whether node (i, j) of level l exists and is split.  Levels above `top`
    // are all split (the roots form a forest); level 0 never is.
    bool is_split(int l, std::int64_t i, std::int64_t j) const {
        if (l > top) return true;
        const std::size_t L = static_cast<std::size_t>(l);
        if (l == 0 || i < 0 || j < 0 || i >= nodes_x[L] || j >= nodes_y[L]) return false;
        return visit(l, [&](const auto& level) { return level.is_split(i, j); });
    }
    // Whether lattice square (i, j) is a finest leaf.
    bool is_finest(std::int64_t i, std::int64_t j) const { return is_split(1, i >> 1, j >> 1); }
};

// Tiles around the seeds whose levels are stored, for a grading buffer of n
// nodes: 1 without (n = 0), 2 + ceil(n / 2) with.
std::int64_t grading_tile_radius(int buffer);

// Build the tree: the set of `warped` points, the active tiles, the
// coarsening codes up to level log2(max_cell) (max_cell 0: as coarse as the
// lattice allows), capped per inside class if `classes` (the signs may hold
// codes -2 - L; without it they are -1, 0, +1 and the pass is skipped),
// widened by the grading buffer (0: none; above), then 2:1 balance.  Throws
// std::invalid_argument if max_cell is negative or not a power of two, if
// buffer is not in 0 .. max_grading_buffer, or if the signs' tiles are larger
// than 128 squares (tile_log > 7: a row of a tile's level-1 nodes is one
// 64-bit word); std::length_error if the lattice has 2^31 squares a side.
Quadtree build_quadtree(const Lattice& lattice, const TiledSigns& signs, std::span<const WarpedPoint> warped,
                        std::int64_t max_cell, int buffer = 0, bool classes = false);

// Sides of a leaf, as bits of Leaf::split_sides: bottom (A-B), right (B-D),
// top (D-C), left (C-A).
inline constexpr std::uint8_t side_bottom = 1, side_right = 2, side_top = 4, side_left = 8;

// A coarse leaf of the tree (level >= 1): squares [i, i + 2^level) x
// [j, j + 2^level), `sign` its σ, `split_sides` the sides halved by a finer
// neighbour (their midpoints are vertices).
struct Leaf {
    std::int32_t i, j;
    std::int8_t level;
    std::int8_t sign;
    std::uint8_t split_sides;
};

// Ring of a coarse leaf (corner points and midpoints of split sides, counter-
// clockwise from A: A → [mid AB] → B → [mid BD] → D → [mid DC] → C → [mid CA])
// and its centre, as lattice points P{i, j}; returns the ring's length.  The
// graded triangulations join the centre to the ring (or, with no split side,
// take one diagonal of ring = A, B, D, C: coarse_tie_break below).
template <class P>
int coarse_ring(const Leaf& leaf, std::array<P, 8>& ring, P& centre) {
    const std::int64_t w = std::int64_t{1} << leaf.level, h = w / 2, i = leaf.i, j = leaf.j;
    centre = {i + h, j + h};
    int n = 0;
    ring[n++] = {i, j};
    if (leaf.split_sides & side_bottom) ring[n++] = {i + h, j};
    ring[n++] = {i + w, j};
    if (leaf.split_sides & side_right) ring[n++] = {i + w, j + h};
    ring[n++] = {i + w, j + w};
    if (leaf.split_sides & side_top) ring[n++] = {i + h, j + w};
    ring[n++] = {i, j + w};
    if (leaf.split_sides & side_left) ring[n++] = {i, j + h};
    return n;
}

// A coarse leaf with no split side takes one diagonal, like a finest square
// scaled by w = 2^level: by the union-jack pattern of its own level, i.e. its
// position (i / w, j / w) among the level's cells (leaves are aligned to
// their level), so coarse regions have no preferred direction either.  Its
// two triangles as ring indices (ring = A, B, D, C, coarse_ring): AD (A, B, D),
// (A, D, C); BC (A, B, C), (B, D, C).
inline TieBreak coarse_tie_break(const Leaf& leaf) { return union_jack(leaf.i >> leaf.level, leaf.j >> leaf.level); }
constexpr std::array<std::array<std::array<int, 3>, 2>, 2> coarse_diagonal_ring{{{{{0, 1, 2}, {0, 2, 3}}}, {{{0, 1, 3}, {1, 2, 3}}}}};

// The leaves of the tree.  The finest leaves (level 0: lattice squares, with
// no sign of their own and never a split side) are listed by their parents:
// a square is a finest leaf iff its level-1 parent is split (level 0 is never
// split), so the finest leaves are exactly the squares inside the lattice
// among the 2 x 2 children of the split level-1 nodes — one record for up to
// four leaves, and a square's neighbours inside its parent need no lookup.
// (With top = 0 there is no level 1: every square is a finest leaf, and
// `parents` lists every column of every row pair.)
//
// The finest leaves' canonical order, in which the graded triangulation
// emits them, is by parents (row pair by row pair, by increasing P), a
// parent's squares row-major (for_each_finest).
struct Leaves {
    std::int64_t nx = 0, ny = 0;           // lattice squares
    std::vector<std::int32_t> parents;     // column P of each split level-1 node (squares 2P, 2P + 1), by row pair, P increasing
    std::vector<std::int64_t> pair_start;  // per row pair R (rows 2R, 2R + 1): its first parent; ceil(ny / 2) + 1 entries
    std::vector<Leaf> coarse;              // levels >= 1, by increasing level; within a level row-major, or tile by tile (leaves.cpp)
    std::int64_t finest = 0;               // number of finest leaves

    std::int64_t row_pairs() const { return static_cast<std::int64_t>(pair_start.size()) - 1; }
    // Columns and rows of parent P's squares in row pair R (1 or 2: the
    // lattice may end in the middle of a parent).
    int columns(std::int64_t P) const { return 2 * P + 1 < nx ? 2 : 1; }
    int rows(std::int64_t R) const { return 2 * R + 1 < ny ? 2 : 1; }
};

// fn(i, j) for every finest leaf, in the canonical order (above).
template <class Fn>
void for_each_finest(const Leaves& leaves, Fn&& fn) {
    for (std::int64_t R = 0; R < leaves.row_pairs(); ++R)
        for (std::int64_t k = leaves.pair_start[static_cast<std::size_t>(R)]; k < leaves.pair_start[static_cast<std::size_t>(R) + 1]; ++k) {
            const std::int64_t P = leaves.parents[static_cast<std::size_t>(k)];
            for (std::int64_t j = 2 * R; j < 2 * R + leaves.rows(R); ++j)
                for (std::int64_t i = 2 * P; i < 2 * P + leaves.columns(P); ++i) fn(i, j);
        }
}

// All leaves (deterministic order, whatever the thread count).
// leaves_per_level[l] counts them.  With drop_outside, coarse leaves outside
// the region (sign +1, which emit nothing) are counted but not returned.
// Work O(leaves + active tiles).
Leaves quadtree_leaves(const Quadtree& tree, std::vector<std::int64_t>* leaves_per_level = nullptr, bool drop_outside = false);

// The checks of the quadtree's invariants, from scratch (O(lattice) memory):
// the leaves tile the lattice; edge-adjacent leaves differ by at most one
// level; every square with a critical corner (zero-valued, or an endpoint of a
// cut edge of `signs`) is a finest leaf; every square on the lattice border
// with an inside corner is a finest leaf; every coarse leaf's points all have
// its sign, non-zero; no coarse leaf of an inside class is above its level.  Used by the
// tests, and asserted in debug builds.
struct QuadtreeCheck {
    std::int64_t untiled = 0;            // squares covered by no leaf or by several
    std::int64_t unbalanced = 0;         // adjacent squares whose leaves differ by >= 2 levels
    std::int64_t coarse_critical = 0;    // squares with a critical corner inside a coarse leaf
    std::int64_t coarse_border = 0;      // inside border squares inside a coarse leaf
    std::int64_t bad_sign = 0;           // coarse leaves with a point of another sign
    std::int64_t over_cap = 0;           // coarse leaves of an inside class above its level (cap_level)
    std::vector<std::string> messages;
    bool ok() const {
        return untiled == 0 && unbalanced == 0 && coarse_critical == 0 && coarse_border == 0 && bad_sign == 0 && over_cap == 0;
    }
};
QuadtreeCheck check_quadtree(const Quadtree& tree, const TiledSigns& signs);

// The invariant the certificates rest on, checked on the leaf list itself
// (cheap: O(warped points + sampled tiles' points), binary searches in
// `parents`): every lattice square with a warped or zero-valued corner is a
// finest leaf (hence has no split side).  mesh_graded runs it whenever
// KeyOptions::check_invariant is set (the pipeline sets it with `warpmesh
// --verify`, release builds included) and throws std::logic_error with
// `first` on a violation.
struct CriticalSquaresCheck {
    std::int64_t critical_points = 0;  // warped points, then zero-valued ones (a point may be both: counted twice)
    std::int64_t squares = 0;          // squares around them checked (with repetitions)
    std::int64_t violations = 0;       // of those, squares that are not finest leaves
    std::string first;                 // the first violation, described
    bool ok() const { return violations == 0; }
};
CriticalSquaresCheck check_critical_squares_finest(const Leaves& leaves, const TiledSigns& signs,
                                                   std::span<const WarpedPoint> warped);

}  // namespace warpmesh
