// write_inp.cpp — Abaqus input file (.inp), which CalculiX reads too.
//
//   ** comments (no *HEADING: the file is meant to be *INCLUDEd by a deck,
//                            which has its own and must have it first)
//   *NODE                    "id, x, y" (id = vertex index + 1; 2D, z = 0;
//                            "id, x, y, z" for tetrahedra; numbers of at most
//                            20 characters, see inp_number)
//   *ELEMENT, TYPE=CPS3      "id, n1, n2, n3" (id = triangle index + 1,
//                            nodes counter-clockwise as the format requires;
//                            TYPE=C3D4 "id, n1, n2, n3, n4" for tetrahedra,
//                            positively oriented as the format requires)
//   *ELSET, ELSET=<region>   one per region tag: the region's elements
//   *NSET, NSET=<group>      one per detail::edge_groups group ("boundary",
//                            "domain_border", "interface_<a>_<b>"): its nodes
//   *ELSET, ELSET=_<group>_S<k>, and
//   *SURFACE, TYPE=ELEMENT, NAME=<group>
//                            the group's edges as element faces: edge (u, v)
//                            is face S1, S2 or S3 of the triangle that has
//                            u → v as its side n1→n2, n2→n3 or n3→n1 (CPS3's
//                            face numbering); boundary edges have their region
//                            on the left, so that triangle is inside the
//                            mesh; an interface surface lies on the faces of
//                            region a's triangles (the left one).  For
//                            tetrahedra the same with triangles as faces
//                            S1–S4 of C3D4 (element_faces).
//
// Set and surface names follow detail::region_name and the edge groups' names,
// made Abaqus-safe: letters, digits and '_' only (others become '_'), starting
// with a letter (else prefixed "R"), at most 80 characters; Abaqus names are
// case-insensitive, so a name equal (ignoring case) to an earlier one gets
// "_<tag>" appended.  Sets list 16 ids per line (the format's limit).  No
// section, material or step is written: a solver deck adds e.g.
// "*SOLID SECTION, ELSET=domain, MATERIAL=…" and includes this file.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <map>
#include <set>
#include <unordered_map>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/output.hpp"
#include "warpmesh/io/writers.hpp"

