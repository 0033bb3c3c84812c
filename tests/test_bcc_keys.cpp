// The keys of the BCC generic tetrahedron (prover/src/bcc/keys.cpp): the
// symmetries are lattice isometries of the reference tetrahedron, a key's
// image under one has the same output geometry (so the parity bit is carried
// correctly), and every background tetrahedron of a stuffed random shape is
// consistent with a canonical key of the enumeration.
#define BOOST_TEST_MODULE bcc_keys
#include <random>
#include <set>

#include "warpmesh/bcc_stuffing.hpp"
#include "support.hpp"
#include "warpmesh/prove_bcc.hpp"

using namespace warpmesh;
using namespace warpmesh::testing;
using namespace warpmesh::bcc_stuffing;
namespace bp = warpmesh::bcc_prover;

namespace {

// Sorted dihedral angles and volumes (x1000, apart from the angles) of the key's output at (t, u).
std::vector<double> angles(const bcc::Config& c, const std::array<double, 4>& t, const std::array<double, 6>& u) {
    const auto q = bcc::generic_points(c, t, u);
    const bcc::Stencil st = bcc::stencil(c.sign, c.parity);
    std::vector<double> out;
    for (int k = 0; k < st.count; ++k) {
        std::array<bcc::Vec<double>, 4> p{};
        for (int v = 0; v < 4; ++v) p[static_cast<std::size_t>(v)] = q[st.tet[static_cast<std::size_t>(k)][static_cast<std::size_t>(v)]];
        out.push_back(1000 * bcc::dihedral_forms(p).volume6);  // orientation preserved too
        for (double a : dihedral_degrees(p)) out.push_back(a);
    }
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(symmetries_are_lattice_isometries_of_the_reference_tet) {
    std::set<std::array<int, 4>> perms;
    for (const bp::Symmetry& s : bcc::symmetries) {
        perms.insert(s.perm);
        for (int i = 0; i < 4; ++i) {
            const bcc::Ivec d = bcc::sub(bcc::reference_tet[static_cast<std::size_t>(i)], bcc::reference_tet[0]);
            bcc::Ivec img{};
            for (std::size_t k = 0; k < 3; ++k) img[k] = s.lin[0][k] * d[0] + s.lin[1][k] * d[1] + s.lin[2][k] * d[2];
            BOOST_TEST((img == bcc::sub(bcc::reference_tet[static_cast<std::size_t>(s.perm[static_cast<std::size_t>(i)])],
                                        bcc::reference_tet[static_cast<std::size_t>(s.perm[0])])));
        }
        for (int d = 0; d < bcc::direction_count; ++d) {  // directions map to directions
            bcc_prover::Key k;
            k.sign = {0, -1, 1, 1};
            k.warp = {d, bcc::stay, bcc::stay, bcc::stay};
            BOOST_TEST(bp::transform(k, s).warp[static_cast<std::size_t>(s.perm[0])] != bcc::stay);
        }
    }
    BOOST_TEST(perms.size() == 8u);
}

BOOST_AUTO_TEST_CASE(a_key_and_its_images_have_the_same_output_geometry) {
    std::mt19937 rng(31);
    std::uniform_real_distribution<double> U(0.05, 0.45);
    std::uniform_int_distribution<int> state(0, 16);
    int checked = 0, parity_keys = 0;
    while (checked < scaled(4000)) {
        bcc::Config c;
        for (std::size_t i = 0; i < 4; ++i) {
            const int s = state(rng);
            c.sign[i] = s == 0 ? -1 : s == 1 ? 1 : 0;
            c.warp[i] = s >= 2 ? s - 2 : bcc::stay;
        }
        c.parity = std::uniform_int_distribution<int>(0, 1)(rng);
        if (!bp::consistent(c) || bcc::stencil(c.sign, c.parity).count == 0) continue;
        parity_keys += bp::has_parity_quad(c.sign);
        std::array<double, 4> t{};
        std::array<double, 6> u{};
        for (double& x : t) x = U(rng);
        for (double& x : u) x = 0.5 + U(rng) - 0.25;
        const auto ref = angles(c, t, u);
        for (const bp::Symmetry& s : bcc::symmetries) {
            const bcc::Config d = bp::transform(c, s);
            std::array<double, 4> t2{};
            std::array<double, 6> u2{};
            bcc::transform_params(s, t, u, t2, u2);
            BOOST_TEST(bp::consistent(d));
            const auto img = angles(d, t2, u2);
            BOOST_REQUIRE(img.size() == ref.size());
            for (std::size_t i = 0; i < ref.size(); ++i) BOOST_TEST(std::fabs(img[i] - ref[i]) < 1e-8);
        }
        ++checked;
    }
    BOOST_TEST(parity_keys > 0);
}

BOOST_AUTO_TEST_CASE(every_stuffed_background_tet_has_an_enumerated_key) {
    const auto keys = bp::enumerate_keys();
    const auto zero_keys = bp::enumerate_keys(true);
    std::set<std::string> codes;
    for (const auto& k : keys) codes.insert(bp::code_of(k));
    for (const auto& k : zero_keys) codes.insert(bp::code_of(k));
    BOOST_TEST(codes.size() == keys.size() + zero_keys.size());  // distinct codes
    std::mt19937 rng(32);
    std::uniform_real_distribution<double> U(-1, 1);
    std::set<std::string> used;
    for (int trial = 0; trial < scaled(30); ++trial) {
        const double cx = 3 + U(rng), cy = 3 + U(rng), cz = 3 + U(rng), r = 2 + 0.5 * U(rng), a = 1 + 0.4 * U(rng);
        const Stuffed m = stuff([&](double x, double y, double z) { return a * (x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz) - r * r; },
                                6, 1.0, bcc::labelle_shewchuk_alphas);
        for (const StuffedTet& bt : m.background) {
            BOOST_TEST(bp::consistent(bp::canonical(bt.config)));  // canonical: parity bit 0 where unused
            const std::string code = bp::code_of(bp::canonical(bt.config));
            BOOST_TEST(codes.count(code) == 1u, code);
            used.insert(code);
            // parameters inside the key's box
            for (const bp::Param& p : bp::key_params(bt.config, bcc::labelle_shewchuk_alphas)) {
                const double x = p.index < 4 ? bt.t[static_cast<std::size_t>(p.index)] : bt.u[static_cast<std::size_t>(p.index - 4)];
                BOOST_TEST((x >= p.lo - 1e-12 && x <= p.hi + 1e-12));
            }
        }
    }
    BOOST_TEST(used.size() > 100u);
}
