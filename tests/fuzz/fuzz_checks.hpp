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
#include <array>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "warpmesh/certify/certified.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/mesh2d/graded.hpp"
#include "../certified_stage.hpp"
#include "../mesh_math.hpp"
#include "mesh2d/graded/quadtree.hpp"
#include "mesh2d/graded/tiles.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/mesh2d/lattice.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/post/quality.hpp"
#include "warpmesh/mesh2d/uniform.hpp"
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
//   byte 5   size control of the graded meshes: bits 0-1 grading (2, 1.5,
//            1.26, 1.1: buffer 0, 2, 3, 8), bits 2-3 max size (none, or
//            √5 s times 1, 1.5, 3: the cell max_cell_for_size gives, the
//            smaller of it and bits 4-5 of byte 3 wins); bit 4 (label mode)
//            also every label as a material (labels 1..3; the background
//            kept if bit 3 of byte 3), graded, label m capped at cell 2^(m-1)
//            if bit 4 + m is set (bits 5, 6, 7)
//   rest     pixels, row-major, cycled (all 0 when empty); label mode: b % 4
// (Byte 5 came with the size options; the seeds got a 0 there, which meshes
// as before.)  Every case also runs the pipeline with --optimize
// (run_optimize_case); multi-material cases are selected by bit 4 of byte 5.
struct PipelineCase {
    Image image;
    ImageLevelSetOptions options;
    double spacing = 1;
    DiagonalRule rule = DiagonalRule::separating;
    bool graded = false;
    std::int64_t max_cell = 0;
    bool around = false;
    int grading_buffer = 0;
    double max_size = 0;  // 0: none (max_cell then as byte 3 says)
    bool materials = false, keep_background = false;
    std::array<std::int64_t, 4> max_cell_of{};  // per material number (0: background), 0 = no cap
};

