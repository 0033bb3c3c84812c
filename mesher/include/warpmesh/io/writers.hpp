// writers.hpp — mesh output formats.
//
//   write_vtu.cpp      → VTK XML UnstructuredGrid (.vtu): appended raw binary,
//                        zlib-compressed appended binary, or ASCII inline
//   write_msh.cpp      → Gmsh MSH 4.1 or 2.2 (.msh), binary or ASCII
//   write_xdmf.cpp     → XDMF 3 (.xdmf + _facets.xdmf), heavy data in HDF5
//                        (.h5 + _facets.h5) or inline XML
//   write_inp.cpp      → Abaqus/CalculiX input (.inp): nodes, CPS3, sets, surfaces
//   write_triangle.cpp → Triangle's .node/.ele (+ .poly with the boundary)
//   write_svg.cpp      → an SVG picture
//   write_png.cpp      → a PNG picture (libpng), anti-aliased, for figures
//   write_medit.cpp    → medit/MMG .mesh (ASCII): vertices, cells and facets
//                        with references
//
// Tetrahedral meshes (TetMesh, the 3D mesher's output) go to the same
// formats through the same code (.vtu, .msh, .xdmf, .inp, .mesh): the cells
// are tetrahedra, the tagged facets are triangles, and every tag and name
// means what it means for triangles (see each format's comment).  Pictures
// and Triangle's formats are 2D only.
//
// Every file is written atomically (src/io/atomic_file.hpp): on failure nothing
// appears under the requested name and OutputError (errors.hpp) names the
// path and the reason.
// Binary by default where the format has it (WriteOptions::ascii for text);
// .inp and .node/.ele are ASCII by specification.  Text prints coordinates and
// cell data as the shortest decimal that reads back to the same double
// (std::to_chars), so text formats round-trip exactly, and is formatted in
// parallel blocks (OpenMP threads).  No writer holds the whole file in
// memory: each streams its file through bounded buffers (src/io/output.hpp).
#pragma once

#include <array>
#include <charconv>
#include <cstdint>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/core/mesh.hpp"
#include "warpmesh/core/tet_mesh.hpp"

