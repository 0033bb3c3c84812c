// The independent checker and the rhombic lattice's certificates
// (proofs/rhombic_maxmin.cert, proofs/rhombic_separating.cert): format 4's
// `metric` line is required, unknown metrics are refused, a rhombic
// certificate read in the square metric (or a square one in the rhombic
// metric) is rejected, and the rhombic claims and leaves are checked in the
// rhombic forms.  Most tests cut the certificate after a few keys (the
// checker stops at the first error, so the runs stay cheap).
#define BOOST_TEST_MODULE checker_tamper_rhombic
#include <boost/test/unit_test.hpp>

#include <boost/multiprecision/cpp_int.hpp>

#include "checker_run.hpp"

#include <sys/wait.h>

#include <filesystem>
#include <string>
#include <vector>

namespace fs = std::filesystem;
using warpmesh::testing::fields;
using warpmesh::testing::line_of;
using warpmesh::testing::read_lines;
using Q = boost::multiprecision::cpp_rational;

namespace {

std::vector<std::string> cert(const char* name = "rhombic_maxmin.cert") {
    auto out = read_lines(fs::path(WARPMESH_PROOFS_DIR) / name);
    BOOST_REQUIRE(out.size() > 100);
    return out;
}

std::string rejected(const std::vector<std::string>& lines, const std::string& name) {
    std::string msg;
    const int rc = warpmesh::testing::run_checker(lines, name, &msg);
    BOOST_TEST(WEXITSTATUS(rc) == 1);  // 1: rejected (not 2 usage, 3 no bound)
    return msg;
}

bool has(const std::string& msg, const char* what) { return msg.find(what) != std::string::npos; }

// The first key at or after line `from` with a leaf tagged `tag`: (key line, leaf line).
std::pair<std::size_t, std::size_t> find_leaf(const std::vector<std::string>& l, char tag, std::size_t from = 0) {
    std::size_t key = 0;
    for (std::size_t i = from; i < l.size(); ++i) {
        if (l[i].rfind("key ", 0) == 0) key = fields(l[i]).size() == 8 ? i : 0;
        else if (key && !l[i].empty() && l[i][0] == tag && l[i][1] == ' ') return {key, i};
    }
    BOOST_FAIL("no leaf " << tag);
    return {0, 0};
}

// The first lines of a certificate: enough for what the checker reads
// before the keys (header, claims, witnesses), so that tests of those stay
// cheap (also under the sanitizers).
std::vector<std::string> head(std::vector<std::string> l) {
    l.resize(300);
    return l;
}

// The certificate up to the end of the key whose line is at `key`.
std::vector<std::string> cut_after(const std::vector<std::string>& l, std::size_t key) {
    std::size_t end = key + 1;
    while (end < l.size() && l[end].rfind("key ", 0) != 0 && l[end] != "end") ++end;
    return {l.begin(), l.begin() + static_cast<long>(end)};
}

}  // namespace

BOOST_AUTO_TEST_CASE(rhombic_certificates_are_format_4_with_their_metric) {
    for (const char* name : {"rhombic_maxmin.cert", "rhombic_separating.cert"}) {
        const auto l = cert(name);
        BOOST_TEST(l[0] == "warpmesh-certificate 4");
        BOOST_TEST(l[line_of(l, "metric ")] == "metric rhombic");
        BOOST_TEST(line_of(l, "metric ") < line_of(l, "rule "));
    }
}

BOOST_AUTO_TEST_CASE(metric_line_missing) {
    auto l = head(cert());
    l.erase(l.begin() + static_cast<long>(line_of(l, "metric ")));
    BOOST_TEST(has(rejected(l, "no_metric"), "expected 'metric' line"));
}

BOOST_AUTO_TEST_CASE(unknown_metric_refused) {
    auto l = head(cert());
    l[line_of(l, "metric ")] = "metric hexagonal";
    BOOST_TEST(has(rejected(l, "unknown_metric"), "unknown metric 'hexagonal'"));
}

