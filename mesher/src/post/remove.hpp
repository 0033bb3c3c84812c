// remove.hpp (internal) — removal of interior vertices, a stage of the
// optimisation pass (optimize.hpp) for the triangles that moves, flips and
// Steiner points cannot lift.
//
// Why.  Moves, flips and refinement only ever add vertices.  Where a fixed
// vertex (a junction of three materials, or an interface vertex) has an
// interior edge to a vertex V that splits its corner into two small angles —
// the tip of a one-pixel-wide strip of a label image, where a 36.87° corner is
// split into two 18.43° angles — no position of V changes those angles and
// no flip helps (V would be left inside the triangle of its other
// neighbours).  Removing V does: its star becomes a triangulation of its link
// polygon without it.
//
// The operation.  For each triangle of `eligible` whose smallest angle is
// below `below_deg` (worst first, ties by index), each of its vertices V that
// is *interior* — on no boundary edge and no interface edge, with a closed
// star (its link is one cycle of k <= max_link vertices), every triangle of
// it in one region — is tried: its link polygon L is re-triangulated by the
// max-min triangulation of L (dynamic programming over L's diagonals; a
// diagonal is used only if it lies inside L: it meets no edge of L but at its
// ends and leaves its first end inside L's interior angle there), under
// the constraints that no triangle's largest angle exceeds max(old star max,
// 110°) nor `max_angle_cap`, and (max_edge > 0) no edge is longer than
// max_edge.  This covers every edge collapse of V onto a neighbour (a fan
// from that neighbour) and more.
//
// The acceptance rule (the pass's monotone rule).  The new triangles replace
// V's star only if their smallest angle exceeds the star's old one by more
// than 1e-9°.  Triangles outside the star are unchanged, so the mesh's
// minimum angle never decreases and no triangle gets a largest angle above
// the cap.  The polygon L is covered by the old and the new triangles alike,
// so the mesh stays a conforming embedding, every region keeps its area (one
// region fills L), the boundary and the interfaces (edges of L or outside
// it) are unchanged and still exactly the edges between different regions.
// The k − 2 new triangles take the region of the star and, in every cell
// data array, the least value over the old star — for "certified_min_angle"
// a valid lower bound (the old star's minimum is >= it and the new minimum is
// larger).
//
// Bookkeeping.  After all removals the mesh is compacted: removed vertices
// and the two emptied triangle slots of each removal go, the others keep
// their order (Mesh::boundary, Mesh::interfaces and triangles are renumbered;
// boundary and interface edges keep their index).  The result gives the
// maps, so callers renumber their own per-vertex and per-triangle state.
// Deterministic and sequential.
#pragma once

#include <cstdint>
#include <limits>
#include <span>
#include <unordered_set>
#include <vector>

#include "warpmesh/core/mesh.hpp"

namespace warpmesh {

struct RemoveParams {
    double below_deg = 0;   // try the interior vertices of triangles with a smaller minimum angle
    double max_edge = 0;    // > 0: no new edge longer than this
    double max_angle_cap = std::numeric_limits<double>::infinity();  // no largest angle above this
    // edge_key of every interface edge (their ends are not interior).
    const std::unordered_set<std::uint64_t>* interfaces = nullptr;
};

struct RemoveResult {
    std::int64_t removed_vertices = 0;
    std::vector<std::size_t> touched;        // rewritten triangles (after compaction), increasing
    std::vector<std::int32_t> vertex_map;    // old vertex -> new, -1: removed (empty: nothing removed)
    std::vector<std::int64_t> triangle_map;  // old triangle -> new, -1: removed (empty: nothing removed)
};

// One pass over the bad triangles of `eligible` (triangle indices of mesh).
RemoveResult remove_interior_vertices(Mesh& mesh, std::span<const std::size_t> eligible, const RemoveParams& params);

}  // namespace warpmesh
