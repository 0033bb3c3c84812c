// report3d.cpp — the 3D mesher's report (report3d.hpp: Mesh3dReport) as text
// (what `warpmesh mesh3d` prints) and as one JSON object (--report FILE, the
// Python module's report dict): the same module and the same conventions as
// the 2D report (report.cpp: json_number's shortest round-trip numbers, null
// when not finite); several materials as the 2D multi-material report
// (material_report.cpp: the same lost-material warning, "materials" per
// material with its reference measure beside the mesh's).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "report_parts.hpp"
#include "warpmesh/certify/bcc_certified.hpp"  // bcc_certificate_path
#include "warpmesh/report/report3d.hpp"

namespace warpmesh {

namespace {

using report_detail::fmt;
using report_detail::json_strings;

// (volume − reference) / reference, NaN without a positive reference.
double relative_error(const Material3Figures& m) {
    return m.reference_volume && *m.reference_volume > 0 ? (m.volume - *m.reference_volume) / *m.reference_volume : NAN;
}

// A material with voxels (or an analytic one) that got no tetrahedron.
bool lost(const Material3Figures& m) { return m.tets == 0 && (!m.voxels || *m.voxels > 0); }

// The multi-material fields, in order (to_json's "materials" ... "junctions").
void material_fields(const Materials3Figures& ms, ReportFields& fields) {
    const auto n = [](auto x) { return json_number(x); };
    std::string list = "[", lost_tags = "[";
    for (const Material3Figures& m : ms.materials) {
        list += std::string(list.size() > 1 ? ", " : "") + "{\"tag\": " + n(std::int64_t{m.tag}) + ", \"name\": " + json_string(m.name) +
                ", \"tetrahedra\": " + n(m.tets) + ", \"volume\": " + n(m.volume) +
                ", \"voxels\": " + (m.voxels ? n(*m.voxels) : "null") +
                ", \"reference_volume\": " + (m.reference_volume ? n(*m.reference_volume) : "null") +
                ", \"relative_error\": " + n(relative_error(m)) + "}";
        if (lost(m)) lost_tags += std::string(lost_tags.size() > 1 ? ", " : "") + n(std::int64_t{m.tag});
    }
    fields.emplace_back("materials", list + "]");
    fields.emplace_back("materials_without_tetrahedra", lost_tags + "]");
    fields.emplace_back("interface_faces", n(ms.interface_faces));
    fields.emplace_back("junctions", "{\"background_tetrahedra\": " + n(ms.junction_background_tets) + ", \"tetrahedra\": " +
                                         n(ms.junction_tets) + ", \"certified\": " + (ms.junctions_certified ? "true" : "false") +
                                         ", \"certificate\": " +
                                         (ms.junctions_certified ? json_string("proofs/bcc_junctions.cert") : std::string("null")) + "}");
    fields.emplace_back("all_zero_filled", n(ms.all_zero_filled));
    fields.emplace_back("all_zero_voids", n(ms.all_zero_voids));
}

// The multi-material lines of the text report.
std::string materials_text(const Materials3Figures& ms) {
    std::ostringstream o;
    o << "materials: " << ms.materials.size() << " (tag name: tetrahedra, volume; label volumes: voxels' volume, relative error)\n";
    for (const Material3Figures& m : ms.materials) {
        o << "  " << m.tag << " " << m.name << ": " << m.tets << " tetrahedra, volume " << fmt(m.volume, 8);
        if (m.reference_volume)
            o << "; " << (m.voxels ? std::to_string(*m.voxels) : std::string("?")) << " voxels, volume " << fmt(*m.reference_volume, 8)
              << ", error " << fmt(100 * relative_error(m), 3) << " %";
        o << '\n';
    }
    o << "interface faces: " << ms.interface_faces << "; junctions (3 or 4 materials): " << ms.junction_background_tets
      << " background tetrahedra, " << ms.junction_tets << " tetrahedra"
      << (ms.junctions_certified ? ", certified by proofs/bcc_junctions.cert\n" : ", not certified\n");
    o << "all-zero background tetrahedra: " << ms.all_zero_filled << " output within the certificate's claim, "
      << ms.all_zero_voids << " left out inside a material (voids)\n";
    return o.str();
}

}  // namespace

std::vector<std::string> material_warnings(const Materials3Figures& ms) {
    std::vector<std::string> warnings;
    for (const Material3Figures& m : ms.materials) {
        if (lost(m)) {
            warnings.push_back(report_detail::lost_material_warning(m.tag, m.name, "tetrahedron"));
            continue;
        }
        const double e = relative_error(m);
        if (m.tag == 0 || !m.voxels || *m.voxels < 1000 || !(std::abs(e) > 0.05)) continue;  // (labels, not the background)
        char text[400];
        std::snprintf(text, sizeof text,
                      "material %d (%s): the mesh's volume, %.6g, is %.1f %% %s its %lld voxels' (%.6g): parts thinner than "
                      "about the spacing are %s; a smaller spacing follows the voxels more closely",
                      static_cast<int>(m.tag), m.name.c_str(), m.volume, 100 * std::abs(e), e < 0 ? "below" : "above",
                      static_cast<long long>(*m.voxels), *m.reference_volume,
                      e < 0 ? "lost (and, where the label reaches the volume's edge, the half voxel beyond the outermost "
                              "voxel centres)"
                            : "thickened");
        warnings.emplace_back(text);
    }
    return warnings;
}

namespace {

// A graded mesh's "graded" object.
std::string graded_json(const Graded3Figures& g) {
    const auto n = [](auto x) { return json_number(x); };
    std::string levels = "[";
    for (std::size_t k = 0; k < g.leaves_per_level.size(); ++k) levels += (k ? ", " : "") + n(g.leaves_per_level[k]);
    return "{\"leaves_per_level\": " + levels + "], \"template_tetrahedra\": " + n(g.template_tets) +
           ", \"max_size\": " + (g.max_size > 0 ? n(g.max_size) : std::string("null")) + ", \"max_level\": " + n(static_cast<std::int64_t>(g.max_level)) +
           ", \"grading\": " + n(g.grading) + ", \"grading_buffer\": " + n(static_cast<std::int64_t>(g.grading_buffer)) + ", \"longest_edge\": " +
           n(g.longest_edge) + ", \"templates\": " +
           (g.templates_certified ? "{\"certificate\": \"proofs/bcc_graded.cert\", \"min_dihedral_deg\": " + n(g.template_min_deg) +
                                        ", \"max_dihedral_deg\": " + n(g.template_max_deg) + "}"
                                  : std::string("null")) +
           "}";
}

std::string graded_text(const Graded3Figures& g) {
    std::ostringstream o;
    o << "graded: leaves per level (0 = finest)";
    for (std::size_t k = 0; k < g.leaves_per_level.size(); ++k) o << (k ? ", " : " ") << g.leaves_per_level[k];
    o << "; " << g.template_tets << " template tetrahedra; longest edge " << fmt(g.longest_edge, 5);
    if (g.max_size > 0) o << " (max size " << fmt(g.max_size, 5) << ")";
    if (g.grading_buffer > 0) o << "; grading " << fmt(g.grading, 4) << " (buffer " << g.grading_buffer << ")";
    o << '\n';
    return o.str();
}

}  // namespace

std::string to_json(const Mesh3dReport& r) {
    const auto n = [](auto x) { return json_number(x); };
    std::string hist = "[";
    for (std::size_t k = 0; k < r.quality.radius_ratio_histogram.size(); ++k)
        hist += (k ? ", " : "") + n(static_cast<std::int64_t>(r.quality.radius_ratio_histogram[k]));
    hist += "]";
    ReportFields fields = {
        {"dimension", "3"},
        {"vertices", n(r.vertices)},
        {"tetrahedra", n(r.tets)},
        {"boundary_faces", n(r.boundary_faces)},
        {"volume", n(r.quality.volume)},
        {"lattice_points", n(r.lattice_points)},
        {"background_tetrahedra", n(r.background_tets)},
        {"cut_points", n(r.cut_points)},
        {"warped_points", n(r.warped)},
        {"all_zero_left_out", n(r.all_zero_left_out)},
        {"min_dihedral_deg", n(r.quality.min_dihedral_deg)},
        {"max_dihedral_deg", n(r.quality.max_dihedral_deg)},
        {"radius_ratio_min", n(r.quality.radius_ratio_min)},
        {"radius_ratio_mean", n(r.quality.radius_ratio_mean)},
        {"radius_ratio_histogram", hist},
        {"boundary_vertex_f_max", n(r.quality.boundary_vertex_f_max)},
        {"boundary_centroid_f_max", n(r.quality.boundary_centroid_f_max)},
        {"nonmanifold_boundary_edges", n(r.nonmanifold_boundary_edges)},
        {"nonmanifold_boundary_vertices", n(r.nonmanifold_boundary_vertices)},
    };
    if (r.manifold_added_vertices) fields.emplace_back("manifold_added_vertices", n(*r.manifold_added_vertices));
    if (r.materials) material_fields(*r.materials, fields);
    if (r.graded) fields.emplace_back("graded", graded_json(*r.graded));
    const ReportFields certification = {
        {"face_rule", json_string(face_rule_name(r.face_rule))},
        {"certified", r.certified ? "{\"certificate\": " + json_string(bcc_certificate_path(r.face_rule)) + ", \"min_dihedral_deg\": " + n(r.certified_min_deg) + ", \"max_dihedral_deg\": " +
                                        n(r.certified_max_deg) + ", \"certified_tetrahedra\": " + n(r.certified_tets) +
                                        ", \"uncertified_tetrahedra\": " + n(r.uncertified_tets) +
                                        ", \"verified\": " + (r.verified ? "true" : "false") + "}"
                                  : "null"},
        {"uncertified_reason", r.uncertified_reason.empty() ? "null" : json_string(r.uncertified_reason)},
        {"narrowest_width", n(r.narrowest_width)},
        {"suggested_spacing", r.suggested_spacing > 0 ? n(r.suggested_spacing) : "null"},
        {"warnings", json_strings(r.warnings)},
        {"seconds", n(r.seconds)},
    };
    fields.insert(fields.end(), certification.begin(), certification.end());
    std::string out = "{";
    for (std::size_t k = 0; k < fields.size(); ++k)
        out += (k ? ",\n  " : "\n  ") + json_string(fields[k].first) + ": " + fields[k].second;
    return out + "\n}\n";
}

std::string to_text(const Mesh3dReport& r) {
    std::ostringstream o;
    o << "mesh: " << r.vertices << " vertices, " << r.tets << " tetrahedra, " << r.boundary_faces << " boundary triangles\n";
    o << "  volume " << fmt(r.quality.volume, 10) << "; lattice " << r.lattice_points << " points, " << r.warped << " warped, "
      << r.cut_points << " cut points; all-zero background tetrahedra left out: " << r.all_zero_left_out << '\n';
    o << "dihedral angles: min " << fmt(r.quality.min_dihedral_deg) << " deg, max " << fmt(r.quality.max_dihedral_deg) << " deg\n";
    o << "radius ratio 3 r_in / R_circ (1 = regular): min " << fmt(r.quality.radius_ratio_min, 4) << ", mean "
      << fmt(r.quality.radius_ratio_mean, 4) << '\n';
    std::int64_t peak = 0;
    for (const std::int64_t c : r.quality.radius_ratio_histogram) peak = std::max(peak, c);
    for (std::size_t k = 0; peak > 0 && k < r.quality.radius_ratio_histogram.size(); ++k) {
        const std::int64_t c = r.quality.radius_ratio_histogram[k];
        if (!c) continue;
        char row[64];
        std::snprintf(row, sizeof row, "  [%.1f, %.1f%c %12lld  ", static_cast<double>(k) / 10, static_cast<double>(k + 1) / 10,
                      k + 1 == r.quality.radius_ratio_histogram.size() ? ']' : ')', static_cast<long long>(c));
        const auto bar = static_cast<std::size_t>(std::llround(40.0 * static_cast<double>(c) / static_cast<double>(peak)));
        o << row << std::string(bar ? bar : 1, '#') << '\n';
    }
    o << "boundary: ";
    if (std::isfinite(r.quality.boundary_vertex_f_max))  // (several materials: no level set)
        o << "|f| at vertices <= " << fmt(r.quality.boundary_vertex_f_max, 3) << ", at face centroids <= "
          << fmt(r.quality.boundary_centroid_f_max, 3) << "; ";
    o << "non-manifold edges " << r.nonmanifold_boundary_edges << ", vertices " << r.nonmanifold_boundary_vertices;
    if (r.manifold_added_vertices) o << " (after --manifold split vertices: " << *r.manifold_added_vertices << " added)";
    o << '\n';
    if (r.materials) o << materials_text(*r.materials);
    if (r.graded) o << graded_text(*r.graded);
    o << "face rule: " << face_rule_name(r.face_rule) << '\n';
    if (r.certified)
        o << "certified (" << bcc_certificate_path(r.face_rule)
          << (r.materials && r.materials->junctions_certified && r.materials->junction_tets > 0 ? " and proofs/bcc_junctions.cert" : "")
          << (r.graded && r.graded->templates_certified && r.graded->template_tets > 0 ? " and proofs/bcc_graded.cert" : "")
          << "): dihedral angles in [" << fmt(r.certified_min_deg, 5) << ", "
          << fmt(r.certified_max_deg, 5) << "] deg for " << r.certified_tets << " tetrahedra"
          << (r.verified ? ", each verified" : "") << "; uncertified: " << r.uncertified_tets
          << (r.uncertified_reason.empty() ? "" : " (" + r.uncertified_reason + ")") << '\n';
    else
        o << "certified: no (" << (r.uncertified_reason.empty() ? "not looked up" : r.uncertified_reason) << "); uncertified: " << r.tets << '\n';
    o << "time: " << fmt(r.seconds, 4) << " s";
    if (r.seconds > 0) o << " (" << fmt(static_cast<double>(r.tets) / r.seconds / 1e6, 4) << " M tetrahedra/s)";
    o << '\n';
    return o.str();
}

}  // namespace warpmesh
