// uniform.hpp — the paper's uniform lattice-warping mesher, end to end.
#pragma once

#include "warpmesh/lattice.hpp"

namespace warpmesh {

struct PhaseTimes {
    double sample = 0, signs = 0, cut_points = 0, warp = 0, triangulate = 0;  // seconds
    double total() const { return sample + signs + cut_points + warp + triangulate; }
};

struct UniformResult {
    Mesh mesh;
    PhaseTimes times;
    TriangulateStats stats;
    std::int64_t cut_edges = 0;
    std::int64_t warped_points = 0;
};

// lattice → signs → cut points → warp → triangulate.
UniformResult mesh_uniform(const LevelSet& f, const Lattice& lattice, DiagonalRule rule);

}  // namespace warpmesh
