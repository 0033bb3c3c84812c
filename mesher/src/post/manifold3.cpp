// manifold3.cpp — making a tetrahedral mesh's boundary manifold where parts
// of the region touch only along edges or at vertices (tet_checks.hpp:
// split_nonmanifold_vertices).
//
// Around a boundary vertex v the tetrahedra that contain v fall into
// classes: two are in one class when they share a face that contains v
// (transitively).  One class is the usual case, a ball or half-ball around
// v.  Several classes are parts of the region that meet only at v, or along
// an edge through v (parts touching across a voxel's edge or corner, where
// all-zero background tetrahedra were left out).  Each class but the first
// gets its own copy of v (same position), so the parts no longer share it;
// a boundary face or interface that contains v takes the copy of the
// tetrahedron it is a face of (both tetrahedra of an interface are in one
// class: they share the face).  Where every vertex of a non-manifold edge is
// split the edge is split too.  No tetrahedron moves or changes shape.
#include <algorithm>
#include <numeric>
#include <span>

#include "warpmesh/post/tet_checks.hpp"

namespace warpmesh {
namespace {

// A face's vertices as positions in its tetrahedron: (tet, position of
// each face vertex), so that the face follows the tetrahedron's copies.
struct FaceInTet {
    std::int64_t tet = -1;
    std::array<std::uint8_t, 3> at{};
};

// The tetrahedron among `around` (those of face[0]) that has the face, and
// where.
FaceInTet locate(const TetMesh& m, std::span<const std::int64_t> around, const std::array<std::int32_t, 3>& face) {
    for (const std::int64_t t : around) {
        const auto& tet = m.tets[static_cast<std::size_t>(t)];
        FaceInTet f{t, {}};
        int found = 0;
        for (std::size_t k = 0; k < 3; ++k)
            for (std::uint8_t q = 0; q < 4; ++q)
                if (tet[q] == face[k]) f.at[k] = q, ++found;
        if (found == 3) return f;
    }
    return {};
}

// Union-find's root.
std::size_t root(std::vector<std::size_t>& parent, std::size_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
}

}  // namespace

std::int64_t split_nonmanifold_vertices(TetMesh& m) {
    const std::size_t V = m.vertices.size();
    // The tetrahedra around each boundary vertex (a counting sort).
    std::vector<std::uint8_t> on(V, 0);
    for (const auto& b : m.boundary)
        for (const std::int32_t v : b) on[static_cast<std::size_t>(v)] = 1;
    std::vector<std::int64_t> start(V + 1, 0);
    for (const auto& t : m.tets)
        for (const std::int32_t v : t) start[static_cast<std::size_t>(v) + 1] += on[static_cast<std::size_t>(v)];
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<std::int64_t> around(static_cast<std::size_t>(start[V]));
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (std::size_t t = 0; t < m.tets.size(); ++t)
        for (const std::int32_t v : m.tets[t])
            if (on[static_cast<std::size_t>(v)]) around[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] = static_cast<std::int64_t>(t);
    const auto tets_of = [&](std::int32_t v) {
        const auto s = static_cast<std::size_t>(v);
        return std::span<const std::int64_t>(around).subspan(static_cast<std::size_t>(start[s]), static_cast<std::size_t>(start[s + 1] - start[s]));
    };
    // Where each boundary face and interface lies, before any vertex moves.
    std::vector<FaceInTet> boundary_at, interface_at;
    for (const auto& b : m.boundary) boundary_at.push_back(locate(m, tets_of(b[0]), b));
    for (const auto& f : m.interfaces) interface_at.push_back(on[static_cast<std::size_t>(f[0])] ? locate(m, tets_of(f[0]), f) : FaceInTet{});
    std::int64_t added = 0;
    for (std::size_t v = 0; v < V; ++v) {
        if (!on[v]) continue;
        const auto ts = tets_of(static_cast<std::int32_t>(v));
        // Classes: tetrahedra sharing a face through v, i.e. the pair of their other vertices on it.
        std::vector<std::size_t> parent(ts.size());
        std::iota(parent.begin(), parent.end(), 0);
        std::vector<std::pair<std::array<std::int32_t, 2>, std::size_t>> pairs;
        for (std::size_t i = 0; i < ts.size(); ++i) {
            std::array<std::int32_t, 3> other{};
            std::size_t n = 0;
            for (const std::int32_t w : m.tets[static_cast<std::size_t>(ts[i])])
                if (static_cast<std::size_t>(w) != v && n < 3) other[n++] = w;
            std::sort(other.begin(), other.end());
            pairs.push_back({{other[0], other[1]}, i}), pairs.push_back({{other[0], other[2]}, i}), pairs.push_back({{other[1], other[2]}, i});
        }
        std::sort(pairs.begin(), pairs.end());
        for (std::size_t k = 1; k < pairs.size(); ++k)
            if (pairs[k].first == pairs[k - 1].first) parent[root(parent, pairs[k].second)] = root(parent, pairs[k - 1].second);
        // Every class but the first one's takes a new vertex.
        std::vector<std::int32_t> copy(ts.size(), -1);
        const std::size_t first = root(parent, 0);
        for (std::size_t i = 0; i < ts.size(); ++i) {
            const std::size_t r = root(parent, i);
            if (r == first) continue;
            if (copy[r] < 0) {
                copy[r] = static_cast<std::int32_t>(m.vertices.size());
                const Point3 p = m.vertices[v];
                m.vertices.push_back(p);
                ++added;
            }
            for (std::int32_t& w : m.tets[static_cast<std::size_t>(ts[i])])
                if (static_cast<std::size_t>(w) == v) w = copy[r];
        }
    }
    if (added == 0) return 0;
    const auto follow = [&](std::array<std::int32_t, 3>& f, const FaceInTet& at) {
        if (at.tet < 0) return;
        const auto& tet = m.tets[static_cast<std::size_t>(at.tet)];
        for (std::size_t k = 0; k < 3; ++k) f[k] = tet[at.at[k]];
    };
    for (std::size_t i = 0; i < m.boundary.size(); ++i) follow(m.boundary[i], boundary_at[i]);
    for (std::size_t i = 0; i < m.interfaces.size(); ++i) follow(m.interfaces[i], interface_at[i]);
    return added;
}

}  // namespace warpmesh
