// The independent checker rejects tampered certificates.  Each test copies the
// committed proofs/maxmin.cert into a temporary directory, changes one thing,
// and runs warpmesh-check on it, which must exit non-zero with a message.
#define BOOST_TEST_MODULE checker_tamper
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <boost/multiprecision/cpp_int.hpp>

#include "checker_run.hpp"

#ifndef WARPMESH_CHECK_EXE
#error "tests/CMakeLists.txt must define WARPMESH_CHECK_EXE"
#endif

namespace fs = std::filesystem;
using namespace warpmesh::testing;

namespace {

std::vector<std::string> cert() {
    auto l = read_lines(fs::path(WARPMESH_PROOFS_DIR) / "maxmin.cert");
    BOOST_REQUIRE(l.size() > 100);
    return l;
}

// Index of the first leaf line of the first key with at least `min_leaves` leaves
// whose leaves carry the tag `tag` (any tag if 0).
std::size_t find_leaf(const std::vector<std::string>& l, char tag, int min_dims = 1) {
    for (std::size_t i = 0; i < l.size(); ++i) {
        if (l[i].rfind("key ", 0) != 0) continue;
        std::istringstream ss(l[i]);
        std::string w, id, code, flat, m, qmin, qmax, leaves;
        ss >> w >> id >> code >> flat >> m >> qmin >> qmax >> leaves;
        if (std::stoi(m) < min_dims || std::stoi(leaves) < 2) continue;
        for (std::size_t j = i + 1; j < l.size() && l[j].rfind("key ", 0) != 0; ++j) {
            const bool leaf = l[j].size() > 2 && l[j][1] == ' ' && std::string("ABXab").find(l[j][0]) != std::string::npos;
            if (leaf && (tag == 0 || l[j][0] == tag)) return j;
        }
    }
    BOOST_FAIL("no suitable leaf");
    return 0;
}

}  // namespace

BOOST_AUTO_TEST_CASE(changed_endpoint) {
    auto l = cert();
    const std::size_t i = find_leaf(l, 0, 2);
    std::istringstream ss(l[i]);
    std::vector<std::string> tok;
    for (std::string t; ss >> t;) tok.push_back(t);
    tok[3] = std::to_string(std::stoll(tok[3]) + 1);  // hi of the first side
    std::string s;
    for (auto& t : tok) s += (s.empty() ? "" : " ") + t;
    l[i] = s;
    BOOST_TEST(run_checker(l, "endpoint") != 0);
}

BOOST_AUTO_TEST_CASE(missing_leaf) {
    auto l = cert();
    const std::size_t i = find_leaf(l, 0, 1);
    l.erase(l.begin() + static_cast<long>(i));
    BOOST_TEST(run_checker(l, "missing") != 0);
}

BOOST_AUTO_TEST_CASE(wrong_diagonal) {
    auto l = cert();
    const std::size_t i = find_leaf(l, 'A', 1);
    l[i][0] = 'B';
    BOOST_TEST(run_checker(l, "diagonal") != 0);
}

BOOST_AUTO_TEST_CASE(claim_raised_by_1e_9) {
    auto l = cert();
    for (auto& s : l)
        if (s.rfind("claim F ", 0) == 0) {
            std::istringstream ss(s);
            std::string w, c, qmin, qmax;
            ss >> w >> c >> qmin >> qmax;
            // A larger min angle is a smaller cot bound: subtract 1e-9 from it.
            const auto slash = qmin.find('/');
            BOOST_REQUIRE(slash != std::string::npos);
            const long double num = std::stold(qmin.substr(0, slash)), den = std::stold(qmin.substr(slash + 1));
            const long double raised = num / den - 1e-9L;
            std::ostringstream q;
            q.precision(0);
            q << std::fixed << raised * 1e12L << "/1000000000000";
            s = "claim F " + q.str() + " " + qmax;
        }
    BOOST_TEST(run_checker(l, "claim") != 0);
}

