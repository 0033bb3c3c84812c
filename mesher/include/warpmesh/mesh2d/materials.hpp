// materials.hpp — multi-material meshes: every material of a label image (or
// of a list of analytic shapes) in one conforming mesh whose interfaces are
// chains of mesh edges.
//
// Model.  Materials are numbered 0 .. count()-1; material 0 is the background
// (label images: every pixel not selected; shapes: outside every shape).  Each
// material m has a function phi_m, negative inside it; the material at a point
// is the one whose phi is smallest, i.e. most inside (an exact tie: label
// images, the tied material of the nearest pixel centre, equally near ones
// the upper, then the right; shapes, the later shape of the spec).  The
// interface between materials a and b is where phi_a = phi_b.
//
// Label numbers do not matter.  No rule below reads a label's value: only
// whether two points' materials are equal and whether a material is the
// background.  Renumbering the labels of an image (0, the background, stays
// 0) gives the same mesh — points, triangles, interfaces, boundary, keys —
// with the region tags renumbered (test_material_relabel.cpp).
//
// Algorithm (mesh_materials, the uniform lattice):
//   1. every lattice point gets its material;
//   2. a lattice edge is cut when its endpoints' materials a, b differ; its
//      one cut point is where phi_a = phi_b on it (a third material that lies
//      between is counted, not meshed: `third_material_edges`);
//   3. warping as for one level set (warp_points): the closer endpoint moves
//      onto the cut point, a point that is the closer end of several cut
//      edges takes the nearest cut point.  At a tie, u = 1/2: against the
//      background the other material's endpoint moves (label mode's rule);
//      else the endpoint with more lattice 4-neighbours of its own material;
//      else the lower (-x or -y) endpoint (mesh_materials.cpp,
//      tie_mover_is_lower);
//   4. per square the diagonal by the separating rule generalised to
//      materials (generic_square.hpp: two opposite corners that stay with
//      different materials force the other diagonal).  Then no triangle has
//      two staying corners of different materials (proof at separating_pair),
//      and each triangle's material is the common material of its staying
//      corners; a triangle whose three corners all moved takes the material at
//      its centroid.  Every square emits both its triangles, so the triangles
//      of all materials tile the warped lattice (no gap, no overlap) and every
//      interface is a chain of mesh edges.  The max-min rule can join two
//      staying corners of different materials by its diagonal: mesh_materials
//      refuses it (InputError).
//
// Graded (mesh_materials_graded): the same steps 1 - 3; the graded mesher's
// quadtree, finest on every square with a corner on a cut edge (those squares
// then get exactly step 4's triangles), coarse 45-45-90 templates of one
// material elsewhere.
//
// Certification.  A square whose corners carry one or two materials is a
// square of the two-material proof: map the material of its first staying
// corner (A, B, C, D; A's if all four moved) to '-' and the other to '+'
// (either way is a key: the rules below ask only whether materials differ).  The key is consistent in the prover's sense (prover.cpp,
// `consistent`): no corner is zero-valued; a corner slides inward only along a
// cut side, i.e. towards the other material, hence the opposite sign; never
// two corners towards each other along one side (a side has one cut point and
// one mover); every cut side has a warped endpoint.  Outward slides are not
// constrained by the key (the neighbour is outside the square), t lies in
// (0, 1/2] as in the proof, and both rules decide the same diagonal on the
// square (the separating test only asks whether two corners differ).  So the
// key's certified bound holds for the square's triangles, and --verify checks
// it.  Squares with three or four materials ("junction squares") have a
// junction key instead (proofs/materials.cert, proofs/README.md "Junction
// keys"): which corners share a material (letters in order of first
// appearance) and the warps, e.g. "aRaUbscs".  The mesher's rules are the
// key's: every point has a material, a side is cut iff its ends' materials
// differ, it has one cut point and one mover (the closer end; at u = 1/2 the
// tie rule of step 3), a warped corner slid t in (0, 1/2] along a cut edge of its
// own, every cut side has a warped end, and outward slides constrain only an
// outside neighbour (not in the key).  The separating test reads the
// materials only through "differ", which the letters preserve.  So junction
// squares are looked up, bounded and verified like the others; an unknown
// junction key is an internal error.  The meshers record these keys
// (KeyOptions::keys: SquareKeys, with the junction squares named); the
// pipeline certifies them (pipeline/mesh2d.hpp: certify).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/mesh2d/lattice.hpp"
#include "warpmesh/levelset/levelset.hpp"
#include "warpmesh/core/mesh.hpp"
#include "warpmesh/mesh2d/material_stats.hpp"  // MaterialStats, JunctionSquare
#include "warpmesh/mesh2d/uniform.hpp"

