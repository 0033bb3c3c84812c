// mesh2d.cpp — the 2D pipeline (pipeline/mesh2d.hpp: mesh()): the lattice,
// the mesher (uniform or graded, one region or materials), the certification
// of the keys it recorded, Guarantee::flat's refinement, the resolution check, the
// optimisation pass, the boundary fidelity, the quality measurement.  Each
// stage is a function here or in its own module; mesh() runs them in order
// and fills the typed report (report.hpp: Mesh2dReport) with their figures;
// its text and JSON are the report module's (only the warnings, messages,
// are written here).
#include "warpmesh/pipeline/mesh2d.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/mesh2d/graded.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/report/report.hpp"
#include "warpmesh/core/memory.hpp"
#include "warpmesh/post/optimize.hpp"
#include "warpmesh/post/resolution.hpp"
#include "warpmesh/mesh2d/uniform.hpp"
#include "mesh2d/uniform/rhombic.hpp"

namespace warpmesh {

namespace {

// A stage's result (uniform.hpp, graded.hpp, materials.hpp) and its
// certification.
template <class Result>
struct Certified {
    Result r;
    CertifiedSummary certified;
};

// The stage's result certified as `options` say (certify, below; nothing
// without options.enabled), its keys then freed.
template <class Result>
Certified<Result> certified_run(Result r, const Lattice& lattice, DiagonalRule rule, const CertifyOptions& options) {
    Certified<Result> c{std::move(r), {}};
    if (options.enabled) c.certified = certify(c.r, lattice, rule, options);
    c.r.keys = {};
    return c;
}

// Run `mesh` (a stage and its certification) n times and return the last
// run with the fastest run's phase times.  The earlier runs are kept only for
// their times (each freed before the next; the heap keeps their pages, so the
// process's peak resident memory can exceed one run's).
template <class Run>
auto fastest_of(std::int64_t n, Run&& mesh) {
    decltype(mesh().r.times) fastest{};
    for (std::int64_t k = 1; k < n; ++k) {
        const auto t = mesh().r.times;
        if (k == 1 || t.total() < fastest.total()) fastest = t;
    }
    auto c = mesh();
    if (n > 1 && fastest.total() < c.r.times.total()) c.r.times = fastest;
    return c;
}

// The certification of a stage's keys, timed with their gathering.
template <class Result>
CertifiedSummary certify_stage(Result& r, const Lattice& lattice, DiagonalRule rule, const CertifyOptions& options) {
    const auto t0 = std::chrono::steady_clock::now();
    CertifiedSummary c = certify_keys(r.mesh, lattice, r.keys, rule, options);
    r.times.certify = r.keys.seconds + seconds_since(t0);
    return c;
}

// A count or size for a message: "%.4g" never overflows (1e+30, inf).
std::string approx(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

double peak_memory_mb() {
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    return static_cast<double>(ru.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

// The lattice of this spacing over the bounds b (domain: images) or around
// them (shapes), within options.max_squares.
Lattice make_lattice(const Box& b, bool domain, double spacing, const MeshOptions& o) {
    if (!domain) {
        const double w = (b.xmax - b.xmin) / spacing + 2, h = (b.ymax - b.ymin) / spacing + 2;
        if (!(w * h <= static_cast<double>(o.max_squares)))
            throw OptionError("max_squares", "the lattice would have about " + approx(w) + " x " + approx(h) +
                                                 " squares, more than {max_squares} " + std::to_string(o.max_squares) +
                                                 " (use a larger {spacing})");
        return lattice_around(b, spacing);
    }
    const double w = (b.xmax - b.xmin) / spacing, h = (b.ymax - b.ymin) / spacing;
    if (!(w * h <= static_cast<double>(o.max_squares)))
        throw OptionError("max_squares", "spacing " + approx(spacing) + " gives about " + approx(w * h) +
                                             " lattice squares, more than {max_squares} " + std::to_string(o.max_squares));
    return lattice_over(b, spacing);
}

// The admission check before a lattice-sized allocation (memory.hpp):
// graded meshes of analytic shapes (not domain-bounded) are sized by their
// boundary, not their squares, and are not estimated.
// materials: their count (0: one region).
// With optimize, a uniform mesh's admission counts the pass too (two
// triangles a square at most), so such a run is refused before the meshing;
// a graded mesh's pass is checked on its triangles (check_optimize_memory).
void check_lattice_memory(const Lattice& lattice, bool domain, int materials, const MeshOptions& o) {
    if (o.graded && !domain) return;
    const std::uint64_t squares = static_cast<std::uint64_t>(lattice.nx) * static_cast<std::uint64_t>(lattice.ny);
    const std::uint64_t per =
        mesh_bytes_per_square(materials > 0, o.graded) + (o.optimize && !o.graded ? optimize_bytes_per_square(materials > 0) : 0);
    const std::uint64_t per_material = mesh_bytes_per_material();
    check_memory(squares * per + static_cast<std::uint64_t>(materials) * per_material, o.max_memory, "meshing",
                 std::to_string(lattice.nx) + " x " + std::to_string(lattice.ny) + " lattice squares at " +
                     std::to_string(per) + " bytes each" + (o.optimize && !o.graded ? ", the optimisation pass included" : "") +
                     (materials > 0 ? ", " + std::to_string(materials) + " materials at " + std::to_string(per_material) + " bytes each"
                                    : std::string()),
                 "use a larger {spacing}");
}

// The optimisation pass's admission, with the mesh made: its bytes a
// triangle above what the process holds (memory.hpp).
void check_optimize_memory(const Mesh& mesh, bool materials, const MeshOptions& o) {
    const std::uint64_t per = optimize_bytes_per_triangle(materials);
    check_memory(static_cast<std::uint64_t>(mesh.triangles.size()) * per, o.max_memory, "the optimisation pass",
                 std::to_string(mesh.triangles.size()) + " triangles at " + std::to_string(per) + " bytes each",
                 "use a larger {spacing}, or leave out {optimize}");
}

}  // namespace

namespace {

// The largest cell the quadtree may keep: max_cell (0: none) and the cell the
// size bound H allows (max_cell_for_size; H = 0: none), the smaller.
std::int64_t largest_cell(std::int64_t max_cell, double max_size, double spacing) {
    if (max_size == 0) return max_cell;
    const std::int64_t K = max_cell_for_size(max_size, spacing);
    return max_cell == 0 ? K : std::min(max_cell, K);
}

}  // namespace

namespace {

using Phases = std::vector<std::pair<std::string, double>>;

// The report's lattice part: what is meshed (options.input, `describe`) and
// on which lattice (of this spacing).
LatticeFigures lattice_figures(const MeshOptions& o, std::string describe, double spacing, const Lattice& lattice) {
    LatticeFigures l;
    l.input = o.input;
    l.levelset = std::move(describe);
    l.rule = rule_of(o);
    l.spacing = spacing;
    l.repeat = o.repeat;
    l.nx = lattice.nx, l.ny = lattice.ny;
    l.metric = o.lattice;
    return l;
}

// A graded mesh's size control for the report, only when the options set one
// (a max size or a grading other than 2: default reports unchanged).
std::optional<SizeControlFigures> size_control(const MeshOptions& o, std::int64_t max_cell, int buffer) {
    if (o.max_size == 0 && o.grading == max_grading) return std::nullopt;
    return SizeControlFigures{o.max_size, max_cell, o.grading, buffer};
}

// One region on one lattice: the uniform or graded mesher (the fastest of
// o.repeat runs) with its certification, its phase times and its counts.
struct RegionMeshed {
    Mesh mesh;
    CertifiedSummary certified;
    Phases phases;
    MesherFigures figures;
};

RegionMeshed mesh_region(const LevelSet& f, const Lattice& lattice, const MeshOptions& o, const CertifyOptions& certify) {
    RegionMeshed out;
    MesherFigures& m = out.figures;
    m.graded = o.graded;
    const KeyOptions keys{certify.enabled, certify.verify};
    auto counts = [&](const auto& r) {
        m.cut_edges = r.cut_edges, m.warped_points = r.warped_points;
        m.warped_squares = r.stats.warped_squares, m.separating_overrides = r.stats.forced_diagonals;
    };
    if (o.graded) {
        const std::int64_t max_cell = largest_cell(o.max_cell, o.max_size, lattice.s);
        const int buffer = grading_buffer(o.grading);
        auto [r, certified] = fastest_of(o.repeat, [&] {
            return certified_run(mesh_graded(f, lattice, rule_of(o), max_cell, keys, buffer), lattice, rule_of(o), certify);
        });
        out.phases = {{"tiles", r.times.tiles}, {"warp", r.times.warp}, {"quadtree", r.times.quadtree}, {"triangulate", r.times.triangulate}};
        if (o.certify) out.phases.emplace_back("certify", r.times.certify);
        counts(r);
        m.leaves_per_level = std::move(r.leaves_per_level);
        m.size_control = size_control(o, max_cell, buffer);
        m.sampled_points = r.sampled_points;
        out.mesh = std::move(r.mesh);
        out.certified = std::move(certified);
    } else {
        auto [r, certified] = fastest_of(o.repeat, [&] {
            return certified_run(mesh_uniform(f, lattice, rule_of(o), keys, o.lattice), lattice, rule_of(o), certify);
        });
        out.phases = {{"sample", r.times.sample}, {"signs", r.times.signs}, {"cut_points", r.times.cut_points},
                      {"warp", r.times.warp},     {"triangulate", r.times.triangulate}};
        if (o.certify) out.phases.emplace_back("certify", r.times.certify);
        counts(r);
        out.mesh = std::move(r.mesh);
        out.certified = std::move(certified);
    }
    return out;
}

// Guarantee::flat stopped at min_spacing with squares still not flat: the
// warning naming them (the first 10, with their keys).
std::string flat_warning(const CertifiedSummary& cert, double spacing, double min_spacing) {
    std::ostringstream w;
    w << "--guarantee flat: " << cert.nonflat_squares << " warped square(s) are still not flat at spacing " << spacing
      << " (--min-spacing " << min_spacing << "); the mesh is written with its true guarantee " << cert.min_deg
      << " deg; non-flat squares (i, j) key:";
    for (std::size_t e = 0; e < cert.nonflat_examples.size() && e < 10; ++e)
        w << (e ? "," : "") << " (" << cert.nonflat_examples[e][0] << ", " << cert.nonflat_examples[e][1] << ") "
          << cert.nonflat_keys[e];
    return w.str();
}

// The resolution check (resolution.hpp): a warning when some boundary loop is
// narrower than default_min_squares_across squares.  Images (`domain`): a
// spacing below one pixel adds no detail.
std::optional<std::string> resolution_warning(const Mesh& mesh, double spacing, bool domain) {
    const ResolutionCheck rc = check_resolution(mesh, spacing, domain ? 1.0 : 0.0);
    if (!rc.unresolved) return std::nullopt;
    std::ostringstream w;
    w << "spacing " << spacing << " is too coarse for this input: " << rc.unresolved << " of " << rc.loops
      << " boundary loop(s) (components or holes) are less than " << default_min_squares_across
      << " squares across (narrowest width 4*area/perimeter = " << approx(rc.narrowest) << "); spacing "
      << approx(rc.suggested_spacing) << " or less would resolve them";
    return w.str();
}

// The optimisation pass on one region (optimize.hpp) after certification:
// it keeps --max-size and the certified bounds.
OptimizeReport optimize_region(Mesh& mesh, const LevelSet& f, double spacing, const MeshOptions& o,
                               const CertifiedSummary& cert) {
    OptimizeOptions oo;
    oo.spacing = spacing;
    oo.max_edge = o.max_size;  // the pass keeps --max-size
    oo.refine_below_deg = 30;  // Steiner points where moves and flips leave a triangle below 30°
    if (cert.available) oo.certified_floor = cert.min_deg, oo.certified_max = cert.max_deg;
    check_optimize_memory(mesh, false, o);
    return optimize_mesh(mesh, f, oo);
}

// The report's last parts once res.mesh and res.certified are final: the
// quality measurement with the phase times, the process's peak memory, the
// certification (with MeshOptions::certify; null without certificates, then
// also a warning).  `junctions`: a multi-material mesh.
void finish_report(MeshResult& res, Phases phases, const MeshOptions& o, bool junctions) {
    if (o.certify && !res.certified.available)
        res.warnings.emplace_back("this build has no certificates (proofs/*.cert); no certified bounds");
    res.report.quality = compute_quality(res.mesh, std::move(phases));
    res.report.peak_memory_mb = peak_memory_mb();
    res.report.certified = {o.certify, junctions, res.certified};
    res.report.certified.summary.nonflat_boxes = {};  // for pictures: MeshResult::certified keeps them
}

}  // namespace

MeshResult mesh(const LevelSet& f0, const MeshOptions& o) {
    const MemoryCall call;  // max_memory bounds what this call needs (memory.hpp)
    validate(o);
    if (!o.max_size_of.empty())
        throw OptionError("max_size_of", "{max_size_of} applies to multi-material meshes; use {max_size}");
    // The rhombic lattice (rhombic.hpp): f0∘P meshed and certified in lattice coordinates
    // (proofs/rhombic_<rule>.cert), then mapped by P; --optimize and the report see f0.
    const bool rhombic = o.lattice == LatticeMetric::rhombic;
    std::optional<RhombicLevelSet> on_rhombic;
    if (rhombic) on_rhombic.emplace(f0);
    const LevelSet& f = rhombic ? static_cast<const LevelSet&>(*on_rhombic) : f0;
    const CertifyOptions certify{o.certify, o.certify && o.cell_data, o.certify && o.verify};
    MeshResult res;
    Phases phases;
    // Guarantee::flat: halve the spacing while some warped square is not
    // flat, but not below min_spacing.
    double spacing = o.spacing;
    const double min_spacing = o.min_spacing ? *o.min_spacing : o.spacing / 16;
    for (;;) {
        res.lattice = make_lattice(f.bounds(), f.bounds_are_domain(), spacing, o);
        check_lattice_memory(res.lattice, f.bounds_are_domain(), 0, o);
        RegionMeshed m = mesh_region(f, res.lattice, o, certify);
        res.mesh = std::move(m.mesh);
        res.certified = std::move(m.certified);
        phases = std::move(m.phases);
        res.report.lattice = lattice_figures(o, f.describe(), spacing, res.lattice);
        res.report.mesher = std::move(m.figures);
        const CertifiedSummary& cert = res.certified;
        if (o.guarantee != Guarantee::flat || !cert.available || cert.nonflat_squares == 0) break;
        if (spacing / 2 < min_spacing) {
            res.warnings.push_back(flat_warning(cert, spacing, min_spacing));
            break;
        }
        spacing /= 2;
        ++res.refinements;
    }
    res.spacing = spacing;
    if (rhombic) map_rhombic(res.mesh);
    if (res.mesh.triangles.empty())
        throw OptionError("spacing", "the region is empty at this spacing: no triangle has all three corners inside "
                                     "(check {iso}/{inside}/{label}, or use a smaller {spacing}); nothing written");
    if (auto w = resolution_warning(res.mesh, res.lattice.s, f0.bounds_are_domain())) res.warnings.push_back(std::move(*w));
    if (o.optimize) {
        res.report.optimize = optimize_region(res.mesh, f0, res.lattice.s, o, res.certified);
        phases.emplace_back("optimize", res.report.optimize->seconds);
    }
    if (res.certified.available && !f0.bounds_are_domain()) measure_fidelity(res.mesh, f0, res.lattice.s, res.certified);
    if (o.guarantee == Guarantee::flat) res.report.refinements = res.refinements;
    finish_report(res, std::move(phases), o, false);
    return res;
}

namespace {

// The size caps of some materials (MeshOptions::max_size_of) resolved against
// the field: per material number its largest quadtree cell and its cap, and
// the report's entries.  Throws InputError for a tag that is no material, or
// the background when it is not output.
struct MaterialCaps {
    std::vector<std::int64_t> max_cell_of;    // per material number (mesh_materials_graded; empty: no cap)
    std::vector<std::optional<double>> cap;   // per material number
    std::vector<MaterialCapFigures> figures;  // in the options' order
};

MaterialCaps material_caps(const MaterialField& field, const MeshOptions& o, double spacing, std::int64_t max_cell) {
    MaterialCaps caps;
    caps.cap.resize(static_cast<std::size_t>(field.count()));
    for (const auto& [tag, h] : o.max_size_of) {
        int m = 0;
        while (m < field.count() && field.tag(m) != tag) ++m;
        if (m == field.count()) {
            std::string known;  // the first 20
            for (int q = 1; q < field.count() && q <= 20; ++q) known += (q > 1 ? ", " : "") + std::to_string(field.tag(q));
            if (field.count() > 21) known += ", ...";
            throw OptionError("max_size_of", "{max_size_of} " + std::to_string(tag) + "=H: no material has tag " + std::to_string(tag) +
                             " (the materials: " + known + ")");
        }
        if (m == 0 && !o.keep_background)
            throw OptionError("max_size_of", "{max_size_of} 0=H: the background (tag 0) is not output; add {background=keep} to mesh it");
        if (caps.max_cell_of.empty()) caps.max_cell_of.assign(static_cast<std::size_t>(field.count()), 0);
        caps.max_cell_of[static_cast<std::size_t>(m)] = max_cell_for_size(h, spacing);
        caps.cap[static_cast<std::size_t>(m)] = h;
        caps.figures.push_back({tag, h, o.graded ? std::optional(largest_cell(max_cell, h, spacing)) : std::nullopt});
    }
    return caps;
}

// The multi-material mesher's phase times (the pipeline adds "optimize").
Phases material_phases(const MaterialResult& r, const MeshOptions& o) {
    Phases phases = {{"sample", r.times.sample}, {"cut_points", r.times.cut_points}, {"warp", r.times.warp}};
    if (o.graded) phases.emplace_back("quadtree", r.quadtree_seconds);
    phases.emplace_back("triangulate", r.times.triangulate);
    if (o.certify) phases.emplace_back("certify", r.times.certify);
    return phases;
}

// The multi-material mesher's counts for the report.
MesherFigures material_mesher_figures(const MaterialResult& r, const MeshOptions& o, std::int64_t max_cell, int buffer,
                                      std::vector<MaterialCapFigures> caps) {
    MesherFigures m;
    m.graded = o.graded;
    if (o.graded) {
        m.leaves_per_level = r.leaves_per_level;
        m.size_control = size_control(o, max_cell, buffer);
    }
    m.max_size_of = std::move(caps);
    m.cut_edges = r.cut_edges, m.warped_points = r.warped_points;
    m.warped_squares = r.warped_squares, m.separating_overrides = r.forced_diagonals;
    return m;
}

// The materials' figures of the (final) multi-material mesh; `certified`:
// certification ran (with certificates).
MaterialsFigures materials_figures(const MaterialResult& r, bool certified) {
    return {r.materials,        static_cast<std::int64_t>(r.mesh.interfaces.size()),
            r.third_material_edges, r.centroid_triangles,
            r.mixed_triangles,  r.junction_squares,
            r.junction_examples, certified};
}

// The optimisation pass on a multi-material mesh (optimize.hpp) after
// certification, with the material figures updated.  --max-size and every
// --max-size-of cap hold after it: the smallest of them bounds the edges the
// pass makes.
OptimizeReport optimize_materials(MaterialResult& r, const CertifiedSummary& cert, const MaterialField& field, double spacing,
                                  const MeshOptions& o) {
    OptimizeOptions oo;
    oo.spacing = spacing;
    oo.max_edge = o.max_size;
    for (const auto& [tag, h] : o.max_size_of) oo.max_edge = oo.max_edge > 0 ? std::min(oo.max_edge, h) : h;
    // Refinement below 35° (one region: 30°): issue 28's target at 2 px;
    // junction and interface triangles reach it only with Steiner points.
    oo.refine_below_deg = 35;
    if (cert.available) oo.certified_floor = cert.min_deg, oo.certified_max = cert.max_deg;
    check_optimize_memory(r.mesh, true, o);
    const RegionMeasures before = measure_regions(r.mesh);
    OptimizeReport report = optimize_mesh(r.mesh, field, oo);
    update_material_stats(r, before, measure_regions(r.mesh));
    if (!o.max_size_of.empty()) measure_longest_edges(r);
    return report;
}

}  // namespace

MeshResult mesh(const MaterialField& field, const MeshOptions& o) {
    const MemoryCall call;
    validate(o);
    if (o.guarantee == Guarantee::flat) throw OptionError("guarantee", "{guarantee=flat} is not available with several materials");
    if (o.lattice != LatticeMetric::square)
        throw OptionError("lattice", "{lattice=rhombic} is not available with several materials (one region only)");
    const CertifyOptions certify{o.certify, o.certify && o.cell_data, o.certify && o.verify};
    MeshResult res;
    res.spacing = o.spacing;
    res.lattice = make_lattice(field.bounds(), field.bounds_are_domain(), o.spacing, o);
    check_lattice_memory(res.lattice, field.bounds_are_domain(), field.count(), o);
    res.report.lattice = lattice_figures(o, field.describe(), o.spacing, res.lattice);
    const MaterialOptions mo{o.keep_background, rule_of(o), KeyOptions{certify.enabled, certify.verify}};
    // Size control (graded: the cells; uniform: bounded by the spacing).
    const std::int64_t max_cell = largest_cell(o.max_cell, o.max_size, res.lattice.s);
    const int buffer = grading_buffer(o.grading);
    MaterialCaps caps = material_caps(field, o, res.lattice.s, max_cell);
    auto [r, certified] = fastest_of(o.repeat, [&] {
        return certified_run(o.graded ? mesh_materials_graded(field, res.lattice, mo, max_cell, buffer, caps.max_cell_of)
                                      : mesh_materials(field, res.lattice, mo),
                             res.lattice, rule_of(o), certify);
    });
    if (!o.max_size_of.empty()) {
        for (std::size_t m = 0; m < r.materials.size(); ++m) r.materials[m].max_size = caps.cap[m];
        measure_longest_edges(r);
    }
    Phases phases = material_phases(r, o);
    res.report.mesher = material_mesher_figures(r, o, max_cell, buffer, std::move(caps.figures));
    if (o.optimize) {
        res.report.optimize = optimize_materials(r, certified, field, res.lattice.s, o);
        phases.emplace_back("optimize", res.report.optimize->seconds);
    }
    res.report.materials = materials_figures(r, certified.available);
    for (std::string& w : material_warnings(*res.report.materials)) res.warnings.push_back(std::move(w));
    res.mesh = std::move(r.mesh);
    res.certified = std::move(certified);
    if (res.mesh.triangles.empty())
        throw OptionError("spacing", "the region is empty at this spacing: no triangle has all three corners inside "
                                     "(check {materials}, or use a smaller {spacing}); nothing written");
    finish_report(res, std::move(phases), o, true);
    return res;
}

CertifiedSummary certify(UniformResult& r, const Lattice& lattice, DiagonalRule rule, const CertifyOptions& options) {
    return certify_stage(r, lattice, rule, options);
}

CertifiedSummary certify(GradedResult& r, const Lattice& lattice, DiagonalRule rule, const CertifyOptions& options) {
    return certify_stage(r, lattice, rule, options);
}

CertifiedSummary certify(MaterialResult& r, const Lattice& lattice, DiagonalRule rule, const CertifyOptions& options) {
    CertifiedSummary c = certify_stage(r, lattice, rule, options);
    if (!c.available) r.junction_squares = 0, r.junction_examples.clear();
    for (JunctionSquare& js : r.junction_examples) {
        const CertifiedBound* b = certified_junction_bound(js.key, rule);  // certify_keys found it
        if (!b)
            throw std::logic_error("junction square (" + std::to_string(js.i) + ", " + std::to_string(js.j) + ") key " + js.pattern +
                                   " not in proofs/" + (rule == DiagonalRule::fan ? "materials_fan" : "materials") + ".cert");
        js.min_deg = b->min_deg, js.max_deg = b->max_deg;
    }
    return c;
}

WriteOptions write_options(const MeshResult& r, bool color_min_angle, bool color_certified) {
    WriteOptions wo;
    wo.svg.color_by_min_angle = color_min_angle;
    const CertifiedSummary& cert = r.certified;
    if (cert.available && !cert.nonflat_boxes.empty()) {
        wo.svg.marked_boxes = cert.nonflat_boxes;
        wo.svg.marked_label = std::to_string(cert.nonflat_squares) +
                              " warped square(s) with a non-flat stencil (outlined in magenta); the mesh is certified down to " +
                              approx(cert.min_deg) + " deg";
    }
    if (color_certified && cert.available) {
        wo.svg.color_by_cell_data = "certified_min_angle";
        wo.png.color_by_cell_data = "certified_min_angle";
    }
    return wo;
}

std::unique_ptr<LevelSet> image_levelset(const Image& image, const ImageLevelSetOptions& options) {
    if (image.width < 2 || image.height < 2)
        throw InputError(image.source + ": the image is " + std::to_string(image.width) + " x " +
                         std::to_string(image.height) + " pixels; at least 2 x 2 are needed for one lattice square");
    return make_image_levelset(image, options);
}

}  // namespace warpmesh
