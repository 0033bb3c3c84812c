// The Delaunay face rule of generic_bcc.hpp ("The diagonal choices"): its
// linear power form is the empty-circle test of the quad, computed here
// independently from the points; it never makes a cyclic prism and every
// stencil it chooses is positive; ties fall back to the parity rule; and a
// stuffing of random level sets with it is conforming.
#define BOOST_TEST_MODULE bcc_delaunay_rule
#include <random>

#include "warpmesh/bcc_stuffing.hpp"
#include "support.hpp"

using namespace warpmesh;
using namespace warpmesh::testing;
using namespace warpmesh::bcc_stuffing;

namespace {

using V = bcc::Vec<double>;
V sub(const V& a, const V& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }

// The quad (a, b, cb, ca) of a planar convex face: a–cb is Delaunay iff the
// angles opposite it, at b and at ca, sum to at most π: cot + cot >= 0, with
// the sines taken along the face normal n (degree 6 in the points).
double incircle_form(const V& a, const V& b, const V& r, const V& ca, const V& cb) {
    const V n = bcc::cross(sub(b, a), sub(r, a));
    const V u = sub(a, b), v = sub(cb, b), u2 = sub(cb, ca), v2 = sub(a, ca);
    return bcc::dot(u, v) * std::fabs(bcc::dot(bcc::cross(u2, v2), n)) +
           bcc::dot(u2, v2) * std::fabs(bcc::dot(bcc::cross(u, v), n));
}

std::array<int, 4> signs_of(int code) {
    std::array<int, 4> s{};
    for (int i = 0; i < 4; ++i, code /= 3) s[static_cast<std::size_t>(i)] = code % 3 - 1;
    return s;
}

}  // namespace

BOOST_AUTO_TEST_CASE(face_form_is_the_empty_circle_test) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> frac(0.05, 0.95);
    int decided = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        std::array<double, 6> u{};
        for (double& x : u) x = frac(rng);
        const auto P = bcc::generic_points(bcc::Config{}, std::array<double, 4>{}, u);
        for (int a = 0; a < 4; ++a)
            for (int b = a + 1; b < 4; ++b)
                for (int r = 0; r < 4; ++r) {
                    if (r == a || r == b) continue;
                    const double g6 = incircle_form(P[static_cast<std::size_t>(a)], P[static_cast<std::size_t>(b)],
                                                    P[static_cast<std::size_t>(r)], P[static_cast<std::size_t>(bcc::cut_point(a, r))],
                                                    P[static_cast<std::size_t>(bcc::cut_point(b, r))]);
                    if (std::fabs(g6) < 1e-9) continue;
                    ++decided;
                    BOOST_TEST((g6 > 0) == (bcc::face_form(a, b, r, u) > 0));
                    BOOST_TEST(bcc::face_form(a, b, r, u) == -bcc::face_form(b, a, r, u));
                }
    }
    BOOST_TEST(decided > 200000);
}

BOOST_AUTO_TEST_CASE(delaunay_stencils_are_positive_and_never_cyclic) {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> frac(0.2, 0.8);
    std::array<int, 8> free_inside{};  // per parity and inside bit: prisms whose inside quad was free
    for (int code = 0; code < 81; ++code)
        for (int parity = 0; parity < 2; ++parity) {
            const auto sign = signs_of(code);
            const int expected = bcc::stencil(sign, parity).count;
            for (int trial = 0; trial < 400; ++trial) {
                std::array<double, 6> u{};
                for (double& x : u) x = frac(rng);
                const bcc::Diagonals d = bcc::delaunay_diagonals(sign, parity, u);
                const bcc::Stencil st = bcc::stencil_with(sign, d);
                BOOST_REQUIRE(st.count == expected);
                const auto P = bcc::generic_points(bcc::Config{}, std::array<double, 4>{}, u);
                for (int k = 0; k < st.count; ++k) {
                    std::array<V, 4> q{};
                    for (std::size_t v = 0; v < 4; ++v) q[v] = P[st.tet[static_cast<std::size_t>(k)][v]];
                    const double v6 = bcc::dihedral_forms(q).volume6;
                    BOOST_TEST(v6 > 0);
                }
                int nn = 0, np = 0;
                for (int s : sign) nn += s < 0, np += s > 0;
                if (nn == 2 && np == 2) {
                    const auto parts = bcc::stencil_with(sign, bcc::Diagonals{d.face, !d.inside});
                    bool differs = false;
                    for (int k = 0; k < 3; ++k) differs = differs || parts.tet[static_cast<std::size_t>(k)] != st.tet[static_cast<std::size_t>(k)];
                    if (differs) ++free_inside[static_cast<std::size_t>(parity * 2 + (d.inside ? 1 : 0))];
                }
            }
        }
    // The inside quad is free in some prisms, and the shorter diagonal goes both ways.
    for (int parity = 0; parity < 2; ++parity) {
        BOOST_TEST(free_inside[static_cast<std::size_t>(parity * 2)] > 0);
        BOOST_TEST(free_inside[static_cast<std::size_t>(parity * 2 + 1)] > 0);
    }
}

