// The prover's interval decisions agree with the mesher's double evaluation,
// and the committed witnesses evaluate exactly to what the certificates say.
#define BOOST_TEST_MODULE prover_agreement
#include <boost/test/unit_test.hpp>

#include <boost/multiprecision/cpp_int.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "warpmesh/certify/certified.hpp"
#include "warpmesh/mesh2d/generic_square.hpp"
#include "warpmesh/prove.hpp"

using namespace warpmesh;
using Q = boost::multiprecision::cpp_rational;


namespace {
// The claims (min_cot, max_cot) of every key of a committed certificate, by index.
std::map<int, std::pair<double, double>> key_claims(const std::string& name) {
    std::ifstream in(std::filesystem::path(WARPMESH_PROOFS_DIR) / (name + ".cert"));
    BOOST_REQUIRE(in.good());
    std::map<int, std::pair<double, double>> out;
    for (std::string line; std::getline(in, line);) {
        if (line.rfind("key ", 0) != 0) continue;
        std::istringstream ss(line);
        std::string w, id, code, flat, m, qmin, qmax;
        ss >> w >> id >> code >> flat >> m >> qmin >> qmax;
        if (qmax.empty()) continue;  // an inverted key
        out[std::stoi(id)] = {Q(qmin).convert_to<double>(), Q(qmax).convert_to<double>()};
    }
    return out;
}
}  // namespace

BOOST_AUTO_TEST_CASE(key_space) {
    const auto keys = prover::consistent_keys();
    BOOST_TEST(keys.size() == 5095u);
    int flat = 0;
    for (const auto& k : keys) flat += prover::flat_compatible(k);
    BOOST_TEST(flat == 383);
}

// The junction keys (proofs/README.md, "Junction keys"): 2546, per pattern as
// stated there, each with >= 2 warped corners, letters in first-appearance order.
BOOST_AUTO_TEST_CASE(junction_key_space) {
    const auto keys = prover::junction_keys();
    BOOST_TEST(keys.size() == 2546u);
    std::map<std::string, int> per_pattern;
    int forced = 0;
    for (const auto& k : keys) {
        BOOST_TEST(k.junction);
        std::string pattern;
        for (const auto& c : k.m) pattern += static_cast<char>('a' + c.material);
        ++per_pattern[pattern];
        BOOST_TEST(prover::key_vars(k).size() >= 2u);
        BOOST_TEST(junction_key_code(junction_letters(k.m)) == prover::code_of(k));
        Diagonal d{};
        forced += separating_diagonal(k.m, d);
    }
    const std::map<std::string, int> expected{{"aabc", 299}, {"abac", 299}, {"abbc", 450}, {"abca", 450},
                                              {"abcb", 299}, {"abcc", 299}, {"abcd", 450}};
    BOOST_TEST((per_pattern == expected));
    BOOST_TEST(forced == 160);
}

// Junction keys: the prover's decided leaves agree with the mesher's double
// evaluation of the rule on material corners (choose_diagonal on MaterialCorner).
BOOST_AUTO_TEST_CASE(double_agrees_with_intervals_on_junction_keys) {
    const auto keys = prover::junction_keys();
    const auto claims = key_claims("materials");
    int checked = 0;
    for (std::size_t i = 0; i < keys.size(); i += 97) {
        const auto& k = keys[i];
        const auto vars = prover::key_vars(k);
        const auto [qmin, qmax] = claims.at(static_cast<int>(i));
        const auto proof = prover::prove_key(DiagonalRule::separating, k, qmin, qmax, 20000);
        BOOST_REQUIRE(proof.ok);
        for (const auto& leaf : proof.leaves) {
            if (leaf.diag == 3) continue;
            for (int s = 0; s < 5; ++s) {
                std::array<double, 4> t{};
                std::array<Warp, 4> w{};
                std::array<MaterialCorner, 4> mats{};  // real material numbers with the key's pattern
                for (int c = 0; c < 4; ++c) w[c] = k.m[c].warp, mats[c] = {static_cast<std::uint16_t>(40 + 7 * k.m[c].material), w[c]};
                for (std::size_t j = 0; j < vars.size(); ++j) {
                    const double lo = std::ldexp(double(leaf.num[2 * j]), -leaf.k);
                    const double hi = std::ldexp(double(leaf.num[2 * j + 1]), -leaf.k);
                    const double u = s == 0 ? 0.5 : ((s + j) % 3) / 2.0;
                    t[vars[j]] = lo + u * (hi - lo);
                }
                const Choice ch = choose_diagonal<double>(DiagonalRule::separating, generic_positions<double>(w, t), mats);
                BOOST_TEST((ch.ad ? 1 : 2) == int(leaf.diag));
                ++checked;
            }
        }
    }
    BOOST_TEST(checked > 100);
}

