// tet_quality.cpp — quality of tetrahedra: dihedral angles, radius ratio,
// and the quality of a mesh of a level set (tet_checks.hpp).
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
// cross products, and radius_ratio's from the same a × b, a × c, b × c.  It
// takes two tetrahedra at once, one per lane of a two-double vector (SSE2's
// arithmetic and √ are IEEE's, lane by lane: the same bits).  The mesh-wide
// extremes of cos θ need √ and a division only near the running extreme:
// for best > 0 (the largest cos so far), c = d / √N cannot exceed it when
// d <= 0 or d² < best² N (1 − 1e-12) (the margin covers the rounding of d²,
// best² N and of d / √N many times over); the smallest cos likewise for
// best < 0 (may_exceed; for a pair at once, Tally::angles_decided).  The
// extremes are then the same doubles as cos evaluated at every edge.
#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "warpmesh/mesh3d/generic_bcc.hpp"
#include "warpmesh/post/tet_checks.hpp"

namespace warpmesh {
namespace {

// Two tetrahedra at once, one in each lane of a vector of two doubles (GCC
// and Clang vector extensions: SSE2 on x86-64): each lane does the scalar
// code's IEEE operations, so gives its bits.
using D2 = double __attribute__((vector_size(16)));
double root(double x) { return std::sqrt(x); }
#ifdef __SSE2__
D2 root(D2 x) { return _mm_sqrt_pd(x); }  // correctly rounded, like std::sqrt
#else
D2 root(D2 x) { return D2{std::sqrt(x[0]), std::sqrt(x[1])}; }
#endif

template <class T>
bcc::Vec<T> neg(const bcc::Vec<T>& v) { return {-v[0], -v[1], -v[2]}; }
template <class T>
T norm(const bcc::Vec<T>& v) { return root(bcc::dot(v, v)); }

// The angle forms (bcc::dihedral_forms's dot, nn and volume6, in
// tet_edges order) and the radius ratio of one tetrahedron (per lane).
template <class T>
struct Measure {
    bcc::DihedralForms<T> forms;
    T radius_ratio;  // 3 r / R, meaningful where volume6 > 0 (then at most 1 up to rounding)
};
using TetMeasure = Measure<double>;

// 3 r_in / R_circ from the edges a, b, c from p0, their cross products
// ab = a × b, ac = a × c, bc = b × c and det = a · (b × c) (> 0 for a meaningful result).
template <class T>
T radius_ratio_of(const bcc::Vec<T>& a, const bcc::Vec<T>& b, const bcc::Vec<T>& c, const bcc::Vec<T>& ab, const bcc::Vec<T>& ac,
                  const bcc::Vec<T>& bc, T det) {
    const bcc::Vec<T> ca = neg(ac);
    const T aa = bcc::dot(a, a), bb = bcc::dot(b, b), cc = bcc::dot(c, c);
    const bcc::Vec<T> num{aa * bc[0] + bb * ca[0] + cc * ab[0], aa * bc[1] + bb * ca[1] + cc * ab[1], aa * bc[2] + bb * ca[2] + cc * ab[2]};
    const T R = norm(num) / (2 * det);
    const bcc::Vec<T> d = bcc::vsub(c, b), e = bcc::vsub(a, b);
    const T area2 = norm(bc) + norm(ca) + norm(ab) + norm(bcc::cross(d, e));  // twice the face areas
    const T r = det / area2;  // 3V / (area sum) = (det / 2) / (area2 / 2)
    return 3 * r / R;
}

template <class T>
Measure<T> measure(const std::array<bcc::Vec<T>, 4>& p) {
    using V = bcc::Vec<T>;
    const V a = bcc::vsub(p[1], p[0]), b = bcc::vsub(p[2], p[0]), c = bcc::vsub(p[3], p[0]);
    const V u = bcc::vsub(p[2], p[1]), v = bcc::vsub(p[3], p[1]), w = bcc::vsub(p[0], p[1]);
    const V s = bcc::vsub(p[3], p[2]), t = bcc::vsub(p[0], p[2]), r = bcc::vsub(p[1], p[2]);
    const V ab = bcc::cross(a, b), ac = bcc::cross(a, c), bc = bcc::cross(b, c);
    const V uw = bcc::cross(u, w), uv = bcc::cross(u, v), vw = bcc::cross(v, w);
    const V st = bcc::cross(s, t), sr = bcc::cross(s, r);
    const T nab = bcc::dot(ab, ab), nac = bcc::dot(ac, ac), nbc = bcc::dot(bc, bc);
    const T nuw = bcc::dot(uw, uw), nuv = bcc::dot(uv, uv), nvw = bcc::dot(vw, vw);
    Measure<T> m{};
    auto& f = m.forms;
    // tet_edges order: 01, 23, 02, 03, 12, 13.
    f.dot = {bcc::dot(ab, ac), bcc::dot(st, sr), -bcc::dot(ab, bc), bcc::dot(ac, bc), bcc::dot(uw, uv), -bcc::dot(vw, uv)};
    f.nn = {nab * nac, bcc::dot(st, st) * bcc::dot(sr, sr), nab * nbc, nac * nbc, nuw * nuv, nvw * nuv};
    f.volume6 = bcc::dot(a, bc);
    m.radius_ratio = radius_ratio_of(a, b, c, ab, ac, bc, f.volume6);
    return m;
}

// Lane k of a pair's measures, with the radius ratio's final form: 0 unless
// positively oriented, at most 1.
TetMeasure lane(const Measure<D2>& m, int k) {
    TetMeasure out{};
    for (std::size_t e = 0; e < 6; ++e) out.forms.dot[e] = m.forms.dot[e][k], out.forms.nn[e] = m.forms.nn[e][k];
    out.forms.volume6 = m.forms.volume6[k];
    out.radius_ratio = out.forms.volume6 > 0 ? std::min(1.0, m.radius_ratio[k]) : 0;
    return out;
}

TetMeasure measure_one(const std::array<Point3, 4>& p) {
    std::array<bcc::Vec<double>, 4> q{};
    for (std::size_t k = 0; k < 4; ++k) q[k] = {p[k].x, p[k].y, p[k].z};
    TetMeasure m = measure(q);
    m.radius_ratio = m.forms.volume6 > 0 ? std::min(1.0, m.radius_ratio) : 0;
    return m;
}

// cos θ of one edge from its forms (1 for a degenerate face).
double cosine(double dot, double nn) { return nn > 0 ? std::clamp(dot / std::sqrt(nn), -1.0, 1.0) : 1.0; }

// Whether cosine(d, nn) might exceed best; false only when best > 0 and the
// squares decide it (d <= 0 or d² < best² nn (1 − 1e-12)), away from over-
// and underflow.  For "might be below best" ask may_exceed(−d, nn, −best).
bool may_exceed(double d, double nn, double best) {
    const bool decided = best > 1e-3 && nn > 1e-280 && nn < 1e280;
    const bool below = (d <= 0) | (d * d < best * best * nn * (1 - 1e-12));
    return !(decided & below);
}

double degrees(double cosine) { return std::acos(cosine) * 180 / std::numbers::pi; }

// The running sums of the pass (one per thread, then combined).
struct Tally {
    double cmax = -1, cmin = 1, rr_min = 1, rr_sum = 0, volume = 0;
    std::array<std::int64_t, TetQuality::radius_ratio_bins> hist{};

