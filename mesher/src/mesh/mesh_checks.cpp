// mesh_checks.cpp — conformity, orientation and boundary checks on a finished mesh.
//
// Every directed triangle edge (a, b) is recorded.  In a conforming,
// consistently oriented triangulation an interior edge appears exactly twice,
// once as (a, b) and once as (b, a); a boundary edge appears once, and the
// boundary edges form closed loops (every vertex has as many boundary edges
// leaving as entering).
#include <array>
#include <iterator>
#include <algorithm>
#include <cstdint>
#include <string>

#include "warpmesh/mesh_checks.hpp"

namespace warpmesh {

double cross2(const Mesh& mesh, std::size_t t) {
    const auto& tri = mesh.triangles[t];
    const Vec2 &a = mesh.vertices[static_cast<std::size_t>(tri[0])], &b = mesh.vertices[static_cast<std::size_t>(tri[1])],
               &c = mesh.vertices[static_cast<std::size_t>(tri[2])];
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

MeshCheck check_mesh(const Mesh& mesh) {
    MeshCheck r;
    auto note = [&r](std::string m) {
        if (r.messages.size() < 10) r.messages.push_back(std::move(m));
    };
    const std::int64_t nv = static_cast<std::int64_t>(mesh.vertices.size());
    std::vector<char> used(mesh.vertices.size(), 0);
    struct Directed {
        std::int32_t lo, hi;
        bool forward;  // traversed lo → hi
        std::int32_t triangle;
        bool operator<(const Directed& o) const { return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : forward < o.forward; }
    };
    std::vector<Directed> edges;
    edges.reserve(mesh.triangles.size() * 3);
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto& tri = mesh.triangles[t];
        bool valid = true;
        for (int k = 0; k < 3; ++k)
            if (tri[k] < 0 || tri[k] >= nv) valid = false;
        if (!valid) {
            ++r.bad_indices;
            note("triangle " + std::to_string(t) + " has an out-of-range vertex index");
            continue;
        }
        for (int k = 0; k < 3; ++k) {
            used[static_cast<std::size_t>(tri[k])] = 1;
            const std::int32_t a = tri[k], b = tri[(k + 1) % 3];
            edges.push_back({std::min(a, b), std::max(a, b), a < b, static_cast<std::int32_t>(t)});
        }
        if (!(cross2(mesh, t) > 0)) {
            ++r.non_ccw;
            note("triangle " + std::to_string(t) + " is not counter-clockwise (cross = " +
                 std::to_string(cross2(mesh, t)) + ")");
        }
    }
    for (std::size_t v = 0; v < used.size(); ++v)
        if (!used[v]) ++r.unused_vertices;
    if (r.unused_vertices) note(std::to_string(r.unused_vertices) + " vertices are in no triangle");

    std::sort(edges.begin(), edges.end());
    std::vector<Directed> once;
    // Interior edges between triangles of different regions: (lo, hi, region
    // of the triangle traversing lo → hi, region of the other).
    std::vector<std::array<std::int32_t, 4>> between;
    const bool regions_ok = mesh.region.size() == mesh.triangles.size();
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i;
        while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
        const std::size_t n = j - i;
        if (n == 1) {
            once.push_back(edges[i]);
        } else if (n == 2) {
            ++r.interior_edges;
            if (edges[i].forward == edges[i + 1].forward) {
                ++r.misoriented_edges;
                note("edge " + std::to_string(edges[i].lo) + "-" + std::to_string(edges[i].hi) +
                     " is traversed the same way by both of its triangles");
            } else if (regions_ok) {
                const Directed& f = edges[i].forward ? edges[i] : edges[i + 1];
                const Directed& b = edges[i].forward ? edges[i + 1] : edges[i];
                const std::int32_t rf = mesh.region[static_cast<std::size_t>(f.triangle)], rb = mesh.region[static_cast<std::size_t>(b.triangle)];
                if (rf != rb) between.push_back({f.lo, f.hi, rf, rb});
            }
        } else {
            ++r.overfull_edges;
            note("edge " + std::to_string(edges[i].lo) + "-" + std::to_string(edges[i].hi) + " is in " +
                 std::to_string(n) + " triangles");
        }
        i = j;
    }
    r.boundary_edges = static_cast<std::int64_t>(once.size());

