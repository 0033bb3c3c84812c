// fixture_meshes.hpp — small hand-built meshes for the writer tests
// (tests/test_writers.cpp) and for the real-client round trips
// (tests/tools/write_fixture_meshes.cpp → tests/python/).
#pragma once

#include <cmath>
#include <vector>

#include "warpmesh/mesh.hpp"

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

}  // namespace warpmesh::testing
