// The 3D prover on A15 keys (prover/src/bcc/a15.cpp, issue 51): root boxes
// enclose the exact parameter boxes; the stencils admitted on a box include
// the rule's stencil at every exact point of it, ties both ways; the branch
// and bound proves tight claims that bracket the keys' witnesses, and fails
// a claim stricter than a witness; the class-1 prism's largest angle is
// found at the exact tie on a corner of its box (proofs/README.md, "The A15
// space").
#define BOOST_TEST_MODULE bcc_a15_prover
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>

#include "warpmesh/prove_bcc.hpp"
#include "exact_rational.hpp"

using namespace warpmesh;
using namespace warpmesh::bcc_prover;
using boost::multiprecision::cpp_rational;
using warpmesh::testing::Q;

namespace {

const a15::Alphas alphas{{39, 100}, {35, 100}, {35, 100}, {35, 100}};

cpp_rational exact(double x) { return cpp_rational(x); }  // doubles are dyadic rationals

bool same(const bcc::Stencil& a, const bcc::Stencil& b) {
    if (a.count != b.count) return false;
    for (std::size_t j = 0; j < static_cast<std::size_t>(a.count); ++j)
        if (a.tet[j] != b.tet[j]) return false;
    return true;
}

a15::Key key(const std::string& code) {
    for (const a15::Key& k : a15::enumerate_keys())
        if (a15::code_of(k) == code) return k;
    BOOST_FAIL("no key " + code);
    return {};
}

}  // namespace

BOOST_AUTO_TEST_CASE(root_boxes_enclose_the_exact_boxes) {
    for (const a15::Key& k : a15::enumerate_keys()) {
        const Subject s = a15_subject(k, alphas);
        const auto ps = a15::key_params(k, alphas);
        BOOST_TEST_REQUIRE(s.ps.size() == ps.size());
        for (std::size_t i = 0; i < ps.size(); ++i) {
            BOOST_TEST(s.ps[i].index == ps[i].index);
            BOOST_TEST((exact(s.ps[i].root_lo) <= cpp_rational(ps[i].lo.num, ps[i].lo.den)));
            BOOST_TEST((exact(s.ps[i].root_hi) >= cpp_rational(ps[i].hi.num, ps[i].hi.den)));
            BOOST_TEST(std::ldexp(s.ps[i].root_lo, 20) == std::floor(std::ldexp(s.ps[i].root_lo, 20)));
            BOOST_TEST(std::ldexp(s.ps[i].root_hi, 20) == std::floor(std::ldexp(s.ps[i].root_hi, 20)));
        }
    }
}

BOOST_AUTO_TEST_CASE(admissible_stencils_hold_the_rule_at_every_exact_point) {
    // Keys with a quad: exact points of their boxes (random on a 1/64 grid,
    // and ties of a face quad constructed exactly); the rule's stencil with
    // exact signs, under either global order of a tie, is admitted on the
    // point's degenerate box and on a box around it.
    std::mt19937 rng(15);
    int checked = 0, ties = 0;
    for (const a15::Key& k : a15::enumerate_keys()) {
        int a = -1, b = -1, r = -1, f = 0;
        while (f < 4 && !bcc::quad_face(k.sign, f, a, b, r)) ++f;
        if (f == 4) continue;
        const Subject s = a15_subject(k, alphas);
        for (int trial = 0; trial < 3; ++trial) {
            std::array<Q, 6> u{};
            for (auto& x : u) x = {cpp_rational(1, 2)};
            Box box, around;
            box.m = around.m = static_cast<int>(s.ps.size());
            for (std::size_t i = 0; i < s.ps.size(); ++i) {
                const double x = std::ldexp(std::round(std::ldexp(s.ps[i].lo + (s.ps[i].hi - s.ps[i].lo) * std::uniform_real_distribution<double>(0, 1)(rng), 6)), -6);
                const double y = std::clamp(x, s.ps[i].lo, s.ps[i].hi);
                box.lo[i] = box.hi[i] = y;
                around.lo[i] = y - 0x1p-10, around.hi[i] = y + 0x1p-10;
                if (s.ps[i].index >= 4) u[static_cast<std::size_t>(s.ps[i].index - 4)] = {exact(y)};
            }
            if (trial == 0) {  // a tie on face f: u_b from P_a = P_b, when it lies in its box
                const auto ea = static_cast<std::size_t>(bcc::edge_index(a, r)), eb = static_cast<std::size_t>(bcc::edge_index(b, r));
                const cpp_rational ua = bcc::tet_edges[ea][0] == a ? u[ea].q : 1 - u[ea].q;
                const cpp_rational ub = 1 - cpp_rational(a15::local_len2(k.cls, a, r)) * (1 - ua) / a15::local_len2(k.cls, b, r);
                const cpp_rational v = bcc::tet_edges[eb][0] == b ? ub : 1 - ub;
                const double vd = v.convert_to<double>();
                if (cpp_rational(vd) != v) continue;  // not dyadic: skip
                for (std::size_t i = 0; i < s.ps.size(); ++i)
                    if (s.ps[i].index == 4 + static_cast<int>(eb)) {
                        if (vd < s.ps[i].lo || vd > s.ps[i].hi) break;
                        box.lo[i] = box.hi[i] = vd, around.lo[i] = vd - 0x1p-10, around.hi[i] = vd + 0x1p-10;
                        u[eb] = {v};
                        ++ties;
                    }
            }
            const auto on_point = admissible_a15_stencils(s, box), on_box = admissible_a15_stencils(s, around);
            for (bool order : {false, true}) {
                std::array<a15::Ivec, 4> global{};
                for (std::size_t i = 0; i < 4; ++i) global[i] = {order ? 3 - static_cast<int>(i) : static_cast<int>(i), 0, 0};
                const bcc::Stencil st = bcc::stencil_with(k.sign, a15::delaunay_diagonals(k.cls, k.sign, u, global));
                BOOST_TEST(std::any_of(on_point.begin(), on_point.end(), [&](const auto& o) { return same(o, st); }));
                BOOST_TEST(std::any_of(on_box.begin(), on_box.end(), [&](const auto& o) { return same(o, st); }));
                ++checked;
            }
        }
    }
    BOOST_TEST(checked > 900);
    BOOST_TEST(ties > 50);
}

