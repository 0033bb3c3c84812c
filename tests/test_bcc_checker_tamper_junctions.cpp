// The independent 3D checker (warpmesh-check-bcc) rejects tampered copies of
// the junction certificate proofs/bcc_junctions.cert, one test per line kind
// and field: the header, the alphas, the global claim, the key count, a key
// line (its code: repeated, not canonical, malformed; its claim: beyond a
// witness, loosened so the theorem is no longer tight, not the extremes; a
// key removed), a face line (its face index, parameter count, root box,
// witnesses, split string: a leaf box changed).  Every edit touches the
// first key, which the checker verifies first, so the tests are fast; the
// untampered certificate is checked whole by scripts/test.sh.
#define BOOST_TEST_MODULE bcc_checker_tamper_junctions
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

std::vector<std::string> cert() { return proof_lines("bcc_junctions.cert", 21); }

// The first face line whose split string starts with a split, and its fields:
// "face F m" + 2m root ends, then m + m + m witness coordinates (min, max,
// face), then SPLITS.
struct FaceFields {
    std::size_t line = 0, m = 0, wmin = 0, wmax = 0, wface = 0;
    std::vector<std::string> f;
};
FaceFields first_split_face(const std::vector<std::string>& l) {
    for (std::size_t i = 0; i < l.size(); ++i) {
        if (l[i].rfind("face ", 0) != 0) continue;
        FaceFields ff;
        ff.f = fields(l[i]);
        if (ff.f.back()[0] == '0') continue;
        ff.line = i, ff.m = std::stoul(ff.f[2]);
        ff.wmin = 3 + 2 * ff.m, ff.wmax = ff.wmin + ff.m, ff.wface = ff.wmax + ff.m;
        return ff;
    }
    BOOST_FAIL("no face with a split");
    return {};
}

}  // namespace

BOOST_AUTO_TEST_CASE(committed_certificate_has_every_line_kind) {
    const auto l = cert();
    BOOST_TEST(l[0] == "warpmesh-bcc-junctions 1");
    BOOST_TEST(l[line_of(l, "alphas")] == "alphas 28500/100000 39850/100000");  // bcc::parity_alphas
    const std::size_t k = line_of(l, "key ");
    BOOST_TEST(fields(l[k]).size() == 5u);
    for (int f = 0; f < 4; ++f) BOOST_TEST(l[k + 1 + static_cast<std::size_t>(f)].rfind("face " + std::to_string(f) + " ", 0) == 0u);
}

BOOST_AUTO_TEST_CASE(header_alphas_and_counts) {
    auto a = cert();
    a[0] = "warpmesh-bcc-junctions 2";
    expect_bcc_rejected(a, "jheader", "not a BCC certificate");
    auto b = cert();
    b[line_of(b, "alphas")] = "alphas 20000/100000 39850/100000";  // the exact boxes grow past the root boxes
    expect_bcc_rejected(b, "jalphas", "root box does not contain");
    auto c = cert();
    c[line_of(c, "alphas")] = "alphas 50000/100000 39850/100000";
    expect_bcc_rejected(c, "jalphahalf", "out of (0, 1/2)");
    auto d = cert();
    d[line_of(d, "keys")] = "keys 11";
    expect_bcc_rejected(d, "jcount", "mismatch");
}

// A key removed with its four face lines (and the count lowered to match).
BOOST_AUTO_TEST_CASE(key_removed) {
    auto l = cert();
    const std::size_t k = line_of(l, "key ");
    const std::size_t n = line_of(l, "keys");
    l.erase(l.begin() + static_cast<long>(k), l.begin() + static_cast<long>(k) + 5);
    l[n] = "keys " + std::to_string(std::stol(fields(cert()[n])[1]) - 1);
    expect_bcc_rejected(l, "jremoved", "does not list every junction key");
}

BOOST_AUTO_TEST_CASE(key_code_repeated_not_canonical_or_malformed) {
    const auto l = cert();
    const std::size_t k = line_of(l, "key ");
    const std::size_t k2 = k + 5;  // the second key line
    auto a = l;
    auto f = fields(a[k2]);
    f[1] = fields(a[k])[1];
    a[k2] = join_fields(f);
    expect_bcc_rejected(a, "jrepeated", "unexpected or repeated");
    auto b = l;
    f = fields(b[k]);
    f[1] = "b,b,a,c/0";  // not by first appearance
    b[k] = join_fields(f);
    expect_bcc_rejected(b, "jletters", "unexpected or repeated");
    auto c = l;
    f = fields(c[k]);
    f[1] = "a,b,c,c/0";  // an image of a,a,b,c/0 (the pairs exchanged, re-lettered): consistent, not canonical
    c[k] = join_fields(f);
    expect_bcc_rejected(c, "jnoncanonical", "unexpected or repeated");
    auto d = l;
    f = fields(d[k]);
    f[1] = "a,a,b,0s/0";  // a warp that is no direction
    d[k] = join_fields(f);
    expect_bcc_rejected(d, "jcode", "bad junction key code");
    auto e = l;
    e[k] = "key " + fields(l[k])[1] + " 1/2 1/2";  // a claim missing
    expect_bcc_rejected(e, "jkeyline", "bad junction key line");
}

