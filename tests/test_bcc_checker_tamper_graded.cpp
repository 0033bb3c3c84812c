// The independent 3D checker (warpmesh-check-bcc) accepts proofs/bcc_graded.cert
// (the transition templates of graded meshes, issue 48) and rejects tampered
// copies, one test per line kind: header, claim, configs, config, tet (its
// vertices, its order, its witnesses, its count), and lines after the end.
#define BOOST_TEST_MODULE bcc_checker_tamper_graded
#include <boost/test/unit_test.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "checker_run.hpp"

#ifndef WARPMESH_CHECK_BCC_EXE
#error "tests/CMakeLists.txt must define WARPMESH_CHECK_BCC_EXE"
#endif

using namespace warpmesh::testing;

namespace {

std::vector<std::string> cert() { return proof_lines("bcc_graded.cert", 101); }

// The index of the n-th line starting with `prefix`.
std::size_t nth(const std::vector<std::string>& l, const std::string& prefix, int n) {
    for (std::size_t i = 0; i < l.size(); ++i)
        if (l[i].rfind(prefix, 0) == 0 && n-- == 0) return i;
    BOOST_FAIL("no such line");
    return 0;
}

}  // namespace

BOOST_AUTO_TEST_CASE(committed_certificate_accepted_with_the_uniform_floor) {
    const auto l = cert();
    std::string msg;
    BOOST_TEST(exit_status(run_checker(l, "graded", &msg, WARPMESH_CHECK_BCC_EXE)) == 0, msg);
    // No template below the uniform certificates' floor (11.78 deg) nor above their ceiling.
    const auto f = fields(l[line_of(l, "claim")]);
    BOOST_TEST(f[1] == "824633721857/1099511627776");  // cos^2 30 deg = 3/4, plus 2^-30
    BOOST_TEST(f[2] == "549755814913/1099511627776");  // cos^2 135 deg = 1/2, plus 2^-30
}

BOOST_AUTO_TEST_CASE(header_changed) {
    expect_bcc_rejected(with_line(cert(), "warpmesh-bcc-graded", "warpmesh-bcc-graded 2"), "header", "not a BCC certificate");
}

BOOST_AUTO_TEST_CASE(claim_tightened_below_a_template_or_loosened_off_its_witness) {
    auto l = cert();
    auto f = fields(l[line_of(l, "claim")]);
    f[1] = "824633720831/1099511627776";  // just below 3/4: the 30 deg templates fail it
    expect_bcc_rejected(with_line(l, "claim", join_fields(f)), "claim_min", "outside the claim");
    f = fields(l[line_of(l, "claim")]);
    f[2] = "549755813887/1099511627776";  // just below 1/2: the 135 deg templates fail it
    expect_bcc_rejected(with_line(l, "claim", join_fields(f)), "claim_max", "outside the claim");
    f = fields(l[line_of(l, "claim")]);
    f[3] = "1000000000000/1099511627776";  // far above the smallest face angle's cos^2: loose
    expect_bcc_rejected(with_line(l, "claim", join_fields(f)), "claim_face", "not within 0.01 deg");
    expect_bcc_rejected(with_line(l, "claim", "claim 3/4 1/2"), "claim_fields", "bad claim line");
}

BOOST_AUTO_TEST_CASE(configs_or_config_line_changed) {
    expect_bcc_rejected(with_line(cert(), "configs", "configs 16"), "configs", "17 configurations");
    auto l = cert();
    l[nth(l, "config ", 1)] = "config 1 4";  // configuration 1 has one split side: 5 tetrahedra
    expect_bcc_rejected(l, "config_count", "tetrahedron count");
    l = cert();
    l[nth(l, "config ", 2)] = "config 3 5";
    expect_bcc_rejected(l, "config_index", "bad config line");
}

BOOST_AUTO_TEST_CASE(tet_vertices_order_or_count_changed) {
    auto l = cert();
    auto f = fields(l[nth(l, "tet ", 0)]);
    f[7] = "5";  // a ring point moved
    l[nth(l, "tet ", 0)] = join_fields(f);
    expect_bcc_rejected(l, "tet_vertex", "not the fan's");
    l = cert();
    std::swap(l[nth(l, "tet ", 0)], l[nth(l, "tet ", 1)]);
    expect_bcc_rejected(l, "tet_order", "not the fan's");
    l = cert();
    l.erase(l.begin() + static_cast<long>(nth(l, "tet ", 0)));
    expect_bcc_rejected(l, "tet_missing", "not the fan's");
    l = cert();
    l.push_back(l[nth(l, "tet ", 0)]);
    expect_bcc_rejected(l, "tet_extra", "lines after the configurations");
}

BOOST_AUTO_TEST_CASE(tet_witnesses_changed) {
    auto l = cert();
    const std::size_t i = nth(l, "tet ", 0);
    auto f = fields(l[i]);
    BOOST_REQUIRE(f.size() == 16u);
    auto g = f;
    g[13] = "1/5";  // not its smallest angle's cos^2 (1/4)
    l[i] = join_fields(g);
    expect_bcc_rejected(l, "witness_min", "not the tetrahedron's extreme");
    g = f;
    g[14] = "1/2";  // it has no obtuse angle: "-"
    l[i] = join_fields(g);
    expect_bcc_rejected(l, "witness_max", "not the tetrahedron's");
    g = f;
    g.push_back("0");
    l[i] = join_fields(g);
    expect_bcc_rejected(l, "trailing", "trailing fields");
}
