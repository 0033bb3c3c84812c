// graded.hpp — graded tetrahedral meshes: fine along the surface, coarse
// inside, on a balanced octree over the BCC lattice (docs/3d.md, "Graded
// meshes").  The pipeline (pipeline/mesh3d.hpp, Mesh3dOptions::graded)
// calls it; the rule of its tetrahedra is mesh3d/generic_octree.hpp.
//
// The lattice's signs, cut points and warps are the uniform mesher's, on
// the whole lattice at the finest spacing.  The octree's leaves are the
// finest cubes wherever the stencils act (every cube one of whose
// background tetrahedra has a vertex on the level set or is cut, and the
// cubes near the lattice's border), coarser inside and outside, at most
// 2^max_level cubes wide, 2:1 balanced across faces and edges.  Between two
// finest leaves the uniform lattice's background tetrahedra are split by
// the uniform stencils, exactly as mesh_bcc splits them, so the uniform
// certificate applies to them unchanged; everything else is a *template*
// (generic_octree.hpp: the BCC tetrahedron scaled, bisected, or between
// leaves of two sizes) with four unwarped vertices inside, output whole
// (proofs/bcc_graded.cert certifies the templates' angles).
//
// SIZE.  Every tetrahedron's longest edge is at most 2 · spacing in the
// finest band (the background tetrahedron's diameter, the spacing, plus two
// warps of less than half a lattice edge each) and at most the leaf's side,
// 2^l · spacing, in a leaf of level l (the fans' longest edges: the BCC
// tetrahedron's long edges, √3/2 of the bigger leaf's side between sizes).
// max_level_for_size(H, s) is the largest l with 2^l s <= H (H >= 2 s).
#pragma once

#include <cstdint>
#include <vector>

#include "warpmesh/mesh3d/mesh3d.hpp"

namespace warpmesh {

struct GradedOptions3 {
    int max_level = 30;   // leaves at most 2^max_level cubes wide (30: as coarse as the lattice allows)
    int buffer = 0;       // grading_buffer(G) (core/grading.hpp); 0: plain 2:1 balance
};

struct GradedBccMesh {
    BccMesh bcc;                                  // the mesh and the uniform counts (background_tets: the lattice's)
    std::vector<std::int64_t> leaves_per_level;   // leaves of level 0, 1, … (2^l cubes wide)
    std::int64_t template_tets = 0;               // tetrahedra output from templates (the rest from the stencils)
};

// The graded mesh of {f <= 0} on `lattice` (its spacing the finest).
// Throws as mesh_bcc does, and std::invalid_argument for a negative
// max_level or a buffer outside 0 .. max_grading_buffer.
GradedBccMesh mesh_bcc_graded(const LevelSet3& f, const Lattice3& lattice, const BccOptions& options, const GradedOptions3& graded);

// The graded mesh of several materials: mesh_bcc_materials (mesh3d.hpp)
// on a balanced octree whose finest leaves are every cube whose 15 points
// are not all unwarped and of one and the same material (the outside
// counted as the background when it is dropped), so every interface and the
// outer boundary lie in the finest band, split by the uniform
// multi-material rule (proofs/bcc_junctions.cert and the parity
// certificate apply unchanged); coarser leaves lie in one material and
// their templates carry its tag.  Throws as mesh_bcc_materials and
// mesh_bcc_graded do.
GradedBccMesh mesh_bcc_materials_graded(const MaterialField3& field, const Lattice3& lattice, const BccOptions& options,
                                        bool keep_background, const GradedOptions3& graded);

// The largest level l with 2^l · spacing <= max_size; std::invalid_argument
// unless max_size >= 2 · spacing (finite).
int max_level_for_size(double max_size, double spacing);

}  // namespace warpmesh
