// write_msh.cpp — Gmsh MSH 4.1, ASCII.
//
// Sections, in the order the format requires (Gmsh manual, "MSH file format"):
//
//   $MeshFormat    "4.1 0 8": version 4.1, ASCII (0), sizeof(size_t) = 8.
//   $PhysicalNames numPhysicalNames, then "dim physicalTag \"name\"" lines:
//                  dim 2: one per region tag — "domain" when the mesh has a
//                         single region, "domain_<tag>" otherwise;
//                  dim 1: one per boundary tag — "boundary" (tag 1, level set),
//                         "domain_border" (tag 2, lattice border),
//                         "boundary_<tag>" for any other.
//   $Entities      "numPoints numCurves numSurfaces numVolumes" (0 B R 0), then
//                  per curve:   "tag minX minY minZ maxX maxY maxZ
//                                numPhysicalTags physicalTag numBoundingPoints(0)"
//                  per surface: "tag minX minY minZ maxX maxY maxZ
//                                numPhysicalTags physicalTag numBoundingCurves(0)".
//   $Nodes         "numEntityBlocks numNodes minNodeTag maxNodeTag", then one
//                  block "entityDim entityTag parametric numNodesInBlock" with
//                  all node tags (one per line) followed by all "x y z" lines.
//                  All nodes are classified on the first surface entity: a
//                  node shared by several regions must live in one block, and
//                  readers (Gmsh, meshio) only need the tags.
//   $Elements      "numEntityBlocks numElements minElementTag maxElementTag",
//                  then per surface entity a block "2 entityTag 2 count" of
//                  3-node triangles (type 2) and per curve entity a block
//                  "1 entityTag 1 count" of 2-node lines (type 1):
//                  "elementTag node node [node]".
//   $ElementData   one view per mesh.cell_data array: 1 string tag (the name),
//                  1 real tag (time 0), 3 integer tags (time step 0,
//                  1 component, number of values), then "elementTag value".
//
// Numbering (all 1-based): node tag = vertex index + 1; triangle k has element
// tag k + 1 (so element data follow triangle order whatever the blocks are);
// boundary edge e has element tag T + e + 1.  Entity and physical tags of a
// region (boundary) tag t are t itself when all region (boundary) tags are
// >= 1, else the 1-based rank of t among the distinct tags.
#include <algorithm>
#include <span>
#include <map>
#include <string_view>
#include <vector>

#include "io/atomic_file.hpp"
#include "warpmesh/writers.hpp"

