// The independent 3D checker (warpmesh-check-bcc) rejects tampered copies of
// proofs/bcc.cert, one test per field: header, alphas, the global claim, key
// count, key code, root box, a key's claim, its witnesses, split string, and
// garbage.  Each edit makes the check
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

using namespace warpmesh::testing;

namespace {

std::vector<std::string> cert() { return proof_lines("bcc.cert", 1001); }

// The first key line whose split string starts with a split ('1' + side).
std::size_t first_split_key(const std::vector<std::string>& l) {
    for (std::size_t i = 0; i < l.size(); ++i) {
        if (l[i].rfind("key ", 0) != 0) continue;
        const auto f = fields(l[i]);
        if (f.size() > 4 && f.back()[0] != '0') return i;
    }
    BOOST_FAIL("no key with a split");
    return 0;
}

}  // namespace

BOOST_AUTO_TEST_CASE(header_changed) {
    auto l = cert();
    l[0] = "warpmesh-bcc-certificate 3";
    expect_bcc_rejected(l, "header", "not a BCC certificate");
}

BOOST_AUTO_TEST_CASE(alpha_lowered_beyond_the_root_boxes_or_raised_beyond_the_witnesses) {
    auto l = cert();
    auto a = l;
    a[line_of(l, "alphas")] = "alphas 20000/100000 39850/100000";  // the exact boxes grow past the root boxes
    expect_bcc_rejected(a, "alphas", "root box does not contain");
    auto b = l;
    b[line_of(l, "alphas")] = "alphas 30000/100000 39850/100000";  // they shrink: witnesses at the old limit fall outside
    expect_bcc_rejected(b, "alphas", "witness outside");
}

BOOST_AUTO_TEST_CASE(global_claim_not_the_keys_extremes) {
    auto l = cert();
    const std::size_t c = line_of(l, "claim");
    auto f = fields(l[c]);
    // cos^2(61 deg) = 0.23504...: a stronger minimum than any key's claim.
    auto a = l;
    a[c] = "claim 258427994931/1099511627776 " + f[2] + " " + f[3];
    expect_bcc_rejected(a, "claim", "not the keys' extremes");
    auto b = l;  // format 4: the face-angle claim too
    b[c] = "claim " + f[1] + " " + f[2] + " 258427994931/1099511627776";
    expect_bcc_rejected(b, "faceclaim", "not the keys' extremes");
    auto d = l;  // format 3's claim line: no face-angle claim
    d[c] = "claim " + f[1] + " " + f[2];
    expect_bcc_rejected(d, "claim3", "bad claim line");
}

// Field offsets in a key line: "key CODE m" + 2m root ends, then CMIN CMAX
// CFACE, then m + m + m witness coordinates (min, max, face), then SPLITS.
namespace {
struct KeyFields {
    std::vector<std::string> f;
    std::size_t m, cmin, wmin, wmax, wface;
};
KeyFields key_fields(const std::string& line) {
    KeyFields k{fields(line), 0, 0, 0, 0, 0};
    k.m = std::stoul(k.f[2]);
    k.cmin = 3 + 2 * k.m, k.wmin = k.cmin + 3, k.wmax = k.wmin + k.m, k.wface = k.wmax + k.m;
    return k;
}
}  // namespace

BOOST_AUTO_TEST_CASE(key_claim_raised_to_61_degrees) {
    for (int j : {0, 2}) {  // the dihedral and the face-angle minimum
        auto l = cert();
        const std::size_t k = first_split_key(l);
        auto kf = key_fields(l[k]);
        // A minimum of 61 deg: the witness contradicts it (a triangle has an angle <= 60 deg).
        kf.f[kf.cmin + static_cast<std::size_t>(j)] = "258427994931/1099511627776";
        l[k] = join_fields(kf.f);
        expect_bcc_rejected(l, j == 0 ? "keyclaim" : "keyfaceclaim", "contradicts its claim");
    }
}

// The theorem must be tight: loosening the extreme key's claim and the
// global claim together (still true, still the keys' extremes) leaves the
// theorem's witness too far from it.  (A key's own claim may be looser than
// 0.01 / 0.1 deg; the checker counts those.)
BOOST_AUTO_TEST_CASE(theorem_loosened_is_not_tight) {
    for (int j = 0; j < 3; ++j) {
        auto l = cert();
        const std::size_t c = line_of(l, "claim");
        auto cf = fields(l[c]);
        std::size_t k = 0;
        for (std::size_t i = 0; i < l.size() && k == 0; ++i)
            if (l[i].rfind("key ", 0) == 0 && key_fields(l[i]).f[key_fields(l[i]).cmin + static_cast<std::size_t>(j)] == cf[1 + static_cast<std::size_t>(j)]) k = i;
        BOOST_REQUIRE(k > 0);
        auto kf = key_fields(l[k]);
        const std::string loose = j != 1 ? "1099511627775/1099511627776" : "1099511627000/1099511627776";  // 0.05 / 179.9 deg
        kf.f[kf.cmin + static_cast<std::size_t>(j)] = loose;
        cf[1 + static_cast<std::size_t>(j)] = loose;
        l[k] = join_fields(kf.f);
        l[c] = join_fields(cf);
        const char* kind[3] = {"min", "max", "face"};
        expect_bcc_rejected(l, std::string("loose") + kind[j], std::string("theorem's ") + kind[j] + " witness");
    }
}

