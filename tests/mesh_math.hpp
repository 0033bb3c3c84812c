// mesh_math.hpp — measurements of a mesh that the tests and the fuzz targets
// share (no Boost.Test here: the fuzz targets include it too).
//
// Angles are measured with atan2(|u x v|, u . v), in degrees: a reference for
// the tests, independent of the exact cotangent forms of the proof.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <tuple>
#include <vector>

#include "warpmesh/core/mesh.hpp"
#include "warpmesh/post/mesh_checks.hpp"

namespace warpmesh::testing {

// The three angles of triangle t, in degrees, at its vertices 0, 1, 2.
inline std::array<double, 3> triangle_angles_deg(const Mesh& m, std::size_t t) {
    std::array<double, 3> a{};
    for (int k = 0; k < 3; ++k) {
        const Vec2 o = m.vertices[static_cast<std::size_t>(m.triangles[t][k])];
        const Vec2 q = m.vertices[static_cast<std::size_t>(m.triangles[t][(k + 1) % 3])];
        const Vec2 r = m.vertices[static_cast<std::size_t>(m.triangles[t][(k + 2) % 3])];
        const double ux = q.x - o.x, uy = q.y - o.y, vx = r.x - o.x, vy = r.y - o.y;
        a[static_cast<std::size_t>(k)] = std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180 / M_PI;
    }
    return a;
}

// The smallest and largest angle of the whole mesh (180, 0 for no triangle).
struct AngleRange {
    double min = 180, max = 0;
};
inline AngleRange angle_range_deg(const Mesh& m) {
    AngleRange r;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (double a : triangle_angles_deg(m, t)) r.min = std::min(r.min, a), r.max = std::max(r.max, a);
    return r;
}

// The signed area of the mesh (positive for counter-clockwise triangles).
inline double mesh_area(const Mesh& m) {
    double a = 0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) a += cross2(m, t) / 2;
    return a;
}

// Boundary edges as coordinates (from, to, tag), sorted: comparable between
// meshes that number their vertices differently (the graded mesh's boundary
// is the uniform mesh's, edge for edge).
using CoordEdge = std::tuple<double, double, double, double, int>;
inline std::vector<CoordEdge> boundary_coords(const Mesh& m) {
    std::vector<CoordEdge> e;
    for (std::size_t k = 0; k < m.boundary.size(); ++k) {
        const Vec2 a = m.vertices[static_cast<std::size_t>(m.boundary[k][0])];
        const Vec2 b = m.vertices[static_cast<std::size_t>(m.boundary[k][1])];
        e.emplace_back(a.x, a.y, b.x, b.y, m.boundary_tag[k]);
    }
    std::sort(e.begin(), e.end());
    return e;
}

}  // namespace warpmesh::testing
