// write_xdmf.cpp — XDMF 3 for FEniCSx (dolfinx), meshio and ParaView.
//
// Two self-contained files, heavy data inline as XML text:
//
//   PATH (e.g. out.xdmf), grid "mesh":
//     <Topology TopologyType="Triangle">  T x 3 vertex indices (0-based)
//     <Geometry GeometryType="XY">        N x 2 coordinates
//     <Attribute Name="region" Center="Cell">  the region tag of each triangle
//     <Information Name="Information">    meshio's field_data: region names
//
//   STEM_facets.xdmf (detail::xdmf_facets_path), grid "facets":
//     <Topology TopologyType="Polyline" NodesPerElement="2">  the boundary
//              edges, then the interface edges, as detail::edge_groups orders
//              and orients them (vertex indices into the same points)
//     <Geometry GeometryType="XY">        the same N points again
//     <Attribute Name="facet_tags" Center="Cell">  the edge group's tag
//     <Information Name="Information">    the group names (dim 1)
//
// dolfinx 0.5 reads them as (ASCII: the heavy data are in the file, no .h5)
//     ascii = XDMFFile.Encoding.ASCII
//     mesh = XDMFFile(comm, "out.xdmf", "r", encoding=ascii).read_mesh(name="mesh")
//     cell_tags = ….read_meshtags(mesh, name="mesh")        # region
//     mesh.topology.create_connectivity(1, 2)
//     facet_tags = XDMFFile(comm, "out_facets.xdmf", "r", encoding=ascii).read_meshtags(mesh, name="facets")
// (read_meshtags takes the grid's Topology and its first Attribute; the
// entity vertex indices refer to the mesh file's point order, which is the
// facet file's too), and meshio reads each file as one mesh (its XDMF reader
// takes one grid per file, hence two files).
//
// Why inline XML and not HDF5: no HDF5 dependency for warpmesh (writing HDF5
// needs libhdf5), each file is complete on its own — nothing to keep beside
// it, nothing to break when it is renamed (the CLI stages outputs under
// temporary names) — and dolfinx reads XML DataItems itself (pugixml).  The
// price is size and parse time: text is ~2-3x larger than binary and is
// parsed on one rank, so for meshes of millions of triangles prefer .msh
// through dolfinx.io.gmshio, or convert once with meshio.
//
// Numbers: Float precision 8 (meshio reads Precision="4" as float32) with the
// shortest round-trip decimal, Int precision 4; values separated by spaces and
// newlines only (dolfinx splits on those two characters).
#include "io/atomic_file.hpp"
#include "warpmesh/writers.hpp"

