// The checker rejects tampered switching leaves (tag S: a max-angle form
// verified only where its diagonal is taken, through a multiplier lambda of
// the rule's comparison; proofs/README.md, "Certificate format") and tight
// bounds pushed beyond their witnesses.  Each test edits the first S leaf of
// proofs/maxmin.cert that carries a multiplier, on a copy cut after that
// leaf's key (the checker stops there), and runs warpmesh-check on it.
#define BOOST_TEST_MODULE checker_tamper_switch
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <boost/multiprecision/cpp_int.hpp>

#include "checker_run.hpp"

namespace fs = std::filesystem;
using namespace warpmesh::testing;
using Q = boost::multiprecision::cpp_rational;

namespace {

std::string join(const std::vector<std::string>& tok) {
    std::string s;
    for (const auto& t : tok) s += (s.empty() ? "" : " ") + t;
    return s;
}

struct SwitchLeaf {
    std::vector<std::string> lines;  // the certificate up to the end of the leaf's key
    std::size_t leaf = 0;            // the S leaf's line
    std::size_t lambda = 0;          // the field of its first multiplier
    std::size_t ref = 0;             // the field k:J:J2:mask of that diagonal
};

// The first S leaf with a multiplier (a diagonal group k:J:J2:mask with a
// non-zero mask and a named J) and the certificate cut after its key.
SwitchLeaf first_switch_leaf() {
    const auto full = read_lines(fs::path(WARPMESH_PROOFS_DIR) / "maxmin.cert");
    BOOST_REQUIRE(full.size() > 100);
    for (std::size_t i = 0; i < full.size(); ++i) {
        if (full[i].rfind("S ", 0) != 0) continue;
        const auto tok = fields(full[i]);
        for (std::size_t at = 2; at < tok.size(); ++at) {
            const auto& g = tok[at];
            if (std::count(g.begin(), g.end(), ':') != 3 || g.substr(g.rfind(':') + 1) == "0" || g[2] == '-') continue;
            std::size_t end = i + 1;
            while (end < full.size() && full[end].rfind("key ", 0) != 0 && full[end] != "end") ++end;
            return {std::vector<std::string>(full.begin(), full.begin() + static_cast<long>(end)), i, at + 1, at};
        }
    }
    BOOST_FAIL("no switching leaf with a multiplier in maxmin.cert");
    return {};
}

int run_with(const SwitchLeaf& s, const std::string& value, const std::string& name, std::string* msg) {
    auto l = s.lines;
    auto tok = fields(l[s.leaf]);
    tok[s.lambda] = value;
    l[s.leaf] = join(tok);
    return run_checker(l, name, msg);
}

}  // namespace

BOOST_AUTO_TEST_CASE(switching_leaf_untouched_passes_up_to_its_key) {
    // The cut copy itself is rejected only for being truncated, not at the leaf.
    const SwitchLeaf s = first_switch_leaf();
    std::string msg;
    run_checker(s.lines, "switch_untouched", &msg);
    BOOST_TEST(msg.find("leaf") == std::string::npos, msg);
}

// A multiplier too small to compensate where the diagonal is not taken: 0
// (the form alone, which does not hold on the box) and lambda / 2^16.
BOOST_AUTO_TEST_CASE(switching_leaf_wrong_lambda) {
    const SwitchLeaf s = first_switch_leaf();
    const Q lam(fields(s.lines[s.leaf])[s.lambda]);
    const Q wrongs[2] = {Q(0), Q(lam / 65536)};
    for (const Q& wrong : wrongs) {
        std::string msg;
        BOOST_TEST(run_with(s, wrong.str(), "switch_wrong_lambda", &msg) != 0);
        BOOST_TEST(msg.find("not verified where the diagonal is taken") != std::string::npos, msg);
    }
}

BOOST_AUTO_TEST_CASE(switching_leaf_false_outright) {
    // The diagonal marked '-' (its max-angle forms hold on the whole box),
    // which they do not (hence the multipliers): the group and its
    // multipliers replaced by '-'.
    const SwitchLeaf s = first_switch_leaf();
    auto l = s.lines;
    auto tok = fields(l[s.leaf]);
    const std::string group = tok[s.ref];
    const int mask = std::stoi(group.substr(group.rfind(':') + 1));
    const int named = group.find(":-:") == std::string::npos ? 2 : 1;
    tok.erase(tok.begin() + static_cast<long>(s.lambda),
              tok.begin() + static_cast<long>(s.lambda) + named * __builtin_popcount(static_cast<unsigned>(mask)));
    tok[s.ref] = "-";
    l[s.leaf] = join(tok);
    std::string msg;
    BOOST_TEST(run_checker(l, "switch_false_dash", &msg) != 0);
    BOOST_TEST(msg.find("max-angle inequality not verified") != std::string::npos, msg);
}

BOOST_AUTO_TEST_CASE(switching_leaf_negative_or_malformed_lambda) {
    const SwitchLeaf s = first_switch_leaf();
    std::string msg;
    BOOST_TEST(run_with(s, "-1/1024", "switch_negative", &msg) != 0);
    BOOST_TEST(msg.find("negative multiplier") != std::string::npos, msg);
    BOOST_TEST(run_with(s, "1/3", "switch_not_dyadic", &msg) != 0);
    BOOST_TEST(msg.find("not dyadic") != std::string::npos, msg);
    BOOST_TEST(run_with(s, "x", "switch_garbage", &msg) != 0);
    BOOST_TEST(msg.find("bad integer") != std::string::npos, msg);
    // A reference index out of range, a malformed group, a missing multiplier.
    auto l = s.lines;
    auto tok = fields(l[s.leaf]);
    const std::string group = tok[s.ref];
    tok[s.ref] = "6" + group.substr(group.find(':'));
    l[s.leaf] = join(tok);
    BOOST_TEST(run_checker(l, "switch_index", &msg) != 0);
    BOOST_TEST(msg.find("out of range") != std::string::npos, msg);
    tok[s.ref] = group.substr(0, group.rfind(':'));
    l[s.leaf] = join(tok);
    BOOST_TEST(run_checker(l, "switch_group", &msg) != 0);
    BOOST_TEST(msg.find("malformed switching certificate") != std::string::npos, msg);
    tok[s.ref] = group;
    tok.erase(tok.begin() + static_cast<long>(s.lambda));
    l[s.leaf] = join(tok);
    BOOST_TEST(run_checker(l, "switch_missing_lambda", &msg) != 0);
}

// Theorem U's max-angle claim (cot, lower bound) raised by 1e-9 above the
// tight value: it no longer follows from the key claims.
BOOST_AUTO_TEST_CASE(theorem_max_raised_by_1e_9) {
    auto l = read_lines(fs::path(WARPMESH_PROOFS_DIR) / "maxmin.cert");
    bool done = false;
    for (auto& s : l)
        if (s.rfind("claim U ", 0) == 0) {
            auto tok = fields(s);
            using Z = boost::multiprecision::cpp_int;
            const Z scale = Z(1) << 64;
            const Q r = (Q(tok[3]) + Q(1, 1000000000)) * scale;
            Z n = numerator(r) / denominator(r);
            if (Q(n) < r) n += 1;
            tok[3] = Q(n, scale).str();
            s = join(tok);
            done = true;
        }
    BOOST_REQUIRE(done);
    std::string msg;
    BOOST_TEST(run_checker(l, "theorem_max_raised", &msg) != 0);
    BOOST_TEST(msg.find("does not follow") != std::string::npos, msg);
}
