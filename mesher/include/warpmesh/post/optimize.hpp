// optimize.hpp — a monotone quality pass after meshing (--optimize).
//
// What it does.  The lattice-warping mesh is right isosceles triangles
// (45°, 45°, 90°) everywhere except in the band of warped squares along the
// boundary, where the certified floor is 18.43° (flat stencils) or 15° and
// measured minima are 20–28°.  optimize_mesh moves the vertices of that band,
// and the interior vertices one edge away from it, to raise each vertex star's
// worst angle, and flips interior edges of the band:
//
//  * the band: every triangle that is not right isosceles (to 1e-9 relative)
//    starts it; its vertices and their neighbours (one ring) are *active*;
//  * active interior vertices move freely;
//  * active vertices on the level-set boundary (tag 1, |f| <= 1e-9 spacing)
//    slide along the level set: a step along the tangent (perpendicular to a
//    central-difference gradient of f), then back onto f = 0 by the level
//    set's own cut_parameter on a segment along the normal — the root finder
//    that placed the cut points, so they stay on the level set to its accuracy;
//  * vertices on the lattice's outer border (tag 2) slide along that border
//    line; vertices where two boundary kinds meet, lattice corners, boundary
//    vertices off the level set, pinch vertices (more than two boundary
//    edges) and endpoints of Mesh::interfaces do not move;
//  * an interior edge is flipped only when both triangles have the same
//    region and the edge is not an interface: boundary and interface edges
//    stay edges, and regions and boundary tags are unchanged.
//
// The quality of an angle θ (degrees) is g(θ) = min(θ, 140 − θ): it rewards
// raising small angles and, for angles beyond 70°, lowering large ones (g = 30
// at 30° and at 110°: the targets); a triangle's quality is the least g of its
// angles, a star's the least over its triangles.  A move of vertex v follows
// the steepest ascent of the star quality (the minimum-norm element of the
// convex hull of the gradients of the nearly-active angles, restricted to the
// vertex's line or the level set's tangent), with a step-halving line search.
//
// The monotone rule (the contract that keeps the proof meaningful).  A move
// is accepted only if
//   (1) no triangle of the star inverts (twice the area stays > 0),
//   (2) the smallest angle among the star's triangles does not decrease,
//   (3) the star quality strictly increases (so the pass terminates),
//   (4) for a boundary vertex, its boundary edges stay within the mesh's
//       largest boundary distance to f = 0 before the pass (same measure as
//       measure_fidelity): the boundary's Hausdorff distance never grows;
//   (5) with OptimizeOptions::max_edge > 0, no edge of the star is longer
//       than it (nor a flipped pair's new diagonal): --max-size holds after
//       the pass too;
//   (6) with OptimizeOptions::certified_max finite, no triangle of the star
//       gets a largest angle above it (nor a flipped pair, nor a refined
//       patch): the certified maximum holds after the pass too;
//   (7) for a boundary vertex, the mesh stays a valid embedding: its two
//       boundary edges meet no other boundary edge nor its link, and no
//       boundary vertex lies in its new star (embedding.hpp) — so a vertex
//       sliding along its curve stays between its neighbours on it, and does
//       not slide past another part of the boundary.
// A flip is accepted only if the smallest angle of the pair strictly
// increases and the pair's quality does not decrease (a flip of a convex
// quadrilateral keeps the embedding).  After the pass the whole mesh is
// checked (check_mesh, mesh_checks.hpp: orientation, manifold edges, closed
// and simple boundary loops, no folds); a failure throws std::logic_error.  Hence the mesh's
// minimum angle never decreases, and every triangle stays at or above the
// mesh's certified floor (the least certified_min_angle).
//
// Certified per-triangle data.  If the mesh has cell data
// "certified_min_angle", it is kept a valid lower bound per triangle: when a
// move or flip leaves a triangle below its own value, the value is lowered to
// the least value among the triangles of that star (or pair), whose old
// minimum angle the rule says the triangle still reaches.  The values never
// fall below the mesh's certified floor.  These transferred bounds rest on
// floating-point angle comparisons, not on the interval proof; the proof
// certifies the unoptimised squares.  optimize_mesh checks at the end that
// every triangle is >= its value and >= the floor (std::logic_error if not:
// a bug).
//
// Local refinement (OptimizeOptions::refine_below_deg > 0).  Moves and flips
// cannot lift a triangle whose three vertices are fixed or can only slide
// along f = 0 — one-pixel strips of label images, where the worst triangles
// stay at atan(1/2) = 26.57°.  After the sweeps, each triangle below the
// threshold (worst first) gets a patch (its region's triangles up to five
// edges away, never across an interface) and up to six greedy Steiner
// insertions, each the first of a few candidates to reach the threshold (else
// the best of them): the worst triangle's
// circumcentre, or, when that lies in a boundary edge's diametral circle, a
// split of that edge (Ruppert); splits of its own and nearby boundary edges;
// the midpoints of its interior edges; its centroid.  A level-set edge
// is split at a point on f = 0 found by the level set's own cut_parameter, so
// boundary vertices stay on the level set; a border edge at its midpoint.
// Each insertion is followed by max-min flips that never touch a boundary,
// interface or patch-border edge, and by smoothing of the patch vertices whose
// whole star lies in the patch (moving as above; corners and pinch vertices
// stay put).  The new patch replaces the old one only if every new triangle
// is positive, the patch's smallest angle strictly rises, its largest stays
// <= max(old patch max, mesh max, 110°), level-set edges at new or moved
// vertices stay within the boundary distance of rule (4), and new or moved
// edges within max_edge (rule (5)).  Then the rewritten triangles' band is
// swept again under the rule above; three such rounds at most.  So the monotone rule
// still reads: the mesh's minimum angle never decreases, and every triangle
// stays >= the certified floor.  Every triangle of a new patch gets, as
// "certified_min_angle", the least value of the old patch (a lower bound: the
// patch's old minimum was >= it and the new minimum is larger); the patch
// keeps its region, a split boundary edge's two halves its tag (the second
// half is appended to Mesh::boundary), vertices are only appended, and
// interface edges are never split or flipped (details: src/post/refine.hpp).
//
// Determinism.  Vertices are visited Gauss-Seidel in increasing index order,
// flips in increasing triangle order, with no dependence on the thread count
// (only the read-only passes that find the band run in parallel, and they
// produce ordered lists), so the result is the same for any number of threads.
// Bounded: at most max_sweeps sweeps; a vertex is revisited only if its star
// changed since its last visit, and left alone once its star's quality is
// >= 42° (a band as good as that costs the meshing's time or less).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "warpmesh/levelset/levelset.hpp"
#include "warpmesh/core/mesh.hpp"
#include "warpmesh/post/optimize_report.hpp"  // OptimizeReport