BOOST_AUTO_TEST_CASE(garbage_and_truncation) {
    // Damage early in the file, so that the checker (which stops at the first
    // error) rejects within the first keys: this suite must stay cheap enough
    // to run under the sanitizers in CI as well.
    auto l = cert();
    const std::size_t early = find_leaf(l, 0, 1);
    std::vector<std::string> t(l.begin(), l.begin() + static_cast<long>(early + 1));
    BOOST_TEST(run_checker(t, "truncated") != 0);
    auto g = l;
    g[early] = "A 99999999999999999999999999999999999999999999 1 2 3";
    BOOST_TEST(run_checker(g, "huge") != 0);
    g[early] = "A 2 " + std::string(5000, '7') + " 1";
    BOOST_TEST(run_checker(g, "long_number") != 0);
    g[early] = "A -2147483649 0 1";
    BOOST_TEST(run_checker(g, "negative_exponent") != 0);
    g[early] = std::string(100, 'A');
    BOOST_TEST(run_checker(g, "no_fields") != 0);
    auto c = l;
    for (auto& s : c)
        if (s.rfind("claim U ", 0) == 0) s = "claim U 1/0 -3/2";
    BOOST_TEST(run_checker(c, "zero_denominator") != 0);
    for (auto& s : c)
        if (s.rfind("claim U ", 0) == 0) s = "claim U -1/-2 -3/2";
    BOOST_TEST(run_checker(c, "negative_denominator") != 0);
    auto k = l;
    for (auto& s : k)
        if (s.rfind("keys ", 0) == 0) s = "keys 99999999999999999999";
    BOOST_TEST(run_checker(k, "key_count") != 0);
    BOOST_TEST(run_checker({"\x01\x02 garbage"}, "garbage") != 0);
    BOOST_TEST(run_checker({std::string(1 << 20, 'x')}, "one_huge_line") != 0);
    BOOST_TEST(run_checker({}, "empty") != 0);
}

// A threshold leaf ('a'/'b') whose H exceeds the winner's quality, so the
// exact decision holds, but by less than the relative margin 2^-28 that makes
// the mesher's double evaluation agree: the checker must reject it for the
// margin.  H is moved down by bisection (on certificates cut after the leaf's
// key, so that each run stops at the leaf) to just above the least H the
// exact test accepts, i.e. within 2^-40 of the winner's quality.
BOOST_AUTO_TEST_CASE(threshold_without_double_agreement_margin, *warpmesh::testing::full_scale_only()) {
    using Z = boost::multiprecision::cpp_int;
    const auto full = cert();
    const std::size_t i = find_leaf(full, 'a', 1);
    std::size_t end = i + 1;
    while (end < full.size() && full[end].rfind("key ", 0) != 0) ++end;
    std::vector<std::string> l(full.begin(), full.begin() + static_cast<long>(end));
    const std::string leaf = l[i].substr(0, l[i].rfind(' '));
    const std::string h = l[i].substr(l[i].rfind(' ') + 1);
    const auto slash = h.find('/');
    BOOST_REQUIRE(slash != std::string::npos);
    const Z num(h.substr(0, slash)), den(h.substr(slash + 1));
    constexpr int bits = 80;  // H' = n / 2^80
    const Z scale = Z(1) << bits;
    BOOST_REQUIRE(scale % den == 0);
    auto run = [&](const Z& n, std::string* msg) {
        l[i] = leaf + " " + n.str() + "/" + scale.str();
        return run_checker(l, "margin", msg);
    };
    std::string msg;
    Z hi = num * (scale / den), lo = hi - (hi >> 10);  // lo: not decided; hi: decided (the committed H)
    BOOST_REQUIRE(run(lo, &msg) != 0 && msg.find("not decided") != std::string::npos);
    while (hi - lo > (Z(1) << (bits - 40))) {
        const Z mid = (lo + hi) / 2;
        run(mid, &msg);
        (msg.find("not decided") != std::string::npos ? lo : hi) = mid;
    }
    BOOST_TEST(run(hi, &msg) != 0);
    BOOST_TEST(msg.find("without the double-agreement margin") != std::string::npos, msg);
}

// ---- junction keys (proofs/materials.cert: multi-material squares with 3 or 4
// materials).  Each tamper sits in the first keys, so that the checker rejects
// early; the message shows which check caught it.
namespace {
std::vector<std::string> junction_cert() {
    auto l = read_lines(fs::path(WARPMESH_PROOFS_DIR) / "materials.cert");
    BOOST_REQUIRE(l.size() > 100);
    return l;
}
// Index of the key line of the first key with >= min_dims variables and >= 2 leaves.
std::size_t find_key(const std::vector<std::string>& l, int min_dims) {
    const std::size_t leaf = find_leaf(l, 0, min_dims);
    std::size_t k = leaf;
    while (l[k].rfind("key ", 0) != 0) --k;
    return k;
}
std::string join(const std::vector<std::string>& tok) {
    std::string s;
    for (const auto& t : tok) s += (s.empty() ? "" : " ") + t;
    return s;
}
}  // namespace

BOOST_AUTO_TEST_CASE(junction_key_missing) {
    auto l = junction_cert();
    // Remove the first key with its leaves and lower the key count to match.
    std::size_t k = 0;
    while (l[k].rfind("key ", 0) != 0) ++k;
    std::size_t end = k + 1;
    while (end < l.size() && l[end].rfind("key ", 0) != 0) ++end;
    l.erase(l.begin() + static_cast<long>(k), l.begin() + static_cast<long>(end));
    for (auto& s : l)
        if (s.rfind("keys ", 0) == 0) s = "keys " + std::to_string(std::stol(s.substr(5)) - 1);
    std::string msg;
    BOOST_TEST(run_checker(l, "junction_missing", &msg) != 0);
    BOOST_TEST(msg.find("key count differs from the enumeration") != std::string::npos, msg);
}

