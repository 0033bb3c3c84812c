// same_mesh.hpp — two meshes with the same points and triangles, in the same
// order, bit for bit, and region tags equal up to a map (tag(a) == b).  For
// the multi-material tests (label mode parity, label-permutation invariance).
// Needs Boost.Test in the including file.
#pragma once
#include <cstddef>

#include "warpmesh/core/mesh.hpp"

namespace warpmesh::testing {

template <class TagMap>
void require_same_points_and_triangles(const Mesh& a, const Mesh& b, TagMap&& tag) {
    BOOST_REQUIRE_EQUAL(a.vertices.size(), b.vertices.size());
    BOOST_REQUIRE_EQUAL(a.triangles.size(), b.triangles.size());
    for (std::size_t k = 0; k < a.vertices.size(); ++k) {
        BOOST_REQUIRE_EQUAL(a.vertices[k].x, b.vertices[k].x);
        BOOST_REQUIRE_EQUAL(a.vertices[k].y, b.vertices[k].y);
    }
    for (std::size_t k = 0; k < a.triangles.size(); ++k) {
        BOOST_REQUIRE(a.triangles[k] == b.triangles[k]);
        BOOST_REQUIRE_EQUAL(tag(a.region[k]), b.region[k]);
    }
}

}  // namespace warpmesh::testing
