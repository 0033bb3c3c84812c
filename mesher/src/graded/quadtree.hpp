// quadtree.hpp — the graded mesher's internals (not installed): the point
// sets, the balanced quadtree, its leaves and their triangulation.  The entry
// point, mesh_graded, is in the public warpmesh/graded.hpp.
//
// The pipeline:
//
//   tiles.cpp               → sample → signs → cut points, only in the tiles
//                             the level set can reach (a range bound per tile);
//                             the same signs and cut points as the uniform
//                             front end, without its O(lattice) work
//   warp.cpp                → the warp, as in the uniform mesher
//   quadtree.cpp            → which squares may be merged into coarse leaves,
//                             2:1 balance, the leaves
//   triangulate_graded.cpp  → triangles of the leaves, vertices, boundary
//   graded.cpp              → the driver, timed
//
// Levels and nodes.  A node of level l covers the 2^l x 2^l block of lattice
// squares [I 2^l, (I+1) 2^l) x [J 2^l, (J+1) 2^l); level 0 nodes are the
// lattice squares.  The tree is conceptually padded to a power-of-two root;
// nodes that do not lie entirely inside the lattice are never leaves (they are
// always split), and parts outside the lattice do not exist.  The roots are
// the nodes of level `top`, with 2^top = K (max_cell) or, for K = 0, the
// smallest power of two covering the lattice.
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
// Cost.  The work follows the boundary, not the lattice's area: f is
// evaluated only in sampled tiles (tiles.hpp), the quadtree below the tiles'
// level exists only in active tiles (quadtree.cpp), the dense levels above it
// have at most 4/3 node per tile, and the triangulation visits leaves.  What
// remains proportional to the area is small: a few bytes per tile, and the
// flags of the warped and used points' blocks (PointSet: one byte per 32 768
// points; their bits are stored, and touched, only in blocks the boundary
// crosses).
#pragma once

#include <array>
#include <atomic>
#include <bit>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "graded/tiles.hpp"
#include "warpmesh/certified.hpp"
#include "warpmesh/graded.hpp"
#include "warpmesh/lattice.hpp"

namespace warpmesh {

// A set of lattice points, one bit each, with ranks: after finish(), rank(p)
// of a member p is the number of members before p in point (row-major)
// order, in O(1) — so a sorted list indexed by members (the warped points,
// the compacted vertices) needs no lattice-sized index array.
//
// Storage is blocked: 4 words (256 points) by 128 rows make a block of one
// 4 KiB page, and each block has a flag "holds a member".  A set that follows
// a curve then touches only the pages the curve crosses — a row-major bitset
// would touch every row's, and on this VM a first touch costs ~2.5 µs a
// page — and the scans in point order visit flagged blocks only.
struct PointSet {
    static constexpr int block_words = 4, block_rows = 128;
    std::int64_t words_per_row = 0, rows = 0, blocks_x = 0, blocks_y = 0;
    ZeroBuffer<std::uint64_t> words;    // zeroed, touched only where written (buffer.hpp)
    Buffer<std::uint32_t> prefix;       // per non-zero word, members before it (after finish; < 2^32)
    std::vector<std::uint8_t> flagged;  // per block: 1 if it may hold a member
    std::int64_t count = 0;               // members (after finish)

