// The compiled-in certified table (certified.hpp) agrees with proofs/*.cert,
// a corrupted copy is detected, and every key the mesher produces is in it.
#define BOOST_TEST_MODULE certified_table
#include <boost/test/unit_test.hpp>

#include "certified_stage.hpp"
#include "support.hpp"

#include <array>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "warpmesh/certify/certified.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "warpmesh/mesh2d/uniform.hpp"

using namespace warpmesh;

namespace {
using warpmesh::testing::slurp;
// A junction key code ("aRaUbscs") as letters and warps.
std::array<MaterialCorner, 4> junction_from_code(const std::string& code) {
    std::array<MaterialCorner, 4> m{};
    for (std::size_t c = 0; c < 4; ++c)
        m[c] = {static_cast<std::uint16_t>(code[2 * c] - 'a'), static_cast<Warp>(std::string("sRLUD").find(code[2 * c + 1]))};
    return m;
}
// Shape `it` of the random series of the mesher tests: a circle, ellipse,
// flower or annulus (it % 4) at a random offset.
std::string random_shape(std::mt19937& rng, int it) {
    std::uniform_real_distribution<double> u(0, 1);
    std::ostringstream spec;
    spec.precision(17);
    const double cx = u(rng), cy = u(rng);
    switch (it % 4) {
        case 0: spec << "circle:" << cx << "," << cy << "," << 2 + 10 * u(rng); break;
        case 1: spec << "ellipse:" << cx << "," << cy << "," << 2 + 10 * u(rng) << "," << 1 + 5 * u(rng); break;
        case 2: spec << "flower:" << cx << "," << cy << "," << 5 + 5 * u(rng) << "," << 1 + 3 * u(rng) << "," << 3 + it % 5; break;
        default: spec << "annulus:" << cx << "," << cy << "," << 2 + 3 * u(rng) << "," << 6 + 5 * u(rng); break;
    }
    return spec.str();
}
}  // namespace

BOOST_AUTO_TEST_CASE(table_matches_certificates) {
    BOOST_REQUIRE(certified_table_available());
    for (DiagonalRule r : {DiagonalRule::maxmin, DiagonalRule::separating, DiagonalRule::fan}) {
        const auto file = parse_cert_key_lines(slurp(std::string(WARPMESH_PROOFS_DIR) + "/" + rule_name(r) + ".cert"));
        const auto compiled = parse_cert_key_lines(certified_table_text(r));
        BOOST_TEST(file.size() == 5095u);
        const std::string diff = compare_cert_keys(file, compiled);
        BOOST_TEST(diff.empty(), rule_name(r) << ": compiled table is stale (re-run cmake): " << diff);
        BOOST_TEST(certified_key_count(r) == file.size());
        // Every key of the file looks up to its own bound.
        for (const auto& k : file) {
            std::array<CornerState, 4> cs{};
            for (int c = 0; c < 4; ++c) {
                const char sc = k.code[static_cast<std::size_t>(2 * c)], wc = k.code[static_cast<std::size_t>(2 * c + 1)];
                cs[static_cast<std::size_t>(c)].sign = static_cast<std::int8_t>(sc == '-' ? -1 : sc == '0' ? 0 : 1);
                cs[static_cast<std::size_t>(c)].warp = static_cast<Warp>(std::string("sRLUD").find(wc));
            }
            BOOST_TEST(key_code(cs) == k.code);
            const CertifiedBound* b = certified_bound(r, cs);
            BOOST_REQUIRE(b);
            BOOST_TEST(b->max_cot == parse_rational(k.qmin));
            BOOST_TEST(b->min_cot == parse_rational(k.qmax));
            BOOST_TEST(b->flat_compatible == k.flat);
            BOOST_TEST(b->min_deg <= b->max_deg);
        }
    }
}

