// leaves.cpp — the leaves of the balanced quadtree (quadtree_leaves in
// quadtree.hpp): the finest leaves as their split level-1 parents, the coarse
// leaves level by level, each with its split sides.
//
// The leaves of level l are the unsplit nodes among the children of the split
// nodes of level l + 1 (all unsplit nodes at the top).  A leaf's side is split
// iff its edge neighbour across it is split: by 2:1 balance that neighbour's
// two children along the side are then leaves one level finer, and the side's
// midpoint is a vertex.
//
// Per level, rows of parents (or, on the tiled levels below tiled.top, tiles)
// in order; with several threads, chunks of them in parallel, each chunk's
// leaves in order, then joined: the list does not depend on the thread count.
#include <algorithm>
#include <numeric>

#include "mesh2d/graded/quadtree.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh {
namespace {

constexpr std::int64_t rows_per_chunk = 32;
// Below this much work (nodes of the level) a listing runs on one thread.
constexpr std::int64_t parallel_min = std::int64_t{1} << 16;

bool more_than_one_thread() {
#ifdef _OPENMP
    return omp_get_max_threads() > 1;
#else
    return false;
#endif
}

// Rows (or tiles) [0, rows) listed by emit(R0, R1, out) -> dropped, appending
// to `all`: in chunks of rows_per_chunk in parallel when there is enough
// work, the chunks' outputs joined in order.  Returns the dropped count.
template <class Out, class Emit>
std::int64_t in_chunks(std::int64_t rows, std::int64_t work, Out& all, Emit&& emit) {
    const std::int64_t nchunks = (rows + rows_per_chunk - 1) / rows_per_chunk;
    if (!more_than_one_thread() || nchunks < 2 || work < parallel_min) return emit(0, rows, all);
    std::vector<Out> parts(static_cast<std::size_t>(nchunks));
    std::int64_t dropped = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : dropped)
    for (std::int64_t ch = 0; ch < nchunks; ++ch)
        dropped += emit(ch * rows_per_chunk, std::min(rows, (ch + 1) * rows_per_chunk), parts[static_cast<std::size_t>(ch)]);
    std::size_t add = 0;
    for (const auto& c : parts) add += c.size();
    all.reserve(all.size() + add);
    for (const auto& c : parts) all.insert(all.end(), c.begin(), c.end());
    return dropped;
}