BOOST_AUTO_TEST_CASE(unknown_version_refused) {
    // A checker of format 3 refuses format 4 by its version; this one refuses 5.
    auto l = head(cert());
    l[0] = "warpmesh-certificate 5";
    BOOST_TEST(has(rejected(l, "version_5"), "unknown version"));
}

BOOST_AUTO_TEST_CASE(format_3_has_no_metric_line) {
    // Format 3 is the square lattice: a metric line there is not read as one.
    auto l = head(cert());
    l[0] = "warpmesh-certificate 3";
    BOOST_TEST(has(rejected(l, "version_3_metric"), "expected 'rule' line"));
}

BOOST_AUTO_TEST_CASE(rhombic_certificate_read_in_the_square_metric) {
    // Its witnesses' values are ratios of the rhombic forms: in the square
    // metric the exact evaluation differs.
    for (const char* name : {"rhombic_maxmin.cert", "rhombic_separating.cert"}) {
        auto l = head(cert(name));
        l[line_of(l, "metric ")] = "metric square";
        BOOST_TEST(has(rejected(l, "as_square"), "witness value differs from exact evaluation"));
    }
}

BOOST_AUTO_TEST_CASE(square_certificate_read_in_the_rhombic_metric) {
    auto l = head(cert("separating.cert"));
    BOOST_REQUIRE(l[0] == "warpmesh-certificate 3");
    l[0] = "warpmesh-certificate 4";
    l.insert(l.begin() + 1, "metric rhombic");
    BOOST_TEST(has(rejected(l, "square_as_rhombic"), "witness value differs from exact evaluation"));
}

BOOST_AUTO_TEST_CASE(rhombic_metric_has_no_fan_rule) {
    auto l = head(cert("rhombic_separating.cert"));
    l[line_of(l, "rule ")] = "rule fan";
    BOOST_TEST(has(rejected(l, "rhombic_fan"), "the rhombic metric has the maxmin and separating rules"));
}

BOOST_AUTO_TEST_CASE(rhombic_claim_raised_by_1e_9) {
    // The theorem U's min-angle bound r <= q lowered by 1e-9 no longer follows
    // from the key claims.
    auto l = cert();
    const std::size_t c = line_of(l, "claim U ");
    const auto f = fields(l[c]);
    l[c] = "claim U " + (Q(f[2]) - Q(1, 1000000000)).str() + " " + f[3];
    BOOST_TEST(has(rejected(l, "claim_raised"), "does not follow from the key claims"));
}

BOOST_AUTO_TEST_CASE(rhombic_leaf_with_the_other_diagonal) {
    // A decided leaf of the max-min rule relabelled with the other diagonal:
    // in the rhombic forms the rule does not take it there.
    const auto l = cert();
    const auto [key, leaf] = find_leaf(l, 'B', line_of(l, "keys "));
    auto t = cut_after(l, key);
    t[leaf][0] = 'A';
    const std::string msg = rejected(t, "other_diagonal");
    BOOST_TEST((has(msg, " leaf ") && !has(msg, "truncated")), msg);
}

BOOST_AUTO_TEST_CASE(rhombic_key_claim_below_its_witness) {
    // A key's min-angle claim lowered below its exact rhombic witness.
    auto l = cert("rhombic_separating.cert");
    const auto [key, leaf] = find_leaf(l, 'A', line_of(l, "keys "));
    auto t = cut_after(l, key);
    auto f = fields(t[key]);
    BOOST_REQUIRE(t[key + 1].rfind("wmin ", 0) == 0);
    f[5] = (Q(fields(t[key + 1]).back()) - Q(1, 1000000000)).str();
    std::string s;
    for (const auto& x : f) s += (s.empty() ? "" : " ") + x;
    t[key] = s;
    const std::string msg = rejected(t, "key_below_witness");
    BOOST_TEST((has(msg, "claim contradicted by its witness") || has(msg, "does not follow")), msg);
}
