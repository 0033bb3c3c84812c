// report2d.cpp — the whole report of a 2D mesh (report.hpp: Mesh2dReport) as
// one JSON object (what `warpmesh mesh --report FILE` writes, the Python
// MeshResult's report dict) and as text (what `warpmesh mesh` prints): the
// quality's part (report.cpp) first, then each stage's part in pipeline order.
#include <string>

#include "report_parts.hpp"

namespace warpmesh {

namespace {

using report_detail::JsonObject;

std::string json_list(const std::vector<std::int64_t>& v) {
    std::string s = "[";
    for (std::size_t k = 0; k < v.size(); ++k) s += (k ? ", " : "") + std::to_string(v[k]);
    return s + "]";
}

std::string json_vec(const std::array<double, 3>& v) {
    return "[" + json_number(v[0]) + ", " + json_number(v[1]) + ", " + json_number(v[2]) + "]";
}

void lattice_fields(JsonObject& json, const LatticeFigures& l) {
    json.field("input", json_string(l.input));
    json.field("levelset", json_string(l.levelset));
    json.field("rule", json_string(rule_name(l.rule)));
    json.field("spacing", json_number(l.spacing));
    if (l.repeat > 1) json.field("repeat", std::to_string(l.repeat));
    json.field("lattice", "[" + std::to_string(l.nx) + ", " + std::to_string(l.ny) + "]");
}

// "lattice_metric" sits among the mesher's fields (after "graded").
void mesher_fields(JsonObject& json, const MesherFigures& m, LatticeMetric metric) {
    json.field("graded", m.graded ? "true" : "false");
    if (metric == LatticeMetric::rhombic) json.field("lattice_metric", json_string("rhombic"));
    if (m.graded) json.field("leaves_per_level", json_list(m.leaves_per_level));
    if (const auto& c = m.size_control) {
        json.field("max_size", c->max_size != 0 ? json_number(c->max_size) : "null");
        json.field("max_cell", json_number(c->max_cell));
        json.field("grading", json_number(c->grading));
        json.field("grading_buffer", json_number(c->grading_buffer));
    }
    if (!m.max_size_of.empty()) {
        std::string caps = "[";
        for (const MaterialCapFigures& c : m.max_size_of)
            caps += std::string(caps.size() > 1 ? ", " : "") + "{\"tag\": " + std::to_string(c.tag) +
                    ", \"max_size\": " + json_number(c.max_size) +
                    ", \"max_cell\": " + (c.max_cell ? json_number(*c.max_cell) : std::string("null")) + "}";
        json.field("max_size_of", caps + "]");
    }
    json.field("cut_edges", std::to_string(m.cut_edges));
    json.field("warped_points", std::to_string(m.warped_points));
    json.field("warped_squares", std::to_string(m.warped_squares));
    json.field("separating_overrides", std::to_string(m.separating_overrides));
    if (m.sampled_points) json.field("sampled_points", std::to_string(*m.sampled_points));
}

void slice_fields(JsonObject& json, const SliceFigures& s) {
    json.field("units", json_string(s.units));
    json.field("slice", "{\"axis\": \"" + std::string(1, "ijk"[s.axis]) + "\", \"index\": " + std::to_string(s.index) +
                            ", \"format\": " + json_string(s.format) + "}");
    json.field("plane", report_detail::slice_plane_json(s));
}

}  // namespace

std::string report_detail::slice_plane_json(const SliceFigures& s) {
    return "{\"origin\": " + json_vec(s.origin) + ", \"x_axis\": " + json_vec(s.x_axis) + ", \"y_axis\": " +
           json_vec(s.y_axis) + ", \"normal\": " + json_vec(s.normal) + "}";
}

std::string to_json(const Mesh2dReport& r) {
    JsonObject json;
    report_detail::quality_fields(json, r.quality);
    lattice_fields(json, r.lattice);
    mesher_fields(json, r.mesher, r.lattice.metric);
    if (r.optimize) json.field("optimize", optimize_json(*r.optimize));
    if (r.materials) report_detail::material_fields(json, *r.materials);
    json.field("peak_memory_mb", json_number(r.peak_memory_mb));
    if (r.refinements) json.field("refinements", std::to_string(*r.refinements));
    if (const CertificationFigures& c = r.certified; c.requested)
        json.field("certified", c.summary.available
                                    ? certified_json(c.summary, r.lattice.rule, c.junctions, r.lattice.metric)
                                    : std::string("null"));
    if (r.slice) slice_fields(json, *r.slice);
    return json.close();
}

std::string to_text(const Mesh2dReport& r) {
    std::string text = quality_text(r.quality);
    if (r.certified.summary.available) text += certified_text(r.certified.summary, r.lattice.rule, r.lattice.metric);
    if (r.materials) text += report_detail::materials_text(*r.materials);
    if (r.optimize) text += optimize_text(*r.optimize);
    return text;
}

}  // namespace warpmesh
