// material_report.cpp — the multi-material part of the 2D report
// (report.hpp: MaterialsFigures, MaterialResult's figures of the output mesh,
// materials.hpp): per material its triangles, area, perimeter and reference
// (pixel-count) area; the junction squares (3 or 4 materials) with their
// junction keys and certified bounds (proofs/materials.cert);
// the edges where a third material lies between a cut edge's two.
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <vector>
#include <sstream>

#include "report_parts.hpp"

namespace warpmesh {

namespace {
// A material with pixels (or an analytic one) that got no triangle; the
// dropped background may well be empty.
bool lost_material(const MaterialStats& s) {
    return (s.tag != 0 || s.output) && s.triangles == 0 && (!s.reference_area || *s.reference_area > 0);
}

bool any_cap(const MaterialsFigures& r) {
    return std::any_of(r.materials.begin(), r.materials.end(), [](const MaterialStats& s) { return s.max_size.has_value(); });
}

std::string tags_text(const std::array<std::int32_t, 4>& t) {
    return "[" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) + ", " + std::to_string(t[3]) + "]";
}
}  // namespace

void report_detail::material_fields(JsonObject& out, const MaterialsFigures& r) {
    const bool capped = any_cap(r);
    std::string m = "[";
    for (std::size_t k = 0; k < r.materials.size(); ++k) {
        const MaterialStats& s = r.materials[k];
        m += std::string(k ? ", " : "") + "{\"tag\": " + std::to_string(s.tag) + ", \"name\": " + json_string(s.name) +
             ", \"output\": " + (s.output ? "true" : "false") + ", \"triangles\": " + std::to_string(s.triangles) +
             ", \"area\": " + json_number(s.area) + ", \"perimeter\": " + json_number(s.perimeter);
        if (s.area_before_optimize) m += ", \"area_before_optimize\": " + json_number(*s.area_before_optimize);
        if (s.reference_area)
            m += ", \"pixel_area\": " + json_number(*s.reference_area) + ", \"area_minus_pixel_area\": " + json_number(s.area - *s.reference_area);
        if (capped)  // (not output: no triangle to measure)
            m += ", \"max_size\": " + (s.max_size ? json_number(*s.max_size) : std::string("null")) +
                 ", \"longest_edge\": " + (s.output ? json_number(s.longest_edge) : std::string("null"));
        m += "}";
    }
    out.field("materials", m + "]");
    std::string lost = "[";  // materials lost at this spacing (material_warnings)
    for (const MaterialStats& s : r.materials)
        if (lost_material(s)) lost += std::string(lost.size() > 1 ? ", " : "") + std::to_string(s.tag);
    out.field("materials_without_triangles", lost + "]");
    out.field("interface_edges", std::to_string(r.interface_edges));
    out.field("third_material_edges", std::to_string(r.third_material_edges));
    out.field("centroid_material_triangles", std::to_string(r.centroid_material_triangles));
    out.field("mixed_triangles", std::to_string(r.mixed_triangles));
    // Junction squares are certified when certification ran (certified.available).
    std::string j = "{\"count\": " + std::to_string(r.junction_squares) +
                    ", \"certified\": " + (r.junctions_certified ? "true" : "false") + ", \"examples\": [";
    for (std::size_t k = 0; k < r.junction_examples.size(); ++k) {
        const JunctionSquare& e = r.junction_examples[k];
        j += std::string(k ? ", " : "") + "{\"i\": " + std::to_string(e.i) + ", \"j\": " + std::to_string(e.j) +
             ", \"materials\": " + tags_text(e.tags) + ", \"key\": " + json_string(e.pattern) +
             ", \"min_angle_deg\": " + json_number(e.min_deg) + ", \"max_angle_deg\": " + json_number(e.max_deg) + "}";
    }
    out.field("junction_squares", j + "]}");
}

std::string report_detail::lost_material_warning(std::int32_t tag, const std::string& name, std::string_view cell) {
    return "material " + std::to_string(tag) + " (" + name + ") got no " + std::string(cell) +
           ": it is lost at this spacing (use a smaller --spacing)";
}

std::vector<std::string> material_warnings(const MaterialsFigures& r) {
    std::vector<std::string> warnings;
    for (const MaterialStats& s : r.materials)
        if (lost_material(s)) warnings.push_back(report_detail::lost_material_warning(s.tag, s.name, "triangle"));
    return warnings;
}

std::string report_detail::materials_text(const MaterialsFigures& r) {
    std::ostringstream t;
    t.precision(6);
    const bool capped = any_cap(r);
    t << "materials            " << r.materials.size() << " (tag, triangles, area, perimeter, pixel area"
      << (capped ? ", longest edge" : "") << ")\n";
    for (const MaterialStats& s : r.materials) {
        t << "  " << s.tag << " " << s.name << (s.output ? "" : " (not output)") << ": " << s.triangles << " triangles, area "
          << s.area << ", perimeter " << s.perimeter;
        if (s.reference_area) t << ", pixel area " << *s.reference_area;
        if (capped && s.output) {
            t << ", longest edge " << s.longest_edge;
            if (s.max_size) t << " (max size " << *s.max_size << ")";
        }
        t << "\n";
    }
    t << "interface edges      " << r.interface_edges << "\n";
    t << "third-material edges " << r.third_material_edges << " (cut edges whose cut point lies in a third material)\n";
    t << "junction squares     " << r.junction_squares
      << (r.junctions_certified ? " (3 or 4 materials: junction keys, proofs/materials.cert)\n"
                                : " (3 or 4 materials; not certified: certification off)\n");
    for (const JunctionSquare& e : r.junction_examples)
        t << "  (" << e.i << ", " << e.j << ") materials " << tags_text(e.tags) << " key " << e.pattern << " certified ["
          << std::setprecision(10) << e.min_deg << ", " << e.max_deg << "] deg\n" << std::setprecision(6);
    if (r.junction_squares > static_cast<std::int64_t>(r.junction_examples.size())) t << "  ...\n";
    return t.str();
}

}  // namespace warpmesh
