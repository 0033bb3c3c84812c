// write_svg.cpp — an SVG picture of the mesh.
//
// Mapping: the mesh's bounding box is scaled uniformly so that its long side
// is `long_side_px` px, with a margin; SVG's y axis points down, so a mesh point
// (x, y) goes to (m + (x - xmin) s, m + (ymax - y) s) and y-up appears up.
// Triangles are <polygon>s (one per triangle, light fill, thin edges), drawn
// under the boundary: one <path> per boundary tag, thicker, coloured by tag.
// Stroke widths follow the typical edge length in px, h ≈ sqrt(4 A / (√3 T))
// (the side of an equilateral triangle of the mean area), so fine meshes are
// not drowned in ink and coarse ones stay readable.
//
// Colouring (optional) maps a per-triangle value to red → yellow → green
// (low → high) with a legend on the right: the minimum angle over 0°–60°, or a
// cell_data array over its finite min–max (non-finite values are grey).
#include <cstdio>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string_view>
#include <vector>

#include "io/atomic_file.hpp"
#include "io/output.hpp"
#include "warpmesh/core/triangle_shape.hpp"
#include "warpmesh/io/writers.hpp"

namespace warpmesh {

namespace {

std::string xml_text(std::string_view s) {
    std::string r;
    for (const char c : s) {
        if (c == '&') r += "&amp;";
        else if (c == '<') r += "&lt;";
        else if (c == '>') r += "&gt;";
        else if (c == '"') r += "&quot;";
        else r += c;
    }
    return r;
}

// Red (0) → yellow (0.5) → green (1), linear in RGB between the stops.
std::string colour(double t) {
    if (!std::isfinite(t)) return "#999999";
    t = std::clamp(t, 0.0, 1.0);
    constexpr std::array<std::array<double, 3>, 3> stops{{{215, 48, 39}, {254, 224, 139}, {26, 152, 80}}};
    const double u = t * 2;
    const std::size_t i = u >= 1 ? 1 : 0;
    const double f = u - static_cast<double>(i);
    char buf[8];
    auto hex = [](int v) { return "0123456789abcdef"[v & 15]; };
    buf[0] = '#';
    for (int c = 0; c < 3; ++c) {
        const int v = static_cast<int>(std::lround(stops[i][static_cast<std::size_t>(c)] * (1 - f) +
                                                   stops[i + 1][static_cast<std::size_t>(c)] * f));
        buf[1 + 2 * c] = hex(v >> 4);
        buf[2 + 2 * c] = hex(v);
    }
    return std::string(buf, 7);
}

std::string boundary_colour(std::int32_t tag) {
    if (tag == boundary_level_set) return "#d62728";
    if (tag == boundary_domain) return "#1f77b4";
    return "#2ca02c";
}

// The picture's geometry: mesh coordinates to SVG pixels (y flipped), and
// the line widths.
struct SvgFrame {
    double xmin = 0, xmax = 0, ymin = 0, ymax = 0, s = 1, margin = 10, legend_w = 0, width = 0, height = 0;
    double edge_w = 0, boundary_w = 0;
    void point(detail::TextSink& out, Vec2 p) const {
        out.fixed(margin + (p.x - xmin) * s, 3) << ',';
        out.fixed(margin + (ymax - p.y) * s, 3);
    }
};

SvgFrame svg_frame(const Mesh& mesh, const SvgOptions& options, bool coloured) {
    SvgFrame f;
    if (!mesh.vertices.empty()) {
        f.xmin = f.xmax = mesh.vertices[0].x, f.ymin = f.ymax = mesh.vertices[0].y;
        for (const Vec2& v : mesh.vertices)
            f.xmin = std::min(f.xmin, v.x), f.xmax = std::max(f.xmax, v.x), f.ymin = std::min(f.ymin, v.y), f.ymax = std::max(f.ymax, v.y);
    }
    const double long_side = std::max(f.xmax - f.xmin, f.ymax - f.ymin);
    f.s = long_side > 0 ? options.long_side_px / long_side : 1;
    f.legend_w = coloured ? 110 : 0;
    f.width = (f.xmax - f.xmin) * f.s + 2 * f.margin + f.legend_w;
    f.height = std::max((f.ymax - f.ymin) * f.s + 2 * f.margin, coloured ? 240.0 : 0.0);
    const double h_px = detail::typical_edge_px(mesh, f.s);
    f.edge_w = std::clamp(0.06 * h_px, 0.02, 1.0);
    f.boundary_w = std::max(std::clamp(0.2 * h_px, 0.5, 3.0), 2 * f.edge_w);
    return f;
}

void put_triangles(detail::TextSink& out, const Mesh& mesh, const SvgFrame& f, const detail::Colouring& colouring,
                   const SvgOptions& options) {
    out << "<g id=\"triangles\" fill=\"#dbe6f4\" stroke=\"" << (options.draw_edges ? "#4a5568" : "none")
        << "\" stroke-width=\"";
    out.fixed(f.edge_w, 3) << "\" stroke-linejoin=\"round\">\n";
    for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
        const auto& t = mesh.triangles[k];
        out << "<polygon points=\"";
        f.point(out, mesh.vertices[static_cast<std::size_t>(t[0])]);
        out << ' ';
        f.point(out, mesh.vertices[static_cast<std::size_t>(t[1])]);
        out << ' ';
        f.point(out, mesh.vertices[static_cast<std::size_t>(t[2])]);
        out << '"';
        if (colouring.legend()) out << " fill=\"" << colour(colouring.normalised(k)) << '"';
        if (colouring.by_region) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "#%06x", static_cast<unsigned>(detail::region_colour(static_cast<std::int32_t>(colouring.value[k]))));
            out << " fill=\"" << hex << '"';
        }
        out << "/>\n";
    }
    out << "</g>\n";
}

