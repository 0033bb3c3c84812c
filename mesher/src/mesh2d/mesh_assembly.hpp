// mesh_assembly.hpp — joining what the triangulations (uniform/triangulate.cpp,
// graded/triangulate_graded.cpp) collect in parallel pieces — per row or per
// chunk, in mesh order — into the Mesh and its statistics.  Private to
// mesher/src.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "warpmesh/mesh2d/lattice.hpp"
#include "warpmesh/core/mesh.hpp"

namespace warpmesh {

// Appends the boundary edges {from, to, tag} of the pieces, in order, to
// mesh.boundary and mesh.boundary_tag.
inline void append_boundary(Mesh& mesh, std::span<const std::vector<std::array<std::int32_t, 3>>> pieces) {
    std::size_t n = 0;
    for (const auto& p : pieces) n += p.size();
    mesh.boundary.reserve(mesh.boundary.size() + n);
    mesh.boundary_tag.reserve(mesh.boundary_tag.size() + n);
    for (const auto& p : pieces)
        for (const auto& e : p) {
            mesh.boundary.push_back({e[0], e[1]});
            mesh.boundary_tag.push_back(e[2]);
        }
}

// The statistics of a triangulation into *stats (if not null): the counts,
// and — if stats->keyed_squares is set — the keyed squares of the pieces,
// joined in order.
inline void record_stats(TriangulateStats* stats, std::int64_t warped_squares, std::int64_t forced_diagonals,
                         std::span<const std::vector<KeyedSquare>> keyed) {
    if (!stats) return;
    stats->warped_squares = warped_squares;
    stats->forced_diagonals = forced_diagonals;
    if (stats->keyed_squares) {
        stats->keyed_squares->clear();
        for (const auto& p : keyed) stats->keyed_squares->insert(stats->keyed_squares->end(), p.begin(), p.end());
    }
}

}  // namespace warpmesh
