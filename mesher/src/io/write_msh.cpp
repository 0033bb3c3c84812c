// write_msh.cpp — Gmsh MSH 4.1 and 2.2, ASCII.
//
// Groups (both versions): one physical surface per region tag, named by
// detail::region_name ("domain", "domain_<tag>" or mesh.region_names), and
// one physical curve per detail::edge_groups group ("boundary",
// "domain_border", "interface_<a>_<b>"), its tag the group's facet tag.
// Every group is one elementary entity with the same tag as its physical
// group, so that readers which only keep entity tags see the same numbers.
//
// MSH 4.1 sections, in the order the format requires (Gmsh manual, "MSH file
// format"):
//
//   $MeshFormat    "4.1 0 8": version 4.1, ASCII (0), sizeof(size_t) = 8.
//   $PhysicalNames numPhysicalNames, then "dim physicalTag \"name\"" lines.
//   $Entities      "numPoints numCurves numSurfaces numVolumes" (0 C R 0), then
//                  per curve:   "tag minX minY minZ maxX maxY maxZ
//                                numPhysicalTags physicalTag numBoundingPoints(0)"
//                  per surface: "tag minX minY minZ maxX maxY maxZ
//                                numPhysicalTags physicalTag numBoundingCurves(0)".
//   $Nodes         "numEntityBlocks numNodes minNodeTag maxNodeTag", then one
//                  block "entityDim entityTag parametric numNodesInBlock" with
//                  all node tags (one per line) followed by all "x y z" lines.
//                  All nodes are classified on the first surface entity: a
//                  node shared by several regions must live in one block, and
//                  readers (Gmsh, meshio, dolfinx's gmshio) only need the tags.
//   $Elements      "numEntityBlocks numElements minElementTag maxElementTag",
//                  then per surface entity a block "2 entityTag 2 count" of
//                  3-node triangles (type 2) and per curve entity a block
//                  "1 entityTag 1 count" of 2-node lines (type 1):
//                  "elementTag node node [node]".
//   $ElementData   only if asked (MshOptions::cell_data): one view per
//                  mesh.cell_data array: 1 string tag (the name), 1 real tag
//                  (time 0), 3 integer tags (time step 0, 1 component, number
//                  of values), then "elementTag value" for EVERY element, the
//                  lines' value being nan, triangles in the order $Elements
//                  lists them (meshio reads the values in file order).
//
// MSH 2.2: $MeshFormat "2.2 0 8", the same $PhysicalNames, "$Nodes" as a count
// then "tag x y z" lines, "$Elements" as a count then
// "tag type 2 physicalTag entityTag node…" lines (triangles first, in mesh
// order, then the lines), and the same $ElementData.
//
// Why cell data stays out of .msh unless asked: a view in Gmsh may cover a
// subset of the elements, but meshio (the hub through which most Python FEM
// codes read .msh) requires one value per element of every cell block and
// refuses the file otherwise ("Incompatible cell data").  A per-triangle
// quantity such as certified_min_angle has no value on a boundary line, so
// the only complete view pads the lines with nan — meaningless values that
// every conversion would then carry along.  A .msh is a solver's input; the
// per-triangle diagnostics go to .vtu (ParaView) by default, and into .msh
// (padded with nan) only on request (warpmesh --msh-cell-data).
//
// Numbering (all 1-based): node tag = vertex index + 1; triangle k has element
// tag k + 1 (so element data follow triangle order whatever the blocks are);
// boundary edge e has element tag T + e + 1 and interface edge i tag
// T + B + i + 1.  Entity and physical tags of a region tag t are t itself when
// all region tags are >= 1, else the 1-based rank of t among the distinct tags.
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
    std::int32_t tag;     // region tag in the mesh
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

void put_entity(detail::TextSink& out, std::int32_t tag, const Bbox& box) {
    out << tag << ' ' << box.xmin << ' ' << box.ymin << " 0 " << box.xmax << ' ' << box.ymax << " 0 1 " << tag << " 0\n";
}

