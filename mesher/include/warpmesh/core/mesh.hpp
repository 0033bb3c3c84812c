// mesh.hpp — the output of every mesher: a conforming triangle mesh.
//
// Invariants (checked for any mesh by `check_mesh` in mesh_checks.hpp, which
// the tests run on every mesher's output):
//  * vertices are compacted: every vertex is used by at least one triangle;
//  * every triangle is counter-clockwise with positive area;
//  * `boundary` lists each edge that belongs to exactly one triangle, oriented
//    as in that triangle (the meshed region lies to its left).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "warpmesh/core/buffer.hpp"

namespace warpmesh {

// Tags of boundary edges.
enum BoundaryTag : std::int32_t {
    boundary_level_set = 1,  // on (or, under max-min, near) the level set f = 0
    boundary_domain = 2,     // the region was cut off there: the lattice's outer border (2D: an image's
                             // border), 3D also a volume's hull (LevelSet3::domain)
};

struct Vec2 {
    double x, y;
};

struct Mesh {
    // The large arrays are Buffers (buffer.hpp): filled in parallel, not zeroed.
    Buffer<Vec2> vertices;
    Buffer<std::array<std::int32_t, 3>> triangles;
    Buffer<std::int32_t> region;  // one tag per triangle
    std::vector<std::array<std::int32_t, 2>> boundary;
    std::vector<std::int32_t> boundary_tag;  // one tag per boundary edge

    // Multi-material meshes: the edges shared by two triangles of different
    // regions, each oriented with region interface_regions[k][0] on its left
    // and interface_regions[k][1] on its right.  Empty for a one-region mesh.
    std::vector<std::array<std::int32_t, 2>> interfaces;
    std::vector<std::array<std::int32_t, 2>> interface_regions;
    // Names of region tags for formats that name groups (.msh physical names,
    // XDMF/Abaqus sets); a tag without an entry is named by its number.
    std::vector<std::pair<std::int32_t, std::string>> region_names;

    // Per-triangle cell data that writers export when present (same length as
    // `triangles`), e.g. the certified minimum angle of the triangle's square.
    std::vector<std::pair<std::string, Buffer<double>>> cell_data;
};

}  // namespace warpmesh