namespace warpmesh {

struct SvgOptions {
    // Fill each triangle by its minimum angle (0° red … 60° green) with a legend.
    bool color_by_min_angle = false;
    // Fill each triangle by this mesh.cell_data array (its min … max range), with
    // a legend; takes precedence over color_by_min_angle.  An unknown name is an
    // OutputError.
    std::string color_by_cell_data;
    // Size of the picture's long side, in px (the mesh's aspect ratio is kept).
    double long_side_px = 1000;
    // Draw the interior edges (thin).  Off is useful for very fine meshes.
    bool draw_edges = true;
    // Axis-aligned boxes {xmin, ymin, xmax, ymax} (mesh coordinates) outlined
    // in magenta on top of the mesh, with `marked_label` in a note: the mesher
    // marks the warped squares whose stencil is not flat this way.
    std::vector<std::array<double, 4>> marked_boxes;
    std::string marked_label;
};

struct PngOptions {
    // Size of the picture's long side, in px, legend excluded (the legend adds
    // columns on the right).  The mesh's aspect ratio is kept.
    int long_side_px = 1600;
    // Samples per pixel along each axis (anti-aliasing by supersampling): the
    // picture is rendered at supersample x supersample samples per pixel and
    // box-filtered down.  1 to 8.
    int supersample = 4;
    // Fill each triangle by its minimum angle (0° red … 60° green), with a
    // colour-bar legend.
    bool color_by_min_angle = false;
    // Fill each triangle by this mesh.cell_data array (its finite min … max
    // range; non-finite values grey), with a legend; takes precedence over
    // color_by_min_angle.  An unknown name is an OutputError.
    std::string color_by_cell_data;
    // Draw the interior edges (thin, dark).  They fade out by themselves when
    // the triangles are only a few pixels wide.
    bool draw_edges = true;
    // Label the legend (title, minimum, middle, maximum) with a built-in
    // 5x7 bitmap font.
    bool legend_labels = true;
};

struct MshOptions {
    // MSH file format version: 41 (4.1, Gmsh's current) or 22 (2.2, the one many
    // solvers' importers still expect).  Anything else is an OutputError.
    int version = 41;
    // Binary (file-type 1, little-endian, sizeof(size_t) = 8) or ASCII.
    bool binary = true;
    // Write mesh.cell_data as $ElementData views.  Off by default: a .msh is a
    // solver's input, and its readers (meshio) require a data value for every
    // element, boundary lines included (see write_msh.cpp).
    bool cell_data = false;
};

struct VtuOptions {
    // raw: appended raw binary (VTK's and ParaView's fastest); zlib: appended
    // binary, each array compressed in blocks with zlib; ascii: inline text.
    enum class Encoding { raw, zlib, ascii };
    Encoding encoding = Encoding::raw;
    // A piece of a partitioned mesh (write_pvtu): per point and per cell its
    // global id (Int64 arrays "GlobalIds", VTK's global-id attribute, so that
    // readers match the points pieces share); written when global_ids is set
    // or the spans are not empty (a piece with no point has them too, empty,
    // as its .pvtu declares them).
    std::span<const std::uint64_t> point_global_ids, cell_global_ids;
    bool global_ids = false;
};

struct XdmfOptions {
    // Heavy data in HDF5 files beside the XDMF files (STEM.h5, STEM_facets.h5),
    // as dolfinx writes it; false: inline XML text, each file self-contained
    // (for tiny meshes).  HDF5 needs the build to have found libhdf5
    // (WARPMESH_HAVE_HDF5), else it is an OutputError.
    bool hdf5 = true;
    // The path the .xdmf file will finally have, when it is written under a
    // temporary name and renamed afterwards (the CLI stages its outputs): the
    // XDMF files name their .h5 files by it.  Empty: the path written.
    std::string final_path;
};

struct WriteOptions {
    // Every output as text: .vtu inline ASCII, .msh ASCII, .xdmf inline XML
    // (the CLI's --ascii).  Overrides vtu.encoding, msh.binary, xdmf.hdf5.
    bool ascii = false;
    VtuOptions vtu;
    MshOptions msh;
    XdmfOptions xdmf;
    SvgOptions svg;
    // .png pictures.  The dispatcher also colours the PNG by minimum angle when
    // svg.color_by_min_angle is set (the CLI's --svg-color minangle), so that
    // one option colours every picture.
    PngOptions png;
};

// Chooses the format by the (case-insensitive) extension of `path`: .vtu,
// .msh, .xdmf (plus STEM_facets.xdmf, and with HDF5 STEM.h5 and
// STEM_facets.h5), .inp, .mesh, .node or .ele (both are written,
// plus .poly, with the same stem), .svg, .png.
// Anything else is an OutputError listing the supported extensions.
void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options = {});
// The same for tetrahedra: .vtu, .msh, .xdmf, .inp, .mesh; a 2D-only format
// (.node/.ele/.poly, .svg, .png) is an OutputError naming the 3D formats.
void write_mesh(const TetMesh& mesh, const std::string& path, const WriteOptions& options = {});

// Throws OutputError if write_mesh(TetMesh) would refuse `path` (a 2D-only or
// unknown format, or a missing directory) — checked before any work is done.
void check_output_path_3d(const std::string& path);

// Throws OutputError if write_mesh would refuse `path` for its extension or
// because its directory does not exist — checked before any work is done.
void check_output_path(const std::string& path);

// True if write_mesh(mesh, path, options) exports mesh.cell_data (.vtu; .msh
// with options.msh.cell_data).
bool format_carries_cell_data(const std::string& path, const WriteOptions& options = {});

// Writes `text` to `path` atomically (a temporary file renamed when complete;
// nothing under `path` on failure).  Throws OutputError naming `path`.
void write_text_file(const std::string& path, std::string_view text);

// The part of check_output_path that does not depend on the format: `path` is
// not a directory, and its directory exists and is writable.  Throws OutputError.
void check_writable(const std::string& path);

