// refine.hpp (internal) — local refinement of the optimisation pass's worst
// triangles (optimize.hpp: OptimizeOptions::refine_below_deg).
//
// For each triangle T whose minimum angle is below `below_deg` (worst first,
// ties by index), take its patch: the triangles reachable from T across at
// most `patch_rings` edges, within `eligible` triangles, of T's region, never
// across an interface edge.  Then, greedily, up to a few times: for the
// patch's current worst triangle W try a few Steiner points —
//  * W's circumcentre, if it lies inside the patch and within no boundary
//    edge's diametral circle; otherwise (Ruppert) split every boundary edge of
//    the patch whose diametral circle it enters;
//  * W's own boundary edges, and the patch's boundary edges at W's vertices;
//  * the midpoints of W's interior edges, longest first; W's centroid —
// each re-triangulated by Lawson flips under the max-min rule (a flip when the
// pair's smallest angle strictly rises) of edges inside the patch only (never
// a boundary edge, an interface edge or the patch border), then smoothed:
// every patch vertex none of whose edges is on the patch border moves to raise
// its star's least quality min(θmin, 140° − θmax) (interior vertices freely,
// level-set vertices with exactly two boundary edges along f = 0 and back
// onto it by cut_parameter, border vertices along their line; corners and
// pinch vertices — more than two boundary edges — stay put), and flipped
// again.  The first candidate whose patch reaches `below_deg` within the
// angle cap of rule (3) is kept, else the best (within the cap first, then the
// largest minimum), and the next insertion starts from it; the patch is
// replaced as soon as it meets the acceptance rule.  Materials: a trial that
// meets the whole acceptance rule below ((6) and (7) included) ranks above
// every other, and one whose smoothing took a region's area beyond its
// budget (7) is made again smoothing only interior vertices (areas kept),
// then without smoothing.
// A level-set boundary edge (tag 1) is split at a point on f = 0, found by
// the level set's own cut_parameter on a segment across the edge's midpoint
// (the root finder that placed the cut points); a lattice-border edge (tag 2)
// at its midpoint, which stays on the border line.  Other tags are never
// split.  Materials (curves.materials()): each of W's interface edges is a
// candidate too, split at a point on the curve of its two materials
// (curves.hpp), found by the curve's cut_parameter on a segment across the
// edge's midpoint; the triangle on the other side joins the trial with its
// own region.  Flips never cross an edge between two regions of the trial,
// vertices on such an edge do not move in the smoothing, and the halves
// must be within `boundary_distance` of their curve.  The acceptance rule
// below counts those other-side triangles in the old patch; on acceptance
// Mesh::interfaces (and `interfaces`) get the two halves, same regions.
//
// The acceptance rule.  The new patch replaces the old one only if
//   (1) every new triangle is counter-clockwise with positive area,
//   (2) the patch's smallest angle strictly increases,
//   (3) the patch's largest angle stays <= max(old patch max, max_angle, 110°)
//       and <= max_angle_cap,
//   (4) every level-set boundary edge at a new or moved vertex is within
//       `boundary_distance` of f = 0 (measure of edge_distance_to_levelset),
//       and those vertices have |f| <= 1e-10 spacing,
//   (5) with max_edge > 0, no new edge, nor one at a new or moved vertex,
//       is longer than max_edge,
//   (6) the mesh stays a valid embedding (embedding.hpp): the boundary edges
//       at new or moved vertices meet no other boundary edge nor the patch
//       border, and no boundary vertex lies inside a new triangle;
//   (7) with an area budget (materials with reference areas), the region's
//       area error stays within it.
// Triangles outside the patch are unchanged (a moved vertex has all its
// triangles in the patch), so the mesh's minimum angle never decreases.  The
// patch's triangles keep their slots (the extra ones are appended) and the
// region; every cell data array gets, on each triangle of the new patch, the
// least value over the old patch — for "certified_min_angle" a valid lower
// bound, since every old triangle was >= its value, so the old patch minimum
// is >= the least value and the new patch minimum exceeds it.  A split
// boundary edge a-b becomes a-m in place plus m-b appended to Mesh::boundary
// with the same tag and orientation.  Vertices are appended, never removed.
// Deterministic and sequential.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <unordered_set>
#include <vector>

#include "warpmesh/core/buffer.hpp"
#include "warpmesh/levelset/levelset.hpp"
#include "warpmesh/core/mesh.hpp"
#include "curves.hpp"
#include "embedding.hpp"

namespace warpmesh {

struct RefineParams {
    double below_deg = 0;          // refine triangles with a smaller minimum angle
    double spacing = 1;            // the lattice spacing (tolerances)
    double max_edge = 0;           // > 0: no new edge longer than this
    double boundary_distance = 0;  // the largest allowed distance of a new level-set edge to f = 0
    double max_angle = 0;          // the mesh's largest angle (rule (3))
    // Rule (3) never allows a largest angle above this (the mesh's certified
    // maximum; infinity: no cap).
    double max_angle_cap = std::numeric_limits<double>::infinity();
    int patch_rings = 5;           // a one-pixel strip needs this many for room to insert
    std::unordered_set<std::uint64_t>* interfaces = nullptr;  // edge_key of every interface edge (kept up to date)
    // The mesh's boundary edges (embedding.hpp), kept up to date: a patch is
    // replaced only if the change is an embedding (rule (6)).
    BoundaryIndex* index = nullptr;
    // With reference areas (materials): a patch is replaced only if its
    // region's area error stays within its budget (curves.hpp), rule (7).
    AreaBudget* areas = nullptr;
};

struct RefineResult {
    std::int64_t refined_triangles = 0;  // bad triangles whose patch was replaced
    std::int64_t inserted_vertices = 0;  // of which on boundary edges: boundary_splits
    std::int64_t boundary_splits = 0;
    std::int64_t interface_splits = 0;  // of which on interfaces (materials)
    std::vector<std::size_t> touched;  // the triangles rewritten or appended, increasing
};

// One pass over the triangles of `eligible` (increasing; the triangles of the
// mesh that may be bad or belong to a patch).  A patch's level-set boundary
// edges lie on the curve curves.boundary_curve(its region) ("f" above).
RefineResult refine_bad_triangles(Mesh& mesh, const SlideCurves& curves, std::span<const std::size_t> eligible,
                                  const RefineParams& params);

}  // namespace warpmesh
