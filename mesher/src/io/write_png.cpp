// write_png.cpp — a PNG picture of the mesh, good enough for a paper figure.
//
// Mapping: the mesh's bounding box is scaled uniformly so that the picture's
// long side (margins included, legend excluded) is `long_side_px`; a mesh
// point (x, y) goes to pixel coordinates (m + (x - xmin) s, m + (ymax - y) s),
// so y-up appears up.  Pixel (c, r) covers [c, c+1) x [r, r+1).
//
// Rendering: the picture is drawn in horizontal bands of output rows, each at
// `supersample` x `supersample` samples per pixel, then box-filtered down
// (anti-aliasing by supersampling; bands keep the memory at a few MB whatever
// the size, and are drawn in parallel).  Per band, three layers, each a
// per-sample mask or colour, so overlapping strokes never darken twice:
//   1. triangle fills: a sample takes the colour of a triangle containing it;
//   2. interior edges: samples within half the edge width of an edge, blended
//      over the fill with the edge colour at opacity `edge_alpha`;
//   3. boundary edges: the same with the (thicker) boundary width, opaque,
//      coloured by tag.
// Widths follow the typical edge length in px, h ≈ sqrt(4 A / (√3 T)), as in
// write_svg.cpp: thin lines on fine meshes; below ~6 px per edge the interior
// edges fade out, so that a very fine mesh shows its fill and boundary rather
// than a grey mush.
//
// Colouring (optional) maps a value to red → yellow → green (low → high), the
// minimum angle over 0°–60° or a cell_data array over its finite min–max; a
// vertical colour bar on the right, labelled with a built-in 5x7 bitmap font
// (digits, capitals, a little punctuation; lower case is drawn as capitals).
//
// PNG encoding: libpng's classic API writing through a callback into the
// stream; libpng's errors longjmp out of a function that holds no C++ objects
// and become an OutputError.  Without libpng (WARPMESH_HAVE_PNG undefined) the
// writer throws OutputError.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string_view>
#include <vector>

#ifdef WARPMESH_HAVE_PNG
#include <png.h>
#endif

#include "io/atomic_file.hpp"
#include "io/output.hpp"
#include "warpmesh/core/triangle_shape.hpp"
#include "warpmesh/io/writers.hpp"

namespace warpmesh {

namespace {

using Rgb = std::array<std::uint8_t, 3>;

constexpr Rgb white{255, 255, 255};
constexpr Rgb fill_colour{219, 230, 244};  // #dbe6f4, as in the SVG
constexpr Rgb edge_colour{45, 55, 72};     // dark slate
constexpr Rgb grey{153, 153, 153};
constexpr Rgb text_colour{30, 30, 30};

Rgb boundary_colour(std::int32_t tag) {
    if (tag == boundary_level_set) return {214, 39, 40};  // red
    if (tag == boundary_domain) return {31, 119, 180};    // blue
    return {44, 160, 44};                                 // green
}

// Red (0) → yellow (0.5) → green (1), linear in RGB between the stops (as in
// write_svg.cpp).
Rgb ramp(double t) {
    if (!std::isfinite(t)) return grey;
    t = std::clamp(t, 0.0, 1.0);
    constexpr std::array<std::array<double, 3>, 3> stops{{{215, 48, 39}, {254, 224, 139}, {26, 152, 80}}};
    const double u = t * 2;
    const std::size_t i = u >= 1 ? 1 : 0;
    const double f = u - static_cast<double>(i);
    Rgb c{};
    for (std::size_t k = 0; k < 3; ++k)
        c[k] = static_cast<std::uint8_t>(std::lround(stops[i][k] * (1 - f) + stops[i + 1][k] * f));
    return c;
}

// ---- a 5x7 bitmap font ---------------------------------------------------------------
// Each glyph is 7 rows, top first; bit 4 is the leftmost column.
struct Glyph {
    char c;
    std::array<std::uint8_t, 7> rows;
};
constexpr Glyph font[] = {
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}}, {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}}, {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}}, {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}}, {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}}, {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}}, {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}}, {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}}, {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}}, {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}}, {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}}, {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}}, {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}}, {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}}, {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}}, {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}}, {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x11, 0x0A, 0x04, 0x04, 0x04}}, {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}}, {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}}, {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}}, {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}},
    {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}}, {'/', {0x00, 0x01, 0x02, 0x04, 0x08, 0x10, 0x00}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}}, {'\xB0', {0x0C, 0x12, 0x12, 0x0C, 0x00, 0x00, 0x00}},  // °
    {' ', {0, 0, 0, 0, 0, 0, 0}},
};

