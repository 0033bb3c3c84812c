// mesh.hpp — the output of every mesher: a conforming triangle mesh.
//
// Invariants (checked by tests/test_mesh_properties.cpp and, for any mesh, by
// `check_mesh` in mesh_checks.hpp):
//  * vertices are compacted: every vertex is used by at least one triangle;
//  * every triangle is counter-clockwise with positive area;
//  * `boundary` lists each edge that belongs to exactly one triangle, oriented
//    as in that triangle (the meshed region lies to its left).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "warpmesh/buffer.hpp"

namespace warpmesh {

// Tags of boundary edges.
enum BoundaryTag : std::int32_t {
    boundary_level_set = 1,  // on (or, under max-min, near) the level set f = 0
    boundary_domain = 2,     // on the lattice's outer border: the region was cut off there
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

    // Per-triangle cell data that writers export when present (same length as
    // `triangles`), e.g. the certified minimum angle of the triangle's square.
    std::vector<std::pair<std::string, Buffer<double>>> cell_data;
};

}  // namespace warpmesh
