// tet_quality.cpp — quality of tetrahedra: dihedral angles, radius ratio,
// and the quality fields of a 3D report (mesh3d.hpp).
//
// The dihedral angle at edge (a, b), with c, d the other vertices, is the
// angle between n_c = e × (pc − pa) and n_d = e × (pd − pa), e = pb − pa
// (generic_bcc.hpp, "Angle forms": the same forms the proof bounds), and
// cos θ = n_c·n_d / √(|n_c|²|n_d|²).  Radius ratio 3 r_in / R_circ: r_in = 3V /
// (sum of face areas), R_circ = |a² (b × c) + b² (c × a) + c² (a × b)| / (12 V)
// with a, b, c the edges from p0 (1 for the regular tetrahedron).
//
// Cost (the report's pass over every tetrahedron).  Per edge the forms need
// two cross products, twelve in all, but only eight are distinct up to sign:
// with a, b, c = p1, p2, p3 − p0, u, v, w = p2, p3, p0 − p1 and s, t, r = p3,
// p0, p1 − p2,
//     edge 01: a × b, a × c        edge 02: −(a × b), b × c
//     edge 03: −(a × c), −(b × c)  edge 12: u × w, u × v
//     edge 13: v × w, −(u × v)     edge 23: s × t, s × r
// and x × y = −(y × x), (−x)·y = −(x·y), |−x|² = |x|² hold exactly in
// floating point (round to nearest is symmetric), so `measure` gives
// bcc::dihedral_forms's numbers bit for bit (a zero's sign aside) from eight
// cross products, and radius_ratio's from the same a × b, a × c, b × c.  The mesh-wide extremes
// of cos θ need √ and a division only near the running extreme: for best >
// 0 (the largest cos so far), c = d / √N cannot exceed it when d <= 0 or
// d² < best² N (1 − 1e-12) (the margin covers the rounding of d², best² N
// and of d / √N many times over); the smallest cos likewise for best < 0
// (may_exceed).
// The extremes are then the same doubles as cos evaluated at every edge.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "uniform3d/uniform3d.hpp"

namespace warpmesh {
namespace {

using V = bcc::Vec<double>;
V vec(const Point3& p) { return {p.x, p.y, p.z}; }
V neg(const V& v) { return {-v[0], -v[1], -v[2]}; }
double norm(const V& v) { return std::sqrt(bcc::dot(v, v)); }

// The angle forms (bcc::dihedral_forms's dot, nn and volume6, in
// tet_edges order) and the radius ratio of one tetrahedron.
struct TetMeasure {
    bcc::DihedralForms<double> forms;
    double radius_ratio;
};

// 3 r_in / R_circ from the edges a, b, c from p0, their cross products
// ab = a × b, ac = a × c, bc = b × c and det = a · (b × c) > 0.
double radius_ratio_of(const V& a, const V& b, const V& c, const V& ab, const V& ac, const V& bc, double det) {
    const V ca = neg(ac);
    const double aa = bcc::dot(a, a), bb = bcc::dot(b, b), cc = bcc::dot(c, c);
    const V num{aa * bc[0] + bb * ca[0] + cc * ab[0], aa * bc[1] + bb * ca[1] + cc * ab[1], aa * bc[2] + bb * ca[2] + cc * ab[2]};
    const double R = norm(num) / (2 * det);
    const V d = bcc::vsub(c, b), e = bcc::vsub(a, b);
    const double area2 = norm(bc) + norm(ca) + norm(ab) + norm(bcc::cross(d, e));  // twice the face areas
    const double r = det / area2;  // 3V / (area sum) = (det / 2) / (area2 / 2)
    return std::min(1.0, 3 * r / R);
}

TetMeasure measure(const std::array<Point3, 4>& p) {
    const V p0 = vec(p[0]), p1 = vec(p[1]), p2 = vec(p[2]), p3 = vec(p[3]);
    const V a = bcc::vsub(p1, p0), b = bcc::vsub(p2, p0), c = bcc::vsub(p3, p0);
    const V u = bcc::vsub(p2, p1), v = bcc::vsub(p3, p1), w = bcc::vsub(p0, p1);
    const V s = bcc::vsub(p3, p2), t = bcc::vsub(p0, p2), r = bcc::vsub(p1, p2);
    const V ab = bcc::cross(a, b), ac = bcc::cross(a, c), bc = bcc::cross(b, c);
    const V uw = bcc::cross(u, w), uv = bcc::cross(u, v), vw = bcc::cross(v, w);
    const V st = bcc::cross(s, t), sr = bcc::cross(s, r);
    const double nab = bcc::dot(ab, ab), nac = bcc::dot(ac, ac), nbc = bcc::dot(bc, bc);
    const double nuw = bcc::dot(uw, uw), nuv = bcc::dot(uv, uv), nvw = bcc::dot(vw, vw);
    TetMeasure m{};
    auto& f = m.forms;
    // tet_edges order: 01, 23, 02, 03, 12, 13.
    f.dot = {bcc::dot(ab, ac), bcc::dot(st, sr), -bcc::dot(ab, bc), bcc::dot(ac, bc), bcc::dot(uw, uv), -bcc::dot(vw, uv)};
    f.nn = {nab * nac, bcc::dot(st, st) * bcc::dot(sr, sr), nab * nbc, nac * nbc, nuw * nuv, nvw * nuv};
    f.volume6 = bcc::dot(a, bc);
    m.radius_ratio = f.volume6 > 0 ? radius_ratio_of(a, b, c, ab, ac, bc, f.volume6) : 0;
    return m;
}

// cos θ of one edge from its forms (1 for a degenerate face).
double cosine(double dot, double nn) { return nn > 0 ? std::clamp(dot / std::sqrt(nn), -1.0, 1.0) : 1.0; }

// Whether cosine(d, nn) might exceed best; false only when best > 0 and the
// squares decide it (d <= 0 or d² < best² nn (1 − 1e-12)), away from over-
// and underflow.  For "might be below best" ask may_exceed(−d, nn, −best).
// Branch-free on purpose: at the 90° edges of the lattice's tetrahedra d is
// rounding noise of either sign.
bool may_exceed(double d, double nn, double best) {
    const bool decided = best > 1e-3 && nn > 1e-280 && nn < 1e280;
    const bool below = (d <= 0) | (d * d < best * best * nn * (1 - 1e-12));
    return !(decided & below);
}

double degrees(double cosine) { return std::acos(cosine) * 180 / std::numbers::pi; }

// The running sums of the pass (one per thread, then combined).
struct Tally {
    double cmax = -1, cmin = 1, rr_min = 1, rr_sum = 0, volume = 0;
    std::array<std::int64_t, Mesh3dReport::radius_ratio_bins> hist{};

