// graded.hpp — the graded interior mesher: the uniform lattice-warping mesh
// near the level set, coarsening inward on a 2:1-balanced quadtree.
//
// The pipeline (mesher/src/mesh2d/graded/, internal headers beside the sources):
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

#include "warpmesh/core/grading.hpp"  // grading_buffer, min_grading, max_grading
#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh {

struct GradedTimes {
    double tiles = 0;  // classify tiles, sample, signs, cut points
    double warp = 0, quadtree = 0, triangulate = 0;  // seconds
    double certify = 0;  // the certification, when the pipeline runs it (as PhaseTimes::certify)
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
    std::int64_t invariant_squares = -1;  // squares check_critical_squares_finest checked (-1: not run)
    SquareKeys keys;  // with keys.keys: what certification reads (empty otherwise)
};

// Size control.
//
// Element size.  A coarse leaf of width K squares (spacing s) is cut into
// right isosceles triangles whose longest edge is at most its diagonal
// √2 K s (the centre template's longest edge is K s); a finest square with
// warped corners has edges of at most √5 s (each corner slides at most s/2
// along a lattice line: a diagonal grows to √((2s)² + s²) at most), the
// same in the uniform mesh.  max_cell_for_size(H, s) is the largest power of
// two K with √2 K s <= H: with it every triangle of a graded mesh has its
// longest edge <= H.  H must be at least √5 s (std::invalid_argument
// otherwise): below that the band's triangles may exceed it whatever K.
//
// Grading.  G in [1.1, 2] bounds how fast leaf sizes grow away from the
// boundary: grading_buffer(G) = n is 0 for G = 2 (the plain 2:1-balanced
// tree: at least one leaf of width w before one of width 2w), else the
// smallest n >= 2 with n >= 1 / log2(G) - 0.01 (the tolerance lets 1.414
// mean √2): every coarse inside leaf of width w is then farther than n w
// (max-norm) from the boundary's critical points, so on any straight path
// from the boundary at least n leaves of width <= w come before one of
// width 2w — a growth of at most 2^(1/n) <= G per leaf on average
// (quadtree.hpp).  A ratio above 2 between neighbours is not offered: it
// would put two vertices on a leaf's side, which the right isosceles
// templates do not allow.  Throws std::invalid_argument outside [1.1, 2].
// (grading_buffer and its constants: core/grading.hpp, shared with 3D.)
std::int64_t max_cell_for_size(double max_size, double spacing);

// tiles (sample → signs → cut points where the level set can pass) → warp →
// quadtree → leaves → triangulate.  max_cell is K, the largest leaf width in
// squares: a power of two, or 0 for as coarse as the lattice allows;
// grading_buffer is n above (0: plain 2:1 balance); `keys` what is recorded
// for the certification (lattice.hpp: KeyOptions; with check_invariant,
// invariant_squares is set).  Throws
// InputError if f is not finite at a sampled point, std::invalid_argument if
// max_cell is negative or not a power of two or grading_buffer is not in
// 0 .. max_grading_buffer, std::length_error if the mesh needs more than
// 32-bit indices.  The mesh does not depend on the thread count.
GradedResult mesh_graded(const LevelSet& f, const Lattice& lattice, DiagonalRule rule, std::int64_t max_cell,
                         KeyOptions keys = {}, int grading_buffer = 0);

}  // namespace warpmesh
