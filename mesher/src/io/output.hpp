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
// cell and each format's name for it) and a flat span of vertex indices, so
// the same writer code serves triangles (now) and tetrahedra (the 3D mesher).
#pragma once

#include <algorithm>
#include <atomic>
#include <charconv>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "warpmesh/mesh.hpp"

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
};
inline constexpr CellKind line_cells{2, 1, 3, 1, "Polyline", "T2D2"};
inline constexpr CellKind triangle_cells{3, 2, 5, 2, "Triangle", "CPS3"};
inline constexpr CellKind tetra_cells{4, 3, 10, 4, "Tetrahedron", "C3D4"};

// `nodes.size() / kind.nodes` cells, cell i's vertices at nodes[i*kind.nodes …].
struct Cells {
    CellKind kind;
    std::span<const std::int32_t> nodes;
    std::size_t size() const { return nodes.size() / static_cast<std::size_t>(kind.nodes); }
    std::span<const std::int32_t> operator[](std::size_t i) const {
        return nodes.subspan(i * static_cast<std::size_t>(kind.nodes), static_cast<std::size_t>(kind.nodes));
    }
};

// The mesh's triangles as Cells (no copy: std::array<int32_t, 3> is three
// packed int32_t).
inline Cells cells_of(const Mesh& mesh) {
    static_assert(sizeof(mesh.triangles[0]) == 3 * sizeof(std::int32_t));
    return {triangle_cells, {mesh.triangles.empty() ? nullptr : mesh.triangles.front().data(), 3 * mesh.triangles.size()}};
}

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
// (dynamic schedule) and consume(buffer) for each block in block order, one
// at a time, while other threads produce later blocks.  Each thread owns one
// Buffer: memory is (threads x one block), whatever count is.  An exception
// from produce or consume stops the work and is rethrown here.
template <class Buffer, class Produce, class Consume>
void ordered_blocks(std::size_t count, Produce&& produce, Consume&& consume) {
    std::exception_ptr error;
    std::atomic<bool> failed{false};
    auto keep = [&] {
#pragma omp critical(warpmesh_ordered_blocks)
        if (!error) error = std::current_exception();
        failed = true;
    };
    const auto n = static_cast<std::int64_t>(count);
#pragma omp parallel
    {
        Buffer buf;
#pragma omp for ordered schedule(dynamic, 1)
        for (std::int64_t b = 0; b < n; ++b) {
            if (!failed) try {
                    produce(static_cast<std::size_t>(b), buf);
                } catch (...) {
                    keep();
                }
#pragma omp ordered
            {
                if (!failed) try {
                        consume(buf);
                    } catch (...) {
                        keep();
                    }
            }
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
// (little-endian host layout: the writers say LittleEndian).
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
