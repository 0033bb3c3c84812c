// report3d.hpp — the 3D mesher's typed report: what the pipeline
// (pipeline/mesh3d.hpp) measured and certified, filled from the stages'
// results (mesh3d/mesh3d.hpp: BccMesh; post/tet_checks.hpp: TetQuality,
// nonmanifold_boundary; post/resolution.hpp: check_resolution3;
// certify/bcc_certified.hpp: bcc_certification), and its text and JSON
// (report3d.cpp; report.hpp's conventions).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "warpmesh/mesh3d/generic_bcc.hpp"  // FaceRule
#include "warpmesh/post/tet_checks.hpp"     // TetQuality

namespace warpmesh {

// One material of a multi-material mesh (mesh3d.hpp: mesh_bcc_materials):
// its output tetrahedra and their volume, and, for a label volume, its
// voxels and their volume (MaterialField3::reference_volume).
struct Material3Figures {
    std::int32_t tag = 0;  // its region tag (a label volume: the label; the background 0)
    std::string name;      // "label_41", "material_2", "background"
    std::int64_t tets = 0;
    double volume = 0;
    std::optional<std::int64_t> voxels;      // label volumes
    std::optional<double> reference_volume;  // voxels x a voxel's volume
};

// The multi-material part of the report: every material that is output
// (the background only when kept), the faces between two materials
// (TetMesh::interfaces), the junctions: background tetrahedra where three
// or four materials meet and the tetrahedra they output (the cone stencil,
// generic_bcc_materials.hpp), certified when proofs/bcc_junctions.cert
// applies (Mesh3dReport's counts and bounds include them), and the all-zero
// background tetrahedra output because they meet the certificate's claim
// (filled) or left out inside an output material (voids; mesh3d.hpp:
// BccMesh).
struct Materials3Figures {
    std::vector<Material3Figures> materials;
    std::int64_t interface_faces = 0;
    std::int64_t junction_background_tets = 0, junction_tets = 0;
    bool junctions_certified = false;
    std::int64_t all_zero_filled = 0, all_zero_voids = 0;
};

// A graded mesh's figures (Mesh3dOptions::graded; mesh3d/graded.hpp).
struct Graded3Figures {
    std::vector<std::int64_t> leaves_per_level;  // leaves 2^l cubes wide, l = 0, 1, …
    std::int64_t template_tets = 0;              // tetrahedra from the templates (the rest from the stencils)
    double max_size = 0;                         // the bound asked for (0: none)
    int max_level = 0;                           // the largest level allowed
    double grading = 2;
    int grading_buffer = 0;
    double longest_edge = 0;                     // measured over every tetrahedron
    // The templates' certification (proofs/bcc_graded.cert): their bounds;
    // the mesh's certified bounds are these and the stencils' together.
    bool templates_certified = false;
    double template_min_deg = 0, template_max_deg = 0;
};

struct Mesh3dReport {
    // Counts.
    std::int64_t lattice_points = 0, background_tets = 0;  // in the lattice
    std::int64_t cut_points = 0;    // cut points kept (vertices)
    std::int64_t warped = 0;        // lattice points warped onto the level set
    std::int64_t vertices = 0, tets = 0, boundary_faces = 0;
    // All-zero background tetrahedra (four vertices on the level set): never
    // output (proofs/README.md, step 6), counted here; their volume, within
    // the α-band of the surface, is not in the mesh.
    std::int64_t all_zero_left_out = 0;
    // Measured quality (Mesh3dOptions::quality): the volume, dihedral
    // extremes, radius ratios, the boundary's fidelity to the level set
    // (not finite for several materials: no level set).
    TetQuality quality;
    std::optional<Materials3Figures> materials;  // several materials
    std::optional<Graded3Figures> graded;        // graded meshes
    // The boundary's non-manifold edges and vertices (nonmanifold_boundary).
    std::int64_t nonmanifold_boundary_edges = 0, nonmanifold_boundary_vertices = 0;
    // Mesh3dOptions::manifold: the vertices split_nonmanifold_vertices added
    // (the counts above are after it).
    std::optional<std::int64_t> manifold_added_vertices;
    // Certification by the face rule's certificate (bcc_certificate_path):
    // certified: it is compiled in and its alphas are the options'; the
    // bounds then hold for every certified tetrahedron (each comes from a
    // certified key), else every tetrahedron is uncertified and a warning
    // says why.  With several materials the junction tetrahedra are
    // certified by the junction certificate where it applies, else
    // uncertified, the reason saying so.  verified: every tetrahedron was checked against its own
    // key's claim (Mesh3dOptions::verify).
    FaceRule face_rule = FaceRule::parity;  // the rule the mesh was split by
    bool certified = false;
    double certified_min_deg = 0, certified_max_deg = 0;
    std::int64_t certified_tets = 0, uncertified_tets = 0;
    std::string uncertified_reason;  // why some are uncertified; empty when none is
    bool verified = false;
    // The resolution check: the narrowest closed boundary component's width
    // 6V/A (a sphere's diameter), and a spacing resolving it (0: resolved).
    double narrowest_width = 0, suggested_spacing = 0;
    std::vector<std::string> warnings;  // e.g. the spacing is too coarse
    double seconds = 0;                 // meshing time (without the quality pass)
};

// The report as one JSON object ("dimension": 3, counts (with
// "all_zero_left_out", the all-zero background tetrahedra), measured
// dihedral extremes and radius ratios, boundary fidelity, the boundary's
// non-manifold edges and vertices; several materials: "materials" (per
// material tag, name, tetrahedra, volume, voxels, reference_volume,
// relative_error), "materials_without_tetrahedra", "interface_faces",
// "junctions" {background_tetrahedra, tetrahedra, certified, certificate},
// "all_zero_filled", "all_zero_voids"; "certified":
// {min/max_dihedral_deg, certified/uncertified tetrahedra, verified} or null,
// "uncertified_reason", warnings, seconds) and as text.
std::string to_json(const Mesh3dReport& report);
std::string to_text(const Mesh3dReport& report);

// The warnings of several materials, each naming its material: one per
// material that got no tetrahedron (lost at this spacing; a label with no
// voxel is not a loss), and one per label (not the background) of at least 1000 voxels whose
// volume is more than 5 % off its voxels' (thin parts lost or thickened).
std::vector<std::string> material_warnings(const Materials3Figures& materials);

}  // namespace warpmesh
