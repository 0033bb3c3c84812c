// graded.cpp — the graded mesher: the tiled front end (tiles.hpp), the
// balanced quadtree and its triangulation, timed.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "warpmesh/mesh2d/graded.hpp"

#include "mesh2d/gather_keys.hpp"
#include "mesh2d/graded/quadtree.hpp"
#include "mesh2d/graded/tiles.hpp"
#include "mesh2d/graded/triangulate_graded.hpp"

namespace warpmesh {

std::int64_t max_cell_for_size(double max_size, double spacing) {
    if (!(spacing > 0) || !(max_size >= std::sqrt(5.0) * spacing) || !std::isfinite(max_size))
        throw std::invalid_argument("max size must be finite and at least sqrt(5) * spacing");
    std::int64_t K = 1;
    while (K < (std::int64_t{1} << 30) && std::sqrt(2.0) * static_cast<double>(2 * K) * spacing <= max_size) K *= 2;
    return K;
}

GradedResult mesh_graded(const LevelSet& f, const Lattice& lattice, DiagonalRule rule, std::int64_t max_cell,
                         KeyOptions keys, int grading_buffer) {
    using clock = std::chrono::steady_clock;
    GradedResult r;
    const TiledFront front = warp_tiles(f, lattice);
    r.times.tiles = front.tiles_seconds;
    r.times.warp = front.warp_seconds;
    r.cut_edges = front.cut_edges;
    r.warped_points = static_cast<std::int64_t>(front.warped.size());
    r.sampled_points = front.sampled_points;
    const TiledSigns& signs = front.signs;
    const auto& warped = front.warped;

    auto t0 = clock::now();
    const Quadtree tree = build_quadtree(lattice, signs, warped, max_cell, grading_buffer);
    const Leaves leaves = quadtree_leaves(tree, &r.leaves_per_level, /*drop_outside=*/true);
    r.times.quadtree = seconds_since(t0);
    if (keys.check_invariant) {  // the invariant the certificates rest on, from the leaf list
        const CriticalSquaresCheck inv = check_critical_squares_finest(leaves, signs, warped);
        if (!inv.ok()) throw std::logic_error(inv.first);
        r.invariant_squares = inv.squares;
    }

    t0 = clock::now();
    std::vector<KeyedSquare> keyed;
    if (keys.keys) r.stats.keyed_squares = &keyed;
    r.mesh = triangulate_graded(f, lattice, signs, tree, leaves, warped, rule, &r.stats);
    r.times.triangulate = seconds_since(t0);
    r.stats.keyed_squares = nullptr;
    if (keys.keys)
        r.keys = gather_keys(lattice, std::move(keyed), warped, LatticeMetric::square, [&](std::int64_t i, std::int64_t j, std::array<std::int8_t, 12>& st) {
            stencil_signs(lattice, i, j, signs, st);
            return false;
        });
    return r;
}

}  // namespace warpmesh