const Glyph* glyph(char c) {
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
    for (const Glyph& g : font)
        if (g.c == c) return &g;
    return nullptr;
}

// The text as single-byte glyph codes: UTF-8 "°" (C2 B0) becomes '\xB0'.
std::string glyph_text(std::string_view s) {
    std::string r;
    for (std::size_t i = 0; i < s.size(); ++i) {
        if (static_cast<unsigned char>(s[i]) == 0xC2 && i + 1 < s.size() && static_cast<unsigned char>(s[i + 1]) == 0xB0) {
            r += '\xB0';
            ++i;
        } else if (static_cast<unsigned char>(s[i]) < 0x80) {
            r += s[i];
        }
    }
    return r;
}

// ---- the output image ------------------------------------------------------------------
struct Image {
    int w = 0, h = 0;
    std::vector<std::uint8_t> rgb;  // row-major, top row first
    void set(int x, int y, Rgb c) {
        if (x < 0 || y < 0 || x >= w || y >= h) return;
        std::uint8_t* p = &rgb[3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x))];
        p[0] = c[0], p[1] = c[1], p[2] = c[2];
    }
    void rect(int x0, int y0, int x1, int y1, Rgb c) {  // [x0, x1) x [y0, y1)
        for (int y = y0; y < y1; ++y)
            for (int x = x0; x < x1; ++x) set(x, y, c);
    }
    // Text with glyph pixels of k x k; returns the width drawn.
    int text(int x, int y, std::string_view s, int k, Rgb c) {
        const std::string t = glyph_text(s);
        int cx = x;
        for (const char ch : t) {
            if (const Glyph* g = glyph(ch)) {
                for (int r = 0; r < 7; ++r)
                    for (int col = 0; col < 5; ++col)
                        if (g->rows[static_cast<std::size_t>(r)] & (0x10 >> col)) rect(cx + col * k, y + r * k, cx + (col + 1) * k, y + (r + 1) * k, c);
            }
            cx += 6 * k;
        }
        return cx - x;
    }
};

int text_width(std::string_view s, int k) { return static_cast<int>(glyph_text(s).size()) * 6 * k; }

std::string number_label(double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 4);
    return std::string(buf, r.ptr);
}

// A stroke: segment p-q in sample coordinates, drawn with half-width hw.
struct Segment {
    float x0, y0, x1, y1;
};

// Samples of row `sy` (sample y coordinate sy + 0.5) within the half-width hw
// of segment s, as a mask over the band's columns [0, sw).
template <class Mark>
void stroke(const Segment& s, float hw, std::int64_t band_y0, std::int64_t band_y1, std::int64_t sw, Mark mark) {
    const float xmin = std::min(s.x0, s.x1) - hw, xmax = std::max(s.x0, s.x1) + hw;
    const float ymin = std::min(s.y0, s.y1) - hw, ymax = std::max(s.y0, s.y1) + hw;
    const std::int64_t r0 = std::max<std::int64_t>(band_y0, static_cast<std::int64_t>(std::floor(ymin - 0.5f)));
    const std::int64_t r1 = std::min<std::int64_t>(band_y1 - 1, static_cast<std::int64_t>(std::ceil(ymax - 0.5f)));
    const std::int64_t c0 = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::floor(xmin - 0.5f)));
    const std::int64_t c1 = std::min<std::int64_t>(sw - 1, static_cast<std::int64_t>(std::ceil(xmax - 0.5f)));
    if (r0 > r1 || c0 > c1) return;
    const float dx = s.x1 - s.x0, dy = s.y1 - s.y0, len2 = dx * dx + dy * dy;
    const float hw2 = hw * hw;
    for (std::int64_t r = r0; r <= r1; ++r) {
        const float py = static_cast<float>(r) + 0.5f;
        for (std::int64_t c = c0; c <= c1; ++c) {
            const float px = static_cast<float>(c) + 0.5f;
            float t = len2 > 0 ? ((px - s.x0) * dx + (py - s.y0) * dy) / len2 : 0.0f;
            t = std::clamp(t, 0.0f, 1.0f);
            const float ex = s.x0 + t * dx - px, ey = s.y0 + t * dy - py;
            if (ex * ex + ey * ey <= hw2) mark(r - band_y0, c);
        }
    }
}