namespace warpmesh {

class MaterialField {
public:
    virtual ~MaterialField() = default;

    virtual int count() const = 0;                    // materials, background included (<= 65536)
    virtual std::int32_t tag(int m) const = 0;        // region tag: the label value; background 0
    virtual std::string name(int m) const = 0;        // e.g. "label_41", "background"
    virtual Box bounds() const = 0;                   // as LevelSet::bounds
    // As LevelSet::bounds_are_domain: true for images (the lattice covers
    // exactly the bounds), false for shapes (a lattice around them).
    virtual bool bounds_are_domain() const { return false; }
    virtual std::string describe() const = 0;

    // phi_m at a point (any finite value; negative inside m).
    virtual double phi(int m, double x, double y) const = 0;
    // argmin_m phi_m(x, y).  Default: every material, ties to the larger m
    // (label images and shapes override it: see Model).
    virtual int material_at(double x, double y) const;
    // The material of every lattice point of `block` (row-major, ni x nj), as
    // material_at at Lattice::position gives it.  Default: material_at.
    virtual void sample_block(const Lattice& lattice, const PointBlock& block, std::span<std::uint16_t> out) const;
    // The parameter u in (0, 1) of the point a + u (b - a) where
    // phi_ma = phi_mb, given that ma is the material at a and mb at b.
    // Default: bracketed_root on phi_ma - phi_mb.
    virtual double cut_parameter(Vec2 a, Vec2 b, int ma, int mb) const;