// proofs/key_table.txt (the human-readable per-key table the prover writes
// beside the certificates) says the same as the compiled table.
BOOST_AUTO_TEST_CASE(key_table_txt_matches) {
    std::istringstream in(slurp(std::string(WARPMESH_PROOFS_DIR) + "/key_table.txt"));
    std::size_t lines = 0;
    for (std::string line; std::getline(in, line);) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream ls(line);
        std::string rule, code, flat, qmin, qmax;
        ls >> rule >> code >> flat >> qmin >> qmax;
        BOOST_REQUIRE(ls);
        BOOST_REQUIRE((rule == "maxmin" || rule == "separating" || rule == "fan"));
        const DiagonalRule r = rule == "maxmin" ? DiagonalRule::maxmin : rule == "separating" ? DiagonalRule::separating : DiagonalRule::fan;
        if (code[0] >= 'a' && code[0] <= 'd') {  // a junction key (proofs/materials.cert, materials_fan.cert)
            BOOST_REQUIRE(r != DiagonalRule::maxmin);
            const CertifiedBound* b = certified_junction_bound(junction_from_code(code), r);
            BOOST_TEST_INFO(line);
            BOOST_REQUIRE(b);
            BOOST_TEST((b->max_cot == parse_rational(qmin) && b->min_cot == parse_rational(qmax) && flat == "any"));
            ++lines;
            continue;
        }
        std::array<CornerState, 4> cs{};
        for (int c = 0; c < 4; ++c) {
            const char sc = code[static_cast<std::size_t>(2 * c)], wc = code[static_cast<std::size_t>(2 * c + 1)];
            cs[static_cast<std::size_t>(c)].sign = static_cast<std::int8_t>(sc == '-' ? -1 : sc == '0' ? 0 : 1);
            cs[static_cast<std::size_t>(c)].warp = static_cast<Warp>(std::string("sRLUD").find(wc));
        }
        const CertifiedBound* b = certified_bound(r, cs);
        BOOST_TEST_INFO(line);
        BOOST_REQUIRE(b);
        BOOST_TEST_INFO(line);
        BOOST_TEST((b->max_cot == parse_rational(qmin) && b->min_cot == parse_rational(qmax) &&
                    b->flat_compatible == (flat == "flat")));
        ++lines;
    }
    BOOST_TEST(lines == certified_key_count(DiagonalRule::maxmin) + certified_key_count(DiagonalRule::separating) +
                            certified_key_count(DiagonalRule::fan) + certified_junction_key_count() +
                            certified_junction_key_count(DiagonalRule::fan));
}

// The junction keys (multi-material squares with 3 or 4 materials):
// proofs/materials.cert compiled in, every key looks up to its own bound, and
// the mesher's own lookup of a square's materials finds the key.
// Both rules' junction keys (materials.cert: separating; materials_fan.cert: fan).
BOOST_AUTO_TEST_CASE(junction_table_matches_certificate) {
  for (const DiagonalRule rule : {DiagonalRule::separating, DiagonalRule::fan}) {
    const std::string name = rule == DiagonalRule::fan ? "materials_fan" : "materials";
    BOOST_TEST_CONTEXT(name) {
    const auto file = parse_cert_key_lines(slurp(std::string(WARPMESH_PROOFS_DIR) + "/" + name + ".cert"));
    const auto compiled = parse_cert_key_lines(certified_junction_table_text(rule));
    BOOST_TEST(file.size() == 2546u);  // proofs/README.md, "Junction keys"
    const std::string diff = compare_cert_keys(file, compiled);
    BOOST_TEST(diff.empty(), name << ": compiled table is stale (re-run cmake): " << diff);
    BOOST_TEST(certified_junction_key_count(rule) == file.size());
    double worst_min = 180, worst_max = 0;
    for (const auto& k : file) {
        const auto letters = junction_from_code(k.code);
        BOOST_TEST(junction_key_code(letters) == k.code);
        BOOST_TEST(!k.flat);
        const CertifiedBound* b = certified_junction_bound(letters, rule);
        BOOST_REQUIRE(b);
        BOOST_TEST(b->max_cot == parse_rational(k.qmin));
        BOOST_TEST(b->min_cot == parse_rational(k.qmax));
        worst_min = std::min(worst_min, b->min_deg), worst_max = std::max(worst_max, b->max_deg);
        // Any materials with the key's pattern give the key (letters in order of first appearance).
        std::array<MaterialCorner, 4> mats{};
        for (std::size_t c = 0; c < 4; ++c) mats[c] = {static_cast<std::uint16_t>(900 - 77 * letters[c].material), letters[c].warp};
        BOOST_TEST(junction_key_code(junction_letters(mats)) == k.code);
    }
    const CertifiedTheorem th = certified_junction_theorem(rule);
    BOOST_TEST(th.min_deg_any == worst_min);
    BOOST_TEST(th.max_deg_any == worst_max);
    // The fan rule's junction floor is the fan rule's unconditional one, above atan(1/3) - 6e-6 deg.
    if (rule == DiagonalRule::fan) BOOST_TEST(th.min_deg_any > 18.4349);
    // Not junction keys: two materials (a sign key), a cut side with both ends
    // staying, two corners sliding towards each other, an inward slide to the same material.
    for (const char* bad : {"asbsbRaL", "asasbscs", "aRbLcsaU", "aRaUbDcs"}) {
        BOOST_TEST_INFO(bad);
        BOOST_TEST(!certified_junction_bound(junction_from_code(bad), rule));
    }
    }
  }
  BOOST_TEST(certified_junction_key_count(DiagonalRule::maxmin) == 0u);  // refused with materials
}

