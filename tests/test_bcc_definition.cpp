// The 3D definition (generic_bcc.hpp): the lattice and its background
// tetrahedra, the parity rule and its local bit, the stencils, and a small
// stuffing of random level sets (warpmesh/bcc_stuffing.hpp) that must be conforming
// and positively oriented, with every background tetrahedron reproduced by
// its local configuration (the prover's key and parameters).
#define BOOST_TEST_MODULE bcc_definition
#include <map>
#include <random>
#include <set>

#include "warpmesh/bcc_stuffing.hpp"
#include "support.hpp"

using namespace warpmesh;
using namespace warpmesh::testing;
using namespace warpmesh::bcc_stuffing;

namespace {

std::vector<std::array<bcc::Ivec, 4>> block_tets(int n) {
    std::vector<std::array<bcc::Ivec, 4>> out;
    for (int z = 0; z < n; ++z)
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                for (int i = 0; i < 12; ++i) out.push_back(bcc::background_tet({2 * x, 2 * y, 2 * z}, i));
    return out;
}

int norm2(const bcc::Ivec& d) { return d[0] * d[0] + d[1] * d[1] + d[2] * d[2]; }

}  // namespace

BOOST_AUTO_TEST_CASE(background_tets_are_congruent_and_tile_space) {
    const auto tets = block_tets(4);
    std::map<std::array<bcc::Ivec, 3>, int> faces;
    for (const auto& p : tets) {
        BOOST_TEST(bcc::orientation(p) == 4);  // volume 4/6 in doubled units: 12 per cube of volume 8
        BOOST_TEST(bcc::is_corner(p[0]));
        BOOST_TEST(bcc::is_corner(p[1]));
        BOOST_TEST(!bcc::is_corner(p[2]));
        BOOST_TEST(!bcc::is_corner(p[3]));
        for (int e = 0; e < 6; ++e) {
            const auto& ed = bcc::tet_edges[static_cast<std::size_t>(e)];
            BOOST_TEST(norm2(bcc::sub(p[static_cast<std::size_t>(ed[1])], p[static_cast<std::size_t>(ed[0])])) == (bcc::edge_is_long(e) ? 4 : 3));
        }
        for (int skip = 0; skip < 4; ++skip) {
            std::array<bcc::Ivec, 3> f{};
            int k = 0;
            for (int i = 0; i < 4; ++i)
                if (i != skip) f[static_cast<std::size_t>(k++)] = p[static_cast<std::size_t>(i)];
            std::sort(f.begin(), f.end());
            ++faces[f];
        }
    }
    // Faces inside [2, 6]^3 (doubled), away from the block's sides, are shared by exactly two tetrahedra.
    int interior = 0;
    for (const auto& [f, count] : faces) {
        bool in = true;
        for (const auto& q : f)
            for (int k = 0; k < 3; ++k) in = in && q[static_cast<std::size_t>(k)] >= 2 && q[static_cast<std::size_t>(k)] <= 6;
        if (!in) continue;
        ++interior;
        BOOST_TEST(count == 2);
    }
    BOOST_TEST(interior > 50);
}

BOOST_AUTO_TEST_CASE(parity_rule_names_one_diagonal_from_both_ends) {
    for (const auto& p : block_tets(2))
        for (int e = 0; e < 2; ++e) {
            const auto& ed = bcc::tet_edges[static_cast<std::size_t>(e)];
            for (int r = 0; r < 4; ++r) {
                if (r == ed[0] || r == ed[1]) continue;
                const auto& A = p[static_cast<std::size_t>(ed[0])];
                const auto& B = p[static_cast<std::size_t>(ed[1])];
                BOOST_TEST(bcc::parity_takes_a(A, B, p[static_cast<std::size_t>(r)]) != bcc::parity_takes_a(B, A, p[static_cast<std::size_t>(r)]));
            }
        }
}

BOOST_AUTO_TEST_CASE(local_parity_bit_reproduces_every_parity_decision) {
    std::set<int> bits;
    for (const auto& p : block_tets(2)) {
        const int pi = bcc::tet_parity(p);
        bits.insert(pi);
        for (int e = 0; e < 2; ++e)
            for (int flip = 0; flip < 2; ++flip) {
                const int a = bcc::tet_edges[static_cast<std::size_t>(e)][static_cast<std::size_t>(flip)];
                const int b = bcc::tet_edges[static_cast<std::size_t>(e)][static_cast<std::size_t>(1 - flip)];
                for (int r = 0; r < 4; ++r) {
                    if (r == a || r == b) continue;
                    BOOST_TEST(bcc::parity_takes_a(p[static_cast<std::size_t>(a)], p[static_cast<std::size_t>(b)], p[static_cast<std::size_t>(r)]) ==
                               bcc::face_takes_a(a, b, r, pi));
                }
            }
    }
    BOOST_TEST(bits.size() == 2u);  // both bits occur: the rule is not symmetric under the tet's reflections
}