// Each triangle's fill colour when the picture is coloured (by value or by
// region); empty: the plain fill colour.
std::vector<Rgb> triangle_colours(const detail::Colouring& colouring, std::size_t nt) {
    std::vector<Rgb> tri_colour;
    if (!colouring.legend() && !colouring.by_region) return tri_colour;
    tri_colour.resize(nt);
    for (std::size_t k = 0; k < nt; ++k) {
        const std::uint32_t c = detail::region_colour(static_cast<std::int32_t>(colouring.value[k]));
        tri_colour[k] = colouring.by_region ? Rgb{static_cast<std::uint8_t>(c >> 16), static_cast<std::uint8_t>(c >> 8), static_cast<std::uint8_t>(c)}
                                            : ramp(colouring.normalised(k));
    }
    return tri_colour;
}

// Where the mesh goes in the picture: its bounding box, the scale s (pixels
// per mesh unit), the margin and the mesh part's size in pixels.
struct Frame {
    double xmin = 0, xmax = 1, ymin = 0, ymax = 1, s = 1;
    int k_font = 1, margin = 6, mesh_w = 0, mesh_h = 0;
};

Frame frame_of(const Mesh& mesh, int L) {
    Frame f;
    if (!mesh.vertices.empty()) {
        f.xmin = f.xmax = mesh.vertices[0].x, f.ymin = f.ymax = mesh.vertices[0].y;
        for (const Vec2& v : mesh.vertices)
            f.xmin = std::min(f.xmin, v.x), f.xmax = std::max(f.xmax, v.x), f.ymin = std::min(f.ymin, v.y), f.ymax = std::max(f.ymax, v.y);
    }
    if (!std::isfinite(f.xmin) || !std::isfinite(f.xmax) || !std::isfinite(f.ymin) || !std::isfinite(f.ymax))
        throw OutputError("the mesh has non-finite coordinates");
    f.k_font = std::max(1, static_cast<int>(std::lround(L / 800.0)));  // glyph pixel size
    f.margin = std::max(6, static_cast<int>(std::lround(0.015 * L)));
    const double long_extent = std::max(f.xmax - f.xmin, f.ymax - f.ymin);
    f.s = long_extent > 0 ? (L - 2.0 * f.margin) / long_extent : 1;
    f.mesh_w = static_cast<int>(std::ceil((f.xmax - f.xmin) * f.s - 1e-6)) + 2 * f.margin;
    f.mesh_h = static_cast<int>(std::ceil((f.ymax - f.ymin) * f.s - 1e-6)) + 2 * f.margin;
    return f;
}

constexpr int band_rows = 16;

// The primitives in sample coordinates, bucketed by bands of output rows.
struct Scene {
    int ss = 1, nbands = 0;
    std::int64_t sw = 0;  // samples per row
    std::vector<std::array<float, 2>> P;
    std::vector<Segment> edges, bedges;
    float ehw = 0, bhw = 0;
    double edge_alpha = 0;
    std::vector<std::vector<std::uint32_t>> tri_bands, edge_bands, bedge_bands;
};

// Each primitive k of `count` goes to every band its row range yrange(k) touches.
template <class Range>
std::vector<std::vector<std::uint32_t>> bucket(int nbands, std::size_t count, Range&& yrange) {
    std::vector<std::vector<std::uint32_t>> b(static_cast<std::size_t>(nbands));
    for (std::size_t k = 0; k < count; ++k) {
        const auto r = yrange(k);
        const int b0 = std::max(0, r[0] / band_rows), b1 = std::min(nbands - 1, r[1] / band_rows);
        for (int i = b0; i <= b1; ++i) b[static_cast<std::size_t>(i)].push_back(static_cast<std::uint32_t>(k));
    }
    return b;
}

