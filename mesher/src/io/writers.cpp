// writers.cpp — the format dispatcher and checks shared by the writers.
#include "warpmesh/writers.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <limits>

#include <unistd.h>

#include "warpmesh/quality.hpp"

namespace warpmesh {

namespace detail {

void check_mesh_arrays(const Mesh& mesh, const std::string& path) {
    auto fail = [&](const std::string& what) { throw OutputError("cannot write '" + path + "': invalid mesh: " + what); };
    const std::size_t nt = mesh.triangles.size();
    if (mesh.region.size() != nt)
        fail("region has " + std::to_string(mesh.region.size()) + " entries for " + std::to_string(nt) + " triangles");
    if (mesh.boundary_tag.size() != mesh.boundary.size())
        fail("boundary_tag has " + std::to_string(mesh.boundary_tag.size()) + " entries for " +
             std::to_string(mesh.boundary.size()) + " boundary edges");
    for (const auto& [name, values] : mesh.cell_data)
        if (values.size() != nt)
            fail("cell data '" + name + "' has " + std::to_string(values.size()) + " entries for " +
                 std::to_string(nt) + " triangles");
    const auto nv = static_cast<std::int64_t>(mesh.vertices.size());
    auto bad = [nv](std::int32_t v) { return v < 0 || v >= nv; };
    for (const auto& t : mesh.triangles)
        if (bad(t[0]) || bad(t[1]) || bad(t[2])) fail("a triangle has a vertex index out of range");
    for (const auto& e : mesh.boundary)
        if (bad(e[0]) || bad(e[1])) fail("a boundary edge has a vertex index out of range");
}

Colouring picture_colouring(const Mesh& mesh, const std::string& cell_data_name, bool by_min_angle,
                            const std::string& what) {
    Colouring c;
    const bool has_array = std::any_of(mesh.cell_data.begin(), mesh.cell_data.end(),
                                       [&](const auto& d) { return d.first == cell_data_name; });
    if (cell_data_name == "region" && !has_array) {
        c.value.assign(mesh.region.begin(), mesh.region.end());
        c.title = "region";
        c.by_region = true;
    } else if (!cell_data_name.empty()) {
        const auto it = std::find_if(mesh.cell_data.begin(), mesh.cell_data.end(),
                                     [&](const auto& d) { return d.first == cell_data_name; });
        if (it == mesh.cell_data.end())
            throw OutputError("no cell data array named '" + cell_data_name + "' to colour the " + what + " by");
        c.value.assign(it->second.begin(), it->second.end());
        c.title = it->first;
        c.lo = std::numeric_limits<double>::infinity(), c.hi = -c.lo;
        for (const double v : c.value)
            if (std::isfinite(v)) c.lo = std::min(c.lo, v), c.hi = std::max(c.hi, v);
        if (!(c.lo <= c.hi)) c.lo = 0, c.hi = 1;
    } else if (by_min_angle) {
        c.value.resize(mesh.triangles.size());
        for (std::size_t k = 0; k < mesh.triangles.size(); ++k) {
            const auto& t = mesh.triangles[k];
            c.value[k] = triangle_angles(mesh.vertices[static_cast<std::size_t>(t[0])],
                                         mesh.vertices[static_cast<std::size_t>(t[1])],
                                         mesh.vertices[static_cast<std::size_t>(t[2])])
                             .min_deg;
        }
        c.title = "min angle (\u00b0)";
    }
    return c;
}

std::uint32_t region_colour(std::int32_t tag) {
    // Hue by the golden angle, so that neighbouring tags differ; two
    // lightness levels alternate.  HSV with s = 0.55, v = 0.95 / 0.8.
    const double h = std::fmod(static_cast<double>(tag) * 137.50776405, 360.0) / 60.0;
    const double v = tag % 2 ? 0.95 : 0.8, s = 0.55, c = v * s, x = c * (1 - std::abs(std::fmod(h, 2.0) - 1)), m = v - c;
    const int sector = static_cast<int>(h) % 6;
    const double rgb[6][3] = {{c, x, 0}, {x, c, 0}, {0, c, x}, {0, x, c}, {x, 0, c}, {c, 0, x}};
    std::uint32_t out = 0;
    for (int k = 0; k < 3; ++k) out = out << 8 | static_cast<std::uint32_t>(std::lround((rgb[sector][k] + m) * 255));
    return out;
}

// The extension of `path` (with its dot), lower-cased: formats are chosen
// case-insensitively.
std::string lower_extension(const std::string& path) {
    std::string ext = std::filesystem::path(path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

std::string triangle_stem(const std::string& path) {
    const std::string ext = lower_extension(path);
    std::string stem = path;
    if (ext == ".node" || ext == ".ele" || ext == ".poly") stem.resize(stem.size() - ext.size());
    return stem;
}

}  // namespace detail

namespace {

enum class Format { vtu, msh, triangle, svg, png };

// The format named by the (case-insensitive) extension of `path`.
Format output_format(const std::string& path) {
    const std::string ext = detail::lower_extension(path);
    if (ext == ".vtu") return Format::vtu;
    if (ext == ".msh") return Format::msh;
    if (ext == ".node" || ext == ".ele" || ext == ".poly") return Format::triangle;
    if (ext == ".svg") return Format::svg;
    if (ext == ".png") {
#ifdef WARPMESH_HAVE_PNG
        return Format::png;
#else
        throw OutputError("cannot write '" + path + "': PNG output needs libpng, which was not found at build time");
#endif
    }
    throw OutputError("cannot write '" + path + "': unknown output format '" + ext +
                      "' (supported: .vtu, .msh, .node/.ele, .svg, .png)");
}

}  // namespace

void check_writable(const std::string& path) {
    namespace fs = std::filesystem;
    const fs::path p(path), dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
    std::error_code ec;
    if (p.filename().empty() || fs::is_directory(p, ec))
        throw OutputError("cannot write '" + path + "': it is a directory, not a file name");
    if (!fs::is_directory(dir, ec))
        throw OutputError("cannot write '" + path + "': '" + dir.string() + "' is not a directory");
    // The file is created in `dir` (a temporary, then renamed), so `dir` must
    // be writable and searchable; an existing file under the name is replaced.
    if (::access(dir.c_str(), W_OK | X_OK) != 0)
        throw OutputError("cannot write '" + path + "': directory '" + dir.string() + "' is not writable");
}

bool format_carries_cell_data(const std::string& path) {
    const Format f = output_format(path);
    return f == Format::vtu || f == Format::msh;
}

void check_output_path(const std::string& path) {
    output_format(path);
    check_writable(path);
}

std::vector<std::string> output_files(const std::string& path) {
    const std::string stem = detail::triangle_stem(path);
    if (stem == path) return {path};
    return {stem + ".node", stem + ".ele", stem + ".poly"};
}

void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options) {
    switch (output_format(path)) {
        case Format::vtu: write_vtu(mesh, path); break;
        case Format::msh: write_msh(mesh, path); break;
        case Format::triangle: write_triangle(mesh, path); break;
        case Format::svg: write_svg(mesh, path, options.svg); break;
        case Format::png: {
            PngOptions png = options.png;
            if (options.svg.color_by_min_angle) png.color_by_min_angle = true;
            write_png(mesh, path, png);
            break;
        }
    }
}

}  // namespace warpmesh
