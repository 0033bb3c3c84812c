// mesh2d.hpp — the 2D pipeline, the library's entry point: a level set (or
// a material field) in, a certified mesh and its typed report out.
//
//   auto f = warpmesh::parse_shape("circle:0,0,1");
//   warpmesh::MeshOptions o;
//   o.spacing = 0.05;
//   warpmesh::MeshResult r = warpmesh::mesh(*f, o);
//   // r.mesh.vertices, r.mesh.triangles, r.mesh.region, r.mesh.boundary, ...
//   std::cout << warpmesh::to_text(r);  // the report (report.hpp): to_text, to_json
//
// Images: read_image (image.hpp), then image_levelset (below) gives the level
// set; the rest is the same.
//
// mesh() owns the whole pipeline the command line runs: the lattice and its
// size limits, the uniform or graded mesher, the diagonal rule, the
// certification against the compiled-in proofs and its verification, the
// `--guarantee flat` refinement, the optional optimisation pass, the
// resolution check (resolution.hpp: a warning when the spacing is too coarse
// for the input), the boundary-fidelity measurement, and the report: it fills
// a Mesh2dReport with each stage's figures, which the report module
// (report.hpp) writes as text and JSON.  It prints nothing: warnings are
// returned in MeshResult::warnings.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "warpmesh/certify/certified.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/mesh2d/lattice.hpp"
#include "warpmesh/levelset/levelset.hpp"
#include "warpmesh/core/mesh.hpp"
#include "warpmesh/pipeline/options.hpp"
#include "warpmesh/report/report.hpp"  // Mesh2dReport, to_json, to_text
#include "warpmesh/io/writers.hpp"

