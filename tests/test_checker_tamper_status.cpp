// The checker's exit status says what was proved (issue 27 item 8): every line
// kind that states a status or a claim — the header, the rule and key space,
// the theorem claims and their witnesses, the key count, every key line (a
// bound, or `inverted` with its exact witness `winv`), the key witnesses and
// `end` — is tampered with the way a lying certificate would, and the checker
// must reject it (exit 1) with a message naming what is wrong.  The leaves
// are covered by test_checker_tamper*.cpp.  Every tamper is caught before the
// leaves of later keys are verified (claims are checked against the key lines
// first), so each run costs a fraction of a full check.
#define BOOST_TEST_MODULE checker_tamper_status
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <sys/wait.h>

#include <boost/multiprecision/cpp_int.hpp>

#include "checker_run.hpp"

namespace fs = std::filesystem;
using namespace warpmesh::testing;
using Q = boost::multiprecision::cpp_rational;

namespace {

std::vector<std::string> cert(const char* name) {
    auto l = read_lines(fs::path(WARPMESH_PROOFS_DIR) / name);
    BOOST_REQUIRE(l.size() > 100);
    return l;
}
std::string join(const std::vector<std::string>& tok) {
    std::string s;
    for (const auto& t : tok) s += (s.empty() ? "" : " ") + t;
    return s;
}
bool starts(const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; }

// The checker must reject `l` (exit 1, not 0 and not 3) with `expected` in its message.
void rejected(const std::vector<std::string>& l, const std::string& name, const std::string& expected) {
    std::string msg;
    const int rc = run_checker(l, name, &msg);
    BOOST_TEST((WIFEXITED(rc) && WEXITSTATUS(rc) == 1), name << ": exit status " << rc << ", " << msg);
    BOOST_TEST(msg.find(expected) != std::string::npos, name << ": expected '" << expected << "' in: " << msg);
}

// `l` without its first line starting with `prefix`; with that line twice;
// with that line replaced by `by`.
std::vector<std::string> without(std::vector<std::string> l, const std::string& prefix) {
    l.erase(l.begin() + static_cast<long>(line_of(l, prefix)));
    return l;
}
std::vector<std::string> doubled(std::vector<std::string> l, const std::string& prefix) {
    const std::size_t i = line_of(l, prefix);
    const std::string copy = l[i];
    l.insert(l.begin() + static_cast<long>(i), copy);
    return l;
}
std::vector<std::string> replaced(std::vector<std::string> l, const std::string& prefix, const std::string& by) {
    l[line_of(l, prefix)] = by;
    return l;
}
// The key line of the first key with >= min_dims variables.
std::size_t key_with_dims(const std::vector<std::string>& l, int min_dims) {
    for (std::size_t i = 0; i < l.size(); ++i)
        if (starts(l[i], "key ") && fields(l[i]).size() == 8 && std::stoi(fields(l[i])[4]) >= min_dims) return i;
    BOOST_FAIL("no key");
    return 0;
}
// One past the last line of the key whose line is at `k` (its witnesses and leaves).
std::size_t key_end(const std::vector<std::string>& l, std::size_t k) {
    std::size_t e = k + 1;
    while (e < l.size() && !starts(l[e], "key ") && l[e] != "end") ++e;
    return e;
}

// Every key marked `inverted` (its witnesses and leaves dropped, `winv` lines
// from `winv(key line, its wmin line)`, none if it returns ""), every claim
// `inverted` with an inverted witness on the first key: the issue's
// certificate, which verified 0 leaves and exited 0.
std::vector<std::string> all_inverted(const std::vector<std::string>& l,
                                      std::string (*winv)(const std::vector<std::string>&, const std::string&)) {
    std::vector<std::string> out;
    std::string first_winv;
    for (std::size_t i = 0; i < l.size(); ++i) {
        const std::string& s = l[i];
        if (starts(s, "claim ")) {
            out.push_back(s.substr(0, 8) + "inverted");
            continue;
        }
        if (starts(s, "witness ")) continue;
        if (!starts(s, "key ")) {
            if (!starts(s, "wmin") && !starts(s, "wmax") && (s.size() < 2 || s[1] != ' ')) out.push_back(s);
            continue;
        }
        auto tok = fields(s);
        tok.resize(5);
        out.push_back(join(tok) + " inverted");
        const std::string w = winv(tok, i + 1 < l.size() ? l[i + 1] : "");
        if (!w.empty()) out.push_back(w);
    }
    return out;
}
// The key's min-angle witness point (a valid configuration) as its `winv`.
std::string winv_at_wmin(const std::vector<std::string>&, const std::string& wmin) {
    auto tok = fields(wmin);
    tok[0] = "winv";
    tok.pop_back();  // the value
    return join(tok);
}

}  // namespace