Scene scene_of(const Mesh& mesh, const PngOptions& options, const Frame& f) {
    Scene sc;
    const std::size_t nt = mesh.triangles.size();
    const double h_px = detail::typical_edge_px(mesh, f.s);
    const double edge_w = std::clamp(0.08 * h_px, 0.6, 1.2);
    sc.edge_alpha = options.draw_edges ? std::clamp((h_px - 2.0) / 4.0, 0.0, 0.85) : 0.0;
    const double boundary_w = std::max(std::clamp(0.25 * h_px, 1.6, 4.0), 2 * edge_w);
    // Sample coordinates of the vertices.
    const int ss = sc.ss = options.supersample;
    sc.P.resize(mesh.vertices.size());
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        sc.P[i] = {static_cast<float>((f.margin + (mesh.vertices[i].x - f.xmin) * f.s) * ss),
                   static_cast<float>((f.margin + (f.ymax - mesh.vertices[i].y) * f.s) * ss)};
    auto segment = [&](std::int32_t a, std::int32_t b) {
        const auto& p = sc.P[static_cast<std::size_t>(a)];
        const auto& q = sc.P[static_cast<std::size_t>(b)];
        return Segment{p[0], p[1], q[0], q[1]};
    };
    // Interior edges, once each: an interior edge appears in its two triangles
    // in opposite directions, so "a < b" picks it once; boundary edges, which
    // this may skip, are drawn over by the boundary layer anyway.
    if (sc.edge_alpha > 0) {
        sc.edges.reserve(nt * 3 / 2 + 1);
        for (const auto& t : mesh.triangles)
            for (int e = 0; e < 3; ++e)
                if (t[static_cast<std::size_t>(e)] < t[static_cast<std::size_t>((e + 1) % 3)])
                    sc.edges.push_back(segment(t[static_cast<std::size_t>(e)], t[static_cast<std::size_t>((e + 1) % 3)]));
    }
    // Boundary edges, then the interfaces between regions (drawn like a third boundary tag).
    sc.bedges.resize(mesh.boundary.size() + mesh.interfaces.size());
    for (std::size_t k = 0; k < mesh.boundary.size(); ++k) sc.bedges[k] = segment(mesh.boundary[k][0], mesh.boundary[k][1]);
    for (std::size_t k = 0; k < mesh.interfaces.size(); ++k)
        sc.bedges[mesh.boundary.size() + k] = segment(mesh.interfaces[k][0], mesh.interfaces[k][1]);

    // Per-primitive y ranges (in output rows) so that bands skip quickly.
    auto rows_of = [ss](float y0, float y1, float pad) {
        return std::array<int, 2>{static_cast<int>(std::floor((std::min(y0, y1) - pad) / static_cast<float>(ss))),
                                  static_cast<int>(std::floor((std::max(y0, y1) + pad) / static_cast<float>(ss)))};
    };
    sc.ehw = static_cast<float>(edge_w * ss / 2), sc.bhw = static_cast<float>(boundary_w * ss / 2);
    sc.nbands = (f.mesh_h + band_rows - 1) / band_rows;
    sc.sw = static_cast<std::int64_t>(f.mesh_w) * ss;
    const auto& P = sc.P;
    sc.tri_bands = bucket(sc.nbands, nt, [&](std::size_t k) {
        const auto& t = mesh.triangles[k];
        const float y0 = P[static_cast<std::size_t>(t[0])][1], y1 = P[static_cast<std::size_t>(t[1])][1], y2 = P[static_cast<std::size_t>(t[2])][1];
        return rows_of(std::min(y0, std::min(y1, y2)), std::max(y0, std::max(y1, y2)), 1);
    });
    sc.edge_bands = bucket(sc.nbands, sc.edges.size(), [&](std::size_t k) { return rows_of(sc.edges[k].y0, sc.edges[k].y1, sc.ehw + 1); });
    sc.bedge_bands = bucket(sc.nbands, sc.bedges.size(), [&](std::size_t k) { return rows_of(sc.bedges[k].y0, sc.bedges[k].y1, sc.bhw + 1); });
    return sc;
}