namespace warpmesh {

class MaterialField;

// One accepted change, for observers (tests): a moved vertex with its old and
// new position and the triangles of its star, or a flip with the old and new
// triangle pair.  The mesh is the state after the change.
struct OptimizeEvent {
    bool flip = false;
    std::int32_t vertex = -1;  // moves
    Vec2 from{}, to{};
    std::span<const std::size_t> star;
    std::array<std::array<std::int32_t, 3>, 2> before{}, after{};  // flips
    // Materials: interior vertices were removed (src/post/remove.hpp) and the
    // mesh compacted: old vertex index -> new, -1 for a removed vertex (the
    // others keep their order).  Empty for moves and flips.
    std::span<const std::int32_t> renumbered;
};

struct OptimizeOptions {
    double spacing = 1;       // the lattice spacing (tolerances, step sizes)
    int max_sweeps = 12;      // Gauss-Seidel sweeps at most (>= 0)
    bool flips = true;        // flip interior edges of the band
    // The mesh's certified floor when it has no "certified_min_angle" cell
    // data (e.g. CertifiedSummary::min_deg); NaN: unknown.
    double certified_floor = std::numeric_limits<double>::quiet_NaN();
    // The mesh's certified maximum angle (CertifiedSummary::max_deg); when
    // finite, no move, flip or refinement makes a triangle's largest angle
    // exceed it, so the report's certified maximum holds after the pass too
    // (rule (6)).  NaN: no cap beyond the rule's own.
    double certified_max = std::numeric_limits<double>::quiet_NaN();
    // > 0: no move or flip makes an edge longer than this (a mesh whose edges
    // are all <= max_edge keeps them so: MeshOptions::max_size); 0: no bound.
    double max_edge = 0;
    // > 0: after the sweeps, refine locally (Steiner points, below) around the
    // triangles whose minimum angle is below this many degrees; 0: off.  The
    // pipeline's --optimize uses 30.
    double refine_below_deg = 0;
    std::function<void(const Mesh&, const OptimizeEvent&)> observer;  // called after every accepted change
};

OptimizeReport optimize_mesh(Mesh& mesh, const LevelSet& f, const OptimizeOptions& options = {});

// Multi-material meshes (mesh(const MaterialField&, ...), mesh_materials,
// mesh_materials_graded): region tags are the field's material tags.  The
// same pass and rule, with the curves of the materials instead of f = 0
// (src/post/curves.hpp):
//  * a vertex with exactly two interface edges, both between the same two
//    materials a and b, no boundary edge and phi_a = phi_b there (to 1e-9
//    spacing) slides along that interface: a tangent step, then back onto
//    phi_a = phi_b by the field's cut_parameter on a segment along the normal
//    (its star is closed, so no embedding test is needed);
//  * a level-set boundary vertex (two tag-1 edges: its material m against
//    the dropped background) slides along phi_m = phi_0, as a boundary vertex
//    along f = 0 (embedding test included); lattice-border vertices as above;
//  * junctions (three or more materials, the dropped background counted;
//    an interface meeting the dropped background's boundary; crossings of
//    interfaces; interface vertices off their curve) with a closed star or
//    exactly two level-set boundary edges move in the plane, like interior
//    vertices, under the same rule (embedding test on their boundary edges);
//    the ascent direction is made area-neutral for the one region (if one)
//    whose budget (8) has no room for the step; vertices on the lattice
//    border or where more boundary edges meet (pinches) stay fixed;
//  * rule (4) bounds every moved boundary or interface edge by the largest
//    distance of the band's boundary and interface edges to their curves
//    before the pass (a junction: each of its boundary and interface edges);
//  * (8) with reference areas (label images: pixel count x pixel area), a
//    move or refined patch is accepted only if every region it changes keeps
//    |area - reference| at or below its value before the pass: no label's
//    area error grows (checked again at the end, std::logic_error if not).
//    A move of a star whose quality is already >= 35° may not use that room
//    at all (its regions' errors may only shrink): the room is kept for the
//    worse stars.
// Flips never cross an interface.  Refinement patches stay inside one
// material; it may split a material's level-set boundary edge and, as a
// candidate for the patch's worst triangle, one of its interface edges, at a
// point on the curve of the two materials (the triangle on the other side
// joins the patch with its own region; the halves replace the edge in
// Mesh::interfaces with the same regions).  So Mesh::interfaces stays exactly
// the edges between different regions (OptimizeReport::interface_splits
// counts the splits).  With materials a candidate whose trial the whole
// acceptance rule takes (angles, embedding, area budget) ranks above every
// other, and a trial whose smoothing moved a label's area beyond its budget
// is tried again smoothing interior vertices only, then not at all (the
// pipeline refines below 35° with materials, 30° for one region).  With
// refine_below_deg > 0, after the refinement an
// interior vertex (no boundary or interface edge) of a triangle below 35° is
// removed where the max-min re-triangulation of its link lifts its star's
// smallest angle (src/post/remove.hpp: areas, boundary and interfaces
// unchanged); the mesh is then compacted, so vertex and triangle indices
// change (OptimizeEvent::renumbered, OptimizeReport::removed_vertices).
// The refinement rounds then run once more over everything the pass changed,
// and last the sweeps run once more over the stars of the triangles still
// below 35°, a junction's area-neutral projection then counting a label's
// room within rounding of zero as none (a label exact before the pass).
OptimizeReport optimize_mesh(Mesh& mesh, const MaterialField& field, const OptimizeOptions& options = {});

// The pass's report as text lines and as a JSON object (the report's
// "optimize" field) are the report module's (report.hpp: optimize_text,
// optimize_json).

}  // namespace warpmesh
