// write_vtu.cpp — VTK XML UnstructuredGrid: appended raw binary, appended
// zlib-compressed binary, or inline ASCII.
//
// Layout (VTK "XML File Formats", UnstructuredGrid, version 1.0):
//
//   <VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian"
//            header_type="UInt64" [compressor="vtkZLibDataCompressor"]>
//     <UnstructuredGrid>
//       <Piece NumberOfPoints="N" NumberOfCells="T">
//         <Points>    one Float64 DataArray, 3 components (x y z; z = 0 in 2D) </Points>
//         <Cells>     "connectivity" (Int32, nodes per cell, 0-based point ids),
//                     "offsets" (Int32, or Int64 beyond 2^31 - 1: end of each
//                     cell in connectivity = 3, 6, …),
//                     "types" (UInt8: the cell kind's VTK type, 5 = triangle,
//                     10 = tetrahedron)
//         </Cells>
//         <PointData Scalars="boundary_marker">
//                     "boundary_marker" (Int32): detail::vertex_markers, as in .node
//         </PointData>
//         <CellData Scalars="region">
//                     "region" (Int32) and each mesh.cell_data array (Float64)
//         </CellData>
//       </Piece>
//     </UnstructuredGrid>
//     [<AppendedData encoding="raw">_ARRAYS</AppendedData>]
//   </VTKFile>
//
// Appended (format="appended" offset="K"): after the underscore, each array in
// the reverse of document order (write_raw says why); its offset K counts
// bytes from just after the underscore.
//   raw:  a UInt64 byte count, then the array's bytes.
//   zlib: a UInt64 header [number of blocks b, uncompressed block size,
//         uncompressed size of the last block, compressed size of block 1 …
//         block b], then the b blocks, each compressed on its own (zlib
//         compress2, level 1: writing speed first).  Blocks are compressed in
//         parallel; since the offsets in the XML come before the data and
//         depend on the compressed sizes, the compressed blocks go to an
//         anonymous temporary file first and are copied after the XML.
// ASCII (format="ascii"): one tuple per line, formatted in parallel.
//
// Only the triangles (tetrahedra) are cells: mixing line (triangle) cells for
// the boundary facets in would give them region/cell-data values too and
// confuse filters; the .msh, .xdmf and .poly outputs carry the boundary.  Non-finite cell data are written as
// "nan"/"inf" in ASCII, which VTK's ASCII reader may reject (binary is exact).
#include <zlib.h>

#include <cstdio>
#include <functional>
#include <limits>
#include <memory>
#include <string_view>

#include "io/atomic_file.hpp"
#include "io/output.hpp"
#include "warpmesh/io/writers.hpp"