// Fills the samples of rows [sy0, sy1) inside triangle abc with `col`.
void fill_triangle(std::vector<std::uint8_t>& buf, const std::array<float, 2>& a, const std::array<float, 2>& b,
                   const std::array<float, 2>& c, Rgb col, std::int64_t sy0, std::int64_t sy1, std::int64_t sw) {
    const float fxmin = std::min(a[0], std::min(b[0], c[0])), fxmax = std::max(a[0], std::max(b[0], c[0]));
    const float fymin = std::min(a[1], std::min(b[1], c[1])), fymax = std::max(a[1], std::max(b[1], c[1]));
    const std::int64_t r0 = std::max<std::int64_t>(sy0, static_cast<std::int64_t>(std::ceil(fymin - 0.5f)));
    const std::int64_t r1 = std::min<std::int64_t>(sy1 - 1, static_cast<std::int64_t>(std::floor(fymax - 0.5f)));
    const std::int64_t c0 = std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil(fxmin - 0.5f)));
    const std::int64_t c1 = std::min<std::int64_t>(sw - 1, static_cast<std::int64_t>(std::floor(fxmax - 0.5f)));
    // Edge functions; either orientation (the y flip reverses it).
    const float area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (area2 == 0) return;
    const float sgn = area2 > 0 ? 1.0f : -1.0f;
    for (std::int64_t r = r0; r <= r1; ++r) {
        const float py = static_cast<float>(r) + 0.5f;
        for (std::int64_t cc = c0; cc <= c1; ++cc) {
            const float px = static_cast<float>(cc) + 0.5f;
            const float w0 = sgn * ((b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]));
            const float w1 = sgn * ((c[0] - b[0]) * (py - b[1]) - (c[1] - b[1]) * (px - b[0]));
            const float w2 = sgn * ((a[0] - c[0]) * (py - c[1]) - (a[1] - c[1]) * (px - c[0]));
            if (w0 >= 0 && w1 >= 0 && w2 >= 0) {
                std::uint8_t* p = &buf[3 * static_cast<std::size_t>((r - sy0) * sw + cc)];
                p[0] = col[0], p[1] = col[1], p[2] = col[2];
            }
        }
    }
}

// One band's samples: fills, interior-edge mask, boundary mask (0: none,
// else 1 + index into the tag colours).
struct BandSamples {
    std::vector<std::uint8_t> buf, emask, bmask;
};

// Composites band samples (edges blended, boundaries opaque) and box-filters
// them down into output rows [row0, row1).
void composite_band(Image& img, const BandSamples& bs, const Scene& sc, int row0, int row1, int mesh_w) {
    const int ss = sc.ss;
    const std::int64_t sw = sc.sw;
    const std::uint8_t er = edge_colour[0], eg = edge_colour[1], eb = edge_colour[2];
    const Rgb bcol[4] = {white, boundary_colour(boundary_level_set), boundary_colour(boundary_domain), boundary_colour(3)};
    const float ea = static_cast<float>(sc.edge_alpha);
    const float norm = 1.0f / static_cast<float>(ss * ss);
    for (int row = row0; row < row1; ++row)
        for (int col = 0; col < mesh_w; ++col) {
            float acc[3] = {0, 0, 0};
            for (int dy = 0; dy < ss; ++dy) {
                const std::size_t base = static_cast<std::size_t>((static_cast<std::int64_t>(row - row0) * ss + dy) * sw +
                                                                  static_cast<std::int64_t>(col) * ss);
                for (int dx = 0; dx < ss; ++dx) {
                    const std::size_t i = base + static_cast<std::size_t>(dx);
                    float r = bs.buf[3 * i], g = bs.buf[3 * i + 1], b = bs.buf[3 * i + 2];
                    if (bs.emask[i]) r += ea * (er - r), g += ea * (eg - g), b += ea * (eb - b);
                    if (bs.bmask[i]) {
                        const Rgb& bc = bcol[bs.bmask[i]];
                        r = bc[0], g = bc[1], b = bc[2];
                    }
                    acc[0] += r, acc[1] += g, acc[2] += b;
                }
            }
            std::uint8_t* p = &img.rgb[3 * (static_cast<std::size_t>(row) * static_cast<std::size_t>(img.w) + static_cast<std::size_t>(col))];
            for (int c = 0; c < 3; ++c) p[c] = static_cast<std::uint8_t>(std::lround(std::clamp(acc[c] * norm, 0.0f, 255.0f)));
        }
}

