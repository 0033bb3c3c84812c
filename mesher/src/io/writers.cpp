// writers.cpp — the format dispatcher and checks shared by the writers.
#include "io/atomic_file.hpp"
#include "io/output.hpp"
#include "warpmesh/io/writers.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <set>

#include <unistd.h>

#include "warpmesh/core/triangle_shape.hpp"

namespace warpmesh {

namespace detail {

void check_mesh_arrays(const MeshView& mesh, const std::string& path) {
    auto fail = [&](const std::string& what) { throw OutputError("cannot write '" + path + "': invalid mesh: " + what); };
    const std::size_t nt = mesh.cells.size(), nb = mesh.num_boundary(), ni = mesh.num_interfaces();
    const std::string cells = mesh.cells.kind.dim == 3 ? " tetrahedra" : " triangles";
    const std::string facets = mesh.facet_kind.dim == 2 ? " triangles" : " edges";
    if (mesh.region.size() != nt)
        fail("region has " + std::to_string(mesh.region.size()) + " entries for " + std::to_string(nt) + cells);
    if (mesh.boundary_tag.size() != nb)
        fail("boundary_tag has " + std::to_string(mesh.boundary_tag.size()) + " entries for " + std::to_string(nb) +
             " boundary" + facets);
    for (const auto& [name, values] : mesh.cell_data)
        if (values.size() != nt)
            fail("cell data '" + name + "' has " + std::to_string(values.size()) + " entries for " + std::to_string(nt) + cells);
    const auto nv = static_cast<std::int64_t>(mesh.num_vertices);
    auto bad = [nv](std::span<const std::int32_t> ids) {
        return std::any_of(ids.begin(), ids.end(), [nv](std::int32_t v) { return v < 0 || v >= nv; });
    };
    if (bad(mesh.cells.nodes)) fail("a" + std::string(mesh.cells.kind.dim == 3 ? " tetrahedron" : " triangle") + " has a vertex index out of range");
    if (bad(mesh.boundary)) fail("a boundary" + facets.substr(0, facets.size() - 1) + " has a vertex index out of range");
    if (mesh.interface_regions.size() != ni)
        fail("interface_regions has " + std::to_string(mesh.interface_regions.size()) + " entries for " + std::to_string(ni) +
             " interface" + facets);
    if (bad(mesh.interfaces)) fail("an interface" + facets.substr(0, facets.size() - 1) + " has a vertex index out of range");
    for (const auto& r : mesh.interface_regions)
        if (r[0] == r[1])
            fail("an interface" + facets.substr(0, facets.size() - 1) + " has the same region (" + std::to_string(r[0]) +
                 ") on both sides");
}

void fill_atomic_file(AtomicFile& f, const std::function<void(std::ostream&)>& body) {
    try {
        body(f.stream());
    } catch (const OutputError&) {
        throw;
    } catch (const std::exception& e) {
        throw OutputError("cannot write '" + f.path() + "': " + e.what());
    }
    f.close();
}

std::string xml_escape(std::string_view s) {
    std::string r;
    for (const char c : s) {
        switch (c) {
            case '&': r += "&amp;"; break;
            case '<': r += "&lt;"; break;
            case '>': r += "&gt;"; break;
            case '"': r += "&quot;"; break;
            case '\'': r += "&apos;"; break;
            default: r += c;
        }
    }
    return r;
}

std::vector<std::int32_t> region_tags(const MeshView& mesh) {
    // Tags come in long runs: compare with the last one before the set lookup.
    std::set<std::int32_t> tags;
    for (std::size_t k = 0; k < mesh.region.size(); ++k)
        if (k == 0 || mesh.region[k] != mesh.region[k - 1]) tags.insert(mesh.region[k]);
    return {tags.begin(), tags.end()};
}

std::string region_name(const MeshView& mesh, std::int32_t tag, bool single_region) {
    for (const auto& [t, name] : mesh.region_names)
        if (t == tag && !name.empty()) return name;
    return single_region ? std::string("domain") : "domain_" + std::to_string(tag);
}

std::vector<FacetGroup> facet_groups(const MeshView& mesh) {
    std::vector<FacetGroup> groups;
    const auto per = static_cast<std::size_t>(mesh.facet_kind.nodes);
    std::map<std::int32_t, std::size_t> by_tag;  // boundary tag → group
    for (const std::int32_t t : mesh.boundary_tag) by_tag.try_emplace(t, 0);
    const bool all_positive = by_tag.empty() || by_tag.begin()->first >= 1;
    std::int32_t last = 2;
    for (auto& [t, slot] : by_tag) {
        slot = groups.size();
        FacetGroup g;
        g.tag = all_positive ? t : static_cast<std::int32_t>(groups.size() + 1);
        g.name = t == boundary_level_set ? "boundary" : t == boundary_domain ? "domain_border" : "boundary_" + std::to_string(t);
        g.kind = mesh.facet_kind;
        last = std::max(last, g.tag);
        groups.push_back(std::move(g));
    }
    for (std::size_t k = 0; k < mesh.num_boundary(); ++k) {
        FacetGroup& g = groups[by_tag.at(mesh.boundary_tag[k])];
        g.index.push_back(k);
        const auto f = mesh.boundary.subspan(k * per, per);
        g.nodes.insert(g.nodes.end(), f.begin(), f.end());
    }
    std::map<std::pair<std::int32_t, std::int32_t>, std::size_t> by_pair;  // {a < b} → group
    for (const auto& r : mesh.interface_regions) by_pair.try_emplace({std::min(r[0], r[1]), std::max(r[0], r[1])}, 0);
    for (auto& [pair, slot] : by_pair) {
        slot = groups.size();
        FacetGroup g;
        g.tag = ++last;
        g.name = "interface_" + std::to_string(pair.first) + "_" + std::to_string(pair.second);
        g.interface = true;
        g.left_region = pair.first, g.right_region = pair.second;
        g.kind = mesh.facet_kind;
        groups.push_back(std::move(g));
    }
    for (std::size_t k = 0; k < mesh.num_interfaces(); ++k) {
        const auto& r = mesh.interface_regions[k];
        const auto f = mesh.interfaces.subspan(k * per, per);
        FacetGroup& g = groups[by_pair.at({std::min(r[0], r[1]), std::max(r[0], r[1])})];
        g.index.push_back(k);
        // Reversing a simplex's vertex order reverses its orientation (an
        // edge's direction, a triangle's normal).
        if (r[0] > r[1]) g.nodes.insert(g.nodes.end(), f.rbegin(), f.rend());
        else g.nodes.insert(g.nodes.end(), f.begin(), f.end());
    }
    return groups;
}

std::vector<std::int32_t> vertex_markers(const MeshView& mesh, const std::vector<FacetGroup>& groups) {
    // One array (group tags are >= 1): interface tags first, kept negative
    // (-smallest), then boundary tags override them (smallest); the vertices
    // left negative are on interfaces only.
    std::vector<std::int32_t> marker(mesh.num_vertices, 0);
    for (const FacetGroup& g : groups)
        if (g.interface)
            for (const std::int32_t v : g.nodes) {
                std::int32_t& m = marker[static_cast<std::size_t>(v)];
                m = m == 0 ? -g.tag : std::max(m, -g.tag);
            }
    for (const FacetGroup& g : groups)
        if (!g.interface)
            for (const std::int32_t v : g.nodes) {
                std::int32_t& m = marker[static_cast<std::size_t>(v)];
                m = m <= 0 ? g.tag : std::min(m, g.tag);
            }
    for (const FacetGroup& g : groups)
        if (g.interface)
            for (const std::int32_t v : g.nodes) marker[static_cast<std::size_t>(v)] = std::abs(marker[static_cast<std::size_t>(v)]);
    return marker;
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

std::string xdmf_facets_path(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    return path.substr(0, path.size() - ext.size()) + "_facets" + ext;
}

std::string xdmf_h5_path(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    return path.substr(0, path.size() - ext.size()) + ".h5";
}

double typical_edge_px(const Mesh& mesh, double scale) {
    const std::size_t nt = mesh.triangles.size();
    if (!nt) return 10;
    double area = 0;
    for (const auto& t : mesh.triangles) {
        const Vec2 &a = mesh.vertices[static_cast<std::size_t>(t[0])], &b = mesh.vertices[static_cast<std::size_t>(t[1])],
                   &c = mesh.vertices[static_cast<std::size_t>(t[2])];
        area += std::abs((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x)) / 2;
    }
    return std::sqrt(4 * area / (std::sqrt(3.0) * static_cast<double>(nt))) * scale;
}

}  // namespace detail

namespace {

enum class Format { vtu, msh, xdmf, inp, medit, triangle, svg, png };

// The format named by the (case-insensitive) extension of `path`.
Format output_format(const std::string& path) {
    const std::string ext = detail::lower_extension(path);
    if (ext == ".vtu") return Format::vtu;
    if (ext == ".msh") return Format::msh;
    if (ext == ".xdmf") return Format::xdmf;
    if (ext == ".inp") return Format::inp;
    if (ext == ".mesh") return Format::medit;
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
                      "' (supported: .vtu, .msh, .xdmf, .inp, .mesh, .node/.ele, .svg, .png)");
}

// The format of a tetrahedral mesh's output `path`: the 2D-only formats are
// refused by name.
Format output_format_3d(const std::string& path) {
    const Format f = output_format(path);
    if (f == Format::triangle || f == Format::svg || f == Format::png)
        throw OutputError("cannot write '" + path + "': '" + detail::lower_extension(path) +
                          "' is a 2D format; a tetrahedral mesh is written as .vtu, .msh, .xdmf, .inp or .mesh");
    return f;
}

// Writes a mesh of either kind in one of the formats both have; false for
// the 2D-only formats (left to the caller).
template <class M>
bool write_shared_format(const M& mesh, Format format, const std::string& path, const WriteOptions& options) {
    switch (format) {
        case Format::vtu: {
            VtuOptions vtu = options.vtu;
            if (options.ascii) vtu.encoding = VtuOptions::Encoding::ascii;
            write_vtu(mesh, path, vtu);
            return true;
        }
        case Format::msh: {
            MshOptions msh = options.msh;
            msh.binary = msh.binary && !options.ascii;
            write_msh(mesh, path, msh);
            return true;
        }
        case Format::xdmf: {
            XdmfOptions xdmf = options.xdmf;
            xdmf.hdf5 = xdmf.hdf5 && !options.ascii;
            write_xdmf(mesh, path, xdmf);
            return true;
        }
        case Format::inp: write_inp(mesh, path); return true;
        case Format::medit: write_medit(mesh, path); return true;
        default: return false;
    }
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

bool format_carries_cell_data(const std::string& path, const WriteOptions& options) {
    const Format f = output_format(path);
    return f == Format::vtu || (f == Format::msh && options.msh.cell_data);
}

void check_output_path(const std::string& path) {
    output_format(path);
    check_writable(path);
}

std::vector<std::string> output_files(const std::string& path, const WriteOptions& options) {
    if (detail::lower_extension(path) == ".xdmf") {
        const std::string facets = detail::xdmf_facets_path(path);
        if (options.ascii || !options.xdmf.hdf5) return {path, facets};
        return {path, facets, detail::xdmf_h5_path(path), detail::xdmf_h5_path(facets)};
    }
    const std::string stem = detail::triangle_stem(path);
    if (stem == path) return {path};
    return {stem + ".node", stem + ".ele", stem + ".poly"};
}

void write_mesh(const Mesh& mesh, const std::string& path, const WriteOptions& options) {
    const Format format = output_format(path);
    if (write_shared_format(mesh, format, path, options)) return;
    switch (format) {
        case Format::triangle: write_triangle(mesh, path); break;
        case Format::svg: write_svg(mesh, path, options.svg); break;
        case Format::png: {
            PngOptions png = options.png;
            if (options.svg.color_by_min_angle) png.color_by_min_angle = true;
            write_png(mesh, path, png);
            break;
        }
        default: break;
    }
}

void write_mesh(const TetMesh& mesh, const std::string& path, const WriteOptions& options) {
    write_shared_format(mesh, output_format_3d(path), path, options);
}

void check_output_path_3d(const std::string& path) {
    output_format_3d(path);
    check_writable(path);
}

void write_text_file(const std::string& path, std::string_view text) {
    write_file_atomically(path, [&](std::ostream& os) { os.write(text.data(), static_cast<std::streamsize>(text.size())); });
}

}  // namespace warpmesh
