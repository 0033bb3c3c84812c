// The independent 3D checker (warpmesh-check-bcc) rejects tampered copies of
// proofs/bcc.cert, one test per line kind: header, alphas, claim, key count,
// key code, root box, split string, and garbage.  Each edit makes the check
// fail at or before the key it touches (the first keys), so the tests are
// fast; the untampered certificate is checked whole by scripts/test.sh.
#define BOOST_TEST_MODULE bcc_checker_tamper
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

std::vector<std::string> cert() {
    auto l = read_lines(fs::path(WARPMESH_PROOFS_DIR) / "bcc.cert");
    BOOST_REQUIRE(l.size() > 1000);
    return l;
}

// Index of the line starting with `prefix`.
std::size_t line_of(const std::vector<std::string>& l, const std::string& prefix) {
    for (std::size_t i = 0; i < l.size(); ++i)
        if (l[i].rfind(prefix, 0) == 0) return i;
    BOOST_FAIL("no line " + prefix);
    return 0;
}

// The first key line whose split string starts with a split.
std::size_t first_split_key(const std::vector<std::string>& l) {
    for (std::size_t i = 0; i < l.size(); ++i) {
        if (l[i].rfind("key ", 0) != 0) continue;
        const auto f = fields(l[i]);
        if (f.size() > 4 && f.back()[0] == '1') return i;
    }
    BOOST_FAIL("no key with a split");
    return 0;
}

void expect_rejected(const std::vector<std::string>& l, const std::string& name, const std::string& why) {
    std::string msg;
    BOOST_TEST(run_checker(l, name, &msg, WARPMESH_CHECK_BCC_EXE) != 0);
    BOOST_TEST(msg.find(why) != std::string::npos, name << ": " << msg);
}

std::string join(const std::vector<std::string>& f) {
    std::string s;
    for (const auto& w : f) s += (s.empty() ? "" : " ") + w;
    return s;
}

}  // namespace

BOOST_AUTO_TEST_CASE(header_changed) {
    auto l = cert();
    l[0] = "warpmesh-bcc-certificate 2";
    expect_rejected(l, "header", "not a BCC certificate");
}

BOOST_AUTO_TEST_CASE(alpha_raised_outside_the_root_boxes) {
    auto l = cert();
    l[line_of(l, "alphas")] = "alphas 26000/100000 41189/100000";
    expect_rejected(l, "alphas", "root box does not contain");
}

BOOST_AUTO_TEST_CASE(claim_raised_to_61_degrees) {
    auto l = cert();
    // cos^2(61 deg) = 0.23504...: the whole background tetrahedron (60 and 90 deg) fails.
    l[line_of(l, "claim")] = "claim 258427994931/1099511627776 " + fields(l[line_of(l, "claim")])[2];
    expect_rejected(l, "claim", "leaf not verified");
}

BOOST_AUTO_TEST_CASE(key_count_and_missing_key) {
    auto l = cert();
    const std::size_t k = line_of(l, "keys");
    auto a = l;
    a[k] = "keys 1";
    expect_rejected(a, "count", "mismatch");
    auto b = l;
    b.erase(b.begin() + static_cast<long>(k) + 1);
    b[k] = "keys " + std::to_string(std::stol(fields(l[k])[1]) - 1);
    expect_rejected(b, "missing", "does not list every key");
}

BOOST_AUTO_TEST_CASE(key_code_repeated_or_not_canonical) {
    auto l = cert();
    const std::size_t k = line_of(l, "key ");
    auto a = l;
    a[k + 1] = a[k];
    expect_rejected(a, "repeated", "unexpected or repeated");
    auto b = l;
    auto f = fields(b[k]);
    f[1] = "+,-,-,-/0";  // an image of -,-,-,+/0 under a symmetry, not the canonical one
    b[k] = join(f);
    expect_rejected(b, "noncanonical", "unexpected or repeated");
}

BOOST_AUTO_TEST_CASE(root_box_narrowed) {
    auto l = cert();
    const std::size_t k = first_split_key(l);
    auto f = fields(l[k]);
    f[4] = "1/1048576";  // t or u box no longer reaches the exact box's end
    f[3] = "0/1048576";
    l[k] = join(f);
    expect_rejected(l, "root", "root box does not contain");
}

BOOST_AUTO_TEST_CASE(split_string_edited) {
    auto l = cert();
    const std::size_t k = first_split_key(l);
    auto a = l;
    auto f = fields(a[k]);
    f.back()[0] = '0';  // the root box declared a leaf
    a[k] = join(f);
    std::string msg;
    BOOST_TEST(run_checker(a, "leaf", &msg, WARPMESH_CHECK_BCC_EXE) != 0);
    auto b = l;
    f = fields(b[k]);
    f.back() += "0";
    b[k] = join(f);
    expect_rejected(b, "long", "split string too long");
    auto c = l;
    f = fields(c[k]);
    f.back().pop_back();
    c[k] = join(f);
    expect_rejected(c, "short", "split string too short");
}

BOOST_AUTO_TEST_CASE(garbage_and_truncation) {
    auto l = cert();
    auto a = l;
    a[line_of(l, "claim")] = "claim 1/3 1/2";
    expect_rejected(a, "nondyadic", "not dyadic");
    auto b = l;
    b.resize(b.size() / 2);
    expect_rejected(b, "truncated", "mismatch");
    auto c = l;
    c[line_of(l, "key ")] = "key -,-,-,x/0 0 0";
    expect_rejected(c, "code", "bad key code");
}
