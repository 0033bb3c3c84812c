// pipeline/mesh3d.hpp — the 3D pipeline: an input (a volume file, a volume,
// an analytic shape or a level set) and options in, a tetrahedral mesh of
// its region, the typed report and the warnings out.  The command line's
// `warpmesh mesh3d` and Python's warpmesh.mesh3d, lattice3d and mesh3d_block
// call these and nothing else.
//
//   warpmesh::Mesh3dOptions o;
//   o.spacing = 0.1;
//   warpmesh::Mesh3dResult r = warpmesh::mesh3d(warpmesh::Shape3{"sphere:0,0,0,1"}, o);
//   // r.mesh (tet_mesh.hpp), r.report (report3d.hpp: to_text, to_json), r.warnings
//
// The stages, in order: the input's level set (levelset3.hpp: a volume read
// and its geometry overridden, then make_volume_levelset3 in label or
// threshold mode; parse_shape3), the lattice (lattice3_for), the mesher
// (mesh3d.hpp: mesh_bcc, verified against the certificate's per-key claims
// with `verify`), the certification (bcc_certified.hpp: bcc_certification),
// the measurements (tet_checks.hpp: measure_quality3, nonmanifold_boundary;
// resolution.hpp: check_resolution3).
//
// Several materials (a label volume with `materials`, or MaterialShapes3):
// the input's material field (levelset/materials3.hpp:
// make_volume_materials3, parse_material_shapes3), the lattice over its
// bounds, mesh_bcc_materials under the parity face rule (every tetrahedron
// tagged by its material, every face between two materials in
// TetMesh::interfaces; all-zero background tetrahedra output iff they meet
// the certificate's claim), then the report with per-material figures: the
// parity certificate covers every tetrahedron but the junctions' (three or
// four materials meet), which the junction certificate covers
// (proofs/bcc_junctions.cert; without it they are counted uncertified);
// `verify` checks every tetrahedron against its key's claim.  Options are checked once, here
// (validate), with messages naming the options by their field names.
// Defined in warpmesh::io (it reads volumes).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "warpmesh/core/memory.hpp"
#include "warpmesh/core/tet_mesh.hpp"
#include "warpmesh/io/volume.hpp"  // Volume, Units
#include "warpmesh/io/writers.hpp"  // VtuOptions
#include "warpmesh/levelset/levelset3.hpp"
#include "warpmesh/mesh3d/mesh3d.hpp"
#include "warpmesh/report/report3d.hpp"

namespace warpmesh {

// Every option of the 3D pipeline, one field each (the command line's and
// Python's option tables set them by name).
struct Mesh3dOptions {
    // The lattice's cube side, in the input's units (> 0, finite).  None: a
    // volume's default, its smallest voxel size (1 in voxel units); shapes
    // and level sets need one.
    std::optional<double> spacing;
    // How the stencils' quads are split (mesh3d.hpp).  None: the input's
    // default (face_rule_in_use): the parity rule for several materials,
    // whose two sides of an interface must agree (generic_bcc_materials.hpp),
    // default_face_rule for one region.  Delaunay with several materials is
    // refused (validate).
    std::optional<FaceRule> face_rule;
    // Violation thresholds (α_long, α_short) in (0, 1/2); none: face_rule_alphas(face_rule_in_use()).
    std::optional<bcc::Alphas> alphas;
    // Check every tetrahedron, once, against its own background
    // tetrahedron's key claim in the face rule's certificate (only when the
    // certificate applies); a violation is a std::logic_error (a bug).
    bool verify = false;
    // Measure dihedral angles, radius ratios and the boundary's distance to
    // the level set for the report (a second pass over the mesh).
    bool quality = true;
    // Split the boundary's non-manifold vertices (split_nonmanifold_vertices,
    // post/tet_checks.hpp) after meshing; mesh3d only (blocks: refused).
    bool manifold = false;
    int threads = 0;                                // OpenMP threads (>= 0); 0 = the OpenMP default
    std::uint64_t max_memory = default_max_memory;  // refuse (InputError) inputs, lattices and meshes above it
    // ---- volumes only
    std::uint64_t max_voxels = std::uint64_t{1} << 28;  // refuse larger volume files (read_volume), >= 1
    // Label mode: the region is the voxels with these labels ("3", "51,52",
    // "1000-1035,2000", or "nonzero"; label_options).  Without: threshold mode.
    std::optional<std::string> labels;
    std::optional<double> iso;          // threshold mode: the iso value (default: the middle of the value range)
    std::optional<bool> inside_above;   // threshold mode: inside above iso (default) or below it
    int band = 4;                       // label mode: voxels of exact distance around the boundary, >= 2
    // Units of a volume file: physical (mm; refused for a file without a
    // physical voxel size, unless voxel_size gives one) or pixels (voxel
    // indices).  None: mm when the volume has a physical size.
    std::optional<Units> units;
    // Voxel size override (x[, y[, z]], missing entries repeat the last), mm.
    std::vector<double> voxel_size;
    // Several materials of a label volume: "all" (every label but 0, which
    // is the background) or a label list ("3,41,42", "1000-1035"; every
    // other voxel joins the background); make_volume_materials3.  Excludes
    // labels, iso and inside.
    std::optional<std::string> materials;
    // ---- several materials (materials, or a MaterialShapes3 input)
    // Output the background's tetrahedra too (region 0); false: it only
    // bounds the materials.
    bool keep_background = false;
    // ---- graded meshes (mesh3d/graded.hpp; one region, not blocks)
    // A graded mesh on a balanced octree: the finest lattice (spacing) along
    // the surface, coarser cells inside and outside.
    bool graded = false;
    // Every tetrahedron's longest edge at most max_size (input units, >= 2 ·
    // spacing); graded: caps the octree's cells (max_level_for_size);
    // uniform: checked (a uniform mesh's edges are below 2 · spacing).
    std::optional<double> max_size;
    // Graded, 1.1 <= G <= 2: cell sizes grow away from the surface by at
    // most a factor G per cell on average (core/grading.hpp); 2: plain 2:1.
    double grading = 2.0;