// An unknown junction key is an internal error (std::logic_error), never a
// silently unbounded square: a one-square mesh whose corners carry three
// materials and do not move (inconsistent: its cut sides have no mover).
BOOST_AUTO_TEST_CASE(unknown_junction_key_is_an_internal_error) {
    Lattice l;
    l.nx = l.ny = 1;
    Mesh m;
    m.vertices.resize(4);
    m.vertices[0] = {0, 0}, m.vertices[1] = {1, 0}, m.vertices[2] = {0, 1}, m.vertices[3] = {1, 1};
    m.triangles.resize(2);
    m.triangles[0] = {0, 1, 3}, m.triangles[1] = {0, 3, 2};
    SquareKeys keys;
    keys.squares = {{0, 0, 2}};
    keys.stencils = {KeyedStencil{{0, 0, 1, 2}, {}, true}};  // letters a a b c, no corner moved
    try {
        certify_keys(m, l, keys, DiagonalRule::separating, CertifyOptions{true, false, true});
        BOOST_FAIL("no error for an unknown junction key");
    } catch (const std::logic_error& e) {
        BOOST_TEST(std::string(e.what()).find("asasbscs") != std::string::npos, e.what());
    }
}

BOOST_AUTO_TEST_CASE(corrupted_copy_is_detected) {
    auto keys = parse_cert_key_lines(certified_table_text(DiagonalRule::maxmin));
    BOOST_REQUIRE(keys.size() > 100);
    auto bad = keys;
    bad[100].qmin = bad[100].qmin == "3" ? "4" : "3";
    BOOST_TEST(compare_cert_keys(keys, keys).empty());
    BOOST_TEST(!compare_cert_keys(keys, bad).empty());
    auto shorter = keys;
    shorter.pop_back();
    BOOST_TEST(!compare_cert_keys(keys, shorter).empty());
}

