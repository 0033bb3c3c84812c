// tet_checks.cpp — tet_mesh.hpp's invariants, checked from scratch
// (check_tet_mesh, tet_checks.hpp), by sorting every face of every tetrahedron:
// nothing is taken from the mesher.  And the boundary's non-manifold edges
// and vertices (nonmanifold_boundary), from the boundary list alone.
//
// The link of a boundary vertex v: for each boundary triangle (v, a, b), in
// the triangle's own (outward) order, the directed edge a → b.  The
// triangles around v form one disc iff the link is one directed cycle
// through distinct vertices; the edge v w lies in as many boundary triangles
// as there are link edges at v starting or ending at w.
#include <algorithm>
#include <span>

#include "warpmesh/post/tet_checks.hpp"

namespace warpmesh {
namespace {

struct Face {
    std::array<std::int32_t, 3> sorted;
    std::array<std::int32_t, 3> oriented;  // as seen from outside its tetrahedron (or the listed boundary face)
    std::int64_t owner;                    // tetrahedron, or −1 − k for boundary face k
};

void note(TetMeshCheck& c, const std::string& what) {
    c.ok = false;
    if (c.problems.size() < 8) c.problems.push_back(what);
}

// Same cyclic order: b is a rotation of a.
bool same_orientation(const std::array<std::int32_t, 3>& a, const std::array<std::int32_t, 3>& b) {
    for (int k = 0; k < 3; ++k)
        if (a[0] == b[static_cast<std::size_t>(k)] && a[1] == b[static_cast<std::size_t>((k + 1) % 3)] && a[2] == b[static_cast<std::size_t>((k + 2) % 3)]) return true;
    return false;
}

using Link = std::array<std::int32_t, 2>;  // a → b

// Whether a link is one cycle through distinct vertices: every link vertex
// the tail of one edge, and from the first edge the edges lead back to its
// tail after using all of them.
bool one_cycle(std::span<const Link> link) {
    for (const Link& e : link)
        if (std::count_if(link.begin(), link.end(), [&](const Link& o) { return o[0] == e[0]; }) != 1) return false;
    std::size_t used = 1;
    for (std::int32_t at = link[0][1]; at != link[0][0]; ++used) {
        const auto next = std::find_if(link.begin(), link.end(), [at](const Link& o) { return o[0] == at; });
        if (next == link.end() || used == link.size()) return false;
        at = (*next)[1];
    }
    return used == link.size();
}

// Classify boundary vertex v from its link: a disc, or a non-manifold vertex
// with its non-manifold edges v w (counted at the lower vertex, each w once).
// At a disc every w is on two link edges: its edge v w is in two triangles.
void classify(std::int32_t v, std::span<const Link> link, NonmanifoldBoundary& out) {
    if (one_cycle(link)) return;
    ++out.vertices;
    const auto end = [&](std::size_t i) { return link[i / 2][i % 2]; };  // the link's vertices, with repeats
    for (std::size_t i = 0; i < 2 * link.size(); ++i) {
        const std::int32_t w = end(i);
        bool first = v < w;
        for (std::size_t j = 0; j < i; ++j) first = first && end(j) != w;
        if (!first) continue;
        int triangles = 0;
        for (const Link& e : link) triangles += (e[0] == w) + (e[1] == w);
        out.edges += triangles > 2;
    }
}

}  // namespace

NonmanifoldBoundary nonmanifold_boundary(const TetMesh& m) {
    // The links, bucketed by vertex (a counting sort: start[v] .. start[v + 1]).
    // Faces with a vertex out of range are check_tet_mesh's problem, skipped here.
    const std::size_t V = m.vertices.size();
    const auto in_range = [V](const std::array<std::int32_t, 3>& b) {
        return std::all_of(b.begin(), b.end(), [V](std::int32_t v) { return v >= 0 && static_cast<std::size_t>(v) < V; });
    };
    std::vector<std::int64_t> start(V + 1, 0);
    for (const auto& b : m.boundary)
        if (in_range(b))
            for (std::int32_t v : b) ++start[static_cast<std::size_t>(v) + 1];
    for (std::size_t v = 0; v < V; ++v) start[v + 1] += start[v];
    std::vector<Link> link(static_cast<std::size_t>(start[V]));
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (const auto& b : m.boundary)
        if (in_range(b))
            for (std::size_t k = 0; k < 3; ++k) link[static_cast<std::size_t>(fill[static_cast<std::size_t>(b[k])]++)] = {b[(k + 1) % 3], b[(k + 2) % 3]};
    NonmanifoldBoundary out;
    for (std::size_t v = 0; v < V; ++v)
        if (start[v + 1] > start[v])
            classify(static_cast<std::int32_t>(v), std::span<const Link>(link).subspan(static_cast<std::size_t>(start[v]), static_cast<std::size_t>(start[v + 1] - start[v])), out);
    return out;
}

// The interfaces listed against the faces between two regions (`between`:
// the two tetrahedra's entries in `faces`): each listed once, oriented out
// of its first region's tetrahedron, the other tetrahedron of its second.
void check_interfaces(const TetMesh& m, const std::vector<Face>& faces, const std::vector<std::array<std::size_t, 2>>& between, TetMeshCheck& c) {
    if (m.interface_regions.size() != m.interfaces.size()) note(c, "interfaces and interface_regions differ in length");
    std::vector<std::pair<std::array<std::int32_t, 3>, std::size_t>> listed;
    for (std::size_t k = 0; k < m.interfaces.size(); ++k) {
        std::array<std::int32_t, 3> s = m.interfaces[k];
        std::sort(s.begin(), s.end());
        listed.emplace_back(s, k);
    }
    std::sort(listed.begin(), listed.end());
    if (listed.size() != between.size())
        ++c.interface_mismatch, note(c, std::to_string(listed.size()) + " interface faces listed, " + std::to_string(between.size()) +
                                            " faces between two regions");
    for (const auto& [e0, e1] : between) {
        const auto it = std::lower_bound(listed.begin(), listed.end(), std::make_pair(faces[e0].sorted, std::size_t{0}));
        if (it == listed.end() || it->first != faces[e0].sorted) {
            ++c.interface_mismatch, note(c, "a face between two regions is not listed as an interface");
            continue;
        }
        const std::size_t k = it->second;
        if (k >= m.interface_regions.size()) continue;
        const std::int32_t r0 = m.region[static_cast<std::size_t>(faces[e0].owner)], r1 = m.region[static_cast<std::size_t>(faces[e1].owner)];
        const auto& want = m.interface_regions[k];
        const Face& first = r0 == want[0] ? faces[e0] : faces[e1];
        const bool regions_ok = (r0 == want[0] && r1 == want[1]) || (r1 == want[0] && r0 == want[1]);
        if (!regions_ok || !same_orientation(first.oriented, m.interfaces[k]))
            ++c.interface_mismatch, note(c, "interface face " + std::to_string(k) + " has the wrong regions or orientation");
    }
}

TetMeshCheck check_tet_mesh(const TetMesh& m) {
    TetMeshCheck c;
    const std::int64_t V = static_cast<std::int64_t>(m.vertices.size());
    std::vector<std::uint8_t> used(static_cast<std::size_t>(V), 0);
    std::vector<Face> faces;
    faces.reserve(m.tets.size() * 4 + m.boundary.size());
    constexpr std::array<std::array<int, 3>, 4> outward{{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
    for (std::size_t t = 0; t < m.tets.size(); ++t) {
        const auto& tet = m.tets[t];
        bool in_range = true;
        for (std::int32_t v : tet) in_range = in_range && v >= 0 && v < V;
        if (!in_range) {
            note(c, "tetrahedron " + std::to_string(t) + " has a vertex out of range");
            continue;
        }
        for (std::int32_t v : tet) used[static_cast<std::size_t>(v)] = 1;
        const Point3 &p0 = m.vertices[static_cast<std::size_t>(tet[0])], &p1 = m.vertices[static_cast<std::size_t>(tet[1])],
                     &p2 = m.vertices[static_cast<std::size_t>(tet[2])], &p3 = m.vertices[static_cast<std::size_t>(tet[3])];
        const double ax = p1.x - p0.x, ay = p1.y - p0.y, az = p1.z - p0.z, bx = p2.x - p0.x, by = p2.y - p0.y, bz = p2.z - p0.z,
                     cx = p3.x - p0.x, cy = p3.y - p0.y, cz = p3.z - p0.z;
        const double det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
        if (!(det > 0)) ++c.inverted, note(c, "tetrahedron " + std::to_string(t) + " is not positively oriented (det " + std::to_string(det) + ")");
        for (const auto& f : outward) {
            const std::array<std::int32_t, 3> o{tet[static_cast<std::size_t>(f[0])], tet[static_cast<std::size_t>(f[1])], tet[static_cast<std::size_t>(f[2])]};
            std::array<std::int32_t, 3> s = o;
            std::sort(s.begin(), s.end());
            faces.push_back({s, o, static_cast<std::int64_t>(t)});
        }
    }
    if (m.boundary_tag.size() != m.boundary.size()) note(c, "boundary_tag and boundary differ in length");
    for (std::size_t k = 0; k < m.boundary.size(); ++k) {
        std::array<std::int32_t, 3> s = m.boundary[k];
        std::sort(s.begin(), s.end());
        faces.push_back({s, m.boundary[k], -1 - static_cast<std::int64_t>(k)});
        if (k < m.boundary_tag.size() && m.boundary_tag[k] != boundary_level_set && m.boundary_tag[k] != boundary_domain)
            note(c, "boundary face " + std::to_string(k) + " has an unknown tag");
    }
    std::sort(faces.begin(), faces.end(), [](const Face& a, const Face& b) {
        for (std::size_t k = 0; k < 3; ++k)
            if (a.sorted[k] != b.sorted[k]) return a.sorted[k] < b.sorted[k];
        return a.owner < b.owner;
    });
    // The faces between two regions: (sorted, the two tetrahedra's entries).
    std::vector<std::array<std::size_t, 2>> between;
    const bool regions = m.region.size() == m.tets.size();
    for (std::size_t i = 0; i < faces.size();) {
        std::size_t j = i;
        int tets = 0, listed = 0;
        while (j < faces.size() && faces[j].sorted == faces[i].sorted) (faces[j].owner >= 0 ? tets : listed)++, ++j;
        const auto name = [&] {  // only when a problem is noted
            return "face (" + std::to_string(faces[i].sorted[0]) + ", " + std::to_string(faces[i].sorted[1]) + ", " +
                   std::to_string(faces[i].sorted[2]) + ")";
        };
        if (tets > 2) ++c.nonmanifold_faces, note(c, name() + " is in " + std::to_string(tets) + " tetrahedra");
        else if (tets == 2 && !same_orientation(faces[j - 1].oriented, {faces[j - 2].oriented[0], faces[j - 2].oriented[2], faces[j - 2].oriented[1]}))
            ++c.nonmanifold_faces, note(c, name() + ": its two tetrahedra lie on the same side");
        else if (tets == 2 && listed > 0) ++c.boundary_mismatch, note(c, name() + " is listed as boundary but shared by two tetrahedra");
        else if (tets == 1 && listed != 1) ++c.boundary_mismatch, note(c, name() + " has one tetrahedron but is listed " + std::to_string(listed) + " times as boundary");
        else if (tets == 1 && !same_orientation(faces[i].oriented, faces[i + 1].oriented))  // listed (owner < 0) sorts first
            ++c.boundary_mismatch, note(c, name() + " is not oriented outward");
        else if (tets == 0) ++c.boundary_mismatch, note(c, name() + " is listed as boundary but in no tetrahedron");
        if (tets == 2 && regions &&
            m.region[static_cast<std::size_t>(faces[j - 1].owner)] != m.region[static_cast<std::size_t>(faces[j - 2].owner)])
            between.push_back({j - 2, j - 1});
        i = j;
    }
    check_interfaces(m, faces, between, c);
    for (std::int64_t v = 0; v < V; ++v)
        if (!used[static_cast<std::size_t>(v)]) ++c.unused_vertices, note(c, "vertex " + std::to_string(v) + " is in no tetrahedron");
    if (!regions) note(c, "region and tets differ in length");
    const NonmanifoldBoundary nb = nonmanifold_boundary(m);
    c.nonmanifold_boundary_edges = nb.edges, c.nonmanifold_boundary_vertices = nb.vertices;
    return c;
}

}  // namespace warpmesh
