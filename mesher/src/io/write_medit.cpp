// write_medit.cpp — medit/MMG mesh format (.mesh, ASCII), which MMG, medit,
// meshio, Gmsh and TetGen read.
//
//   MeshVersionFormatted 2        (2: coordinates are double precision)
//   Dimension 3                   (2 for a triangle mesh)
//   Vertices / N / "x y z ref"    ref = detail::vertex_markers (the smallest
//                                 facet-group tag at the vertex, else 0), as
//                                 the .vtu's boundary_marker
//   Tetrahedra / T / "a b c d ref"  (a triangle mesh: Triangles, "a b c ref")
//                                 1-based vertex indices, positively oriented
//                                 (counter-clockwise triangles); ref = the
//                                 cell's region tag
//   Triangles / F / "a b c ref"   (a triangle mesh: Edges, "a b ref") the
//                                 boundary facets then the interface facets,
//                                 as detail::facet_groups orders and orients
//                                 them; ref = the group's tag (the .msh
//                                 physical group's and XDMF facet tag)
//   End
//
// Numbers are the shortest decimals that read back to the same double, so
// the file round-trips exactly.  Group names have no place in the format;
// they are in every other output.
#include "io/output.hpp"
#include "warpmesh/io/writers.hpp"

namespace warpmesh {

namespace {

using detail::TextBuf;

// One section of cells: KEYWORD, the count, then "v1 … vn ref" lines.
template <class Ref>
void put_cells(detail::TextSink& out, const detail::Cells& cells, Ref&& ref) {
    out << cells.kind.medit << '\n' << static_cast<std::uint64_t>(cells.size()) << '\n';
    detail::write_text_parallel(out.stream(), cells.size(), [&](TextBuf& b, std::size_t i) {
        for (const std::int32_t v : cells[i]) b << v + std::int64_t{1} << ' ';
        b << ref(i) << '\n';
    });
}

void write_view(const detail::MeshView& mesh, std::ostream& os) {
    detail::check_mesh_arrays(mesh, "<medit stream>");
    const auto groups = detail::facet_groups(mesh);
    const auto markers = detail::vertex_markers(mesh, groups);
    detail::TextSink out(os);
    out << "MeshVersionFormatted 2\nDimension " << std::int32_t{mesh.dim} << "\nVertices\n"
        << static_cast<std::uint64_t>(mesh.num_vertices) << '\n';
    detail::write_text_parallel(out.stream(), mesh.num_vertices, [&](TextBuf& b, std::size_t i) {
        for (int k = 0; k < mesh.dim; ++k) b << mesh.coord(i, k) << ' ';
        b << markers[i] << '\n';
    });
    put_cells(out, mesh.cells, [&](std::size_t i) { return mesh.region[i]; });
    std::vector<std::int32_t> nodes, tags;
    for (const auto& g : groups) {
        nodes.insert(nodes.end(), g.nodes.begin(), g.nodes.end());
        tags.insert(tags.end(), g.size(), g.tag);
    }
    put_cells(out, {mesh.facet_kind, nodes}, [&](std::size_t i) { return tags[i]; });
    out << "End\n";
}

}  // namespace

void write_medit(const Mesh& mesh, std::ostream& os) { write_view(detail::view_of(mesh), os); }
void write_medit(const TetMesh& mesh, std::ostream& os) { write_view(detail::view_of(mesh), os); }
void write_medit(const Mesh& mesh, const std::string& path) {
    detail::write_mesh_file(mesh, path, [](const detail::MeshView& v, std::ostream& os) { write_view(v, os); });
}
void write_medit(const TetMesh& mesh, const std::string& path) {
    detail::write_mesh_file(mesh, path, [](const detail::MeshView& v, std::ostream& os) { write_view(v, os); });
}

}  // namespace warpmesh
