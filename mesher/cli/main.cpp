// main.cpp — the `warpmesh` command line.
//
//   warpmesh mesh INPUT -o OUT [options]      mesh an image
//   warpmesh mesh --shape SPEC -o OUT         mesh an analytic shape
//   warpmesh mesh3d INPUT|--shape SPEC -o OUT tetrahedra of a volume or a 3D shape
//   warpmesh prove [--out DIR] [--threads N]  run the angle prover
//
// Exit codes: 0 success, 1 bad input or output (a clear message, nothing
// written under the requested name), 2 usage error, 3 internal error.
#include <malloc.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <limits>
#include <filesystem>
#include <unistd.h>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <chrono>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/pipeline/slices.hpp"
#include "warpmesh/io/volume.hpp"
#include "warpmesh/pipeline/mesh3d.hpp"
#include "warpmesh/warpmesh.hpp"
#ifdef WARPMESH_HAVE_PROVER
#include "warpmesh/prove.hpp"
#endif

namespace {

using namespace warpmesh;

constexpr const char* version = "0.1.0";

constexpr const char* usage = R"(warpmesh — conforming triangle meshes of 2D level sets by lattice warping

usage:
  warpmesh mesh INPUT -o OUT [options]     mesh an image (PGM P2/P5 8/16-bit, PNG, TIFF)
                                           or a slice of a volume (NRRD, NIfTI, TIFF)
  warpmesh mesh --shape SPEC -o OUT [opts] mesh an analytic shape
  warpmesh mesh3d INPUT|--shape SPEC -o OUT [opts]
                                           tetrahedra of a volume (NRRD, NIfTI, TIFF) or
                                           a 3D shape: see "3D" below
  warpmesh prove [--out DIR] [--threads N] run the interval-arithmetic angle prover
  warpmesh --help | --version

input (images):
  --iso V                threshold mode: the region is where the bilinear image is
                         above V (default: half the maximum value)
  --inside above|below   threshold mode: objects brighter (above, default) or darker than V
  --label L[,L...]       label mode: the region is the pixels with one of these labels;
  --label nonzero        or every non-zero pixel.  f is the signed distance to the
                         region's boundary, interpolated bilinearly
  --max-pixels N         refuse images and volumes with more pixels (voxels) than N
                         (default 268435456)
  --max-memory MB        refuse, before the work, inputs whose reading or meshing would
                         take more than about MB megabytes (default 2048)
  --materials all|L,...  multi-material mesh of a label image: every label (all; 0 is the
                         background) or these labels, every other pixel one background
                         material; interfaces between materials are mesh edges
                         (2D images and volume slices, in the units below, as for one
                         region)
  --background drop|keep with --materials/--shapes: output the background's triangles
                         (keep) or not (drop, default; it still bounds the materials)

input (volumes: NRRD .nrrd/.nhdr, NIfTI .nii/.nii.gz, multi-page TIFF):
  --slice AXIS=INDEX     mesh one slice: AXIS is the index axis i, j or k, e.g. k=60
  --slices AXIS=A:B      mesh slices A .. B-1, in parallel, one output per slice: -o and
                         --also need a %d field (out_%03d.vtu); --report is a summary
  --units mm|pixels      mesh in the file's physical coordinates (mm, default for NRRD
                         and NIfTI) or in pixels (default for PGM, PNG and TIFF)
                         (--units, --pixel-size, --slice, --slices and --points-3d apply
                         to --label, --iso and --materials alike)
  --pixel-size SX[,SY[,SZ]]  pixel (voxel) size in mm, for any input; implies mm
  --points-3d FILE       also write the mesh's vertices at their 3D positions (CSV x,y,z,
                         in vertex order; with --slices a %d pattern)

input (shapes):
  --shape SPEC           circle:cx,cy,r  ellipse:cx,cy,a,b  annulus:cx,cy,r1,r2
                         flower:cx,cy,a,b,k  rect:x0,y0,x1,y1
                         union(S;S)  intersect(S;S)  diff(S;S)   (nestable; an intersection
                         of shapes with disjoint bounding boxes is the empty set)
  --shapes T=S;T=S...    analytic materials, region tag T for shape S; a later shape wins
                         where they overlap; outside all: background (tag 0)

