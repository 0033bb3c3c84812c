// The independent 3D checker (warpmesh-check-bcc) on the ceiling certificate
// proofs/bcc_ceiling.cert (for every threshold pair in [0, 1/2]², a
// single-tetrahedron key's point with a dihedral angle below 11.88°).  It
// accepts the committed file, prints NO BOUND and exits 3 (verified, no
// bound: never 0, which means a bound holds); it rejects (exit 1) every
// tampered copy, one test per line kind: the header, the below line (an
// angle whose cos² exceeds C / 2^40, out of range, malformed), the quadtree's
// shape (a box left unsettled, lines after it, too deep) and the witness
// lines (a key that is not canonical or outputs more than one tetrahedron, a
// point outside the box's parameter box or miscounted, a point whose angles
// are all above the ceiling, a witness moved to another box).
#define BOOST_TEST_MODULE bcc_checker_tamper_ceiling
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "checker_run.hpp"

#ifndef WARPMESH_CHECK_BCC_EXE
#error "tests/CMakeLists.txt must define WARPMESH_CHECK_BCC_EXE"
#endif

namespace fs = std::filesystem;
using namespace warpmesh::testing;

namespace {

std::vector<std::string> cert() { return read_lines(fs::path(WARPMESH_PROOFS_DIR) / "bcc_ceiling.cert"); }

// The certificate with the line starting with `prefix` replaced by `line`.
std::vector<std::string> with(const std::string& prefix, const std::string& line) { return with_line(cert(), prefix, line); }

// The first witness line of the committed certificate: the box [0, 1/8]²
// (after two splits), key -,0c,0m,+/0 at t = (0, 0), u = 1/8.
const std::string first_witness = "witness -,0c,0m,+/0 0 0 1/8";

}  // namespace

BOOST_AUTO_TEST_CASE(committed_ceiling_accepted) {
    const auto l = cert();
    BOOST_TEST(l[line_of(l, "below")] == "below 297/25 1052915284546");
    BOOST_TEST(l[line_of(l, "witness")] == first_witness);
    std::string msg;
    BOOST_TEST(exit_status(run_checker(l, "ceiling", &msg, WARPMESH_CHECK_BCC_EXE)) == 3, msg);
}

BOOST_AUTO_TEST_CASE(header_changed) {
    expect_bcc_rejected(with("warpmesh-bcc-ceiling", "warpmesh-bcc-ceiling 2"), "header", "not a BCC certificate");
}

BOOST_AUTO_TEST_CASE(below_line_claims_more_than_its_threshold_or_is_malformed) {
    // 11.5°: cos² 11.5° = 0.96032 > C / 2^40 = 0.95762, so C does not bound it.
    expect_bcc_rejected(with("below", "below 23/2 1052915284546"), "below_angle", "not >= cos^2");
    // C one less than cos²(11.88°) rounded: below the rational bound of cos².
    expect_bcc_rejected(with("below", "below 297/25 1052900000000"), "below_c", "not >= cos^2");
    expect_bcc_rejected(with("below", "below 61 1052915284546"), "below_range", "out of (0, 60]");
    expect_bcc_rejected(with("below", "below 297/25 1099511627776"), "below_c_one", "C out of (0, 2^40)");
    expect_bcc_rejected(with("below", "above 297/25 1052915284546"), "below_word", "bad below line");
}

BOOST_AUTO_TEST_CASE(a_stronger_claim_fails_at_a_witness) {
    // 11.8°: C = 2^40 cos²(11.8°) rounded up passes the below check, but some
    // witness (made for 11.88°) has no angle below 11.8°.
    expect_bcc_rejected(with("below", "below 59/5 1053531856623"), "below_stronger", "below the ceiling at the point");
}

BOOST_AUTO_TEST_CASE(quadtree_unsettled_extended_or_too_deep) {
    auto l = cert();
    l.pop_back();
    expect_bcc_rejected(l, "short", "ends before every box is settled");
    l = cert();
    l.push_back(first_witness);
    expect_bcc_rejected(l, "long", "lines after the quadtree");
    l = cert();
    const std::size_t at = line_of(l, "witness");
    l.erase(l.begin() + static_cast<long>(at));
    l.insert(l.begin() + static_cast<long>(at), 40, "split");
    expect_bcc_rejected(l, "deep", "deeper than 39");
    expect_bcc_rejected(with("witness", "witnes -,0c,0m,+/0 0 0 1/8"), "word", "bad quadtree line");
}

BOOST_AUTO_TEST_CASE(witness_key_not_canonical_or_not_one_tetrahedron) {
    // The first witness's key with c0 and c1 exchanged (the symmetry z -> −z).
    expect_bcc_rejected(with("witness", "witness -,0c,+,0i/0 0 0 1/8"), "key_noncanonical", "not canonical");
    // A pyramid (two output tetrahedra: its quad would need a face rule).
    expect_bcc_rejected(with("witness", "witness -,0h,+,-/0 0 1/8 1/8"), "key_pyramid", "more than one output tetrahedron");
}

BOOST_AUTO_TEST_CASE(witness_point_outside_its_box_or_miscounted) {
    // u = 1/16 < α_short = 1/8 at the box's high end: outside.
    expect_bcc_rejected(with("witness", "witness -,0c,0m,+/0 0 0 1/16"), "cut_low", "point outside the parameter box");
    // t = 1/16 > α_long = 0 at the box's low end: outside.
    expect_bcc_rejected(with("witness", "witness -,0c,0m,+/0 1/16 0 1/8"), "warp_high", "point outside the parameter box");
    expect_bcc_rejected(with("witness", "witness -,0c,0m,+/0 0 0"), "few", "too few parameters");
    expect_bcc_rejected(with("witness", "witness -,0c,0m,+/0 0 0 1/8 0"), "many", "too many parameters");
    expect_bcc_rejected(with("witness", "witness -,0c,0m,+/0 0 0 1/7"), "nondyadic", "not dyadic");
}

BOOST_AUTO_TEST_CASE(witness_above_the_ceiling_or_moved_to_another_box) {
    // Key -,+,0i,0m/0 with no warps and its cut point at the middle of k0 k1
    // (inside the box [0, 1/8]²'s parameter box): no angle below 11.88°.
    expect_bcc_rejected(with("witness", "witness -,+,0i,0m/0 0 0 1/2"), "above", "below the ceiling at the point");
    // The last witness (the box at (1/2, 1/2)) as the first box's: its
    // warps exceed the first box's thresholds.
    auto l = cert();
    l[line_of(l, "witness")] = l.back();
    expect_bcc_rejected(l, "moved", "point outside the parameter box");
}