namespace warpmesh {

namespace {

// One named group for meshio's field_data: <map key="NAME" dim="D">TAG</map>.
struct FieldName {
    std::string name;
    int dim;
    std::int32_t tag;
};

void put_header(detail::TextSink& out, std::string_view grid) {
    out << "<?xml version=\"1.0\"?>\n"
           "<Xdmf Version=\"3.0\">\n"
           "  <Domain>\n"
           "    <Grid Name=\""
        << grid << "\" GridType=\"Uniform\">\n";
}

void put_footer(detail::TextSink& out, const std::vector<FieldName>& names) {
    // meshio parses the text of <Information> as XML: the CDATA holds
    // <main><map key=… dim=…>tag</map>…</main>, names escaped for XML (which
    // also keeps "]]>" out of the CDATA).
    out << "      <Information Name=\"Information\" Value=\"" << static_cast<std::uint64_t>(names.size())
        << "\"><![CDATA[<main>";
    for (const auto& n : names)
        out << "<map key=\"" << detail::xml_escape(n.name) << "\" dim=\"" << static_cast<std::int32_t>(n.dim) << "\">"
            << n.tag << "</map>";
    out << "</main>]]></Information>\n"
           "    </Grid>\n"
           "  </Domain>\n"
           "</Xdmf>\n";
}

void put_geometry(detail::TextSink& out, const Mesh& mesh) {
    out << "      <Geometry GeometryType=\"XY\">\n"
           "        <DataItem Dimensions=\""
        << static_cast<std::uint64_t>(mesh.vertices.size())
        << " 2\" NumberType=\"Float\" Precision=\"8\" Format=\"XML\">\n";
    for (const Vec2& v : mesh.vertices) out << "          " << v.x << ' ' << v.y << '\n';
    out << "        </DataItem>\n"
           "      </Geometry>\n";
}

// <Topology> of `count` cells with `per` vertices each, given by cell(i, out).
template <class Cell>
void put_topology(detail::TextSink& out, std::string_view type, std::size_t count, int per, Cell&& cell) {
    const auto n = static_cast<std::uint64_t>(count);
    out << "      <Topology TopologyType=\"" << type << "\" NumberOfElements=\"" << n << "\" NodesPerElement=\""
        << static_cast<std::int32_t>(per) << "\">\n"
        << "        <DataItem Dimensions=\"" << n << ' ' << static_cast<std::int32_t>(per)
        << "\" NumberType=\"Int\" Precision=\"4\" Format=\"XML\">\n";
    for (std::size_t i = 0; i < count; ++i) {
        out << "          ";
        cell(i);
        out << '\n';
    }
    out << "        </DataItem>\n"
           "      </Topology>\n";
}

// <Attribute> of one Int32 per cell, given by value(i), 10 per line.
template <class Value>
void put_cell_attribute(detail::TextSink& out, std::string_view name, std::size_t count, Value&& value) {
    out << "      <Attribute Name=\"" << name << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n"
        << "        <DataItem Dimensions=\"" << static_cast<std::uint64_t>(count)
        << "\" NumberType=\"Int\" Precision=\"4\" Format=\"XML\">\n";
    for (std::size_t i = 0; i < count; ++i) {
        out << (i % 10 == 0 ? std::string_view("          ") : std::string_view(" ")) << value(i);
        if (i % 10 == 9 || i + 1 == count) out << '\n';
    }
    out << "        </DataItem>\n"
           "      </Attribute>\n";
}

}  // namespace

void write_xdmf_mesh(const Mesh& mesh, std::ostream& os) {
    detail::check_mesh_arrays(mesh, "<xdmf stream>");
    detail::TextSink out(os);
    put_header(out, "mesh");
    put_topology(out, "Triangle", mesh.triangles.size(), 3, [&](std::size_t k) {
        const auto& t = mesh.triangles[k];
        out << t[0] << ' ' << t[1] << ' ' << t[2];
    });
    put_geometry(out, mesh);
    put_cell_attribute(out, "region", mesh.triangles.size(), [&](std::size_t k) { return mesh.region[k]; });
    std::vector<FieldName> names;
    const auto tags = detail::region_tags(mesh);
    for (const std::int32_t t : tags) names.push_back({detail::region_name(mesh, t, tags.size() == 1), 2, t});
    put_footer(out, names);
}

void write_xdmf_facets(const Mesh& mesh, std::ostream& os) {
    detail::check_mesh_arrays(mesh, "<xdmf stream>");
    const auto groups = detail::edge_groups(mesh);
    std::vector<std::array<std::int32_t, 2>> edges;
    std::vector<std::int32_t> tags;
    std::vector<FieldName> names;
    for (const auto& g : groups) {
        edges.insert(edges.end(), g.edges.begin(), g.edges.end());
        tags.insert(tags.end(), g.edges.size(), g.tag);
        names.push_back({g.name, 1, g.tag});
    }
    detail::TextSink out(os);
    put_header(out, "facets");
    put_topology(out, "Polyline", edges.size(), 2, [&](std::size_t k) { out << edges[k][0] << ' ' << edges[k][1]; });
    put_geometry(out, mesh);
    put_cell_attribute(out, "facet_tags", edges.size(), [&](std::size_t k) { return tags[k]; });
    put_footer(out, names);
}

void write_xdmf(const Mesh& mesh, const std::string& path) {
    detail::check_mesh_arrays(mesh, path);
    // Both files complete before either is renamed into place.
    AtomicFile main(path), facets(detail::xdmf_facets_path(path));
    detail::fill_atomic_file(main, [&](std::ostream& os) { write_xdmf_mesh(mesh, os); });
    detail::fill_atomic_file(facets, [&](std::ostream& os) { write_xdmf_facets(mesh, os); });
    main.commit();
    facets.commit();
}

}  // namespace warpmesh
