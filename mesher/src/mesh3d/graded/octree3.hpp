// octree3.hpp — the graded 3D mesher's balanced octree over the BCC
// lattice's cubes (internal; the public side is mesh3d/graded.hpp, the rule
// of its tetrahedra mesh3d/generic_octree.hpp).
//
// THE FINEST-BAND INVARIANT (what lets the uniform certificate apply).  A
// background tetrahedron is *active* if, after warping, one of its vertices
// is on the level set (sign 0: warped, or f = 0 at the lattice point) or two
// have opposite signs (an edge of it is cut): only then does its stencil do
// more than output it whole or not at all.  Its four points (the centres of
// its two cubes, two corners of their shared face) are among the 15 points
// of each of its cubes: a cube's 8 corners, its centre and its 6 face
// neighbours' centres.  A cube is *critical* if its 15 points are not all of
// one strict sign, or it lies within 2 cubes of the lattice's border (so no
// template touches the border, where the uniform path names the cut-off
// faces).  Critical cubes are finest leaves, so every active background
// tetrahedron has both its cubes finest: it is a fan tetrahedron of an
// equal-size finest piece (generic_octree.hpp), i.e. the uniform lattice's,
// split by its stencil exactly as the uniform mesher splits it (the signs,
// cut points and warps are the uniform mesher's, computed on the whole
// lattice).  Every template has four vertices of one strict sign: they lie
// in the 15-point sets of non-critical cubes of one class (a coarse leaf's
// cubes all have its class; a finest leaf X beside a coarser leaf Y: the
// cube of Y against X lists X's centre and the piece's corners, and Y's
// centre is a corner of one of Y's cubes; two equal coarse leaves share
// their face's corners), and no point of a non-critical cube is warped (a
// warped point has sign 0).  So a template is output whole (inside) or not
// at all.
// SEVERAL MATERIALS (materials3.cpp, mesh_bcc_materials_graded): the same
// argument with "one strict sign" read as "unwarped and of one material".
// A background tetrahedron whose stencil does more than output it whole in
// one material has a warped vertex or two vertices of different materials
// (generic_bcc_materials.hpp: its letters); a cube is critical unless its
// 15 points are unwarped and of one material, so every such tetrahedron lies
// between finest leaves and is split by the uniform multi-material rule
// (two-material sides, junctions: proofs/bcc_junctions.cert) unchanged, and
// every template has four unwarped vertices of one material, output whole
// with that material's tag (or not at all, when it is not output).
// A cell of level l ≥ 1 is *coarsenable* if its 8 children are coarsenable
// (level 0: non-critical) with one sign, and, with a grading buffer n ≥ 2,
// every cell of its level within n cells (max norm) is coarsenable too
// (sizes then grow by at most 2^(1/n) per cell on average, as in 2D,
// docs/graded.md); the leaves are the largest coarsenable cells up to
// max_level, then refined until 2:1 balanced across faces and edges (splits
// only refine, so the invariant stays).  Stage 5 checks it where it is
// cheap (tets3.cpp: every inside template's four vertices, as it is
// written); tests/test_mesh3d_graded.cpp checks every active background
// tetrahedron.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "mesh3d/uniform3d.hpp"
#include "warpmesh/mesh3d/generic_octree.hpp"
#include "warpmesh/mesh3d/graded.hpp"

namespace warpmesh::graded3 {

using Cube = std::array<std::int64_t, 3>;

struct Octree3 {
    std::array<std::int64_t, 3> cubes{0, 0, 0};
    std::vector<std::int8_t> level;  // per cube (x fastest): the level of its leaf
    std::vector<std::int64_t> leaves_per_level;
    std::int64_t index(const Cube& c) const { return (c[2] * cubes[1] + c[1]) * cubes[0] + c[0]; }
    bool contains(const Cube& c) const {
        return c[0] >= 0 && c[1] >= 0 && c[2] >= 0 && c[0] < cubes[0] && c[1] < cubes[1] && c[2] < cubes[2];
    }
    int level_at(const Cube& c) const { return level[static_cast<std::size_t>(index(c))]; }
};

// The octree of a warped window of the whole lattice: leaves at most
// 2^max_level cubes wide, grading buffer `buffer` (1: plain 2:1 balance).
// One region: a point's class is its post-warp sign.  Several materials
// (`material`: every window point's code, materials3.cpp's): a point's class
// is its material (merge_outside: the outside counted as the background,
// code 0), and a warped point is critical, so a cube is coarsenable iff its
// 15 points are unwarped and strictly inside one and the same material —
// every interface and the outer boundary (a cut between materials or
// against the outside) stay in the finest band.
Octree3 build_octree3(const uniform3d::Window& w, int max_level, int buffer, std::span<const std::uint16_t> material = {},
                      bool merge_outside = false);

// std::invalid_argument for a negative max_level or a buffer outside
// 0 .. max_grading_buffer (graded3.cpp).
void check_graded_options(const GradedOptions3& g);

// Cube c of a finest leaf: the bits of its background tetrahedra
// (background_tet's index) that the uniform stencils split — those of its
// low faces whose neighbour is a finest leaf too (or absent: the uniform
// path skips a missing tetrahedron itself).
unsigned uniform_mask(const Octree3& t, const Cube& c);

// The templates the leaf with origin cube c owns (none if c is not a leaf's
// origin): the fans of its low faces against equal coarse leaves and of its
// faces against leaves twice its size, positively oriented, in doubled
// lattice coordinates.  At most 6 faces × 8.
using Templates = std::array<bcc::LatticeTet, 48>;
int leaf_templates(const Octree3& t, const Cube& c, Templates& out);

}  // namespace warpmesh::graded3