// The fan rule on junction keys (proofs/materials_fan.cert): where the
// prover's leaf decides (a diagonal: 1 AD, 2 BC; the fan: 4), the mesher's
// double evaluation of choose_diagonal on material corners decides the same
// with either tie-break; on undecided leaves (5, Y: the fan or a diagonal)
// the mesher does take the fan at some points (the rule reaches it on
// junction keys).
BOOST_AUTO_TEST_CASE(double_agrees_with_intervals_on_junction_keys_under_the_fan_rule) {
    const auto keys = prover::junction_keys();
    const auto claims = key_claims("materials_fan");
    int checked = 0, fans = 0;
    for (std::size_t i = 0; i < keys.size(); i += 37) {
        const auto& k = keys[i];
        const auto vars = prover::key_vars(k);
        const auto [qmin, qmax] = claims.at(static_cast<int>(i));
        const auto proof = prover::prove_key(DiagonalRule::fan, k, qmin, qmax, 20000);
        BOOST_REQUIRE(proof.ok);
        for (const auto& leaf : proof.leaves) {
            if (leaf.diag != 1 && leaf.diag != 2 && leaf.diag != 4 && leaf.diag != 5) continue;
            for (int s = 0; s < 5; ++s) {
                std::array<double, 4> t{};
                std::array<Warp, 4> w{};
                std::array<MaterialCorner, 4> mats{};
                for (int c = 0; c < 4; ++c) w[c] = k.m[c].warp, mats[c] = {static_cast<std::uint16_t>(900 - 11 * k.m[c].material), w[c]};
                for (std::size_t j = 0; j < vars.size(); ++j) {
                    const double lo = std::ldexp(double(leaf.num[2 * j]), -leaf.k);
                    const double hi = std::ldexp(double(leaf.num[2 * j + 1]), -leaf.k);
                    t[vars[j]] = lo + (s == 0 ? 0.5 : ((s + j) % 3) / 2.0) * (hi - lo);
                }
                for (const TieBreak tie : {TieBreak::ad, TieBreak::bc}) {
                    const Choice ch = choose_diagonal<double>(DiagonalRule::fan, generic_positions<double>(w, t), mats, tie);
                    fans += ch.fan;
                    if (leaf.diag == 5) continue;
                    BOOST_TEST((ch.fan ? 4 : ch.ad ? 1 : 2) == int(leaf.diag));
                    ++checked;
                }
            }
        }
    }
    BOOST_TEST(checked > 100);
    BOOST_TEST(fans > 0);
    BOOST_TEST_MESSAGE("junction fan agreement: " << checked << " decided points, the fan taken at " << fans);
}

// For a spread of keys: prove the key's committed claims (loose claims are
// proved on undecided boxes, with switching leaves and the mean-value form:
// nothing left to sample), then at sample points of every leaf whose diagonal
// is decided, choose_diagonal<double> takes that diagonal with either
// tie-break (the mesher's union-jack pattern breaks exact ties by position).
BOOST_AUTO_TEST_CASE(double_agrees_with_intervals) {
    const auto keys = prover::consistent_keys();
    int checked = 0;
    const std::map<int, std::pair<double, double>> claims[2] = {key_claims("maxmin"), key_claims("separating")};
    for (std::size_t i = 0; i < keys.size(); i += 173) {
        for (DiagonalRule rule : {DiagonalRule::maxmin, DiagonalRule::separating}) {
            const auto& k = keys[i];
            const auto vars = prover::key_vars(k);
            const auto it = claims[rule == DiagonalRule::separating].find(static_cast<int>(i));
            if (it == claims[rule == DiagonalRule::separating].end()) continue;
            const auto proof = prover::prove_key(rule, k, it->second.first, it->second.second, 20000);
            BOOST_TEST(proof.ok);
            for (const auto& leaf : proof.leaves) {
                if (leaf.diag == 3) continue;
                for (int s = 0; s < 5; ++s) {
                    std::array<double, 4> t{};
                    std::array<Warp, 4> w{};
                    for (int c = 0; c < 4; ++c) w[c] = k.s[c].warp;
                    for (std::size_t j = 0; j < vars.size(); ++j) {
                        const double lo = std::ldexp(double(leaf.num[2 * j]), -leaf.k);
                        const double hi = std::ldexp(double(leaf.num[2 * j + 1]), -leaf.k);
                        const double u = s == 0 ? 0.5 : ((s + j) % 3) / 2.0;
                        t[vars[j]] = lo + u * (hi - lo);
                    }
                    for (TieBreak tie : {TieBreak::ad, TieBreak::bc}) {
                        const Choice ch = choose_diagonal<double>(rule, generic_positions<double>(w, t), k.s, tie);
                        BOOST_TEST((ch.ad ? 1 : 2) == int(leaf.diag));
                    }
                    ++checked;
                }
            }
        }
    }
    BOOST_TEST(checked > 100);
}