BOOST_AUTO_TEST_CASE(key_claim_beyond_a_witness_or_not_the_extremes) {
    const auto l = cert();
    const std::size_t k = line_of(l, "key ");
    for (std::size_t j : {2u, 4u}) {  // the dihedral and the face-angle minimum: 61 deg, beyond every witness
        auto a = l;
        auto f = fields(a[k]);
        f[j] = "258427994931/1099511627776";
        a[k] = join_fields(f);
        expect_bcc_rejected(a, "jkeyclaim" + std::to_string(j), "contradicts its key's claim");
    }
    auto b = l;  // the global claim stronger than every key's
    auto c = fields(b[line_of(b, "claim")]);
    c[1] = "258427994931/1099511627776";
    b[line_of(b, "claim")] = join_fields(c);
    expect_bcc_rejected(b, "jclaim", "not the keys' extremes");
}

// Loosening the extreme key's claim and the global claim together (still
// true, still the extremes) leaves the theorem's witness too far from it.
BOOST_AUTO_TEST_CASE(theorem_loosened_is_not_tight) {
    for (std::size_t j = 0; j < 3; ++j) {
        auto l = cert();
        const std::size_t c = line_of(l, "claim");
        auto cf = fields(l[c]);
        std::size_t k = 0;
        for (std::size_t i = 0; i < l.size() && k == 0; ++i)
            if (l[i].rfind("key ", 0) == 0 && fields(l[i])[2 + j] == cf[1 + j]) k = i;
        BOOST_REQUIRE(k > 0);
        auto kf = fields(l[k]);
        const std::string loose = j != 1 ? "1099511627775/1099511627776" : "1099511627000/1099511627776";  // 0.05 / 179.9 deg
        kf[2 + j] = loose, cf[1 + j] = loose;
        l[k] = join_fields(kf), l[c] = join_fields(cf);
        const char* kind[3] = {"min", "max", "face"};
        expect_bcc_rejected(l, std::string("jloose") + kind[j], std::string("theorem's ") + kind[j] + " witness");
    }
}

BOOST_AUTO_TEST_CASE(face_index_or_parameter_count_changed) {
    const auto l = cert();
    const std::size_t k = line_of(l, "key ");
    auto a = l;
    std::swap(a[k + 1], a[k + 2]);  // faces 1, 0
    expect_bcc_rejected(a, "jfaceorder", "expected face line 0");
    auto b = l;
    auto f = fields(b[k + 1]);
    f[2] = std::to_string(std::stoul(f[2]) + 1);
    b[k + 1] = join_fields(f);
    expect_bcc_rejected(b, "jfacecount", "wrong parameter count");
    auto c = l;
    c[k + 1] = "fase" + c[k + 1].substr(4);
    expect_bcc_rejected(c, "jfaceword", "expected face line 0");
}

BOOST_AUTO_TEST_CASE(witness_moved_outside_contradicting_or_garbled) {
    const auto l = cert();
    const FaceFields ff = first_split_face(l);
    for (std::size_t w : {ff.wmin, ff.wmax, ff.wface}) {
        auto a = l;
        auto f = ff.f;
        f[w] = "16777216/16777216";  // t or u = 1: outside [0, alpha] and [alpha, 1 - alpha]
        a[ff.line] = join_fields(f);
        expect_bcc_rejected(a, "jwoutside" + std::to_string(w), "witness outside");
    }
    auto b = l;
    auto f = ff.f;
    f[ff.wmax] = "1/3";
    b[ff.line] = join_fields(f);
    expect_bcc_rejected(b, "jwnondyadic", "not dyadic");
    // The key's min claim tightened to its own witness's angle less 2^-40:
    // some face's min witness then contradicts it.
    auto c = l;
    const std::size_t k = line_of(l, "key ");
    auto kf = fields(c[k]);
    const std::string num = kf[2].substr(0, kf[2].find('/'));
    kf[2] = std::to_string(std::stoll(num) - 1000000000) + "/1099511627776";  // about 0.05 deg stronger
    c[k] = join_fields(kf);
    expect_bcc_rejected(c, "jwcontradicts", "contradicts its key's claim");
}

BOOST_AUTO_TEST_CASE(root_box_narrowed_or_leaf_boxes_changed) {
    const auto l = cert();
    const FaceFields ff = first_split_face(l);
    auto a = l;
    auto f = ff.f;
    f[3] = "0/1048576", f[4] = "1/1048576";  // the first side no longer reaches the exact box's end
    a[ff.line] = join_fields(f);
    expect_bcc_rejected(a, "jroot", "root box does not contain");
    auto b = l;
    f = ff.f;
    f.back() = "0";  // the root box declared a leaf
    b[ff.line] = join_fields(f);
    expect_bcc_rejected(b, "jleaf", "leaf not verified");
    // Two sibling leaves merged into their parent (a split followed by two
    // leaves becomes one leaf): a box the prover had to split.  (Another
    // side split first may tile the box into leaves that verify too: a
    // different proof, not a tampered one.)
    auto c = l;
    f = ff.f;
    std::size_t at = 0;
    while (at + 2 < f.back().size() && !(f.back()[at] != '0' && f.back()[at + 1] == '0' && f.back()[at + 2] == '0')) ++at;
    BOOST_REQUIRE(at + 2 < f.back().size());
    f.back().replace(at, 3, "0");
    c[ff.line] = join_fields(f);
    expect_bcc_rejected(c, "jmerged", "leaf not verified");
    auto d = l;
    f = ff.f;
    f.back() += "0";
    d[ff.line] = join_fields(f);
    expect_bcc_rejected(d, "jlong", "split string too long");
    auto e = l;
    f = ff.f;
    f.back()[0] = static_cast<char>('1' + ff.m);
    e[ff.line] = join_fields(f);
    expect_bcc_rejected(e, "jside", "bad split string");
}
