// triangulate_graded.hpp — the triangles of the graded mesher's quadtree
// leaves (triangulate_graded.cpp).  Private to mesher/src.
#pragma once

#include <span>

#include "mesh2d/graded/quadtree.hpp"
#include "mesh2d/graded/tiles.hpp"
#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh {

// Triangles of the leaves.  Finest leaves: the square's diagonal by `rule`
// exactly as the uniform triangulation (warped_square_split where a corner
// is warped or zero-valued, AD otherwise) and the triangles with three inside
// corners; or the centroid fan (DiagonalRule::fan), whose centres are
// numbered after the lattice points' vertices, in the leaves' canonical order.  Coarse inside leaves: AD if no side is split; otherwise the centre
// template (centre joined to the corners and to the split sides' midpoints).
// Vertices compacted in lattice-point order, boundary edges oriented with the
// region on their left, region tags as in the uniform mesh.  `leaves` as
// quadtree_leaves(tree) returns them (with or without the outside ones);
// `warped` sorted by point.  Throws std::length_error beyond 2^31 - 1
// vertices or triangles.
Mesh triangulate_graded(const LevelSet& f, const Lattice& lattice, const TiledSigns& signs, const Quadtree& tree,
                        const Leaves& leaves, std::span<const WarpedPoint> warped, DiagonalRule rule,
                        TriangulateStats* stats = nullptr);

}  // namespace warpmesh
