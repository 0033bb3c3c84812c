// tet_quality.cpp — quality of tetrahedra: dihedral angles, radius ratio,
// and the quality fields of a 3D report (mesh3d.hpp).
//
// The dihedral angle at edge (a, b), with c, d the other vertices, is the
// angle between n_c = e × (pc − pa) and n_d = e × (pd − pa), e = pb − pa
// (generic_bcc.hpp, "Angle forms": the same forms the proof bounds).  The
// mesh-wide extremes are tracked on cos θ = n_c·n_d / √(|n_c|²|n_d|²) and
// turned into degrees once.  Radius ratio 3 r_in / R_circ: r_in = 3V / (sum
// of face areas), R_circ = |a² (b × c) + b² (c × a) + c² (a × b)| / (12 V) with
// a, b, c the edges from p0 (1 for the regular tetrahedron).
#include <algorithm>
#include <cmath>
#include <numbers>

#include "uniform3d/uniform3d.hpp"

namespace warpmesh {
namespace {

using V = bcc::Vec<double>;
V vec(const Point3& p) { return {p.x, p.y, p.z}; }
double norm(const V& v) { return std::sqrt(bcc::dot(v, v)); }

// cos of the six dihedral angles.
std::array<double, 6> dihedral_cos(const std::array<Point3, 4>& p) {
    const auto f = bcc::dihedral_forms<double>({vec(p[0]), vec(p[1]), vec(p[2]), vec(p[3])});
    std::array<double, 6> c{};
    for (std::size_t k = 0; k < 6; ++k) c[k] = f.nn[k] > 0 ? std::clamp(f.dot[k] / std::sqrt(f.nn[k]), -1.0, 1.0) : 1.0;
    return c;
}

double degrees(double cosine) { return std::acos(cosine) * 180 / std::numbers::pi; }

}  // namespace

std::array<double, 6> dihedral_angles_deg(const std::array<Point3, 4>& p) {
    std::array<double, 6> a = dihedral_cos(p);
    for (double& x : a) x = degrees(x);
    return a;
}

double radius_ratio(const std::array<Point3, 4>& p) {
    const V a = bcc::vsub(vec(p[1]), vec(p[0])), b = bcc::vsub(vec(p[2]), vec(p[0])), c = bcc::vsub(vec(p[3]), vec(p[0]));
    const double det = bcc::dot(a, bcc::cross(b, c));
    if (!(det > 0)) return 0;
    const V bc = bcc::cross(b, c), ca = bcc::cross(c, a), ab = bcc::cross(a, b);
    const double aa = bcc::dot(a, a), bb = bcc::dot(b, b), cc = bcc::dot(c, c);
    const V num{aa * bc[0] + bb * ca[0] + cc * ab[0], aa * bc[1] + bb * ca[1] + cc * ab[1], aa * bc[2] + bb * ca[2] + cc * ab[2]};
    const double R = norm(num) / (2 * det);
    const V d = bcc::vsub(c, b), e = bcc::vsub(a, b);
    const double area2 = norm(bc) + norm(ca) + norm(ab) + norm(bcc::cross(d, e));  // twice the face areas
    const double r = det / area2;  // 3V / (area sum) = (det / 2) / (area2 / 2)
    return std::min(1.0, 3 * r / R);
}

void measure_quality3(const TetMesh& mesh, const LevelSet3& f, Mesh3dReport& r) {
    double cmax = -1, cmin = 1, rr_min = 1, rr_sum = 0, volume = 0;
    std::array<std::int64_t, Mesh3dReport::radius_ratio_bins> hist{};
    const std::int64_t T = static_cast<std::int64_t>(mesh.tets.size());
#pragma omp parallel
    {
        double lcmax = -1, lcmin = 1, lrr_min = 1, lrr_sum = 0, lvol = 0;
        std::array<std::int64_t, Mesh3dReport::radius_ratio_bins> lh{};
#pragma omp for schedule(static) nowait
        for (std::int64_t t = 0; t < T; ++t) {
            const auto& tet = mesh.tets[static_cast<std::size_t>(t)];
            const std::array<Point3, 4> p{mesh.vertices[static_cast<std::size_t>(tet[0])], mesh.vertices[static_cast<std::size_t>(tet[1])],
                                          mesh.vertices[static_cast<std::size_t>(tet[2])], mesh.vertices[static_cast<std::size_t>(tet[3])]};
            for (double c : dihedral_cos(p)) lcmax = std::max(lcmax, c), lcmin = std::min(lcmin, c);
            const double q = radius_ratio(p);
            lrr_min = std::min(lrr_min, q), lrr_sum += q;
            ++lh[static_cast<std::size_t>(std::min(Mesh3dReport::radius_ratio_bins - 1, static_cast<int>(q * Mesh3dReport::radius_ratio_bins)))];
            const V a = bcc::vsub(vec(p[1]), vec(p[0])), b = bcc::vsub(vec(p[2]), vec(p[0])), c = bcc::vsub(vec(p[3]), vec(p[0]));
            lvol += bcc::dot(a, bcc::cross(b, c)) / 6;
        }
#pragma omp critical
        {
            cmax = std::max(cmax, lcmax), cmin = std::min(cmin, lcmin), rr_min = std::min(rr_min, lrr_min);
            rr_sum += lrr_sum, volume += lvol;
            for (std::size_t i = 0; i < hist.size(); ++i) hist[i] += lh[i];
        }
    }
    r.min_dihedral_deg = degrees(cmax), r.max_dihedral_deg = degrees(cmin);
    r.radius_ratio_min = rr_min, r.radius_ratio_mean = T ? rr_sum / static_cast<double>(T) : 0;
    r.radius_ratio_histogram = hist, r.volume = volume;
    double fv = 0, fc = 0;
    for (std::size_t i = 0; i < mesh.boundary.size(); ++i) {
        if (mesh.boundary_tag[i] != boundary_level_set) continue;
        Point3 c{0, 0, 0};
        for (std::int32_t v : mesh.boundary[i]) {
            const Point3& p = mesh.vertices[static_cast<std::size_t>(v)];
            fv = std::max(fv, std::abs(f.value(p.x, p.y, p.z)));
            c = {c.x + p.x / 3, c.y + p.y / 3, c.z + p.z / 3};
        }
        fc = std::max(fc, std::abs(f.value(c.x, c.y, c.z)));
    }
    r.boundary_vertex_f_max = fv, r.boundary_centroid_f_max = fc;
}

}  // namespace warpmesh
