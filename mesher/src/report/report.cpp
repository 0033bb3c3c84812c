// report.cpp — the reports' text and JSON (report.hpp): JSON values, the
// quality report, the certification's part, the optimisation pass's part.
// The multi-material part is material_report.cpp, the whole 2D report
// report2d.cpp.
#include "warpmesh/report/report.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "io/atomic_file.hpp"
#include "report_parts.hpp"

namespace warpmesh {

namespace {

std::string tag_name(std::int32_t tag) {
    if (tag == boundary_level_set) return "level set";
    if (tag == boundary_domain) return "lattice border";
    return "tag " + std::to_string(tag);
}

}  // namespace

std::string report_detail::fmt(double x, int digits) {
    if (!std::isfinite(x)) return "n/a";
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, digits);
    return std::string(buf, r.ptr);
}

std::string json_string(std::string_view s) {
    std::string r = "\"";
    for (const char ch : s) {
        const auto c = static_cast<unsigned char>(ch);
        switch (c) {
            case '"': r += "\\\""; break;
            case '\\': r += "\\\\"; break;
            case '\n': r += "\\n"; break;
            case '\r': r += "\\r"; break;
            case '\t': r += "\\t"; break;
            default:
                if (c < 0x20) {
                    char buf[8];
                    std::snprintf(buf, sizeof buf, "\\u%04x", c);
                    r += buf;
                } else {
                    r += ch;
                }
        }
    }
    return r + "\"";
}

std::string json_number(double x) {
    if (!std::isfinite(x)) return "null";
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, x);
    return std::string(buf, r.ptr);
}

std::string json_number(std::int64_t i) { return std::to_string(i); }

std::string report_detail::json_strings(const std::vector<std::string>& items) {
    std::string r = "[";
    for (std::size_t k = 0; k < items.size(); ++k) r += (k ? ", " : "") + json_string(items[k]);
    return r + "]";
}

const char* rule_name(DiagonalRule rule) {
    return name_of(diagonal_rule_names, rule).data();
}

std::string quality_text(const QualityReport& q) {
    using report_detail::fmt;
    std::ostringstream o;
    o << "mesh: " << q.vertices << " vertices, " << q.triangles << " triangles, " << q.boundary_edges
      << " boundary edges\n";
    if (q.triangles_by_region.size() > 1) {
        o << "  regions:";
        for (const auto& [r, count] : q.triangles_by_region) o << ' ' << r << ": " << count;
        o << '\n';
    }
    o << "  area " << fmt(q.area, 10) << ", boundary length " << fmt(q.boundary_length, 10);
    for (const auto& [tag, count] : q.boundary_edges_by_tag)
        o << "; " << tag_name(tag) << ": " << count << " edges, length " << fmt(q.boundary_length_by_tag.at(tag), 8);
    o << '\n';
    if (q.nonpositive_triangles) o << "  WARNING: " << q.nonpositive_triangles << " triangles with area <= 0\n";
    o << "angles: min " << fmt(q.min_angle_deg) << " deg, max " << fmt(q.max_angle_deg) << " deg; mean minimum angle "
      << fmt(q.mean_min_angle_deg, 4) << " deg\n";
    o << "  largest angle per triangle: min " << fmt(q.max_angle_min_deg, 4) << ", mean " << fmt(q.max_angle_mean_deg, 4)
      << ", > 90 deg: " << q.max_angle_over_90 << ", > 120 deg: " << q.max_angle_over_120 << '\n';
    o << "radius ratio 2 r_in / R_circ (1 = equilateral): min " << fmt(q.radius_ratio_min, 4) << ", mean "
      << fmt(q.radius_ratio_mean, 4) << '\n';

    // Histogram rows from the first to the last non-empty bin, bars up to 40 #.
    const auto& h = q.min_angle_histogram;
    const auto first = std::find_if(h.begin(), h.end(), [](std::int64_t c) { return c > 0; });
    if (first != h.end()) {
        const auto last = std::find_if(h.rbegin(), h.rend(), [](std::int64_t c) { return c > 0; }).base();
        const std::int64_t peak = *std::max_element(h.begin(), h.end());
        o << "minimum-angle histogram (" << QualityReport::histogram_bin_deg << " deg bins):\n";
        for (auto it = first; it != last; ++it) {
            const int i = static_cast<int>(it - h.begin());
            const int lo = i * QualityReport::histogram_bin_deg, hi = lo + QualityReport::histogram_bin_deg;
            char row[64];
            std::snprintf(row, sizeof row, "  [%2d, %2d%c %12lld  ", lo, hi, i + 1 == QualityReport::histogram_bins ? ']' : ')',
                          static_cast<long long>(*it));
            const auto bar = static_cast<std::size_t>(std::llround(40.0 * static_cast<double>(*it) / static_cast<double>(peak)));
            o << row << std::string(bar == 0 && *it > 0 ? 1 : bar, '#') << '\n';
        }
    }
    if (!q.phase_seconds.empty()) {
        double total = 0;
        std::size_t width = 5;
        for (const auto& [name, s] : q.phase_seconds) total += s, width = std::max(width, name.size());
        o << "time:\n";
        for (const auto& [name, s] : q.phase_seconds)
            o << "  " << name << std::string(width - name.size(), ' ') << "  " << fmt(s, 4) << " s\n";
        o << "  total" << std::string(width - 5, ' ') << "  " << fmt(total, 4) << " s\n";
    }
    return o.str();
}

