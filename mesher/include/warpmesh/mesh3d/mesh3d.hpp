// mesh3d.hpp — the 3D meshing stage: a level set f(x, y, z) (levelset3.hpp)
// and a BCC lattice in, a conforming tetrahedral mesh of {f <= 0} out, by
// lattice warping (isosurface stuffing), every stage from the one definition
// the 3D proof is about (generic_bcc.hpp).  The pipeline (pipeline/mesh3d.hpp:
// mesh3d) builds the level set from its input, checks the options, runs this
// stage and measures and certifies its output; call it unless you drive the
// stages yourself:
//
//   const auto f = warpmesh::parse_shape3("sphere:0,0,0,1");
//   const warpmesh::Lattice3 lattice = warpmesh::lattice3_for(*f, 0.1);
//   warpmesh::BccMesh m = warpmesh::mesh_bcc(*f, lattice, {});
//
// THE OUTPUT (tet_mesh.hpp's invariants, checked by check_tet_mesh):
// positively oriented tetrahedra, each interior face shared by exactly two,
// the boundary faces oriented outward and tagged boundary_level_set (all
// three vertices on the level set) or boundary_domain (the region is cut off
// by the lattice: only for level sets whose bounds() do not enclose the
// region, or volumes whose region reaches the lattice's edge).  One region,
// tag 1.
//
// VERTEX NUMBERING (what makes blocks mergeable and the output independent
// of the thread count).  Lattice points come first, in lexicographic order of
// their doubled coordinates read (z, y, x) — z slowest; then the cut points,
// ordered by their edge's lower endpoint (the endpoint that comes first in
// that order) and then by the edge's direction index (neighbour_offsets).
// Only used vertices are kept, in that order.  Tetrahedra come in the order
// of their background tetrahedron's owning cube (z, y, x), its index 0..11
// (background_tet), then the stencil's order.  The boundary faces are sorted
// by their vertex triples.  `vertex_key` (below) is the global name of a
// vertex in this order.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "warpmesh/core/memory.hpp"
#include "warpmesh/core/tet_mesh.hpp"
#include "warpmesh/levelset/levelset3.hpp"
#include "warpmesh/mesh3d/generic_bcc.hpp"  // FaceRule, Alphas