BOOST_AUTO_TEST_CASE(theorems_from_table) {
    for (DiagonalRule r : {DiagonalRule::maxmin, DiagonalRule::separating}) {
        const CertifiedTheorem th = certified_theorem(r);
        BOOST_TEST(th.min_deg_any > 14.99);
        BOOST_TEST(th.min_deg_any < 15.0);
        BOOST_TEST(th.min_deg_flat > 18.4349488);
        BOOST_TEST(th.min_deg_flat < 18.4349489);
    }
    // The fan rule: the unconditional floor is arccot(3 + 17 2^-24), within 6e-6 deg of atan(1/3).
    const CertifiedTheorem fan = certified_theorem(DiagonalRule::fan);
    BOOST_TEST(fan.min_deg_any > 18.4349);
    BOOST_TEST(fan.min_deg_any < 18.4349489);
    BOOST_TEST(fan.min_deg_flat > 18.4349);
    // The theorem lines of the certificates are what the compiled table implies:
    // the min-angle side exactly (the claim is the largest key cot bound), and
    // the max-angle side equal to arccot of the claim's least cot bound.
    for (const char* rule : {"maxmin", "separating", "fan"}) {
        const std::string rn(rule);
        const CertifiedTheorem th = certified_theorem(rn == "maxmin" ? DiagonalRule::maxmin : rn == "separating" ? DiagonalRule::separating : DiagonalRule::fan);
        std::ifstream in(std::string(WARPMESH_PROOFS_DIR) + "/" + rule + ".cert");
        int claims = 0;
        for (std::string line; std::getline(in, line) && line.rfind("keys ", 0) != 0;) {
            std::istringstream ss(line);
            std::string w, set, qmin, qmax;
            ss >> w >> set >> qmin >> qmax;
            if (w != "claim") continue;
            ++claims;
            const double cmin = parse_rational(qmin), cmax = parse_rational(qmax);
            const double deg_max = std::atan2(1.0, cmax) * 180 / M_PI;
            BOOST_TEST_INFO(rule << " claim " << set);
            BOOST_TEST((set == "U" ? th.max_cot_any : th.max_cot_flat) == cmin);
            BOOST_TEST_INFO(rule << " claim " << set);
            BOOST_TEST((set == "U" ? th.max_deg_any : th.max_deg_flat) == deg_max, boost::test_tools::tolerance(1e-12));
        }
        BOOST_TEST(claims == 2);
    }
    BOOST_TEST(parse_rational("25769803777/8589934592") == 3.0 + 1.0 / 8589934592.0);
    BOOST_TEST(parse_rational("-4097/4096") == -4097.0 / 4096.0);
}

BOOST_AUTO_TEST_CASE(flatness) {
    std::array<std::int8_t, 12> s{};
    s.fill(-1);
    BOOST_TEST(stencil_is_flat(s));
    s.fill(0);
    BOOST_TEST(stencil_is_flat(s));
    // x - 1/2 sign pattern: flat.  Points at x <= 0 negative, x >= 1 positive.
    for (int k = 0; k < 12; ++k) s[static_cast<std::size_t>(k)] = stencil_offsets[static_cast<std::size_t>(k)][0] <= 0 ? -1 : 1;
    BOOST_TEST(stencil_is_flat(s));
    // x = 0 line with zeros: flat.
    for (int k = 0; k < 12; ++k) {
        const int x = stencil_offsets[static_cast<std::size_t>(k)][0];
        s[static_cast<std::size_t>(k)] = static_cast<std::int8_t>(x < 0 ? -1 : x == 0 ? 0 : 1);
    }
    BOOST_TEST(stencil_is_flat(s));
    // Opposite corners positive, the others negative (saddle): not flat.
    s.fill(-1);
    s[0] = s[3] = 1;
    BOOST_TEST(!stencil_is_flat(s));
    // A single positive point in the middle of negatives along a line... A + and
    // both its outside neighbours -, B, C, D -: flat (a small disc around A? no:
    // affine sign sets are half-planes; {A} alone is a half-plane's trace iff A is
    // a vertex of the convex hull, and A=(0,0) is interior to the stencil's hull).
    s.fill(-1);
    s[0] = 1;
    BOOST_TEST(!stencil_is_flat(s));
    // Hull vertex (2,0) alone positive: flat.
    s.fill(-1);
    s[6] = 1;
    BOOST_TEST(stencil_is_flat(s));
}

namespace {
// `count` random analytic shapes (seed `seed`) at random spacings and offsets,
// both rules, meshed and verified in `metric`: certify_keys throws on any key
// that is not in the metric's table or any triangle outside its key's bound.
// Returns the keyed squares.
std::int64_t mesh_random_shapes(std::uint32_t seed, int count, LatticeMetric metric) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, 1);
    std::int64_t keyed = 0;
    for (int it = 0; it < count; ++it) {
        const auto f = parse_shape(random_shape(rng, it));
        const Lattice lat = lattice_around(f->bounds(), 0.3 + 1.5 * u(rng));
        for (DiagonalRule r : {DiagonalRule::maxmin, DiagonalRule::separating}) {
            testing::Certified<UniformResult> res;
            BOOST_REQUIRE_NO_THROW(res = testing::certified(mesh_uniform(*f, lat, r, testing::with_keys, metric), lat, r, {true, false, true}));
            BOOST_REQUIRE(res.certified.available);
            BOOST_TEST(res.certified.verified);
            BOOST_TEST(res.certified.min_deg >= certified_theorem(r, metric).min_deg_any);
            keyed += res.certified.keyed_squares;
        }
    }
    return keyed;
}

}  // namespace

