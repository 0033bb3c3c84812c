// region_measures.cpp — the per-material figures of a mesh changed after
// meshing (materials.hpp: measure_regions, update_material_stats).
#include <cmath>
#include <type_traits>
#include <unordered_map>

#include "warpmesh/mesh2d/materials.hpp"

namespace warpmesh {

namespace {

double length(const Mesh& m, std::int32_t a, std::int32_t b) {
    const Vec2 p = m.vertices[static_cast<std::size_t>(a)], q = m.vertices[static_cast<std::size_t>(b)];
    return std::hypot(q.x - p.x, q.y - p.y);
}

}  // namespace

RegionMeasures measure_regions(const Mesh& m) {
    RegionMeasures r;
    const auto grow = [&](std::int32_t tag) {
        const auto k = static_cast<std::size_t>(tag);
        if (k >= r.area.size()) r.triangles.resize(k + 1, 0), r.area.resize(k + 1, 0.0), r.perimeter.resize(k + 1, 0.0);
        return k;
    };
    // The boundary edges by direction (as in their triangle); only triangles
    // with two boundary vertices are looked up.
    std::vector<char> on_boundary(m.vertices.size(), 0);
    std::unordered_map<std::uint64_t, std::size_t> directed;
    const auto key = [](std::int32_t a, std::int32_t b) {
        return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
    };
    for (std::size_t e = 0; e < m.boundary.size(); ++e) {
        const auto [a, b] = m.boundary[e];
        on_boundary[static_cast<std::size_t>(a)] = on_boundary[static_cast<std::size_t>(b)] = 1;
        directed[key(a, b)] = e;
        const std::int32_t tag = e < m.boundary_tag.size() ? m.boundary_tag[e] : 0;
        if (tag == boundary_level_set) r.level_set_length += length(m, a, b);
        if (tag == boundary_domain) r.border_length += length(m, a, b);
    }
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const auto k = grow(m.region[t]);
        const auto& T = m.triangles[t];
        const Vec2 a = m.vertices[static_cast<std::size_t>(T[0])], b = m.vertices[static_cast<std::size_t>(T[1])],
                   c = m.vertices[static_cast<std::size_t>(T[2])];
        ++r.triangles[k];
        r.area[k] += 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
        for (int i = 0; i < 3; ++i) {
            const std::int32_t u = T[static_cast<std::size_t>(i)], v = T[static_cast<std::size_t>((i + 1) % 3)];
            if (on_boundary[static_cast<std::size_t>(u)] && on_boundary[static_cast<std::size_t>(v)] && directed.count(key(u, v)))
                r.perimeter[k] += length(m, u, v);
        }
    }
    for (std::size_t i = 0; i < m.interfaces.size() && i < m.interface_regions.size(); ++i) {
        const double len = length(m, m.interfaces[i][0], m.interfaces[i][1]);
        for (const std::int32_t tag : m.interface_regions[i]) r.perimeter[grow(tag)] += len;
    }
    return r;
}

void update_material_stats(MaterialResult& r, const RegionMeasures& before, const RegionMeasures& after) {
    const auto at = [](const auto& v, std::size_t k) { return k < v.size() ? v[k] : typename std::decay_t<decltype(v)>::value_type{}; };
    double area_change = 0;  // of the output materials
    for (MaterialStats& s : r.materials) {
        if (!s.output || s.tag < 0) continue;
        const auto k = static_cast<std::size_t>(s.tag);
        s.area_before_optimize = s.area;
        s.triangles += at(after.triangles, k) - at(before.triangles, k);
        s.area += at(after.area, k) - at(before.area, k);
        s.perimeter += at(after.perimeter, k) - at(before.perimeter, k);
        area_change += at(after.area, k) - at(before.area, k);
    }
    const double border_change = after.border_length - before.border_length;
    for (MaterialStats& s : r.materials)
        if (!s.output) {
            s.area -= area_change;
            s.perimeter += (after.level_set_length - before.level_set_length) - border_change;
        }
}

}  // namespace warpmesh