namespace warpmesh {

namespace bcc {
struct JunctionKey;  // generic_bcc_materials.hpp
}

// ---------------------------------------------------------------------------
// The lattice.  Cubes [0, cubes[a]) along each axis of side `spacing`; the
// point with doubled coordinates q is at origin + q · spacing / 2; corners
// have 0 <= q <= 2 cubes, centres 1 <= q <= 2 cubes − 1.  A background
// tetrahedron exists iff both cubes of its face exist, so the covered region
// is the box less a layer of up to one cube at its faces; lattice3_for puts
// two cubes of margin around bounds().
struct Lattice3 {
    double spacing = 1;
    Point3 origin{0, 0, 0};
    std::array<std::int64_t, 3> cubes{0, 0, 0};
    Point3 position(const bcc::Ivec& q) const {
        const double h = 0.5 * spacing;
        return {origin.x + q[0] * h, origin.y + q[1] * h, origin.z + q[2] * h};
    }
    // Lattice points (corners and centres).
    std::int64_t point_count() const;
    // The global index of lattice point q in the (z, y, x) order.
    std::int64_t point_index(const bcc::Ivec& q) const;
};
// The lattice of `spacing` over f.bounds() with two cubes of margin.  Throws
// InputError for a spacing that is not positive and finite, or a lattice of
// more than 2^31 points or cubes.
Lattice3 lattice3_for(const LevelSet3& f, double spacing);
// The same over a box (`what` names its source in messages); with at_min,
// a lattice corner lies at the box's minimum (two cubes in from the
// lattice's own corner) instead of the box being centred.  The
// multi-material mesher uses at_min for volumes: the box's minimum is the
// first voxel centre, so lattice planes pass through voxel centres and, at a
// spacing equal to the voxel size, the voxel interfaces (midway between
// centres) lie on lattice planes instead of a quarter spacing off them, where
// planar interfaces warp all four vertices of background tetrahedra onto
// themselves (flat all-zero tetrahedra, left out as voids).
Lattice3 lattice3_for(const Box3& box, double spacing, const std::string& what, bool at_min = false);

// ---------------------------------------------------------------------------
// The face rule (generic_bcc.hpp, "The diagonal choices") splits the quads of
// the stencils: `parity` (Labelle–Shewchuk's parity rule, proofs/bcc.cert) or
// `delaunay` (each face quad by the empty-circle test, the prism's inside
// quad by the shorter diagonal; proofs/README.md, "The Delaunay face rule"),
// decided by exact signs of the rule's forms so that the two tetrahedra
// sharing a face agree.  Each rule has its own alphas, those its certificate
// is proved at (face_rule_alphas).  The default is the Delaunay face rule:
// its certificate's bounds, [11.78°, 161.25°], are tighter at both ends than
// the parity rule's [10.76°, 164.75°]; the default alphas follow the rule.
inline constexpr FaceRule default_face_rule = FaceRule::delaunay;
constexpr bcc::Alphas face_rule_alphas(FaceRule rule) {
    return rule == FaceRule::delaunay ? bcc::delaunay_alphas : bcc::parity_alphas;
}

// The claim of a key a mesh is verified against: every output tetrahedron
// of the key is positively oriented and, per edge with d = n_c·n_d and N =
// |n_c|²|n_d|² (generic_bcc.hpp, "Angle forms"), d <= 0 or d² <= cos2_min N,
// and d >= 0 or d² <= cos2_max N.
struct BccKeyClaim {
    double cos2_min = 0, cos2_max = 0;
};
// The claims of canonical keys (bcc::key_of), nothing for a key without one
// (the pipeline gives the certificate's: certify/bcc_certified.hpp,
// bcc_key_claims), and a name for messages.
struct BccKeyClaims {
    std::function<std::optional<BccKeyClaim>(const bcc::Config& canonical_key)> claim;
    std::string source;
    // Multi-material meshes: the claims of canonical junction keys
    // (bcc::junction_key_of; proofs/bcc_junctions.cert), checked against
    // every tetrahedron of a junction background tetrahedron; empty: those
    // are not checked.
    std::function<std::optional<BccKeyClaim>(const bcc::JunctionKey& canonical_key)> junction_claim;
    // Graded meshes (mesh3d/graded.hpp): the claim of the transition
    // templates (proofs/bcc_graded.cert), checked against every template
    // tetrahedron; none: those are not checked.
    std::optional<BccKeyClaim> template_claim;
};

// What the meshing stage is told.  Throws InputError for alphas not in
// (0, 1/2).
struct BccOptions {
    FaceRule face_rule = default_face_rule;           // how the stencils' quads are split (above)
    bcc::Alphas alphas = face_rule_alphas(default_face_rule);  // violation thresholds (α_long, α_short)
    int threads = 0;                                  // OpenMP threads; 0 = the OpenMP default
    std::uint64_t max_memory = default_max_memory;    // refuse (InputError) a lattice or mesh above it
    // With claims: check every tetrahedron, once, against its own background
    // tetrahedron's key claim; a key without a claim or a violation throws
    // std::logic_error (an internal failure, not bad input).
    const BccKeyClaims* verify = nullptr;
    // Multi-material meshes (mesh_bcc_materials): an all-zero background
    // tetrahedron is output iff, with its vertices where warping put them, it
    // meets this claim (the certificate's bounds, checked in double precision
    // with a relative margin of 1e-9 on cos²); none: every one is left out.
    std::optional<BccKeyClaim> fill_claim;
};

// The stage's mesh and its counts.
struct BccMesh {
    TetMesh mesh;
    std::int64_t lattice_points = 0, background_tets = 0;  // in the lattice
    std::int64_t cut_points = 0;    // cut points kept (vertices)
    std::int64_t warped = 0;        // lattice points warped onto the level set
    // All-zero background tetrahedra (four vertices on the level set): never
    // output (proofs/README.md, step 6), counted here; their volume, within
    // the α-band of the surface, is not in the mesh.
    std::int64_t all_zero_left_out = 0;
    bool verified = false;          // every tetrahedron was checked (BccOptions::verify)
    double seconds = 0;             // meshing time
    // Multi-material meshes (mesh_bcc_materials): the background tetrahedra
    // where three or four materials meet (junctions, split by the cone
    // stencil: generic_bcc_materials.hpp) and the tetrahedra they output.
    std::int64_t junction_background_tets = 0, junction_tets = 0;
    std::int64_t all_zero_filled = 0;  // all-zero background tetrahedra output (fill_claim)
    // Of all_zero_left_out, those whose centroid lies in an output material
    // (the claim failed): voids inside the mesh, their faces boundary faces.
    std::int64_t all_zero_voids = 0;
};

// Mesh {f <= 0} on `lattice`.  Throws InputError for bad options, a lattice or
// a mesh over max_memory (before allocating it), an empty region ("no
// tetrahedron inside at spacing s").
BccMesh mesh_bcc(const LevelSet3& f, const Lattice3& lattice, const BccOptions& options);

// ---------------------------------------------------------------------------
// Multi-material meshes: every material of a field (levelset/materials3.hpp)
// in one conforming mesh on `lattice`, split as generic_bcc_materials.hpp
// says (the parity face rule: options.face_rule must be parity).  Each
// tetrahedron's region is its material's tag; the background's tetrahedra
// are output only with keep_background; every face between two materials is
// listed in `interfaces` (oriented from interface_regions[k][0] into [1]);
// the faces against the background (dropped), outside the field's domain or
// on the lattice's cut-off are the boundary (boundary_level_set, or
// boundary_domain on the cut-off).  An all-zero background tetrahedron
// (four warped vertices, every one on an interface) has no key; it is
// output, with the material at its centroid, iff it meets
// options.fill_claim — so every output tetrahedron is within the claimed
// bounds — and is otherwise left out (counted in all_zero_left_out; its
// faces are then boundary faces: a void of the α-band's thickness or less).
// With options.verify, every tetrahedron of a two-material background
// tetrahedron is checked against its side's key claim (each side is a
// one-region key), every junction tetrahedron against its junction key's
// (BccKeyClaims::junction_claim).  Vertex order:
// lattice points, cut points (as mesh_bcc), then the face points of
// junction faces, by (the face's lowest lattice point's index, the forward
// slots s1 < s2 of its two edges from that point), then the junctions'
// centres, in the order of their background tetrahedra (cube, index);
// tetrahedra in the order of their background tetrahedron (cube, index),
// then the stencil's.  The interfaces, like the boundary, are sorted by their
// vertex triples.  `region_names` lists every output material.  Throws
// InputError as mesh_bcc does, and for a mesh with no tetrahedron.
class MaterialField3;
BccMesh mesh_bcc_materials(const MaterialField3& field, const Lattice3& lattice, const BccOptions& options, bool keep_background);

// ---------------------------------------------------------------------------
// Blocks (issue 30's "beyond one machine").  The cubes [lo, hi) of the
// lattice `lattice` are meshed on their own, looking at the level set on the
// block grown by a halo large enough for the closest-first warping order to
// be decided there exactly (the halo grows until no decision in the block
// depends on the halo's edge); vertices carry their global key (the order
// above: lattice point index, then point_count() + 7 × lower endpoint's
// index + the edge's slot among the 7 forward directions).  merge_tet_blocks
// of blocks that tile the lattice's cubes equals mesh_bcc(f, lattice,
// options) exactly: vertices, tetrahedra, boundary and tags.
//
// Multi-material blocks (mesh_bcc_materials_block) do the same for
// mesh_bcc_materials: the block's window is grown until no point of its
// background tetrahedra is decided differently from the whole lattice, and
// the keys, with P = point_count(), follow mesh_bcc_materials' order:
// lattice points and cut points as above; the face point of a junction face
// 8P + 49 × (its lowest point's index) + 7 s1 + s2 (the forward slots s1 <
// s2 of the face's two edges from that point); the centre of background
// tetrahedron i (background_tet's index) of cube c (its index in (z, y, x)
// order) 57P + 12c + i; tetrahedra 24 (12c + i) + k, k the stencil's order
// (one-region blocks' tetrahedra: 48c + 4i + k).  Their merge equals
// mesh_bcc_materials(field, lattice, options, keep_background) exactly:
// vertices, tetrahedra, regions, boundary and tags, interfaces and their
// regions, region_names.
struct CubeRange {
    std::array<std::int64_t, 3> lo{0, 0, 0}, hi{0, 0, 0};
};
// What the merged mesh's report needs of the input a block was made from
// (the pipeline's mesh3d_block fills it, merge_mesh3d_blocks reads it; the
// stage leaves it empty): blocks of one mesh carry the same facts, and
// open_face_f holds the block's own measurements.
struct BlockFacts {
    std::string source;  // the input and the options that shape the mesh (blocks of different ones are refused)
    bool quality = false;  // measure the merged mesh's quality (Mesh3dOptions::quality)
    // One region: the level set's reference volume, feature size and
    // resolution (levelset3.hpp), and per TetBlock::open_faces its max |f| at
    // the three vertices and |f| at the centroid (tet_checks.hpp: face_fidelity).
    std::optional<double> reference_volume;
    double feature_size = 0, resolution = 0;
    std::vector<std::array<double, 2>> open_face_f;
    // Several materials: every output material's tag, name and, for a
    // label volume, its voxels' count and volume.
    struct Material {
        std::int32_t tag = 0;
        std::string name;
        std::optional<std::int64_t> voxels;
        std::optional<double> reference_volume;
        bool operator==(const Material&) const = default;
    };
    std::vector<Material> materials;
    std::vector<std::string> warnings;  // the input's (the volume reader's, threshold mode's guess)
    // A block of a part of a volume (Volume::is_part): its materials'
    // voxels are those of its own cubes (each voxel's centre lies in one
    // block's cubes), summed by the merge, times voxel_volume.
    bool part = false;
    double voxel_volume = 0;
};
struct TetBlock {
    std::vector<std::uint64_t> vertex_key;        // sorted, one per vertex
    std::vector<Point3> vertices;
    // Per vertex: one region, a zero lattice point or a cut point (on the
    // level set); several materials, a vertex on an interface (a warped
    // lattice point, a cut point, a junction's face point or centre).  The
    // merge's boundary and interface faces have three such vertices or lie
    // on the lattice's cut-off.
    std::vector<std::uint8_t> on_level_set;
    std::vector<std::array<std::int32_t, 4>> tets;  // indices into vertices
    std::vector<std::uint64_t> tet_key;           // sorted: the tetrahedra's global order
    std::vector<std::uint8_t> lattice_edge;       // per tet: bit f set if its face without vertex f is on the lattice's cut-off
    // Several materials: per tet its region tag, and the mesh's region_names
    // (the same in every block).  Both empty for one region (tag 1).
    std::vector<std::int32_t> region;
    std::vector<std::pair<std::int32_t, std::string>> region_names;
    // What the block is a part of: the lattice, its cubes [lo, hi) of it,
    // the face rule and alphas it was split by.  The merge refuses blocks
    // that do not tile one lattice exactly once under one rule.
    Lattice3 lattice;
    CubeRange range;
    FaceRule face_rule = default_face_rule;
    bcc::Alphas alphas = face_rule_alphas(default_face_rule);
    // The stage's counts of the block's own cubes and lattice points (each
    // lattice point is the block's whose cube min(⌊q/2⌋, cubes − 1) along
    // every axis is), summed by the merge into BccMesh's.
    std::int64_t warped = 0, all_zero_left_out = 0, all_zero_filled = 0, all_zero_voids = 0;
    std::int64_t junction_background_tets = 0, junction_tets = 0;
    // One region: the faces of the block's tetrahedra that no other of its
    // tetrahedra shares and whose three vertices are on the level set,
    // outward (as find_boundary orients them), in block vertex indices —
    // every level-set boundary face of the merged mesh is one of them, in
    // exactly one block.  Empty for several materials.
    std::vector<std::array<std::int32_t, 3>> open_faces;
    BlockFacts facts;
};
// Throws InputError unless 0 <= lo <= hi <= lattice.cubes (options.verify is
// not used: blocks are not verified).
TetBlock mesh_bcc_block(const LevelSet3& f, const Lattice3& lattice, const BccOptions& options, const CubeRange& block);
// The cubes [lo, hi) of mesh_bcc_materials(field, lattice, options,
// keep_background).  Throws InputError as mesh_bcc_materials does for bad
// options and unless 0 <= lo <= hi <= lattice.cubes; a block with no
// tetrahedron is not an error (options.verify is not used).
TetBlock mesh_bcc_materials_block(const MaterialField3& field, const Lattice3& lattice, const BccOptions& options, bool keep_background,
                                  const CubeRange& block);
// Merge blocks tiling the lattice (any order): vertices by key, tetrahedra by
// key with their regions, boundary faces and interfaces found as in mesh_bcc
// and mesh_bcc_materials; the counts of BccMesh summed over the blocks
// (cut_points: the merged mesh's cut-point vertices; seconds 0, verified
// false).  Throws std::invalid_argument, naming what is wrong, for no block,
// blocks of different lattices, face rules or alphas, blocks whose cube
// ranges do not cover the lattice's cubes exactly once (a gap: the first
// cubes no block covers; an overlap or a block given twice: the two
// blocks), a tetrahedron outside its block's range, two blocks giving a key
// different positions or a tetrahedron twice, or naming their regions
// differently.  merge_tet_blocks: its mesh only.
BccMesh merge_bcc_blocks(std::span<const TetBlock> blocks);
TetMesh merge_tet_blocks(std::span<const TetBlock> blocks);
// The first of the problems above with the blocks' lattices, rules and
// ranges (not their contents), or nothing; the merge throws it.
std::optional<std::string> tiling_problem(std::span<const TetBlock> blocks);

}  // namespace warpmesh