BOOST_AUTO_TEST_CASE(mesher_keys_are_in_table) { BOOST_TEST(mesh_random_shapes(12345, 60, LatticeMetric::square) > 1000); }

// The rhombic lattice's tables (issue 33): proofs/rhombic_<rule>.cert
// compiled in, looked up only with LatticeMetric::rhombic, their degrees the
// physical angles of the bounds on r = sqrt(3) cot; and the rhombic mesher
// (lattice coordinates, before the map by P) produces only keys they hold,
// every triangle within its key's bound in the rhombic forms (--verify).
BOOST_AUTO_TEST_CASE(issue33_rhombic_tables_match_their_certificates) {
    BOOST_REQUIRE(certified_table_available(LatticeMetric::rhombic));
    for (DiagonalRule r : {DiagonalRule::maxmin, DiagonalRule::separating}) {
        const auto file =
            parse_cert_key_lines(slurp(std::string(WARPMESH_PROOFS_DIR) + "/rhombic_" + rule_name(r) + ".cert"));
        BOOST_TEST(file.size() == 5095u);
        const std::string diff = compare_cert_keys(file, parse_cert_key_lines(certified_table_text(r, LatticeMetric::rhombic)));
        BOOST_TEST(diff.empty(), rule_name(r) << ": compiled rhombic table is stale (re-run cmake): " << diff);
        BOOST_TEST(certified_key_count(r, LatticeMetric::rhombic) == file.size());
    }
    BOOST_TEST(certified_key_count(DiagonalRule::fan, LatticeMetric::rhombic) == 0u);
    // Key -L-s+s-U (the separating rule's worst, forced long diagonal): the
    // same key has different bounds on the two lattices.
    const std::array<CornerState, 4> cs{{{-1, Warp::mx}, {-1, Warp::stay}, {1, Warp::stay}, {-1, Warp::py}}};
    const CertifiedBound* rh = certified_bound(DiagonalRule::separating, cs, LatticeMetric::rhombic);
    const CertifiedBound* sq = certified_bound(DiagonalRule::separating, cs);
    BOOST_REQUIRE((rh && sq));
    BOOST_TEST(rh->min_deg > 10.8933 - 1e-9);
    BOOST_TEST(rh->min_deg < 10.8934);
    BOOST_TEST(rh->max_deg > 158.2132);
    BOOST_TEST(sq->min_deg > 18.43);
    // The theorems: separating U [10.8933, 158.2133], max-min U >= 12.8294, F >= 13.8978.
    const CertifiedTheorem s = certified_theorem(DiagonalRule::separating, LatticeMetric::rhombic);
    const CertifiedTheorem m = certified_theorem(DiagonalRule::maxmin, LatticeMetric::rhombic);
    BOOST_TEST((s.min_deg_any > 10.8933 && s.min_deg_any < 10.8934));
    BOOST_TEST((s.max_deg_any > 158.2132 && s.max_deg_any < 158.2134));
    BOOST_TEST((m.min_deg_any > 12.8294 && m.min_deg_any < 12.8295));
    BOOST_TEST((m.min_deg_flat > 13.8978 && m.min_deg_flat < 13.8979));
    BOOST_TEST((m.max_deg_any > 150.0 && m.max_deg_any < 150.0201));
}

BOOST_AUTO_TEST_CASE(issue33_rhombic_mesher_keys_are_in_its_tables_and_verified) {
    BOOST_TEST(mesh_random_shapes(33, 24, LatticeMetric::rhombic) > 1000);
}