// The files that write_mesh(mesh, path, options) creates: `path` itself, for
// XDMF also STEM_facets.xdmf (and with HDF5 STEM.h5, STEM_facets.h5), for the
// Triangle format the stem's .node, .ele and .poly.
std::vector<std::string> output_files(const std::string& path, const WriteOptions& options = {});

// VTK XML UnstructuredGrid (version 1.0, header UInt64, LittleEndian).
// Points are 3D with z = 0; cells are the triangles only (VTK_TRIANGLE = 5;
// boundary edges are not written — use .msh or .poly for them); CellData:
// "region" (Int32) and every mesh.cell_data array (Float64); PointData:
// "boundary_marker" (Int32, detail::vertex_markers, the same markers as the
// .node file).  See write_vtu.cpp for the appended layouts.
void write_vtu(const Mesh& mesh, const std::string& path, const VtuOptions& options = {});
void write_vtu(const Mesh& mesh, std::ostream& out, const VtuOptions& options = {});
void write_vtu(const TetMesh& mesh, const std::string& path, const VtuOptions& options = {});
void write_vtu(const TetMesh& mesh, std::ostream& out, const VtuOptions& options = {});
// The collection file of a partitioned tetrahedral mesh (.pvtu, VTK's
// PUnstructuredGrid): its pieces, .vtu files written by write_vtu with
// global ids (named as given, relative to the .pvtu's folder), each with the
// arrays write_vtu writes (boundary_marker, GlobalIds; region, GlobalIds),
// and no cell data arrays but those.  Written atomically; OutputError.
void write_pvtu(const std::string& path, std::span<const std::string> pieces);

// Gmsh MSH 4.1 or 2.2, binary or ASCII; see write_msh.cpp for the
// entity/physical layout: one named physical group per region, per boundary
// tag and per interface.
void write_msh(const Mesh& mesh, const std::string& path, const MshOptions& options = {});
void write_msh(const Mesh& mesh, std::ostream& out, const MshOptions& options = {});
void write_msh(const TetMesh& mesh, const std::string& path, const MshOptions& options = {});
void write_msh(const TetMesh& mesh, std::ostream& out, const MshOptions& options = {});

// XDMF 3 for FEniCSx (and meshio, ParaView): `path` holds the mesh (grid
// "mesh": triangles, XY points, cell attribute "region") and STEM_facets.xdmf
// the tagged edges (grid "facets": boundary and interface lines, attribute
// "facet_tags" = detail::edge_groups' tags); heavy data in STEM.h5 and
// STEM_facets.h5 or inline; see write_xdmf.cpp.  Every file is complete
// under a temporary name before any is renamed into place (the .h5 files
// first), so a failed write leaves none of them.
void write_xdmf(const Mesh& mesh, const std::string& path, const XdmfOptions& options = {});
// The inline-XML documents (XdmfOptions::hdf5 false).
void write_xdmf_mesh(const Mesh& mesh, std::ostream& out);
void write_xdmf_facets(const Mesh& mesh, std::ostream& out);
void write_xdmf(const TetMesh& mesh, const std::string& path, const XdmfOptions& options = {});
void write_xdmf_mesh(const TetMesh& mesh, std::ostream& out);
void write_xdmf_facets(const TetMesh& mesh, std::ostream& out);

// Abaqus/CalculiX input: *NODE, *ELEMENT TYPE=CPS3, an *ELSET per region, an
// *NSET and an element-edge *SURFACE per boundary tag and per interface; see
// write_inp.cpp.
void write_inp(const Mesh& mesh, const std::string& path);
void write_inp(const Mesh& mesh, std::ostream& out);
void write_inp(const TetMesh& mesh, const std::string& path);
void write_inp(const TetMesh& mesh, std::ostream& out);

