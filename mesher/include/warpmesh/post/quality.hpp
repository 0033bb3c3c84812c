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

namespace warpmesh {

// Smallest and largest interior angle of triangle abc, in degrees (either
// orientation).  The smallest angle is opposite the shortest side and the
// largest opposite the longest (law of sines), so only these two are computed,
// each as atan2(|cross|, dot) of the two sides at that vertex — accurate for
// tiny and near-180° angles alike.  Three distinct collinear points give 0 and
// 180; at a repeated vertex atan2(0, 0) = 0 is used.
struct TriangleAngles {
    double min_deg, max_deg;
};
TriangleAngles triangle_angles(Vec2 a, Vec2 b, Vec2 c);
// triangle_angles(a, b, c).min_deg, bit for bit, with one atan2 and no square
// root (the optimisation pass's monotone rule).
double triangle_min_angle(Vec2 a, Vec2 b, Vec2 c);

// Radius ratio normalised so that the equilateral triangle has 1:
//   2 r_in / R_circ = 16 A² / ((a + b + c) a b c) = 4 cross² / ((a + b + c) a b c),
// using r_in = 2A / (a + b + c), R_circ = a b c / (4A) and cross = 2A.  It lies
// in [0, 1]; 0 for degenerate triangles.
double radius_ratio(Vec2 a, Vec2 b, Vec2 c);

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
