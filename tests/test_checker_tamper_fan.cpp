// The independent checker rejects tampered certificates of the fan rule
// (proofs/fan.cert, and its junction keys, proofs/materials_fan.cert): the
// leaves and claims that are new with the rule — fan leaves (F), undecided
// fan/diagonal leaves (Y), the fan only on squares whose corners are all
// inside (junction keys: whose staying corners share a material), and the
// qualifying threshold of diagonal leaves.
// Each test changes one leaf or key line, cuts the certificate after that key
// (the checker stops at the first error, so the run stays cheap) and asserts
// the checker's message names the tampered leaf, not the truncation.
#define BOOST_TEST_MODULE checker_tamper_fan
#include <boost/test/unit_test.hpp>

#include <boost/multiprecision/cpp_int.hpp>

#include "checker_run.hpp"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#ifndef WARPMESH_CHECK_EXE
#error "tests/CMakeLists.txt must define WARPMESH_CHECK_EXE"
#endif

namespace fs = std::filesystem;
using warpmesh::testing::fields;
using warpmesh::testing::read_lines;

namespace {

std::vector<std::string> cert(const char* name = "fan.cert") {
    auto out = read_lines(fs::path(WARPMESH_PROOFS_DIR) / name);
    BOOST_REQUIRE(out.size() > 100);
    return out;
}

// The checker's message on a tampered copy, which it must reject.
std::string run_checker(const std::vector<std::string>& lines, const std::string& name) {
    std::string msg;
    BOOST_TEST(warpmesh::testing::run_checker(lines, name, &msg) != 0);
    return msg;
}

bool all_inside(const std::string& code) {  // no corner stays outside ("+s")
    for (std::size_t c = 0; c < 4; ++c)
        if (code[2 * c] == '+' && code[2 * c + 1] == 's') return false;
    return true;
}

// A junction key (letters a-d and warps) on which the fan rule may take the
// fan: its staying corners ("Xs") share one letter.
bool junction_all_inside(const std::string& code) {
    char letter = 0;
    for (std::size_t c = 0; c < 4; ++c) {
        if (code[2 * c + 1] != 's') continue;
        if (letter && code[2 * c] != letter) return false;
        letter = code[2 * c];
    }
    return true;
}

// First key satisfying `want(code)` having a leaf tagged `tag` (and, if
// `also`, a leaf tagged `also` too): returns (key line, leaf line).
std::pair<std::size_t, std::size_t> find(const std::vector<std::string>& l, bool (*want)(const std::string&), char tag,
                                         char also = 0) {
    for (std::size_t i = 0; i < l.size(); ++i) {
        if (l[i].rfind("key ", 0) != 0) continue;
        const auto f = fields(l[i]);
        if (f.size() != 8 || !want(f[2])) continue;
        std::size_t leaf = 0;
        bool has_also = also == 0;
        for (std::size_t j = i + 1; j < l.size() && l[j].rfind("key ", 0) != 0 && l[j] != "end"; ++j) {
            if (!leaf && l[j][0] == tag) leaf = j;
            has_also = has_also || l[j][0] == also;
        }
        if (leaf && has_also) return {i, leaf};
    }
    BOOST_FAIL("no suitable key");
    return {0, 0};
}

// The certificate up to the end of the key whose line is at `key`.
std::vector<std::string> cut_after(const std::vector<std::string>& l, std::size_t key) {
    std::size_t end = key + 1;
    while (end < l.size() && l[end].rfind("key ", 0) != 0 && l[end] != "end") ++end;
    return {l.begin(), l.begin() + static_cast<long>(end)};
}

bool names_a_leaf(const std::string& msg) {
    return msg.find(" leaf ") != std::string::npos && msg.find("truncated") == std::string::npos;
}

}  // namespace

BOOST_AUTO_TEST_CASE(fan_certificate_has_undecided_fan_leaves) {
    // (The committed proof has no F leaf: wherever the fan is taken, the Y leaf
    // — the fan verified whole, the claim covering a qualifying diagonal — holds
    // on boxes at least as large as those that decide the exclusion.)
    const auto l = cert();
    BOOST_TEST(l[2].find("fan") != std::string::npos);
    find(l, all_inside, 'Y');
}

BOOST_AUTO_TEST_CASE(fan_leaf_relabelled_as_a_diagonal, *warpmesh::testing::full_scale_only()) {
    const auto l = cert();
    const auto [key, leaf] = find(l, all_inside, 'Y');
    auto t = cut_after(l, key);
    t[leaf][0] = 'A';
    const std::string msg = run_checker(t, "fan_as_diagonal");
    BOOST_TEST(names_a_leaf(msg), msg);
}