    void add_angles(const bcc::DihedralForms<double>& f) {
        for (std::size_t k = 0; k < 6; ++k) {
            const double d = f.dot[k], nn = f.nn[k];
            if (may_exceed(d, nn, cmax)) cmax = std::max(cmax, cosine(d, nn));
            if (may_exceed(-d, nn, -cmin)) cmin = std::min(cmin, cosine(d, nn));
        }
    }
    void add_size(double q, double volume6) {
        rr_min = std::min(rr_min, q), rr_sum += q;
        ++hist[static_cast<std::size_t>(std::min(TetQuality::radius_ratio_bins - 1, static_cast<int>(q * TetQuality::radius_ratio_bins)))];
        volume += volume6 / 6;
    }
    // Whether may_exceed is false at all twelve checks of both lanes of a
    // pair (the same arithmetic, two lanes at a time): then its angles
    // cannot move the extremes.  ((−d)² = d² and (−c)² = c² exactly.)
    bool angles_decided(const Measure<D2>& m) const {
        if (!(cmax > 1e-3 && -cmin > 1e-3)) return false;
        auto all = ~decltype(D2{} < D2{}){};
        for (std::size_t k = 0; k < 6; ++k) {
            const D2 d = m.forms.dot[k], nn = m.forms.nn[k], dd = d * d;
            all &= (nn > 1e-280) & (nn < 1e280);
            all &= (d <= 0) | (dd < cmax * cmax * nn * (1 - 1e-12));
            all &= (d >= 0) | (dd < cmin * cmin * nn * (1 - 1e-12));
        }
        return all[0] && all[1];
    }
    void merge(const Tally& o) {
        cmax = std::max(cmax, o.cmax), cmin = std::min(cmin, o.cmin), rr_min = std::min(rr_min, o.rr_min);
        rr_sum += o.rr_sum, volume += o.volume;
        for (std::size_t i = 0; i < hist.size(); ++i) hist[i] += o.hist[i];
    }
};

Point3 centroid(const std::array<Point3, 3>& p) {
    Point3 c{0, 0, 0};
    for (const Point3& x : p) c = {c.x + x.x / 3, c.y + x.y / 3, c.z + x.z / 3};
    return c;
}

// Max |f| at the level-set boundary's vertices (each once) and at its faces' centroids.
void boundary_fidelity(const TetMesh& mesh, const LevelSet3& f, TetQuality& r) {
    double fv = 0, fc = 0;
    std::vector<std::uint8_t> seen(mesh.vertices.size(), 0);
    for (std::size_t i = 0; i < mesh.boundary.size(); ++i) {
        if (mesh.boundary_tag[i] != boundary_level_set) continue;
        std::array<Point3, 3> face;
        for (std::size_t k = 0; k < 3; ++k) {
            const std::int32_t v = mesh.boundary[i][k];
            const Point3& p = face[k] = mesh.vertices[static_cast<std::size_t>(v)];
            if (!seen[static_cast<std::size_t>(v)]) seen[static_cast<std::size_t>(v)] = 1, fv = std::max(fv, std::abs(f.value(p.x, p.y, p.z)));
        }
        const Point3 c = centroid(face);
        fc = std::max(fc, std::abs(f.value(c.x, c.y, c.z)));
    }
    r.boundary_vertex_f_max = fv, r.boundary_centroid_f_max = fc;
}

}  // namespace

std::array<double, 6> dihedral_angles_deg(const std::array<Point3, 4>& p) {
    const TetMeasure m = measure_one(p);
    std::array<double, 6> a{};
    for (std::size_t k = 0; k < 6; ++k) a[k] = degrees(cosine(m.forms.dot[k], m.forms.nn[k]));
    return a;
}

double radius_ratio(const std::array<Point3, 4>& p) { return measure_one(p).radius_ratio; }

std::array<double, 2> face_fidelity(const std::array<Point3, 3>& face, const LevelSet3& f) {
    double fv = 0;
    for (const Point3& p : face) fv = std::max(fv, std::abs(f.value(p.x, p.y, p.z)));
    const Point3 c = centroid(face);
    return {fv, std::abs(f.value(c.x, c.y, c.z))};
}

TetQuality measure_quality3(const TetMesh& mesh, const LevelSet3& f) {
    TetQuality r = measure_quality3(mesh);
    boundary_fidelity(mesh, f, r);
    return r;
}

double longest_tet_edge(const TetMesh& mesh) {
    double longest2 = 0;
    const std::int64_t T = static_cast<std::int64_t>(mesh.tets.size());
#pragma omp parallel for schedule(static) reduction(max : longest2)
    for (std::int64_t t = 0; t < T; ++t) {
        const auto& v = mesh.tets[static_cast<std::size_t>(t)];
        for (std::size_t i = 0; i < 4; ++i)
            for (std::size_t j = i + 1; j < 4; ++j) {
                const Point3& a = mesh.vertices[static_cast<std::size_t>(v[i])];
                const Point3& b = mesh.vertices[static_cast<std::size_t>(v[j])];
                const double dx = a.x - b.x, dy = a.y - b.y, dz = a.z - b.z;
                longest2 = std::max(longest2, dx * dx + dy * dy + dz * dz);
            }
    }
    return std::sqrt(longest2);
}

std::vector<RegionMeasure> measure_regions3(const TetMesh& mesh) {
    std::map<std::int32_t, RegionMeasure> by_tag;
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
        std::array<bcc::Vec<double>, 4> q{};
        for (std::size_t k = 0; k < 4; ++k) {
            const Point3& p = mesh.vertices[static_cast<std::size_t>(mesh.tets[t][k])];
            q[k] = {p.x, p.y, p.z};
        }
        RegionMeasure& m = by_tag[mesh.region[t]];
        m.tag = mesh.region[t], ++m.tets;
        m.volume += bcc::dot(bcc::vsub(q[1], q[0]), bcc::cross(bcc::vsub(q[2], q[0]), bcc::vsub(q[3], q[0]))) / 6;
    }
    std::vector<RegionMeasure> out;
    for (const auto& [tag, m] : by_tag) out.push_back(m);
    return out;
}