    // The area the material should have, where known (label images: its
    // pixel count times the pixel area), for the report.
    virtual std::optional<double> reference_area(int /*m*/) const { return std::nullopt; }
};

// ---- fields ------------------------------------------------------------------
// A label image.  `spec`: "all" (every label present except 0, which is the
// background) or a label list as parse_label_list reads it ("3,41,42",
// "1000-1035"); every other pixel joins the background.  phi_m at a pixel
// centre is label mode's field for the region "label m" (image_levelset.hpp):
// -(d_out - 1/2) on m's pixels, d_in - 1/2 elsewhere, with the distances
// between pixel centres capped at 3 pixels, and bilinear in between.  The
// winner at a point is always a label of its pixel cell's four corners (the
// others have phi >= 1/2 there, the corner with the largest weight's label
// phi <= 0.36), whose distances are at most sqrt 2: so the materials are
// those of the uncapped fields, computed from each pixel's 7 x 7 window and
// only in cells whose corners differ — no distance transform per label.  Cut
// points are exact zeros of the piecewise-linear phi_a - phi_b (exact for
// spacings up to 2 pixels; beyond, segments farther than 3 pixels from a
// material see the cap).
// Coordinates as image_levelset.hpp's: pixel (c, y) at (x0 + c sx, y0 + y
// sy) for the PixelGeometry given (default: pixel units, x = c, y = H - 1 -
// row).  As in label mode, phi stays a distance in pixels, so that
// interfaces pass midway between 4-adjacent pixels along both axes whatever
// the pixel sizes; every computation is done in pixel coordinates ((x - x0)
// / sx, (y - y0) / sy, the identity bit for bit in pixel units), and a
// material's reference area is its pixel count times sx sy.
// Throws InputError: label 0 in the list (it is the background), labels absent
// from the image (named), no label at all, more than 65535 labels, a
// geometry check_pixel_geometry refuses.
// Refuses (InputError naming --max-memory) an image whose field would take
// the resident memory above max_memory (memory.hpp).
std::unique_ptr<MaterialField> make_label_materials(const Image& image, const std::string& spec,
                                                    const PixelGeometry& geometry = {},
                                                    std::uint64_t max_memory = default_max_memory);

// Analytic materials: "1=circle:0,0,10;2=circle:6,0,8;3=rect:-2,-2,2,12"
// (shapes.hpp syntax after '='; tags 1..65535, each once).  A later shape wins
// where shapes overlap; outside all of them: background (tag 0).  With f_k the
// shapes' level sets, phi_m = max(f_m, -f_k for every later k), background
// phi_0 = max(-f_k): negative exactly in the material's own region, and
// phi_a = phi_b on the curve separating a and b.  Throws InputError.
std::unique_ptr<MaterialField> parse_material_shapes(const std::string& spec);

// ---- the mesher ----------------------------------------------------------------
struct MaterialOptions {
    bool keep_background = false;  // false: the background's triangles are not output
    DiagonalRule rule = DiagonalRule::separating;  // maxmin is refused
    KeyOptions keys;  // what is recorded for the certification (lattice.hpp)
};

struct MaterialResult {
    Mesh mesh;
    PhaseTimes times;
    std::int64_t cut_edges = 0, warped_points = 0, warped_squares = 0, forced_diagonals = 0;
    std::int64_t third_material_edges = 0;  // cut edges whose cut point lies in a third material
    std::int64_t mixed_triangles = 0;       // two staying corners of different materials: 0 (proved)
    std::int64_t centroid_triangles = 0;    // all corners moved: material at the centroid
    std::vector<MaterialStats> materials;   // index = material number
    // With MaterialOptions::keys.keys (else empty): what certification reads,
    // junction squares included; the keyed squares with 3 or 4 materials
    // (junction keys) and the first 20 of them (by square index), their
    // bounds left to the certification.
    SquareKeys keys;
    std::int64_t junction_squares = 0;
    std::vector<JunctionSquare> junction_examples;
    // mesh_materials_graded only:
    bool graded = false;
    std::vector<std::int64_t> leaves_per_level;  // index = level; all leaves, background included
    std::int64_t invariant_squares = -1;         // squares check_critical_squares_finest checked (-1: not run)
    double quadtree_seconds = 0;                 // signs, tiles, quadtree, leaves, invariant check
};

// The multi-material uniform mesher (see the top of this file).  Throws
// InputError for --diagonal maxmin or more than 65536 materials.
MaterialResult mesh_materials(const MaterialField& field, const Lattice& lattice, const MaterialOptions& options);

// The multi-material graded mesher (mesh_materials_graded.cpp): the graded
// mesher's 2:1-balanced quadtree (graded.hpp), whose finest band now follows
// every interface.  Every lattice square with a corner on a cut edge
// between different materials (an endpoint of it: every warped point and
// every tie) is a finest leaf with no split side, meshed exactly as by
// mesh_materials (the same vertices, diagonal, triangles and materials), so
// its certification is the uniform one; every other leaf lies inside one
// material and is a 45-45-90 template of that material.  The interfaces and
// boundary edges are the uniform mesh's; only the materials' interiors are
// coarser.  Size control (graded.hpp): max_cell and grading_buffer as for
// mesh_graded (0: as coarse as the lattice allows; 0: plain 2:1 balance);
// max_cell_of, empty or one entry per material number, that material's own
// largest cell (a power of two; 0: max_cell only) — the smaller of it and
// max_cell wins; nothing else changes (the band, interfaces and boundary
// are the same).  std::invalid_argument if a cell size is not 0 or a power
// of two, max_cell_of's size is wrong or the buffer is out of
// 0 .. max_grading_buffer.  With options.keys.check_invariant the band
// invariant is checked on the leaves (std::logic_error if violated).  Throws
// as mesh_materials.
MaterialResult mesh_materials_graded(const MaterialField& field, const Lattice& lattice, const MaterialOptions& options,
                                     std::int64_t max_cell, int grading_buffer = 0,
                                     std::span<const std::int64_t> max_cell_of = {});

// MaterialStats::longest_edge of every material: the longest edge of its
// triangles in r.mesh (by region tag; 0 for a material without output
// triangles).
void measure_longest_edges(MaterialResult& r);

// Per region tag (index) of a mesh: its triangles, area, and perimeter (the
// length of its interface edges and of the boundary edges of its triangles);
// and the total length of the level-set boundary edges (tag 1) and of the
// lattice-border edges (tag 2).
struct RegionMeasures {
    std::vector<std::int64_t> triangles;
    std::vector<double> area, perimeter;
    double level_set_length = 0, border_length = 0;
};
RegionMeasures measure_regions(const Mesh& mesh);

// After a pass that changed r.mesh (optimize_mesh): each output material's
// triangles, area and perimeter change by after - before; a dropped
// background's area by minus the output materials' total change (the tiling
// covers the same lattice), its perimeter by the level-set boundary's change
// minus the border's (what the materials gained along the lattice border, it
// lost).  Each output material keeps its area before the pass in
// area_before_optimize.
void update_material_stats(MaterialResult& r, const RegionMeasures& before, const RegionMeasures& after);

}  // namespace warpmesh
