// The checker rejects tampered switching leaves (tag S: a max-angle form
// verified only where its diagonal is taken, through a multiplier lambda of
// the rule's comparison; proofs/README.md, "Certificate format") and tight
// bounds pushed beyond their witnesses.  Each test edits the first S leaf of
// proofs/maxmin.cert that carries a multiplier, on a copy cut after that
// leaf's key (the checker stops there), and runs warpmesh-check on it.
#define BOOST_TEST_MODULE checker_tamper_switch
#include <boost/test/unit_test.hpp>

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
    std::size_t ref = 0;             // the field of that diagonal's reference index k
};

// The first S leaf with a multiplier (a field that is neither '-' nor a
// reference index) and the certificate cut after its key.
SwitchLeaf first_switch_leaf() {
    const auto full = read_lines(fs::path(WARPMESH_PROOFS_DIR) / "maxmin.cert");
    BOOST_REQUIRE(full.size() > 100);
    for (std::size_t i = 0; i < full.size(); ++i) {
        if (full[i].rfind("S ", 0) != 0) continue;
        const auto tok = fields(full[i]);
        const std::size_t m = (tok.size() - 32) / 2;  // S k lo_1 hi_1 .. lo_m hi_m, then 2 x 15 fields
        for (std::size_t d = 0; d < 2; ++d) {
            const std::size_t at = 2 + 2 * m + 15 * d;  // k J J2, then the multipliers
            if (tok[at] == "-") continue;
            for (std::size_t x = 0; x < 12; ++x)
                if (tok[at + 3 + x] != "-") {
                    std::size_t end = i + 1;
                    while (end < full.size() && full[end].rfind("key ", 0) != 0 && full[end] != "end") ++end;
                    return {std::vector<std::string>(full.begin(), full.begin() + static_cast<long>(end)), i,
                            at + 3 + x, at};
                }
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

BOOST_AUTO_TEST_CASE(switching_leaf_wrong_lambda) {
    const SwitchLeaf s = first_switch_leaf();
    const Q lam(fields(s.lines[s.leaf])[s.lambda]);
    const Q wrongs[2] = {Q(lam * 65536), Q(lam / 65536)};
    for (const Q& wrong : wrongs) {
        std::string msg;
        BOOST_TEST(run_with(s, wrong.str(), "switch_wrong_lambda", &msg) != 0);
        BOOST_TEST(msg.find("not verified where the diagonal is taken") != std::string::npos, msg);
    }
}

BOOST_AUTO_TEST_CASE(switching_leaf_false_outright) {
    // '-' claims the form holds on the whole box, which it does not (hence the multiplier).
    const SwitchLeaf s = first_switch_leaf();
    std::string msg;
    BOOST_TEST(run_with(s, "-", "switch_false_dash", &msg) != 0);
    BOOST_TEST(msg.find("not verified") != std::string::npos, msg);
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
    // A reference index out of range, and a diagonal half-marked outright.
    auto l = s.lines;
    auto tok = fields(l[s.leaf]);
    const std::size_t at = s.ref;
    tok[at] = "6";
    l[s.leaf] = join(tok);
    BOOST_TEST(run_checker(l, "switch_index", &msg) != 0);
    BOOST_TEST(msg.find("out of range") != std::string::npos, msg);
    tok[at] = "-";
    l[s.leaf] = join(tok);
    BOOST_TEST(run_checker(l, "switch_half_dash", &msg) != 0);
    BOOST_TEST(msg.find("malformed switching certificate") != std::string::npos, msg);
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