TetQuality measure_quality3(const TetMesh& mesh) {
    TetQuality r;
    Tally all;
    const std::int64_t T = static_cast<std::int64_t>(mesh.tets.size());
#pragma omp parallel
    {
        Tally mine;
#pragma omp for schedule(static) nowait
        for (std::int64_t pair = 0; pair < (T + 1) / 2; ++pair) {
            // Tetrahedra 2 pair and 2 pair + 1 (the last one twice when T is odd, counted once).
            const auto& t0 = mesh.tets[static_cast<std::size_t>(2 * pair)];
            const auto& t1 = mesh.tets[static_cast<std::size_t>(std::min(2 * pair + 1, T - 1))];
            std::array<bcc::Vec<D2>, 4> q{};
            for (std::size_t k = 0; k < 4; ++k) {
                const Point3 &a = mesh.vertices[static_cast<std::size_t>(t0[k])], &b = mesh.vertices[static_cast<std::size_t>(t1[k])];
                q[k] = {D2{a.x, b.x}, D2{a.y, b.y}, D2{a.z, b.z}};
            }
            const Measure<D2> m = measure(q);
            const bool decided = mine.angles_decided(m);
            for (int k = 0; k < (2 * pair + 1 < T ? 2 : 1); ++k) {
                const TetMeasure one = lane(m, k);
                if (!decided) mine.add_angles(one.forms);
                mine.add_size(one.radius_ratio, one.forms.volume6);
            }
        }
#pragma omp critical
        all.merge(mine);
    }
    r.min_dihedral_deg = degrees(all.cmax), r.max_dihedral_deg = degrees(all.cmin);
    r.radius_ratio_min = all.rr_min, r.radius_ratio_mean = T ? all.rr_sum / static_cast<double>(T) : 0;
    r.radius_ratio_histogram = all.hist, r.volume = all.volume;
    r.boundary_vertex_f_max = r.boundary_centroid_f_max = std::numeric_limits<double>::quiet_NaN();
    return r;
}

}  // namespace warpmesh