// What both versions write: the region groups (with their bounding boxes) and
// the edge groups.
struct Layout {
    Grouping by_region;
    std::vector<std::string> region_names;  // per region group
    std::vector<detail::EdgeGroup> curves;
    std::vector<Bbox> curve_box;
    std::uint64_t nt = 0, nb = 0, ne = 0;  // triangles, boundary edges, elements

    explicit Layout(const Mesh& mesh)
        : by_region(group_by_tag(mesh.region)),
          curves(detail::edge_groups(mesh)),
          nt(mesh.triangles.size()),
          nb(mesh.boundary.size()),
          ne(nt + nb + mesh.interfaces.size()) {
        for (Group& g : by_region.groups) {
            for (std::size_t i = g.begin; i < g.end; ++i)
                for (const std::int32_t v : mesh.triangles[by_region.member(i)]) g.box.add(mesh.vertices[static_cast<std::size_t>(v)]);
            region_names.push_back(detail::region_name(mesh, g.tag, by_region.groups.size() == 1));
        }
        for (const detail::EdgeGroup& c : curves) {
            Bbox& box = curve_box.emplace_back();
            for (const auto& e : c.edges)
                for (const std::int32_t v : e) box.add(mesh.vertices[static_cast<std::size_t>(v)]);
        }
    }
    // Element tag of the i-th member of curve c.
    std::uint64_t line_tag(const detail::EdgeGroup& c, std::size_t i) const {
        return nt + (c.interface ? nb : 0) + c.index[i] + 1;
    }
};

void put_physical_names(detail::TextSink& out, const Layout& l) {
    const auto& regions = l.by_region.groups;
    out << "$PhysicalNames\n" << static_cast<std::uint64_t>(regions.size() + l.curves.size()) << '\n';
    for (const auto& c : l.curves) out << "1 " << c.tag << ' ' << quoted(c.name) << '\n';
    for (std::size_t r = 0; r < regions.size(); ++r)
        out << "2 " << regions[r].entity << ' ' << quoted(l.region_names[r]) << '\n';
    out << "$EndPhysicalNames\n";
}

// The triangles' values in the order $Elements lists the triangles (MSH 4.1:
// region block by region block; 2.2: by tag).  Gmsh reads them by tag either
// way, but meshio pairs them with the elements in file order, ignoring the
// tags: in tag order, a mesh of several regions got its values shuffled.
void put_element_data(detail::TextSink& out, const Mesh& mesh, const Layout& l, bool block_order) {
    for (const auto& [name, values] : mesh.cell_data) {
        out << "$ElementData\n1\n" << quoted(name) << "\n1\n0\n3\n0\n1\n" << l.ne << '\n';
        for (std::uint64_t i = 0; i < l.nt; ++i) {
            const std::uint64_t k = block_order ? static_cast<std::uint64_t>(l.by_region.member(static_cast<std::size_t>(i))) : i;
            out << k + 1 << ' ' << values[k] << '\n';
        }
        for (std::uint64_t k = l.nt; k < l.ne; ++k) out << k + 1 << " nan\n";
        out << "$EndElementData\n";
    }
}