BOOST_AUTO_TEST_CASE(stencils_are_positive_in_the_reference_configuration) {
    for (int code = 0; code < 81; ++code)
        for (int parity = 0; parity < 2; ++parity) {
            std::array<int, 4> sign{};
            for (int i = 0, c = code; i < 4; ++i, c /= 3) sign[static_cast<std::size_t>(i)] = c % 3 - 1;
            const bcc::Stencil st = bcc::stencil(sign, parity);
            int neg = 0, pos = 0;
            for (int s : sign) neg += s < 0, pos += s > 0;
            // No - vertex: nothing, all-zero included (never output).
            const int expect = neg == 0 ? 0 : pos == 0 || neg == 1 ? 1 : neg == 2 && pos == 1 ? 2 : 3;
            BOOST_TEST(st.count == expect);
            long volume = 0;
            for (int k = 0; k < st.count; ++k) {
                std::array<bcc::Ivec, 4> q{};
                for (int v = 0; v < 4; ++v) q[static_cast<std::size_t>(v)] = bcc::reference_point(st.tet[static_cast<std::size_t>(k)][static_cast<std::size_t>(v)]);
                BOOST_TEST(bcc::orientation(q) > 0);
                volume += bcc::orientation(q);
                for (int v = 0; v < 4; ++v) {  // only the -, 0 vertices and the (-, +) cut points
                    const int pt = st.tet[static_cast<std::size_t>(k)][static_cast<std::size_t>(v)];
                    if (pt < 4) BOOST_TEST(sign[static_cast<std::size_t>(pt)] <= 0);
                    else {
                        const auto& ed = bcc::tet_edges[static_cast<std::size_t>(pt - 4)];
                        BOOST_TEST(sign[static_cast<std::size_t>(ed[0])] * sign[static_cast<std::size_t>(ed[1])] == -1);
                    }
                }
            }
            // Volume of the inside part with cut points at the midpoints (quadrupled
            // units: the whole tetrahedron is 4 * 8 = 32): the corner cut off at the
            // midpoints is 1/8 of it, the prism of two - and two + vertices 1/2.
            if (pos == 0 && neg > 0) BOOST_TEST(volume == 32);
            if (neg == 1 && pos == 3) BOOST_TEST(volume == 4);
            if (neg == 3 && pos == 1) BOOST_TEST(volume == 32 - 4);
            if (neg == 2 && pos == 2) BOOST_TEST(volume == 16);
        }
}

BOOST_AUTO_TEST_CASE(stuffed_random_shapes_are_conforming_and_reproduced_by_their_keys) {
    std::mt19937 rng(29);
    const int n = 6;
    std::set<int> seen;  // stencil size, parity quad, parity bit
    for (int trial = 0; trial < scaled(40); ++trial) {
        const Quadric f = random_shape(rng, n);
        const Stuffed m = stuff(f, n, 1.0, bcc::labelle_shewchuk_alphas);
        BOOST_REQUIRE(!m.tets.empty());
        const Conformity c = conformity(m, n);
        BOOST_TEST(c.ok());
        BOOST_TEST(c.interior > 0);
        BOOST_TEST(c.volume > 0);
        for (const StuffedTet& bt : m.background) {
            bool long_quad = false;  // a quad on a long edge: the parity rule decides
            for (int e = 0; e < 2; ++e) {
                const auto& ed = bcc::tet_edges[static_cast<std::size_t>(e)];
                long_quad = long_quad || (bt.config.sign[static_cast<std::size_t>(ed[0])] < 0 && bt.config.sign[static_cast<std::size_t>(ed[1])] < 0 && bt.count > 1);
            }
            seen.insert(bt.count * 4 + (long_quad ? 2 : 0) + bt.config.parity);
        }
        // Each background tetrahedron's configuration reproduces its output tetrahedra.
        for (const StuffedTet& bt : m.background) {
            const auto q = bcc::generic_points(bt.config, bt.t, bt.u);
            const bcc::Stencil st = bcc::stencil(bt.config.sign, bt.config.parity);
            BOOST_REQUIRE(st.count == bt.count);
            for (int k = 0; k < bt.count; ++k) {
                std::array<bcc::Vec<double>, 4> a{}, b{};
                for (int v = 0; v < 4; ++v) {
                    a[static_cast<std::size_t>(v)] = q[st.tet[static_cast<std::size_t>(k)][static_cast<std::size_t>(v)]];
                    b[static_cast<std::size_t>(v)] = m.points[static_cast<std::size_t>(m.tets[static_cast<std::size_t>(bt.first + k)][static_cast<std::size_t>(v)])];
                }
                const auto da = dihedral_degrees(a), db = dihedral_degrees(b);
                for (int e = 0; e < 6; ++e) BOOST_TEST(std::fabs(da[static_cast<std::size_t>(e)] - db[static_cast<std::size_t>(e)]) < 1e-7);
                // volumes in doubled units: 8 times the mesh's
                BOOST_TEST(std::fabs(bcc::dihedral_forms(a).volume6 - 8 * bcc::dihedral_forms(b).volume6) < 1e-9);
            }
        }
    }
    for (int count = 2; count <= 3; ++count)  // pyramids and prisms, decided by the parity rule both ways
        for (int parity = 0; parity < 2; ++parity) BOOST_TEST(seen.count(count * 4 + 2 + parity) == 1u);
}