    PointSet() = default;
    PointSet(std::int64_t points_x, std::int64_t nrows)
        : words_per_row((points_x + 63) / 64),
          rows(nrows),
          blocks_x((words_per_row + block_words - 1) / block_words),
          blocks_y((nrows + block_rows - 1) / block_rows),
          words(static_cast<std::size_t>(blocks_x * blocks_y * block_words * block_rows)),
          flagged(static_cast<std::size_t>(blocks_x * blocks_y), 0) {}
    // Point (i, j): shifts and masks only, no division on the hot paths.
    std::size_t block(std::int64_t i, std::int64_t j) const {
        return static_cast<std::size_t>((j >> 7) * blocks_x + (i >> 8));
    }
    std::size_t word(std::int64_t i, std::int64_t j) const {
        return block(i, j) * (block_words * block_rows) + static_cast<std::size_t>(((j & 127) << 2) + ((i >> 6) & 3));
    }
    static std::uint64_t bit(std::int64_t i) { return std::uint64_t{1} << (i & 63); }
    bool contains(std::int64_t i, std::int64_t j) const { return words[word(i, j)] & bit(i); }
    void insert(std::int64_t i, std::int64_t j) { insert_bits<false>(i, j, 1); }
    // Points (i + k, j) for the bits k of rel (non-zero): at most two words,
    // the one of i and the next, since k < 64.  `concurrent`: for threads
    // marking the same set at once (relaxed atomics).
    template <bool concurrent>
    void insert_bits(std::int64_t i, std::int64_t j, std::uint64_t rel) {
        const int b = static_cast<int>(i & 63);
        or_word<concurrent>(i, j, rel << b);
        if (b && (rel >> (64 - b))) or_word<concurrent>(i - b + 64, j, rel >> (64 - b));
    }

private:
    template <bool concurrent>
    void or_word(std::int64_t i, std::int64_t j, std::uint64_t bits) {
        if constexpr (concurrent) {
            std::atomic_ref<std::uint64_t>(words[word(i, j)]).fetch_or(bits, std::memory_order_relaxed);
            std::atomic_ref<std::uint8_t>(flagged[block(i, j)]).store(1, std::memory_order_relaxed);
        } else {
            words[word(i, j)] |= bits;
            flagged[block(i, j)] = 1;
        }
    }

public:
    // Membership of (i + q, j), q < n <= 64, as bit q: the word of i and,
    // past its end, the next (the points must lie in the row).
    std::uint64_t members(std::int64_t i, std::int64_t j, int n) const {
        const int b = static_cast<int>(i & 63);
        std::uint64_t m = words[word(i, j)] >> b;
        if (b + n > 64) m |= words[word(i - b + 64, j)] << (64 - b);
        return n == 64 ? m : m & ((std::uint64_t{1} << n) - 1);
    }
    // Prefix sums and count.  Throws std::length_error beyond 2^32 - 1
    // members (a mesh's vertex ids are 32-bit anyway).
    void finish();
    // Members before (i, j) in point order: its vertex id if a member.  A
    // word with no member has no prefix written, and is not read (0).
    std::int64_t rank(std::int64_t i, std::int64_t j) const {
        const std::size_t w = word(i, j);
        return words[w] ? rank_in_word(w, static_cast<int>(i & 63)) : 0;
    }
    // Members before bit b of word w, a word with a member (after finish).
    std::int64_t rank_in_word(std::size_t w, int b) const {
        return static_cast<std::int64_t>(prefix[w]) + std::popcount(words[w] & ((std::uint64_t{1} << b) - 1));
    }
    // rank(i + q, j) for q < n <= 3 (the points must lie in the row), valid
    // for the members among them: one word's prefix and bits, unless the run
    // crosses into the next word.
    std::array<std::int64_t, 3> rank_run(std::int64_t i, std::int64_t j, int n) const {
        const int b = static_cast<int>(i & 63);
        std::array<std::int64_t, 3> r{};
        if (b + n > 64) {
            for (int q = 0; q < n; ++q) r[static_cast<std::size_t>(q)] = rank(i + q, j);
            return r;
        }
        const std::size_t w = word(i, j);
        const std::uint64_t bits = words[w] >> b;
        if (!bits) return r;  // no member among them
        r[0] = rank_in_word(w, b);
        r[1] = r[0] + static_cast<std::int64_t>(bits & 1);
        r[2] = r[1] + static_cast<std::int64_t>((bits >> 1) & 1);
        return r;
    }
    // fn(w, i0, bits, rank0) for every non-zero word of row j, in increasing
    // i (after finish): its index w, its first point i0, its members and the
    // rank of its first member.  Point sets of the same dimensions share the
    // word layout, so w indexes theirs too.
    template <class Fn>
    void for_each_word_in_row(std::int64_t j, Fn&& fn) const {
        const std::int64_t by = j >> 7;
        for (std::int64_t bx = 0; bx < blocks_x; ++bx) {
            if (!flagged[static_cast<std::size_t>(by * blocks_x + bx)]) continue;
            const std::size_t base = static_cast<std::size_t>((by * blocks_x + bx) * (block_words * block_rows) + ((j & 127) << 2));
            for (int q = 0; q < block_words; ++q)
                if (const std::uint64_t bits = words[base + static_cast<std::size_t>(q)])
                    fn(base + static_cast<std::size_t>(q), (bx * block_words + q) * 64, bits,
                       static_cast<std::int64_t>(prefix[base + static_cast<std::size_t>(q)]));
        }
    }
};

// The balanced quadtree, as arrays (no pointers).  Level 0 (the lattice
// squares) stores nothing: a square is a finest leaf iff its level-1 parent is
// split (or top = 0).  The levels below the tiles' (1 .. local_top, local_top =
// min(tile_log - 1, top)) are stored per tile of the signs (tiles.hpp), and
// only for *active* tiles: tiles with sampled signs or on the lattice border,
// and their eight neighbours.  In any other tile every point is non-critical
// with the tile's sign σ, so all its nodes below the tile's level are
// coarsenable with σ and none is split: a split can only come from a
// non-coarsenable node, all of which lie in tiles with sampled signs or on
// the border, and 2:1 balance carries a split from level m to level m + 1 at
// most 2^(m+1) squares further, which sums to less than one tile (T = 2^tile_log)
// below the tiles' level.  Levels local_top + 1 .. top are dense arrays,
// nodes_x[l] x nodes_y[l], row-major, with at most one node per tile.
// Level 1 stores no split array: it has no balance constraint (nothing is
// split below it), so its nodes are split iff not coarsenable.
struct Quadtree {
    std::int64_t nx = 0, ny = 0;  // lattice squares
    int top = 0;                  // level of the roots
    PointSet warped;              // the warped points (warped[k] has rank k)
    std::vector<std::int64_t> nodes_x, nodes_y;     // per level: ceil(n / 2^l)
    // Dense levels l > local_top: σ if coarsenable, else 0; 1 if split.
    std::vector<std::vector<std::int8_t>> sign;
    std::vector<std::vector<std::uint8_t>> split;
    std::int64_t nodes(int l) const { return nodes_x[static_cast<std::size_t>(l)] * nodes_y[static_cast<std::size_t>(l)]; }

