// The independent 3D checker (warpmesh-check-bcc) on the counter-example
// certificate proofs/bcc_half.cert (the α = ½ closer-endpoint rule: an exact
// point of key -,0c,0d,0d/0's space where its output tetrahedron is
// inverted).  It accepts the committed file, prints NO BOUND and exits 3
// (verified, no bound: never 0, which means a bound holds); it rejects (exit 1)
// every tampered copy, one test per field: header, line count, alphas (above
// ½, or the default pair, whose box excludes the point), the key (not
// canonical, inconsistent, or a canonical key whose tetrahedron is positive
// there), the point (outside the box, too few or too many values, a point
// where the tetrahedron is positive) and the claimed tetrahedron (not an
// output tetrahedron of the key).
#define BOOST_TEST_MODULE bcc_checker_tamper_half
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

std::vector<std::string> cert() { return read_lines(fs::path(WARPMESH_PROOFS_DIR) / "bcc_half.cert"); }

// The certificate with the line starting with `prefix` replaced by `line`.
std::vector<std::string> with(const std::string& prefix, const std::string& line) { return with_line(cert(), prefix, line); }

}  // namespace

BOOST_AUTO_TEST_CASE(committed_counterexample_accepted) {
    const auto l = cert();
    BOOST_TEST(l[line_of(l, "alphas")] == "alphas 50000/100000 50000/100000");
    BOOST_TEST(l[line_of(l, "key")] == "key -,0c,0d,0d/0");
    std::string msg;
    BOOST_TEST(exit_status(run_checker(l, "half", &msg, WARPMESH_CHECK_BCC_EXE)) == 3, msg);  // issue29_counterexample_exit_3
}

BOOST_AUTO_TEST_CASE(header_or_line_count_changed) {
    expect_bcc_rejected(with("warpmesh-bcc-counterexample", "warpmesh-bcc-counterexample 2"), "header", "not a BCC certificate");
    auto l = cert();
    l.push_back("inverted 0 1 2 3");
    expect_bcc_rejected(l, "lines", "five lines");
}

BOOST_AUTO_TEST_CASE(alphas_above_one_half_or_the_default_pair) {
    expect_bcc_rejected(with("alphas", "alphas 50001/100000 50000/100000"), "alpha_above", "out of (0, 1/2]");
    // At the default pair t <= 0.285 on the long warps: the point t = 1/2 is outside.
    expect_bcc_rejected(with("alphas", "alphas 28500/100000 39850/100000"), "alpha_default", "point outside the parameter box");
    expect_bcc_rejected(with("alphas", "alphas 1/2 50000/100000"), "alpha_den", "one denominator");
}

BOOST_AUTO_TEST_CASE(key_not_canonical_inconsistent_or_positive_there) {
    expect_bcc_rejected(with("key", "key -,0c,0d,0c/0"), "key_noncanonical", "not canonical");
    // k1 did not move (0s): two parameters, the point has three.
    expect_bcc_rejected(with("key", "key -,0s,0d,0d/0"), "key_stay", "too many parameters");
    // A parity bit where the stencil has no quad on a long edge.
    expect_bcc_rejected(with("key", "key -,0b,0d,0d/1"), "key_parity", "not a consistent key");
    // A canonical consistent key whose tetrahedron is positive at t = (1/2, 1/2, 1/2).
    expect_bcc_rejected(with("key", "key -,0c,0c,0d/0"), "key_positive", "positively oriented at the point");
}

BOOST_AUTO_TEST_CASE(point_outside_the_box_miscounted_or_positive) {
    expect_bcc_rejected(with("point", "point 1/2 1/2 9/16"), "point_out", "point outside the parameter box");
    expect_bcc_rejected(with("point", "point -1/16 1/2 1/2"), "point_negative", "point outside the parameter box");
    expect_bcc_rejected(with("point", "point 1/2 1/2"), "point_few", "too few parameters");
    expect_bcc_rejected(with("point", "point 1/2 1/2 1/2 1/2"), "point_many", "too many parameters");
    expect_bcc_rejected(with("point", "point 1/2 1/2 1/3"), "point_nondyadic", "not dyadic");
    // t = 1/4 each: 6·volume = +1 (doubled coordinates), positively oriented.
    expect_bcc_rejected(with("point", "point 1/4 1/4 1/4"), "point_positive", "positively oriented at the point");
}

BOOST_AUTO_TEST_CASE(claimed_tetrahedron_not_an_output_tetrahedron) {
    expect_bcc_rejected(with("inverted", "inverted 0 1 2 4"), "tet_other", "not an output tetrahedron");
    expect_bcc_rejected(with("inverted", "inverted 0 1 2"), "tet_short", "bad inverted line");
    expect_bcc_rejected(with("inverted", "volume 0 1 2 3"), "tet_word", "bad inverted line");
}