// Draws band `band` of the mesh part into img.
void render_band(Image& img, BandSamples& bs, const Mesh& mesh, const Scene& sc, const std::vector<Rgb>& tri_colour,
                 const Frame& f, int band) {
    const int ss = sc.ss;
    const std::int64_t sw = sc.sw;
    const int row0 = band * band_rows, row1 = std::min(f.mesh_h, row0 + band_rows);
    const std::int64_t sy0 = static_cast<std::int64_t>(row0) * ss, sy1 = static_cast<std::int64_t>(row1) * ss;
    const std::size_t nsamples = static_cast<std::size_t>((sy1 - sy0) * sw);
    bs.buf.assign(nsamples * 3, 255);
    bs.emask.assign(nsamples, 0);
    bs.bmask.assign(nsamples, 0);
    const auto b = static_cast<std::size_t>(band);
    // 1. fills
    for (const std::uint32_t k : sc.tri_bands[b]) {
        const auto& t = mesh.triangles[k];
        fill_triangle(bs.buf, sc.P[static_cast<std::size_t>(t[0])], sc.P[static_cast<std::size_t>(t[1])],
                      sc.P[static_cast<std::size_t>(t[2])], tri_colour.empty() ? fill_colour : tri_colour[k], sy0, sy1, sw);
    }
    // 2. interior edges
    for (const std::uint32_t k : sc.edge_bands[b])
        stroke(sc.edges[k], sc.ehw, sy0, sy1, sw, [&](std::int64_t r, std::int64_t c) { bs.emask[static_cast<std::size_t>(r * sw + c)] = 1; });
    // 3. boundary edges
    for (const std::uint32_t k : sc.bedge_bands[b]) {
        const std::int32_t tag = k < mesh.boundary.size() ? mesh.boundary_tag[k] : 0;
        const std::uint8_t code = tag == boundary_level_set ? 1 : tag == boundary_domain ? 2 : 3;
        stroke(sc.bedges[k], sc.bhw, sy0, sy1, sw, [&](std::int64_t r, std::int64_t c) {
            std::uint8_t& m = bs.bmask[static_cast<std::size_t>(r * sw + c)];
            m = std::max(m, code);  // deterministic where tags overlap
        });
    }
    composite_band(img, bs, sc, row0, row1, f.mesh_w);
}

// A vertical colour bar right of the mesh, low at the bottom, with a title
// and three labels.
void draw_legend(Image& img, const Frame& f, const PngOptions& options, const std::string& title,
                 const std::array<std::string, 3>& labels, int bar_w, int bar_h) {
    const int k_font = f.k_font, margin = f.margin;
    const int x0 = f.mesh_w + margin, y0 = margin + 12 * k_font;
    if (options.legend_labels) img.text(f.mesh_w + margin / 2, margin, title, k_font, text_colour);
    for (int y = 0; y < bar_h; ++y) {
        const Rgb c = ramp(1.0 - (y + 0.5) / bar_h);
        img.rect(x0, y0 + y, x0 + bar_w, y0 + y + 1, c);
    }
    // Frame.
    img.rect(x0 - 1, y0 - 1, x0 + bar_w + 1, y0, text_colour);
    img.rect(x0 - 1, y0 + bar_h, x0 + bar_w + 1, y0 + bar_h + 1, text_colour);
    img.rect(x0 - 1, y0, x0, y0 + bar_h, text_colour);
    img.rect(x0 + bar_w, y0, x0 + bar_w + 1, y0 + bar_h, text_colour);
    if (options.legend_labels)
        for (int i = 0; i <= 2; ++i) {
            const int yc = y0 + bar_h - bar_h * i / 2;
            img.rect(x0 + bar_w, yc, x0 + bar_w + 3 * k_font, yc + std::max(1, k_font / 2), text_colour);
            img.text(x0 + bar_w + 5 * k_font, yc - 3 * k_font, labels[static_cast<std::size_t>(i)], k_font, text_colour);
        }
}