BOOST_AUTO_TEST_CASE(junction_key_inconsistent) {
    auto l = junction_cert();
    // The first key renamed to an inconsistent one: corners A and B both stay
    // with different materials (a cut side without a mover).
    const std::size_t k = find_key(l, 1);
    auto tok = fields(l[k]);
    const std::string original = tok[2];
    tok[2] = "asbs" + original.substr(4);
    l[k] = join(tok);
    std::string msg;
    BOOST_TEST(run_checker(l, "junction_inconsistent", &msg) != 0);
    BOOST_TEST(msg.find("is not " + original) != std::string::npos, msg);
    // A junction certificate read as sign keys (the `space` line dropped).
    auto s = junction_cert();
    s.erase(std::find(s.begin(), s.end(), "space junctions"));
    BOOST_TEST(run_checker(s, "junction_space_dropped") != 0);
    // A flat claim added to the junction keys.
    auto f = junction_cert();
    const auto u = std::find_if(f.begin(), f.end(), [](const std::string& x) { return x.rfind("claim U ", 0) == 0; });
    BOOST_REQUIRE(u != f.end());
    f.insert(u + 1, "claim F" + u->substr(7));
    BOOST_TEST(run_checker(f, "junction_flat_claim", &msg) != 0);
    BOOST_TEST(msg.find("claim U only") != std::string::npos, msg);
}

BOOST_AUTO_TEST_CASE(junction_key_bound_raised) {
    auto l = junction_cert();
    // The first 2-dimensional key's min-angle bound raised to 60 deg (cot 1/2
    // < cot 60 deg = 0.577): false on its box, so some leaf fails.
    const std::size_t k = find_key(l, 2);
    auto tok = fields(l[k]);
    tok[5] = "1/2";
    l[k] = join(tok);
    std::string msg;
    BOOST_TEST(run_checker(l, "junction_raised", &msg) != 0);
    BOOST_TEST(msg.find("key " + tok[2]) != std::string::npos, msg);
    // Caught by its witness (the claimed bound is beyond the witness's exact
    // value) or, were the witness moved too, by a leaf.
    BOOST_TEST((msg.find("contradicted by its witness") != std::string::npos ||
                msg.find("not verified") != std::string::npos),
               msg);
}

// A key's claim made stronger than the key's true extreme by 1e-9: the min-angle
// bound (cot) lowered to 1e-9 below the exact cot at the key's witness, and
// separately the max-angle bound raised to 1e-9 above it.  The claims are tight
// (within 0.01 deg resp. 0.1 deg of the witnesses), so 1e-9 beyond the witness
// is a false claim: the checker must reject it (the witness contradicts it).
BOOST_AUTO_TEST_CASE(key_bound_raised_by_1e_9_above_tight_value) {
    using Q = boost::multiprecision::cpp_rational;
    const auto full = cert();
    for (int which : {0, 1}) {  // 0: min-angle bound, 1: max-angle bound
        auto l = full;
        bool done = false;
        for (std::size_t i = 0; i + 2 < l.size() && !done; ++i) {
            if (l[i].rfind("key ", 0) != 0) continue;
            std::istringstream ss(l[i]);
            std::vector<std::string> tok;
            for (std::string t; ss >> t;) tok.push_back(t);
            if (tok.size() != 8) continue;
            const std::string& w = l[i + 1 + static_cast<std::size_t>(which)];
            BOOST_REQUIRE(w.rfind(which ? "wmax " : "wmin ", 0) == 0);
            const Q wit(w.substr(w.rfind(' ') + 1));
            const Q bound(tok[5 + static_cast<std::size_t>(which)]);
            // Only a key whose claim is tight: within 1e-3 of its witness in cot.
            if (abs(bound - wit) > Q(1, 1000)) continue;
            // Dyadic, as every claim: rounded further away from the witness (2^-64).
            using Z = boost::multiprecision::cpp_int;
            const Z scale = Z(1) << 64;
            const Q r = (which ? wit + Q(1, 1000000000) : wit - Q(1, 1000000000)) * scale;
            Z n = numerator(r) / denominator(r);  // truncates toward 0
            if (which && Q(n) < r) n += 1;
            if (!which && Q(n) > r) n -= 1;
            tok[5 + static_cast<std::size_t>(which)] = Q(n, scale).str();
            std::string s;
            for (auto& t : tok) s += (s.empty() ? "" : " ") + t;
            l[i] = s;
            done = true;
        }
        BOOST_REQUIRE(done);
        std::string msg;
        BOOST_TEST(run_checker(l, which ? "key_max_raised" : "key_min_raised", &msg) != 0);
        BOOST_TEST(msg.find("contradicted by its witness") != std::string::npos, msg);
    }
}