// medit/MMG mesh (.mesh, "MeshVersionFormatted 2", ASCII, 1-based):
// Vertices (ref = detail::vertex_markers), the cells (Triangles or
// Tetrahedra, ref = region tag), then the tagged facets (Edges or Triangles,
// ref = facet-group tag, as the .msh physical groups); see write_medit.cpp.
void write_medit(const Mesh& mesh, const std::string& path);
void write_medit(const Mesh& mesh, std::ostream& out);
void write_medit(const TetMesh& mesh, const std::string& path);
void write_medit(const TetMesh& mesh, std::ostream& out);

// Triangle's formats, 1-based: STEM.node ("N 2 0 1": the vertex's marker,
// detail::vertex_markers: the boundary tag of a boundary vertex as on the
// .poly segments, an interface's tag, 0 inside), STEM.ele ("T 3 1": the
// region tag as attribute) and STEM.poly (no vertices — they are in .node —
// the boundary edges as segments with their tag as marker, then the
// interface edges with theirs, no holes).  `path` may name any of the three
// files or the bare stem.
void write_triangle(const Mesh& mesh, const std::string& path);
void write_triangle_node(const Mesh& mesh, std::ostream& out);
void write_triangle_ele(const Mesh& mesh, std::ostream& out);
void write_triangle_poly(const Mesh& mesh, std::ostream& out);

// SVG picture: one <polygon> per triangle, boundary edges as <path>s coloured
// by tag (level set: red, lattice border: blue), y flipped so that y-up is up.
void write_svg(const Mesh& mesh, const std::string& path, const SvgOptions& options = {});
void write_svg(const Mesh& mesh, std::ostream& out, const SvgOptions& options = {});

// PNG picture (8-bit RGB), drawn with libpng: white background, light triangle
// fill (or a colour by minimum angle / cell data, with a colour bar on the
// right), thin dark interior edges, boundary edges thicker and coloured by tag
// (level set: red, lattice border: blue); y up.  Anti-aliased by
// supersampling.  Throws OutputError if the build has no libpng
// (WARPMESH_HAVE_PNG) or on any failure; written atomically.
void write_png(const Mesh& mesh, const std::string& path, const PngOptions& options = {});
void write_png(const Mesh& mesh, std::ostream& out, const PngOptions& options = {});

namespace detail {

// What a picture (SVG or PNG) colours its triangles by: a cell data array
// (by name, its finite min … max range) or, failing that and if asked, each
// triangle's minimum angle over 0°–60°; `title` empty = no colouring.  An
// unknown array name is an OutputError naming `what` ("SVG", "PNG").
struct Colouring {
    std::vector<double> value;
    std::string title;
    double lo = 0, hi = 60;
    // cell_data_name "region" (with no cell data array of that name): each
    // triangle's region tag, to be coloured by region_colour (no legend).
    bool by_region = false;

    // A value scale to draw beside the picture (not for regions).
    bool legend() const { return !title.empty() && !by_region; }
    // Triangle k's value mapped to [0, 1] over lo … hi.
    double normalised(std::size_t k) const { return (value[k] - lo) / (hi > lo ? hi - lo : 1); }
};
// A distinct colour per region tag (golden-angle hues), as 0xRRGGBB.
std::uint32_t region_colour(std::int32_t tag);
// The edge length, in picture pixels at `scale` pixels per mesh unit, of an
// equilateral triangle of the mesh's mean triangle area: what the pictures
// scale their line widths by.  10 for a mesh without triangles.
double typical_edge_px(const Mesh& mesh, double scale);

Colouring picture_colouring(const Mesh& mesh, const std::string& cell_data_name, bool by_min_angle,
                            const std::string& what);

// `path` without a (case-insensitive) .node/.ele/.poly extension: the stem of
// the Triangle files.  Any other path is returned unchanged.
std::string triangle_stem(const std::string& path);

// `s` escaped for an XML attribute value or text (& < > " ').
std::string xml_escape(std::string_view s);

// The facet-tag file written beside the XDMF file `path`: STEM_facets.xdmf
// (the extension keeps its case).
std::string xdmf_facets_path(const std::string& path);
// The HDF5 file of the XDMF file `path`: STEM.h5.
std::string xdmf_h5_path(const std::string& path);

}  // namespace detail

}  // namespace warpmesh
