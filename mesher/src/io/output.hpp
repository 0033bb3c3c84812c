// output.hpp — the writers' shared core: cell kinds, number formatting, text
// formatted in parallel blocks and binary arrays written through bounded
// buffers.
//
// Contract of every writer built on it: the file is produced in one pass,
// front to back, holding at most a bounded buffer per thread beyond the mesh
// itself (streaming), and numbers are printed as the shortest decimal that
// reads back to the same double (std::to_chars), so text round-trips exactly.
//
// Cells are a parameter, not a type: a Cells view is a CellKind (nodes per
// cell and each format's name for it) and a flat span of vertex indices, and
// a MeshView is a Mesh or a TetMesh seen through them, so the same writer
// code serves triangles and tetrahedra.
#pragma once

#include <algorithm>
#include <array>
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "io/atomic_file.hpp"
#include "warpmesh/core/mesh.hpp"
#include "warpmesh/core/tet_mesh.hpp"

namespace warpmesh::detail {

// ---- cell kinds -------------------------------------------------------------------

// One kind of cell as each format names it.  Node order is the one all these
// formats share for simplices (counter-clockwise triangles; tetrahedra with
// positive orientation).
struct CellKind {
    int nodes;               // vertices per cell
    int dim;                 // topological dimension
    std::uint8_t vtk;        // VTK cell type (VTK_TRIANGLE 5, VTK_TETRA 10, VTK_LINE 3)
    std::int32_t gmsh;       // Gmsh element type (2 triangle, 4 tetrahedron, 1 line)
    std::string_view xdmf;   // XDMF TopologyType
    std::string_view abaqus; // Abaqus element type
    std::string_view medit;  // medit (.mesh) section keyword
};
inline constexpr CellKind line_cells{2, 1, 3, 1, "Polyline", "T2D2", "Edges"};
inline constexpr CellKind triangle_cells{3, 2, 5, 2, "Triangle", "CPS3", "Triangles"};
inline constexpr CellKind tetra_cells{4, 3, 10, 4, "Tetrahedron", "C3D4", "Tetrahedra"};

// `nodes.size() / kind.nodes` cells, cell i's vertices at nodes[i*kind.nodes …].
struct Cells {
    CellKind kind;
    std::span<const std::int32_t> nodes;
    std::size_t size() const { return nodes.size() / static_cast<std::size_t>(kind.nodes); }
    std::span<const std::int32_t> operator[](std::size_t i) const {
        return nodes.subspan(i * static_cast<std::size_t>(kind.nodes), static_cast<std::size_t>(kind.nodes));
    }
};

// ---- the mesh as the writers see it -------------------------------------------------

// A read-only view of a triangle mesh (Mesh) or a tetrahedral mesh (TetMesh):
// what every writer needs, with the cell shape as a parameter.  Facets are
// the cells' faces of one dimension lower (edges of triangles, triangles of
// tetrahedra); boundary facets and interface facets are flat node lists of
// `facet_kind.nodes` vertices each, oriented as in mesh.hpp / tet_mesh.hpp
// (the meshed region on the left of an edge, below an outward-normal
// triangle).  No copy is made: the spans point into the mesh.
struct MeshView {
    int dim = 2;                          // coordinates per vertex (2 or 3)
    std::size_t num_vertices = 0;
    const double* coords = nullptr;       // num_vertices x dim, packed (Vec2, Point3)
    Cells cells{triangle_cells, {}};
    CellKind facet_kind = line_cells;
    std::span<const std::int32_t> region;
    std::span<const std::int32_t> boundary;      // flat, facet_kind.nodes each
    std::span<const std::int32_t> boundary_tag;  // one per boundary facet
    std::span<const std::int32_t> interfaces;    // flat, facet_kind.nodes each
    std::span<const std::array<std::int32_t, 2>> interface_regions;
    std::span<const std::pair<std::int32_t, std::string>> region_names;
    std::span<const std::pair<std::string, Buffer<double>>> cell_data;

