// fuzz_checks.hpp — what the fuzz targets check, shared with the regression
// tests.
//
// tests/fuzz/fuzz_image_reader.cpp and tests/fuzz/fuzz_pipeline.cpp are thin
// libFuzzer entry points around check_image_reader and check_pipeline;
// tests/test_degenerate.cpp replays the seed corpus and every crash found so
// far (tests/fuzz/regressions/) through the same two functions.  A violated
// invariant prints what went wrong and calls std::abort(), which both
// libFuzzer and Boost.Test report as a failure.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "warpmesh/certified.hpp"
#include "warpmesh/errors.hpp"
#include "warpmesh/graded.hpp"
#include "../mesh_math.hpp"
#include "graded/quadtree.hpp"
#include "graded/tiles.hpp"
#include "warpmesh/image.hpp"
#include "warpmesh/image_levelset.hpp"
#include "warpmesh/lattice.hpp"
#include "warpmesh/mesh_checks.hpp"
#include "warpmesh/uniform.hpp"
#include "../without_range.hpp"

namespace warpmesh::fuzz {

// The certified theorem U of the rule (proofs/*.cert, compiled in), as
// degrees with round-off slack: every angle of every mesh lies in it.  Each
// warped square is also checked against its own key's interval by the
// mesher's verify pass (a violation throws std::logic_error: a crash here).
struct AngleBounds {
    double min_deg, max_deg;
};
inline AngleBounds certified_bounds(DiagonalRule rule) {
    const CertifiedTheorem t = certified_theorem(rule);
    return {t.min_deg_any - 1e-6, t.max_deg_any + 1e-6};
}

// Pixel limit of the image-reader target: small, so that no input can make
// the reader allocate much.
inline constexpr std::uint64_t fuzz_max_pixels = std::uint64_t{1} << 16;

[[noreturn]] inline void violation(const std::string& what) {
    std::fprintf(stderr, "fuzz invariant violated: %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

// ---------------------------------------------------------------------------
// Target 1: the image readers.  Either a consistent Image or an InputError.
inline void check_one_image(std::span<const std::uint8_t> bytes) {
    Image img;
    try {
        img = decode_image(bytes, "fuzz-input", fuzz_max_pixels);
    } catch (const InputError& e) {
        if (std::string(e.what()).find("fuzz-input") == std::string::npos)
            violation(std::string("an InputError does not name the input: ") + e.what());
        return;
    }
    if (img.width < 1 || img.height < 1) violation("decoded image with a zero dimension");
    const std::uint64_t n = static_cast<std::uint64_t>(img.width) * static_cast<std::uint64_t>(img.height);
    if (n > fuzz_max_pixels) violation("decoded image larger than max_pixels");
    if (img.pixels.size() != n) violation("pixel count differs from width x height");
    if (img.maxval < 1 || img.maxval > 65535) violation("maxval out of 1..65535");
    for (std::uint16_t v : img.pixels)
        if (v > img.maxval) violation("a sample exceeds maxval");
}

// PNG chunks carry a CRC, so almost every mutation of a PNG is refused at the
// first chunk.  To reach the decoder proper, a PNG input is also decoded with
// every complete chunk's CRC recomputed (the raw bytes are decoded too, so
// the CRC errors stay covered).
inline std::uint32_t crc32(const std::uint8_t* p, std::size_t n) {
    std::uint32_t c = 0xffffffffu;
    for (std::size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
}

// The bytes with the CRC of every complete chunk recomputed; false if the
// input is not a PNG or no CRC changed.
inline bool png_with_fixed_crcs(std::span<const std::uint8_t> in, std::vector<std::uint8_t>& out) {
    static constexpr std::uint8_t sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    if (in.size() < 8 || !std::equal(sig, sig + 8, in.begin())) return false;
    out.assign(in.begin(), in.end());
    bool changed = false;
    std::size_t pos = 8;
    while (pos + 12 <= out.size()) {
        const std::uint64_t len = std::uint64_t{out[pos]} << 24 | std::uint64_t{out[pos + 1]} << 16 |
                                  std::uint64_t{out[pos + 2]} << 8 | out[pos + 3];
        if (len > out.size() - pos - 12) break;
        const std::size_t end = pos + 8 + static_cast<std::size_t>(len);
        const std::uint32_t crc = crc32(out.data() + pos + 4, static_cast<std::size_t>(len) + 4);
        const std::uint8_t b[4] = {static_cast<std::uint8_t>(crc >> 24), static_cast<std::uint8_t>(crc >> 16),
                                   static_cast<std::uint8_t>(crc >> 8), static_cast<std::uint8_t>(crc)};
        if (!std::equal(b, b + 4, out.begin() + static_cast<std::ptrdiff_t>(end))) {
            std::copy(b, b + 4, out.begin() + static_cast<std::ptrdiff_t>(end));
            changed = true;
        }
        pos = end + 4;
    }
    return changed;
}

inline void check_image_reader(std::span<const std::uint8_t> bytes) {
    check_one_image(bytes);
    std::vector<std::uint8_t> fixed;
    if (png_with_fixed_crcs(bytes, fixed)) check_one_image(fixed);
}

// ---------------------------------------------------------------------------
// Target 2: the whole pipeline on a tiny image.  Layout of the input:
//
//   byte 0   width  = 2 + b % 23          (2..24)
//   byte 1   height = 2 + b % 23          (2..24)
//   byte 2   spacing: b < 128 → one of 1, 1/2, 1/4, 2, 3, 3/2, 3/4, 0.3 (b % 8);
//            else 0.4 + (b - 128) * 4.6 / 127 (0.4..5)
//   byte 3   flags: bit 0 label mode, bit 1 maxmin rule, bit 2 graded,
//            bit 3 inside below, bits 4-5 max_cell (0, 1, 2, 4),
//            bit 6 iso + 1/2, bit 7 lattice_around instead of lattice_over
//   byte 4   threshold: iso = b (+ 1/2); label mode: label b % 4, or, with
//            bit 7 set, "nonzero"
//   rest     pixels, row-major, cycled (all 0 when empty); label mode: b % 4
struct PipelineCase {
    Image image;
    ImageLevelSetOptions options;
    double spacing = 1;
    DiagonalRule rule = DiagonalRule::separating;
    bool graded = false;
    std::int64_t max_cell = 0;
    bool around = false;
};

inline bool decode_pipeline_case(std::span<const std::uint8_t> d, PipelineCase& c) {
    if (d.size() < 5) return false;
    const int w = 2 + d[0] % 23, h = 2 + d[1] % 23;
    static constexpr double table[8] = {1, 0.5, 0.25, 2, 3, 1.5, 0.75, 0.3};
    c.spacing = d[2] < 128 ? table[d[2] % 8] : 0.4 + (d[2] - 128) * 4.6 / 127;
    const std::uint8_t flags = d[3];
    const bool label = flags & 1;
    c.rule = flags & 2 ? DiagonalRule::maxmin : DiagonalRule::separating;
    c.graded = flags & 4;
    c.max_cell = std::int64_t{1} << ((flags >> 4) & 3) >> 1;  // 0, 1, 2, 4
    c.around = flags & 128;
    c.image.width = w, c.image.height = h, c.image.maxval = 255, c.image.source = "fuzz-pipeline";
    const auto px = d.subspan(5);
    c.image.pixels.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    for (std::size_t k = 0; k < c.image.pixels.size(); ++k) {
        const std::uint8_t b = px.empty() ? 0 : px[k % px.size()];
        c.image.pixels[k] = label ? b % 4 : b;
    }
    if (label) {
        c.options.mode = ImageMode::label;
        if (d[4] & 128) c.options.label_nonzero = true;
        else c.options.labels = {d[4] % 4};
    } else {
        c.options.mode = ImageMode::threshold;
        c.options.iso = d[4] + (flags & 64 ? 0.5 : 0.0);
        c.options.inside_above = !(flags & 8);
    }
    return true;
}

using testing::mesh_area;

// Checks every invariant of a mesh of `lattice`; `what` names the mesher.
inline void check_mesh_invariants(const Mesh& m, const Lattice& lattice, DiagonalRule rule, const char* what) {
    const AngleBounds bounds = certified_bounds(rule);
    const MeshCheck mc = check_mesh(m);
    if (!mc.ok()) violation(std::string(what) + ": check_mesh failed: " + (mc.messages.empty() ? "" : mc.messages[0]));
    if (m.region.size() != m.triangles.size()) violation(std::string(what) + ": region array size");
    if (m.boundary_tag.size() != m.boundary.size()) violation(std::string(what) + ": boundary_tag array size");
    for (std::int32_t t : m.boundary_tag)
        if (t != boundary_level_set && t != boundary_domain) violation(std::string(what) + ": unknown boundary tag");
    const double tol = 1e-9 * lattice.s;
    const double x1 = lattice.x0 + static_cast<double>(lattice.nx) * lattice.s;
    const double y1 = lattice.y0 + static_cast<double>(lattice.ny) * lattice.s;
    for (const Vec2& v : m.vertices)
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || v.x < lattice.x0 - tol || v.x > x1 + tol ||
            v.y < lattice.y0 - tol || v.y > y1 + tol)
            violation(std::string(what) + ": a vertex outside the lattice");
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const auto a = testing::triangle_angles_deg(m, t);
        for (int k = 0; k < 3; ++k) {
            const double deg = a[static_cast<std::size_t>(k)];
            const Vec2 o = m.vertices[static_cast<std::size_t>(m.triangles[t][k])];
            if (!(deg >= bounds.min_deg && deg <= bounds.max_deg)) {
                char buf[240];
                std::snprintf(buf, sizeof buf, "%s: angle %.9f deg at vertex (%.17g, %.17g) outside the certified [%.6f, %.6f]",
                              what, deg, o.x, o.y, bounds.min_deg, bounds.max_deg);
                violation(buf);
            }
        }
    }
}

using testing::boundary_coords;

// Runs the case; returns false if it was refused with an InputError (e.g. a
// label that is not in the image).  Any violated invariant aborts.
inline bool run_pipeline_case(const PipelineCase& c) {
    std::unique_ptr<LevelSet> f;
    try {
        f = make_image_levelset(c.image, c.options);
    } catch (const InputError&) {
        return false;
    }
    const Lattice lattice = c.around ? lattice_around(f->bounds(), c.spacing) : lattice_over(f->bounds(), c.spacing);
    const CertifyOptions verify{true, true, true};
    const UniformResult u = mesh_uniform(*f, lattice, c.rule, verify);
    check_mesh_invariants(u.mesh, lattice, c.rule, "uniform");
    if (c.rule == DiagonalRule::separating) {
        // The fan rule: within its own (unconditional) certified bounds, every
        // square verified against its key, and the separating rule's boundary
        // (a fan's centre is never a boundary vertex).
        const UniformResult fan = mesh_uniform(*f, lattice, DiagonalRule::fan, verify);
        check_mesh_invariants(fan.mesh, lattice, DiagonalRule::fan, "uniform fan");
        if (boundary_coords(u.mesh) != boundary_coords(fan.mesh)) violation("fan and separating boundaries differ");
        if (fan.mesh.triangles.size() < u.mesh.triangles.size()) violation("fan rule lost triangles");
    }
    if (c.graded) {
        const GradedResult g = mesh_graded(*f, lattice, c.rule, c.max_cell, verify);
        check_mesh_invariants(g.mesh, lattice, c.rule, "graded");
        const double au = mesh_area(u.mesh), ag = mesh_area(g.mesh);
        if (std::abs(au - ag) > 1e-9 * std::max(1.0, au)) violation("graded and uniform areas differ");
        if (boundary_coords(u.mesh) != boundary_coords(g.mesh)) violation("graded and uniform boundaries differ");
        // The quadtree's own invariants, rebuilt from the public stages.
        const auto values = sample_values(*f, lattice);
        const auto signs = compute_signs(values);
        const auto cuts = find_cut_edges(*f, lattice, values, signs);
        const auto warped = warp_points(lattice, cuts);
        const TiledSigns tiles = tile_signs(lattice, signs);
        const Quadtree tree = build_quadtree(lattice, tiles, warped, c.max_cell);
        const QuadtreeCheck qc = check_quadtree(tree, tiles);
        if (!qc.ok()) violation("check_quadtree failed: " + (qc.messages.empty() ? std::string() : qc.messages[0]));
        // The range bounds skip tiles but change nothing: the same mesh as
        // with every tile sampled.
        const GradedResult all = mesh_graded(testing::WithoutRange(*f), lattice, c.rule, c.max_cell, verify);
        if (!testing::same_mesh(all.mesh, g.mesh)) violation("graded mesh differs from the one with every tile sampled");
    }
    return true;
}

inline void check_pipeline(std::span<const std::uint8_t> bytes) {
    PipelineCase c;
    if (!decode_pipeline_case(bytes, c)) return;
    try {
        run_pipeline_case(c);
    } catch (const InputError& e) {
        // The pipeline may refuse a level set (e.g. non-finite values), never crash.
        (void)e;
    }
}

}  // namespace warpmesh::fuzz