    // The boundary list must be exactly the once-used edges, with their direction.
    std::vector<Directed> listed;
    listed.reserve(mesh.boundary.size());
    for (const auto& e : mesh.boundary) {
        if (e[0] < 0 || e[0] >= nv || e[1] < 0 || e[1] >= nv) {
            ++r.boundary_mismatch;
            continue;
        }
        listed.push_back({std::min(e[0], e[1]), std::max(e[0], e[1]), e[0] < e[1], -1});
    }
    std::sort(listed.begin(), listed.end());
    std::vector<Directed> diff;
    auto same = [](const Directed& a, const Directed& b) { return !(a < b) && !(b < a); };
    std::set_symmetric_difference(once.begin(), once.end(), listed.begin(), listed.end(), std::back_inserter(diff));
    r.boundary_mismatch += static_cast<std::int64_t>(diff.size());
    if (std::adjacent_find(listed.begin(), listed.end(), same) != listed.end()) ++r.boundary_mismatch;
    if (r.boundary_mismatch)
        note(std::to_string(r.boundary_mismatch) + " boundary edges differ from the edges in exactly one triangle");
    if (mesh.boundary_tag.size() != mesh.boundary.size()) {
        ++r.boundary_mismatch;
        note("boundary_tag has a different length from boundary");
    }

    // Interfaces (multi-material meshes, when listed): exactly the interior
    // edges between different regions, each once, its left region on its left.
    if (!mesh.interfaces.empty() || !mesh.interface_regions.empty()) {
        if (mesh.interface_regions.size() != mesh.interfaces.size()) {
            ++r.interface_mismatch;
            note("interface_regions has a different length from interfaces");
        } else {
            std::vector<std::array<std::int32_t, 4>> listed_if;
            for (std::size_t k = 0; k < mesh.interfaces.size(); ++k) {
                const auto& e = mesh.interfaces[k];
                const auto& lr = mesh.interface_regions[k];
                if (e[0] < e[1]) listed_if.push_back({e[0], e[1], lr[0], lr[1]});
                else listed_if.push_back({e[1], e[0], lr[1], lr[0]});
            }
            std::sort(listed_if.begin(), listed_if.end());
            std::sort(between.begin(), between.end());
            std::vector<std::array<std::int32_t, 4>> d;
            std::set_symmetric_difference(between.begin(), between.end(), listed_if.begin(), listed_if.end(), std::back_inserter(d));
            r.interface_mismatch += static_cast<std::int64_t>(d.size());
            if (std::adjacent_find(listed_if.begin(), listed_if.end()) != listed_if.end()) ++r.interface_mismatch;
            if (r.interface_mismatch)
                note(std::to_string(r.interface_mismatch) +
                     " interface edges differ from the interior edges between triangles of different regions");
        }
        r.interface_edges = static_cast<std::int64_t>(mesh.interfaces.size());
    }

    std::vector<std::int32_t> degree(mesh.vertices.size(), 0);
    for (const Directed& e : once) {
        const std::int32_t from = e.forward ? e.lo : e.hi, to = e.forward ? e.hi : e.lo;
        ++degree[static_cast<std::size_t>(from)];
        --degree[static_cast<std::size_t>(to)];
    }
    for (std::int32_t d : degree)
        if (d != 0) ++r.open_loop_vertices;
    if (r.open_loop_vertices) note(std::to_string(r.open_loop_vertices) + " vertices where a boundary loop is open");
    return r;
}

}  // namespace warpmesh