void report_detail::quality_fields(JsonObject& json, const QualityReport& q) {
    auto field = [&](std::string_view key, const std::string& value) { json.field(key, value); };
    auto num = [](double x) { return json_number(x); };
    auto integer = [](std::int64_t i) { return json_number(i); };
    field("vertices", integer(q.vertices));
    field("triangles", integer(q.triangles));
    field("boundary_edges", integer(q.boundary_edges));
    field("min_angle_deg", num(q.min_angle_deg));
    field("max_angle_deg", num(q.max_angle_deg));
    field("mean_min_angle_deg", num(q.mean_min_angle_deg));
    std::string hist = "{\"bin_width_deg\": " + std::to_string(QualityReport::histogram_bin_deg) + ", \"counts\": [";
    for (std::size_t i = 0; i < q.min_angle_histogram.size(); ++i)
        hist += (i ? ", " : "") + std::to_string(q.min_angle_histogram[i]);
    field("min_angle_histogram", hist + "]}");
    field("max_angle", "{\"min_deg\": " + num(q.max_angle_min_deg) + ", \"mean_deg\": " + num(q.max_angle_mean_deg) +
                           ", \"max_deg\": " + num(q.max_angle_deg) + ", \"over_90\": " + integer(q.max_angle_over_90) +
                           ", \"over_120\": " + integer(q.max_angle_over_120) + "}");
    field("radius_ratio", "{\"min\": " + num(q.radius_ratio_min) + ", \"mean\": " + num(q.radius_ratio_mean) + "}");
    field("area", num(q.area));
    field("nonpositive_triangles", integer(q.nonpositive_triangles));
    field("boundary_length", num(q.boundary_length));
    auto by_tag = [](const auto& map, auto value) {
        std::string s = "{";
        for (const auto& [tag, v] : map) s += (s.size() > 1 ? ", " : "") + json_string(std::to_string(tag)) + ": " + value(v);
        return s + "}";
    };
    field("boundary_edges_by_tag", by_tag(q.boundary_edges_by_tag, integer));
    field("boundary_length_by_tag", by_tag(q.boundary_length_by_tag, num));
    field("triangles_by_region", by_tag(q.triangles_by_region, integer));
    std::string phases = "{";
    double total = 0;
    for (const auto& [name, s] : q.phase_seconds) {
        phases += (phases.size() > 1 ? ", " : "") + json_string(name) + ": " + num(s);
        total += s;
    }
    field("phase_seconds", phases + "}");
    field("total_seconds", num(total));
}

std::string quality_json(const QualityReport& q) {
    report_detail::JsonObject json;
    report_detail::quality_fields(json, q);
    return json.close();
}

void write_quality_json(const std::string& path, const QualityReport& report) {
    const std::string text = quality_json(report);
    write_file_atomically(path, [&](std::ostream& os) { os << text; });
}

