// quality.cpp — the mesh quality measurement (quality.hpp); its text and JSON
// are the report module's (report/report.cpp).
#include "warpmesh/post/quality.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh {

namespace {

constexpr double nan = std::numeric_limits<double>::quiet_NaN();
// Lattice meshes are full of exact right angles; atan2 may return them as
// 90.00000000000001°.  Counts "over 90°/120°" ignore such rounding.
constexpr double angle_slack_deg = 1e-9;

// Per-thread partial results of the triangle pass.
struct Partial {
    double min_angle = std::numeric_limits<double>::infinity(), max_angle = -std::numeric_limits<double>::infinity();
    double sum_min_angle = 0;
    std::array<std::int64_t, QualityReport::histogram_bins> hist{};
    double min_max_angle = std::numeric_limits<double>::infinity(), sum_max_angle = 0;
    std::int64_t over_90 = 0, over_120 = 0;
    double min_rr = std::numeric_limits<double>::infinity(), sum_rr = 0;
    double area = 0;
    std::int64_t nonpositive = 0;
};

}  // namespace

QualityReport compute_quality(const Mesh& mesh, std::vector<std::pair<std::string, double>> phase_seconds) {
    QualityReport q;
    q.vertices = static_cast<std::int64_t>(mesh.vertices.size());
    q.triangles = static_cast<std::int64_t>(mesh.triangles.size());
    q.boundary_edges = static_cast<std::int64_t>(mesh.boundary.size());
    q.phase_seconds = std::move(phase_seconds);

    const std::int64_t nt = q.triangles;
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    std::vector<Partial> partial(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
    {
        int me = 0;
#ifdef _OPENMP
        me = omp_get_thread_num();
#endif
        Partial p;
#pragma omp for schedule(static)
        for (std::int64_t k = 0; k < nt; ++k) {
            const auto& t = mesh.triangles[static_cast<std::size_t>(k)];
            const Vec2 a = mesh.vertices[static_cast<std::size_t>(t[0])], b = mesh.vertices[static_cast<std::size_t>(t[1])],
                       c = mesh.vertices[static_cast<std::size_t>(t[2])];
            const TriangleShape sh = triangle_shape(a, b, c);
            const TriangleAngles& ang = sh.angles;
            p.min_angle = std::min(p.min_angle, ang.min_deg);
            p.max_angle = std::max(p.max_angle, ang.max_deg);
            p.sum_min_angle += ang.min_deg;
            const int bin = std::clamp(static_cast<int>(ang.min_deg / QualityReport::histogram_bin_deg), 0,
                                       QualityReport::histogram_bins - 1);
            ++p.hist[static_cast<std::size_t>(bin)];
            p.min_max_angle = std::min(p.min_max_angle, ang.max_deg);
            p.sum_max_angle += ang.max_deg;
            p.over_90 += ang.max_deg > 90 + angle_slack_deg;
            p.over_120 += ang.max_deg > 120 + angle_slack_deg;
            p.min_rr = std::min(p.min_rr, sh.ratio);
            p.sum_rr += sh.ratio;
            p.area += sh.twice_area / 2;
            p.nonpositive += !(sh.twice_area > 0);
        }
        partial[static_cast<std::size_t>(me)] = p;
    }

    Partial all;
    for (const Partial& p : partial) {
        all.min_angle = std::min(all.min_angle, p.min_angle);
        all.max_angle = std::max(all.max_angle, p.max_angle);
        all.sum_min_angle += p.sum_min_angle;
        for (std::size_t i = 0; i < all.hist.size(); ++i) all.hist[i] += p.hist[i];
        all.min_max_angle = std::min(all.min_max_angle, p.min_max_angle);
        all.sum_max_angle += p.sum_max_angle;
        all.over_90 += p.over_90;
        all.over_120 += p.over_120;
        all.min_rr = std::min(all.min_rr, p.min_rr);
        all.sum_rr += p.sum_rr;
        all.area += p.area;
        all.nonpositive += p.nonpositive;
    }
    const double n = static_cast<double>(nt);
    q.min_angle_deg = nt ? all.min_angle : nan;
    q.max_angle_deg = nt ? all.max_angle : nan;
    q.mean_min_angle_deg = nt ? all.sum_min_angle / n : nan;
    q.min_angle_histogram = all.hist;
    q.max_angle_min_deg = nt ? all.min_max_angle : nan;
    q.max_angle_mean_deg = nt ? all.sum_max_angle / n : nan;
    q.max_angle_over_90 = all.over_90;
    q.max_angle_over_120 = all.over_120;
    q.radius_ratio_min = nt ? all.min_rr : nan;
    q.radius_ratio_mean = nt ? all.sum_rr / n : nan;
    q.area = all.area;
    q.nonpositive_triangles = all.nonpositive;

    // Boundary (O(sqrt T) edges) and regions (tags come in runs: cache the
    // last map entry).
    for (std::size_t e = 0; e < mesh.boundary.size(); ++e) {
        const Vec2 a = mesh.vertices[static_cast<std::size_t>(mesh.boundary[e][0])],
                   b = mesh.vertices[static_cast<std::size_t>(mesh.boundary[e][1])];
        const double len = std::hypot(b.x - a.x, b.y - a.y);
        const std::int32_t tag = e < mesh.boundary_tag.size() ? mesh.boundary_tag[e] : 0;
        q.boundary_length += len;
        ++q.boundary_edges_by_tag[tag];
        q.boundary_length_by_tag[tag] += len;
    }
    auto last = q.triangles_by_region.end();
    for (const std::int32_t r : mesh.region) {
        if (last == q.triangles_by_region.end() || last->first != r) last = q.triangles_by_region.try_emplace(r, 0).first;
        ++last->second;
    }
    return q;
}


}  // namespace warpmesh
