// mesh_checks.cpp — conformity, orientation and boundary checks on a finished mesh.
//
// Every directed triangle edge (a, b) is recorded.  In a conforming,
// consistently oriented triangulation an interior edge appears exactly twice,
// once as (a, b) and once as (b, a); a boundary edge appears once, and the
// boundary edges form closed loops (every vertex has as many boundary edges
// leaving as entering).  Then the embedding: angle sums at the vertices,
// boundary edges that meet, boundary vertices inside other triangles.
#include <array>
#include <iterator>
#include <algorithm>
#include <cstdint>
#include <cmath>
#include <numbers>
#include <string>

#include "warpmesh/post/mesh_checks.hpp"
#include "embedding.hpp"

namespace warpmesh {

double cross2(const Mesh& mesh, std::size_t t) {
    const auto& tri = mesh.triangles[t];
    const Vec2 &a = mesh.vertices[static_cast<std::size_t>(tri[0])], &b = mesh.vertices[static_cast<std::size_t>(tri[1])],
               &c = mesh.vertices[static_cast<std::size_t>(tri[2])];
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

namespace {

struct Directed {
    std::int32_t lo, hi;
    bool forward;  // traversed lo → hi
    std::int32_t triangle;
    bool operator<(const Directed& o) const { return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : forward < o.forward; }
};

struct Checker {
    const Mesh& mesh;
    MeshCheck r;
    std::vector<Directed> edges, once;
    // Interior edges between triangles of different regions: (lo, hi, region
    // of the triangle traversing lo → hi, region of the other).
    std::vector<std::array<std::int32_t, 4>> between;

    void note(std::string m) {
        if (r.messages.size() < 10) r.messages.push_back(std::move(m));
    }
    std::int64_t nv() const { return static_cast<std::int64_t>(mesh.vertices.size()); }

    // Indices, orientation, unused vertices; every directed edge.
    void triangles() {
        std::vector<char> used(mesh.vertices.size(), 0);
        edges.reserve(mesh.triangles.size() * 3);
        for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
            const auto& tri = mesh.triangles[t];
            if (std::any_of(tri.begin(), tri.end(), [&](std::int32_t v) { return v < 0 || v >= nv(); })) {
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
                note("triangle " + std::to_string(t) + " is not counter-clockwise (cross = " + std::to_string(cross2(mesh, t)) + ")");
            }
        }
        r.unused_vertices = std::count(used.begin(), used.end(), 0);
        if (r.unused_vertices) note(std::to_string(r.unused_vertices) + " vertices are in no triangle");
    }

    // Edge manifoldness and orientation: each edge in one or two triangles,
    // traversed both ways when in two.
    void manifold() {
        std::sort(edges.begin(), edges.end());
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
                note("edge " + std::to_string(edges[i].lo) + "-" + std::to_string(edges[i].hi) + " is in " + std::to_string(n) + " triangles");
            }
            i = j;
        }
        r.boundary_edges = static_cast<std::int64_t>(once.size());
    }

