// verify3.cpp — the 3D report's certification and verification, the
// resolution check and the boundary's non-manifold count (mesh3d.hpp:
// Mesh3dReport, nonmanifold_boundary).
//
// Certification.  The certificate of the mesh's face rule (bcc_certified.hpp:
// proofs/bcc.cert for parity, proofs/bcc_delaunay.cert for the Delaunay face
// rule; never the other rule's) claims, at its alphas, for every key with
// output (a − vertex), that every output tetrahedron is positively oriented
// with every dihedral angle θ in the key's own [θmin, θmax], within the
// theorem (the extremes of the keys' claims; bcc_claim), stated as cos²
// thresholds C_min, C_max.  Every output tetrahedron comes from such a key
// (all-zero background tetrahedra are never output), so at the
// certificate's alphas none is uncertified.  With `verify`, stage 5
// (tets3.cpp: check_key, check_claim) checks each background tetrahedron's
// canonical key against the certificate's list and each output tetrahedron,
// once, against its own key's claim with the certificate's own test
// (key_claim_holds; generic_bcc.hpp, "Angle forms"): volume > 0 and, per
// edge, d = n_c·n_d, N = |n_c|²|n_d|²,
//     θ >= θmin  <=>  d <= 0  or  d² <= C_min N,
//     θ <= θmax  <=>  d >= 0  or  d² <= C_max N,
// in double precision on the mesh's coordinates.  Each key's claim implies
// the theorem, so no second pass checks it.
//
// Resolution.  A closed boundary component (faces tagged boundary_level_set,
// joined by shared vertices) of area A enclosing the volume V has the width
// 6V/A (a sphere's diameter, twice a slab's thickness); it is resolved when
// that is at least 4 lattice spacings.  Parts smaller than a cube vanish and
// leave no component: the level set's feature_size() (when known) must be at
// least 2 spacings too.  Otherwise the report warns, naming a spacing that
// resolves the input — never below the input's own resolution (a volume's
// voxel), and not at all at a spacing at or below it (as in 2D,
// resolution.hpp).
#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

#include "mesh3d/uniform3d.hpp"

namespace warpmesh::uniform3d {
namespace {

constexpr double min_cubes_across = 4;

std::size_t find(std::vector<std::int32_t>& parent, std::size_t x) {
    while (static_cast<std::size_t>(parent[x]) != x) x = static_cast<std::size_t>(parent[x] = parent[static_cast<std::size_t>(parent[x])]);
    return x;
}

// The narrowest closed boundary component's width 6V/A (0 without one).
double narrowest_width(const TetMesh& m) {
    std::vector<std::int32_t> parent(m.vertices.size());
    std::iota(parent.begin(), parent.end(), 0);
    for (std::size_t i = 0; i < m.boundary.size(); ++i) {
        if (m.boundary_tag[i] != boundary_level_set) continue;
        const auto& b = m.boundary[i];
        for (int k = 1; k < 3; ++k) parent[find(parent, static_cast<std::size_t>(b[static_cast<std::size_t>(k)]))] = static_cast<std::int32_t>(find(parent, static_cast<std::size_t>(b[0])));
    }
    std::vector<double> area(m.vertices.size(), 0), volume(m.vertices.size(), 0);
    for (std::size_t i = 0; i < m.boundary.size(); ++i) {
        if (m.boundary_tag[i] != boundary_level_set) continue;
        const auto& b = m.boundary[i];
        const Point3 &p = m.vertices[static_cast<std::size_t>(b[0])], &q = m.vertices[static_cast<std::size_t>(b[1])], &r = m.vertices[static_cast<std::size_t>(b[2])];
        const bcc::Vec<double> a{p.x, p.y, p.z}, u{q.x - p.x, q.y - p.y, q.z - p.z}, v{r.x - p.x, r.y - p.y, r.z - p.z};
        const bcc::Vec<double> n = bcc::cross(u, v);
        const std::size_t c = find(parent, static_cast<std::size_t>(b[0]));
        area[c] += 0.5 * std::sqrt(bcc::dot(n, n));
        volume[c] += bcc::dot(a, bcc::cross(bcc::Vec<double>{q.x, q.y, q.z}, bcc::Vec<double>{r.x, r.y, r.z})) / 6;
    }
    double narrowest = 0;
    for (std::size_t c = 0; c < area.size(); ++c)
        if (area[c] > 0) {
            const double w = 6 * std::abs(volume[c]) / area[c];
            narrowest = narrowest == 0 ? w : std::min(narrowest, w);
        }
    return narrowest;
}

// x rounded down to two significant digits.
double two_digits(double x) {
    const double e = std::pow(10.0, std::floor(std::log10(x)) - 1);
    return std::floor(x / e) * e;
}

void check_resolution(const TetMesh& mesh, const LevelSet3& f, double s, Mesh3dReport& r) {
    r.narrowest_width = narrowest_width(mesh);
    double want = 0;
    if (r.narrowest_width > 0 && r.narrowest_width < min_cubes_across * s) want = r.narrowest_width / min_cubes_across;
    const double feature = f.feature_size();
    if (feature > 0 && feature < 2 * s) want = want > 0 ? std::min(want, feature / 2) : feature / 2;
    const double finest = f.resolution();
    if (want <= 0 || s <= finest) return;
    r.suggested_spacing = std::max(two_digits(want), finest);
    std::ostringstream w;
    w << "--spacing " << s << " is too coarse for this input: its narrowest part is about "
      << (r.narrowest_width > 0 ? r.narrowest_width : 2 * feature) << " across (resolved at " << min_cubes_across
      << " cubes across); --spacing " << r.suggested_spacing << " resolves it";
    r.warnings.push_back(w.str());
}

}  // namespace

void finish_report(const TetMesh& mesh, const LevelSet3& f, const Mesh3dOptions& o, bool verified, Mesh3dReport& r) {
    const FaceRule rule = o.face_rule;
    const std::optional<BccClaim> claim = bcc_claim(rule);
    const bool same = certificate_applies(o.alphas_in_use(), rule);
    const std::string cert = bcc_certificate_path(rule);
    r.face_rule = rule;
    r.certified = same;
    r.uncertified_tets = same ? 0 : r.tets;
    r.certified_tets = r.tets - r.uncertified_tets;
    if (same) r.certified_min_deg = claim->min_deg, r.certified_max_deg = claim->max_deg;
    else {
        r.uncertified_reason = claim ? "no certificate for these alphas: " + cert + " (face rule " + face_rule_name(rule) + ") is at other alphas"
                                     : std::string("this build has no certificate of the ") + face_rule_name(rule) + " face rule (" + cert +
                                           "): the angles are measured, not certified";
        r.warnings.push_back(r.uncertified_reason);
    }
    r.verified = same && verified;
    if (o.quality) measure_quality3(mesh, f, r);
    const NonmanifoldBoundary nb = nonmanifold_boundary(mesh);
    r.nonmanifold_boundary_edges = nb.edges, r.nonmanifold_boundary_vertices = nb.vertices;
    check_resolution(mesh, f, o.spacing, r);
}

}  // namespace warpmesh::uniform3d