    std::size_t num_boundary() const { return boundary.size() / static_cast<std::size_t>(facet_kind.nodes); }
    std::size_t num_interfaces() const { return interfaces.size() / static_cast<std::size_t>(facet_kind.nodes); }
    // Coordinate k (0 x, 1 y, 2 z; z = 0 for a 2D mesh) of vertex i.
    double coord(std::size_t i, int k) const { return k < dim ? coords[i * static_cast<std::size_t>(dim) + static_cast<std::size_t>(k)] : 0.0; }
};

// A span of N-element int32 arrays as a flat span (std::array<int32_t, N> is
// N packed int32_t).
template <std::size_t N, class Container>
std::span<const std::int32_t> flat(const Container& c) {
    static_assert(sizeof(std::array<std::int32_t, N>) == N * sizeof(std::int32_t));
    return {c.empty() ? nullptr : c.front().data(), N * c.size()};
}

inline MeshView view_of(const Mesh& m) {
    static_assert(sizeof(Vec2) == 2 * sizeof(double));
    return {2, m.vertices.size(), m.vertices.empty() ? nullptr : &m.vertices.front().x, {triangle_cells, flat<3>(m.triangles)},
            line_cells, m.region, flat<2>(m.boundary), m.boundary_tag, flat<2>(m.interfaces), m.interface_regions,
            m.region_names, m.cell_data};
}

inline MeshView view_of(const TetMesh& m) {
    static_assert(sizeof(m.vertices[0]) == 3 * sizeof(double));
    return {3, m.vertices.size(), m.vertices.empty() ? nullptr : &m.vertices.front().x, {tetra_cells, flat<4>(m.tets)},
            triangle_cells, m.region, flat<3>(m.boundary), m.boundary_tag, flat<3>(m.interfaces), m.interface_regions,
            m.region_names, m.cell_data};
}

// The mesh's triangles as Cells (no copy).
inline Cells cells_of(const Mesh& mesh) { return view_of(mesh).cells; }

// Throws OutputError("cannot write 'PATH': invalid mesh: …") unless every
// per-cell array (region, cell_data) has one entry per cell, boundary_tag one
// per boundary facet, interface_regions one per interface facet with two
// different regions, and every vertex index is in range.
void check_mesh_arrays(const MeshView& mesh, const std::string& path);

// Checks `mesh`'s arrays (check_mesh_arrays), then writes `path` atomically
// (atomic_file.hpp) with write(view, stream).
template <class M, class Write>
void write_mesh_file(const M& mesh, const std::string& path, Write&& write) {
    const MeshView view = view_of(mesh);
    check_mesh_arrays(view, path);
    write_file_atomically(path, [&](std::ostream& os) { write(view, os); });
}

// ---- named groups, shared by the formats that tag or name them ------------------
//
// Regions: the name of region tag `tag` is its mesh.region_names entry, else
// "domain" when the mesh has one region, else "domain_<tag>".
std::string region_name(const MeshView& mesh, std::int32_t tag, bool single_region);

// The distinct region tags of `mesh`, in increasing order.
std::vector<std::int32_t> region_tags(const MeshView& mesh);

// Tagged facets (edges in 2D, triangles in 3D): one group per boundary tag
// (in increasing tag order), then one per unordered pair of regions {a < b}
// that share interface facets.
//  * A boundary group's tag is the boundary tag itself when every boundary tag
//    is >= 1 (the meshers' 1 and 2), else the 1-based rank of the tag; its
//    name is "boundary" (tag 1, the level set), "domain_border" (tag 2, the
//    lattice border) or "boundary_<tag>".  Its facets are as in mesh.boundary
//    (oriented outwards: the meshed region on their left / below them).
//  * An interface group's tag is max(2, largest boundary group tag) + 1 + its
//    rank among the pairs (so 3, 4, … for a mesher's mesh); its name is
//    "interface_<a>_<b>" with the region tags; its facets are reoriented so
//    that they face out of region a (a on the left of an edge, behind a
//    triangle) for all of them.
// Group tags are the facet tags of every format (.msh physical curves or
// surfaces, XDMF facet_tags, .poly/.node markers, medit refs); they are >= 1
// and distinct.
struct FacetGroup {
    std::int32_t tag;
    std::string name;
    bool interface = false;
    std::int32_t left_region = 0, right_region = 0;  // interfaces only
    std::vector<std::size_t> index;                  // into mesh.boundary or mesh.interfaces
    CellKind kind = line_cells;                      // the facets' kind
    std::vector<std::int32_t> nodes;                 // flat, oriented as described above
    std::size_t size() const { return index.size(); }
    Cells facets() const { return {kind, nodes}; }
};
std::vector<FacetGroup> facet_groups(const MeshView& mesh);

// One marker per vertex: the smallest facet-group tag of the boundary facets
// at the vertex, else the smallest of the interface facets at it, else 0.
std::vector<std::int32_t> vertex_markers(const MeshView& mesh, const std::vector<FacetGroup>& groups);

// ---- text ------------------------------------------------------------------------

// A text buffer with number formatting: shortest round-trip doubles, integers.
class TextBuf {
public:
    TextBuf& operator<<(std::string_view s) { return s_.append(s), *this; }
    TextBuf& operator<<(char c) { return s_.push_back(c), *this; }
    TextBuf& operator<<(double x) { return put(x); }
    TextBuf& operator<<(std::int32_t i) { return put(i); }
    TextBuf& operator<<(std::int64_t i) { return put(i); }
    TextBuf& operator<<(std::uint64_t i) { return put(i); }
    // Fixed notation with `digits` decimals (SVG coordinates).
    TextBuf& fixed(double x, int digits) {
        char tmp[64];
        const auto r = std::to_chars(tmp, tmp + sizeof tmp, x, std::chars_format::fixed, digits);
        return s_.append(tmp, r.ptr), *this;
    }
    std::size_t size() const { return s_.size(); }
    const char* data() const { return s_.data(); }
    void clear() { s_.clear(); }

private:
    template <class T>
    TextBuf& put(T x) {
        char tmp[64];
        const auto r = std::to_chars(tmp, tmp + sizeof tmp, x);
        return s_.append(tmp, r.ptr), *this;
    }
    std::string s_;
};

// A TextBuf written out to a stream whenever it holds ~1 MiB (and on
// destruction): sequential text of bounded memory.
class TextSink {
public:
    explicit TextSink(std::ostream& out) : out_(out) {}
    ~TextSink() { flush(); }
    TextSink(const TextSink&) = delete;
    TextSink& operator=(const TextSink&) = delete;

