// report3d.cpp — the 3D mesher's report (report3d.hpp: Mesh3dReport) as text
// (what `warpmesh mesh3d` prints) and as one JSON object (--report FILE, the
// Python module's report dict): the same module and the same conventions as
// the 2D report (report.cpp: json_number's shortest round-trip numbers, null
// when not finite).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "warpmesh/certify/bcc_certified.hpp"  // bcc_certificate_path
#include "warpmesh/report/report.hpp"
#include "warpmesh/report/report3d.hpp"

namespace warpmesh {

namespace {

std::string fmt(double x, int digits = 6) {
    if (!std::isfinite(x)) return "n/a";
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, x, std::chars_format::general, digits);
    return std::string(buf, r.ptr);
}

std::string json_strings(const std::vector<std::string>& items) {
    std::string r = "[";
    for (std::size_t k = 0; k < items.size(); ++k) r += (k ? ", " : "") + json_string(items[k]);
    return r + "]";
}

}  // namespace

std::string to_json(const Mesh3dReport& r) {
    const auto n = [](auto x) { return json_number(x); };
    std::string hist = "[";
    for (std::size_t k = 0; k < r.quality.radius_ratio_histogram.size(); ++k)
        hist += (k ? ", " : "") + n(static_cast<std::int64_t>(r.quality.radius_ratio_histogram[k]));
    hist += "]";
    const ReportFields fields = {
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
        {"face_rule", json_string(face_rule_name(r.face_rule))},
        {"certified", r.certified ? "{\"certificate\": " + json_string(bcc_certificate_path(r.face_rule)) + ", \"min_dihedral_deg\": " + n(r.certified_min_deg) + ", \"max_dihedral_deg\": " +
                                        n(r.certified_max_deg) + ", \"certified_tetrahedra\": " + n(r.certified_tets) +
                                        ", \"uncertified_tetrahedra\": " + n(r.uncertified_tets) +
                                        ", \"verified\": " + (r.verified ? "true" : "false") + "}"
                                  : "null"},
        {"uncertified_reason", r.certified ? "null" : json_string(r.uncertified_reason)},
        {"narrowest_width", n(r.narrowest_width)},
        {"suggested_spacing", r.suggested_spacing > 0 ? n(r.suggested_spacing) : "null"},
        {"warnings", json_strings(r.warnings)},
        {"seconds", n(r.seconds)},
    };
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
    o << "boundary: |f| at vertices <= " << fmt(r.quality.boundary_vertex_f_max, 3) << ", at face centroids <= "
      << fmt(r.quality.boundary_centroid_f_max, 3) << "; non-manifold edges " << r.nonmanifold_boundary_edges << ", vertices "
      << r.nonmanifold_boundary_vertices << '\n';
    o << "face rule: " << face_rule_name(r.face_rule) << '\n';
    if (r.certified)
        o << "certified (" << bcc_certificate_path(r.face_rule) << "): dihedral angles in [" << fmt(r.certified_min_deg, 5) << ", "
          << fmt(r.certified_max_deg, 5) << "] deg for " << r.certified_tets << " tetrahedra"
          << (r.verified ? ", each verified" : "") << "; uncertified: " << r.uncertified_tets << '\n';
    else
        o << "certified: no (" << (r.uncertified_reason.empty() ? "not looked up" : r.uncertified_reason) << "); uncertified: " << r.tets << '\n';
    o << "time: " << fmt(r.seconds, 4) << " s";
    if (r.seconds > 0) o << " (" << fmt(static_cast<double>(r.tets) / r.seconds / 1e6, 4) << " M tetrahedra/s)";
    o << '\n';
    return o.str();
}

}  // namespace warpmesh