BOOST_AUTO_TEST_CASE(tight_claims_bracket_the_witnesses) {
    // The worst keys found at (0.39, 0.35, 0.35, 0.35): proved tight; the
    // claimed minimum is at most the witness's angle and within 0.01° of it
    // (the maximum: at least, within 0.1°); a claim 0.01° stricter than the
    // witness's minimum fails.
    for (const std::string code : {"0:0f,0g,+,-", "0:0k,0j,-,0m"}) {
        const Subject s = a15_subject(key(code), alphas);
        const KeyProof p = prove_subject_tight(s);
        BOOST_TEST_REQUIRE(p.ok, code);
        const double wmin = std::acos(p.wmin.cos) * 180 / M_PI, cmin = std::acos(std::sqrt(p.claim.cmin)) * 180 / M_PI;
        const double wmax = std::acos(p.wmax.cos) * 180 / M_PI, cmax = 180 - std::acos(std::sqrt(p.claim.cmax)) * 180 / M_PI;
        BOOST_TEST((cmin <= wmin && wmin - cmin < 0.01), code << " " << cmin << " " << wmin);
        BOOST_TEST((cmax >= wmax && cmax - wmax < 0.1), code << " " << cmax << " " << wmax);
        Claim stricter = p.claim;
        const double c = std::cos((wmin + 0.01) * M_PI / 180);
        stricter.cmin = c * c;
        BOOST_TEST(!prove_subject(s, stricter, default_max_depth, 20000).ok, code);
    }
}

BOOST_AUTO_TEST_CASE(the_class_2_prism_is_proved_under_a_cap) {
    // 2:-,-,+,+ (n- = 2, n+ = 2 in the BBBB class): its inside quad's tie
    // admits both diagonals on the boxes that straddle it, and the witness
    // search (the rule's own values) does not follow that tie, so a tight
    // claim is out of the search's reach; the caps (11°, 160°) are proved.
    const Subject s = a15_subject(key("2:-,-,+,+"), alphas);
    BOOST_TEST(prove_subject(s, cap_claim(11.0, 160.0)).ok);
    BOOST_TEST(!prove_subject(s, cap_claim(14.0, 160.0), default_max_depth, 20000).ok);
}

BOOST_AUTO_TEST_CASE(the_class_1_prism_peaks_at_an_exact_tie_on_a_corner) {
    // 1:+,-,-,+: where its four cut fractions are equal its two face quads
    // and its inside quad all tie (a line of the box, by the class's
    // threefold symmetry); the mesher on the reference tetrahedron then takes
    // the face diagonals by the reference's coordinate order and the inside
    // quad's against the face (a, b, r0), and the largest dihedral angle
    // grows to 155.286° at the line's end, the corner where all four
    // parameters are at their upper end, 0.65.  Off the line the rule's
    // stencil stays near 150°, so the grid search does not find it; the
    // search tries the exact corners, and the certificate writes their
    // coordinates as the exact ends.
    const Subject s = a15_subject(key("1:+,-,-,+"), alphas);
    const Witness w = search_subject(s, -1);
    const double wmax = std::acos(w.cos) * 180 / M_PI;
    BOOST_TEST((wmax > 155.28 && wmax < 155.29), wmax);
    for (std::size_t i = 0; i < s.ps.size(); ++i) {
        a15::Fraction end{};
        BOOST_TEST_REQUIRE(a15_exact_end(s, i, w.x[i], end));
        BOOST_TEST((end.num * 100 == 65 * end.den));
    }
    std::array<double, 4> off = w.x;  // off the tie line, one grid step
    for (std::size_t i = 0; i < s.ps.size(); ++i) off[i] = std::floor(std::ldexp(w.x[i], 24)) / 16777216.0 - (i == 0 ? 0x1p-24 : 0);
    BOOST_TEST(std::acos(subject_witness_cos(s, off, -1)) * 180 / M_PI < 151.0);
}