namespace warpmesh {

namespace {

// `name` as a unique Abaqus name (see the header comment); `used` holds the
// upper-cased names given so far.
std::string abaqus_name(const std::string& name, std::int32_t tag, std::set<std::string>& used) {
    std::string r;
    for (const char c : name) r += std::isalnum(static_cast<unsigned char>(c)) || c == '_' ? c : '_';
    if (r.empty() || !std::isalpha(static_cast<unsigned char>(r[0]))) r.insert(r.begin(), 'R');
    auto upper = [](std::string s) {
        std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
        return s;
    };
    r.resize(std::min<std::size_t>(r.size(), 80));
    if (used.count(upper(r))) {
        // (Appended piecewise: GCC 12 warns falsely on "_" + std::to_string.)
        const std::string number = std::to_string(tag);
        r.resize(std::min<std::size_t>(r.size(), 80 - 1 - number.size()));
        r.append(1, '_').append(number);
        for (int k = 2; used.count(upper(r)); ++k) r.erase(r.rfind('_') + 1).append(std::to_string(k));
    }
    used.insert(upper(r));
    return r;
}

// The 1-based ids id(0) … id(count-1), 16 per line, formatted in parallel.
template <class Id>
void put_ids(detail::TextSink& out, std::size_t count, Id&& id) {
    detail::write_text_parallel(out.stream(), (count + 15) / 16, [&](detail::TextBuf& b, std::size_t line) {
        const std::size_t end = std::min(count, 16 * line + 16);
        for (std::size_t i = 16 * line; i < end; ++i) b << static_cast<std::uint64_t>(id(i)) << (i + 1 == end ? "\n" : ", ");
    });
}
void put_ids(detail::TextSink& out, const std::vector<std::uint64_t>& ids) {
    put_ids(out, ids.size(), [&](std::size_t i) { return ids[i]; });
}

// The triangles of each region tag, as positions [begin, end) of `order`
// (triangle indices grouped by tag, in mesh order within a tag; empty order
// = the identity, for a single region).
struct RegionRuns {
    std::map<std::int32_t, std::pair<std::size_t, std::size_t>> range;
    std::vector<std::uint32_t> order;
    std::size_t at(std::size_t i) const { return order.empty() ? i : order[i]; }
};

RegionRuns region_runs(const detail::MeshView& mesh) {
    RegionRuns r;
    std::map<std::int32_t, std::size_t> count;
    auto last = count.end();
    for (const std::int32_t t : mesh.region) {
        if (last == count.end() || last->first != t) last = count.try_emplace(t, 0).first;
        ++last->second;
    }
    std::size_t begin = 0;
    for (const auto& [t, n] : count) r.range[t] = {begin, begin + n}, begin += n;
    if (count.size() > 1) {
        r.order.resize(mesh.region.size());
        std::map<std::int32_t, std::size_t> next;
        for (const auto& [t, range] : r.range) next[t] = range.first;
        auto it = next.end();
        for (std::size_t k = 0; k < mesh.region.size(); ++k) {
            if (it == next.end() || it->first != mesh.region[k]) it = next.find(mesh.region[k]);
            r.order[it->second++] = static_cast<std::uint32_t>(k);
        }
    }
    return r;
}

// `x` in at most 20 characters, the width of CalculiX's number fields (a
// longer number is a fatal "error reading *NODE"): the shortest decimal that
// reads back to x when it fits (any |x| in [1e-5, 1e15) with up to 17
// significant digits does), else the most significant digits that fit (at
// least 13, a relative rounding of at most 5e-14).
void put_inp_number(detail::TextBuf& out, double x) {
    char buf[64];
    auto r = std::to_chars(buf, buf + sizeof buf, x);
    for (int digits = 16; r.ptr - buf > 20 && digits >= 1; --digits)
        r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, digits);
    out << std::string_view(buf, static_cast<std::size_t>(r.ptr - buf));
}

// The faces of an element as Abaqus numbers them, each as the local vertex
// indices of the facet ORIENTED OUT OF the element (the orientation of
// mesh.boundary): CPS3 side Sk is the edge n_k → n_{k+1} (the triangle on its
// left); C3D4 faces S1 = n1 n2 n3, S2 = n1 n4 n2, S3 = n2 n4 n3, S4 = n3 n4 n1
// (Abaqus's table; each is listed here reversed, since Abaqus's face order
// has its normal pointing into a positively oriented tetrahedron).
std::span<const std::array<int, 3>> element_faces(const detail::CellKind& kind) {
    static constexpr std::array<std::array<int, 3>, 3> triangle{{{0, 1, -1}, {1, 2, -1}, {2, 0, -1}}};
    static constexpr std::array<std::array<int, 3>, 4> tetra{{{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}}};
    if (kind.nodes == 4) return tetra;
    return triangle;
}

// An oriented facet as a key: an edge (u, v) as it is (-1 third), a triangle
// rotated cyclically (which keeps its orientation) to start at its smallest
// vertex.
using FacetKey = std::array<std::int32_t, 3>;
struct FacetKeyHash {
    std::size_t operator()(const FacetKey& k) const {
        std::uint64_t h = 0;
        for (const std::int32_t v : k) h = (h ^ static_cast<std::uint32_t>(v)) * 0x100000001b3ull;
        return static_cast<std::size_t>(h ^ (h >> 29));
    }
};
FacetKey facet_key(std::span<const std::int32_t> f) {
    if (f.size() == 2) return {f[0], f[1], -1};
    const std::size_t m = static_cast<std::size_t>(std::min_element(f.begin(), f.end()) - f.begin());
    return {f[m], f[(m + 1) % 3], f[(m + 2) % 3]};
}

// For every grouped facet, the face (element id, side 1..4) that has it on
// its outer side; an OutputError if there is none.
struct Face {
    std::uint64_t element = 0;
    int side = 0;
};
std::vector<std::vector<Face>> group_faces(const detail::MeshView& mesh, const std::vector<detail::FacetGroup>& groups) {
    std::vector<std::vector<Face>> faces(groups.size());
    std::unordered_map<FacetKey, std::pair<std::size_t, std::size_t>, FacetKeyHash> wanted;  // facet → (group, member)
    // The vertices of grouped facets: a cell's side is looked up only if its
    // first vertex is one (a small fraction of the cells' sides).
    std::vector<std::uint8_t> on_facet(mesh.num_vertices, 0);
    for (std::size_t g = 0; g < groups.size(); ++g) {
        faces[g].resize(groups[g].size());
        for (std::size_t i = 0; i < groups[g].size(); ++i) wanted[facet_key(groups[g].facets()[i])] = {g, i};
        for (const std::int32_t v : groups[g].nodes) on_facet[static_cast<std::size_t>(v)] = 1;
    }
    const auto sides = element_faces(mesh.cells.kind);
    const auto per = static_cast<std::size_t>(mesh.facet_kind.nodes);
    // Read-only lookups in parallel; each grouped facet is the face of one
    // cell only in a conforming mesh, so the writes do not collide.
    const auto nt = static_cast<std::int64_t>(wanted.empty() ? 0 : mesh.cells.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t kk = 0; kk < nt; ++kk) {
        const auto k = static_cast<std::size_t>(kk);
        const auto t = mesh.cells[k];
        for (std::size_t s = 0; s < sides.size(); ++s) {
            std::int32_t f[3];
            for (std::size_t j = 0; j < per; ++j) f[j] = t[static_cast<std::size_t>(sides[s][j])];
            if (!on_facet[static_cast<std::size_t>(f[0])]) continue;
            const auto it = wanted.find(facet_key({f, per}));
            if (it == wanted.end()) continue;
            const auto [g, i] = it->second;
            // An interface's face must be on its left region's side (a
            // wrong interface_regions entry would put it on the other).
            if (!groups[g].interface || mesh.region[k] == groups[g].left_region) faces[g][i] = {k + 1, static_cast<int>(s + 1)};
        }
    }
    const std::string cell = mesh.cells.kind.dim == 3 ? "tetrahedron" : "triangle";
    for (std::size_t g = 0; g < groups.size(); ++g)
        for (std::size_t i = 0; i < faces[g].size(); ++i)
            if (faces[g][i].side == 0) {
                std::string ids;
                for (const std::int32_t v : groups[g].facets()[i]) ids += (ids.empty() ? "" : ", ") + std::to_string(v);
                throw OutputError(std::string("invalid mesh: ") + (per == 2 ? "edge (" : "triangle (") + ids + ") of '" +
                                  groups[g].name + "' is not " + (per == 2 ? "a side of a triangle on its left" : "an outward face of a tetrahedron") +
                                  (groups[g].interface ? " in region " + std::to_string(groups[g].left_region) : std::string()));
            }
    return faces;
}

void write_view(const detail::MeshView& mesh, std::ostream& os) {
    detail::check_mesh_arrays(mesh, "<inp stream>");
    const auto groups = detail::facet_groups(mesh);
    const auto faces = group_faces(mesh, groups);
    const std::size_t nsides = element_faces(mesh.cells.kind).size();

    detail::TextSink out(os);
    out << "** Written by warpmesh: " << (mesh.dim == 3 ? "tetrahedra (C3D4)" : "2D triangles (CPS3)")
        << " with region element sets and boundary/interface\n"
           "** node sets and surfaces.  *INCLUDE it in a deck that adds sections, materials and steps, e.g.\n"
           "**   *SOLID SECTION, ELSET=<region>, MATERIAL=<material>\n"
           "*NODE\n";
    detail::write_text_parallel(out.stream(), mesh.num_vertices, [&](detail::TextBuf& b, std::size_t i) {
        b << static_cast<std::uint64_t>(i + 1);
        for (int k = 0; k < mesh.dim; ++k) b << ", ", put_inp_number(b, mesh.coord(i, k));
        b << '\n';
    });
    const detail::Cells cells = mesh.cells;
    if (cells.size()) {
        out << "*ELEMENT, TYPE=" << cells.kind.abaqus << '\n';
        detail::write_text_parallel(out.stream(), cells.size(), [&](detail::TextBuf& b, std::size_t k) {
            b << static_cast<std::uint64_t>(k + 1);
            for (const std::int32_t v : cells[k]) b << ", " << v + std::int64_t{1};
            b << '\n';
        });
    }

    std::set<std::string> used;
    // Element sets per region, streamed (4 bytes a triangle of order when
    // there are several regions, none for one).
    const RegionRuns runs = region_runs(mesh);
    for (const auto& [tag, range] : runs.range) {
        out << "*ELSET, ELSET=" << abaqus_name(detail::region_name(mesh, tag, runs.range.size() == 1), tag, used) << '\n';
        put_ids(out, range.second - range.first, [&, first = range.first](std::size_t i) { return runs.at(first + i) + 1; });
    }
    for (std::size_t g = 0; g < groups.size(); ++g) {
        const auto& group = groups[g];
        const std::string name = abaqus_name(group.name, group.tag, used);
        std::set<std::uint64_t> nodes;
        for (const std::int32_t v : group.nodes) nodes.insert(v + std::uint64_t{1});
        out << "*NSET, NSET=" << name << '\n';
        put_ids(out, {nodes.begin(), nodes.end()});
        std::array<std::vector<std::uint64_t>, 4> by_side;
        for (const Face& f : faces[g]) by_side[static_cast<std::size_t>(f.side - 1)].push_back(f.element);
        for (std::size_t s = 0; s < nsides; ++s) {
            auto& ids = by_side[s];
            if (ids.empty()) continue;
            std::sort(ids.begin(), ids.end());
            const char side = static_cast<char>('1' + s);  // faces S1..S3 (S4)
            out << "*ELSET, ELSET=_" << name << "_S" << side << '\n';
            put_ids(out, ids);
        }
        out << "*SURFACE, TYPE=ELEMENT, NAME=" << name << '\n';
        for (std::size_t s = 0; s < nsides; ++s) {
            const char side = static_cast<char>('1' + s);
            if (!by_side[s].empty()) out << '_' << name << "_S" << side << ", S" << side << '\n';
        }
    }
}

}  // namespace

void write_inp(const Mesh& mesh, std::ostream& os) { write_view(detail::view_of(mesh), os); }
void write_inp(const TetMesh& mesh, std::ostream& os) { write_view(detail::view_of(mesh), os); }
void write_inp(const Mesh& mesh, const std::string& path) {
    detail::write_mesh_file(mesh, path, [](const detail::MeshView& v, std::ostream& os) { write_view(v, os); });
}
void write_inp(const TetMesh& mesh, const std::string& path) {
    detail::write_mesh_file(mesh, path, [](const detail::MeshView& v, std::ostream& os) { write_view(v, os); });
}

}  // namespace warpmesh
