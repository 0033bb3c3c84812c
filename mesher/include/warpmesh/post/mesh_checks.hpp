// mesh_checks.hpp — the invariants every warpmesh mesh must satisfy, checked
// from scratch on the mesh alone.  Used by the tests, the fuzzers and --verify.
#pragma once

#include <string>
#include <vector>

#include "warpmesh/core/mesh.hpp"

namespace warpmesh {

struct MeshCheck {
    std::int64_t non_ccw = 0;            // triangles with cross product <= 0
    std::int64_t bad_indices = 0;        // vertex indices out of range
    std::int64_t unused_vertices = 0;    // vertices in no triangle (not compacted)
    std::int64_t overfull_edges = 0;     // edges in more than two triangles
    std::int64_t misoriented_edges = 0;  // interior edges traversed the same way by both triangles
    std::int64_t boundary_mismatch = 0;  // boundary list differs from the edges in exactly one triangle
    std::int64_t open_loop_vertices = 0; // vertices where boundary in-degree != out-degree
    std::int64_t boundary_edges = 0;
    std::int64_t interior_edges = 0;
    // Checked when the mesh lists interfaces (multi-material meshes): the list
    // must be exactly the interior edges whose two triangles' regions differ,
    // each once, oriented with interface_regions[k][0] on its left.
    std::int64_t interface_mismatch = 0;
    std::int64_t interface_edges = 0;
    // The embedding, checked when everything above holds (the mesh covers each
    // point at most once): boundary edges that meet other than at a shared
    // endpoint, and folds (a vertex's angles not summing to 360° — at most
    // 360° on the boundary — or a boundary vertex inside a triangle that does
    // not have it).
    std::int64_t crossing_boundary_edges = 0;
    std::int64_t overlaps = 0;
    std::vector<std::string> messages;   // the first few problems, for humans

    bool ok() const {
        return non_ccw == 0 && bad_indices == 0 && unused_vertices == 0 && overfull_edges == 0 &&
               misoriented_edges == 0 && boundary_mismatch == 0 && open_loop_vertices == 0 &&
               interface_mismatch == 0 && crossing_boundary_edges == 0 && overlaps == 0;
    }
};

MeshCheck check_mesh(const Mesh& mesh);

// Twice the signed area of triangle t.
double cross2(const Mesh& mesh, std::size_t t);

}  // namespace warpmesh
