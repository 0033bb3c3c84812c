// pipeline.cpp — mesh(): lattice, mesher, certification, refinement, report
// (pipeline.hpp).
#include "warpmesh/pipeline.hpp"

#include <sys/resource.h>

#include <cstdio>
#include <sstream>

#include "warpmesh/errors.hpp"
#include "warpmesh/graded.hpp"
#include "warpmesh/uniform.hpp"

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

const char* rule_name(DiagonalRule rule) { return rule == DiagonalRule::maxmin ? "maxmin" : "separating"; }

// The lattice of this spacing for f, within options.max_squares.
Lattice make_lattice(const LevelSet& f, double spacing, const MeshOptions& o) {
    const Box b = f.bounds();
    if (!f.bounds_are_domain()) {
        const double w = (b.xmax - b.xmin) / spacing + 2, h = (b.ymax - b.ymin) / spacing + 2;
        if (!(w * h <= static_cast<double>(o.max_squares)))
            throw InputError("the lattice would have about " + approx(w) + " x " + approx(h) +
                             " squares, more than --max-squares " + std::to_string(o.max_squares) +
                             " (use a larger --spacing)");
        return lattice_around(b, spacing);
    }
    const double w = (b.xmax - b.xmin) / spacing, h = (b.ymax - b.ymin) / spacing;
    if (!(w * h <= static_cast<double>(o.max_squares)))
        throw InputError("spacing " + approx(spacing) + " gives about " + approx(w * h) +
                         " lattice squares, more than --max-squares " + std::to_string(o.max_squares));
    return lattice_over(b, spacing);
}

// The "certified" object of the JSON report and the certification's lines of
// the text report.
std::pair<std::string, std::string> certified_report(const CertifiedSummary& cert, DiagonalRule rule) {
    const CertifiedTheorem th = certified_theorem(rule);
    std::string j = "{\"min_angle_deg\": " + json_number(cert.min_deg) +
                    ", \"max_angle_deg\": " + json_number(cert.max_deg) +
                    ", \"warped_min_angle_deg\": " + json_number(cert.keyed_min_deg) +
                    ", \"warped_squares\": " + std::to_string(cert.keyed_squares) +
                    ", \"flat_squares\": " + std::to_string(cert.flat_squares) +
                    ", \"nonflat_squares\": " + std::to_string(cert.nonflat_squares) + ", \"nonflat\": [";
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
    j += "}";
    std::ostringstream t;
    t.precision(10);
    t << "certified angles     [" << cert.min_deg << ", " << cert.max_deg << "] deg (proofs/" << rule_name(rule)
      << ".cert" << (cert.verified ? ", every triangle verified" : ", not verified") << ")\n";
    t << "warped squares       " << cert.keyed_squares << " (" << cert.flat_squares << " flat, "
      << cert.nonflat_squares << " not flat)\n";
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
    return {j, t.str()};
}

}  // namespace

void validate(const MeshOptions& o) {
    if (!(o.spacing > 0) || o.spacing > 1e9) throw InputError("--spacing must be positive and at most 1e9");
    if (o.max_cell < 0 || (o.max_cell & (o.max_cell - 1)) != 0) throw InputError("--max-cell must be a power of two");
    if (o.min_spacing && !(*o.min_spacing > 0)) throw InputError("--min-spacing must be positive");
    if (o.guarantee == Guarantee::flat && !o.certify)
        throw InputError("--guarantee flat needs the certification (drop --no-certify)");
    if (o.max_squares < 1) throw InputError("--max-squares must be positive");
    if (o.repeat < 1 || o.repeat > 1000) throw InputError("--repeat expects 1 to 1000");
}

MeshResult mesh(const LevelSet& f, const MeshOptions& o) {
    validate(o);
    const CertifyOptions certify{o.certify, o.certify && o.cell_data, o.certify && o.verify};
    MeshResult res;
    Mesh& mesh = res.mesh;
    CertifiedSummary& cert = res.certified;
    std::vector<std::pair<std::string, double>> phases;
    std::vector<std::pair<std::string, std::string>> extra;
    double spacing = o.spacing;
    const double min_spacing = o.min_spacing ? *o.min_spacing : o.spacing / 16;
    for (;;) {
        res.lattice = make_lattice(f, spacing, o);
        const Lattice& lattice = res.lattice;
        extra.clear();
        extra.emplace_back("input", json_string(o.input));
        extra.emplace_back("levelset", json_string(f.describe()));
        extra.emplace_back("rule", json_string(rule_name(o.rule)));
        extra.emplace_back("spacing", json_number(spacing));
        if (o.repeat > 1) extra.emplace_back("repeat", std::to_string(o.repeat));  // phase times: the fastest run
        extra.emplace_back("lattice", "[" + std::to_string(lattice.nx) + ", " + std::to_string(lattice.ny) + "]");
        if (o.graded) {
            GradedResult r = fastest_of(o.repeat, [&] { return mesh_graded(f, lattice, o.rule, o.max_cell, certify); });
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
            UniformResult r = fastest_of(o.repeat, [&] { return mesh_uniform(f, lattice, o.rule, certify); });
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
    if (mesh.triangles.empty())
        throw InputError("the region is empty at this spacing: no triangle has all three corners inside "
                         "(check --iso/--inside/--label, or use a smaller --spacing); nothing written");
    if (cert.available && !f.bounds_are_domain()) measure_fidelity(mesh, f, res.lattice.s, cert);
    if (o.certify && !cert.available)
        res.warnings.emplace_back("this build has no certificates (proofs/*.cert); no certified bounds");

    res.report = compute_quality(mesh, phases);
    extra.emplace_back("peak_memory_mb", json_number(peak_memory_mb()));
    if (o.guarantee == Guarantee::flat) extra.emplace_back("refinements", std::to_string(res.refinements));
    if (o.certify) {
        if (!cert.available) {
            extra.emplace_back("certified", "null");
        } else {
            auto [json, text] = certified_report(cert, o.rule);
            extra.emplace_back("certified", std::move(json));
            res.certified_text = std::move(text);
        }
    }
    res.report.extra = std::move(extra);
    return res;
}

std::string to_json(const MeshResult& r) { return quality_json(r.report); }

std::string to_text(const MeshResult& r) { return quality_text(r.report) + r.certified_text; }

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