// The finest leaves: the split level-1 nodes, by row pairs.  Reserved for the
// most there can be (only the pages written are ever touched, and no growth
// copies them): on a tiled level 1 only in active tiles, on a dense one one
// per node; with top = 0, every column.
void list_finest(const Quadtree& t, Leaves& out) {
    const std::int64_t pairs = (t.ny + 1) / 2, px = (t.nx + 1) / 2;
    out.parents.reserve(static_cast<std::size_t>(t.top == 0          ? px * pairs
                                                 : t.is_tiled(1) ? t.tiled.slots() << (2 * t.tiled.nodes_log(1))
                                                                 : t.nodes(1)));
    out.pair_start.assign(static_cast<std::size_t>(pairs) + 1, 0);
    in_chunks(pairs, px * pairs, out.parents, [&](std::int64_t R0, std::int64_t R1, std::vector<std::int32_t>& o) {
        for (std::int64_t R = R0; R < R1; ++R) {
            const std::size_t before = o.size();
            auto add = [&](std::int64_t P) { o.push_back(static_cast<std::int32_t>(P)); };
            if (t.top == 0)
                for (std::int64_t P = 0; P < px; ++P) add(P);
            else
                t.visit(1, [&](const auto& level) { level.for_each_split(R, add); });
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
}

// The coarse leaves of one level l >= 1.
struct LevelLeaves {
    const Quadtree& t;
    int l;
    bool drop_outside;
    std::int64_t mx, my;  // the level's nodes
    int h;                // on a tiled level: a tile has 2^h x 2^h nodes

    LevelLeaves(const Quadtree& tree, int level, bool drop)
        : t(tree),
          l(level),
          drop_outside(drop),
          mx(tree.nodes_x[static_cast<std::size_t>(level)]),
          my(tree.nodes_y[static_cast<std::size_t>(level)]),
          h(tree.is_tiled(level) ? tree.tiled.nodes_log(level) : 0) {}

    // Node (I, J), with sign σ, is a leaf: only counted when it is outside
    // and dropped (before its sides are looked up), else appended with its
    // split sides, asked of split(a, b) for its four edge neighbours.
    template <class Split>
    void put(std::vector<Leaf>& o, std::int64_t& dropped, std::int64_t I, std::int64_t J, std::int8_t sign, Split&& split) const {
        if (drop_outside && sign > 0) return void(++dropped);
        const std::uint8_t sides = static_cast<std::uint8_t>((split(I, J - 1) ? side_bottom : 0) | (split(I + 1, J) ? side_right : 0) |
                                                             (split(I, J + 1) ? side_top : 0) | (split(I - 1, J) ? side_left : 0));
        o.push_back({static_cast<std::int32_t>(I << l), static_cast<std::int32_t>(J << l), static_cast<std::int8_t>(l), sign, sides});
    }
    void put_node(std::vector<Leaf>& o, std::int64_t& dropped, std::int64_t I, std::int64_t J) const {
        put(o, dropped, I, J, t.code(l, I, J), [&](std::int64_t a, std::int64_t b) { return t.is_split(l, a, b); });
    }

    // put() for the unsplit nodes among (2P, J), (2P + 1, J) of a tiled level,
    // which lie in one tile: its slot is looked up once, and neighbours inside
    // the tile are read from it; only those across its sides go through
    // Quadtree::is_split.  An inactive tile has no split node.
    void put_pair_in_tile(std::int64_t P, std::int64_t J, std::vector<Leaf>& o, std::int64_t& dropped) const {
        const TileLevels& tl = t.tiled;
        const std::int64_t k = tl.tile_of(l, 2 * P, J);
        const std::int32_t s = tl.slot_of_tile[static_cast<std::size_t>(k)];
        const std::int64_t first = s < 0 ? 0 : tl.index(l, s, 2 * P, J);  // node (2P, J) in the slot
        auto split_at = [&](std::int64_t d) { return tl.is_split_at(l, s, first + d); };  // node at offset d from (2P, J), in the tile
        for (std::int64_t q = 0; q < 2 && 2 * P + q < mx; ++q) {
            if (s >= 0 && split_at(q)) continue;
            const std::int64_t I = 2 * P + q;
            put(o, dropped, I, J, s < 0 ? tl.tile_code[static_cast<std::size_t>(k)] : tl.codes[static_cast<std::size_t>(first + q)],
                [&](std::int64_t a, std::int64_t b) {
                    // Across the tile's side, or no node: as is_split.  Else
                    // the same answer from the slot found above.
                    if (a < 0 || b < 0 || a >= mx || b >= my || ((a ^ I) | (b ^ J)) >> h) return t.is_split(l, a, b);
                    return s >= 0 && split_at((a - 2 * P) + ((b - J) << h));
                });
        }
    }

    // The leaves in rows of parents R0 .. R1 - 1 (rows of the level at the top).
    std::int64_t by_rows(std::int64_t R0, std::int64_t R1, std::vector<Leaf>& o) const {
        std::int64_t dropped = 0;
        const bool roots = l == t.top, tiled = t.is_tiled(l);
        for (std::int64_t R = R0; R < R1; ++R) {
            if (roots && tiled) {
                for (std::int64_t P = 0; 2 * P < mx; ++P) put_pair_in_tile(P, R, o, dropped);
            } else if (roots) {
                for (std::int64_t I = 0; I < mx; ++I)
                    if (!t.is_split(l, I, R)) put_node(o, dropped, I, R);
            } else {
                for (std::int64_t J = 2 * R; J < std::min(2 * R + 2, my); ++J)
                    t.visit(l + 1, [&](const auto& parents) {
                        parents.for_each_split(R, [&](std::int64_t P) {
                            if (tiled) return put_pair_in_tile(P, J, o, dropped);
                            for (std::int64_t I = 2 * P; I < std::min(2 * P + 2, mx); ++I)
                                if (!t.is_split(l, I, J)) put_node(o, dropped, I, J);
                        });
                    });
            }
        }
        return dropped;
    }

    // Split bits beyond side (di, dj) of the tile of slot s, whose nodes
    // start at (I0, J0) and exist for ex columns and ey rows: the row of
    // nodes below or above the tile (bit x: column I0 + x) or the column left
    // or right of it (bit y: row J0 + y), read in the neighbouring tile and
    // answered as is_split does: no node (outside the level's nodes), or an
    // inactive tile: not split.
    std::uint64_t split_beyond(std::int64_t s, std::int64_t I0, std::int64_t J0, std::int64_t ex, std::int64_t ey, std::int64_t di,
                               std::int64_t dj) const {
        const TileLevels& tl = t.tiled;
        const std::int64_t n = std::int64_t{1} << h;
        if ((di < 0 && I0 == 0) || (di > 0 && I0 + ex >= mx) || (dj < 0 && J0 == 0) || (dj > 0 && J0 + ey >= my)) return 0;
        const std::size_t k = static_cast<std::size_t>(tl.tile_of_slot[static_cast<std::size_t>(s)] + di + dj * tl.tiles_x);
        const std::int32_t o = tl.slot_of_tile[k];
        if (o < 0) return 0;
        if (dj) return tl.split_bits(l, o, tl.index(l, o, I0, dj < 0 ? J0 - 1 : J0 + n), n) & bits::low_bits(ex);
        const std::int64_t I = di < 0 ? I0 - 1 : I0 + n;  // (a right neighbour exists only if the tile is full)
        std::uint64_t m = 0;
        for (std::int64_t y = 0; y < ey; ++y) m |= static_cast<std::uint64_t>(tl.is_split_at(l, o, tl.index(l, o, I, J0 + y))) << y;
        return m;
    }

    // The leaves of tiled level l < tiled.top in slots s0 .. s1 - 1, tile by
    // tile: a leaf's parent is then a node of the same tile (so only active
    // tiles have leaves), and a row of the tile's n = 2^h <= 64 nodes is one
    // word of split bits.  A row's leaves are its unsplit nodes under split
    // parents, and their split sides come from shifts of the row and the rows
    // above and below — the tile's own, or those of the neighbouring tiles.
    std::int64_t by_tiles(std::int64_t s0, std::int64_t s1, std::vector<Leaf>& o) const {
        const TileLevels& tl = t.tiled;
        std::int64_t dropped = 0;
        const std::int64_t n = std::int64_t{1} << h;
        std::array<std::uint64_t, bits::word_bits + 2> S;  // split bits of rows -1 .. n of the tile, at S[y + 1]
        std::array<std::uint64_t, bits::word_bits / 2> parent;  // split bits of the parents' rows, doubled
        for (std::int64_t s = s0; s < s1; ++s) {
            const std::int64_t I0 = tl.column_of_slot[static_cast<std::size_t>(s)] << h,
                               J0 = (tl.tile_of_slot[static_cast<std::size_t>(s)] / tl.tiles_x) << h;
            const std::int64_t ex = std::min(n, mx - I0), ey = std::min(n, my - J0);  // the tile's nodes that exist
            const std::uint64_t exist = bits::low_bits(ex);
            // Split parents first: a tile without any has no leaf of level l.
            const std::int64_t pfirst = tl.index(l + 1, s, I0, J0);
            std::uint64_t any = 0;
            for (std::int64_t yp = 0; 2 * yp < ey; ++yp)
                any |= parent[static_cast<std::size_t>(yp)] = bits::double_bits(tl.split_bits(l + 1, s, pfirst + (yp << (h - 1)), n / 2)) & exist;
            if (!any) continue;
            const std::int64_t first = tl.index(l, s, I0, J0);
            for (std::int64_t y = 0; y < ey; ++y) S[static_cast<std::size_t>(y) + 1] = tl.split_bits(l, s, first + (y << h), n) & exist;
            std::uint64_t left = 0, right = 0;
            bool have_columns = false;
            for (std::int64_t y = 0; y < ey; ++y) {
                const std::uint64_t cur = S[static_cast<std::size_t>(y) + 1];
                const std::uint64_t leaves = ~cur & parent[static_cast<std::size_t>(y >> 1)];
                if (!leaves) continue;
                if (y == 0) S[0] = split_beyond(s, I0, J0, ex, ey, 0, -1);
                if (y == ey - 1) S[static_cast<std::size_t>(ey) + 1] = split_beyond(s, I0, J0, ex, ey, 0, 1);
                if (!have_columns && (leaves & (1 | std::uint64_t{1} << (ex - 1)))) {
                    left = split_beyond(s, I0, J0, ex, ey, -1, 0), right = split_beyond(s, I0, J0, ex, ey, 1, 0);
                    have_columns = true;
                }
                const std::uint64_t below = S[static_cast<std::size_t>(y)], above = S[static_cast<std::size_t>(y) + 2];
                const std::uint64_t to_left = cur << 1 | ((left >> y) & 1), to_right = cur >> 1 | ((right >> y) & 1) << (ex - 1);
                bits::for_each_bit(leaves, [&](int x) {
                    const std::int8_t sign = tl.codes[static_cast<std::size_t>(first + (y << h) + x)];
                    if (drop_outside && sign > 0) return void(++dropped);
                    const std::uint8_t sides = static_cast<std::uint8_t>(((below >> x) & 1) * side_bottom | ((to_right >> x) & 1) * side_right |
                                                                         ((above >> x) & 1) * side_top | ((to_left >> x) & 1) * side_left);
                    o.push_back({static_cast<std::int32_t>((I0 + x) << l), static_cast<std::int32_t>((J0 + y) << l), static_cast<std::int8_t>(l),
                                 sign, sides});
                });
            }
        }
        return dropped;
    }
};

}  // namespace

Leaves quadtree_leaves(const Quadtree& t, std::vector<std::int64_t>* per_level, bool drop_outside) {
    Leaves out;
    out.nx = t.nx, out.ny = t.ny;
    if (per_level) per_level->clear();
    list_finest(t, out);
    if (per_level) per_level->push_back(out.finest);

    // Coarse leaves, level by level, reserved for the most there can be.
    std::size_t bound = static_cast<std::size_t>(t.tiled.slots()) << (2 * t.tiled.tile_log);
    for (int l = t.tiled.top + 1; l <= t.top; ++l) bound += static_cast<std::size_t>(t.nodes(l));  // the dense levels
    if (t.top > 0 && t.tiled.top == t.top) bound += static_cast<std::size_t>(t.nodes(t.top));      // roots below the tiles' level
    out.coarse.reserve(bound);
    for (int l = 1; l <= t.top; ++l) {
        const LevelLeaves level(t, l, drop_outside);
        const std::size_t before = out.coarse.size();
        const std::int64_t rows = l == t.top ? level.my : t.nodes_y[static_cast<std::size_t>(l) + 1], work = level.mx * level.my;
        const std::int64_t dropped =
            l < t.tiled.top
                ? in_chunks(t.tiled.slots(), work, out.coarse, [&](std::int64_t s0, std::int64_t s1, std::vector<Leaf>& o) { return level.by_tiles(s0, s1, o); })
                : in_chunks(rows, work, out.coarse, [&](std::int64_t R0, std::int64_t R1, std::vector<Leaf>& o) { return level.by_rows(R0, R1, o); });
        if (per_level) per_level->push_back(static_cast<std::int64_t>(out.coarse.size() - before) + dropped);
    }
    return out;
}

}  // namespace warpmesh