BOOST_AUTO_TEST_CASE(diagonal_leaf_relabelled_as_the_fan, *warpmesh::testing::full_scale_only()) {
    // Where the diagonal qualifies (q <= H0), the rule does not take the fan.
    const auto l = cert();
    const auto [key, leaf] = find(l, all_inside, 'A', 'Y');
    auto t = cut_after(l, key);
    t[leaf][0] = 'F';
    const std::string msg = run_checker(t, "diagonal_as_fan");
    BOOST_TEST(msg.find("fan not decided") != std::string::npos, msg);
}

BOOST_AUTO_TEST_CASE(fan_on_a_square_with_an_outside_corner) {
    // The fan's centre would be a boundary vertex off the level set: refused.
    const auto l = cert();
    const auto [key, leaf] = find(l, [](const std::string& c) { return !all_inside(c); }, 'A');
    auto t = cut_after(l, key);
    t[leaf][0] = 'F';
    const std::string msg = run_checker(t, "fan_outside");
    BOOST_TEST(msg.find("bad diagonal tag") != std::string::npos, msg);
}

BOOST_AUTO_TEST_CASE(undecided_leaf_with_a_claim_below_the_threshold, *warpmesh::testing::full_scale_only()) {
    // A Y leaf may take a diagonal with q up to H0 (1 + 2^-30): a key claim of
    // cot <= 3 (exactly atan(1/3)) does not cover it.  The key is one whose
    // min-angle witness (since format 2: the `wmin` line after the key line) has
    // cot <= 3, so that the witness does not already contradict the lowered
    // claim and the checker reaches the leaf.
    const auto l = cert();
    std::size_t key = 0;
    for (std::size_t i = 0; i < l.size() && !key; ++i) {
        if (l[i].rfind("key ", 0) != 0) continue;
        const auto f = fields(l[i]);
        if (f.size() != 8 || !all_inside(f[2]) || i + 1 >= l.size() || l[i + 1].rfind("wmin ", 0) != 0) continue;
        if (boost::multiprecision::cpp_rational(fields(l[i + 1]).back()) > 3) continue;
        for (std::size_t j = i + 1; j < l.size() && l[j].rfind("key ", 0) != 0 && l[j] != "end"; ++j)
            if (l[j][0] == 'Y') key = i;
    }
    BOOST_REQUIRE(key);
    auto t = cut_after(l, key);
    auto f = fields(t[key]);
    f[5] = "3";
    std::string s;
    for (auto& w : f) s += (s.empty() ? "" : " ") + w;
    t[key] = s;
    const std::string msg = run_checker(t, "undecided_low_claim");
    BOOST_TEST(names_a_leaf(msg), msg);
}

// ---- the junction keys under the fan rule (proofs/materials_fan.cert) ----------

BOOST_AUTO_TEST_CASE(junction_fan_certificate_has_undecided_fan_leaves) {
    const auto l = cert("materials_fan.cert");
    BOOST_TEST(l[2] == "rule fan");
    BOOST_TEST(l[3] == "space junctions");
    find(l, junction_all_inside, 'Y');
}

BOOST_AUTO_TEST_CASE(junction_fan_leaf_relabelled_as_a_diagonal) {
    const auto l = cert("materials_fan.cert");
    const auto [key, leaf] = find(l, junction_all_inside, 'Y');
    auto t = cut_after(l, key);
    t[leaf][0] = 'A';
    const std::string msg = run_checker(t, "junction_fan_as_diagonal");
    BOOST_TEST(names_a_leaf(msg), msg);
}

BOOST_AUTO_TEST_CASE(junction_fan_on_a_square_with_staying_corners_of_two_materials) {
    // Two opposite corners staying with different materials force a diagonal;
    // a fan there would join them through its centre: refused.
    const auto l = cert("materials_fan.cert");
    const auto [key, leaf] = find(l, [](const std::string& c) { return !junction_all_inside(c); }, 'A');
    auto t = cut_after(l, key);
    t[leaf][0] = 'F';
    const std::string msg = run_checker(t, "junction_fan_forced");
    BOOST_TEST(msg.find("bad diagonal tag") != std::string::npos, msg);
}

BOOST_AUTO_TEST_CASE(junction_keys_under_the_max_min_rule_are_refused) {
    // The junction key space exists for the separating and fan rules only.
    auto t = cert("materials_fan.cert");
    t[2] = "rule maxmin";
    t.resize(20);
    const std::string msg = run_checker(t, "junction_maxmin");
    BOOST_TEST(msg.find("unknown key space") != std::string::npos, msg);
}

BOOST_AUTO_TEST_CASE(junction_fan_claim_below_the_fan_floor_is_refused) {
    // The separating rule's junction floor (15 deg) is not what the fan rule's
    // keys prove: a claim lowered to it is weaker than the keys' extremes.
    auto t = cert("materials_fan.cert");
    BOOST_REQUIRE(t[4].rfind("claim U ", 0) == 0);
    t[4] = "claim U 500907389/134217728 " + fields(t[4])[3];
    const std::string msg = run_checker(t, "junction_fan_weak_claim");
    BOOST_TEST(msg.find("claim") != std::string::npos, msg);
}