BOOST_AUTO_TEST_CASE(witness_moved_outside_the_box_or_garbled) {
    auto l = cert();
    const std::size_t k = first_split_key(l);
    auto a = l;
    auto kf = key_fields(a[k]);
    kf.f[kf.wmin] = "16777216/16777216";  // t or u = 1: outside [0, alpha] and [alpha, 1 - alpha]
    a[k] = join_fields(kf.f);
    expect_bcc_rejected(a, "outside", "witness outside");
    auto b = l;
    kf = key_fields(b[k]);
    kf.f[kf.wmax] = "1/3";
    b[k] = join_fields(kf.f);
    expect_bcc_rejected(b, "nondyadic", "not dyadic");
    auto c = l;  // format 4: the face-angle witness
    kf = key_fields(c[k]);
    kf.f[kf.wface] = "16777216/16777216";
    c[k] = join_fields(kf.f);
    expect_bcc_rejected(c, "faceoutside", "witness outside");
}

BOOST_AUTO_TEST_CASE(key_count_and_missing_key) {
    auto l = cert();
    const std::size_t k = line_of(l, "keys");
    auto a = l;
    a[k] = "keys 1";
    expect_bcc_rejected(a, "count", "mismatch");
    auto b = l;
    b.erase(b.begin() + static_cast<long>(k) + 1);
    b[k] = "keys " + std::to_string(std::stol(fields(l[k])[1]) - 1);
    expect_bcc_rejected(b, "missing", "does not list every key");
}

BOOST_AUTO_TEST_CASE(key_code_repeated_or_not_canonical) {
    auto l = cert();
    const std::size_t k = line_of(l, "key ");
    auto a = l;
    a[k + 1] = a[k];
    expect_bcc_rejected(a, "repeated", "unexpected or repeated");
    auto b = l;
    auto f = fields(b[k]);
    f[1] = "+,-,-,-/0";  // an image of -,-,-,+/0 under a symmetry, not the canonical one
    b[k] = join_fields(f);
    expect_bcc_rejected(b, "noncanonical", "unexpected or repeated");
}

BOOST_AUTO_TEST_CASE(root_box_narrowed) {
    auto l = cert();
    const std::size_t k = first_split_key(l);
    auto f = fields(l[k]);
    f[4] = "1/1048576";  // t or u box no longer reaches the exact box's end
    f[3] = "0/1048576";
    l[k] = join_fields(f);
    expect_bcc_rejected(l, "root", "root box does not contain");
}

BOOST_AUTO_TEST_CASE(split_string_edited) {
    auto l = cert();
    const std::size_t k = first_split_key(l);
    auto a = l;
    auto f = fields(a[k]);
    f.back() = "0";  // the root box declared a leaf
    a[k] = join_fields(f);
    expect_bcc_rejected(a, "leaf", "leaf not verified");
    auto b = l;
    f = fields(b[k]);
    f.back() += "0";
    b[k] = join_fields(f);
    expect_bcc_rejected(b, "long", "split string too long");
    auto c = l;
    f = fields(c[k]);
    f.back().pop_back();
    c[k] = join_fields(f);
    expect_bcc_rejected(c, "short", "split string too short");
}

BOOST_AUTO_TEST_CASE(garbage_and_truncation) {
    auto l = cert();
    auto a = l;
    a[line_of(l, "claim")] = "claim 1/3 1/2 1/2";
    expect_bcc_rejected(a, "nondyadic", "not dyadic");
    auto b = l;
    b.resize(b.size() / 2);
    expect_bcc_rejected(b, "truncated", "mismatch");
    auto c = l;
    c[line_of(l, "key ")] = "key -,-,-,x/0 0 0";
    expect_bcc_rejected(c, "code", "bad key code");
}

// Format 3: each split names its side ('1' + j).  A side beyond the key's m
// parameters is malformed; another side tiles the box differently, so some
// leaf no longer verifies.
BOOST_AUTO_TEST_CASE(split_side_out_of_range_or_changed) {
    auto l = cert();
    const std::size_t k = first_split_key(l);
    auto a = l;
    auto kf = key_fields(a[k]);
    BOOST_REQUIRE(kf.m >= 2);
    kf.f.back()[0] = static_cast<char>('1' + kf.m);
    a[k] = join_fields(kf.f);
    expect_bcc_rejected(a, "side", "bad split string");
    auto b = l;
    kf = key_fields(b[k]);
    kf.f.back()[0] = kf.f.back()[0] == '1' ? '2' : '1';
    b[k] = join_fields(kf.f);
    expect_bcc_rejected(b, "otherside", "leaf not verified");
}

// issue29_acute_max_witness: a max witness at which every dihedral angle is
// acute is accepted (the key's max claim, at least 90°, is then counted
// loose); formats 1 and 2 rejected it ("max witness without a right or
// obtuse angle"), so (0.20, 0.35) was not certifiable.  The key -,0b,0b,0c/0
// at t = (1/4, 1/32, 3/16) has largest angle 80.5°.  The witness stage passes,
// so the check goes on to the leaves, where an edited split string rejects.
BOOST_AUTO_TEST_CASE(issue29_acute_max_witness_passes_the_witness_stage) {
    auto l = cert();
    const std::size_t k = line_of(l, "key -,0b,0b,0c/0 ");
    auto kf = key_fields(l[k]);
    BOOST_REQUIRE(kf.m == 3);
    kf.f[kf.wmax] = "4194304/16777216", kf.f[kf.wmax + 1] = "524288/16777216", kf.f[kf.wmax + 2] = "3145728/16777216";
    l[k] = join_fields(kf.f);
    const std::size_t s = first_split_key(l);
    auto f = fields(l[s]);
    f.back() = "0";
    l[s] = join_fields(f);
    expect_bcc_rejected(l, "acute", "leaf not verified");
}