namespace warpmesh {

class MaterialField;  // materials.hpp

enum class Guarantee {
    any,   // mesh at the given spacing; the certified bound is whatever it is
    flat,  // halve the spacing until every warped square's stencil is flat
};

struct MeshOptions {
    // Lattice spacing in the level set's units (pixels for images), > 0 and
    // at most 1e9.
    double spacing = 1;
    // The diagonal rule; unset: the fan rule on the square lattice (the
    // paper's bound, every angle in [18.4349°, 143.1302°] on every input,
    // several materials included), separating on the rhombic lattice (which
    // has no fan rule).  rule_of() gives the rule a mesh uses.
    std::optional<DiagonalRule> rule;
    // Graded mesh on a 2:1-balanced quadtree (graded.hpp), finest along the
    // boundary; max_cell is the largest cell in lattice squares (a power of
    // two, 0 = as coarse as the domain allows); a non-zero max_cell without
    // graded is refused (validate).
    bool graded = false;
    std::int64_t max_cell = 0;
    // Size control (graded.hpp).  max_size H > 0, in the level set's units:
    // every triangle's longest edge is at most H; 0 = no bound.  H must be at
    // least √5 spacing (the warped band's edges reach √5 s).  A graded mesh
    // (single region or multi-material) takes as its largest cell the
    // smaller of max_cell and max_cell_for_size(H, s); a uniform one is
    // bounded by the spacing already: H is only checked.  The optimisation
    // pass keeps the bound (OptimizeOptions::max_edge).  grading G in
    // [1.1, 2] (graded only; 2 = plain 2:1 balance): sizes grow away from the
    // boundary (and the interfaces) by at most a factor 2^(1/n) <= G per
    // leaf on average, n = grading_buffer(G); G other than 2 without graded
    // is refused (validate).
    double max_size = 0;
    double grading = 2;
    // Per-material maximum sizes (multi-material meshes only): pairs (tag T,
    // H_T), each tag once, H_T as max_size (> 0, >= √5 spacing): every
    // triangle of material T has its longest edge at most H_T (and at most
    // max_size).  Graded: the material's cells are capped at
    // max_cell_for_size(H_T, s) (mesh_materials_graded's max_cell_of);
    // uniform: bounded by the spacing already, only checked.  The report
    // gives each material's cap and its longest edge.  Tag 0 (the
    // background) only with keep_background.
    std::vector<std::pair<std::int32_t, double>> max_size_of;
    // Refuse lattices with more squares than this (InputError, before any
    // lattice-sized allocation).
    std::int64_t max_squares = std::int64_t{1} << 30;
    // Refuse, before any lattice-sized allocation, a mesh whose estimated
    // peak memory is above this many bytes (OptionError naming max_memory):
    // the process's resident memory when mesh() starts (the input and its
    // level set or material field) plus the pipeline's bytes a lattice
    // square (memory_per_square).
    std::uint64_t max_memory = default_max_memory;
    // Certification (certified.hpp): the per-square bounds and the summary;
    // cell_data adds the per-triangle array "certified_min_angle" to the mesh
    // (8 bytes a triangle); verify checks every keyed triangle against its
    // certified interval (a violation is a std::logic_error: a bug).
    bool certify = true, cell_data = true, verify = true;
    // Guarantee::flat: halve the spacing while some warped square is not
    // flat, but not below min_spacing (default spacing / 16); if squares are
    // still not flat there, the mesh of the last spacing is returned with a
    // warning.  Needs certify.
    Guarantee guarantee = Guarantee::any;
    std::optional<double> min_spacing;
    // After meshing (and certification), the monotone optimisation pass
    // (optimize.hpp): raises the band's worst angles, never a star's minimum
    // lower; the certified floor and the cell data stay valid lower bounds.
    bool optimize = false;
    // Benchmarks: mesh `repeat` times (1..1000) and report the fastest run's
    // phase times; the mesh is the same every time.
    std::int64_t repeat = 1;
    // Multi-material meshes (mesh(const MaterialField&, ...)): output the
    // background's triangles (region 0) too; false: it only bounds the
    // materials.  Ignored by mesh(const LevelSet&, ...).
    bool keep_background = false;
    // The lattice.  LatticeMetric::rhombic meshes on the
    // 60-degree rhombic lattice (equilateral interior triangles; the lattice
    // edges have length `spacing`): uniform meshes of one region only, with
    // the separating or maxmin rule, certified by proofs/rhombic_<rule>.cert
    // (certify, cell_data, verify and Guarantee::flat as on the square
    // lattice).  graded, max_size, DiagonalRule::fan and multi-material
    // meshes are refused with it (validate, mesh(MaterialField)).
    LatticeMetric lattice = LatticeMetric::square;
    // What the report names as the input ("input" in the JSON), e.g. a path
    // or a shape string.
    std::string input;
};

// Throws OptionError (errors.hpp) naming the option if an option is out of
// range or options contradict each other (max_size_of: a size out of range or
// a tag given twice; its tags are checked against the materials by mesh()).
// `given`: the options a client set by name (mesh2d_option_table), which
// refuses a few values that only look like settings (max_size 0, max_cell 0:
// the defaults, "no bound", which one gets by leaving the option out) and
// options given that do not apply (grading 2 without graded).  mesh() calls
// it with nothing given.
void validate(const MeshOptions& options, const GivenOptions& given = {});

// The rule a mesh with these options uses: options.rule, or its default
// (fan on the square lattice, separating on the rhombic one).
DiagonalRule rule_of(const MeshOptions& options);

// The options of mesh() by name (options.hpp): the command line's `warpmesh
// mesh` options and Python's keywords of mesh, mesh_shape and mesh_shapes are
// this table's entries, their help its help; its validate is validate().
// (input, cell_data: set by the clients, not options.)
const OptionTable<MeshOptions>& mesh2d_option_table();

struct MeshResult {
    Mesh mesh;                   // mesh.hpp: vertices, triangles, region, boundary (+ tags), interfaces, cell data
    CertifiedSummary certified;  // available = false without certification (or without certificates)
    Lattice lattice;             // the lattice of the returned mesh (after refinements)
    double spacing = 0;          // its spacing
    int refinements = 0;         // halvings made by Guarantee::flat
    // Each stage's figures (report.hpp): the quality with the phase times,
    // the lattice, the mesher's counts, the optimisation pass (report.optimize,
    // with MeshOptions::optimize: before/after figures), the materials, the
    // certification (a copy of `certified` without the boxes).
    Mesh2dReport report;
    std::vector<std::string> warnings;  // e.g. Guarantee::flat stopped at min_spacing; no certificates in this build
};

// The result's report as one JSON object (what `warpmesh mesh --report`
// writes) and as text (what the command line prints): report.hpp's
// to_json/to_text of result.report.
inline std::string to_json(const MeshResult& result) { return to_json(result.report); }
inline std::string to_text(const MeshResult& result) { return to_text(result.report); }

// Mesh the region {f <= 0}.  (max_size_of is refused: InputError.)
//
// The lattice: if f.bounds() is the domain (images, LevelSet::bounds_are_domain),
// the lattice of the given spacing over it (lattice_over: the mesh may reach the
// domain border, tagged boundary_domain); otherwise a lattice around the
// bounds with a margin (lattice_around: the mesh never reaches it).
//
// Returns the mesh, its certified bounds (certify: every triangle's angles lie
// in [certified.min_deg, certified.max_deg], by the proofs of proofs/*.cert;
// for analytic level sets also the boundary fidelity), and the report.
// Throws InputError for invalid options, a lattice over max_squares or beyond
// the lattice's limits (lattice.hpp), a non-finite value of f, or an empty
// mesh (no triangle inside at this spacing).  Time and memory: linear in the
// lattice's squares (uniform) or in the boundary's length over the spacing
// (graded), times 2 per refinement at most; f is evaluated once per lattice
// point (uniform) or per point of the tiles the boundary reaches (graded).
// Uses OpenMP threads (omp_set_num_threads); thread-safe for distinct results.
MeshResult mesh(const LevelSet& f, const MeshOptions& options);

// Multi-material meshes (materials.hpp: label images, analytic shapes): every
// material in one conforming mesh whose interfaces are mesh edges
// (Mesh::interfaces, interface_regions, region_names), region tag = the
// material's tag; the background's triangles only with keep_background.  The
// lattice as for mesh(f): over the bounds for images, around them for
// shapes; uniform, or with `graded` the quadtree whose finest band follows
// every interface (mesh_materials_graded, materials.hpp).  The report adds
// the per-material figures, interface and junction-square counts
// (report.hpp: MaterialsFigures); a material that got no triangle is a
// warning (material_warnings).  With optimize, the pass for materials (optimize_mesh(Mesh&, const
// MaterialField&, ...)) runs after certification, as for one region, and the
// per-material figures are those of the optimised mesh.  Throws InputError as
// mesh(f), for options that do not apply to several materials
// (Guarantee::flat, DiagonalRule::maxmin), and
// for a max_size_of tag that is no material (or the dropped background).
MeshResult mesh(const MaterialField& field, const MeshOptions& options);

// mesh()'s certification of one 2D stage's mesh, for callers of the stages
// (uniform.hpp, graded.hpp, materials.hpp) that asked them for their keys
// (KeyOptions::keys): certify_keys (certified.hpp) on r.mesh and r.keys, in
// the keys' lattice metric; its time, with the keys' gathering, in
// r.times.certify.  A multi-material result's junction examples get their
// keys' bounds; without certificates in this build (an empty summary) its
// junction figures are cleared, as none is certified.  Throws as
// certify_keys.
struct UniformResult;   // uniform.hpp
struct GradedResult;    // graded.hpp
struct MaterialResult;  // materials.hpp
CertifiedSummary certify(UniformResult& r, const Lattice& lattice, DiagonalRule rule, const CertifyOptions& options);
CertifiedSummary certify(GradedResult& r, const Lattice& lattice, DiagonalRule rule, const CertifyOptions& options);
CertifiedSummary certify(MaterialResult& r, const Lattice& lattice, DiagonalRule rule, const CertifyOptions& options);

// Write options for pictures of this result: the warped squares whose stencil
// is not flat outlined in SVGs, with a note; with color_certified, pictures
// coloured by "certified_min_angle" (needs the cell data).
WriteOptions write_options(const MeshResult& result, bool color_min_angle = false, bool color_certified = false);

// The level set of an image for mesh(): threshold or label mode
// (image_levelset.hpp: make_image_levelset, label_options).  Throws
// InputError for an image smaller than 2 x 2 pixels (no lattice square, the
// message names image.source), then as make_image_levelset.
std::unique_ptr<LevelSet> image_levelset(const Image& image, const ImageLevelSetOptions& options);

}  // namespace warpmesh
