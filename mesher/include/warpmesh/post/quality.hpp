// quality.hpp — a quality report of a mesh: its measurement.  Its text and
// JSON (quality_text, quality_json) are the report module's (report.hpp).
//
// This is the *reporting* path: angles are computed in floating point with
// std::atan2 and are not part of any proof.  compute_quality is one parallel
// pass over the triangles (OpenMP, per-thread partial results merged in thread
// order, so the result is deterministic for a given thread count).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "warpmesh/core/mesh.hpp"
#include "warpmesh/core/triangle_shape.hpp"  // triangle_angles, triangle_min_angle, radius_ratio

namespace warpmesh {

struct QualityReport {
    static constexpr int histogram_bin_deg = 2;
    static constexpr int histogram_bins = 30;  // 0°–60°: bin i is [2i, 2i + 2), 60° goes to the last

    std::int64_t vertices = 0, triangles = 0, boundary_edges = 0;

    // Over all triangles (NaN when there are none).
    double min_angle_deg = 0, max_angle_deg = 0;
    double mean_min_angle_deg = 0;
    std::array<std::int64_t, histogram_bins> min_angle_histogram{};  // of each triangle's minimum angle

    // Statistics of each triangle's maximum angle.
    double max_angle_min_deg = 0, max_angle_mean_deg = 0;
    std::int64_t max_angle_over_90 = 0, max_angle_over_120 = 0;  // obtuse / very obtuse (beyond 1e-9° rounding)

    // 2 r_in / R_circ (1 = equilateral).
    double radius_ratio_min = 0, radius_ratio_mean = 0;

    double area = 0;                          // sum of signed areas
    std::int64_t nonpositive_triangles = 0;   // signed area <= 0 (should be none)
    double boundary_length = 0;               // sum of boundary edge lengths
    std::map<std::int32_t, std::int64_t> boundary_edges_by_tag;
    std::map<std::int32_t, double> boundary_length_by_tag;
    std::map<std::int32_t, std::int64_t> triangles_by_region;

    // Wall time per pipeline phase, in order, as passed to compute_quality.
    std::vector<std::pair<std::string, double>> phase_seconds;
};

QualityReport compute_quality(const Mesh& mesh, std::vector<std::pair<std::string, double>> phase_seconds = {});

}  // namespace warpmesh