    // Per-tile levels 1 .. local_top.
    int tile_log = 1, local_top = 0;
    std::int64_t tiles_x = 0;
    std::vector<std::int32_t> tile_slot;     // per tile: its slot if active, else -1
    std::vector<std::int8_t> tile_sign;      // per tile: σ of an inactive tile
    std::vector<std::int64_t> active;        // per slot: its tile (row-major order)
    std::vector<std::int64_t> active_x;      // per slot: its tile's column
    std::vector<std::int64_t> row_start;     // per tile row: its first slot
    std::vector<std::int64_t> local_offset;  // per level: offset of its nodes in a slot
    std::int64_t local_size = 0;             // nodes per slot, all levels
    std::vector<std::int8_t> local_sign;     // per slot and level, (T >> l)^2 nodes, row-major
    // Split flags of levels 2 .. local_top only (level 1 is split iff not
    // coarsenable), per slot: local_size - level1 bytes each.
    std::int64_t level1 = 0;                 // nodes of level 1 per slot, (T / 2)^2
    Buffer<std::uint8_t> local_split;        // every byte written by build_quadtree

    // Node (I, J) of per-tile level l: its slot (-1: inactive tile) and index
    // in the slot's arrays.
    std::int64_t tile_of(int l, std::int64_t I, std::int64_t J) const {
        const int h = tile_log - l;
        return (I >> h) + (J >> h) * tiles_x;
    }
    std::int64_t local_index(int l, std::int64_t slot, std::int64_t I, std::int64_t J) const {
        const int h = tile_log - l;
        const std::int64_t m = (std::int64_t{1} << h) - 1;
        return slot * local_size + local_offset[static_cast<std::size_t>(l)] + ((J & m) << h) + (I & m);
    }
    // The same for local_split, levels 2 .. local_top: a node's index there
    // from its index `local` in local_sign (slot `slot`), or from (I, J).
    std::int64_t split_of_local(std::int64_t slot, std::int64_t local) const { return local - (slot + 1) * level1; }
    std::int64_t split_index(int l, std::int64_t slot, std::int64_t I, std::int64_t J) const {
        return split_of_local(slot, local_index(l, slot, I, J));
    }
    // Whether the node at index `local` of local_sign (slot `slot`, per-tile
    // level 1 <= l <= local_top) is split: level 1 where not coarsenable
    // (code 0), higher levels by their flag.
    bool local_is_split(int l, std::int64_t slot, std::int64_t local) const {
        return l == 1 ? local_sign[static_cast<std::size_t>(local)] == 0
                      : local_split[static_cast<std::size_t>(split_of_local(slot, local))] != 0;
    }
    // σ of node (I, J) of level 1 <= l <= top if coarsenable, else 0; (I, J)
    // within the level's nodes.
    std::int8_t node_sign(int l, std::int64_t I, std::int64_t J) const {
        if (l > local_top)
            return sign[static_cast<std::size_t>(l)][static_cast<std::size_t>(I + J * nodes_x[static_cast<std::size_t>(l)])];
        const std::int64_t k = tile_of(l, I, J);
        const std::int32_t s = tile_slot[static_cast<std::size_t>(k)];
        return s < 0 ? tile_sign[static_cast<std::size_t>(k)] : local_sign[static_cast<std::size_t>(local_index(l, s, I, J))];
    }

