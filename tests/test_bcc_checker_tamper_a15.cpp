// The independent 3D checker (warpmesh-check-bcc) on A15 certificates
// ("warpmesh-a15-certificate 1", proofs/README.md "The A15 space") rejects
// (exit 1) every tampered one, one test per new line or kind: the alphas
// line (four thresholds, one per edge class and per end of the mixed edges),
// A15 key codes (class, warp letters of the site's own edges, canonical
// forms), the rational witness coordinates (exact ends of a box), and a
// claim its exact witness contradicts (the class-1 prism's largest angle at
// the exact tie on a corner of its box: the checker's own tie rule).  The
// certificates are made here: the header, the tampered key line first, then
// filler lines to the key count (the checker re-derives the lattice and the
// 15 535 keys, then stops at the first key line); the key lines are the
// prover's for two keys at (0.39, 0.35, 0.35, 0.35) (warpmesh-prove-a15
// --keys 13034,6162 --cap-min-deg 11.645 --cap-max-deg 158), their split
// strings cut to "0" (no leaf is reached).  The committed certificate is
// checked whole by scripts/test.sh (exit 0), which also shows the theorem
// tight only through the exact corner witness.
#define BOOST_TEST_MODULE bcc_checker_tamper_a15
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "checker_run.hpp"

#ifndef WARPMESH_CHECK_BCC_EXE
#error "tests/CMakeLists.txt must define WARPMESH_CHECK_BCC_EXE"
#endif

using namespace warpmesh::testing;

namespace {

const std::string alphas = "alphas 39000/100000 35000/100000 35000/100000 35000/100000";
// 0:0f,0g,+,-, the key of the smallest angle: both chain ends warped out of
// the tetrahedron (t0 along a mixed edge, at most α_B; t1 along a wide one,
// at most α_wide), u of the A–B'' edge in [α_A, 1 − α_B].
const std::string min_key = "0:0f,0g,+,-";
const std::string min_line =
    "key 0:0f,0g,+,- 3 0/1048576 367003/1048576 0/1048576 367003/1048576 367000/1048576 681576/1048576 "
    "1054714996870/1099511627776 593976109800/1099511627776 1044241103739/1099511627776 35000/100000 35000/100000 "
    "65000/100000 35000/100000 35000/100000 65000/100000 0/16777216 35000/100000 65000/100000 0";
// 1:+,-,-,+, the key of the largest angle, witnessed at the exact corner u = 65000/100000.
const std::string max_key = "1:+,-,-,+";
const std::string max_line =
    "key 1:+,-,-,+ 4 367000/1048576 681576/1048576 367000/1048576 681576/1048576 367000/1048576 681576/1048576 "
    "367000/1048576 681576/1048576 1054206243097/1099511627776 908489491475/1099511627776 995132850929/1099511627776 "
    "65000/100000 65000/100000 65000/100000 65000/100000 65000/100000 65000/100000 65000/100000 65000/100000 "
    "65000/100000 35000/100000 35000/100000 35000/100000 0";

// A certificate: the header with `alpha_line`, the key line `first`, then
// filler lines (rejected as bad key lines: only the first is judged).
std::vector<std::string> cert(const std::string& first, const std::string& alpha_line = alphas) {
    std::vector<std::string> l{"warpmesh-a15-certificate 1", alpha_line,
                               "claim 1054714996870/1099511627776 908489491475/1099511627776 1044241103739/1099511627776",
                               "keys 15535", first};
    l.resize(4 + 15535, "key -");
    return l;
}
// Field positions of a key line: "key CODE m" then 2m root ends, 3 claims, 3m witness coordinates.
std::size_t claim_field(std::size_t m, int j) { return 3 + 2 * m + static_cast<std::size_t>(j); }
std::size_t witness_field(std::size_t m, int j, std::size_t i) { return 6 + 2 * m + static_cast<std::size_t>(j) * m + i; }

}  // namespace

// The untampered lines pass as the first key line: the run stops at the
// filler; a key listed twice stops there.
BOOST_AUTO_TEST_CASE(untampered_lines_reach_the_filler) {
    expect_bcc_rejected(cert(min_line), "min", "bad key line");
    expect_bcc_rejected(cert(max_line), "max", "bad key line");
    auto l = cert(min_line);
    l[5] = min_line;
    expect_bcc_rejected(l, "twice", "unexpected or repeated key " + min_key);
}

