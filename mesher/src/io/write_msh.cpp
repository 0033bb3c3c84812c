// write_msh.cpp — Gmsh MSH 4.1 and 2.2, binary (the default) or ASCII.
//
// Groups (both versions): one physical surface per region tag, named by
// detail::region_name ("domain", "domain_<tag>" or mesh.region_names), and
// one physical curve per detail::edge_groups group ("boundary",
// "domain_border", "interface_<a>_<b>"), its tag the group's facet tag.
// Every group is one elementary entity with the same tag as its physical
// group, so that readers which only keep entity tags see the same numbers.
// A tetrahedral mesh (TetMesh) is the same one dimension up: one physical
// volume per region (4-node tetrahedra, type 4) and one physical surface per
// facet group (3-node triangles, type 2, oriented outwards), the nodes on the
// first volume entity, $Entities "0 0 F R".
//
// MSH 4.1 sections, in the order the format requires (Gmsh manual, "MSH file
// format"):
//
//   $MeshFormat    "4.1 F 8": version 4.1, ASCII (F = 0) or binary (F = 1,
//                  followed by the int 1 so that readers see the byte order),
//                  sizeof(size_t) = 8.
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
// Binary 4.1 (Gmsh manual, "MSH file format", binary): the same sections and
// the same numbers in the same order, as little-endian int (4 bytes), size_t
// (8) and double (8) — every count, node and element tag a size_t, entity
// dimensions, tags and types an int — with no separators; each section's
// binary part is followed by "\n" before its $End line.  $PhysicalNames and
// the $ElementData headers stay text; the data lines are (int elementTag,
// double value) pairs.
//
// MSH 2.2: $MeshFormat "2.2 F 8", the same $PhysicalNames, "$Nodes" as a count
// then "tag x y z" lines, "$Elements" as a count then
// "tag type 2 physicalTag entityTag node…" lines (triangles first, in mesh
// order, then the lines), and the same $ElementData.  Binary 2.2: nodes as
// (int tag, 3 doubles); elements in blocks of one type, each an int header
// (type, count, 2 tags) then per element the ints (tag, physical, entity,
// nodes…).
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
// tag k + 1 (so element data follow triangle order whatever the blocks are) —
// except in binary 4.1, where the triangles are numbered in the order the
// region blocks list them (one region: the same), because meshio's binary
// reader requires the $ElementData tags to be 1, 2, … in file order;
// boundary edge e has element tag T + e + 1 and interface edge i tag
// T + B + i + 1.
//
// Region tags: the entity and physical tag of region tag t is t itself — the
// label value, as in every other format — when t >= 1.  Gmsh's tags must be
// positive (gmsh drops the name of a physical group 0), so a region tag
// t <= 0 — the background 0 of `--background keep` — gets the tag
// max(largest region tag, 0) + 1 + the rank of t among the non-positive tags:
// the background of labels 1 … 9 is physical surface 10, named "background".
#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <span>
#include <string_view>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/output.hpp"
#include "warpmesh/io/writers.hpp"