// Multi-material meshes (junctions) also count the junction squares (3 or 4
// materials), certified by their junction keys (proofs/materials.cert).
std::string certified_json(const CertifiedSummary& cert, DiagonalRule rule, bool junctions, LatticeMetric metric) {
    const CertifiedTheorem th = certified_theorem(rule, metric);
    std::string j = "{\"min_angle_deg\": " + json_number(cert.min_deg) +
                    ", \"max_angle_deg\": " + json_number(cert.max_deg) +
                    ", \"warped_min_angle_deg\": " + json_number(cert.keyed_min_deg) +
                    ", \"warped_squares\": " + std::to_string(cert.keyed_squares) +
                    ", \"flat_squares\": " + std::to_string(cert.flat_squares) +
                    ", \"nonflat_squares\": " + std::to_string(cert.nonflat_squares) +
                    (junctions ? ", \"junction_squares\": " + std::to_string(cert.junction_squares) : std::string()) +
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
    j += "}";
    return j;
}

// The rhombic lattice's certificates are proofs/rhombic_<rule>.cert.
std::string certified_text(const CertifiedSummary& cert, DiagonalRule rule, LatticeMetric metric) {
    std::ostringstream t;
    t.precision(10);
    t << "certified angles     [" << cert.min_deg << ", " << cert.max_deg << "] deg (proofs/"
      << (metric == LatticeMetric::rhombic ? "rhombic_" : "") << rule_name(rule)
      << ".cert" << (cert.junction_squares ? " and proofs/materials.cert" : "")
      << (cert.verified ? ", every triangle verified" : ", not verified") << ")\n";
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
    return t.str();
}

std::string optimize_text(const OptimizeReport& r) {
    using report_detail::fmt;
    std::ostringstream o;
    o << "optimize             min angle " << fmt(r.min_angle_before) << " -> " << fmt(r.min_angle_after)
      << " deg, max angle " << fmt(r.max_angle_before) << " -> " << fmt(r.max_angle_after) << " deg, mean minimum "
      << fmt(r.mean_min_angle_before) << " -> " << fmt(r.mean_min_angle_after) << " deg\n";
    o << "                     " << r.moves << " moves, " << r.flips << " flips, " << r.sweeps << " sweeps over "
      << r.active_vertices << " movable vertices of " << r.band_triangles << " band triangles, " << fmt(r.seconds)
      << " s\n";
    if (r.inserted_vertices)
        o << "                     refinement: " << r.refined_triangles << " bad triangles re-triangulated, "
          << r.inserted_vertices << " vertices inserted (" << r.boundary_splits << " on boundary edges"
          << (r.interface_splits ? ", " + std::to_string(r.interface_splits) + " on interfaces" : std::string()) << ")\n";
    if (r.removed_vertices)
        o << "                     " << r.removed_vertices << " interior vertices removed (their stars re-triangulated)\n";
    o << "                     certified floor " << fmt(r.certified_floor)
      << " deg (every triangle stays above it: monotone rule); boundary distance to f = 0 "
      << fmt(r.boundary_distance_before) << " -> " << fmt(r.boundary_distance_after) << "\n";
    return o.str();
}

std::string optimize_json(const OptimizeReport& r) {
    auto n = [](double x) { return json_number(x); };
    return "{\"min_angle_before_deg\": " + n(r.min_angle_before) + ", \"min_angle_after_deg\": " + n(r.min_angle_after) +
           ", \"max_angle_before_deg\": " + n(r.max_angle_before) + ", \"max_angle_after_deg\": " + n(r.max_angle_after) +
           ", \"mean_min_angle_before_deg\": " + n(r.mean_min_angle_before) +
           ", \"mean_min_angle_after_deg\": " + n(r.mean_min_angle_after) + ", \"certified_floor_deg\": " +
           n(r.certified_floor) + ", \"boundary_distance_before\": " + n(r.boundary_distance_before) +
           ", \"boundary_distance_after\": " + n(r.boundary_distance_after) +
           ", \"moves\": " + json_number(r.moves) + ", \"flips\": " + json_number(r.flips) +
           ", \"sweeps\": " + json_number(static_cast<std::int64_t>(r.sweeps)) +
           ", \"movable_vertices\": " + json_number(r.active_vertices) +
           ", \"band_triangles\": " + json_number(r.band_triangles) +
           ", \"refined_triangles\": " + json_number(r.refined_triangles) +
           ", \"inserted_vertices\": " + json_number(r.inserted_vertices) +
           ", \"boundary_splits\": " + json_number(r.boundary_splits) + ", \"interface_splits\": " +
           json_number(r.interface_splits) + ", \"removed_vertices\": " + json_number(r.removed_vertices) +
           ", \"seconds\": " + n(r.seconds) + "}";
}

}  // namespace warpmesh
