// fixture_meshes.hpp — small hand-built meshes for the writer tests
// (tests/test_writers.cpp) and for the real-client round trips
// (tests/tools/write_fixture_meshes.cpp → tests/python/).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "warpmesh/core/mesh.hpp"
#include "warpmesh/core/tet_mesh.hpp"

namespace warpmesh::testing {

// nx x ny squares with awkward coordinates (non-representable spacing, an
// offset with all 17 digits), each split into two CCW triangles; the left
// half is region 3, the right half region 8; the outer boundary is tagged 1
// on bottom/top and 2 on left/right; two cell-data arrays.
inline Mesh grid_mesh(int nx = 5, int ny = 3) {
    Mesh m;
    const double x0 = -1.2345678901234567, y0 = 1e-7 / 3, s = 1.0 / 3;
    auto id = [&](int i, int j) { return static_cast<std::int32_t>(i + j * (nx + 1)); };
    for (int j = 0; j <= ny; ++j)
        for (int i = 0; i <= nx; ++i) m.vertices.push_back({x0 + i * s, y0 + j * s * 1.1});
    std::vector<double> a, b;
    for (int j = 0; j < ny; ++j)
        for (int i = 0; i < nx; ++i) {
            const auto p = id(i, j), q = id(i + 1, j), r = id(i, j + 1), t = id(i + 1, j + 1);
            const std::int32_t region = 2 * i < nx ? 3 : 8;
            m.triangles.push_back({p, q, t});
            m.triangles.push_back({p, t, r});
            m.region.push_back(region);
            m.region.push_back(region);
        }
    for (std::size_t k = 0; k < m.triangles.size(); ++k) {
        a.push_back(static_cast<double>(k) / 7 + 1e-300);
        b.push_back(-std::sqrt(2.0) * static_cast<double>(k) * 1e20);
    }
    m.cell_data = {{"certified_min_angle", Buffer<double>(a.begin(), a.end())}, {"weird <name> & \"q\"", Buffer<double>(b.begin(), b.end())}};
    for (int i = 0; i < nx; ++i) m.boundary.push_back({id(i, 0), id(i + 1, 0)}), m.boundary_tag.push_back(1);
    for (int j = 0; j < ny; ++j) m.boundary.push_back({id(nx, j), id(nx, j + 1)}), m.boundary_tag.push_back(2);
    for (int i = nx; i > 0; --i) m.boundary.push_back({id(i, ny), id(i - 1, ny)}), m.boundary_tag.push_back(1);
    for (int j = ny; j > 0; --j) m.boundary.push_back({id(0, j), id(0, j - 1)}), m.boundary_tag.push_back(2);
    return m;
}

// grid_mesh with interfaces: the vertical edges between its region 3 (left)
// and region 8 (right) columns, oriented alternately so that the writers must
// reorient some; region 3 is named, region 8 is not.
inline Mesh two_region_mesh(int nx = 4, int ny = 3) {
    Mesh m = grid_mesh(nx, ny);
    const int mid = (nx + 1) / 2;  // first column of region 8
    auto id = [&](int i, int j) { return static_cast<std::int32_t>(i + j * (nx + 1)); };
    for (int j = 0; j < ny; ++j) {
        // Upwards, region 3 (smaller x) is on the left; downwards region 8.
        if (j % 2 == 0) m.interfaces.push_back({id(mid, j), id(mid, j + 1)}), m.interface_regions.push_back({3, 8});
        else m.interfaces.push_back({id(mid, j + 1), id(mid, j)}), m.interface_regions.push_back({8, 3});
    }
    m.region_names = {{3, "left material"}};
    return m;
}

// nx x ny x nz cubes with awkward coordinates, each split into the 6 Kuhn
// tetrahedra around its main diagonal, every one positively oriented; cubes
// with 2i < nx are region 3 ("left material"), the others region 8
// (unnamed).  Boundary triangles are found as the faces of one tetrahedron,
// oriented outwards, tagged 1 on the z = const sides and 2 elsewhere; the
// faces between the regions are interfaces, oriented alternately out of
// region 3 and out of region 8 (so that the writers must reorient some); one
// cell-data array.
inline TetMesh cube_tet_mesh(int nx = 4, int ny = 2, int nz = 3) {
    TetMesh m;
    const double x0 = -1.2345678901234567, y0 = 1e-7 / 3, z0 = 2.0 / 7, s = 1.0 / 3;
    auto id = [&](int i, int j, int k) { return static_cast<std::int32_t>(i + (nx + 1) * (j + (ny + 1) * k)); };
    for (int k = 0; k <= nz; ++k)
        for (int j = 0; j <= ny; ++j)
            for (int i = 0; i <= nx; ++i) m.vertices.push_back({x0 + i * s, y0 + j * s * 1.1, z0 + k * s * 0.9});
    constexpr int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (int k = 0; k < nz; ++k)
        for (int j = 0; j < ny; ++j)
            for (int i = 0; i < nx; ++i)
                for (const auto& p : perms) {
                    int c[3] = {i, j, k};
                    std::array<std::int32_t, 4> t{};
                    t[0] = id(c[0], c[1], c[2]);
                    for (int a = 0; a < 3; ++a) ++c[p[a]], t[static_cast<std::size_t>(a + 1)] = id(c[0], c[1], c[2]);
                    // The path's tetrahedron has the permutation's sign: an
                    // odd permutation is made positive by swapping two vertices.
                    if (((p[0] > p[1]) + (p[0] > p[2]) + (p[1] > p[2])) % 2) std::swap(t[2], t[3]);
                    m.tets.push_back(t);
                    m.region.push_back(2 * i < nx ? 3 : 8);
                }
    // Faces oriented out of their tetrahedron (normal away from the opposite
    // vertex), keyed by their sorted vertices.
    constexpr int face[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    std::map<std::array<std::int32_t, 3>, std::vector<std::pair<std::array<std::int32_t, 3>, std::int32_t>>> faces;
    for (std::size_t t = 0; t < m.tets.size(); ++t)
        for (const auto& f : face) {
            const std::array<std::int32_t, 3> tri{m.tets[t][static_cast<std::size_t>(f[0])], m.tets[t][static_cast<std::size_t>(f[1])],
                                                  m.tets[t][static_cast<std::size_t>(f[2])]};
            auto key = tri;
            std::sort(key.begin(), key.end());
            faces[key].push_back({tri, m.region[t]});
        }
    auto z_of = [&](std::int32_t v) { return m.vertices[static_cast<std::size_t>(v)].z; };
    std::vector<double> q;
    std::size_t interface_count = 0;
    for (const auto& [key, sides] : faces) {
        if (sides.size() == 1) {
            const auto& tri = sides[0].first;
            m.boundary.push_back(tri);
            m.boundary_tag.push_back(z_of(tri[0]) == z_of(tri[1]) && z_of(tri[1]) == z_of(tri[2]) ? 1 : 2);
        } else if (sides[0].second != sides[1].second) {
            const auto& side = sides[interface_count++ % 2];
            m.interfaces.push_back(side.first);
            m.interface_regions.push_back({side.second, side.second == 3 ? 8 : 3});
        }
    }
    for (std::size_t t = 0; t < m.tets.size(); ++t) q.push_back(static_cast<double>(t) / 7 + 1e-300);
    m.cell_data = {{"min_dihedral", Buffer<double>(q.begin(), q.end())}};
    m.region_names = {{3, "left material"}};
    return m;
}

}  // namespace warpmesh::testing
