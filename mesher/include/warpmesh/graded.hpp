// graded.hpp — the graded interior mesher: the uniform lattice-warping mesh
// near the level set, coarsening inward on a 2:1-balanced quadtree.
//
// Every lattice square with a critical corner (on the level set, or an
// endpoint of a cut edge) is a finest leaf with no split side, so the warped
// squares — the only ones whose angles depend on f — are triangulated as in the
// uniform mesh and the same certified bounds apply; coarse leaves are right
// isosceles templates (45°, 45°, 90°).  The work follows the boundary's length,
// not the lattice's area.  The quadtree and its invariants are described with
// the internals (src/graded/quadtree.hpp); most callers want mesh() in
// pipeline.hpp, which runs this with graded = true.
#pragma once

#include <cstdint>
#include <vector>

#include "warpmesh/certified.hpp"
#include "warpmesh/lattice.hpp"

namespace warpmesh {

struct GradedTimes {
    double tiles = 0;  // classify tiles, sample, signs, cut points (tiles.hpp)
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
    std::int64_t sampled_points = 0;  // evaluations of f (tiles.hpp; neighbouring sampled tiles share a border)
    std::vector<std::int64_t> leaves_per_level;  // index = level; all leaves, inside or outside
    CertifiedSummary certified;  // available = false unless certification ran
};

// tiles (sample → signs → cut points where the level set can pass) → warp →
// quadtree → triangulate.  max_cell is K,
// the largest leaf width in squares: a power of two, or 0 for as coarse as the
// lattice allows.
GradedResult mesh_graded(const LevelSet& f, const Lattice& lattice, DiagonalRule rule, std::int64_t max_cell,
                         const CertifyOptions& certify = CertifyOptions{false, false, false});

}  // namespace warpmesh