// ---- `inverted` keys and claims ----------------------------------------------------
BOOST_AUTO_TEST_CASE(every_key_inverted_without_witness_is_not_a_proof) {
    for (const char* name : {"maxmin.cert", "materials.cert"}) {
        const auto l = all_inverted(cert(name), [](const std::vector<std::string>&, const std::string&) { return std::string(); });
        rejected(l, std::string("all_inverted_") + name, "inverted without its exact witness ('winv' line)");
    }
}

BOOST_AUTO_TEST_CASE(every_key_inverted_at_a_valid_configuration) {
    // Witnesses inside the box, where every chosen triangle is positively
    // oriented (the key's own min-angle witness point).
    const auto l = all_inverted(cert("maxmin.cert"), winv_at_wmin);
    rejected(l, "all_inverted_valid_witness", "inverted witness is not inverted");
}

BOOST_AUTO_TEST_CASE(inverted_key_witness_outside_the_box) {
    // A t of 1 slides the corner onto its neighbour (a degenerate triangle):
    // outside the key's box [0, 1/2]^m.
    auto l = cert("maxmin.cert");
    const std::size_t k = key_with_dims(l, 1);
    auto tok = fields(l[k]);
    const int m = std::stoi(tok[4]);
    tok.resize(5);
    std::vector<std::string> key{join(tok) + " inverted", "winv"};
    for (int j = 0; j < m; ++j) key[1] += " 1";
    l.erase(l.begin() + static_cast<long>(k), l.begin() + static_cast<long>(key_end(l, k)));
    l.insert(l.begin() + static_cast<long>(k), key.begin(), key.end());
    rejected(l, "inverted_outside_box", "witness t outside [0, 1/2]");
    // And with one t value too few.
    l[k + 1] = "winv" + std::string(m > 1 ? " 1/4" : "");
    for (int j = 2; j < m; ++j) l[k + 1] += " 1/4";
    rejected(l, "inverted_short_witness", "'winv' has the wrong number of t values");
}

BOOST_AUTO_TEST_CASE(claim_inverted_while_no_key_is) {
    auto l = cert("maxmin.cert");
    const std::size_t c = line_of(l, "claim U ");
    l[c] = "claim U inverted";
    l.erase(std::remove_if(l.begin(), l.end(), [](const std::string& s) { return starts(s, "witness U "); }), l.end());
    rejected(l, "claim_inverted", "claim U is 'inverted', but no key is inverted");
}

BOOST_AUTO_TEST_CASE(inverted_witness_on_a_bound) {
    // An `inverted` theorem witness beside a bound claim, on a key whose
    // configuration is valid.
    auto l = cert("maxmin.cert");
    const std::size_t w = line_of(l, "witness U min ");
    auto tok = fields(l[w]);
    tok[2] = "inverted";
    tok.pop_back();
    l.insert(l.begin() + static_cast<long>(w), join(tok));
    rejected(l, "inverted_witness_on_bound", "has 1 'inverted' witnesses");
}

// ---- theorem claims -------------------------------------------------------------------
BOOST_AUTO_TEST_CASE(claim_weaker_than_its_keys_give) {
    // A true but weaker theorem (min-angle cot bound + 1) is not what was proved.
    const auto full = cert("maxmin.cert");
    auto tok = fields(full[line_of(full, "claim U ")]);
    tok[2] = (Q(tok[2]) + 1).str();
    rejected(replaced(full, "claim U ", join(tok)), "claim_weaker", "claim U is weaker than its keys give");
}