namespace warpmesh {

namespace {

using detail::TextBuf;

// One DataArray: `count` tuples of `components` values of type `type`.
struct Array {
    std::string_view type;
    std::string name;
    int components;
    std::size_t count, tuple_bytes;
    std::function<void(std::byte*, std::size_t, std::size_t)> fill;  // tuples first … first+n-1
    std::function<void(TextBuf&, std::size_t)> text;                // one tuple's values
    std::size_t bytes() const { return count * tuple_bytes; }
};

// An array of `count` scalars of type T, value(i).
template <class T, class Value>
Array scalars(std::string_view type, std::string name, std::size_t count, Value value) {
    return {type, std::move(name), 1, count, sizeof(T),
            [value](std::byte* dst, std::size_t first, std::size_t n) {
                for (std::size_t i = 0; i < n; ++i) {
                    const T v = static_cast<T>(value(first + i));
                    std::memcpy(dst + i * sizeof(T), &v, sizeof(T));
                }
            },
            [value](TextBuf& b, std::size_t i) {
                if constexpr (sizeof(T) == 1) b << static_cast<std::int32_t>(value(i));
                else b << value(i);
            }};
}

// An array that is `count` contiguous scalars at `data` (copied as they are).
template <class T>
Array direct(std::string_view type, std::string name, int components, std::size_t count, const T* data) {
    const auto c = static_cast<std::size_t>(components);
    return {type, std::move(name), components, count, c * sizeof(T),
            [data, c](std::byte* dst, std::size_t first, std::size_t n) { std::memcpy(dst, data + first * c, n * c * sizeof(T)); },
            [data, c](TextBuf& b, std::size_t i) {
                for (std::size_t k = 0; k < c; ++k) (k ? b << ' ' : b) << data[i * c + k];
            }};
}

struct Sections {
    std::vector<Array> points, cells, point_data, cell_data;
};

Sections arrays_of(const detail::MeshView& mesh, const std::vector<std::int32_t>& markers, const VtuOptions& o) {
    const detail::Cells cells = mesh.cells;
    const std::size_t nv = mesh.num_vertices, nt = cells.size();
    const auto per = static_cast<std::int64_t>(cells.kind.nodes);
    const std::uint8_t vtk_type = cells.kind.vtk;
    Sections s;
    if (mesh.dim == 3) {
        s.points.push_back(direct("Float64", "Points", 3, nv, mesh.coords));
    } else {
        s.points.push_back({"Float64", "Points", 3, nv, 24,
                            [xy = mesh.coords](std::byte* dst, std::size_t first, std::size_t n) {
                                for (std::size_t i = 0; i < n; ++i) {
                                    const double p[3] = {xy[2 * (first + i)], xy[2 * (first + i) + 1], 0.0};
                                    std::memcpy(dst + 24 * i, p, 24);
                                }
                            },
                            [mesh](TextBuf& b, std::size_t i) { b << mesh.coord(i, 0) << ' ' << mesh.coord(i, 1) << ' ' << mesh.coord(i, 2); }});
    }
    s.cells.push_back(direct("Int32", "connectivity", 1, cells.nodes.size(), cells.nodes.data()));
    auto offset = [per](std::size_t i) { return per * static_cast<std::int64_t>(i + 1); };
    if (per * static_cast<std::int64_t>(nt) <= std::numeric_limits<std::int32_t>::max())
        s.cells.push_back(scalars<std::int32_t>("Int32", "offsets", nt, [offset](std::size_t i) { return static_cast<std::int32_t>(offset(i)); }));
    else
        s.cells.push_back(scalars<std::int64_t>("Int64", "offsets", nt, offset));
    s.cells.push_back(scalars<std::uint8_t>("UInt8", "types", nt, [vtk_type](std::size_t) { return vtk_type; }));
    s.point_data.push_back(direct("Int32", "boundary_marker", 1, nv, markers.data()));
    s.cell_data.push_back(direct("Int32", "region", 1, nt, mesh.region.data()));
    for (const auto& [name, values] : mesh.cell_data) s.cell_data.push_back(direct("Float64", name, 1, nt, values.data()));
    if (o.global_ids || !o.point_global_ids.empty() || !o.cell_global_ids.empty()) {
        if (o.point_global_ids.size() != nv || o.cell_global_ids.size() != nt)
            throw OutputError("the global ids of a .vtu piece must be one per point and one per cell");
        const std::uint64_t* pid = o.point_global_ids.data();
        const std::uint64_t* cid = o.cell_global_ids.data();
        s.point_data.push_back(scalars<std::int64_t>("Int64", "GlobalIds", nv, [pid](std::size_t i) { return static_cast<std::int64_t>(pid[i]); }));
        s.cell_data.push_back(scalars<std::int64_t>("Int64", "GlobalIds", nt, [cid](std::size_t i) { return static_cast<std::int64_t>(cid[i]); }));
    }
    return s;
}

// The XML of one array: inline ASCII text, or a reference to the appended data.
void put_array(std::ostream& os, const Array& a, VtuOptions::Encoding enc, std::uint64_t offset) {
    detail::TextSink out(os);
    out << "        <DataArray type=\"" << a.type << "\" Name=\"" << detail::xml_escape(a.name) << '"';
    if (a.components != 1) out << " NumberOfComponents=\"" << static_cast<std::int32_t>(a.components) << '"';
    if (enc != VtuOptions::Encoding::ascii) {
        out << " format=\"appended\" offset=\"" << offset << "\"/>\n";
        return;
    }
    out << " format=\"ascii\">\n";
    detail::write_text_parallel(out.stream(), a.count, [&a](TextBuf& b, std::size_t i) { a.text(b, i), b << '\n'; });
    out << "        </DataArray>\n";
}

// The XML document; `offsets[k]` is the appended offset of the k-th array.
void put_xml(std::ostream& os, const detail::MeshView& mesh, const Sections& s, VtuOptions::Encoding enc,
             const std::vector<std::uint64_t>& offsets) {
    std::size_t k = 0;
    auto section = [&](std::string_view open, std::string_view close, const std::vector<Array>& arrays) {
        detail::write_bytes(os, open.data(), open.size());
        for (const Array& a : arrays) put_array(os, a, enc, offsets.empty() ? 0 : offsets[k++]);
        detail::write_bytes(os, close.data(), close.size());
    };
    {
        detail::TextSink out(os);
        out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
               "header_type=\"UInt64\""
            << (enc == VtuOptions::Encoding::zlib ? std::string_view(" compressor=\"vtkZLibDataCompressor\"") : "")
            << ">\n  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"" << static_cast<std::uint64_t>(mesh.num_vertices)
            << "\" NumberOfCells=\"" << static_cast<std::uint64_t>(mesh.cells.size()) << "\">\n";
    }
    section("      <Points>\n", "      </Points>\n", s.points);
    section("      <Cells>\n", "      </Cells>\n", s.cells);
    const bool ids = s.point_data.size() > 1;  // the global ids follow boundary_marker
    section(ids ? "      <PointData Scalars=\"boundary_marker\" GlobalIds=\"GlobalIds\">\n" : "      <PointData Scalars=\"boundary_marker\">\n",
            "      </PointData>\n", s.point_data);
    section(ids ? "      <CellData Scalars=\"region\" GlobalIds=\"GlobalIds\">\n" : "      <CellData Scalars=\"region\">\n",
            "      </CellData>\n", s.cell_data);
    const std::string_view end = "    </Piece>\n  </UnstructuredGrid>\n";
    detail::write_bytes(os, end.data(), end.size());
}

std::vector<const Array*> all_arrays(const Sections& s) {
    std::vector<const Array*> r;
    for (const auto* v : {&s.points, &s.cells, &s.point_data, &s.cell_data})
        for (const Array& a : *v) r.push_back(&a);
    return r;
}

// The appended data holds the arrays in the REVERSE of document order (any
// order is valid VTK).  meshio 5 reads raw and zlib appended data by
// rewriting each array's offset attribute as it goes and finding the next
// array with find(".//DataArray[@offset='K']"), the first match in document
// order: in document order, an array already rewritten could shadow a later
// one whose raw offset equals the rewritten value (a 5-point mesh did, see
// tests/python/test_solver_formats.py).  In reverse order every array still
// to be found precedes, in the document, every array already rewritten.
void write_raw(std::ostream& os, const detail::MeshView& mesh, const Sections& s) {
    const auto arrays = all_arrays(s);
    std::vector<std::uint64_t> offsets(arrays.size());
    std::uint64_t at = 0;
    for (std::size_t k = arrays.size(); k-- > 0;) offsets[k] = at, at += 8 + arrays[k]->bytes();
    put_xml(os, mesh, s, VtuOptions::Encoding::raw, offsets);
    os << "  <AppendedData encoding=\"raw\">\n   _";
    for (std::size_t k = arrays.size(); k-- > 0;) {
        const Array* a = arrays[k];
        detail::write_value(os, static_cast<std::uint64_t>(a->bytes()));
        detail::write_binary(os, a->count, a->tuple_bytes, a->fill);
    }
    os << "\n  </AppendedData>\n</VTKFile>\n";
}

// ---- zlib ----------------------------------------------------------------------

struct FileCloser {
    void operator()(std::FILE* f) const { std::fclose(f); }
};
using TempFile = std::unique_ptr<std::FILE, FileCloser>;

struct Compressed {
    std::vector<std::uint64_t> header;  // b, block size, last block size, sizes…
    std::uint64_t bytes() const {
        std::uint64_t n = 8 * header.size();
        for (std::size_t k = 3; k < header.size(); ++k) n += header[k];
        return n;
    }
};

struct Block {
    std::vector<std::byte> raw;
    std::vector<Bytef> packed;
    uLongf packed_size = 0;
};

// Compresses `a` block by block (in parallel, in order) into `tmp`.
Compressed compress_array(const Array& a, std::FILE* tmp) {
    const std::size_t per = std::max<std::size_t>(1, (std::size_t{1} << 18) / a.tuple_bytes);  // tuples a block
    const std::size_t blocks = (a.count + per - 1) / per;
    Compressed c;
    c.header = {blocks, per * a.tuple_bytes, blocks ? (a.count - (blocks - 1) * per) * a.tuple_bytes : 0};
    detail::ordered_blocks<Block>(
        blocks,
        [&](std::size_t b, Block& blk) {
            const std::size_t first = b * per, n = std::min(per, a.count - first);
            blk.raw.resize(n * a.tuple_bytes);
            a.fill(blk.raw.data(), first, n);
            blk.packed.resize(compressBound(static_cast<uLong>(blk.raw.size())));
            blk.packed_size = static_cast<uLongf>(blk.packed.size());
            if (compress2(blk.packed.data(), &blk.packed_size, reinterpret_cast<const Bytef*>(blk.raw.data()),
                          static_cast<uLong>(blk.raw.size()), 1) != Z_OK)
                throw OutputError("zlib compression failed");
        },
        [&](const Block& blk) {
            if (std::fwrite(blk.packed.data(), 1, blk.packed_size, tmp) != blk.packed_size)
                throw OutputError("cannot write the temporary file of compressed data");
            c.header.push_back(blk.packed_size);
        });
    return c;
}

void write_zlib(std::ostream& os, const detail::MeshView& mesh, const Sections& s) {
    const auto arrays = all_arrays(s);
    const TempFile tmp(std::tmpfile());
    if (!tmp) throw OutputError("cannot create a temporary file for the compressed data");
    // Compressed and written in reverse document order, as write_raw.
    std::vector<Compressed> packed;
    std::vector<std::uint64_t> offsets(arrays.size());
    std::uint64_t at = 0;
    for (std::size_t k = arrays.size(); k-- > 0;) {
        packed.push_back(compress_array(*arrays[k], tmp.get()));
        offsets[k] = at, at += packed.back().bytes();
    }
    put_xml(os, mesh, s, VtuOptions::Encoding::zlib, offsets);
    os << "  <AppendedData encoding=\"raw\">\n   _";
    std::rewind(tmp.get());
    std::vector<char> buf(std::size_t{1} << 20);
    for (const Compressed& c : packed) {
        detail::write_bytes(os, c.header.data(), 8 * c.header.size());
        for (std::uint64_t left = c.bytes() - 8 * c.header.size(); left > 0;) {
            const std::size_t n = std::fread(buf.data(), 1, std::min<std::uint64_t>(left, buf.size()), tmp.get());
            if (n == 0) throw OutputError("cannot read back the temporary file of compressed data");
            detail::write_bytes(os, buf.data(), n);
            left -= n;
        }
    }
    os << "\n  </AppendedData>\n</VTKFile>\n";
}

// `mesh` has passed detail::check_mesh_arrays.
void write_view(const detail::MeshView& mesh, std::ostream& os, const VtuOptions& options) {
    const auto markers = detail::vertex_markers(mesh, detail::facet_groups(mesh));
    const Sections s = arrays_of(mesh, markers, options);
    switch (options.encoding) {
        case VtuOptions::Encoding::raw: write_raw(os, mesh, s); break;
        case VtuOptions::Encoding::zlib: write_zlib(os, mesh, s); break;
        case VtuOptions::Encoding::ascii:
            put_xml(os, mesh, s, options.encoding, {});
            os << "</VTKFile>\n";
            break;
    }
}

template <class M>
void write_vtu_stream(const M& mesh, std::ostream& os, const VtuOptions& options) {
    const detail::MeshView view = detail::view_of(mesh);
    detail::check_mesh_arrays(view, "<vtu stream>");
    write_view(view, os, options);
}

}  // namespace

void write_vtu(const Mesh& mesh, std::ostream& os, const VtuOptions& options) { write_vtu_stream(mesh, os, options); }
void write_vtu(const TetMesh& mesh, std::ostream& os, const VtuOptions& options) { write_vtu_stream(mesh, os, options); }
void write_vtu(const Mesh& mesh, const std::string& path, const VtuOptions& options) {
    detail::write_mesh_file(mesh, path, [&](const detail::MeshView& v, std::ostream& os) { write_view(v, os, options); });
}
void write_vtu(const TetMesh& mesh, const std::string& path, const VtuOptions& options) {
    detail::write_mesh_file(mesh, path, [&](const detail::MeshView& v, std::ostream& os) { write_view(v, os, options); });
}

void write_pvtu(const std::string& path, std::span<const std::string> pieces) {
    write_file_atomically(path, [&](std::ostream& os) {
    os << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
          "header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n"
          "    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n    </PPoints>\n"
          "    <PPointData Scalars=\"boundary_marker\" GlobalIds=\"GlobalIds\">\n"
          "      <PDataArray type=\"Int32\" Name=\"boundary_marker\"/>\n      <PDataArray type=\"Int64\" Name=\"GlobalIds\"/>\n"
          "    </PPointData>\n    <PCellData Scalars=\"region\" GlobalIds=\"GlobalIds\">\n"
          "      <PDataArray type=\"Int32\" Name=\"region\"/>\n      <PDataArray type=\"Int64\" Name=\"GlobalIds\"/>\n"
          "    </PCellData>\n";
    for (const std::string& piece : pieces) os << "    <Piece Source=\"" << detail::xml_escape(piece) << "\"/>\n";
    os << "  </PUnstructuredGrid>\n</VTKFile>\n";
    });
}

}  // namespace warpmesh
