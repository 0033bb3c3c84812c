// uniform.hpp — the paper's uniform lattice-warping mesher, end to end.
#pragma once

#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh {

struct PhaseTimes {
    double sample = 0, signs = 0, cut_points = 0, warp = 0, triangulate = 0;  // seconds
    // The certification, when the pipeline runs it (pipeline/mesh2d.hpp:
    // certify): the keys' gathering (SquareKeys::seconds) and their lookup.
    double certify = 0;
    double total() const { return sample + signs + cut_points + warp + triangulate + certify; }
};

// The uniform front end, in order and timed: sample f at every lattice point
// → signs → cut points → warp.  The sampled values are dropped after the cut
// points.  (The graded mesher samples only where the boundary can be:
// src/mesh2d/graded/tiles.hpp.)
struct WarpedLattice {
    Buffer<std::int8_t> signs;
    std::vector<WarpedPoint> warped;
    std::int64_t cut_edges = 0;
    double sample = 0, signs_seconds = 0, cut_points = 0, warp = 0;  // seconds
};
WarpedLattice warp_lattice(const LevelSet& f, const Lattice& lattice);

// GradedResult (graded.hpp) starts with the same fields and adds the graded
// path's own (sampled points, leaves per level, the invariant check); the two
// stay separate types because their phase times differ (PhaseTimes against
// GradedTimes) — `duplicates` lists the pair, on purpose.
struct UniformResult {
    Mesh mesh;
    PhaseTimes times;
    TriangulateStats stats;
    std::int64_t cut_edges = 0;
    std::int64_t warped_points = 0;
    SquareKeys keys;  // with keys.keys: what certification reads (empty otherwise)
};

// lattice → signs → cut points → warp → triangulate.
// With `keys.keys`, also the mesh's SquareKeys (lattice.hpp), which the
// pipeline certifies (pipeline/mesh2d.hpp: certify; cell data
// "certified_min_angle", the summary, optionally the verification).
// `metric`: LatticeMetric::rhombic meshes f in lattice coordinates with the
// rhombic rule: f is then f∘P and the mesh's vertices are in lattice
// coordinates (rhombic.hpp maps them); its keys are in that metric, and so
// certified (the rhombic tables, the rhombic forms for verify).
UniformResult mesh_uniform(const LevelSet& f, const Lattice& lattice, DiagonalRule rule, KeyOptions keys = {},
                           LatticeMetric metric = LatticeMetric::square);

}  // namespace warpmesh