BOOST_AUTO_TEST_CASE(claim_stronger_than_a_key_gives) {
    // The flat min-angle claim below the largest flat key's cot bound.
    const auto full = cert("maxmin.cert");
    auto tok = fields(full[line_of(full, "claim F ")]);
    tok[2] = (Q(tok[2]) - Q(1, 1 << 20)).str();
    rejected(replaced(full, "claim F ", join(tok)), "claim_stronger", "claim F does not follow from the key claims");
}

BOOST_AUTO_TEST_CASE(claim_missing_duplicated_or_malformed) {
    const auto full = cert("maxmin.cert");
    rejected(without(full, "claim F "), "claim_missing", "missing claims");
    rejected(doubled(full, "claim U "), "claim_duplicated", "duplicate claim");
    rejected(replaced(full, "claim U ", "claim U 3"), "claim_malformed", "bad claim line");
    rejected(replaced(full, "claim U ", "claim X 3 -1"), "claim_unknown_category", "bad claim/witness line");
}

// ---- theorem witnesses ---------------------------------------------------------------
BOOST_AUTO_TEST_CASE(theorem_witness_missing_duplicated_or_unknown) {
    const auto full = cert("maxmin.cert");
    rejected(without(full, "witness U max "), "witness_missing", "has 0 'max' witnesses");
    rejected(doubled(full, "witness F min "), "witness_duplicated", "has 2 'min' witnesses");
    auto tok = fields(full[line_of(full, "witness U min ")]);
    tok[2] = "mean";
    rejected(replaced(full, "witness U min ", join(tok)), "witness_unknown_kind", "bad witness line");
}

BOOST_AUTO_TEST_CASE(theorem_witness_value_point_or_key_wrong) {
    const auto full = cert("maxmin.cert");
    const auto tok = fields(full[line_of(full, "witness U max ")]);
    auto edit = [&](auto change, const std::string& name, const std::string& expected) {
        auto t = tok;
        change(t);
        rejected(replaced(full, "witness U max ", join(t)), name, expected);
    };
    edit([](auto& t) { t.back() = (Q(t.back()) + Q(1, 1 << 20)).str(); }, "witness_value",
         "witness value differs from exact evaluation");
    edit([](auto& t) { t[4] = "3/4"; }, "witness_outside_box", "witness t outside [0, 1/2]");
    edit([](auto& t) { t.erase(t.begin() + 4); }, "witness_short", "witness has the wrong number of t values");
    // A and B stay with opposite signs: a cut side without a mover.
    edit([](auto& t) { t[3] = "-s+s-s+s"; }, "witness_key_unknown", "is not a consistent key");
    // A flat witness on a key that is not flat-compatible: theorem U's min
    // witness key (15 deg, below theorem F's floor atan(1/3)).
    rejected(replaced(full, "witness F min ", "witness F" + full[line_of(full, "witness U min ")].substr(9)),
             "witness_flat_on_any", "flat witness on a key that is not flat-compatible");
}

// ---- keys ------------------------------------------------------------------------------
BOOST_AUTO_TEST_CASE(key_missing_duplicated_or_miscounted) {
    const auto full = cert("maxmin.cert");
    const std::size_t k = key_with_dims(full, 1), e = key_end(full, k);
    auto l = full;  // a key dropped, the count kept
    l.erase(l.begin() + static_cast<long>(k), l.begin() + static_cast<long>(e));
    rejected(l, "key_missing", "is not ");
    l = full;  // a key repeated (with its witnesses and leaves)
    l.insert(l.begin() + static_cast<long>(e), full.begin() + static_cast<long>(k), full.begin() + static_cast<long>(e));
    rejected(l, "key_duplicated", "is not ");
    for (auto& s : l)
        if (starts(s, "keys ")) s = "keys " + std::to_string(std::stol(s.substr(5)) + 1);
    rejected(l, "key_duplicated_counted", "key count differs from the enumeration");
}

