// write_xdmf.cpp — XDMF 3 for FEniCSx (dolfinx), meshio and ParaView.
//
// Two XDMF files, each with its heavy data either in an HDF5 file beside it
// (the default, as dolfinx writes XDMF) or inline as XML text (tiny meshes,
// --ascii):
//
//   PATH (e.g. out.xdmf), grid "mesh", heavy data in out.h5:
//     <Topology TopologyType="Triangle">  T x 3 vertex indices (0-based)   /mesh/topology
//               (or "Tetrahedron", T x 4, for a tetrahedral mesh)
//     <Geometry GeometryType="XY">        N x 2 coordinates                /mesh/geometry
//               ("XYZ", N x 3, for a tetrahedral mesh)
//     <Attribute Name="region" Center="Cell">  the region tag of each cell /mesh/region
//     <Information Name="Information">    meshio's field_data: region names
//
//   STEM_facets.xdmf (detail::xdmf_facets_path), grid "facets", heavy data
//   in STEM_facets.h5:
//     <Topology TopologyType="Polyline" NodesPerElement="2">  the boundary
//              edges, then the interface edges, as detail::facet_groups orders
//              and orients them (vertex indices into the same points)  /facets/topology
//              (a tetrahedral mesh: "Triangle", its boundary and interface
//              triangles)
//     <Geometry GeometryType="XY">        the same N points: a reference to
//                                         out.h5:/mesh/geometry (no copy)
//     <Attribute Name="facet_tags" Center="Cell">  the edge group's tag   /facets/facet_tags
//     <Information Name="Information">    the group names (dim 1; 2 in 3D)
//
// Why two .h5 files: dolfinx's XDMFFile reads every HDF DataItem from the one
// HDF5 file named after the XDMF file (STEM.h5 for STEM.xdmf), whatever file
// the item names, so the facet tags must be in STEM_facets.h5; its
// read_meshtags reads only the Topology and the Attribute, while meshio
// (one grid per file, hence two files) follows the Geometry's reference.
// The DataItems name the .h5 files without a directory: they are beside the
// XDMF file, which may be moved with them.
//
// dolfinx 0.5 reads them as
//     mesh = XDMFFile(comm, "out.xdmf", "r").read_mesh(name="mesh")
//     cell_tags = ….read_meshtags(mesh, name="mesh")        # region
//     mesh.topology.create_connectivity(1, 2)
//     facet_tags = XDMFFile(comm, "out_facets.xdmf", "r").read_meshtags(mesh, name="facets")
// (inline XML: XDMFFile(…, encoding=XDMFFile.Encoding.ASCII); read_meshtags
// takes the grid's Topology and its first Attribute; the entity vertex
// indices refer to the mesh file's point order).
//
// Atomicity: the four files are written under temporary names and renamed
// only when all are complete, the .h5 files first, so an .xdmf never appears
// without its heavy data.  The serial HDF5 library is not thread-safe: HDF5
// writes are serialised by a mutex (the CLI writes --slices in parallel).
//
// Numbers: Float precision 8 (meshio reads Precision="4" as float32), Int
// precision 4; inline text is the shortest round-trip decimal, values
// separated by spaces and newlines only (dolfinx splits on those two).
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <functional>
#include <mutex>
#include <vector>

#ifdef WARPMESH_HAVE_HDF5
#include <hdf5.h>
#endif

#include "io/atomic_file.hpp"
#include "io/output.hpp"
#include "warpmesh/io/writers.hpp"