    // The boundary list must be exactly the once-used edges, with their
    // direction; the loops closed.
    void boundary() {
        std::vector<Directed> listed;
        listed.reserve(mesh.boundary.size());
        for (const auto& e : mesh.boundary) {
            if (e[0] < 0 || e[0] >= nv() || e[1] < 0 || e[1] >= nv()) {
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
        if (r.boundary_mismatch) note(std::to_string(r.boundary_mismatch) + " boundary edges differ from the edges in exactly one triangle");
        if (mesh.boundary_tag.size() != mesh.boundary.size()) {
            ++r.boundary_mismatch;
            note("boundary_tag has a different length from boundary");
        }
        std::vector<std::int32_t> degree(mesh.vertices.size(), 0);
        for (const Directed& e : once) {
            ++degree[static_cast<std::size_t>(e.forward ? e.lo : e.hi)];
            --degree[static_cast<std::size_t>(e.forward ? e.hi : e.lo)];
        }
        r.open_loop_vertices = std::count_if(degree.begin(), degree.end(), [](std::int32_t d) { return d != 0; });
        if (r.open_loop_vertices) note(std::to_string(r.open_loop_vertices) + " vertices where a boundary loop is open");
    }

    // Interfaces (multi-material meshes, when listed): exactly the interior
    // edges between different regions, each once, its left region on its left.
    void interfaces() {
        if (mesh.interfaces.empty() && mesh.interface_regions.empty()) return;
        r.interface_edges = static_cast<std::int64_t>(mesh.interfaces.size());
        if (mesh.interface_regions.size() != mesh.interfaces.size()) {
            ++r.interface_mismatch;
            note("interface_regions has a different length from interfaces");
            return;
        }
        std::vector<std::array<std::int32_t, 4>> listed;
        for (std::size_t k = 0; k < mesh.interfaces.size(); ++k) {
            const auto& e = mesh.interfaces[k];
            const auto& lr = mesh.interface_regions[k];
            if (e[0] < e[1]) listed.push_back({e[0], e[1], lr[0], lr[1]});
            else listed.push_back({e[1], e[0], lr[1], lr[0]});
        }
        std::sort(listed.begin(), listed.end());
        std::sort(between.begin(), between.end());
        std::vector<std::array<std::int32_t, 4>> d;
        std::set_symmetric_difference(between.begin(), between.end(), listed.begin(), listed.end(), std::back_inserter(d));
        r.interface_mismatch += static_cast<std::int64_t>(d.size());
        if (std::adjacent_find(listed.begin(), listed.end()) != listed.end()) ++r.interface_mismatch;
        if (r.interface_mismatch)
            note(std::to_string(r.interface_mismatch) + " interface edges differ from the interior edges between triangles of different regions");
    }

    // The embedding (embedding.hpp), on a mesh that passed the checks above:
    // the angles at each vertex sum to 360° if it has no boundary edge and to
    // at most 360° otherwise (so the mesh is locally one sheet); no two
    // boundary edges meet except at a shared endpoint; no boundary vertex lies
    // in a triangle near it that does not have it.  With the triangles
    // counter-clockwise, these make the mesh cover each point at most once.
    void embedding();
};

void Checker::embedding() {
    if (!r.ok() || mesh.boundary.empty()) return;
    std::vector<double> angle_sum(mesh.vertices.size(), 0.0);
    std::vector<char> on_boundary(mesh.vertices.size(), 0);
    double length = 0;
    for (const auto& e : mesh.boundary) {
        on_boundary[static_cast<std::size_t>(e[0])] = on_boundary[static_cast<std::size_t>(e[1])] = 1;
        const Vec2 d = plane::operator-(mesh.vertices[static_cast<std::size_t>(e[1])], mesh.vertices[static_cast<std::size_t>(e[0])]);
        length += std::sqrt(plane::norm2(d));
    }
    for (const auto& tri : mesh.triangles)
        for (int k = 0; k < 3; ++k) {
            const Vec2 p = mesh.vertices[static_cast<std::size_t>(tri[k])];
            const Vec2 u = plane::operator-(mesh.vertices[static_cast<std::size_t>(tri[(k + 1) % 3])], p);
            const Vec2 w = plane::operator-(mesh.vertices[static_cast<std::size_t>(tri[(k + 2) % 3])], p);
            angle_sum[static_cast<std::size_t>(tri[k])] += std::atan2(std::abs(plane::cross(u, w)), plane::dot(u, w));
        }
    constexpr double full = 2 * std::numbers::pi, tol = 1e-9;
    for (std::size_t v = 0; v < angle_sum.size(); ++v)
        if (on_boundary[v] ? angle_sum[v] > full + tol : std::abs(angle_sum[v] - full) > tol) {
            ++r.overlaps;
            note("the angles at vertex " + std::to_string(v) + " sum to " + std::to_string(angle_sum[v] * plane::deg_per_rad) +
                 " deg: the mesh folds there");
        }
    const BoundaryIndex index(mesh, length / static_cast<double>(mesh.boundary.size()));
    for (std::size_t e = 0; e < mesh.boundary.size(); ++e) {
        const std::int32_t a = mesh.boundary[e][0], b = mesh.boundary[e][1];  // not a structured binding: clang 14 cannot capture one
        const Vec2 pa = mesh.vertices[static_cast<std::size_t>(a)], pb = mesh.vertices[static_cast<std::size_t>(b)];
        index.near({std::min(pa.x, pb.x), std::min(pa.y, pb.y)}, {std::max(pa.x, pb.x), std::max(pa.y, pb.y)}, [&](std::size_t o) {
            const auto [c, d] = mesh.boundary[o];
            if (o > e && edges_conflict(a, b, pa, pb, c, d, mesh.vertices[static_cast<std::size_t>(c)], mesh.vertices[static_cast<std::size_t>(d)])) {
                ++r.crossing_boundary_edges;
                note("boundary edges " + std::to_string(a) + "-" + std::to_string(b) + " and " + std::to_string(c) + "-" + std::to_string(d) + " meet");
            }
        });
    }
    for (const auto& tri : mesh.triangles) {
        const Vec2 a = mesh.vertices[static_cast<std::size_t>(tri[0])], b = mesh.vertices[static_cast<std::size_t>(tri[1])],
                   c = mesh.vertices[static_cast<std::size_t>(tri[2])];
        index.near({std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y})}, {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y})}, [&](std::size_t e) {
            for (const std::int32_t v : mesh.boundary[e])
                if (v != tri[0] && v != tri[1] && v != tri[2] && in_triangle(a, b, c, mesh.vertices[static_cast<std::size_t>(v)])) {
                    ++r.overlaps;
                    note("boundary vertex " + std::to_string(v) + " lies in a triangle that does not have it");
                }
        });
    }
}

}  // namespace

MeshCheck check_mesh(const Mesh& mesh) {
    Checker c{mesh, {}, {}, {}, {}};
    c.triangles();
    c.manifold();
    c.boundary();
    c.interfaces();
    c.embedding();
    return std::move(c.r);
}

}  // namespace warpmesh