// Exact ties (issue 33): the mesher breaks them by position (union_jack), so
// the prover must never decide a box on which the two diagonals can tie.  On
// the unit square (key -s-s-s-s, no parameter) and on a warped key at a
// symmetric point (A and B slide +y by the same t: a rectangle, symmetric
// about x = 1/2, whose diagonals give congruent triangles),
// the double rule takes the tie-break, and the prover's interval choice
// leaves both diagonals open, so the certificate bounds both.
BOOST_AUTO_TEST_CASE(exact_ties_are_never_decided) {
    const auto keys = prover::consistent_keys();
    auto find = [&](const std::string& code) {
        for (const auto& k : keys)
            if (prover::code_of(k) == code) return k;
        BOOST_FAIL("no key " + code);
        return keys[0];
    };
    for (const auto& [code, tval] : {std::pair<std::string, double>{"-s-s-s-s", 0.0}, {"-U-U+s+s", 0.25}}) {
        const prover::Key k = find(code);
        std::array<Warp, 4> w{};
        std::array<double, 4> t{};
        for (int c = 0; c < 4; ++c) w[c] = k.s[c].warp, t[c] = k.s[c].warp == Warp::stay ? 0.0 : tval;
        const auto p = generic_positions<double>(w, t);
        BOOST_TEST(diagonal_quality(p, Diagonal::AD).worst_cot == diagonal_quality(p, Diagonal::BC).worst_cot);
        for (DiagonalRule rule : {DiagonalRule::maxmin, DiagonalRule::separating, DiagonalRule::fan}) {
            BOOST_TEST(choose_diagonal<double>(rule, p, k.s, TieBreak::ad).ad);
            BOOST_TEST(choose_diagonal<double>(rule, p, k.s, TieBreak::bc).bc);
            std::array<double, 4> lo{}, hi{};
            const auto vars = prover::key_vars(k);
            for (std::size_t j = 0; j < vars.size(); ++j) lo[j] = hi[j] = tval;
            BOOST_TEST(prover::interval_choice(rule, k, lo, hi) == 3);  // both diagonals open
        }
    }
}

// Witness lines of the committed certificates: exact re-evaluation with
// rationals of the chosen diagonal's extreme cotangent.
BOOST_AUTO_TEST_CASE(witnesses_exact) {
    for (const char* name : {"maxmin", "separating", "materials"}) {  // materials.cert: the junction keys
        const auto keys = std::string(name) == "materials" ? prover::junction_keys() : prover::consistent_keys();
        std::ifstream in(std::filesystem::path(WARPMESH_PROOFS_DIR) / (std::string(name) + ".cert"));
        BOOST_REQUIRE(in.good());
        const DiagonalRule rule = std::string(name) == "maxmin" ? DiagonalRule::maxmin : DiagonalRule::separating;
        int seen = 0;
        for (std::string line; std::getline(in, line);) {
            if (line.rfind("witness ", 0) != 0) continue;
            std::istringstream ss(line);
            std::vector<std::string> tok;
            for (std::string t; ss >> t;) tok.push_back(t);
            if (tok[2] == "inverted") continue;
            const prover::Key* key = nullptr;
            for (const auto& k : keys)
                if (prover::code_of(k) == tok[3]) key = &k;
            BOOST_REQUIRE(key);
            const auto vars = prover::key_vars(*key);
            std::array<Q, 4> t{};
            for (std::size_t j = 0; j < vars.size(); ++j) t[vars[j]] = Q(tok[4 + j]);
            std::array<Point<Q>, 4> p;
            for (int c = 0; c < 4; ++c) {
                const Warp w = key->s[c].warp;
                p[c] = {Q(c & 1) + warp_dx(w) * t[c], Q(c >> 1) + warp_dy(w) * t[c]};
            }
            // The chosen diagonal, exactly (max-min on exact forms; separating forcing).
            auto quality = [&](Diagonal d, bool& valid) {
                Q q = -1000000;
                valid = true;
                for (const auto& tri : diagonal_triangles(d)) {
                    const auto f = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]]);
                    if (f.cross <= 0) {
                        valid = false;
                        continue;
                    }
                    for (const Q& dot : f.dot) q = std::max(q, Q(dot / f.cross));
                }
                return q;
            };
            bool va = false, vb = false;
            const Q qa = quality(Diagonal::AD, va), qb = quality(Diagonal::BC, vb);
            Diagonal d = vb && (!va || qb < qa) ? Diagonal::BC : Diagonal::AD;
            Diagonal forced{};
            if (rule == DiagonalRule::separating &&
                (key->junction ? separating_diagonal(key->m, forced) : separating_diagonal(key->s, forced)))
                d = forced;
            Q lo = 1000000, hi = -1000000;
            for (const auto& tri : diagonal_triangles(d)) {
                const auto f = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]]);
                BOOST_REQUIRE(f.cross > 0);
                for (const Q& dot : f.dot) lo = std::min(lo, Q(dot / f.cross)), hi = std::max(hi, Q(dot / f.cross));
            }
            BOOST_TEST((tok[2] == "min" ? hi : lo) == Q(tok.back()), line);
            ++seen;
        }
        BOOST_TEST(seen >= 2);
    }
}