inline bool decode_pipeline_case(std::span<const std::uint8_t> d, PipelineCase& c) {
    if (d.size() < 6) return false;
    const int w = 2 + d[0] % 23, h = 2 + d[1] % 23;
    static constexpr double table[8] = {1, 0.5, 0.25, 2, 3, 1.5, 0.75, 0.3};
    c.spacing = d[2] < 128 ? table[d[2] % 8] : 0.4 + (d[2] - 128) * 4.6 / 127;
    const std::uint8_t flags = d[3];
    const bool label = flags & 1;
    c.rule = flags & 2 ? DiagonalRule::maxmin : DiagonalRule::separating;
    c.graded = flags & 4;
    c.max_cell = std::int64_t{1} << ((flags >> 4) & 3) >> 1;  // 0, 1, 2, 4
    c.around = flags & 128;
    const std::uint8_t sizes = d[5];
    c.grading_buffer = std::array<int, 4>{0, 2, 3, 8}[sizes & 3];
    if ((sizes >> 2) & 3) {
        c.max_size = std::sqrt(5.0) * c.spacing * std::array<double, 3>{1, 1.5, 3}[((sizes >> 2) & 3) - 1];
        const std::int64_t K = max_cell_for_size(c.max_size, c.spacing);
        c.max_cell = c.max_cell == 0 ? K : std::min(c.max_cell, K);
    }
    c.materials = label && (sizes & 16);
    c.keep_background = flags & 8;
    for (int m = 1; m <= 3; ++m)
        c.max_cell_of[static_cast<std::size_t>(m)] = (sizes >> (4 + m)) & 1 ? std::int64_t{1} << (m - 1) : 0;
    c.image.width = w, c.image.height = h, c.image.maxval = 255, c.image.source = "fuzz-pipeline";
    const auto px = d.subspan(6);
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

// Interface edges as coordinate pairs with the regions on either side,
// direction-independent, sorted.
inline std::vector<std::tuple<double, double, double, double, std::int32_t, std::int32_t>> interface_coords(const Mesh& m) {
    std::vector<std::tuple<double, double, double, double, std::int32_t, std::int32_t>> e;
    for (std::size_t k = 0; k < m.interfaces.size(); ++k) {
        Vec2 a = m.vertices[static_cast<std::size_t>(m.interfaces[k][0])], b = m.vertices[static_cast<std::size_t>(m.interfaces[k][1])];
        std::int32_t l = m.interface_regions[k][0], r = m.interface_regions[k][1];
        if (std::tie(b.x, b.y) < std::tie(a.x, a.y)) std::swap(a, b), std::swap(l, r);
        e.emplace_back(a.x, a.y, b.x, b.y, l, r);
    }
    std::sort(e.begin(), e.end());
    return e;
}

// Every label of the image as a material, uniform and graded with the case's
// size control: the graded mesh conforms, has no mixed triangle, passed the
// band invariant and every keyed triangle's verification, has the uniform
// mesh's interfaces and boundary and areas, and every triangle of material
// m has its longest edge at most max(√2 min(K_m, K) s, √5 s) (K the global
// cell, K_m the material's cap; 0 = none).
inline void run_materials_case(const PipelineCase& c, const Lattice& lattice) {
    std::unique_ptr<MaterialField> f;
    try {
        f = make_label_materials(c.image, "all");
    } catch (const InputError&) {  // no label but 0
        return;
    }
    using testing::certified;
    const MaterialOptions o{c.keep_background, DiagonalRule::separating, testing::with_keys};
    const auto u = certified(mesh_materials(*f, lattice, o), lattice, o.rule);
    std::vector<std::int64_t> caps(static_cast<std::size_t>(f->count()), 0);
    for (int m = 1; m < f->count(); ++m) {
        const std::int32_t tag = f->tag(m);  // a label 1..3
        caps[static_cast<std::size_t>(m)] = c.max_cell_of[static_cast<std::size_t>(tag)];
    }
    const auto g = certified(mesh_materials_graded(*f, lattice, o, c.max_cell, c.grading_buffer, caps), lattice, o.rule);
    const MeshCheck mc = check_mesh(g.mesh);
    if (!mc.ok()) violation("graded materials: check_mesh failed: " + (mc.messages.empty() ? std::string() : mc.messages[0]));
    if (g.mixed_triangles != 0) violation("graded materials: a mixed triangle");
    if (g.invariant_squares < 0) violation("graded materials: the band invariant was not checked");
    if (interface_coords(g.mesh) != interface_coords(u.mesh)) violation("graded and uniform interfaces differ");
    if (boundary_coords(g.mesh) != boundary_coords(u.mesh)) violation("graded and uniform material boundaries differ");
    const double au = mesh_area(u.mesh), ag = mesh_area(g.mesh);
    if (std::abs(au - ag) > 1e-9 * std::max(1.0, au)) violation("graded and uniform material areas differ");
    const double band = std::sqrt(5.0) * lattice.s * (1 + 1e-12);
    for (std::size_t t = 0; t < g.mesh.triangles.size(); ++t) {
        int m = 0;
        while (m < f->count() && f->tag(m) != g.mesh.region[t]) ++m;
        const std::int64_t Km = caps[static_cast<std::size_t>(m)], K = c.max_cell;
        const std::int64_t cell = Km == 0 ? K : K == 0 ? Km : std::min(K, Km);
        if (cell == 0) continue;
        const double bound = std::max(std::sqrt(2.0) * static_cast<double>(cell) * lattice.s * (1 + 1e-12), band);
        for (int k = 0; k < 3; ++k) {
            const Vec2 a = g.mesh.vertices[static_cast<std::size_t>(g.mesh.triangles[t][k])];
            const Vec2 b = g.mesh.vertices[static_cast<std::size_t>(g.mesh.triangles[t][(k + 1) % 3])];
            if (std::hypot(b.x - a.x, b.y - a.y) > bound) violation("graded materials: an edge longer than its material's cap");
        }
    }
}

// --optimize, on every case: the pipeline's mesh (uniform, or graded with the
// case's grading and max size) with and without the pass.  The optimised mesh
// passes check_mesh (no fold), every angle stays within the certified
// [min, max] reported for it, and its minimum angle is not below the
// unoptimised one; the pass's own internal errors (std::logic_error) abort.
inline void run_optimize_case(const PipelineCase& c, const LevelSet& f) {
    MeshOptions o;
    o.spacing = c.spacing, o.rule = c.rule, o.graded = c.graded, o.max_cell = c.max_cell;
    if (c.graded) o.grading = std::array<double, 4>{2, 1.5, 1.26, 1.1}[static_cast<std::size_t>(c.grading_buffer == 0 ? 0 : c.grading_buffer == 2 ? 1 : c.grading_buffer == 3 ? 2 : 3)];
    o.max_size = c.max_size;
    MeshResult plain, opt;
    try {
        plain = mesh(f, o);
        o.optimize = true;
        opt = mesh(f, o);
    } catch (const InputError&) {
        return;  // an empty region, a size bound below the band's
    }
    const MeshCheck mc = check_mesh(opt.mesh);
    if (!mc.ok()) violation("optimised: check_mesh failed: " + (mc.messages.empty() ? std::string() : mc.messages[0]));
    const auto angles = [](const Mesh& m, const std::array<std::int32_t, 3>& t) {
        return triangle_angles(m.vertices[static_cast<std::size_t>(t[0])], m.vertices[static_cast<std::size_t>(t[1])],
                               m.vertices[static_cast<std::size_t>(t[2])]);
    };
    double before = 180, after = 180, largest = 0;
    for (const auto& t : plain.mesh.triangles) before = std::min(before, angles(plain.mesh, t).min_deg);
    for (const auto& t : opt.mesh.triangles) {
        after = std::min(after, angles(opt.mesh, t).min_deg);
        largest = std::max(largest, angles(opt.mesh, t).max_deg);
    }
    if (after < before) violation("optimised: the minimum angle decreased");
    if (opt.certified.available && (after < opt.certified.min_deg - 1e-9 || largest > opt.certified.max_deg + 1e-9))
        violation("optimised: an angle outside the certified bounds reported for the mesh");
}

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
    using testing::certified, testing::with_keys;  // certified and verified (--verify): a violation throws
    const auto u = certified(mesh_uniform(*f, lattice, c.rule, with_keys), lattice, c.rule);
    check_mesh_invariants(u.mesh, lattice, c.rule, "uniform");
    if (c.rule == DiagonalRule::separating) {
        // The fan rule: within its own (unconditional) certified bounds, every
        // square verified against its key, and the separating rule's boundary
        // (a fan's centre is never a boundary vertex).
        const auto fan = certified(mesh_uniform(*f, lattice, DiagonalRule::fan, with_keys), lattice, DiagonalRule::fan);
        check_mesh_invariants(fan.mesh, lattice, DiagonalRule::fan, "uniform fan");
        if (boundary_coords(u.mesh) != boundary_coords(fan.mesh)) violation("fan and separating boundaries differ");
        if (fan.mesh.triangles.size() < u.mesh.triangles.size()) violation("fan rule lost triangles");
    }
    if (c.graded) {
        const auto g = certified(mesh_graded(*f, lattice, c.rule, c.max_cell, with_keys, c.grading_buffer), lattice, c.rule);
        check_mesh_invariants(g.mesh, lattice, c.rule, "graded");
        if (c.max_size != 0)
            for (std::size_t t = 0; t < g.mesh.triangles.size(); ++t)
                for (int k = 0; k < 3; ++k) {
                    const Vec2 a = g.mesh.vertices[static_cast<std::size_t>(g.mesh.triangles[t][k])];
                    const Vec2 b = g.mesh.vertices[static_cast<std::size_t>(g.mesh.triangles[t][(k + 1) % 3])];
                    if (std::hypot(b.x - a.x, b.y - a.y) > c.max_size * (1 + 1e-12)) violation("graded: an edge longer than max_size");
                }
        const double au = mesh_area(u.mesh), ag = mesh_area(g.mesh);
        if (std::abs(au - ag) > 1e-9 * std::max(1.0, au)) violation("graded and uniform areas differ");
        if (boundary_coords(u.mesh) != boundary_coords(g.mesh)) violation("graded and uniform boundaries differ");
        // The quadtree's own invariants, rebuilt from the public stages.
        const auto values = sample_values(*f, lattice);
        const auto signs = compute_signs(values);
        const auto cuts = find_cut_edges(*f, lattice, values, signs);
        const auto warped = warp_points(lattice, cuts);
        const TiledSigns tiles = tile_signs(lattice, signs);
        const Quadtree tree = build_quadtree(lattice, tiles, warped, c.max_cell, c.grading_buffer);
        const QuadtreeCheck qc = check_quadtree(tree, tiles);
        if (!qc.ok()) violation("check_quadtree failed: " + (qc.messages.empty() ? std::string() : qc.messages[0]));
        // The range bounds skip tiles but change nothing: the same mesh as
        // with every tile sampled.
        const auto all =
            certified(mesh_graded(testing::WithoutRange(*f), lattice, c.rule, c.max_cell, with_keys, c.grading_buffer), lattice, c.rule);
        if (!testing::same_mesh(all.mesh, g.mesh)) violation("graded mesh differs from the one with every tile sampled");
    }
    if (c.materials) run_materials_case(c, lattice);
    run_optimize_case(c, *f);
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