namespace warpmesh {

namespace {

using detail::TextBuf;
using detail::TextSink;

// One named group for meshio's field_data: <map key="NAME" dim="D">TAG</map>.
struct FieldName {
    std::string name;
    int dim;
    std::int32_t tag;
};

// A DataItem: `rows` rows of `cols` values, inline (row(buf, i) appends row
// i's text) or in an HDF5 dataset ("FILE.h5:/path").
struct Item {
    std::size_t rows, cols;
    bool is_float;
    std::string hdf;  // empty: inline
    std::function<void(TextBuf&, std::size_t)> row;
};

void put_item(TextSink& out, const Item& item) {
    out << "        <DataItem Dimensions=\"" << static_cast<std::uint64_t>(item.rows);
    if (item.cols > 1) out << ' ' << static_cast<std::uint64_t>(item.cols);
    out << "\" NumberType=\"" << (item.is_float ? "Float\" Precision=\"8" : "Int\" Precision=\"4") << "\" Format=\""
        << (item.hdf.empty() ? "XML" : "HDF") << "\">";
    if (!item.hdf.empty()) {
        out << detail::xml_escape(item.hdf) << "</DataItem>\n";
        return;
    }
    out << '\n';
    detail::write_text_parallel(out.stream(), item.rows, [&](TextBuf& b, std::size_t i) { item.row(b, i), b << '\n'; });
    out << "        </DataItem>\n";
}

// The whole XDMF document of one grid.
void put_grid(std::ostream& os, std::string_view grid, const detail::CellKind& kind, const Item& topology,
              const Item& geometry, std::string_view attribute, const Item& values, const std::vector<FieldName>& names) {
    TextSink out(os);
    out << "<?xml version=\"1.0\"?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n    <Grid Name=\"" << grid
        << "\" GridType=\"Uniform\">\n      <Topology TopologyType=\"" << kind.xdmf << "\" NumberOfElements=\""
        << static_cast<std::uint64_t>(topology.rows) << "\" NodesPerElement=\"" << static_cast<std::int32_t>(kind.nodes)
        << "\">\n";
    put_item(out, topology);
    out << "      </Topology>\n      <Geometry GeometryType=\"" << (geometry.cols == 3 ? "XYZ" : "XY") << "\">\n";
    put_item(out, geometry);
    out << "      </Geometry>\n      <Attribute Name=\"" << attribute << "\" AttributeType=\"Scalar\" Center=\"Cell\">\n";
    put_item(out, values);
    // meshio parses the text of <Information> as XML: the CDATA holds
    // <main><map key=… dim=…>tag</map>…</main>, names escaped for XML (which
    // also keeps "]]>" out of the CDATA).
    out << "      </Attribute>\n      <Information Name=\"Information\" Value=\"" << static_cast<std::uint64_t>(names.size())
        << "\"><![CDATA[<main>";
    for (const auto& n : names)
        out << "<map key=\"" << detail::xml_escape(n.name) << "\" dim=\"" << static_cast<std::int32_t>(n.dim) << "\">"
            << n.tag << "</map>";
    out << "</main>]]></Information>\n    </Grid>\n  </Domain>\n</Xdmf>\n";
}

// What the facet file holds: the grouped facets (flat, kind.nodes each),
// their tags and names.
struct Facets {
    detail::CellKind kind;
    std::vector<std::int32_t> nodes;
    std::vector<std::int32_t> tags;
    std::vector<FieldName> names;
    explicit Facets(const detail::MeshView& mesh) : kind(mesh.facet_kind) {
        for (const auto& g : detail::facet_groups(mesh)) {
            nodes.insert(nodes.end(), g.nodes.begin(), g.nodes.end());
            tags.insert(tags.end(), g.size(), g.tag);
            names.push_back({g.name, kind.dim, g.tag});
        }
    }
    detail::Cells facets() const { return {kind, nodes}; }
};

std::vector<FieldName> region_field_names(const detail::MeshView& mesh) {
    std::vector<FieldName> names;
    const auto tags = detail::region_tags(mesh);
    for (const std::int32_t t : tags) names.push_back({detail::region_name(mesh, t, tags.size() == 1), mesh.cells.kind.dim, t});
    return names;
}

// Row i of a table of cells: its vertex indices separated by spaces.
void put_cell_row(TextBuf& b, const detail::Cells& cells, std::size_t i) {
    bool first = true;
    for (const std::int32_t v : cells[i]) (first ? b : b << ' ') << v, first = false;
}

// The DataItems of the two grids; `mesh_h5`/`facets_h5` empty: inline.
Item geometry_item(const detail::MeshView& mesh, const std::string& mesh_h5) {
    return {mesh.num_vertices, static_cast<std::size_t>(mesh.dim), true, mesh_h5.empty() ? "" : mesh_h5 + ":/mesh/geometry",
            [mesh](TextBuf& b, std::size_t i) {
                for (int k = 0; k < mesh.dim; ++k) (k ? b << ' ' : b) << mesh.coord(i, k);
            }};
}

void put_mesh_document(std::ostream& os, const detail::MeshView& mesh, const std::string& h5) {
    const detail::Cells cells = mesh.cells;
    const Item topology{cells.size(), static_cast<std::size_t>(cells.kind.nodes), false, h5.empty() ? "" : h5 + ":/mesh/topology",
                        [cells](TextBuf& b, std::size_t i) { put_cell_row(b, cells, i); }};
    const Item region{mesh.region.size(), 1, false, h5.empty() ? "" : h5 + ":/mesh/region",
                      [&mesh](TextBuf& b, std::size_t i) { b << mesh.region[i]; }};
    put_grid(os, "mesh", cells.kind, topology, geometry_item(mesh, h5), "region", region, region_field_names(mesh));
}

void put_facets_document(std::ostream& os, const detail::MeshView& mesh, const Facets& f, const std::string& mesh_h5,
                         const std::string& facets_h5) {
    const detail::Cells facets = f.facets();
    const Item topology{facets.size(), static_cast<std::size_t>(f.kind.nodes), false,
                        facets_h5.empty() ? "" : facets_h5 + ":/facets/topology",
                        [facets](TextBuf& b, std::size_t i) { put_cell_row(b, facets, i); }};
    const Item tags{f.tags.size(), 1, false, facets_h5.empty() ? "" : facets_h5 + ":/facets/facet_tags",
                    [&f](TextBuf& b, std::size_t i) { b << f.tags[i]; }};
    put_grid(os, "facets", f.kind, topology, geometry_item(mesh, mesh_h5), "facet_tags", tags, f.names);
}

#ifdef WARPMESH_HAVE_HDF5
std::mutex hdf5_mutex;

// An HDF5 file being written; every failure is an OutputError naming `path`.
class H5Writer {
public:
    H5Writer(const std::string& temp, std::string path) : path_(std::move(path)) {
        H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported here, not printed
        id_ = H5Fcreate(temp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
        if (id_ < 0) fail("cannot create the HDF5 file");
    }
    ~H5Writer() {
        if (id_ >= 0) H5Fclose(id_);
    }
    H5Writer(const H5Writer&) = delete;
    H5Writer& operator=(const H5Writer&) = delete;

    // Dataset `name` ("/group/name", groups created) of rows x cols values at
    // `data`, written in slabs of rows of about 1 MiB copied to one reused
    // buffer: the kernel copies from a small, reused buffer several times
    // faster than from a large array in one write(2) (docs/performance.md,
    // "Writers").
    void dataset(const char* name, hid_t type, std::size_t rows, std::size_t cols, const void* data) {
        const hsize_t dims[2] = {rows, cols};
        const int rank = cols > 1 ? 2 : 1;
        const hid_t space = H5Screate_simple(rank, dims, nullptr);
        const hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
        H5Pset_create_intermediate_group(lcpl, 1);
        const hid_t set = H5Dcreate2(id_, name, type, space, lcpl, H5P_DEFAULT, H5P_DEFAULT);
        const std::size_t row_bytes = cols * H5Tget_size(type);
        const std::size_t slab = std::max<std::size_t>(1, (std::size_t{1} << 20) / std::max<std::size_t>(1, row_bytes));
        std::vector<std::byte> buffer(std::min(slab, rows) * row_bytes);
        bool ok = set >= 0;
        for (std::size_t first = 0; ok && cols && first < rows; first += slab) {
            const hsize_t start[2] = {first, 0}, count[2] = {std::min(slab, rows - first), cols};
            std::memcpy(buffer.data(), static_cast<const std::byte*>(data) + first * row_bytes, count[0] * row_bytes);
            const hid_t mem = H5Screate_simple(rank, count, nullptr);
            ok = H5Sselect_hyperslab(space, H5S_SELECT_SET, start, nullptr, count, nullptr) >= 0 &&
                 H5Dwrite(set, type, mem, space, H5P_DEFAULT, buffer.data()) >= 0;
            H5Sclose(mem);
        }
        if (set >= 0) H5Dclose(set);
        H5Pclose(lcpl);
        H5Sclose(space);
        if (!ok) fail(std::string("cannot write the dataset ") + name);
    }
    void close() {
        const herr_t r = H5Fclose(id_);
        id_ = -1;
        if (r < 0) fail("cannot close the HDF5 file (write error)");
    }

private:
    [[noreturn]] void fail(const std::string& what) { throw OutputError("cannot write '" + path_ + "': " + what); }
    std::string path_;
    hid_t id_ = -1;
};

void write_h5(AtomicFile& mesh_file, AtomicFile& facets_file, const detail::MeshView& mesh, const Facets& f) {
    const std::lock_guard lock(hdf5_mutex);
    const detail::Cells cells = mesh.cells;
    mesh_file.close();  // only its name is used: HDF5 writes the file itself
    H5Writer m(mesh_file.temp_path(), mesh_file.path());
    m.dataset("/mesh/topology", H5T_NATIVE_INT32, cells.size(), static_cast<std::size_t>(cells.kind.nodes), cells.nodes.data());
    m.dataset("/mesh/geometry", H5T_NATIVE_DOUBLE, mesh.num_vertices, static_cast<std::size_t>(mesh.dim), mesh.coords);
    m.dataset("/mesh/region", H5T_NATIVE_INT32, mesh.region.size(), 1, mesh.region.data());
    m.close();
    facets_file.close();
    H5Writer g(facets_file.temp_path(), facets_file.path());
    g.dataset("/facets/topology", H5T_NATIVE_INT32, f.facets().size(), static_cast<std::size_t>(f.kind.nodes), f.nodes.data());
    g.dataset("/facets/facet_tags", H5T_NATIVE_INT32, f.tags.size(), 1, f.tags.data());
    g.close();
}
#endif

void write_mesh_view(const detail::MeshView& mesh, std::ostream& os) {
    detail::check_mesh_arrays(mesh, "<xdmf stream>");
    put_mesh_document(os, mesh, "");
}

void write_facets_view(const detail::MeshView& mesh, std::ostream& os) {
    detail::check_mesh_arrays(mesh, "<xdmf stream>");
    put_facets_document(os, mesh, Facets(mesh), "", "");
}

void write_view(const detail::MeshView& mesh, const std::string& path, const XdmfOptions& options) {
    detail::check_mesh_arrays(mesh, path);
    AtomicFile main(path), facets(detail::xdmf_facets_path(path));
    if (!options.hdf5) {
        // Both files complete before either is renamed into place.
        detail::fill_atomic_file(main, [&](std::ostream& os) { write_mesh_view(mesh, os); });
        detail::fill_atomic_file(facets, [&](std::ostream& os) { write_facets_view(mesh, os); });
        main.commit();
        facets.commit();
        return;
    }
#ifdef WARPMESH_HAVE_HDF5
    const std::string final_path = options.final_path.empty() ? path : options.final_path;
    auto file_name = [](const std::string& p) { return std::filesystem::path(p).filename().string(); };
    const std::string mesh_h5 = file_name(detail::xdmf_h5_path(final_path));
    const std::string facets_h5 = file_name(detail::xdmf_h5_path(detail::xdmf_facets_path(final_path)));
    AtomicFile main_h5(detail::xdmf_h5_path(path)), facets_h5_file(detail::xdmf_h5_path(detail::xdmf_facets_path(path)));
    const Facets f(mesh);
    write_h5(main_h5, facets_h5_file, mesh, f);
    detail::fill_atomic_file(main, [&](std::ostream& os) { put_mesh_document(os, mesh, mesh_h5); });
    detail::fill_atomic_file(facets, [&](std::ostream& os) { put_facets_document(os, mesh, f, mesh_h5, facets_h5); });
    main_h5.commit();
    facets_h5_file.commit();
    main.commit();
    facets.commit();
#else
    throw OutputError("cannot write '" + path + "': XDMF with HDF5 heavy data needs libhdf5, which was not found at build "
                      "time (write inline XML instead: --ascii, or XdmfOptions::hdf5 = false)");
#endif
}

}  // namespace

void write_xdmf_mesh(const Mesh& mesh, std::ostream& os) { write_mesh_view(detail::view_of(mesh), os); }
void write_xdmf_mesh(const TetMesh& mesh, std::ostream& os) { write_mesh_view(detail::view_of(mesh), os); }
void write_xdmf_facets(const Mesh& mesh, std::ostream& os) { write_facets_view(detail::view_of(mesh), os); }
void write_xdmf_facets(const TetMesh& mesh, std::ostream& os) { write_facets_view(detail::view_of(mesh), os); }
void write_xdmf(const Mesh& mesh, const std::string& path, const XdmfOptions& options) {
    write_view(detail::view_of(mesh), path, options);
}
void write_xdmf(const TetMesh& mesh, const std::string& path, const XdmfOptions& options) {
    write_view(detail::view_of(mesh), path, options);
}

}  // namespace warpmesh