void write_msh41(const Mesh& mesh, const Layout& l, detail::TextSink& out) {
    const auto nv = static_cast<std::uint64_t>(mesh.vertices.size());
    const auto& regions = l.by_region.groups;
    out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
    put_physical_names(out, l);

    out << "$Entities\n0 " << static_cast<std::uint64_t>(l.curves.size()) << ' '
        << static_cast<std::uint64_t>(regions.size()) << " 0\n";
    for (std::size_t c = 0; c < l.curves.size(); ++c) put_entity(out, l.curves[c].tag, l.curve_box[c]);
    for (const Group& g : regions) put_entity(out, g.entity, g.box);
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

    out << "$Elements\n"
        << static_cast<std::uint64_t>(regions.size() + l.curves.size()) << ' ' << l.ne << ' ' << (l.ne ? 1 : 0) << ' '
        << l.ne << '\n';
    for (const Group& g : regions) {
        out << "2 " << g.entity << " 2 " << static_cast<std::uint64_t>(g.end - g.begin) << '\n';
        for (std::size_t i = g.begin; i < g.end; ++i) {
            const std::size_t k = l.by_region.member(i);
            const auto& t = mesh.triangles[k];
            out << static_cast<std::uint64_t>(k + 1) << ' ' << t[0] + std::int64_t{1} << ' ' << t[1] + std::int64_t{1}
                << ' ' << t[2] + std::int64_t{1} << '\n';
        }
    }
    for (const auto& c : l.curves) {
        out << "1 " << c.tag << " 1 " << static_cast<std::uint64_t>(c.edges.size()) << '\n';
        for (std::size_t i = 0; i < c.edges.size(); ++i)
            out << l.line_tag(c, i) << ' ' << c.edges[i][0] + std::int64_t{1} << ' ' << c.edges[i][1] + std::int64_t{1}
                << '\n';
    }
    out << "$EndElements\n";
}

void write_msh22(const Mesh& mesh, const Layout& l, detail::TextSink& out) {
    out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n";
    put_physical_names(out, l);
    out << "$Nodes\n" << static_cast<std::uint64_t>(mesh.vertices.size()) << '\n';
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        out << static_cast<std::uint64_t>(i + 1) << ' ' << mesh.vertices[i].x << ' ' << mesh.vertices[i].y << " 0\n";
    out << "$EndNodes\n";

    // Physical (= entity) tag of each triangle, by region group.
    std::vector<std::int32_t> entity(mesh.triangles.size());
    for (const Group& g : l.by_region.groups)
        for (std::size_t i = g.begin; i < g.end; ++i) entity[l.by_region.member(i)] = g.entity;
    out << "$Elements\n" << l.ne << '\n';
    for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
        const auto& t = mesh.triangles[k];
        out << static_cast<std::uint64_t>(k + 1) << " 2 2 " << entity[k] << ' ' << entity[k] << ' ' << t[0] + std::int64_t{1}
            << ' ' << t[1] + std::int64_t{1} << ' ' << t[2] + std::int64_t{1} << '\n';
    }
    // Lines in element-tag order: boundary edges, then interface edges.
    std::vector<std::pair<const detail::EdgeGroup*, std::size_t>> lines(l.ne - l.nt);
    for (const auto& c : l.curves)
        for (std::size_t i = 0; i < c.edges.size(); ++i) lines[l.line_tag(c, i) - l.nt - 1] = {&c, i};
    for (const auto& [c, i] : lines)
        out << l.line_tag(*c, i) << " 1 2 " << c->tag << ' ' << c->tag << ' ' << c->edges[i][0] + std::int64_t{1} << ' '
            << c->edges[i][1] + std::int64_t{1} << '\n';
    out << "$EndElements\n";
}

}  // namespace

void write_msh(const Mesh& mesh, std::ostream& os, const MshOptions& options) {
    detail::check_mesh_arrays(mesh, "<msh stream>");
    if (options.version != 41 && options.version != 22)
        throw OutputError("unsupported MSH version " + std::to_string(options.version / 10) + "." +
                          std::to_string(options.version % 10) + " (supported: 4.1, 2.2)");
    const Layout layout(mesh);
    detail::TextSink out(os);
    if (options.version == 41) write_msh41(mesh, layout, out);
    else write_msh22(mesh, layout, out);
    if (options.cell_data) put_element_data(out, mesh, layout, options.version == 41);
}

void write_msh(const Mesh& mesh, const std::string& path, const MshOptions& options) {
    detail::check_mesh_arrays(mesh, path);
    write_file_atomically(path, [&](std::ostream& os) { write_msh(mesh, os, options); });
}

}  // namespace warpmesh