void put_boundary(detail::TextSink& out, const Mesh& mesh, const SvgFrame& f) {
    // Boundary: one path per tag, "M x,y L x,y …" polylines.
    std::vector<std::int32_t> tags(mesh.boundary_tag);
    std::sort(tags.begin(), tags.end());
    tags.erase(std::unique(tags.begin(), tags.end()), tags.end());
    out << "<g id=\"boundary\" fill=\"none\" stroke-width=\"";
    out.fixed(f.boundary_w, 3) << "\" stroke-linecap=\"round\">\n";
    for (const std::int32_t tag : tags) {
        out << "<path class=\"boundary-" << tag << "\" stroke=\"" << boundary_colour(tag) << "\" d=\"";
        // Consecutive edges that chain (the next starts where the last ended)
        // continue the polyline instead of starting a new subpath.
        std::int32_t pen = -1;
        for (std::size_t k = 0; k < mesh.boundary.size(); ++k) {
            if (mesh.boundary_tag[k] != tag) continue;
            const auto& e = mesh.boundary[k];
            if (e[0] != pen) {
                out << (pen < 0 ? "M" : " M");
                f.point(out, mesh.vertices[static_cast<std::size_t>(e[0])]);
            }
            out << " L";
            f.point(out, mesh.vertices[static_cast<std::size_t>(e[1])]);
            pen = e[1];
        }
        out << "\"/>\n";
    }
    out << "</g>\n";
    if (!mesh.interfaces.empty()) {  // multi-material meshes: the interfaces between regions
        out << "<g id=\"interfaces\" fill=\"none\" stroke=\"#222222\" stroke-width=\"";
        out.fixed(f.boundary_w / 2, 3) << "\" stroke-linecap=\"round\">\n<path d=\"";
        for (const auto& e : mesh.interfaces) {
            out << " M";
            f.point(out, mesh.vertices[static_cast<std::size_t>(e[0])]);
            out << " L";
            f.point(out, mesh.vertices[static_cast<std::size_t>(e[1])]);
        }
        out << "\"/>\n</g>\n";
    }
}

