// Multi-material 3D meshes check their junction tetrahedra (three or four
// materials in a background tetrahedron) against the claims of their
// canonical junction keys (proofs/bcc_junctions.cert, compiled in:
// bcc_key_claims(parity).junction_claim; materials3.cpp, verify_junction):
// the certificate's claims hold on meshes of meeting shapes and random label
// volumes, every junction tetrahedron's key has a claim, and a violated or
// missing claim is reported (the check is not vacuous).
#define BOOST_TEST_MODULE mesh3d_junction_claims
#include <cmath>
#include <random>
#include <stdexcept>

#include "support.hpp"
#include "warpmesh/certify/bcc_certified.hpp"
#include "warpmesh/io/volume.hpp"
#include "warpmesh/levelset/materials3.hpp"
#include "warpmesh/mesh3d/mesh3d.hpp"
#include "warpmesh/post/tet_checks.hpp"

using namespace warpmesh;

namespace {

BccOptions options(const BccKeyClaims* claims) {
    BccOptions o;
    o.face_rule = FaceRule::parity;
    o.alphas = face_rule_alphas(FaceRule::parity);
    o.verify = claims;
    return o;
}

const MaterialField3& meeting_shapes() {
    static const auto f = parse_material_shapes3(
        "1=box:-1,-1,-1,0.03,1,1;2=box:0.03,-1,-1,1,0.013,1;3=box:0.03,0.013,-1,1,1,1;4=sphere:0.03,0.013,0.2,0.4");
    return *f;
}

// The message of the logic_error mesh_bcc_materials throws, or "" if none.
std::string verify_error(const MaterialField3& f, const Lattice3& L, const BccKeyClaims& claims) {
    try {
        (void)mesh_bcc_materials(f, L, options(&claims), false);
    } catch (const std::logic_error& e) {
        return e.what();
    }
    return "";
}

}  // namespace

BOOST_AUTO_TEST_CASE(junction_tetrahedra_meet_their_keys_claims) {
    const BccKeyClaims claims = bcc_key_claims(FaceRule::parity);
    BOOST_REQUIRE(static_cast<bool>(claims.junction_claim));  // the build has proofs/bcc_junctions.cert
    const Lattice3 L = lattice3_for(meeting_shapes().bounds(), 0.1, meeting_shapes().describe());
    const BccMesh m = mesh_bcc_materials(meeting_shapes(), L, options(&claims), false);  // throws on a violation
    BOOST_TEST(m.verified);
    BOOST_TEST(m.junction_tets > 0);
    // Every tetrahedron, junctions included, within the junction theorem's and
    // the one-region certificate's bounds (the junction theorem lies inside).
    const BccKeyBound j = bcc_junction_certified_theorem().value();
    const BccClaim c = bcc_claim(FaceRule::parity).value();
    BOOST_TEST(j.min_deg >= c.min_deg);
    BOOST_TEST(j.max_deg <= c.max_deg);
    double lo = 180, hi = 0;
    for (const auto& t : m.mesh.tets) {
        std::array<Point3, 4> p{};
        for (std::size_t k = 0; k < 4; ++k) p[k] = m.mesh.vertices[static_cast<std::size_t>(t[k])];
        for (const double a : dihedral_angles_deg(p)) lo = std::min(lo, a), hi = std::max(hi, a);
    }
    BOOST_TEST(lo >= c.min_deg);
    BOOST_TEST(hi <= c.max_deg);
}

BOOST_AUTO_TEST_CASE(random_label_volumes_meet_the_junction_claims) {
    const BccKeyClaims claims = bcc_key_claims(FaceRule::parity);
    std::mt19937 rng(470);
    long junctions = 0;
    for (int trial = 0; trial < 6; ++trial) {
        Volume v;
        const int n = 12;
        v.dims = {n, n, n};
        v.values.resize(static_cast<std::size_t>(n) * n * n);
        // Blobs of four labels around random centres: many triple lines and quadruple points.
        std::array<std::array<double, 3>, 6> c{};
        for (auto& x : c)
            for (double& y : x) y = std::uniform_real_distribution<double>(0, n)(rng);
        for (int k = 0; k < n; ++k)
            for (int jj = 0; jj < n; ++jj)
                for (int i = 0; i < n; ++i) {
                    std::size_t best = 0;
                    double bd = 1e30;
                    for (std::size_t b = 0; b < c.size(); ++b) {
                        const double d = (i - c[b][0]) * (i - c[b][0]) + (jj - c[b][1]) * (jj - c[b][1]) + (k - c[b][2]) * (k - c[b][2]);
                        if (d < bd) bd = d, best = b;
                    }
                    v.values[static_cast<std::size_t>(i + n * (jj + n * k))] = static_cast<double>(1 + best % 4);
                }
        const auto f = make_volume_materials3(v, "all");
        const Lattice3 L = lattice3_for(f->bounds(), trial % 2 ? 0.8 : 1.1, f->describe());
        const BccMesh m = mesh_bcc_materials(*f, L, options(&claims), trial % 3 == 0);  // throws on a violation
        BOOST_TEST(m.verified);
        junctions += m.junction_tets;
    }
    BOOST_TEST(junctions > 0);
}

// The check is not vacuous: a claim no tetrahedron meets (every dihedral
// angle >= 89.9 deg) is reported as violated, a missing claim as missing.
BOOST_AUTO_TEST_CASE(violated_or_missing_junction_claims_are_reported) {
    const Lattice3 L = lattice3_for(meeting_shapes().bounds(), 0.1, meeting_shapes().describe());
    BccKeyClaims strict = bcc_key_claims(FaceRule::parity);
    const double c = std::cos(89.9 * M_PI / 180);
    strict.junction_claim = [c](const bcc::JunctionKey&) { return std::optional<BccKeyClaim>(BccKeyClaim{c * c, c * c}); };
    const std::string violated = verify_error(meeting_shapes(), L, strict);
    BOOST_TEST(violated.find("verify: 0 keys without a claim") != std::string::npos, violated);
    BOOST_TEST(violated.find(", 0 tetrahedra outside") == std::string::npos, violated);
    BccKeyClaims none = bcc_key_claims(FaceRule::parity);
    none.junction_claim = [](const bcc::JunctionKey&) { return std::optional<BccKeyClaim>(); };
    const std::string missing = verify_error(meeting_shapes(), L, none);
    BOOST_TEST(!missing.empty());
    BOOST_TEST(missing.find("verify: 0 keys without a claim") == std::string::npos, missing);
}
