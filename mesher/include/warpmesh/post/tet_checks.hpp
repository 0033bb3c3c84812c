// tet_checks.hpp — checks and quality of any tetrahedral mesh (tet_mesh.hpp):
// its invariants checked from scratch, the boundary's non-manifold places,
// dihedral angles and radius ratios, and the quality figures of a mesh of a
// level set (the 3D report's: pipeline/mesh3d.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "warpmesh/core/tet_mesh.hpp"
#include "warpmesh/levelset/levelset3.hpp"

namespace warpmesh {

struct TetMeshCheck {
    bool ok = true;
    std::vector<std::string> problems;  // the first few, each naming the element
    std::int64_t inverted = 0;          // tetrahedra with det <= 0
    std::int64_t nonmanifold_faces = 0; // faces in more than two tetrahedra
    std::int64_t boundary_mismatch = 0; // boundary faces missing, extra or not outward
    std::int64_t unused_vertices = 0;
    std::int64_t interface_mismatch = 0; // interfaces missing, extra, or with the wrong regions or orientation
    // Not problems (ok stays true): the boundary's non-manifold places
    // (nonmanifold_boundary below), counted.
    std::int64_t nonmanifold_boundary_edges = 0, nonmanifold_boundary_vertices = 0;
};
// From scratch: positive orientation, every face in one or two tetrahedra,
// the one-tetrahedron faces exactly the boundary list, each oriented as its
// tetrahedron sees it from outside, every vertex used, tags per face, the
// interfaces exactly the faces between two regions (tet_mesh.hpp); and the
// boundary's non-manifold edges and vertices, counted.
TetMeshCheck check_tet_mesh(const TetMesh& mesh);

// The boundary surface's non-manifold places.  A conforming mesh with a
// closed, outward boundary can still have boundary edges in more than two
// boundary triangles (four, six, ...: two parts of the region touch along
// the edge) and boundary vertices around which the boundary triangles are
// not one disc (their link, the edges opposite the vertex, is not one
// cycle: two parts touch at the vertex, or it ends a non-manifold edge).
// The 3D mesher's can, where all-zero background tetrahedra are left out
// (docs/3d.md, "Non-manifold boundary").
struct NonmanifoldBoundary {
    std::int64_t edges = 0, vertices = 0;
};
NonmanifoldBoundary nonmanifold_boundary(const TetMesh& mesh);

// Makes the boundary manifold where parts of the region touch only at a
// vertex or along edges: each boundary vertex whose tetrahedra fall into
// several classes (joined across faces through the vertex) gets one copy per
// class but the first, at the same position; the classes' tetrahedra, and
// the boundary faces and interfaces on them, take their copy.  No
// tetrahedron moves (its shape, hence any certified bound, is unchanged);
// the mesh stays conforming (no face is shared across classes), but the
// parts no longer share those vertices (a finite-element field is not
// continuous there).  Places where the parts also share faces around the
// vertex (a link that is not a disc although its tetrahedra are one class)
// stay non-manifold: nonmanifold_boundary counts them.  Returns the vertices
// added.
std::int64_t split_nonmanifold_vertices(TetMesh& mesh);

// The six dihedral angles (degrees) of a tetrahedron, at edges 01 02 03 12
// 13 23, and its radius ratio 3 r_in / R_circ (1 for the regular one, 0 flat).
std::array<double, 6> dihedral_angles_deg(const std::array<Point3, 4>& p);
double radius_ratio(const std::array<Point3, 4>& p);

// The quality of a mesh of {f <= 0}: dihedral extremes, the radius-ratio
// histogram, the volume, and the boundary's fidelity to f.
struct TetQuality {
    double volume = 0;  // sum of the tetrahedra's volumes
    double min_dihedral_deg = 0, max_dihedral_deg = 0;
    static constexpr int radius_ratio_bins = 10;  // bin i: [i/10, (i+1)/10), 1 in the last
    std::array<std::int64_t, radius_ratio_bins> radius_ratio_histogram{};
    double radius_ratio_min = 0, radius_ratio_mean = 0;  // 3 r_in / R_circ (1: regular)
    // Max |f| at the boundary vertices (0 up to the root finder's tolerance)
    // and at the boundary faces' centroids (the surface's deviation between
    // its vertices; a distance for signed-distance level sets), in f's units.
    double boundary_vertex_f_max = 0, boundary_centroid_f_max = 0;
};
TetQuality measure_quality3(const TetMesh& mesh, const LevelSet3& f);
// One boundary face's fidelity as measure_quality3 measures it: max |f| at
// its three vertices, and |f| at its centroid (the vertices in the order
// given: the boundary face's, outward).
std::array<double, 2> face_fidelity(const std::array<Point3, 3>& face, const LevelSet3& f);
// The same for a mesh of no one level set (several materials): the
// boundary's fidelity is not measured (NaN).
TetQuality measure_quality3(const TetMesh& mesh);

// The longest edge of any tetrahedron (0 for none): --max-size's measure.
double longest_tet_edge(const TetMesh& mesh);

// Per region tag, in increasing order: its tetrahedra and their volume.
struct RegionMeasure {
    std::int32_t tag = 0;
    std::int64_t tets = 0;
    double volume = 0;
};
std::vector<RegionMeasure> measure_regions3(const TetMesh& mesh);

}  // namespace warpmesh
