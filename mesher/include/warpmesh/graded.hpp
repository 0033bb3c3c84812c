// graded.hpp — the graded interior mesher: the uniform lattice-warping mesh
// near the level set, coarsening inward on a 2:1-balanced quadtree.
//
// The pipeline (mesher/src/graded/, internal headers beside the sources):
//
//   tiles.cpp               → sample → signs → cut points, only in the tiles
//                             the level set can reach (a range bound per tile);
//                             the same signs and cut points as the uniform
//                             front end, without its O(lattice) work (tiles.hpp)
//   warp.cpp                → the warp, as in the uniform mesher
//   quadtree.cpp            → which squares may be merged into coarse leaves,
//                             2:1 balance (quadtree.hpp: the mathematics, the
//                             invariant the angle proof rests on);
//   leaves.cpp              → the leaves
//   triangulate_graded.cpp  → triangles of the leaves, vertices, boundary
//   graded.cpp              → the driver, timed
//
// Every square with a warped or zero-valued corner is a finest leaf,
// triangulated exactly as in the uniform mesh (a fan square of
// DiagonalRule::fan too: its centroid fan, the centre a new vertex), so the
// certified angle bounds hold; coarse leaves are exact 45-45-90 templates.  The graded mesh covers
// the uniform mesh's region with the same boundary edges.  The work follows
// the boundary, not the lattice's area.
#pragma once

#include <cstdint>
#include <vector>

#include "warpmesh/certified.hpp"
#include "warpmesh/lattice.hpp"

namespace warpmesh {

struct GradedTimes {
    double tiles = 0;  // classify tiles, sample, signs, cut points
    double warp = 0, quadtree = 0, triangulate = 0;  // seconds
    double certify = 0;  // certification post-pass (certified.hpp), if asked
    double total() const { return tiles + warp + quadtree + triangulate + certify; }
};

struct GradedResult {
    Mesh mesh;
    GradedTimes times;
    TriangulateStats stats;
    std::int64_t cut_edges = 0;
    std::int64_t warped_points = 0;
    std::int64_t sampled_points = 0;  // evaluations of f (neighbouring sampled tiles share a border)
    std::vector<std::int64_t> leaves_per_level;  // index = level; all leaves, inside or outside
    CertifiedSummary certified;  // available = false unless certification ran
    std::int64_t invariant_squares = -1;  // squares check_critical_squares_finest checked (-1: not run)
};

// tiles (sample → signs → cut points where the level set can pass) → warp →
// quadtree → leaves → triangulate [→ certify].  max_cell is K, the largest
// leaf width in squares: a power of two, or 0 for as coarse as the lattice
// allows.  Throws InputError if f is not finite at a sampled point,
// std::invalid_argument if max_cell is negative or not a power of two,
// std::length_error if the mesh needs more than 32-bit indices.  The mesh
// does not depend on the thread count.
GradedResult mesh_graded(const LevelSet& f, const Lattice& lattice, DiagonalRule rule, std::int64_t max_cell,
                         const CertifyOptions& certify = CertifyOptions{false, false, false});

}  // namespace warpmesh
