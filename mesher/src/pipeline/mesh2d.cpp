// pipeline.cpp — mesh(): lattice, mesher, certification, refinement, report
// (pipeline.hpp).
#include "warpmesh/pipeline/mesh2d.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/mesh2d/graded.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/report/report.hpp"
#include "warpmesh/core/memory.hpp"
#include "warpmesh/post/resolution.hpp"
#include "warpmesh/mesh2d/uniform.hpp"
#include "mesh2d/uniform/rhombic.hpp"

namespace warpmesh {

namespace {

// Run `mesh` n times and return the last result with the fastest run's phase
// times.  The earlier runs are kept only for their times (each freed before
// the next; the heap keeps their pages, so the process's peak resident memory
// can exceed one run's).
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
void check_lattice_memory(const Lattice& lattice, bool domain, int materials, const MeshOptions& o) {
    if (o.graded && !domain) return;
    const std::uint64_t squares = static_cast<std::uint64_t>(lattice.nx) * static_cast<std::uint64_t>(lattice.ny);
    const std::uint64_t per = mesh_bytes_per_square(materials > 0, o.graded);
    const std::uint64_t per_material = mesh_bytes_per_material();
    check_memory(squares * per + static_cast<std::uint64_t>(materials) * per_material, o.max_memory, "meshing",
                 std::to_string(lattice.nx) + " x " + std::to_string(lattice.ny) + " lattice squares at " +
                     std::to_string(per) + " bytes each" +
                     (materials > 0 ? ", " + std::to_string(materials) + " materials at " + std::to_string(per_material) + " bytes each"
                                    : std::string()),
                 "use a larger {spacing}");
}

using Extra = ReportFields;

// The report's first fields: input, level set (or material field), rule,
// spacing, repeat, lattice.
void report_head(Extra& extra, const MeshOptions& o, const std::string& describe, double spacing, const Lattice& lattice) {
    extra.emplace_back("input", json_string(o.input));
    extra.emplace_back("levelset", json_string(describe));
    extra.emplace_back("rule", json_string(rule_name(o.rule)));
    extra.emplace_back("spacing", json_number(spacing));
    if (o.repeat > 1) extra.emplace_back("repeat", std::to_string(o.repeat));  // phase times: the fastest run
    extra.emplace_back("lattice", "[" + std::to_string(lattice.nx) + ", " + std::to_string(lattice.ny) + "]");
}

// The "certified" field (null without certificates) and res.certified_text.
void report_certified(Extra& extra, MeshResult& res, DiagonalRule rule, bool junctions,
                      LatticeMetric metric = LatticeMetric::square) {
    if (!res.certified.available) {
        extra.emplace_back("certified", "null");
        return;
    }
    extra.emplace_back("certified", certified_json(res.certified, rule, junctions, metric));
    res.certified_text = certified_text(res.certified, rule, metric);
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

MeshResult mesh(const LevelSet& f0, const MeshOptions& o) {
    validate(o);
    if (!o.max_size_of.empty())
        throw OptionError("max_size_of", "{max_size_of} applies to multi-material meshes; use {max_size}");
    // The rhombic lattice (rhombic.hpp): f0∘P meshed and certified in lattice coordinates
    // (proofs/rhombic_<rule>.cert), then mapped by P; --optimize and the report see f0.
    const bool rhombic = o.lattice == LatticeMetric::rhombic;
    std::optional<RhombicLevelSet> on_rhombic;
    if (rhombic) on_rhombic.emplace(f0);
    const LevelSet& f = rhombic ? static_cast<const LevelSet&>(*on_rhombic) : f0;
    const CertifyOptions certify{o.certify, o.certify && o.cell_data, o.certify && o.verify, o.lattice};
    MeshResult res;
    Mesh& mesh = res.mesh;
    CertifiedSummary& cert = res.certified;
    std::vector<std::pair<std::string, double>> phases;
    ReportFields extra;
    double spacing = o.spacing;
    const double min_spacing = o.min_spacing ? *o.min_spacing : o.spacing / 16;
    for (;;) {
        res.lattice = make_lattice(f.bounds(), f.bounds_are_domain(), spacing, o);
        const Lattice& lattice = res.lattice;
        check_lattice_memory(lattice, f.bounds_are_domain(), 0, o);
        extra.clear();
        report_head(extra, o, f.describe(), spacing, lattice);
        if (o.graded) {
            const std::int64_t max_cell = largest_cell(o.max_cell, o.max_size, lattice.s);
            const int buffer = grading_buffer(o.grading);
            GradedResult r =
                fastest_of(o.repeat, [&] { return mesh_graded(f, lattice, o.rule, max_cell, certify, buffer); });
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
            if (o.max_size != 0 || o.grading != max_grading) {  // (only then: default reports unchanged)
                extra.emplace_back("max_size", o.max_size != 0 ? json_number(o.max_size) : "null");
                extra.emplace_back("max_cell", json_number(max_cell));
                extra.emplace_back("grading", json_number(o.grading));
                extra.emplace_back("grading_buffer", json_number(std::int64_t{buffer}));
            }
            extra.emplace_back("cut_edges", std::to_string(r.cut_edges));
            extra.emplace_back("warped_points", std::to_string(r.warped_points));
            extra.emplace_back("warped_squares", std::to_string(r.stats.warped_squares));
            extra.emplace_back("separating_overrides", std::to_string(r.stats.forced_diagonals));
            extra.emplace_back("sampled_points", std::to_string(r.sampled_points));
        } else {
            UniformResult r = fastest_of(o.repeat, [&] { return mesh_uniform(f, lattice, o.rule, certify, o.lattice); });
            mesh = std::move(r.mesh);
            cert = std::move(r.certified);
            phases = {{"sample", r.times.sample},
                      {"signs", r.times.signs},
                      {"cut_points", r.times.cut_points},
                      {"warp", r.times.warp},
                      {"triangulate", r.times.triangulate}};
            if (o.certify) phases.emplace_back("certify", r.times.certify);
            extra.emplace_back("graded", "false");
            if (rhombic) extra.emplace_back("lattice_metric", json_string("rhombic"));
            extra.emplace_back("cut_edges", std::to_string(r.cut_edges));
            extra.emplace_back("warped_points", std::to_string(r.warped_points));
            extra.emplace_back("warped_squares", std::to_string(r.stats.warped_squares));
            extra.emplace_back("separating_overrides", std::to_string(r.stats.forced_diagonals));
        }
        if (o.guarantee != Guarantee::flat || !cert.available || cert.nonflat_squares == 0) break;
        if (spacing / 2 < min_spacing) {
            std::ostringstream w;
            w << "--guarantee flat: " << cert.nonflat_squares << " warped square(s) are still not flat at spacing "
              << spacing << " (--min-spacing " << min_spacing << "); the mesh is written with its true guarantee "
              << cert.min_deg << " deg; non-flat squares (i, j) key:";
            for (std::size_t e = 0; e < cert.nonflat_examples.size() && e < 10; ++e)
                w << (e ? "," : "") << " (" << cert.nonflat_examples[e][0] << ", " << cert.nonflat_examples[e][1]
                  << ") " << cert.nonflat_keys[e];
            res.warnings.push_back(w.str());
            break;
        }
        spacing /= 2;
        ++res.refinements;
    }
    res.spacing = spacing;
    if (rhombic) map_rhombic(mesh);
    if (mesh.triangles.empty())
        throw OptionError("spacing", "the region is empty at this spacing: no triangle has all three corners inside "
                                     "(check {iso}/{inside}/{label}, or use a smaller {spacing}); nothing written");
    // Images: a spacing below one pixel adds no detail (resolution.hpp).
    if (const ResolutionCheck rc = check_resolution(mesh, res.lattice.s, f0.bounds_are_domain() ? 1.0 : 0.0);
        rc.unresolved) {
        std::ostringstream w;
        w << "spacing " << res.lattice.s << " is too coarse for this input: " << rc.unresolved << " of " << rc.loops
          << " boundary loop(s) (components or holes) are less than " << default_min_squares_across
          << " squares across (narrowest width 4*area/perimeter = " << approx(rc.narrowest) << "); spacing "
          << approx(rc.suggested_spacing) << " or less would resolve them";
        res.warnings.push_back(w.str());
    }
    if (o.optimize) {
        OptimizeOptions oo;
        oo.spacing = res.lattice.s;
        oo.max_edge = o.max_size;  // the pass keeps --max-size
        oo.refine_below_deg = 30;  // Steiner points where moves and flips leave a triangle below 30°
        if (cert.available) oo.certified_floor = cert.min_deg, oo.certified_max = cert.max_deg;
        res.optimized = optimize_mesh(mesh, f0, oo);
        phases.emplace_back("optimize", res.optimized->seconds);
        extra.emplace_back("optimize", optimize_json(*res.optimized));
    }
    if (cert.available && !f0.bounds_are_domain()) measure_fidelity(mesh, f0, res.lattice.s, cert);
    if (o.certify && !cert.available)
        res.warnings.emplace_back("this build has no certificates (proofs/*.cert); no certified bounds");

    res.report = compute_quality(mesh, phases);
    extra.emplace_back("peak_memory_mb", json_number(peak_memory_mb()));
    if (o.guarantee == Guarantee::flat) extra.emplace_back("refinements", std::to_string(res.refinements));
    if (o.certify) report_certified(extra, res, o.rule, false, o.lattice);
    res.report.extra = std::move(extra);
    return res;
}

namespace {

// The optimisation pass on a multi-material mesh (optimize.hpp) after
// certification, with the material figures updated.  --max-size and every
// --max-size-of cap hold after it: the smallest of them bounds the edges the
// pass makes.
OptimizeReport optimize_materials(MaterialResult& r, const MaterialField& field, double spacing, const MeshOptions& o) {
    OptimizeOptions oo;
    oo.spacing = spacing;
    oo.max_edge = o.max_size;
    for (const auto& [tag, h] : o.max_size_of) oo.max_edge = oo.max_edge > 0 ? std::min(oo.max_edge, h) : h;
    // Refinement below 35° (one region: 30°): issue 28's target at 2 px;
    // junction and interface triangles reach it only with Steiner points.
    oo.refine_below_deg = 35;
    if (r.certified.available) oo.certified_floor = r.certified.min_deg, oo.certified_max = r.certified.max_deg;
    const RegionMeasures before = measure_regions(r.mesh);
    OptimizeReport report = optimize_mesh(r.mesh, field, oo);
    update_material_stats(r, before, measure_regions(r.mesh));
    if (!o.max_size_of.empty()) measure_longest_edges(r);
    return report;
}

}  // namespace

MeshResult mesh(const MaterialField& field, const MeshOptions& o) {
    validate(o);
    if (o.guarantee == Guarantee::flat) throw OptionError("guarantee", "{guarantee=flat} is not available with several materials");
    if (o.lattice != LatticeMetric::square)
        throw OptionError("lattice", "{lattice=rhombic} is not available with several materials (one region only)");
    const CertifyOptions certify{o.certify, o.certify && o.cell_data, o.certify && o.verify};
    MeshResult res;
    res.spacing = o.spacing;
    res.lattice = make_lattice(field.bounds(), field.bounds_are_domain(), o.spacing, o);
    check_lattice_memory(res.lattice, field.bounds_are_domain(), field.count(), o);
    ReportFields extra;
    report_head(extra, o, field.describe(), o.spacing, res.lattice);
    const MaterialOptions mo{o.keep_background, o.rule, certify};
    // Size control (graded: the cells; uniform: bounded by the spacing).
    const std::int64_t max_cell = largest_cell(o.max_cell, o.max_size, res.lattice.s);
    const int buffer = grading_buffer(o.grading);
    std::vector<std::int64_t> max_cell_of;  // per material number (mesh_materials_graded)
    std::vector<std::optional<double>> cap(static_cast<std::size_t>(field.count()));
    std::string caps = "[";
    for (const auto& [tag, h] : o.max_size_of) {
        int m = 0;
        while (m < field.count() && field.tag(m) != tag) ++m;
        if (m == field.count()) {
            std::string known;  // the first 20
            for (int q = 1; q < field.count() && q <= 20; ++q) known += (q > 1 ? ", " : "") + std::to_string(field.tag(q));
            if (field.count() > 21) known += ", ...";
            throw OptionError("max_size_of", "{max_size_of} " + std::to_string(tag) + "=H: no material has tag " +
                                                 std::to_string(tag) + " (the materials: " + known + ")");
        }
        if (m == 0 && !o.keep_background)
            throw OptionError("max_size_of", "{max_size_of} 0=H: the background (tag 0) is not output; add {background=keep} to mesh it");
        if (max_cell_of.empty()) max_cell_of.assign(static_cast<std::size_t>(field.count()), 0);
        const std::int64_t K = max_cell_for_size(h, res.lattice.s);
        max_cell_of[static_cast<std::size_t>(m)] = K;
        cap[static_cast<std::size_t>(m)] = h;
        caps += std::string(caps.size() > 1 ? ", " : "") + "{\"tag\": " + std::to_string(tag) + ", \"max_size\": " + json_number(h) +
                ", \"max_cell\": " + (o.graded ? json_number(largest_cell(max_cell, h, res.lattice.s)) : std::string("null")) + "}";
    }
    MaterialResult r = fastest_of(o.repeat, [&] {
        return o.graded ? mesh_materials_graded(field, res.lattice, mo, max_cell, buffer, max_cell_of)
                        : mesh_materials(field, res.lattice, mo);
    });
    if (!o.max_size_of.empty()) {
        for (std::size_t m = 0; m < r.materials.size(); ++m) r.materials[m].max_size = cap[m];
        measure_longest_edges(r);
    }
    std::vector<std::pair<std::string, double>> phases = {{"sample", r.times.sample}, {"cut_points", r.times.cut_points}, {"warp", r.times.warp}};
    if (o.graded) phases.emplace_back("quadtree", r.quadtree_seconds);
    phases.emplace_back("triangulate", r.times.triangulate);
    if (o.certify) phases.emplace_back("certify", r.times.certify);
    extra.emplace_back("graded", o.graded ? "true" : "false");
    if (o.graded) {
        std::string levels = "[";
        for (std::size_t k = 0; k < r.leaves_per_level.size(); ++k) levels += (k ? ", " : "") + std::to_string(r.leaves_per_level[k]);
        extra.emplace_back("leaves_per_level", levels + "]");
        if (o.max_size != 0 || o.grading != max_grading) {  // as for one region (only then: default reports unchanged)
            extra.emplace_back("max_size", o.max_size != 0 ? json_number(o.max_size) : "null");
            extra.emplace_back("max_cell", json_number(max_cell));
            extra.emplace_back("grading", json_number(o.grading));
            extra.emplace_back("grading_buffer", json_number(std::int64_t{buffer}));
        }
    }
    if (!o.max_size_of.empty()) extra.emplace_back("max_size_of", caps + "]");
    extra.emplace_back("cut_edges", std::to_string(r.cut_edges));
    extra.emplace_back("warped_points", std::to_string(r.warped_points));
    extra.emplace_back("warped_squares", std::to_string(r.warped_squares));
    extra.emplace_back("separating_overrides", std::to_string(r.forced_diagonals));
    if (o.optimize) {
        res.optimized = optimize_materials(r, field, res.lattice.s, o);
        phases.emplace_back("optimize", res.optimized->seconds);
        extra.emplace_back("optimize", optimize_json(*res.optimized));
    }
    for (auto& e : material_report_json(r)) extra.push_back(std::move(e));
    res.materials_text = material_report_text(r, &res.warnings);
    res.mesh = std::move(r.mesh);
    res.certified = std::move(r.certified);
    if (res.mesh.triangles.empty())
        throw OptionError("spacing", "the region is empty at this spacing: no triangle has all three corners inside "
                                     "(check {materials}, or use a smaller {spacing}); nothing written");
    const CertifiedSummary& cert = res.certified;
    if (o.certify && !cert.available)
        res.warnings.emplace_back("this build has no certificates (proofs/*.cert); no certified bounds");
    res.report = compute_quality(res.mesh, phases);
    extra.emplace_back("peak_memory_mb", json_number(peak_memory_mb()));
    if (o.certify) report_certified(extra, res, o.rule, true);
    res.report.extra = std::move(extra);
    return res;
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