Image render(const Mesh& mesh, const PngOptions& options) {
    if (options.long_side_px < 16 || options.long_side_px > 20000)
        throw OutputError("PNG long side must be 16 to 20000 px, got " + std::to_string(options.long_side_px));
    if (options.supersample < 1 || options.supersample > 8)
        throw OutputError("PNG supersampling must be 1 to 8, got " + std::to_string(options.supersample));

    // Values to colour by, normalised to [0, 1].
    const detail::Colouring colouring =
        detail::picture_colouring(mesh, options.color_by_cell_data, options.color_by_min_angle, "PNG");
    const bool coloured = colouring.legend();
    const std::vector<Rgb> tri_colour = triangle_colours(colouring, mesh.triangles.size());
    const Frame f = frame_of(mesh, options.long_side_px);

    // Legend geometry.
    const int k_font = f.k_font, margin = f.margin;
    const int bar_w = 14 * k_font, bar_h = std::max(60, std::min(f.mesh_h - 2 * margin - 24 * k_font, 240 * k_font));
    int legend_w = 0;
    const double lo = colouring.lo, hi = colouring.hi;
    const std::array<std::string, 3> labels{number_label(lo), number_label((lo + hi) / 2), number_label(hi)};
    if (coloured) {
        int lw = 0;
        for (const auto& l : labels) lw = std::max(lw, text_width(l, k_font));
        legend_w = 2 * margin + bar_w + (options.legend_labels ? 5 * k_font + lw : 0);
        if (options.legend_labels) legend_w = std::max(legend_w, text_width(colouring.title, k_font) + margin);
    }
    Image img;
    img.w = f.mesh_w + legend_w;
    img.h = std::max(f.mesh_h, coloured ? bar_h + 2 * margin + 24 * k_font : 0);
    img.rgb.assign(static_cast<std::size_t>(img.w) * static_cast<std::size_t>(img.h) * 3, 255);

    const Scene sc = scene_of(mesh, options, f);
#pragma omp parallel
    {
        BandSamples bs;
#pragma omp for schedule(dynamic, 1)
        for (int band = 0; band < sc.nbands; ++band) render_band(img, bs, mesh, sc, tri_colour, f, band);
    }
    if (coloured) draw_legend(img, f, options, colouring.title, labels, bar_w, bar_h);
    return img;
}

#ifdef WARPMESH_HAVE_PNG

struct PngSink {
    std::ostream* out;
    bool failed;
    char error[256];
};

extern "C" void png_write_to_stream(png_structp png, png_bytep data, png_size_t n) {
    auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
    if (sink->failed) return;
    sink->out->write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(n));
    if (!*sink->out) {
        sink->failed = true;
        png_error(png, "write error");
    }
}
extern "C" void png_flush_stream(png_structp png) {
    auto* sink = static_cast<PngSink*>(png_get_io_ptr(png));
    if (!sink->failed) sink->out->flush();
}
extern "C" void png_write_error_to_jmp(png_structp png, png_const_charp msg) {
    auto* sink = static_cast<PngSink*>(png_get_error_ptr(png));
    std::snprintf(sink->error, sizeof sink->error, "%s", msg ? msg : "libpng error");
    png_longjmp(png, 1);
}
extern "C" void png_write_ignore_warning(png_structp, png_const_charp) {}

// Every libpng call that can longjmp, in a function holding no C++ objects
// with destructors.  Returns false on a libpng error (message in sink->error).
bool png_encode(png_structp png, png_infop info, png_uint_32 w, png_uint_32 h, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_set_IHDR(png, info, w, h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 6);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, nullptr);
    return true;
}

#endif

}  // namespace

void write_png(const Mesh& mesh, std::ostream& out, const PngOptions& options) {
#ifdef WARPMESH_HAVE_PNG
    detail::check_mesh_arrays(detail::view_of(mesh), "<png stream>");
    Image img = render(mesh, options);
    std::vector<png_bytep> rows(static_cast<std::size_t>(img.h));
    for (int y = 0; y < img.h; ++y) rows[static_cast<std::size_t>(y)] = &img.rgb[3 * static_cast<std::size_t>(y) * static_cast<std::size_t>(img.w)];

    PngSink sink{&out, false, {0}};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &sink, png_write_error_to_jmp, png_write_ignore_warning);
    if (!png) throw OutputError("cannot create a libpng writer");
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        throw OutputError("cannot create a libpng info structure");
    }
    png_set_write_fn(png, &sink, png_write_to_stream, png_flush_stream);
    const bool ok = png_encode(png, info, static_cast<png_uint_32>(img.w), static_cast<png_uint_32>(img.h), rows.data());
    png_destroy_write_struct(&png, &info);
    if (!ok) throw OutputError(std::string("PNG encoding failed: ") + sink.error);
#else
    (void)mesh, (void)out, (void)options;
    throw OutputError("PNG output needs libpng, which was not found at build time");
#endif
}

void write_png(const Mesh& mesh, const std::string& path, const PngOptions& options) {
    detail::check_mesh_arrays(detail::view_of(mesh), path);
#ifndef WARPMESH_HAVE_PNG
    throw OutputError("cannot write '" + path + "': PNG output needs libpng, which was not found at build time");
#endif
    write_file_atomically(path, [&](std::ostream& os) { write_png(mesh, os, options); });
}

}  // namespace warpmesh
