// main.cpp — the `warpmesh` command line.
//
//   warpmesh mesh INPUT -o OUT [options]      mesh an image
//   warpmesh mesh --shape SPEC -o OUT         mesh an analytic shape
//   warpmesh prove [--out DIR] [--threads N]  run the angle prover
//
// Exit codes: 0 success, 1 bad input or output (a clear message, nothing
// written under the requested name), 2 usage error, 3 internal error.
#include <malloc.h>
#include <sys/resource.h>

#include <cerrno>
#include <charconv>
#include <limits>
#include <filesystem>
#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "warpmesh/errors.hpp"
#include "warpmesh/graded.hpp"
#include "warpmesh/image.hpp"
#include "warpmesh/image_levelset.hpp"
#include "warpmesh/materials.hpp"
#include "warpmesh/mesh_checks.hpp"
#include "warpmesh/quality.hpp"
#include "warpmesh/shapes.hpp"
#include "warpmesh/uniform.hpp"
#include "warpmesh/writers.hpp"
#ifdef WARPMESH_HAVE_PROVER
#include "warpmesh/prove.hpp"
#endif

namespace {

using namespace warpmesh;

constexpr const char* version = "0.1.0";

constexpr const char* usage = R"(warpmesh — conforming triangle meshes of 2D level sets by lattice warping

usage:
  warpmesh mesh INPUT -o OUT [options]     mesh an image (PGM P2/P5 8/16-bit, PNG)
  warpmesh mesh --shape SPEC -o OUT [opts] mesh an analytic shape
  warpmesh prove [--out DIR] [--threads N] run the interval-arithmetic angle prover
  warpmesh --help | --version

input (images):
  --iso V                threshold mode: the region is where the bilinear image is
                         above V (default: half the maximum value)
  --inside above|below   threshold mode: objects brighter (above, default) or darker than V
  --label L[,L...]       label mode: the region is the pixels with one of these labels;
  --label nonzero        or every non-zero pixel.  f is the signed distance to the
                         region's boundary, interpolated bilinearly
  --max-pixels N         refuse images with more pixels than N (default 268435456)
  --materials all|L,...  multi-material mesh of a label image: every label (all; 0 is the
                         background) or these labels, every other pixel one background
                         material; interfaces between materials are mesh edges
  --background drop|keep with --materials/--shapes: output the background's triangles
                         (keep) or not (drop, default; it still bounds the materials)

input (shapes):
  --shape SPEC           circle:cx,cy,r  ellipse:cx,cy,a,b  annulus:cx,cy,r1,r2
                         flower:cx,cy,a,b,k  rect:x0,y0,x1,y1
                         union(S;S)  intersect(S;S)  diff(S;S)   (nestable)
  --shapes T=S;T=S...    analytic materials, region tag T for shape S; a later shape wins
                         where they overlap; outside all: background (tag 0)

lattice and algorithm:
  --spacing S            lattice spacing, in pixels for images (default 1)
  --diagonal RULE        separating (default): the mesh boundary follows the level set;
                         maxmin: the paper's rule, the diagonal with the larger minimum angle
  --graded               graded mesh on a 2:1-balanced quadtree: finest along the boundary
  --max-cell K           graded: largest cell, K lattice squares wide (a power of two;
                         default: as coarse as the domain allows)
  --max-squares N        refuse lattices with more than N squares (default 1073741824)

certificates (proofs/*.cert, compiled in):
  --verify / --no-verify check every triangle of a warped square against its key's
                         certified angle interval (default: on); a violation exits
                         with code 3, naming the square
  --no-certify           skip the per-square bounds (no certified_min_angle, no report)
  --guarantee flat       halve the spacing until every warped square's 12-point
                         stencil is flat (theorem F applies); --guarantee any: no refinement
  --min-spacing S        --guarantee flat stops before the spacing drops below S
                         (default: spacing/16)

output:
  -o, --output FILE      the mesh; the format follows the extension:
                         .vtu (VTK XML), .msh (Gmsh 4.1), .node/.ele (Triangle),
                         .svg or .png (pictures)
  --also FILE            write the mesh to another file as well (repeatable)
  --svg-color minangle   colour SVG/PNG triangles by their minimum angle
  --svg-color certified  colour them by the certified minimum angle of their square
  --svg-color region     colour them by region (label); interfaces drawn
  --report FILE          the quality report as JSON (it is printed as text on stdout too)
  --quiet                do not print the text report
  --threads N            OpenMP threads (default: all cores)
  --repeat N             (benchmarks) mesh N times in this process and report the
                         fastest run's phase times; the mesh is the same every time
)";

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

double parse_number(const std::string& opt, const std::string& text) {
    double v = 0;
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (ec != std::errc() || ptr != end || !std::isfinite(v))
        throw UsageError(opt + " expects a finite number, got '" + text + "'");
    return v;
}

std::int64_t parse_integer(const std::string& opt, const std::string& text) {
    std::int64_t v = 0;
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, v);
    if (ec != std::errc() || ptr != end) throw UsageError(opt + " expects an integer, got '" + text + "'");
    return v;
}

struct MeshOptions {
    std::string input, shape;
    std::vector<std::string> outputs;
    std::string report;
    double spacing = 1;
    std::optional<double> iso;
    bool inside_above = true;
    std::optional<std::string> labels;
    std::optional<std::string> materials, shapes;  // multi-material input (materials.hpp)
    std::optional<bool> keep_background;
    DiagonalRule rule = DiagonalRule::separating;
    bool graded = false;
    std::int64_t max_cell = 0;
    std::int64_t max_pixels = std::int64_t{1} << 28;
    std::int64_t max_squares = std::int64_t{1} << 30;
    bool svg_min_angle = false;
    bool svg_certified = false;
    bool svg_region = false;
    bool quiet = false;
    bool certify = true, verify = true, guarantee_flat = false;
    std::optional<double> min_spacing;
    std::int64_t repeat = 1;
};

MeshOptions parse_mesh_options(int argc, char** argv) {
    MeshOptions o;
    for (int i = 0; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) throw UsageError(a + " needs a value");
            return argv[++i];
        };
        if (a == "-o" || a == "--output") o.outputs.insert(o.outputs.begin(), value());
        else if (a == "--also") o.outputs.push_back(value());
        else if (a == "--report") o.report = value();
        else if (a == "--shape") o.shape = value();
        else if (a == "--spacing") o.spacing = parse_number(a, value());
        else if (a == "--iso") o.iso = parse_number(a, value());
        else if (a == "--inside") {
            const std::string v = value();
            if (v != "above" && v != "below") throw UsageError("--inside expects 'above' or 'below', got '" + v + "'");
            o.inside_above = v == "above";
        } else if (a == "--label") o.labels = value();
        else if (a == "--materials") o.materials = value();
        else if (a == "--shapes") o.shapes = value();
        else if (a == "--background") {
            const std::string v = value();
            if (v != "drop" && v != "keep") throw UsageError("--background expects 'drop' or 'keep', got '" + v + "'");
            o.keep_background = v == "keep";
        }
        else if (a == "--diagonal") {
            const std::string v = value();
            if (v == "maxmin") o.rule = DiagonalRule::maxmin;
            else if (v == "separating") o.rule = DiagonalRule::separating;
            else throw UsageError("--diagonal expects 'maxmin' or 'separating', got '" + v + "'");
        } else if (a == "--graded") o.graded = true;
        else if (a == "--max-cell") o.max_cell = parse_integer(a, value());
        else if (a == "--max-pixels") o.max_pixels = parse_integer(a, value());
        else if (a == "--max-squares") o.max_squares = parse_integer(a, value());
        else if (a == "--svg-color") {
            const std::string v = value();
            if (v == "minangle") o.svg_min_angle = true;
            else if (v == "certified") o.svg_certified = true;
            else if (v == "region") o.svg_region = true;
            else throw UsageError("--svg-color expects 'minangle', 'certified' or 'region', got '" + v + "'");
        } else if (a == "--verify") o.verify = true;
        else if (a == "--no-verify") o.verify = false;
        else if (a == "--no-certify") o.certify = false;
        else if (a == "--min-spacing") o.min_spacing = parse_number(a, value());
        else if (a == "--guarantee") {
            const std::string v = value();
            if (v == "flat") o.guarantee_flat = true;
            else if (v == "any") o.guarantee_flat = false;
            else throw UsageError("--guarantee expects 'flat' or 'any', got '" + v + "'");
        } else if (a == "--quiet") o.quiet = true;
        else if (a == "--repeat") {
            o.repeat = parse_integer(a, value());
            if (o.repeat < 1 || o.repeat > 1000) throw UsageError("--repeat expects 1 to 1000");
        }
        else if (a == "--threads") {
            const std::int64_t n = parse_integer(a, value());
            if (n < 1 || n > 1024) throw UsageError("--threads expects 1 to 1024");
#ifdef _OPENMP
            omp_set_num_threads(static_cast<int>(n));
#endif
        } else if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + a + "'");
        else if (o.input.empty()) o.input = a;
        else throw UsageError("more than one input: '" + o.input + "' and '" + a + "'");
    }
    if (!o.input.empty() + !o.shape.empty() + o.shapes.has_value() != 1)
        throw UsageError("give exactly one of an input image or --shape SPEC (or --shapes SPEC)");
    if (o.outputs.empty() && o.report.empty() && o.quiet)
        throw UsageError("nothing to do: no -o, no --report and --quiet");
    if (!(o.spacing > 0) || o.spacing > 1e9) throw UsageError("--spacing must be positive and at most 1e9");
    if (o.max_cell < 0 || (o.max_cell & (o.max_cell - 1)) != 0)
        throw UsageError("--max-cell must be a power of two");
    if (o.min_spacing && !(*o.min_spacing > 0)) throw UsageError("--min-spacing must be positive");
    if (o.guarantee_flat && !o.certify) throw UsageError("--guarantee flat needs the certification (drop --no-certify)");
    if (o.svg_certified && !o.certify) throw UsageError("--svg-color certified needs the certification (drop --no-certify)");
    if (o.max_pixels < 1 || o.max_squares < 1) throw UsageError("--max-pixels and --max-squares must be positive");
    if (!o.shape.empty() && (o.iso || o.labels)) throw UsageError("--iso and --label apply to images, not to --shape");
    if (o.labels && o.iso) throw UsageError("--iso (threshold mode) and --label (label mode) exclude each other");
    if (o.materials && (o.labels || o.iso || o.input.empty()))
        throw UsageError("--materials applies to a label image and excludes --label and --iso");
    if (o.keep_background && !o.materials && !o.shapes) throw UsageError("--background applies to --materials and --shapes");
    if ((o.materials || o.shapes) && o.graded)
        throw UsageError("--graded does not mesh several materials yet: drop --graded (--materials/--shapes mesh the "
                         "uniform lattice)");
    if ((o.materials || o.shapes) && o.guarantee_flat)
        throw UsageError("--guarantee flat is not available with --materials/--shapes");
    return o;
}

// --repeat: run `mesh` n times and return the last result with the fastest
// run's phase times.  The earlier runs are kept only for their times (each
// freed before the next; the heap keeps their pages, so the process's peak
// resident memory can exceed one run's).
template <class Run>
auto fastest_of(std::int64_t n, Run&& mesh) {
    decltype(mesh().times) fastest{};
    for (std::int64_t k = 1; k < n; ++k) {
        const auto t = mesh().times;
        if (k == 1 || t.total() < fastest.total()) fastest = t;
    }
    auto r = mesh();
    if (n > 1 && fastest.total() < r.times.total()) r.times = fastest;
    return r;
}

// A count or size for a message: "%.4g" never overflows (1e+30, inf).
std::string approx(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

// All outputs of one run appear together or not at all.  Each is first written
// (atomically, see atomic_file.hpp) under a staging name in its own directory,
// ".NAME.warpmesh-PID"; only when every file is complete are they renamed onto
// the requested names.  A failure on the way removes the staged files, so a
// failed run leaves neither partial nor stale-mixed outputs behind.  (The
// final renames are within one directory each and do not fail in practice.)
class StagedOutputs {
public:
    // Calls write(staged name) for `path`; remembers to rename it later.  An
    // OutputError's message names the requested path, not the staged one.
    template <class Write>
    void write(const std::string& path, Write&& write) {
        namespace fs = std::filesystem;
        const fs::path p(path);
        const std::string tag = ".warpmesh-" + std::to_string(::getpid()) + "-" + std::to_string(renames_.size());
        // Keep the extension last: the writers choose the format by it.
        const fs::path staged = p.parent_path() / ("." + p.stem().string() + tag + p.extension().string());
        const auto real = output_files(p.string()), tmp = output_files(staged.string());
        for (std::size_t k = 0; k < real.size(); ++k) renames_.emplace_back(tmp[k], real[k]);
        try {
            write(staged.string());
        } catch (const OutputError& e) {
            std::string m = e.what();
            for (std::size_t k = 0; k < real.size(); ++k)
                for (std::size_t at; (at = m.find(tmp[k])) != std::string::npos;) m.replace(at, tmp[k].size(), real[k]);
            throw OutputError(m);
        }
    }
    void commit() {
        for (const auto& [from, to] : renames_)
            if (std::rename(from.c_str(), to.c_str()) != 0)
                throw OutputError("cannot rename '" + from + "' to '" + to + "': " + std::strerror(errno));
        renames_.clear();
    }
    ~StagedOutputs() {
        for (const auto& r : renames_) std::remove(r.first.c_str());
    }

private:
    std::vector<std::pair<std::string, std::string>> renames_;
};

double peak_memory_mb() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return static_cast<double>(ru.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

int run_mesh(int argc, char** argv) {
    const MeshOptions o = parse_mesh_options(argc, argv);
    // Check the outputs' extensions and directories before doing any work.
    for (const auto& out : o.outputs) check_output_path(out);
    if (!o.report.empty()) check_writable(o.report);

    std::unique_ptr<LevelSet> f;
    std::unique_ptr<MaterialField> mf;  // --materials / --shapes: the multi-material mesher
    std::optional<Image> image;
    if (!o.shape.empty()) {
        f = parse_shape(o.shape);
    } else if (o.shapes) {
        mf = parse_material_shapes(*o.shapes);
    } else {
        image = read_image(o.input, static_cast<std::uint64_t>(o.max_pixels));
        const Image& img = *image;
        ImageLevelSetOptions io;
        if (o.labels) {
            io = label_options(*o.labels);
        } else {
            io.mode = ImageMode::threshold;
            io.iso = o.iso ? *o.iso : img.maxval / 2.0;
            io.inside_above = o.inside_above;
        }
        if (img.width < 2 || img.height < 2)
            throw InputError(o.input + ": the image is " + std::to_string(img.width) + " x " +
                             std::to_string(img.height) + " pixels; at least 2 x 2 are needed for one lattice square");
        if (o.materials) mf = make_label_materials(img, *o.materials);
        else f = make_image_levelset(img, io);
    }
    const bool analytic = !o.shape.empty() || o.shapes;
    const Box domain = f ? f->bounds() : mf->bounds();
    auto make_lattice = [&](double spacing) {
        if (analytic) {
            const Box b = domain;
            const double w = (b.xmax - b.xmin) / spacing + 2, h = (b.ymax - b.ymin) / spacing + 2;
            if (!(w * h <= static_cast<double>(o.max_squares)))
                throw InputError("the lattice would have about " + approx(w) + " x " + approx(h) +
                                 " squares, more than --max-squares " +
                                 std::to_string(o.max_squares) + " (use a larger --spacing)");
            return lattice_around(b, spacing);
        }
        const double w = (image->width - 1) / spacing, h = (image->height - 1) / spacing;
        if (!(w * h <= static_cast<double>(o.max_squares)))
            throw InputError("spacing " + approx(spacing) + " gives about " + approx(w * h) +
                             " lattice squares, more than --max-squares " +
                             std::to_string(o.max_squares));
        return lattice_over(domain, spacing);
    };

    // The per-triangle array certified_min_angle (8 bytes a triangle) only when
    // a file will carry it or a picture is coloured by it.
    bool cell_data = o.svg_certified;
    for (const auto& out : o.outputs) cell_data = cell_data || format_carries_cell_data(out);
    const CertifyOptions certify{o.certify, o.certify && cell_data, o.certify && o.verify};
    Mesh mesh;
    CertifiedSummary cert;
    Lattice lattice;
    std::vector<std::pair<std::string, double>> phases;
    std::vector<std::pair<std::string, std::string>> extra;
    std::string material_text;  // the multi-material report's lines
    double spacing = o.spacing;
    const double min_spacing = o.min_spacing ? *o.min_spacing : o.spacing / 16;
    int refinements = 0;
    for (;;) {
        lattice = make_lattice(spacing);
        extra.clear();
        extra.emplace_back("input", json_string(o.shapes ? *o.shapes : o.shape.empty() ? o.input : o.shape));
        extra.emplace_back("levelset", json_string(f ? f->describe() : mf->describe()));
        extra.emplace_back("rule", json_string(o.rule == DiagonalRule::maxmin ? "maxmin" : "separating"));
        extra.emplace_back("spacing", json_number(spacing));
        if (o.repeat > 1) extra.emplace_back("repeat", std::to_string(o.repeat));  // phase times: the fastest run
        extra.emplace_back("lattice", "[" + std::to_string(lattice.nx) + ", " + std::to_string(lattice.ny) + "]");
        if (mf) {
            const MaterialOptions mo{o.keep_background.value_or(false), o.rule, certify};
            MaterialResult r = fastest_of(o.repeat, [&] { return mesh_materials(*mf, lattice, mo); });
            phases = {{"sample", r.times.sample}, {"cut_points", r.times.cut_points}, {"warp", r.times.warp}, {"triangulate", r.times.triangulate}};
            if (o.certify) phases.emplace_back("certify", r.times.certify);
            extra.emplace_back("graded", "false");
            extra.emplace_back("cut_edges", std::to_string(r.cut_edges));
            extra.emplace_back("warped_points", std::to_string(r.warped_points));
            extra.emplace_back("warped_squares", std::to_string(r.warped_squares));
            extra.emplace_back("separating_overrides", std::to_string(r.forced_diagonals));
            for (auto& e : material_report_json(r)) extra.push_back(std::move(e));
            std::vector<std::string> warnings;
            material_text = material_report_text(r, &warnings);
            for (const auto& w : warnings) std::cerr << "warpmesh: warning: " << w << "\n";
            mesh = std::move(r.mesh);
            cert = std::move(r.certified);
        } else if (o.graded) {
            GradedResult r = fastest_of(o.repeat, [&] { return mesh_graded(*f, lattice, o.rule, o.max_cell, certify); });
            mesh = std::move(r.mesh);
            cert = std::move(r.certified);
            phases = {{"tiles", r.times.tiles},
                      {"warp", r.times.warp},
                      {"quadtree", r.times.quadtree},
                      {"triangulate", r.times.triangulate}};
            if (o.certify) phases.emplace_back("certify", r.times.certify);
            std::string levels = "[";
            for (std::size_t k = 0; k < r.leaves_per_level.size(); ++k)
                levels += (k ? ", " : "") + std::to_string(r.leaves_per_level[k]);
            extra.emplace_back("graded", "true");
            extra.emplace_back("leaves_per_level", levels + "]");
            extra.emplace_back("cut_edges", std::to_string(r.cut_edges));
            extra.emplace_back("warped_points", std::to_string(r.warped_points));
            extra.emplace_back("warped_squares", std::to_string(r.stats.warped_squares));
            extra.emplace_back("separating_overrides", std::to_string(r.stats.forced_diagonals));
            extra.emplace_back("sampled_points", std::to_string(r.sampled_points));
        } else {
            UniformResult r = fastest_of(o.repeat, [&] { return mesh_uniform(*f, lattice, o.rule, certify); });
            mesh = std::move(r.mesh);
            cert = std::move(r.certified);
            phases = {{"sample", r.times.sample},
                      {"signs", r.times.signs},
                      {"cut_points", r.times.cut_points},
                      {"warp", r.times.warp},
                      {"triangulate", r.times.triangulate}};
            if (o.certify) phases.emplace_back("certify", r.times.certify);
            extra.emplace_back("graded", "false");
            extra.emplace_back("cut_edges", std::to_string(r.cut_edges));
            extra.emplace_back("warped_points", std::to_string(r.warped_points));
            extra.emplace_back("warped_squares", std::to_string(r.stats.warped_squares));
            extra.emplace_back("separating_overrides", std::to_string(r.stats.forced_diagonals));
        }
        if (!o.guarantee_flat || !cert.available || cert.nonflat_squares == 0) break;
        if (spacing / 2 < min_spacing) {
            std::cerr << "warpmesh: warning: --guarantee flat: " << cert.nonflat_squares
                      << " warped square(s) are still not flat at spacing " << spacing << " (--min-spacing "
                      << min_spacing << "); the mesh is written with its true guarantee "
                      << cert.min_deg << " deg; non-flat squares (i, j) key:";
            for (std::size_t e = 0; e < cert.nonflat_examples.size() && e < 10; ++e)
                std::cerr << (e ? "," : "") << " (" << cert.nonflat_examples[e][0] << ", "
                          << cert.nonflat_examples[e][1] << ") " << cert.nonflat_keys[e];
            std::cerr << "\n";
            break;
        }
        spacing /= 2;
        ++refinements;
    }
    if (mesh.triangles.empty())
        throw InputError("the region is empty at this spacing: no triangle has all three corners inside "
                         "(check --iso/--inside/--label, or use a smaller --spacing); nothing written");
    if (cert.available && !o.shape.empty()) measure_fidelity(mesh, *f, lattice.s, cert);
    if (o.certify && !cert.available)
        std::cerr << "warpmesh: warning: this build has no certificates (proofs/*.cert); no certified bounds\n";

    StagedOutputs staged;
    for (const auto& out : o.outputs) {
        WriteOptions wo;
        wo.svg.color_by_min_angle = o.svg_min_angle;
        if (cert.available && !cert.nonflat_boxes.empty()) {
            wo.svg.marked_boxes = cert.nonflat_boxes;
            wo.svg.marked_label = std::to_string(cert.nonflat_squares) +
                                  " warped square(s) with a non-flat stencil (outlined in magenta); the mesh is certified down to " +
                                  approx(cert.min_deg) + " deg";
        }
        if (o.svg_region) wo.svg.color_by_cell_data = wo.png.color_by_cell_data = "region";
        if (o.svg_certified && cert.available) {
            wo.svg.color_by_cell_data = "certified_min_angle";
            wo.png.color_by_cell_data = "certified_min_angle";
        }
        staged.write(out, [&](const std::string& path) { write_mesh(mesh, path, wo); });
    }
    QualityReport q = compute_quality(mesh, phases);
    extra.emplace_back("peak_memory_mb", json_number(peak_memory_mb()));
    if (o.guarantee_flat) extra.emplace_back("refinements", std::to_string(refinements));
    std::string cert_text;
    if (o.certify) {
        if (!cert.available) {
            extra.emplace_back("certified", "null");
        } else {
            const CertifiedTheorem th = certified_theorem(o.rule);
            std::string j = "{\"min_angle_deg\": " + json_number(cert.min_deg) +
                            ", \"max_angle_deg\": " + json_number(cert.max_deg) +
                            ", \"warped_min_angle_deg\": " + json_number(cert.keyed_min_deg) +
                            ", \"warped_squares\": " + std::to_string(cert.keyed_squares) +
                            ", \"flat_squares\": " + std::to_string(cert.flat_squares) +
                            ", \"nonflat_squares\": " + std::to_string(cert.nonflat_squares) +
                            (mf ? ", \"uncertified_junction_squares\": " + std::to_string(cert.junction_squares) : std::string()) +
                            ", \"nonflat\": [";
            for (std::size_t e = 0; e < cert.nonflat_examples.size(); ++e)
                j += std::string(e ? ", " : "") + "{\"i\": " + std::to_string(cert.nonflat_examples[e][0]) +
                     ", \"j\": " + std::to_string(cert.nonflat_examples[e][1]) + ", \"key\": " +
                     json_string(cert.nonflat_keys[e]) + "}";
            j += "], \"verified\": " + std::string(cert.verified ? "true" : "false") +
                 ", \"theorem_any_deg\": " + json_number(th.min_deg_any) +
                 ", \"theorem_flat_deg\": " + json_number(th.min_deg_flat);
            if (cert.has_fidelity)
                j += ", \"max_boundary_distance\": " + json_number(cert.max_boundary_distance) +
                     ", \"boundary_edges_off_levelset\": " + std::to_string(cert.boundary_edges_off_levelset);
            extra.emplace_back("certified", j + "}");
            std::ostringstream t;
            t.precision(10);
            t << "certified angles     [" << cert.min_deg << ", " << cert.max_deg << "] deg (proofs/"
              << (o.rule == DiagonalRule::maxmin ? "maxmin" : "separating") << ".cert"
              << (cert.verified ? ", every triangle verified" : ", not verified") << ")\n";
            t << "warped squares       " << cert.keyed_squares << " (" << cert.flat_squares << " flat, "
              << cert.nonflat_squares << " not flat)\n";
            if (cert.junction_squares)
                t << "uncertified junction squares " << cert.junction_squares
                  << " (excluded from the certified angles above: no bound is claimed for them)\n";
            if (cert.nonflat_squares) {
                t << "not flat (i, j)     ";
                for (std::size_t e = 0; e < cert.nonflat_examples.size(); ++e)
                    t << " (" << cert.nonflat_examples[e][0] << ", " << cert.nonflat_examples[e][1] << ")";
                if (cert.nonflat_squares > static_cast<std::int64_t>(cert.nonflat_examples.size())) t << " ...";
                t << "\n";
            }
            if (cert.has_fidelity)
                t << "boundary fidelity    max distance to level set " << cert.max_boundary_distance << ", "
                  << cert.boundary_edges_off_levelset << " boundary edges off it\n";
            cert_text = t.str();
        }
    }
    q.extra = extra;
    if (!o.report.empty()) staged.write(o.report, [&](const std::string& path) { write_quality_json(path, q); });
    staged.commit();
    if (!o.quiet) std::cout << quality_text(q) << cert_text << material_text;
    return 0;
}

}  // namespace

// The pipeline allocates and frees large arrays stage after stage.  glibc
// hands each large one fresh pages from mmap and returns them on free, so the
// next stage pays the page faults again (on the 2-core build VM a first touch
// runs at ~1.6 GB/s, slower than the graded mesher's own work).  Serving
// blocks up to 32 MiB (glibc's maximum) from the heap and never trimming it
// lets later stages reuse the pages of earlier ones; peak memory is unchanged.
void tune_malloc() {
#ifdef M_MMAP_THRESHOLD
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, std::numeric_limits<int>::max());
#endif
}

int main(int argc, char** argv) {
    tune_malloc();
    try {
        if (argc < 2) {
            std::cerr << usage;
            return 2;
        }
        const std::string cmd = argv[1];
        if (cmd == "--help" || cmd == "-h" || cmd == "help") {
            std::cout << usage;
            return 0;
        }
        if (cmd == "--version") {
            std::cout << "warpmesh " << version << "\n";
            return 0;
        }
        if (cmd == "mesh") {
            for (int i = 2; i < argc; ++i)
                if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
                    std::cout << usage;
                    return 0;
                }
            return run_mesh(argc - 2, argv + 2);
        }
        if (cmd == "prove") {
#ifdef WARPMESH_HAVE_PROVER
            return prove_main(argc - 1, argv + 1);
#else
            std::cerr << "warpmesh: this build has no prover\n";
            return 3;
#endif
        }
        throw UsageError("unknown command '" + cmd + "' (try 'warpmesh --help')");
    } catch (const UsageError& e) {
        std::cerr << "warpmesh: " << e.what() << "\n";
        return 2;
    } catch (const InputError& e) {
        std::cerr << "warpmesh: error: " << e.what() << "\n";
        return 1;
    } catch (const OutputError& e) {
        std::cerr << "warpmesh: error: " << e.what() << "\n";
        return 1;
    } catch (const std::bad_alloc&) {
        std::cerr << "warpmesh: error: out of memory (try a larger --spacing)\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "warpmesh: internal error: " << e.what() << "\n";
        return 3;
    }
}