lattice and algorithm:
  --spacing S            lattice spacing, in the input's units: mm for physical inputs
                         (default: the smaller pixel size), else pixels (default 1)
  --diagonal RULE        separating (default): the mesh boundary follows the level set;
                         maxmin: the paper's rule, the diagonal with the larger minimum angle;
                         fan: separating, but a square whose corners are all inside and
                         whose diagonals both have an angle below atan(1/3) = 18.43 deg
                         gets 4 triangles around its centroid: certified minimum angle
                         18.4349 deg on every input (uniform and --graded
                         meshes of two phases; not with several materials)
  --lattice rhombic      the 60-degree rhombic lattice (interior triangles equilateral,
                         edges of length --spacing) instead of the square one (default):
                         lower error per unknown, lower certified bounds
                         (proofs/rhombic_*.cert: separating [10.8933, 158.2133] deg,
                         maxmin [12.8294, 150.0200] deg); uniform one-region meshes,
                         --diagonal separating or maxmin
  --graded               graded mesh on a 2:1-balanced quadtree: finest along the boundary
                         (with --materials/--shapes: along every interface)
  --max-cell K           graded: largest cell, K lattice squares wide (a power of two;
                         default: as coarse as the domain allows)
  --max-size H           every triangle's longest edge at most H (input units; H >= sqrt(5)
                         * spacing); graded: caps the cells (the smaller of this and
                         --max-cell wins); uniform: the spacing already bounds it (checked)
  --max-size-of T=H      with --materials/--shapes: the triangles of material T (its label
                         or tag) have their longest edge at most H (rules as --max-size;
                         the smaller of the two wins; repeatable, each T once; graded:
                         caps that material's cells; uniform: checked)
  --grading G            graded, 1.1 <= G <= 2 (default 2: 2:1 balance): cell sizes grow
                         away from the boundary by at most a factor G per cell on average
                         (--grading and --max-cell need --graded; --max-size and --max-cell
                         need a positive value: leave them out for no bound)
  --max-squares N        refuse lattices with more than N squares (default 1073741824)
  --optimize             after meshing, move the boundary band's vertices (boundary ones
                         along the level set, interface ones along their interface) and
                         flip its interior edges to raise the worst angles; no triangle's
                         star gets a smaller minimum angle (materials: no label's area
                         error grows, junctions stay put)

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
                         .vtu (VTK XML), .msh (Gmsh), .xdmf (FEniCSx; + _facets.xdmf),
                         .inp (Abaqus/CalculiX), .node/.ele (Triangle), .svg or .png
  --msh-version V        .msh format version: 4.1 (default) or 2.2
  --ascii                every output as text (.vtu, .msh, .xdmf are binary by default)
  --compress             .vtu: zlib-compressed appended binary (default: raw binary)
  --xdmf-inline          .xdmf: heavy data inline as XML, no .h5 (for tiny meshes)
  --msh-cell-data        also write per-triangle data (certified_min_angle) into .msh
  --also FILE            write the mesh to another file as well (repeatable)
  --svg-color minangle   colour SVG/PNG triangles by their minimum angle
  --svg-color certified  colour them by the certified minimum angle of their square
  --svg-color region     colour them by region (label); interfaces drawn
  --report FILE          the quality report as JSON (it is printed as text on stdout too)
  --quiet                do not print the text report
  --threads N            OpenMP threads (default: all cores)
  --repeat N             (benchmarks) mesh N times in this process and report the
                         fastest run's phase times; the mesh is the same every time

