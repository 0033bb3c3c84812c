// The 3D certified table compiled into the mesher (bcc_certified.hpp, from
// proofs/bcc.cert by cmake/certified_table.cmake): its alphas are the
// certificate's, every key of the enumeration has a claim, the theorem is
// their extremes, and on stuffed random quadrics (warpmesh/bcc_stuffing.hpp, the
// mesher's contract at the certificate's alphas) every output tetrahedron's
// dihedral angles lie within its background tetrahedron's key's claim,
// looked up through bcc::key_of from global signs and warps.
#define BOOST_TEST_MODULE bcc_certified_table
#include <random>

#include "warpmesh/bcc_stuffing.hpp"
#include "support.hpp"
#include "warpmesh/certify/bcc_certified.hpp"
#include "warpmesh/prove_bcc.hpp"

using namespace warpmesh;
using namespace warpmesh::testing;
using namespace warpmesh::bcc_stuffing;

BOOST_AUTO_TEST_CASE(every_key_has_a_claim_and_the_theorem_is_their_extreme) {
    const auto al = bcc_certified_alphas();
    BOOST_REQUIRE(al.has_value());
    const auto th = bcc_certified_theorem();
    BOOST_REQUIRE(th.has_value());
    double worst_min = 90, worst_max = 90;
    for (const auto& k : bcc_prover::enumerate_keys()) {
        const auto b = bcc_certified_bound(k);
        BOOST_REQUIRE_MESSAGE(b.has_value(), bcc::code_of(k));
        BOOST_TEST(b->min_deg > 0.0);
        BOOST_TEST(b->max_deg < 180.0);
        worst_min = std::min(worst_min, b->min_deg), worst_max = std::max(worst_max, b->max_deg);
    }
    BOOST_TEST(worst_min == th->min_deg);
    BOOST_TEST(worst_max == th->max_deg);
    bcc::Config all_zero;
    all_zero.sign = {0, 0, 0, 0};
    BOOST_TEST(!bcc_certified_bound(all_zero).has_value());  // no output (never output), so not listed
}

BOOST_AUTO_TEST_CASE(stuffed_tetrahedra_lie_within_their_keys_claims) {
    const bcc::Alphas al = *bcc_certified_alphas();
    std::mt19937 rng(33);
    std::uniform_real_distribution<double> U(-1, 1);
    long checked = 0;
    for (int trial = 0; trial < scaled(12); ++trial) {
        const double cx = 3 + U(rng), cy = 3 + U(rng), cz = 3 + U(rng), r = 2 + 0.5 * U(rng), a = 1 + 0.4 * U(rng);
        const Stuffed m = stuff([&](double x, double y, double z) { return a * (x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz) - r * r; },
                                6, 1.0, al);
        for (const StuffedTet& bt : m.background) {
            if (std::all_of(bt.config.sign.begin(), bt.config.sign.end(), [](int s) { return s == 0; })) continue;
            const auto b = bcc_certified_bound(bcc::canonical(bt.config));
            BOOST_REQUIRE_MESSAGE(b.has_value(), bcc::code_of(bcc::canonical(bt.config)));
            for (int k = bt.first; k < bt.first + bt.count; ++k) {
                std::array<bcc::Vec<double>, 4> p{};
                for (int v = 0; v < 4; ++v) p[static_cast<std::size_t>(v)] = m.points[static_cast<std::size_t>(m.tets[static_cast<std::size_t>(k)][static_cast<std::size_t>(v)])];
                for (double x : dihedral_degrees(p)) {
                    BOOST_TEST(x >= b->min_deg - 1e-7);
                    BOOST_TEST(x <= b->max_deg + 1e-7);
                    ++checked;
                }
            }
        }
    }
    BOOST_TEST(checked > 1000);
}

// The junction keys' table (proofs/bcc_junctions.cert): at the parity rule's
// alphas (multi-material meshes use them), every canonical junction key has
// a claim within the one-region floor of proofs/bcc.cert, the theorem is
// their extremes, and the certification reports it at those alphas only.
BOOST_AUTO_TEST_CASE(every_junction_key_has_a_claim_within_the_one_region_floor) {
    const auto al = bcc_junction_certified_alphas();
    BOOST_REQUIRE(al.has_value());
    BOOST_TEST((al->long_num * bcc::parity_alphas.long_den == bcc::parity_alphas.long_num * al->long_den &&
                al->short_num * bcc::parity_alphas.short_den == bcc::parity_alphas.short_num * al->short_den));
    const auto th = bcc_junction_certified_theorem();
    const auto floor = bcc_certified_theorem(FaceRule::parity);
    BOOST_REQUIRE((th.has_value() && floor.has_value()));
    double worst_min = 90, worst_max = 90;
    for (const auto& k : bcc_prover::enumerate_junction_keys()) {
        const auto b = bcc_junction_certified_bound(k);
        BOOST_REQUIRE_MESSAGE(b.has_value(), bcc::code_of(k));
        worst_min = std::min(worst_min, b->min_deg), worst_max = std::max(worst_max, b->max_deg);
    }
    BOOST_TEST(worst_min == th->min_deg);
    BOOST_TEST(worst_max == th->max_deg);
    BOOST_TEST(th->cmin_num <= floor->cmin_num);  // at least the one-region floor: cos² no larger
    BOOST_TEST(th->cmax_num <= floor->cmax_num);
    const BccCertification c = bcc_junction_certification(bcc::parity_alphas);
    BOOST_TEST(c.certified);
    BOOST_TEST(c.min_deg == th->min_deg);
    BOOST_TEST(!bcc_junction_certification(bcc::delaunay_alphas).certified);
    // The key of a junction background tetrahedron as the mesher computes it:
    // letters (0, 0, 1, 2) and parity of background tetrahedron 0 of the cube at the origin.
    const auto p = bcc::background_tet({2, 2, 2}, 0);
    const bcc::JunctionKey k = bcc::junction_key_of(p, {0, 0, 1, 2}, {bcc::stay, bcc::stay, bcc::stay, bcc::stay});
    BOOST_TEST(bcc_junction_certified_bound(k).has_value(), bcc::code_of(k));
}