BOOST_AUTO_TEST_CASE(alphas_line_malformed) {
    const std::string rest = " 35000/100000 35000/100000";
    expect_bcc_rejected(cert(min_line, "alphas 39000/100000" + rest), "three", "bad alphas line");
    expect_bcc_rejected(cert(min_line, "alphas 39000/100000" + rest + " 35/100"), "twodens", "one denominator");
    expect_bcc_rejected(cert(min_line, "alphas 50000/100000 35000/100000" + rest), "half", "alphas out of (0, 1/2)");
    expect_bcc_rejected(cert(min_line, "alphas 39000/100000 0/100000" + rest), "zero", "alphas out of (0, 1/2)");
}

// Each threshold bounds its own parameters: the A end's α the lower end of
// u on a mixed edge from its A end, the B end's α the upper end and the
// warp of a B vertex along a mixed edge, α_wide a warp along a wide edge.
// Moved by 0.01, the key's root box no longer contains its exact box.
BOOST_AUTO_TEST_CASE(alphas_per_end) {
    for (const char* al : {"alphas 39000/100000 35000/100000 34000/100000 35000/100000",
                           "alphas 39000/100000 35000/100000 35000/100000 34000/100000",
                           "alphas 39000/100000 35000/100000 35000/100000 36000/100000",
                           "alphas 39000/100000 36000/100000 35000/100000 35000/100000"})
        expect_bcc_rejected(cert(min_line, al), "ends", "root box does not contain the parameter box of " + min_key);
}

BOOST_AUTO_TEST_CASE(key_codes) {
    const auto f = fields(min_line);
    // The image of 0:0f,0g,+,- under class 0's mirror (chain ends swapped):
    // the same configuration, not canonical.
    auto g = f;
    g[1] = "0:0k,0d,+,-";
    expect_bcc_rejected(cert(join_fields(g)), "image", "unexpected or repeated key 0:0k,0d,+,-");
    // The A vertex of class 1 has 12 edges: letters a..l.
    auto a = f;
    a[1] = "1:0m,-,+,+";
    expect_bcc_rejected(cert(join_fields(a)), "letter", "unexpected or repeated key 1:0m,-,+,+");
    for (const char* bad : {"3:0f,0g,+,-", "0:0f,0g,+", "0:0f,0g,+,-,+", "0;0f,0g,+,-", "0:0f,0g,+,1", "0:-,-,-,-/0"}) {
        auto b = f;
        b[1] = bad;
        expect_bcc_rejected(cert(join_fields(b)), "code", "bad A15 key code");
    }
}

BOOST_AUTO_TEST_CASE(rational_witnesses) {
    const auto f = fields(max_line);
    const std::size_t m = 4;
    BOOST_REQUIRE(f[witness_field(m, 1, 0)] == "65000/100000");  // the max witness: the exact corner
    for (const auto& [x, why] : std::vector<std::pair<std::string, std::string>>{
             {"2/3", "bad witness denominator"}, {"65000/100001", "bad witness denominator"}, {"1/33554432", "bad witness denominator"},
             {"65001/100000", "witness outside the parameter box"}, {"34999/100000", "witness outside the parameter box"},
             {"10905191/16777216", "witness outside the parameter box"}, {"0.65", "bad integer"}}) {
        auto g = f;
        g[witness_field(m, 1, 0)] = x;
        expect_bcc_rejected(cert(join_fields(g)), "witness", why);
    }
    // On the grid, inside the box: accepted (the run reaches the filler).
    auto g = f;
    g[witness_field(m, 1, 0)] = "10905190/16777216";
    expect_bcc_rejected(cert(join_fields(g)), "grid", "bad key line");
}

// The class-1 prism's max claim lowered to 155.28°: its exact corner
// witness, where the checker's own tie rule (face quads by the reference's
// coordinate order, the inside quad against the face (a, b, r0)) gives
// 155.286°, contradicts it; at 155.29° it does not.
BOOST_AUTO_TEST_CASE(claim_below_the_exact_tie) {
    for (const double deg : {155.28, 155.29}) {
        auto f = fields(max_line);
        const double c = std::cos(deg * M_PI / 180);
        f[claim_field(4, 1)] = std::to_string(std::llround(std::ldexp(c * c, 40))) + "/1099511627776";
        expect_bcc_rejected(cert(join_fields(f)), "tie",
                            deg < 155.285 ? "the witness of " + max_key + " contradicts its claim" : "bad key line");
    }
}
