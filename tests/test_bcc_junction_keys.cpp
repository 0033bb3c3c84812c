// The junction keys of the BCC generic tetrahedron (generic_bcc_materials.hpp:
// JunctionKey, its symmetries and canonical form; prover/src/bcc/junctions.cpp:
// consistency, enumeration, parameters, the decomposition by faces): a key's
// image under a symmetry has the same output geometry (so letters are
// re-lettered and the parity bit carried correctly), every consistent key's
// canonical form is enumerated, junction_points is junction_points12 / 12,
// and a face's cone tetrahedra depend on its parameters only.
#define BOOST_TEST_MODULE bcc_junction_keys
#include <random>
#include <set>

#include "support.hpp"
#include "warpmesh/bcc_stuffing.hpp"  // dihedral_degrees
#include "warpmesh/prove_bcc.hpp"

using namespace warpmesh;
using namespace warpmesh::testing;
using warpmesh::bcc_stuffing::dihedral_degrees;
namespace bp = warpmesh::bcc_prover;

namespace {

// Every consistent junction key (not only canonical ones).
std::vector<bcc::JunctionKey> consistent_keys() {
    std::vector<bcc::JunctionKey> out;
    for (int code = 0; code < 18 * 18 * 18 * 18 * 2; ++code) {
        bcc::JunctionKey k;
        for (std::size_t i = 0, c = static_cast<std::size_t>(code / 2); i < 4; ++i, c /= 18) {
            k.letter[i] = c % 18 < 4 ? static_cast<int>(c % 18) : -1;
            k.warp[i] = c % 18 < 4 ? bcc::stay : static_cast<int>(c % 18) - 4;
        }
        k.parity = code % 2;
        if (bp::junction_consistent(k)) out.push_back(k);
    }
    return out;
}

// Sorted dihedral angles and 1000 × the volumes of the key's output at (t, u).
std::vector<double> angles(const bcc::JunctionKey& k, const std::array<double, 4>& t, const std::array<double, 6>& u) {
    const auto q = bcc::junction_points(bcc::junction_config(k), t, u);
    const bcc::MaterialStencil st = bcc::junction_stencil(k.letter, k.parity);
    std::vector<double> out;
    for (int j = 0; j < st.count; ++j) {
        std::array<bcc::Vec<double>, 4> p{};
        for (std::size_t v = 0; v < 4; ++v) p[v] = q[st.tet[static_cast<std::size_t>(j)].tet[v]];
        out.push_back(1000 * bcc::dihedral_forms(p).volume6);  // orientation preserved too
        for (double a : dihedral_degrees(p)) out.push_back(a);
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(a_junction_key_and_its_images_have_the_same_output_geometry) {
    std::mt19937 rng(47);
    std::uniform_real_distribution<double> U(0.05, 0.45);
    int parity_keys = 0;
    for (const bcc::JunctionKey& k : consistent_keys()) {
        parity_keys += bcc::has_junction_parity_quad(k.letter);
        std::array<double, 4> t{};
        std::array<double, 6> u{};
        for (double& x : t) x = U(rng);
        for (double& x : u) x = 0.5 + U(rng) - 0.25;
        const auto ref = angles(k, t, u);
        for (const bcc::Symmetry& s : bcc::symmetries) {
            const bcc::JunctionKey d = bcc::transform(k, s);
            std::array<double, 4> t2{};
            std::array<double, 6> u2{};
            bcc::transform_params(s, t, u, t2, u2);
            BOOST_TEST(bp::junction_consistent(d), bcc::code_of(k) << " -> " << bcc::code_of(d));
            const auto img = angles(d, t2, u2);
            BOOST_REQUIRE(img.size() == ref.size());
            for (std::size_t i = 0; i < ref.size(); ++i) BOOST_TEST(std::fabs(img[i] - ref[i]) < 1e-8, bcc::code_of(k) << " -> " << bcc::code_of(d));
        }
    }
    BOOST_TEST(parity_keys > 0);
}

BOOST_AUTO_TEST_CASE(every_consistent_key_has_an_enumerated_canonical_form) {
    const auto keys = bp::enumerate_junction_keys();
    std::set<std::string> codes;
    for (const auto& k : keys) codes.insert(bcc::code_of(k));
    BOOST_TEST(codes.size() == keys.size());
    // Three keys without a warp (two letters on a long edge, on a short one,
    // four letters) and nine with one: a vertex (all equivalent), its 14
    // directions up to the reflection that fixes it (a, b, c, d fixed; e..n
    // in five pairs).
    BOOST_TEST(keys.size() == 12u);
    std::set<std::string> seen;
    for (const auto& k : consistent_keys()) {
        const bcc::JunctionKey c = bcc::canonical(k);
        BOOST_TEST(codes.count(bcc::code_of(c)) == 1u, bcc::code_of(k));
        seen.insert(bcc::code_of(c));
    }
    BOOST_TEST(seen.size() == keys.size());
}

BOOST_AUTO_TEST_CASE(junction_points_are_junction_points12_over_12) {
    std::mt19937 rng(48);
    std::uniform_real_distribution<double> U(0.05, 0.45);
    for (const bcc::JunctionKey& k : bp::enumerate_junction_keys()) {
        std::array<double, 4> t{};
        std::array<double, 6> u{};
        for (double& x : t) x = U(rng);
        for (double& x : u) x = 0.5 + U(rng) - 0.25;
        const auto p = bcc::junction_points(bcc::junction_config(k), t, u);
        const auto p12 = bcc::junction_points12(bcc::junction_config(k), t, u);
        const auto g = bcc::generic_points(bcc::junction_config(k), t, u);
        for (std::size_t q = 0; q < 15; ++q)
            for (std::size_t c = 0; c < 3; ++c) {
                BOOST_TEST(std::fabs(12 * p[q][c] - p12[q][c]) < 1e-12);
                if (q < 10) BOOST_TEST(p[q][c] == g[q][c]);
            }
        // The face point is the average of its face's cut points, the centre of the vertices.
        for (std::size_t c = 0; c < 3; ++c) {
            BOOST_TEST(std::fabs(p[bcc::face_point(3)][c] - (g[4][c] + g[6][c] + g[8][c]) / 3) < 1e-12);  // face 0 1 2: edges 01, 02, 12
            BOOST_TEST(std::fabs(p[bcc::centre_point][c] - (g[0][c] + g[1][c] + g[2][c] + g[3][c]) / 4) < 1e-12);
        }
    }
}

// A face's tetrahedra, as the face's subject evaluates them, do not move
// when a parameter outside the face's list changes; the four faces' lists
// cover the stencil.
BOOST_AUTO_TEST_CASE(a_face_depends_on_its_parameters_only) {
    std::mt19937 rng(49);
    std::uniform_real_distribution<double> U(0.05, 0.45);
    for (const bcc::JunctionKey& k : bp::enumerate_junction_keys()) {
        std::size_t tets = 0;
        for (int f = 0; f < 4; ++f) {
            const auto face = bp::junction_face_tets(k, f);
            tets += face.size();
            std::array<double, 4> t{};
            std::array<double, 6> u{};
            for (double& x : t) x = U(rng);
            for (double& x : u) x = 0.5 + U(rng) - 0.25;
            const auto p = bcc::junction_points12(bcc::junction_config(k), t, u);
            std::array<double, 4> t2 = t;
            std::array<double, 6> u2 = u;
            std::set<int> mine;
            for (const bp::Param& q : bp::junction_face_params(k, f, bcc::parity_alphas)) mine.insert(q.index);
            for (int i = 0; i < 4; ++i)
                if (!mine.count(i)) t2[static_cast<std::size_t>(i)] += 0.1;
            for (int e = 0; e < 6; ++e)
                if (!mine.count(4 + e)) u2[static_cast<std::size_t>(e)] += 0.1;
            const auto p2 = bcc::junction_points12(bcc::junction_config(k), t2, u2);
            for (const bcc::OutTet& tet : face)
                for (const std::uint8_t q : tet) BOOST_TEST((p[q] == p2[q]), bcc::code_of(k) << " face " << f << " point " << int(q));
        }
        BOOST_TEST(tets == static_cast<std::size_t>(bcc::junction_stencil(k.letter, k.parity).count));
    }
}