BOOST_AUTO_TEST_CASE(ties_fall_back_to_parity) {
    // Midpoints: on a face whose - vertices a, b are joined by a long edge,
    // ar and br are short and P_a = P_b (cocircular): the parity rule decides.
    // On the others P differs and names the long edge's cut point, as the
    // parity rule's short-AB case does.  So at the midpoints the two rules agree.
    std::array<double, 6> half{};
    half.fill(0.5);
    for (int code = 0; code < 81; ++code)
        for (int parity = 0; parity < 2; ++parity) {
            const auto sign = signs_of(code);
            const bcc::Diagonals d = bcc::delaunay_diagonals(sign, parity, half);
            const auto a = bcc::stencil_with(sign, d), b = bcc::stencil(sign, parity);
            BOOST_TEST(a.count == b.count);
            for (int k = 0; k < a.count; ++k) BOOST_TEST(a.tet[static_cast<std::size_t>(k)] == b.tet[static_cast<std::size_t>(k)]);
        }
    // Off the tie the rule does not read the parity bit.
    std::array<double, 6> u = half;
    u[static_cast<std::size_t>(bcc::edge_index(0, 2))] = 0.4;  // cut(k0, c0) nearer k0: P_k0 = 3 · 0.6 > P_k1
    const std::array<int, 4> sign{-1, -1, 1, 0};                // the face (k0, k1, c0): AB long
    const auto d0 = bcc::delaunay_diagonals(sign, 0, u), d1 = bcc::delaunay_diagonals(sign, 1, u);
    BOOST_TEST(d0.face == d1.face);
    BOOST_TEST(!bcc::takes(d0, 0, 1, 2));  // P_k0 > P_k1: the diagonal is k1–cut(k0, c0)
}

BOOST_AUTO_TEST_CASE(stuffing_with_the_delaunay_rule_is_conforming) {
    std::mt19937 rng(31);
    const int n = 6;
    int changed = 0;
    for (int trial = 0; trial < scaled(30); ++trial) {
        const Quadric f = random_shape(rng, n);
        const Stuffed m = stuff(f, n, 1.0, bcc::Alphas{26750, 100000, 39000, 100000}, nullptr, true);
        BOOST_REQUIRE(!m.tets.empty());
        const Conformity c = conformity(m, n);
        BOOST_TEST(c.ok());
        BOOST_TEST(c.interior > 0);
        for (const StuffedTet& bt : m.background) {
            const bcc::Diagonals p = bcc::parity_diagonals(bt.config.sign, bt.config.parity);
            const auto a = bcc::stencil_with(bt.config.sign, bt.diagonals), b = bcc::stencil_with(bt.config.sign, p);
            for (int k = 0; k < a.count; ++k) changed += a.tet[static_cast<std::size_t>(k)] != b.tet[static_cast<std::size_t>(k)] ? 1 : 0;
        }
    }
    BOOST_TEST(changed > 0);  // the rule differs from parity on real shapes
}