    // The rule and alphas the mesh is split at: the options', else the
    // input's defaults.  `material_shapes`: the input is MaterialShapes3
    // (several materials without `materials`).
    FaceRule face_rule_in_use(bool material_shapes = false) const {
        return face_rule ? *face_rule : (materials || material_shapes) ? FaceRule::parity : default_face_rule;
    }
    bcc::Alphas alphas_in_use(bool material_shapes = false) const {
        return alphas ? *alphas : face_rule_alphas(face_rule_in_use(material_shapes));
    }
};

// The input: a volume file (read_volume), a volume already read, an analytic
// shape (parse_shape3's syntax), a level set of the caller's, or analytic
// materials ("1=sphere:0,0,0,1;2=sphere:0,0,0,0.5": parse_material_shapes3's
// syntax, tag=shape, a later shape winning where they overlap).
struct VolumeFile {
    std::string path;
};
struct Shape3 {
    std::string spec;
};
struct MaterialShapes3 {
    std::string spec;
};
using Mesh3dInput = std::variant<VolumeFile, std::reference_wrapper<const Volume>, Shape3, std::reference_wrapper<const LevelSet3>,
                                 MaterialShapes3>;

// Whether the input is meshed as several materials (options.materials, or
// MaterialShapes3).
bool several_materials(const Mesh3dInput& input, const Mesh3dOptions& options);

// Throws InputError naming the option if an option is out of range, two
// options exclude each other, or an option does not apply to the input
// (volume options on a shape or a level set; no spacing for one; materials
// on anything but a volume, or with labels, iso or inside; keep_background
// with one region; the Delaunay face rule with several materials).  The
// pipeline calls it; clients may call it early (before reading anything).
void validate(const Mesh3dInput& input, const Mesh3dOptions& options);

struct Mesh3dResult {
    TetMesh mesh;
    Mesh3dReport report;
    Lattice3 lattice;                   // the lattice the mesh was made on
    std::vector<std::string> warnings;  // the input's (the volume reader's), then report.warnings
};

// Stage lines for long runs ("meshing a BCC lattice of N points at spacing
// s"): called only for large inputs (2^22 voxels or 2^24 lattice points).
using Mesh3dProgress = std::function<void(const std::string& stage)>;

// Mesh the input's region.  Throws InputError for bad options (validate),
// an unreadable volume, an empty region, a lattice or mesh over max_memory;
// a spacing too coarse for the input gives a warning naming one that
// resolves it.
Mesh3dResult mesh3d(const Mesh3dInput& input, const Mesh3dOptions& options, const Mesh3dProgress& progress = {});

// Blocks (mesh3d.hpp, "Blocks"): the lattice mesh3d uses for this input
// (its cubes, to split into blocks), the mesh of the cubes [lo, hi) of it
// (0 <= lo < hi <= cubes along every axis; InputError otherwise), and the
// merge of blocks that tile it — equal to mesh3d's mesh and report (but its
// seconds and verified: blocks are not verified).  A worker needs only the
// input and the options.  Each block carries its lattice, cube range, face
// rule and alphas, and the facts of its input the report needs
// (BlockFacts: the input's description, the level set's reference volume,
// feature size and resolution, its own open faces' fidelity to the level
// set; several materials: the materials' voxels); the merge refuses
// (InputError naming what is wrong) an empty list and blocks that do not
// tile one lattice exactly once or come from different inputs or options
// (mesh3d.hpp: merge_bcc_blocks).  Several materials too (mesh3d.hpp:
// mesh_bcc_materials_block): the merge carries their regions, interfaces
// and region names.
// `region`: the whole region's facts, for a part in label mode (below).
Lattice3 lattice3d(const Mesh3dInput& input, const Mesh3dOptions& options, const LabelRegionFacts* region = nullptr);
TetBlock mesh3d_block(const Mesh3dInput& input, const Mesh3dOptions& options, const CubeRange& block,
                      const LabelRegionFacts* region = nullptr);
Mesh3dResult merge_mesh3d_blocks(std::span<const TetBlock> blocks);

// Blocks that read only their part of a volume: several materials (listed:
// "all" depends on the whole volume), or one region in label mode.  The
// input is a Volume that is a part of the whole (Volume::is_part: its offset
// and the whole's dimensions; the whole's origin); the lattice is the
// whole's, and a block of a part that holds the voxels block_voxels names
// merges with the others into exactly mesh3d's mesh of the whole volume,
// report included.  Several materials: the field's bounds are the whole
// volume's hull, and each block counts the materials' voxels of its own
// cubes.  One region (levelset3.hpp, "One region of a label volume in
// parts"): the lattice lies on the whole region's voxel box, so a reduction
// runs first — each part of a tiling of the volume, read as
// region_part_voxels names (its own voxels and label_reach around them),
// gives region_part_facts; merge_region_facts combines them (InputError
// unless they tile the volume exactly once with one labels, band and voxel
// size; for an empty region or an absent label, as mesh3d) — and every
// lattice3d, block_voxels and mesh3d_block of a part takes the result as
// `region` (required there; refused elsewhere, and when it is of other
// labels, band, voxel size or volume, or of some parts only).
// block_voxels: the whole volume's voxels [lo, hi) (index order i, j, k) a
// block reads when its window is its cubes grown by `halo` cubes: the
// window's box, its voxel cells' corners and what their values depend on
// (several materials: their 3 x 3 x 3 neighbourhoods, phi in
// levelset/materials3.hpp; one region: label_reach), one voxel more for
// rounding.  The window is grown from 2 cubes, doubling while a warping
// decision in the block depends on its edge (mesh3d.hpp, "Blocks"), so halo
// 2 covers most blocks; mesh3d_block refuses (InputError) a part that lacks
// a voxel the block read, and a part in threshold mode (its iso and bounds
// are the whole volume's).
// Partitioned output, for meshes never merged in one process: a block as a
// .vtu piece (its tetrahedra with their regions and its vertices; the
// GlobalIds point and cell arrays hold their keys, equal in every piece that
// shares a vertex — the merged mesh numbers its vertices in the keys' order),
// and the blocks as pieces STEM_NNNN.vtu beside a .pvtu that lists them
// (write_pvtu), written only if they tile one lattice exactly once
// (InputError as merge_mesh3d_blocks; OutputError when a file cannot be
// written).  write_blocks_pvtu returns the pieces' file names.
// check_blocks: InputError unless blocks tile one lattice exactly once and
// come from one input and options (merge_mesh3d_blocks' checks), from their
// lattices, ranges, rules and facts only: blocks whose arrays were dropped
// (the pieces a driver lists) will do.
void check_blocks(std::span<const TetBlock> blocks);
void write_block_vtu(const TetBlock& block, const std::string& path, const VtuOptions& options = {});
std::vector<std::string> write_blocks_pvtu(const std::string& path, std::span<const TetBlock> blocks, const VtuOptions& options = {});

std::array<std::array<std::int64_t, 3>, 2> block_voxels(const Mesh3dInput& input, const Mesh3dOptions& options, const CubeRange& block,
                                                        std::int64_t halo = 2, const LabelRegionFacts* region = nullptr);
// The reduction before one region's blocks (above): the voxels [lo, hi) a
// part owning the voxels `owned` [lo, hi) reads (the input: any part of the
// volume, for its geometry), that part's facts, and the whole region's.
std::array<std::array<std::int64_t, 3>, 2> region_part_voxels(const Mesh3dInput& input, const Mesh3dOptions& options,
                                                              const std::array<std::array<std::int64_t, 3>, 2>& owned);
LabelRegionFacts region_part_facts(const Mesh3dInput& part, const Mesh3dOptions& options,
                                   const std::array<std::array<std::int64_t, 3>, 2>& owned);
LabelRegionFacts merge_region_facts(std::span<const LabelRegionFacts> parts);

}  // namespace warpmesh