    template <class T>
    TextSink& operator<<(const T& x) {
        buf_ << x;
        if (buf_.size() >= chunk) flush();
        return *this;
    }
    TextSink& fixed(double x, int digits) {
        buf_.fixed(x, digits);
        return *this;
    }
    void flush() {
        if (buf_.size()) out_.write(buf_.data(), static_cast<std::streamsize>(buf_.size()));
        buf_.clear();
    }
    std::ostream& stream() { return flush(), out_; }

private:
    static constexpr std::size_t chunk = std::size_t{1} << 20;
    std::ostream& out_;
    TextBuf buf_;
};

// Runs produce(b, buffer) for the blocks b = 0 … count-1 on all OpenMP threads
// and consume(buffer) for each block in block order.  The blocks go in rounds
// of a few per thread: the round's blocks are produced in parallel (dynamic
// schedule), then consumed in order by one thread.  Memory is one Buffer per
// block of a round, whatever count is.  (An `omp ordered` loop had threads
// spin-wait for their turn: on a loaded machine most of the CPU went there.)
// An exception from produce or consume stops the work and is rethrown here.
template <class Buffer, class Produce, class Consume>
void ordered_blocks(std::size_t count, Produce&& produce, Consume&& consume) {
#ifdef _OPENMP
    const auto round = static_cast<std::size_t>(4 * std::max(1, omp_get_max_threads()));
#else
    const std::size_t round = 4;
#endif
    std::vector<Buffer> bufs(std::min(count, round));
    std::exception_ptr error;
    for (std::size_t first = 0; first < count && !error; first += round) {
        const auto n = static_cast<std::int64_t>(std::min(round, count - first));
#pragma omp parallel for schedule(dynamic, 1) if (n > 1)
        for (std::int64_t b = 0; b < n; ++b) {
            try {
                produce(first + static_cast<std::size_t>(b), bufs[static_cast<std::size_t>(b)]);
            } catch (...) {
#pragma omp critical(warpmesh_ordered_blocks)
                if (!error) error = std::current_exception();
            }
        }
        if (error) break;
        try {
            for (std::int64_t b = 0; b < n; ++b) consume(bufs[static_cast<std::size_t>(b)]);
        } catch (...) {
            error = std::current_exception();
        }
    }
    if (error) std::rethrow_exception(error);
}

// The text of items 0 … count-1, format(buf, i) appending item i's, written
// to `out` in order; items are formatted in blocks in parallel
// (ordered_blocks).  `out` must have no pending text of a TextSink (flush it
// first: TextSink::stream()).
template <class Format>
void write_text_parallel(std::ostream& out, std::size_t count, Format&& format) {
    constexpr std::size_t block = 8192;
    ordered_blocks<TextBuf>(
        (count + block - 1) / block,
        [&](std::size_t b, TextBuf& buf) {
            buf.clear();
            const std::size_t end = std::min(count, (b + 1) * block);
            for (std::size_t i = b * block; i < end; ++i) format(buf, i);
        },
        [&](const TextBuf& buf) { out.write(buf.data(), static_cast<std::streamsize>(buf.size())); });
}

// ---- binary -----------------------------------------------------------------------

inline void write_bytes(std::ostream& out, const void* p, std::size_t n) {
    out.write(static_cast<const char*>(p), static_cast<std::streamsize>(n));
}
template <class T>
void write_value(std::ostream& out, T x) {
    write_bytes(out, &x, sizeof x);
}

// Items 0 … count-1 of `item_bytes` bytes each, fill(dst, first, n) writing
// items first … first+n-1 to dst, streamed to `out` through a bounded buffer
// (little-endian host layout: the writers say LittleEndian).  Arrays already
// in memory as written go through it too: the kernel copies from a small,
// reused buffer several times faster than from a large array in one write(2)
// (docs/performance.md, "Writers").
template <class Fill>
void write_binary(std::ostream& out, std::size_t count, std::size_t item_bytes, Fill&& fill) {
    const std::size_t per = std::max<std::size_t>(1, (std::size_t{1} << 20) / item_bytes);
    std::vector<std::byte> buf(std::min(count, per) * item_bytes);
    for (std::size_t first = 0; first < count; first += per) {
        const std::size_t n = std::min(per, count - first);
        fill(buf.data(), first, n);
        write_bytes(out, buf.data(), n * item_bytes);
    }
}

}  // namespace warpmesh::detail