    void add(const TetMeasure& m) {
        for (std::size_t k = 0; k < 6; ++k) {
            const double d = m.forms.dot[k], nn = m.forms.nn[k];
            if (may_exceed(d, nn, cmax)) cmax = std::max(cmax, cosine(d, nn));
            if (may_exceed(-d, nn, -cmin)) cmin = std::min(cmin, cosine(d, nn));
        }
        const double q = m.radius_ratio;
        rr_min = std::min(rr_min, q), rr_sum += q;
        ++hist[static_cast<std::size_t>(std::min(Mesh3dReport::radius_ratio_bins - 1, static_cast<int>(q * Mesh3dReport::radius_ratio_bins)))];
        volume += m.forms.volume6 / 6;
    }
    void merge(const Tally& o) {
        cmax = std::max(cmax, o.cmax), cmin = std::min(cmin, o.cmin), rr_min = std::min(rr_min, o.rr_min);
        rr_sum += o.rr_sum, volume += o.volume;
        for (std::size_t i = 0; i < hist.size(); ++i) hist[i] += o.hist[i];
    }
};

// Max |f| at the level-set boundary's vertices (each once) and at its faces' centroids.
void boundary_fidelity(const TetMesh& mesh, const LevelSet3& f, Mesh3dReport& r) {
    double fv = 0, fc = 0;
    std::vector<std::uint8_t> seen(mesh.vertices.size(), 0);
    for (std::size_t i = 0; i < mesh.boundary.size(); ++i) {
        if (mesh.boundary_tag[i] != boundary_level_set) continue;
        Point3 c{0, 0, 0};
        for (std::int32_t v : mesh.boundary[i]) {
            const Point3& p = mesh.vertices[static_cast<std::size_t>(v)];
            if (!seen[static_cast<std::size_t>(v)]) seen[static_cast<std::size_t>(v)] = 1, fv = std::max(fv, std::abs(f.value(p.x, p.y, p.z)));
            c = {c.x + p.x / 3, c.y + p.y / 3, c.z + p.z / 3};
        }
        fc = std::max(fc, std::abs(f.value(c.x, c.y, c.z)));
    }
    r.boundary_vertex_f_max = fv, r.boundary_centroid_f_max = fc;
}

}  // namespace

std::array<double, 6> dihedral_angles_deg(const std::array<Point3, 4>& p) {
    const TetMeasure m = measure(p);
    std::array<double, 6> a{};
    for (std::size_t k = 0; k < 6; ++k) a[k] = degrees(cosine(m.forms.dot[k], m.forms.nn[k]));
    return a;
}

double radius_ratio(const std::array<Point3, 4>& p) { return measure(p).radius_ratio; }

void measure_quality3(const TetMesh& mesh, const LevelSet3& f, Mesh3dReport& r) {
    Tally all;
    const std::int64_t T = static_cast<std::int64_t>(mesh.tets.size());
#pragma omp parallel
    {
        Tally mine;
#pragma omp for schedule(static) nowait
        for (std::int64_t t = 0; t < T; ++t) {
            const auto& tet = mesh.tets[static_cast<std::size_t>(t)];
            mine.add(measure({mesh.vertices[static_cast<std::size_t>(tet[0])], mesh.vertices[static_cast<std::size_t>(tet[1])],
                              mesh.vertices[static_cast<std::size_t>(tet[2])], mesh.vertices[static_cast<std::size_t>(tet[3])]}));
        }
#pragma omp critical
        all.merge(mine);
    }
    r.min_dihedral_deg = degrees(all.cmax), r.max_dihedral_deg = degrees(all.cmin);
    r.radius_ratio_min = all.rr_min, r.radius_ratio_mean = T ? all.rr_sum / static_cast<double>(T) : 0;
    r.radius_ratio_histogram = all.hist, r.volume = all.volume;
    boundary_fidelity(mesh, f, r);
}

}  // namespace warpmesh