    // Whether node (i, j) of level l exists and is split.  Levels above `top`
    // are all split (the roots form a forest); level 0 never is.
    bool is_split(int l, std::int64_t i, std::int64_t j) const {
        if (l > top) return true;
        const std::size_t L = static_cast<std::size_t>(l);
        if (l == 0 || i < 0 || j < 0 || i >= nodes_x[L] || j >= nodes_y[L]) return false;
        if (l > local_top) return split[L][static_cast<std::size_t>(i + j * nodes_x[L])] != 0;
        const std::int64_t k = tile_of(l, i, j);
        const std::int32_t s = tile_slot[static_cast<std::size_t>(k)];
        // An inactive tile: no split node above level 1, and level 1 split
        // only if the tile's σ is 0.
        if (s < 0) return l == 1 && tile_sign[static_cast<std::size_t>(k)] == 0;
        return local_is_split(l, s, local_index(l, s, i, j));
    }
    // Whether lattice square (i, j) is a finest leaf.
    bool is_finest(std::int64_t i, std::int64_t j) const { return is_split(1, i >> 1, j >> 1); }
};

// Build the tree: critical points from the signs, the set of `warped` points,
// the coarsenability pyramid up to level log2(max_cell) (max_cell 0: as coarse
// as the lattice allows), then 2:1 balance.  Throws std::invalid_argument if
// max_cell is negative or not a power of two, or if the signs' tiles are
// larger than 128 squares (tile_log > 7: a row of a tile's level-1 nodes is
// one 64-bit word).
Quadtree build_quadtree(const Lattice& lattice, const TiledSigns& signs, std::span<const WarpedPoint> warped,
                        std::int64_t max_cell);

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
    std::vector<Leaf> coarse;              // levels >= 1, by increasing level; within a level row-major, or tile by tile (quadtree.cpp)
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

// All leaves (deterministic order).  leaves_per_level[l] counts them.  With
// drop_outside, coarse leaves outside the region (sign +1, which emit
// nothing) are counted but not returned.
Leaves quadtree_leaves(const Quadtree& tree, std::vector<std::int64_t>* leaves_per_level = nullptr, bool drop_outside = false);

// The checks of the quadtree's invariants, from scratch (O(lattice) memory):
// the leaves tile the lattice; edge-adjacent leaves differ by at most one
// level; every square with a critical corner (zero-valued, or an endpoint of a
// cut edge of `signs`) is a finest leaf; every square on the lattice border
// with an inside corner is a finest leaf; every coarse leaf's points all have
// its sign, non-zero.  Used by the tests, and asserted in debug builds.
struct QuadtreeCheck {
    std::int64_t untiled = 0;            // squares covered by no leaf or by several
    std::int64_t unbalanced = 0;         // adjacent squares whose leaves differ by >= 2 levels
    std::int64_t coarse_critical = 0;    // squares with a critical corner inside a coarse leaf
    std::int64_t coarse_border = 0;      // inside border squares inside a coarse leaf
    std::int64_t bad_sign = 0;           // coarse leaves with a point of another sign
    std::vector<std::string> messages;
    bool ok() const { return untiled == 0 && unbalanced == 0 && coarse_critical == 0 && coarse_border == 0 && bad_sign == 0; }
};
QuadtreeCheck check_quadtree(const Quadtree& tree, const TiledSigns& signs);

// Triangles of the leaves.  Finest leaves: the square's diagonal by `rule`
// exactly as the uniform triangulation (warped_square_diagonal where a corner
// is warped or zero-valued, AD otherwise) and the triangles with three inside corners.
// Coarse inside leaves: AD if no side is split; otherwise the centre template
// (centre joined to the corners and to the split sides' midpoints).  Vertices
// compacted in lattice-point order, boundary edges oriented with the region on
// their left, region tags as in the uniform mesh.
Mesh triangulate_graded(const LevelSet& f, const Lattice& lattice, const TiledSigns& signs,
                        const Quadtree& tree, const Leaves& leaves, std::span<const WarpedPoint> warped,
                        DiagonalRule rule, TriangulateStats* stats = nullptr);

}  // namespace warpmesh