3D (warpmesh mesh3d): tetrahedra by BCC lattice warping, dihedral angles certified
(proofs/bcc.cert).  The options of mesh, meaning the same:
  INPUT                  a volume: --label L[,L...]|nonzero (label mode: signed distance
                         between voxel centres) or --iso V [--inside above|below]
                         (threshold mode, trilinear); --units mm|pixels, --pixel-size,
                         --max-pixels, --max-memory as for slices
  --shape SPEC           sphere:cx,cy,cz,r  ellipsoid:cx,cy,cz,a,b,c  torus:cx,cy,cz,R,r
                         box:x0,y0,z0,x1,y1,z1  cylinder:x0,y0,z0,x1,y1,z1,r
                         union(S;S)  intersect(S;S)  diff(S;S)   (needs --spacing)
  --spacing S            the BCC lattice's cube side (default: the smallest voxel size)
  --face-rule parity|delaunay
                         how the stencils' quads are split: delaunay (the default:
                         each face quad by the empty-circle test, at alphas (0.2675,
                         0.39), proofs/bcc_delaunay.cert) or parity (Labelle and
                         Shewchuk's rule at (0.285, 0.3985), proofs/bcc.cert)
  --verify / --no-verify check every certified tetrahedron against the certificate
                         (default: off in 3D)
  -o, --also             .vtu, .msh, .xdmf (+ _facets.xdmf), .inp (C3D4) or .mesh (medit);
                         --ascii, --compress, --xdmf-inline, --msh-version, --msh-cell-data
  --report FILE, --quiet, --threads N
  Other options of mesh have no effect in 3D and are refused.
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

// The value of an option with a fixed set of words: its index in `words`.
std::size_t parse_choice(const std::string& opt, const std::string& v, std::initializer_list<const char*> words) {
    std::string list;
    std::size_t k = 0;
    for (const char* w : words) {
        if (v == w) return k;
        list += std::string(k == 0 ? "" : k + 1 == words.size() ? " or " : ", ") + "'" + w + "'";
        ++k;
    }
    throw UsageError(opt + " expects " + list + ", got '" + v + "'");
}

// The command line's options: the library's MeshOptions (pipeline.hpp) and
// what concerns input and output.
struct CliOptions {
    std::string input, shape;
    std::vector<std::string> outputs;
    std::string report;
    MeshOptions mesh;
    FaceRule face_rule = default_face_rule;  // 3D only (Mesh3dOptions::face_rule)
    std::optional<double> iso;
    bool inside_above = true;
    std::optional<std::string> labels;
    std::optional<std::string> materials, shapes;  // multi-material input (materials.hpp)
    std::int64_t max_pixels = std::int64_t{1} << 28;
    MshOptions msh;
    WriteOptions formats;  // --ascii, --compress, --xdmf-inline (and msh, copied in)
    bool svg_min_angle = false;
    bool svg_certified = false;
    bool svg_region = false;
    bool quiet = false;
    // Volumes and units (volume.hpp).
    std::optional<std::string> slice, slices;
    bool units_pixels = false;
    std::vector<double> pixel_size;
    std::string points_3d;
    // Every option given (for the checks of combinations, e.g. --grading
    // without --graded).
    std::set<std::string> given;
    bool has(const char* option) const { return given.count(option) != 0; }
};

// The arguments, one at a time; value() takes the current option's value.
struct Args {
    int argc;
    char** argv;
    int i = 0;
    std::string value(const std::string& opt) {
        if (i + 1 >= argc) throw UsageError(opt + " needs a value");
        return argv[++i];
    }
};

// Each parse_*_option reads option `a` (and its value) into `o` and returns
// true, or returns false when `a` is none of its options.

// Inputs: images, volumes and units, shapes, materials.
bool parse_input_option(const std::string& a, Args& args, CliOptions& o) {
    if (a == "--shape") o.shape = args.value(a);
    else if (a == "--shapes") o.shapes = args.value(a);
    else if (a == "--slice") o.slice = args.value(a);
    else if (a == "--slices") o.slices = args.value(a);
    else if (a == "--units") o.units_pixels = parse_choice(a, args.value(a), {"mm", "pixels"}) == 1;
    else if (a == "--pixel-size") {
        std::stringstream list(args.value(a));
        o.pixel_size.clear();
        for (std::string item; std::getline(list, item, ',');) o.pixel_size.push_back(parse_number(a, item));
        if (o.pixel_size.empty() || o.pixel_size.size() > 3) throw UsageError("--pixel-size expects SX[,SY[,SZ]]");
    } else if (a == "--iso") o.iso = parse_number(a, args.value(a));
    else if (a == "--inside") o.inside_above = parse_choice(a, args.value(a), {"above", "below"}) == 0;
    else if (a == "--label") o.labels = args.value(a);
    else if (a == "--materials") o.materials = args.value(a);
    else if (a == "--background") o.mesh.keep_background = parse_choice(a, args.value(a), {"drop", "keep"}) == 1;
    else if (a == "--max-pixels") o.max_pixels = parse_integer(a, args.value(a));
    else if (a == "--max-memory") {
        const std::int64_t mb = parse_integer(a, args.value(a));
        if (mb < 1 || mb > (std::int64_t{1} << 40)) throw UsageError("--max-memory expects megabytes, 1 to 2^40");
        o.mesh.max_memory = static_cast<std::uint64_t>(mb) << 20;
    } else return false;
    return true;
}

// The lattice, the algorithm, size control and the certificates.
bool parse_mesher_option(const std::string& a, Args& args, CliOptions& o) {
    MeshOptions& m = o.mesh;
    if (a == "--spacing") m.spacing = parse_number(a, args.value(a));
    else if (a == "--diagonal") {
        constexpr DiagonalRule rules[] = {DiagonalRule::maxmin, DiagonalRule::separating, DiagonalRule::fan};
        m.rule = rules[parse_choice(a, args.value(a), {"maxmin", "separating", "fan"})];
    } else if (a == "--lattice") {
        m.lattice = parse_choice(a, args.value(a), {"square", "rhombic"}) == 1 ? LatticeMetric::rhombic : LatticeMetric::square;
    } else if (a == "--graded") m.graded = true;
    else if (a == "--optimize") m.optimize = true;
    else if (a == "--max-cell") m.max_cell = parse_integer(a, args.value(a));
    else if (a == "--max-size") m.max_size = parse_number(a, args.value(a));
    else if (a == "--grading") m.grading = parse_number(a, args.value(a));
    else if (a == "--max-size-of") {
        const std::string v = args.value(a);
        const std::size_t eq = v.find('=');
        if (eq == std::string::npos) throw UsageError("--max-size-of expects T=H (a material's tag and a size), got '" + v + "'");
        const std::int64_t tag = parse_integer(a + " T", v.substr(0, eq));
        if (tag < 0 || tag > 65535) throw UsageError("--max-size-of T=H: T must be a label or tag 0..65535, got " + std::to_string(tag));
        m.max_size_of.emplace_back(static_cast<std::int32_t>(tag), parse_number(a + " H", v.substr(eq + 1)));
    } else if (a == "--max-squares") m.max_squares = parse_integer(a, args.value(a));
    else if (a == "--verify") m.verify = true;
    else if (a == "--no-verify") m.verify = false;
    else if (a == "--no-certify") m.certify = false;
    else if (a == "--min-spacing") m.min_spacing = parse_number(a, args.value(a));
    else if (a == "--guarantee") m.guarantee = parse_choice(a, args.value(a), {"flat", "any"}) == 0 ? Guarantee::flat : Guarantee::any;
    else if (a == "--face-rule") {
        const std::string v = args.value(a);
        parse_choice(a, v, {face_rule_name(face_rules[0]), face_rule_name(face_rules[1])});  // the message for a bad name
        o.face_rule = *parse_face_rule(v);
    }
    else return false;
    return true;
}

// Outputs, formats, the report, and how the run goes.
bool parse_output_option(const std::string& a, Args& args, CliOptions& o) {
    if (a == "-o" || a == "--output") o.outputs.insert(o.outputs.begin(), args.value(a));
    else if (a == "--also") o.outputs.push_back(args.value(a));
    else if (a == "--report") o.report = args.value(a);
    else if (a == "--points-3d") o.points_3d = args.value(a);
    else if (a == "--msh-version") o.msh.version = parse_choice(a, args.value(a), {"4.1", "2.2"}) == 0 ? 41 : 22;
    else if (a == "--msh-cell-data") o.msh.cell_data = true;
    else if (a == "--ascii") o.formats.ascii = true;
    else if (a == "--compress") o.formats.vtu.encoding = VtuOptions::Encoding::zlib;
    else if (a == "--xdmf-inline") o.formats.xdmf.hdf5 = false;
    else if (a == "--svg-color") {
        const std::size_t c = parse_choice(a, args.value(a), {"minangle", "certified", "region"});
        (c == 0 ? o.svg_min_angle : c == 1 ? o.svg_certified : o.svg_region) = true;
    } else if (a == "--quiet") o.quiet = true;
    else if (a == "--repeat") {
        o.mesh.repeat = parse_integer(a, args.value(a));
        if (o.mesh.repeat < 1 || o.mesh.repeat > 1000) throw UsageError("--repeat expects 1 to 1000");
    } else if (a == "--threads") {
        const std::int64_t n = parse_integer(a, args.value(a));
        if (n < 1 || n > 1024) throw UsageError("--threads expects 1 to 1024");
#ifdef _OPENMP
        omp_set_num_threads(static_cast<int>(n));
#endif
    } else return false;
    return true;
}

// Options that have no effect in this combination are refused rather than
// silently ignored; so are values that only look like sizes (--max-size 0,
// --max-cell 0: the library's "no bound", which the user gets by leaving the
// option out).
void check_mesher_options(const CliOptions& o) {
    const MeshOptions& m = o.mesh;
    try {
        validate(m);
    } catch (const InputError& e) {
        throw UsageError(e.what());
    }
    if (o.has("--max-size") && !(m.max_size > 0))
        throw UsageError("--max-size must be positive and finite (leave it out for no size bound)");
    if (o.has("--max-cell") && m.max_cell < 1)
        throw UsageError("--max-cell must be a power of two >= 1, in lattice squares (leave it out for cells as coarse "
                         "as the domain allows)");
    for (const char* option : {"--grading", "--max-cell"})
        if (o.has(option) && !m.graded)
            throw UsageError(std::string(option) + " applies to graded meshes: add --graded (a uniform mesh's size is its spacing)");
    if (o.has("--min-spacing") && m.guarantee != Guarantee::flat)
        throw UsageError("--min-spacing applies to --guarantee flat");
    if (o.svg_certified && !m.certify) throw UsageError("--svg-color certified needs the certification (drop --no-certify)");
    if (o.slices && m.repeat > 1) throw UsageError("--repeat does not combine with --slices");
    if (o.has("--face-rule"))
        throw UsageError("--face-rule applies to 3D meshes (warpmesh mesh3d): it splits the BCC stencils' quads; 2D's diagonals are --diagonal");
}

void check_input_options(const CliOptions& o) {
    const MeshOptions& m = o.mesh;
    if (!o.input.empty() + !o.shape.empty() + o.shapes.has_value() != 1)
        throw UsageError("give exactly one of an input image or --shape SPEC (or --shapes SPEC)");
    if (o.max_pixels < 1) throw UsageError("--max-pixels must be positive");
    const bool analytic = !o.shape.empty() || o.shapes;
    if (analytic && (o.iso || o.labels || o.has("--inside")))
        throw UsageError("--iso, --inside and --label apply to images, not to --shape/--shapes");
    if (o.labels && o.iso) throw UsageError("--iso (threshold mode) and --label (label mode) exclude each other");
    if (analytic && (o.slice || o.slices || o.has("--units") || !o.pixel_size.empty() || !o.points_3d.empty()))
        throw UsageError("--slice, --slices, --units, --pixel-size and --points-3d apply to images and volumes, not to "
                         "--shape/--shapes");
    if (o.slice && o.slices) throw UsageError("--slice and --slices exclude each other");
    if (o.materials && (o.labels || o.iso || o.has("--inside") || o.input.empty()))
        throw UsageError("--materials applies to a label image and excludes --label, --iso and --inside");
    if (o.labels && o.has("--inside")) throw UsageError("--inside applies to threshold mode (--iso), not to --label");
    if (o.has("--background") && !o.materials && !o.shapes) throw UsageError("--background applies to --materials and --shapes");
    if (!m.max_size_of.empty() && !o.materials && !o.shapes)
        throw UsageError("--max-size-of applies to --materials and --shapes (one region: use --max-size)");
    if (o.materials || o.shapes) {
        if (m.guarantee == Guarantee::flat) throw UsageError("--guarantee flat is not available with --materials/--shapes");
    }
}

// The options of `mesh` and `mesh3d`, before the checks of combinations.
CliOptions parse_arguments(int argc, char** argv) {
    CliOptions o;
    Args args{argc, argv};
    for (; args.i < argc; ++args.i) {
        const std::string a = argv[args.i];
        if (parse_input_option(a, args, o) || parse_mesher_option(a, args, o) || parse_output_option(a, args, o))
            o.given.insert(a);
        else if (!a.empty() && a[0] == '-') throw UsageError("unknown option '" + a + "'");
        else if (o.input.empty()) o.input = a;
        else throw UsageError("more than one input: '" + o.input + "' and '" + a + "'");
    }
    if (o.outputs.empty() && o.report.empty() && o.quiet)
        throw UsageError("nothing to do: no -o, no --report and --quiet");
    return o;
}

CliOptions parse_mesh_options(int argc, char** argv) {
    CliOptions o = parse_arguments(argc, argv);
    check_input_options(o);
    check_mesher_options(o);
    return o;
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
    // `options`: which files a mesh output makes (output_files).
    template <class Write>
    void write(const std::string& path, Write&& write, const WriteOptions& options = {}) {
        namespace fs = std::filesystem;
        const fs::path p(path);
        std::unique_lock lock(mutex_);  // --slices writes from several threads
        const std::string tag = ".warpmesh-" + std::to_string(::getpid()) + "-" + std::to_string(renames_.size());
        // Keep the extension last: the writers choose the format by it.
        const fs::path staged = p.parent_path() / ("." + p.stem().string() + tag + p.extension().string());
        const auto real = output_files(p.string(), options), tmp = output_files(staged.string(), options);
        for (std::size_t k = 0; k < real.size(); ++k) renames_.emplace_back(tmp[k], real[k]);
        lock.unlock();
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
    std::mutex mutex_;
};

// The input file as a volume (images are one slice), with --pixel-size.
Volume read_input(const CliOptions& o) {
    Volume v = read_volume(o.input, {static_cast<std::uint64_t>(o.max_pixels), o.mesh.max_memory});
    for (const auto& w : v.warnings) std::cerr << "warpmesh: warning: " << w << "\n";
    if (!o.pixel_size.empty()) set_pixel_size(v, o.pixel_size);
    if (o.has("--units") && !o.units_pixels && !v.physical)
        throw InputError("--units mm: '" + o.input + "' (" + v.format +
                         ") gives no physical pixel size; give one with --pixel-size SX[,SY]");
    return v;
}

SliceOptions slice_options(const CliOptions& o, std::optional<SliceSpec> slice) {
    SliceOptions so;
    so.slice = slice;
    so.units = o.units_pixels ? Units::pixels : Units::physical;
    so.materials = o.materials;
    so.max_memory = o.mesh.max_memory;
    if (o.labels) {
        so.levelset = label_options(*o.labels);
    } else {
        so.levelset.iso = o.iso;  // default: half the image's maxval, or midway between the slice's extremes
        so.levelset.inside_above = o.inside_above;
    }
    return so;
}

// Mesh one input (a LevelSet, or a MaterialField for --materials/--shapes)
// and stage its outputs (meshes, --points-3d, report); the slice's placement
// goes into the report.  The warnings are returned, not printed.
template <class Field>
MeshResult mesh_and_stage(const CliOptions& o, const Field& f, const LoadedSlice* input, StagedOutputs& staged) {
    // The per-triangle array certified_min_angle (8 bytes a triangle) only when
    // a file will carry it or a picture is coloured by it.
    MeshOptions m = o.mesh;
    m.cell_data = o.svg_certified;
    WriteOptions formats;
    formats.msh = o.msh;
    for (const auto& out : o.outputs) m.cell_data = m.cell_data || format_carries_cell_data(out, formats);
    m.input = o.shapes ? *o.shapes : o.shape.empty() ? o.input : o.shape;
    if (input && !o.has("--spacing")) m.spacing = input->pixel_min;  // mm inputs: the smaller pixel size
    MeshResult r = mesh(f, m);
    if (input) r.report.slice = slice_figures(*input);
    WriteOptions wo = write_options(r, o.svg_min_angle, o.svg_certified);
    if (o.svg_region && !o.svg_certified) wo.svg.color_by_cell_data = wo.png.color_by_cell_data = "region";
    wo.msh = o.msh;
    wo.ascii = o.formats.ascii, wo.vtu = o.formats.vtu, wo.xdmf = o.formats.xdmf;
    for (const auto& out : o.outputs) {
        wo.xdmf.final_path = out;  // the staged .xdmf names its .h5 by the final name
        staged.write(out, [&](const std::string& path) { write_mesh(r.mesh, path, wo); }, wo);
    }
    if (!o.points_3d.empty())
        staged.write(o.points_3d, [&](const std::string& path) { write_points_3d(r.mesh, input->plane, path); });
    if (!o.report.empty()) staged.write(o.report, [&](const std::string& path) { write_text_file(path, to_json(r)); });
    return r;
}

// A loaded slice: its level set, or its materials.
MeshResult mesh_and_stage(const CliOptions& o, const LoadedSlice& input, StagedOutputs& staged) {
    return input.materials ? mesh_and_stage(o, *input.materials, &input, staged) : mesh_and_stage(o, *input.f, &input, staged);
}

void print_warnings(const std::vector<std::string>& warnings) {
    for (const auto& w : warnings) std::cerr << "warpmesh: warning: " << w << "\n";
}

int run_slices(const CliOptions& o);

int run_mesh(int argc, char** argv) {
    CliOptions o = parse_mesh_options(argc, argv);
    if (o.slices) return run_slices(o);
    // Check the outputs' extensions and directories before doing any work.
    for (const auto& out : o.outputs) check_output_path(out);
    if (!o.report.empty()) check_writable(o.report);
    if (!o.points_3d.empty()) check_writable(o.points_3d);

    StagedOutputs staged;
    MeshResult r;
    if (!o.shape.empty() || o.shapes) {
        if (o.shapes) r = mesh_and_stage(o, *parse_material_shapes(*o.shapes), nullptr, staged);
        else r = mesh_and_stage(o, *parse_shape(o.shape), nullptr, staged);
    } else {
        // An image or a slice of a volume: one region, or with --materials
        // every material of its labels.
        const LoadedSlice input =
            load_slice(read_input(o), slice_options(o, o.slice ? std::optional(parse_slice(*o.slice)) : std::nullopt));
        r = mesh_and_stage(o, input, staged);
    }
    print_warnings(r.warnings);
    staged.commit();
    if (!o.quiet) std::cout << to_text(r);
    return 0;
}

// --slices AXIS=A:B: the volume is read once and its slices meshed in
// parallel by mesh_slices (slices.hpp), one output set per slice from the %d
// patterns, one summary (stdout, --report); the slices' warnings are printed
// after the batch, each naming its slices.
int run_slices(const CliOptions& o) {
    const SliceRange range = parse_slice_range(*o.slices);
    auto name = [&](const std::string& pattern, std::int64_t k) {
        try {
            return slice_file_name(pattern, k);
        } catch (const InputError& e) {
            throw UsageError(e.what());
        }
    };
    for (const auto& out : o.outputs) check_output_path(name(out, range.first));
    if (!o.points_3d.empty()) check_writable(name(o.points_3d, range.first));
    if (!o.report.empty()) check_writable(o.report);
    const auto t0 = std::chrono::steady_clock::now();
    const Volume volume = read_input(o);
    StagedOutputs staged;
    const SliceBatch batch = mesh_slices(
        volume, range, slice_options(o, std::nullopt),
        [&](const LoadedSlice& input) {
            const std::int64_t k = input.slice.index;
            CliOptions ok = o;
            ok.outputs.clear();
            for (const auto& out : o.outputs) ok.outputs.push_back(name(out, k));
            if (!o.points_3d.empty()) ok.points_3d = name(o.points_3d, k);
            ok.report.clear();
            MeshResult r = mesh_and_stage(ok, input, staged);
            SliceMeshed m{std::move(r.report.quality), {}, std::move(r.warnings)};
            for (const auto& out : ok.outputs) m.outputs += (m.outputs.empty() ? "" : ", ") + out;
            return m;
        },
        seconds_since(t0));
    print_warnings(batch_warnings(batch));
    if (!o.report.empty()) staged.write(o.report, [&](const std::string& path) { write_text_file(path, to_json(batch)); });
    staged.commit();
    if (!o.quiet) std::cout << to_text(batch);
    return 0;
}

// ---- warpmesh mesh3d ------------------------------------------------------------------
//
// The 3D pipeline (pipeline/mesh3d.hpp: validate, mesh3d) behind the same
// option names and parsing as `mesh`.  Options of `mesh` that would have no
// effect in 3D are refused with the reason, never ignored.

// Why an option of `mesh` is refused by mesh3d (empty: it applies).
std::string refused_in_3d(const std::string& option) {
    static const std::set<std::string> applies = {
        "--shape",   "--iso",       "--inside", "--label",  "--units",       "--pixel-size", "--max-pixels",
        "--max-memory", "--spacing", "--verify", "--no-verify", "-o",        "--output",     "--also",
        "--report",  "--quiet",     "--threads", "--ascii", "--compress",    "--xdmf-inline", "--msh-version",
        "--msh-cell-data", "--face-rule"};
    if (applies.count(option)) return {};
    if (option == "--materials" || option == "--shapes" || option == "--background" || option == "--max-size-of")
        return "multi-material 3D meshes are not built yet (docs/3d.md); mesh one region with --label L,...";
    if (option == "--graded" || option == "--max-cell" || option == "--max-size" || option == "--grading")
        return "graded (octree) 3D meshes are not built yet (docs/3d.md); the size is the --spacing";
    if (option == "--slice" || option == "--slices" || option == "--points-3d")
        return "mesh3d meshes the whole volume in 3D; it applies to 2D meshes of slices (warpmesh mesh)";
    if (option == "--diagonal" || option == "--guarantee" || option == "--min-spacing")
        return "3D splits the BCC stencils' quads by --face-rule parity|delaunay, certified as they are";
    if (option == "--svg-color") return "pictures are 2D (.svg, .png); 3D meshes go to .vtu, .msh, .xdmf, .inp or .mesh";
    if (option == "--no-certify") return "every 3D mesh is looked up in the certificate (it costs nothing)";
    return "it is an option of the 2D mesher (warpmesh mesh)";
}

// The input the command line names: a volume file or --shape SPEC.
Mesh3dInput mesh3d_input(const CliOptions& o) {
    if (o.shape.empty()) return VolumeFile{o.input};
    return Shape3{o.shape};
}

// The library's options from the command line's.
Mesh3dOptions mesh3d_options(const CliOptions& o) {
    Mesh3dOptions mo;
    if (o.has("--spacing")) mo.spacing = o.mesh.spacing;
    mo.face_rule = o.face_rule;  // and the rule's alphas (face_rule_alphas)
    mo.verify = o.has("--verify") && o.mesh.verify;
    mo.max_memory = o.mesh.max_memory;
    mo.max_voxels = static_cast<std::uint64_t>(std::max<std::int64_t>(o.max_pixels, 0));
    mo.labels = o.labels;
    mo.iso = o.iso;
    if (o.has("--inside")) mo.inside_above = o.inside_above;
    if (o.has("--units")) mo.units = o.units_pixels ? Units::pixels : Units::physical;
    mo.voxel_size = o.pixel_size;
    return mo;
}

CliOptions parse_mesh3d_options(int argc, char** argv) {
    CliOptions o = parse_arguments(argc, argv);
    for (const auto& option : o.given)
        if (const std::string why = refused_in_3d(option); !why.empty())
            throw UsageError(option + " has no effect in 3D (warpmesh mesh3d): " + why);
    if (o.input.empty() == o.shape.empty()) throw UsageError("give exactly one of an input volume or --shape SPEC");
    try {
        validate(mesh3d_input(o), mesh3d_options(o));
    } catch (const InputError& e) {
        throw UsageError(e.what());
    }
    return o;
}

// Stage lines on stderr ("warpmesh: meshing ... (12.3 s)"), only on a
// terminal and for large inputs: a user waiting on a brain volume sees where
// the time goes; pipes and small runs stay quiet.
struct Progress {
    bool terminal = false;  // stderr is a terminal and not --quiet
    bool large = false;     // the input is large enough to be worth it
    std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
    void stage(const std::string& what) const {
        if (!terminal || !large) return;
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        char buf[32];
        std::snprintf(buf, sizeof buf, " (%.1f s)", t);
        std::cerr << "warpmesh: " << what << buf << std::endl;
    }
};

int run_mesh3d(int argc, char** argv) {
    const CliOptions o = parse_mesh3d_options(argc, argv);
    for (const auto& out : o.outputs) check_output_path_3d(out);
    if (!o.report.empty()) check_writable(o.report);
    Progress progress;
    progress.terminal = !o.quiet && ::isatty(STDERR_FILENO);
    const Mesh3dResult r = mesh3d(mesh3d_input(o), mesh3d_options(o), [&](const std::string& stage) {
        progress.large = true;
        progress.stage(stage);
    });
    const TetMesh& mesh = r.mesh;
    const Mesh3dReport& report = r.report;
    StagedOutputs staged;
    WriteOptions wo = o.formats;
    wo.msh = o.msh;
    for (const auto& out : o.outputs) {
        progress.stage("writing " + out);
        wo.xdmf.final_path = out;  // the staged .xdmf names its .h5 by the final name
        staged.write(out, [&](const std::string& path) { write_mesh(mesh, path, wo); }, wo);
    }
    if (!o.report.empty()) staged.write(o.report, [&](const std::string& path) { write_text_file(path, to_json(report)); });
    print_warnings(r.warnings);
    staged.commit();
    progress.stage("done");
    if (!o.quiet) std::cout << to_text(report);
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
        if (cmd == "mesh" || cmd == "mesh3d") {
            for (int i = 2; i < argc; ++i)
                if (std::strcmp(argv[i], "--help") == 0 || std::strcmp(argv[i], "-h") == 0) {
                    std::cout << usage;
                    return 0;
                }
            return cmd == "mesh" ? run_mesh(argc - 2, argv + 2) : run_mesh3d(argc - 2, argv + 2);
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
        std::cerr << "warpmesh: error: out of memory: an allocation failed although the estimate was within the "
                     "--max-memory limit (this machine or a ulimit allows less): lower --max-memory to what is "
                     "available, or use a larger --spacing or a smaller input\n";
        return 1;
    } catch (const std::exception& e) {
        std::cerr << "warpmesh: internal error: " << e.what() << "\n";
        return 3;
    }
}