namespace warpmesh {

namespace {

struct Bbox {
    double xmin = 0, ymin = 0, xmax = 0, ymax = 0;
    bool empty = true;
    void add(Vec2 p) {
        if (empty) {
            xmin = xmax = p.x, ymin = ymax = p.y, empty = false;
            return;
        }
        xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
        ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
    }
};

// A group of elements sharing a tag: the future entity and physical group.
struct Group {
    std::int32_t tag;     // region or boundary tag in the mesh
    std::int32_t entity;  // entity tag = physical tag in the file
    std::size_t begin = 0, end = 0;  // members: Grouping::member(begin … end - 1)
    Bbox box;
};

// Element indices grouped by tag, groups in increasing tag order, elements in
// their original order within a group (a counting sort).  With a single group
// (the usual case) no permutation is stored.
struct Grouping {
    std::vector<Group> groups;
    std::vector<std::int32_t> order;  // empty: identity
    std::size_t member(std::size_t i) const { return order.empty() ? i : static_cast<std::size_t>(order[i]); }
};

Grouping group_by_tag(std::span<const std::int32_t> tags) {
    // Count per tag (tags come in long runs, so cache the last map lookup).
    std::map<std::int32_t, std::size_t> count;
    auto last = count.end();
    for (const std::int32_t t : tags) {
        if (last == count.end() || last->first != t) last = count.try_emplace(t, 0).first;
        ++last->second;
    }
    Grouping g;
    const bool all_positive = count.empty() || count.begin()->first >= 1;
    std::map<std::int32_t, std::size_t> slot;  // tag → group index
    std::size_t begin = 0;
    for (const auto& [t, n] : count) {
        slot[t] = g.groups.size();
        g.groups.push_back({t, all_positive ? t : static_cast<std::int32_t>(g.groups.size() + 1), begin, begin + n, {}});
        begin += n;
    }
    if (g.groups.size() > 1) {
        g.order.resize(tags.size());
        std::vector<std::size_t> next(g.groups.size());
        for (std::size_t i = 0; i < next.size(); ++i) next[i] = g.groups[i].begin;
        auto it = slot.end();
        for (std::size_t i = 0; i < tags.size(); ++i) {
            if (it == slot.end() || it->first != tags[i]) it = slot.find(tags[i]);
            g.order[next[it->second]++] = static_cast<std::int32_t>(i);
        }
    }
    return g;
}

std::string quoted(std::string_view s) {
    // MSH strings are double-quoted; a double quote inside cannot be escaped,
    // so it is replaced.
    std::string r = "\"";
    for (const char c : s) r += (c == '"' || c == '\n') ? '\'' : c;
    return r + "\"";
}

std::string boundary_name(std::int32_t tag) {
    if (tag == boundary_level_set) return "boundary";
    if (tag == boundary_domain) return "domain_border";
    return "boundary_" + std::to_string(tag);
}

void put_entity(detail::TextSink& out, const Group& g) {
    out << g.entity << ' ' << g.box.xmin << ' ' << g.box.ymin << " 0 " << g.box.xmax << ' ' << g.box.ymax << " 0 1 "
        << g.entity << " 0\n";
}

}  // namespace

void write_msh(const Mesh& mesh, std::ostream& os) {
    detail::check_mesh_arrays(mesh, "<msh stream>");
    const auto nv = static_cast<std::uint64_t>(mesh.vertices.size());
    const auto nt = static_cast<std::uint64_t>(mesh.triangles.size());
    const auto nb = static_cast<std::uint64_t>(mesh.boundary.size());

    Grouping by_region = group_by_tag(mesh.region), by_tag = group_by_tag(mesh.boundary_tag);
    std::vector<Group>&regions = by_region.groups, &curves = by_tag.groups;
    for (Group& g : regions)
        for (std::size_t i = g.begin; i < g.end; ++i)
            for (const std::int32_t v : mesh.triangles[by_region.member(i)])
                g.box.add(mesh.vertices[static_cast<std::size_t>(v)]);
    for (Group& g : curves)
        for (std::size_t i = g.begin; i < g.end; ++i)
            for (const std::int32_t v : mesh.boundary[by_tag.member(i)]) g.box.add(mesh.vertices[static_cast<std::size_t>(v)]);

    detail::TextSink out(os);
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";

    out << "$PhysicalNames\n" << static_cast<std::uint64_t>(regions.size() + curves.size()) << '\n';
    for (const Group& g : curves) out << "1 " << g.entity << ' ' << quoted(boundary_name(g.tag)) << '\n';
    for (const Group& g : regions)
        out << "2 " << g.entity << ' '
            << quoted(regions.size() == 1 ? std::string("domain") : "domain_" + std::to_string(g.tag)) << '\n';
    out << "$EndPhysicalNames\n";

    out << "$Entities\n0 " << static_cast<std::uint64_t>(curves.size()) << ' '
        << static_cast<std::uint64_t>(regions.size()) << " 0\n";
    for (const Group& g : curves) put_entity(out, g);
    for (const Group& g : regions) put_entity(out, g);
    out << "$EndEntities\n";

    // Nodes: one block on the first surface (a mesh without triangles has no
    // surface and so no nodes block; its vertices are not written).
    const bool have_nodes = !regions.empty() && nv > 0;
    out << "$Nodes\n";
    if (have_nodes) {
        out << "1 " << nv << " 1 " << nv << '\n' << "2 " << regions.front().entity << " 0 " << nv << '\n';
        for (std::uint64_t i = 1; i <= nv; ++i) out << i << '\n';
        for (const Vec2& v : mesh.vertices) out << v.x << ' ' << v.y << " 0\n";
    } else {
        out << "0 0 0 0\n";
    }
    out << "$EndNodes\n";

    const std::uint64_t ne = nt + nb;
    out << "$Elements\n"
        << static_cast<std::uint64_t>(regions.size() + curves.size()) << ' ' << ne << ' ' << (ne ? 1 : 0) << ' ' << ne
        << '\n';
    for (const Group& g : regions) {
        out << "2 " << g.entity << " 2 " << static_cast<std::uint64_t>(g.end - g.begin) << '\n';
        for (std::size_t i = g.begin; i < g.end; ++i) {
            const std::size_t k = by_region.member(i);
            const auto& t = mesh.triangles[k];
            out << static_cast<std::uint64_t>(k + 1) << ' ' << t[0] + std::int64_t{1} << ' ' << t[1] + std::int64_t{1}
                << ' ' << t[2] + std::int64_t{1} << '\n';
        }
    }
    for (const Group& g : curves) {
        out << "1 " << g.entity << " 1 " << static_cast<std::uint64_t>(g.end - g.begin) << '\n';
        for (std::size_t i = g.begin; i < g.end; ++i) {
            const std::size_t k = by_tag.member(i);
            const auto& e = mesh.boundary[k];
            out << nt + k + 1 << ' ' << e[0] + std::int64_t{1} << ' ' << e[1] + std::int64_t{1} << '\n';
        }
    }
    out << "$EndElements\n";

    for (const auto& [name, values] : mesh.cell_data) {
        out << "$ElementData\n1\n" << quoted(name) << "\n1\n0\n3\n0\n1\n" << nt << '\n';
        for (std::uint64_t k = 0; k < nt; ++k) out << k + 1 << ' ' << values[k] << '\n';
        out << "$EndElementData\n";
    }
}

void write_msh(const Mesh& mesh, const std::string& path) {
    detail::check_mesh_arrays(mesh, path);
    write_file_atomically(path, [&](std::ostream& os) { write_msh(mesh, os); });
}

}  // namespace warpmesh