void put_marked(detail::TextSink& out, const SvgFrame& f, const SvgOptions& options) {
    if (options.marked_boxes.empty()) return;
    out << "<g id=\"marked\" fill=\"none\" stroke=\"#d000d0\" stroke-width=\"";
    out.fixed(f.boundary_w, 3) << "\">\n";
    if (!options.marked_label.empty()) out << "<title>" << xml_text(options.marked_label) << "</title>\n";
    for (const auto& b : options.marked_boxes) {
        out << "<rect x=\"";
        out.fixed(f.margin + (b[0] - f.xmin) * f.s, 3) << "\" y=\"";
        out.fixed(f.margin + (f.ymax - b[3]) * f.s, 3) << "\" width=\"";
        out.fixed((b[2] - b[0]) * f.s, 3) << "\" height=\"";
        out.fixed((b[3] - b[1]) * f.s, 3) << "\"/>\n";
    }
    out << "</g>\n";
    if (!options.marked_label.empty()) {
        out << "<text x=\"";
        out.fixed(f.margin, 1) << "\" y=\"";
        out.fixed(f.height - 2, 1) << "\" font-family=\"sans-serif\" font-size=\"10\" fill=\"#d000d0\">"
                                  << xml_text(options.marked_label) << "</text>\n";
    }
}

// A vertical colour bar (low at the bottom) with three labels.
void put_legend(detail::TextSink& out, const SvgFrame& f, const detail::Colouring& colouring) {
    const double lo = colouring.lo, hi = colouring.hi;
    const double x0 = f.width - f.legend_w + 15, y0 = f.margin + 25, bar_h = 180, bar_w = 18;
    out << "<defs><linearGradient id=\"legend-gradient\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">";
    for (int i = 0; i <= 4; ++i) {
        out << "<stop offset=\"";
        out.fixed(i / 4.0, 2) << "\" stop-color=\"" << colour(i / 4.0) << "\"/>";
    }
    out << "</linearGradient></defs>\n<g id=\"legend\" font-family=\"sans-serif\" font-size=\"12\">\n<text x=\"";
    out.fixed(x0 - 5, 1) << "\" y=\"";
    out.fixed(y0 - 10, 1) << "\">" << xml_text(colouring.title) << "</text>\n<rect x=\"";
    out.fixed(x0, 1) << "\" y=\"";
    out.fixed(y0, 1) << "\" width=\"";
    out.fixed(bar_w, 1) << "\" height=\"";
    out.fixed(bar_h, 1) << "\" fill=\"url(#legend-gradient)\" stroke=\"#333\" stroke-width=\"0.5\"/>\n";
    for (int i = 0; i <= 2; ++i) {
        const double v = lo + (hi - lo) * i / 2.0;
        char label[32];
        const auto r = std::to_chars(label, label + sizeof label, v, std::chars_format::general, 4);
        out << "<text x=\"";
        out.fixed(x0 + bar_w + 5, 1) << "\" y=\"";
        out.fixed(y0 + bar_h - bar_h * i / 2.0 + 4, 1) << "\">" << std::string_view(label, r.ptr) << "</text>\n";
    }
    out << "</g>\n";
}

}  // namespace

void write_svg(const Mesh& mesh, std::ostream& os, const SvgOptions& options) {
    detail::check_mesh_arrays(detail::view_of(mesh), "<svg stream>");
    const detail::Colouring colouring =
        detail::picture_colouring(mesh, options.color_by_cell_data, options.color_by_min_angle, "SVG");
    const SvgFrame f = svg_frame(mesh, options, colouring.legend());
    detail::TextSink out(os);
    out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"";
    out.fixed(f.width, 1) << "\" height=\"";
    out.fixed(f.height, 1) << "\" viewBox=\"0 0 ";
    out.fixed(f.width, 1) << ' ';
    out.fixed(f.height, 1) << "\">\n";
    out << "<title>warpmesh: " << static_cast<std::uint64_t>(mesh.vertices.size()) << " vertices, "
        << static_cast<std::uint64_t>(mesh.triangles.size()) << " triangles</title>\n";
    out << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
    put_triangles(out, mesh, f, colouring, options);
    put_boundary(out, mesh, f);
    put_marked(out, f, options);
    if (colouring.legend()) put_legend(out, f, colouring);
    out << "</svg>\n";
}

void write_svg(const Mesh& mesh, const std::string& path, const SvgOptions& options) {
    detail::check_mesh_arrays(detail::view_of(mesh), path);
    write_file_atomically(path, [&](std::ostream& os) { write_svg(mesh, os, options); });
}

}  // namespace warpmesh
