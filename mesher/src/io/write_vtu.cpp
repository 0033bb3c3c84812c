// write_vtu.cpp — VTK XML UnstructuredGrid, ASCII inline data.
//
// Layout (VTK "XML File Formats", UnstructuredGrid):
//
//   <VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
//     <UnstructuredGrid>
//       <Piece NumberOfPoints="N" NumberOfCells="T">
//         <Points>    one Float64 DataArray, 3 components (x y 0)     </Points>
//         <Cells>     "connectivity" (Int32, 3 per cell, 0-based point ids),
//                     "offsets" (Int64: end of each cell in connectivity = 3, 6, …),
//                     "types" (UInt8: 5 = VTK_TRIANGLE)                </Cells>
//         <PointData Scalars="boundary_marker">
//                     "boundary_marker" (Int32): detail::vertex_markers, as in .node
//         </PointData>
//         <CellData Scalars="region">
//                     "region" (Int32) and each mesh.cell_data array (Float64)
//         </CellData>
//       </Piece>
//     </UnstructuredGrid>
//   </VTKFile>
//
// Only the triangles are cells: mixing line cells for the boundary edges in
// would give them region/cell-data values too and confuse filters; the .msh and
// .poly outputs carry the boundary.  Values are written 6 per line.  Non-finite
// cell data are written as "nan"/"inf", which VTK's ASCII reader may reject.
#include <string_view>

#include "io/atomic_file.hpp"
#include "warpmesh/writers.hpp"

namespace warpmesh {

namespace {

// `count` values produced by value(i), six per line, each line indented.
template <class F>
void put_values(detail::TextSink& out, std::size_t count, F&& value) {
    for (std::size_t i = 0; i < count; ++i) {
        out << (i % 6 == 0 ? std::string_view("          ") : std::string_view(" "));
        value(i);
        if (i % 6 == 5 || i + 1 == count) out << '\n';
    }
}

}  // namespace

void write_vtu(const Mesh& mesh, std::ostream& os) {
    detail::check_mesh_arrays(mesh, "<vtu stream>");
    const std::size_t nv = mesh.vertices.size(), nt = mesh.triangles.size();
    detail::TextSink out(os);
    out << "<?xml version=\"1.0\"?>\n"
           "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
           "  <UnstructuredGrid>\n"
           "    <Piece NumberOfPoints=\""
        << static_cast<std::uint64_t>(nv) << "\" NumberOfCells=\"" << static_cast<std::uint64_t>(nt) << "\">\n";

    out << "      <Points>\n"
           "        <DataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Vec2& v : mesh.vertices) out << "          " << v.x << ' ' << v.y << " 0\n";
    out << "        </DataArray>\n"
           "      </Points>\n";

    out << "      <Cells>\n"
           "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const auto& t : mesh.triangles) out << "          " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    out << "        </DataArray>\n"
           "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    put_values(out, nt, [&](std::size_t i) { out << static_cast<std::int64_t>(3 * (i + 1)); });
    out << "        </DataArray>\n"
           "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    put_values(out, nt, [&](std::size_t) { out << '5'; });
    out << "        </DataArray>\n"
           "      </Cells>\n";

    out << "      <PointData Scalars=\"boundary_marker\">\n"
           "        <DataArray type=\"Int32\" Name=\"boundary_marker\" format=\"ascii\">\n";
    const auto markers = detail::vertex_markers(mesh, detail::edge_groups(mesh));
    put_values(out, nv, [&](std::size_t i) { out << markers[i]; });
    out << "        </DataArray>\n"
           "      </PointData>\n";

    out << "      <CellData Scalars=\"region\">\n"
           "        <DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n";
    put_values(out, nt, [&](std::size_t i) { out << mesh.region[i]; });
    out << "        </DataArray>\n";
    for (const auto& field : mesh.cell_data) {
        const auto& values = field.second;
        out << "        <DataArray type=\"Float64\" Name=\"" << detail::xml_escape(field.first) << "\" format=\"ascii\">\n";
        put_values(out, nt, [&](std::size_t i) { out << values[i]; });
        out << "        </DataArray>\n";
    }
    out << "      </CellData>\n"
           "    </Piece>\n"
           "  </UnstructuredGrid>\n"
           "</VTKFile>\n";
}

void write_vtu(const Mesh& mesh, const std::string& path) {
    detail::check_mesh_arrays(mesh, path);
    write_file_atomically(path, [&](std::ostream& os) { write_vtu(mesh, os); });
}

}  // namespace warpmesh
