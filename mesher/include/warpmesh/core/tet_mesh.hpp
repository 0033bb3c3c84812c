// tet_mesh.hpp — the output of the 3D mesher: a conforming tetrahedral mesh.
//
// The 3D sibling of mesh.hpp (same field names, same meaning of tags), so
// the writers, the report and the Python wrapper treat both alike.
//
// Invariants (checked for any tetrahedral mesh by the 3D mesh checks, which
// the tests run on every 3D mesher's output):
//  * vertices are compacted: every vertex is used by at least one tetrahedron;
//  * every tetrahedron (v0, v1, v2, v3) is positively oriented:
//    det(v1 − v0, v2 − v0, v3 − v0) > 0;
//  * `boundary` lists each triangular face that belongs to exactly one
//    tetrahedron, ordered so that its normal (v1 − v0) × (v2 − v0) points out
//    of the meshed region; every other face is shared by exactly two
//    tetrahedra (conformity);
//  * `interfaces` lists each face shared by two tetrahedra of different
//    regions, its normal pointing from interface_regions[k][0] into
//    interface_regions[k][1].
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "warpmesh/core/buffer.hpp"
#include "warpmesh/core/mesh.hpp"  // BoundaryTag: the same tags in 2D and 3D

namespace warpmesh {

// A point of a tetrahedral mesh.  (Not `Vec3`: volume.hpp's Vec3 is the
// std::array of the readers' geometry, and both headers are public.)
struct Point3 {
    double x, y, z;
};

struct TetMesh {
    // The large arrays are Buffers (buffer.hpp): filled in parallel, not zeroed.
    Buffer<Point3> vertices;
    Buffer<std::array<std::int32_t, 4>> tets;
    Buffer<std::int32_t> region;  // one tag per tetrahedron
    std::vector<std::array<std::int32_t, 3>> boundary;
    std::vector<std::int32_t> boundary_tag;  // one BoundaryTag per boundary face

    // Multi-material meshes (empty for one region), as in Mesh.
    std::vector<std::array<std::int32_t, 3>> interfaces;
    std::vector<std::array<std::int32_t, 2>> interface_regions;
    std::vector<std::pair<std::int32_t, std::string>> region_names;

    // Per-tetrahedron cell data that writers export when present (same
    // length as `tets`), e.g. the tetrahedron's minimum dihedral angle.
    std::vector<std::pair<std::string, Buffer<double>>> cell_data;
};

}  // namespace warpmesh