BOOST_AUTO_TEST_CASE(key_line_fields_wrong) {
    const auto full = cert("maxmin.cert");
    const std::size_t k = key_with_dims(full, 2);
    const auto tok = fields(full[k]);
    auto edit = [&](std::size_t field, const std::string& v, const std::string& name, const std::string& expected) {
        auto l = full;
        auto t = tok;
        t[field] = v;
        l[k] = join(t);
        rejected(l, name, expected);
    };
    edit(1, std::to_string(std::stol(tok[1]) + 1), "key_index", "is not " + tok[2]);
    edit(3, tok[3] == "1" ? "0" : "1", "key_flat_flag", "flatness flag differs");
    edit(4, "1", "key_dimension", "dimension");
    {  // a min-angle cot bound of 300 (the claims raised with it, so that they follow)
        auto l = full;
        auto t = tok;
        t[5] = "300";
        l[k] = join(t);
        for (auto& s : l)
            if (starts(s, "claim U ") || (tok[3] == "1" && starts(s, "claim F "))) {
                auto c = fields(s);
                c[2] = "300";
                s = join(c);
            }
        rejected(l, "key_qmin_above_256", "min-angle cot bound above 256");
    }
    edit(7, "0", "key_no_leaves", "integer out of range");
    edit(7, std::to_string(std::stol(tok[7]) + 1), "key_leaf_count", tok[2]);
    auto l = full;
    auto t = tok;
    t.pop_back();
    l[k] = join(t);
    rejected(l, "key_line_short", "malformed key line");
}

BOOST_AUTO_TEST_CASE(key_witness_missing_or_wrong) {
    const auto full = cert("maxmin.cert");
    const std::size_t k = key_with_dims(full, 2);
    const std::string code = fields(full[k])[2];
    auto l = full;
    l.erase(l.begin() + static_cast<long>(k + 1));
    rejected(l, "key_wmin_missing", "expected 'wmin' line");
    l = full;
    auto t = fields(l[k + 2]);
    t.back() = (Q(t.back()) + Q(1, 1 << 30)).str();
    l[k + 2] = join(t);
    rejected(l, "key_wmax_value", "key " + code + ": witness value differs from exact evaluation");
    l = full;
    t = fields(l[k + 1]);
    t[1] = "5/8";
    l[k + 1] = join(t);
    rejected(l, "key_wmin_outside_box", "witness t outside [0, 1/2]");
}

// ---- header, space and end ---------------------------------------------------------
BOOST_AUTO_TEST_CASE(header_rule_or_space_wrong) {
    const auto full = cert("maxmin.cert");
    auto l = full;
    l[0] = "warpmesh-certificate 2";
    rejected(l, "version", "unknown version");
    l = full;
    l[line_of(l, "rule ")] = "rule delaunay";
    rejected(l, "rule_unknown", "unknown rule");
    l = full;  // the max-min certificate read as the separating rule's
    l[line_of(l, "rule ")] = "rule separating";
    rejected(l, "rule_relabelled", "separating rule forces the other diagonal");
    l = full;
    l.insert(l.begin() + static_cast<long>(line_of(l, "rule ")) + 1, "space junctions");
    rejected(l, "space_on_maxmin", "unknown key space");
    rejected({"warpmesh-certificate 3"}, "header_only", "truncated: expected rule");
    rejected({"# only a comment"}, "empty", "empty certificate");
}

// A missing `end` is found only after every key is verified: the smallest
// certificate (materials.cert), and not under the sanitizers.  Data after
// `end` is refused before the leaves.
BOOST_AUTO_TEST_CASE(end_missing, *warpmesh::testing::full_scale_only()) {
    auto l = cert("materials.cert");
    BOOST_REQUIRE(l.back() == "end");
    l.pop_back();
    rejected(l, "end_missing", "truncated: expected end");
}
BOOST_AUTO_TEST_CASE(data_after_end) {
    const auto full = cert("materials.cert");
    auto l = full;
    l.push_back("end");
    rejected(l, "data_after_end", "data after end");
    l = full;
    l.insert(l.begin() + static_cast<long>(line_of(l, "key 5 ")), "end");
    rejected(l, "end_inside", "data after end");
}