namespace warpmesh {

namespace {

using detail::TextBuf;
using detail::write_value;

struct Bbox {
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    bool empty = true;
    void add(const detail::MeshView& mesh, std::int32_t v) {
        for (int k = 0; k < 3; ++k) {
            const double x = mesh.coord(static_cast<std::size_t>(v), k);
            lo[k] = empty ? x : std::min(lo[k], x), hi[k] = empty ? x : std::max(hi[k], x);
        }
        empty = false;
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

// The file's tag of each region tag (see the header comment: t itself when
// t >= 1, else after the largest).
std::map<std::int32_t, std::int32_t> entity_tags(const std::map<std::int32_t, std::size_t>& count) {
    std::map<std::int32_t, std::int32_t> entity;
    const std::int32_t top = count.empty() ? 0 : std::max(0, count.rbegin()->first);
    std::int32_t next = top;
    for (const auto& [t, n] : count) entity[t] = t >= 1 ? t : ++next;
    return entity;
}

Grouping group_by_tag(std::span<const std::int32_t> tags) {
    // Count per tag (tags come in long runs, so cache the last map lookup).
    std::map<std::int32_t, std::size_t> count;
    auto last = count.end();
    for (const std::int32_t t : tags) {
        if (last == count.end() || last->first != t) last = count.try_emplace(t, 0).first;
        ++last->second;
    }
    Grouping g;
    const auto entity = entity_tags(count);
    std::map<std::int32_t, std::size_t> slot;  // tag → group index
    std::size_t begin = 0;
    for (const auto& [t, n] : count) {
        slot[t] = g.groups.size();
        g.groups.push_back({t, entity.at(t), begin, begin + n, {}});
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

// What both versions write: the region groups (with their bounding boxes) and
// the facet groups (curves of a triangle mesh, surfaces of a tetrahedral one).
struct Layout {
    detail::Cells cells;
    detail::CellKind facet_kind;
    Grouping by_region;
    std::vector<std::string> region_names;  // per region group
    std::vector<detail::FacetGroup> curves;
    std::vector<Bbox> curve_box;
    std::uint64_t nt = 0, nb = 0, ne = 0;  // cells, boundary facets, elements
    bool binary = true;

    Layout(const detail::MeshView& mesh, bool bin)
        : cells(mesh.cells),
          facet_kind(mesh.facet_kind),
          by_region(group_by_tag(mesh.region)),
          curves(detail::facet_groups(mesh)),
          nt(cells.size()),
          nb(mesh.num_boundary()),
          ne(nt + nb + mesh.num_interfaces()),
          binary(bin) {
        region_boxes(mesh);
        for (const Group& g : by_region.groups) region_names.push_back(detail::region_name(mesh, g.tag, by_region.groups.size() == 1));
        for (const detail::FacetGroup& c : curves) {
            Bbox& box = curve_box.emplace_back();
            for (const std::int32_t v : c.nodes) box.add(mesh, v);
        }
    }
    // Each region group's box: one pass over the cells in mesh order, a run
    // of cells of one region tag at a time.
    void region_boxes(const detail::MeshView& mesh) {
        const double inf = std::numeric_limits<double>::infinity();
        std::vector<std::array<double, 6>> box(by_region.groups.size(), {inf, inf, inf, -inf, -inf, -inf});
        const auto per = static_cast<std::size_t>(cells.kind.nodes);
        for (std::size_t k = 0; k < cells.size();) {
            std::size_t end = k + 1;
            while (end < cells.size() && mesh.region[end] == mesh.region[k]) ++end;
            const auto g = std::lower_bound(by_region.groups.begin(), by_region.groups.end(), mesh.region[k],
                                            [](const Group& a, std::int32_t t) { return a.tag < t; }) - by_region.groups.begin();
            const auto nodes = cells.nodes.subspan(k * per, (end - k) * per);
            if (mesh.dim == 3) add_to_box<3>(mesh.coords, nodes, box[static_cast<std::size_t>(g)]);
            else add_to_box<2>(mesh.coords, nodes, box[static_cast<std::size_t>(g)]);
            k = end;
        }
        for (std::size_t i = 0; i < box.size(); ++i) {
            Bbox& out = by_region.groups[i].box;
            for (std::size_t d = 0; d < 3; ++d)
                out.lo[d] = d < static_cast<std::size_t>(mesh.dim) ? box[i][d] : 0.0, out.hi[d] = d < static_cast<std::size_t>(mesh.dim) ? box[i][3 + d] : 0.0;
            out.empty = false;
        }
    }
    // box = {min x, y, z, max x, y, z} grown by the vertices `nodes` (D coordinates each).
    template <std::size_t D>
    static void add_to_box(const double* coords, std::span<const std::int32_t> nodes, std::array<double, 6>& box) {
        std::array<double, D> lo, hi;
        for (std::size_t d = 0; d < D; ++d) lo[d] = box[d], hi[d] = box[3 + d];
        for (const std::int32_t v : nodes) {
            const double* p = coords + static_cast<std::size_t>(v) * D;
            for (std::size_t d = 0; d < D; ++d) lo[d] = std::min(lo[d], p[d]), hi[d] = std::max(hi[d], p[d]);
        }
        for (std::size_t d = 0; d < D; ++d) box[d] = lo[d], box[3 + d] = hi[d];
    }
    // Element tag of the i-th member of facet group c.
    std::uint64_t line_tag(const detail::FacetGroup& c, std::size_t i) const {
        return nt + (c.interface ? nb : 0) + c.index[i] + 1;
    }
};

// Numbers of one record: text separated by spaces, or binary.
struct Record {
    Record(std::ostream& out, bool bin) : os(out), binary(bin) {}
    Record(const Record&) = delete;
    Record& operator=(const Record&) = delete;
    ~Record() { end_line(); }
    std::ostream& os;
    bool binary;
    TextBuf text;
    bool first = true;
    template <class T>
    Record& operator()(T x) {
        if (binary) return write_value(os, x), *this;
        if (!first) text << ' ';
        first = false;
        text << x;
        return *this;
    }
    void end_line() {
        if (binary || first) return;
        text << '\n';
        os.write(text.data(), static_cast<std::streamsize>(text.size()));
        text.clear();
        first = true;
    }
};

void put_text(std::ostream& os, std::string_view s) { detail::write_bytes(os, s.data(), s.size()); }

// The end of a section: binary data are followed by a newline.
void end_section(std::ostream& os, bool binary, std::string_view end) {
    if (binary) put_text(os, "\n");
    put_text(os, end);
}

void put_format(std::ostream& os, std::string_view version, bool binary) {
    put_text(os, "$MeshFormat\n");
    put_text(os, version);
    put_text(os, binary ? " 1 8\n" : " 0 8\n");
    if (binary) write_value(os, std::int32_t{1});
    end_section(os, binary, "$EndMeshFormat\n");
}

void put_physical_names(std::ostream& os, const Layout& l) {
    const auto& regions = l.by_region.groups;
    TextBuf out;
    out << "$PhysicalNames\n" << static_cast<std::uint64_t>(regions.size() + l.curves.size()) << '\n';
    for (const auto& c : l.curves) out << std::int32_t{l.facet_kind.dim} << ' ' << c.tag << ' ' << quoted(c.name) << '\n';
    for (std::size_t r = 0; r < regions.size(); ++r)
        out << std::int32_t{l.cells.kind.dim} << ' ' << regions[r].entity << ' ' << quoted(l.region_names[r]) << '\n';
    out << "$EndPhysicalNames\n";
    detail::write_bytes(os, out.data(), out.size());
}

void put_entities(std::ostream& os, const Layout& l) {
    const auto& regions = l.by_region.groups;
    put_text(os, "$Entities\n");
    auto entity = [&](std::int32_t tag, const Bbox& b) {
        Record r{os, l.binary};
        r(tag)(b.lo[0])(b.lo[1])(b.lo[2])(b.hi[0])(b.hi[1])(b.hi[2])(std::uint64_t{1})(tag)(std::uint64_t{0});
    };
    {
        // numPoints numCurves numSurfaces numVolumes: the facet groups one
        // dimension below the regions.
        std::uint64_t count[4] = {0, 0, 0, 0};
        count[l.facet_kind.dim] = l.curves.size();
        count[l.cells.kind.dim] = regions.size();
        Record r{os, l.binary};
        r(count[0])(count[1])(count[2])(count[3]);
    }
    for (std::size_t c = 0; c < l.curves.size(); ++c) entity(l.curves[c].tag, l.curve_box[c]);
    for (const Group& g : regions) entity(g.entity, g.box);
    end_section(os, l.binary, "$EndEntities\n");
}

// Items 0 … count-1 as text (format(buf, i)) or binary (fill(dst, first, n),
// `bytes` each).
template <class Format, class Fill>
void put_items(std::ostream& os, bool binary, std::size_t count, std::size_t bytes, Format&& format, Fill&& fill) {
    if (binary) detail::write_binary(os, count, bytes, fill);
    else detail::write_text_parallel(os, count, format);
}

void put_nodes41(std::ostream& os, const detail::MeshView& mesh, const Layout& l) {
    const auto nv = static_cast<std::uint64_t>(mesh.num_vertices);
    put_text(os, "$Nodes\n");
    // One block on the first region entity (a mesh without cells has none and
    // so no nodes block; its vertices are not written).
    if (!l.by_region.groups.empty()) {
        Record(os, l.binary)(std::uint64_t{1})(nv)(std::uint64_t{1})(nv).end_line();
        Record(os, l.binary)(std::int32_t{l.cells.kind.dim})(l.by_region.groups.front().entity)(std::int32_t{0})(nv);
        put_items(
            os, l.binary, nv, 8, [](TextBuf& b, std::size_t i) { b << static_cast<std::uint64_t>(i + 1) << '\n'; },
            [](std::byte* dst, std::size_t first, std::size_t n) {
                for (std::size_t i = 0; i < n; ++i) {
                    const auto tag = static_cast<std::uint64_t>(first + i + 1);
                    std::memcpy(dst + 8 * i, &tag, 8);
                }
            });
        put_items(
            os, l.binary, nv, 24,
            [&](TextBuf& b, std::size_t i) { b << mesh.coord(i, 0) << ' ' << mesh.coord(i, 1) << ' ' << mesh.coord(i, 2) << '\n'; },
            [&](std::byte* dst, std::size_t first, std::size_t n) {
                for (std::size_t i = 0; i < n; ++i) {
                    const double p[3] = {mesh.coord(first + i, 0), mesh.coord(first + i, 1), mesh.coord(first + i, 2)};
                    std::memcpy(dst + 24 * i, p, 24);
                }
            });
    } else {
        Record(os, l.binary)(std::uint64_t{0})(std::uint64_t{0})(std::uint64_t{0})(std::uint64_t{0});
    }
    end_section(os, l.binary, "$EndNodes\n");
}

// A block of `count` elements: element i has tag tag(i) and vertices
// nodes(i) (a span of `per` 0-based indices), written as size_t.
template <class Tag, class Nodes>
void put_element_block41(std::ostream& os, const Layout& l, std::size_t count, std::size_t per, Tag&& tag, Nodes&& nodes) {
    put_items(
        os, l.binary, count, 8 * (per + 1),
        [&](TextBuf& b, std::size_t i) {
            b << tag(i);
            for (const std::int32_t v : nodes(i)) b << ' ' << v + std::int64_t{1};
            b << '\n';
        },
        [&](std::byte* dst, std::size_t first, std::size_t n) {
            for (std::size_t i = 0; i < n; ++i, dst += 8 * (per + 1)) {
                const std::uint64_t t = tag(first + i);
                std::memcpy(dst, &t, 8);
                std::size_t k = 1;
                for (const std::int32_t v : nodes(first + i)) {
                    const auto u = static_cast<std::uint64_t>(v) + 1;
                    std::memcpy(dst + 8 * k++, &u, 8);
                }
            }
        });
}

void put_elements41(std::ostream& os, const Layout& l) {
    const auto& regions = l.by_region.groups;
    put_text(os, "$Elements\n");
    Record(os, l.binary)(static_cast<std::uint64_t>(regions.size() + l.curves.size()))(l.ne)(std::uint64_t{l.ne ? 1u : 0u})(l.ne)
        .end_line();
    const auto per = static_cast<std::size_t>(l.cells.kind.nodes);
    for (const Group& g : regions) {
        Record(os, l.binary)(std::int32_t{l.cells.kind.dim})(g.entity)(l.cells.kind.gmsh)(static_cast<std::uint64_t>(g.end - g.begin));
        put_element_block41(
            os, l, g.end - g.begin, per,
            [&](std::size_t i) { return static_cast<std::uint64_t>((l.binary ? g.begin + i : l.by_region.member(g.begin + i)) + 1); },
            [&](std::size_t i) { return l.cells[l.by_region.member(g.begin + i)]; });
    }
    for (const auto& c : l.curves) {
        const detail::Cells facets = c.facets();
        Record(os, l.binary)(std::int32_t{l.facet_kind.dim})(c.tag)(l.facet_kind.gmsh)(static_cast<std::uint64_t>(c.size()));
        put_element_block41(
            os, l, c.size(), static_cast<std::size_t>(l.facet_kind.nodes), [&](std::size_t i) { return l.line_tag(c, i); },
            [&](std::size_t i) { return facets[i]; });
    }
    end_section(os, l.binary, "$EndElements\n");
}

void put_nodes22(std::ostream& os, const detail::MeshView& mesh, const Layout& l) {
    put_text(os, "$Nodes\n");
    Record(os, false)(static_cast<std::uint64_t>(mesh.num_vertices));
    put_items(
        os, l.binary, mesh.num_vertices, 28,
        [&](TextBuf& b, std::size_t i) {
            b << static_cast<std::uint64_t>(i + 1) << ' ' << mesh.coord(i, 0) << ' ' << mesh.coord(i, 1) << ' ' << mesh.coord(i, 2) << '\n';
        },
        [&](std::byte* dst, std::size_t first, std::size_t n) {
            for (std::size_t i = 0; i < n; ++i, dst += 28) {
                const auto tag = static_cast<std::int32_t>(first + i + 1);
                const double p[3] = {mesh.coord(first + i, 0), mesh.coord(first + i, 1), mesh.coord(first + i, 2)};
                std::memcpy(dst, &tag, 4);
                std::memcpy(dst + 4, p, 24);
            }
        });
    end_section(os, l.binary, "$EndNodes\n");
}

// MSH 2.2 elements of one type: element i has tag tag(i), physical = entity
// tag phys(i) and vertices nodes(i).
template <class Tag, class Phys, class Nodes>
void put_elements22(std::ostream& os, const Layout& l, std::int32_t type, std::size_t count, std::size_t per, Tag&& tag,
                    Phys&& phys, Nodes&& nodes) {
    if (l.binary && count) Record(os, true)(type)(static_cast<std::int32_t>(count))(std::int32_t{2});
    put_items(
        os, l.binary, count, 4 * (3 + per),
        [&](TextBuf& b, std::size_t i) {
            b << tag(i) << ' ' << type << " 2 " << phys(i) << ' ' << phys(i);
            for (const std::int32_t v : nodes(i)) b << ' ' << v + std::int64_t{1};
            b << '\n';
        },
        [&](std::byte* dst, std::size_t first, std::size_t n) {
            for (std::size_t i = 0; i < n; ++i, dst += 4 * (3 + per)) {
                std::int32_t rec[8] = {static_cast<std::int32_t>(tag(first + i)), phys(first + i), phys(first + i)};
                std::size_t k = 3;
                for (const std::int32_t v : nodes(first + i)) rec[k++] = v + 1;
                std::memcpy(dst, rec, 4 * (3 + per));
            }
        });
}

void write_msh22(std::ostream& os, const detail::MeshView& mesh, const Layout& l) {
    put_format(os, "2.2", l.binary);
    put_physical_names(os, l);
    put_nodes22(os, mesh, l);
    // Physical (= entity) tag of each cell, by region group.
    std::vector<std::int32_t> entity(l.nt);
    for (const Group& g : l.by_region.groups)
        for (std::size_t i = g.begin; i < g.end; ++i) entity[l.by_region.member(i)] = g.entity;
    put_text(os, "$Elements\n");
    Record(os, false)(l.ne);
    put_elements22(
        os, l, l.cells.kind.gmsh, l.nt, static_cast<std::size_t>(l.cells.kind.nodes), [](std::size_t k) { return static_cast<std::uint64_t>(k + 1); },
        [&](std::size_t k) { return entity[k]; }, [&](std::size_t k) { return l.cells[k]; });
    // Facets in element-tag order: boundary facets, then interface facets.
    std::vector<std::pair<const detail::FacetGroup*, std::size_t>> lines(l.ne - l.nt);
    for (const auto& c : l.curves)
        for (std::size_t i = 0; i < c.size(); ++i) lines[l.line_tag(c, i) - l.nt - 1] = {&c, i};
    put_elements22(
        os, l, l.facet_kind.gmsh, lines.size(), static_cast<std::size_t>(l.facet_kind.nodes), [&](std::size_t k) { return l.nt + k + 1; },
        [&](std::size_t k) { return lines[k].first->tag; },
        [&](std::size_t k) { return lines[k].first->facets()[lines[k].second]; });
    end_section(os, l.binary, "$EndElements\n");
}

// The cells' values in the order $Elements lists the cells (MSH 4.1: region
// block by region block; 2.2: by tag).  Gmsh reads them by tag either way,
// but meshio pairs them with the elements in file order, ignoring the tags:
// in tag order, a mesh of several regions got its values shuffled.
void put_element_data(std::ostream& os, const detail::MeshView& mesh, const Layout& l, bool block_order) {
    for (const auto& field : mesh.cell_data) {
        const std::string& name = field.first;
        const auto& values = field.second;  // (not a structured binding: lambdas capture it)
        TextBuf head;
        head << "$ElementData\n1\n" << quoted(name) << "\n1\n0\n3\n0\n1\n" << l.ne << '\n';
        detail::write_bytes(os, head.data(), head.size());
        // Binary 4.1 numbers the cells in block order, so tags and file order agree.
        const bool renumbered = block_order && l.binary;
        auto tag = [&](std::size_t i) {
            if (i >= l.nt || renumbered) return i;
            return block_order ? l.by_region.member(i) : i;
        };
        auto value = [&](std::size_t i) {
            return i >= l.nt ? std::numeric_limits<double>::quiet_NaN() : values[block_order ? l.by_region.member(i) : i];
        };
        put_items(
            os, l.binary, l.ne, 12, [&](TextBuf& b, std::size_t i) { b << static_cast<std::uint64_t>(tag(i) + 1) << ' ' << value(i) << '\n'; },
            [&](std::byte* dst, std::size_t first, std::size_t n) {
                for (std::size_t i = 0; i < n; ++i, dst += 12) {
                    const auto t = static_cast<std::int32_t>(tag(first + i) + 1);
                    const double v = value(first + i);
                    std::memcpy(dst, &t, 4);
                    std::memcpy(dst + 4, &v, 8);
                }
            });
        end_section(os, l.binary, "$EndElementData\n");
    }
}

void write_view(const detail::MeshView& mesh, std::ostream& os, const MshOptions& options) {
    detail::check_mesh_arrays(mesh, "<msh stream>");
    if (options.version != 41 && options.version != 22)
        throw OutputError("unsupported MSH version " + std::to_string(options.version / 10) + "." +
                          std::to_string(options.version % 10) + " (supported: 4.1, 2.2)");
    const Layout layout(mesh, options.binary);
    if (options.version == 41) {
        put_format(os, "4.1", layout.binary);
        put_physical_names(os, layout);
        put_entities(os, layout);
        put_nodes41(os, mesh, layout);
        put_elements41(os, layout);
    } else {
        write_msh22(os, mesh, layout);
    }
    if (options.cell_data) put_element_data(os, mesh, layout, options.version == 41);
}

}  // namespace

void write_msh(const Mesh& mesh, std::ostream& os, const MshOptions& options) { write_view(detail::view_of(mesh), os, options); }
void write_msh(const TetMesh& mesh, std::ostream& os, const MshOptions& options) { write_view(detail::view_of(mesh), os, options); }
void write_msh(const Mesh& mesh, const std::string& path, const MshOptions& options) {
    detail::write_mesh_file(mesh, path, [&](const detail::MeshView& v, std::ostream& os) { write_view(v, os, options); });
}
void write_msh(const TetMesh& mesh, const std::string& path, const MshOptions& options) {
    detail::write_mesh_file(mesh, path, [&](const detail::MeshView& v, std::ostream& os) { write_view(v, os, options); });
}

}  // namespace warpmesh
