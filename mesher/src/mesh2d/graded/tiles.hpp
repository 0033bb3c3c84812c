// tiles.hpp — the graded mesher's front end: f is sampled only where the
// level set can pass.  Private to mesher/src.
//
// The uniform front end (uniform.hpp) samples f at every lattice point; the
// graded mesh has O(boundary) triangles, so that work would dominate it.  Here
// the lattice is cut into tiles of T x T squares (T = 2^tile_log; the last
// tile of a row or column may be smaller).  A tile's *reach* is the closed box
// of its points grown by one spacing on every side: it holds the tile's points
// and all their 4-neighbours.  LevelSet::range bounds f on the reach of a
// tile — found top-down: a block of tiles whose reach the bound decides
// decides all of its tiles, others split in four, so the bounds asked for
// follow the boundary too:
//
//   * lo > 0 or hi < 0: every point of the tile has that sign σ and so has
//     every neighbour, so no point of the tile is critical (quadtree.hpp): none
//     is zero-valued, none is an endpoint of a cut edge, none warps.  The
//     tile is *uniform* and is never sampled.
//   * otherwise the tile is *sampled*: f at its (T+1)^2 points, their signs,
//     and the cut edges that start at points it owns (below).
//
// A range bound is conservative (levelset.hpp), so every sign read from a
// uniform tile is the sign value() would have given: the signs, cut edges and
// warped points are exactly those of the uniform front end, and the graded
// mesh is the same mesh as with every tile sampled (tested: a level set with
// no range bound samples every tile).  Only the work differs: sampled tiles
// lie within about a tile of the level set, O(boundary length x T) points.
//
// Ownership.  Point (i, j) belongs to tile (min(i >> b, tx - 1), min(j >> b,
// ty - 1)), b = tile_log: points on a border between tiles belong to the
// upper / right one.  The cut edge from p to p + x or p + y is found by the
// tile that owns p; both endpoints lie in that tile's point box, so one
// tile's samples decide it.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh {

// Signs of f at the lattice points, per tile.
struct TiledSigns {
    int tile_log = 4;
    std::int64_t nx = 0, ny = 0;  // lattice squares
    std::int64_t tx = 0, ty = 0;  // tiles
    // Per tile (row-major): the index of its block in `blocks`, or -1 for a
    // uniform tile, whose points all have sign uniform[t] (never 0).
    std::vector<std::int32_t> slot;
    std::vector<std::int8_t> uniform;
    // Per sampled tile, (T + 3)^2 signs: its points (T + 1)^2 and a ring of one
    // point around them (0 where the ring leaves the lattice), row-major.
    std::vector<std::int8_t> blocks;

    std::int64_t size() const { return std::int64_t{1} << tile_log; }
    std::int64_t stride() const { return size() + 3; }
    std::int64_t tile_of_x(std::int64_t i) const { return std::min(i >> tile_log, tx - 1); }
    std::int64_t tile_of_y(std::int64_t j) const { return std::min(j >> tile_log, ty - 1); }
    // The sign at lattice point (i, j), 0 <= i <= nx, 0 <= j <= ny.
    std::int8_t operator()(std::int64_t i, std::int64_t j) const {
        const std::int64_t I = tile_of_x(i), J = tile_of_y(j);
        const std::int32_t s = slot[static_cast<std::size_t>(I + J * tx)];
        return s < 0 ? uniform[static_cast<std::size_t>(I + J * tx)] : *at(s, I, J, i, j);
    }
    // The signs at the corners A, B, C, D of lattice square (i, j), i < nx,
    // j < ny: one lookup, since a tile's block holds all corners of its squares.
    std::array<std::int8_t, 4> square(std::int64_t i, std::int64_t j) const {
        const std::int64_t I = i >> tile_log, J = j >> tile_log;
        const std::int32_t s = slot[static_cast<std::size_t>(I + J * tx)];
        if (s < 0) {
            const std::int8_t u = uniform[static_cast<std::size_t>(I + J * tx)];
            return {u, u, u, u};
        }
        const std::int8_t* c = at(s, I, J, i, j);
        return {c[0], c[1], c[stride()], c[stride() + 1]};
    }
    // Point (i, j) in the block of sampled tile (I, J), slot s.
    const std::int8_t* at(std::int32_t s, std::int64_t I, std::int64_t J, std::int64_t i, std::int64_t j) const {
        return block(s) + (j - (J << tile_log) + 1) * stride() + (i - (I << tile_log) + 1);
    }
    const std::int8_t* block(std::int32_t s) const { return blocks.data() + static_cast<std::int64_t>(s) * stride() * stride(); }
    std::int8_t* block(std::int32_t s) { return blocks.data() + static_cast<std::int64_t>(s) * stride() * stride(); }
    std::int64_t sampled_tiles() const { return static_cast<std::int64_t>(blocks.size()) / (stride() * stride()); }
};

// Default tile: 16 x 16 squares.  Smaller tiles sample fewer points near the
// level set but ask for more range bounds and lookups.
inline constexpr int default_tile_log = 4;

struct TiledFront {
    TiledSigns signs;
    std::vector<WarpedPoint> warped;  // sorted by point, as warp_points returns them
    std::int64_t cut_edges = 0;
    std::int64_t sampled_points = 0;
    double tiles_seconds = 0, warp_seconds = 0;  // classify + sample + signs + cut points; warp
};

// Classify the tiles, sample the others, signs, cut edges, warp.  Throws
// InputError if f is not finite at a sampled point.
TiledFront warp_tiles(const LevelSet& f, const Lattice& lattice, int tile_log = default_tile_log);

// The same tiles from the signs of all points: every tile sampled (tests), or
// (sample_every_tile false) only those whose points do not all share one
// non-zero sign — the others uniform, as warp_tiles would make them
// (multi-material graded meshes, whose signs are given per point).
TiledSigns tile_signs(const Lattice& lattice, std::span<const std::int8_t> signs, int tile_log = default_tile_log,
                      bool sample_every_tile = true);

}  // namespace warpmesh
