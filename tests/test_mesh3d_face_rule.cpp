// The 3D mesher's face rule (Mesh3dOptions::face_rule; generic_bcc.hpp, "The
// diagonal choices"): the (signs, diagonals) plan table extends the parity
// table and keeps every stencil's count and points (stage 5's first pass);
// delaunay_choice equals the Delaunay rule in exact rationals, also at ties
// and at near-ties where rounded arithmetic errs; meshes of a sphere, a torus,
// random quadrics and the brain crop with the Delaunay face rule are
// conforming, within the rule's sampled dihedral range on smooth shapes,
// different from parity's, the same for any block split; exact and near ties
// on shared faces never split a face two ways; and a Delaunay mesh is never
// reported with proofs/bcc.cert's (parity) bounds.
#define BOOST_TEST_MODULE mesh3d_face_rule
#include <boost/multiprecision/cpp_int.hpp>
#include <cmath>
#include <random>

#include "brain_crop.hpp"
#include "support.hpp"
#include "mesh3d/uniform3d.hpp"
#include "warpmesh/certify/bcc_certified.hpp"
#include "warpmesh/pipeline/mesh3d.hpp"
#include "warpmesh/post/tet_checks.hpp"
#include "warpmesh/report/report3d.hpp"

using namespace warpmesh;
using namespace warpmesh::testing;

namespace {

// Exact rationals for the reference evaluation of the rule.
struct Q {
    boost::multiprecision::cpp_rational q;
};
Q operator+(const Q& a, const Q& b) { return {a.q + b.q}; }
Q operator-(const Q& a, const Q& b) { return {a.q - b.q}; }
Q operator*(const Q& a, const Q& b) { return {a.q * b.q}; }

}  // namespace

template <>
struct warpmesh::ScalarOps<Q> {
    static Q from_int(int v) { return {boost::multiprecision::cpp_rational(v)}; }
    static Truth positive(const Q& a) { return truth(a.q > 0); }
};

namespace {

std::array<int, 4> signs_of(int code) {
    std::array<int, 4> s{};
    for (int i = 0; i < 4; ++i, code /= 3) s[static_cast<std::size_t>(i)] = code % 3 - 1;
    return s;
}

// The rule on the stored cut parameters u (from each edge's lower endpoint;
// local fraction 1 − u where bit e of from_upper is set), in exact rationals
// or in plain doubles (1 − u rounded).
bcc::Diagonals exact_rule(const std::array<int, 4>& sign, int parity, const std::array<double, 6>& u, unsigned from_upper) {
    std::array<Q, 6> local{};
    for (std::size_t e = 0; e < 6; ++e) {
        const Q x{boost::multiprecision::cpp_rational(u[e])};
        local[e] = (from_upper >> e & 1u) ? Q{1 - x.q} : x;
    }
    return bcc::delaunay_diagonals<Q>(sign, parity, local);
}
bcc::Diagonals rounded_rule(const std::array<int, 4>& sign, int parity, const std::array<double, 6>& u, unsigned from_upper) {
    std::array<double, 6> local{};
    for (std::size_t e = 0; e < 6; ++e) local[e] = (from_upper >> e & 1u) ? 1 - u[e] : u[e];
    return bcc::delaunay_diagonals<double>(sign, parity, local);
}

// Whether two choices give the same stencil (a cyclic choice: none).
bool same_diagonals(const std::array<int, 4>& sign, const bcc::Diagonals& a, const bcc::Diagonals& b) {
    int code = 0;
    for (int i = 3; i >= 0; --i) code = 3 * code + sign[static_cast<std::size_t>(i)] + 1;
    const auto plan = [&](const bcc::Diagonals& d) -> const uniform3d::Plan& {
        return uniform3d::diagonal_plans()[static_cast<std::size_t>(code * uniform3d::diagonal_slots + uniform3d::diagonal_slot(d))];
    };
    const uniform3d::Plan &x = plan(a), &y = plan(b);
    if (x.cyclic || y.cyclic || x.stencil.count != y.stencil.count) return x.cyclic && y.cyclic;
    for (int k = 0; k < x.stencil.count; ++k)
        if (x.stencil.tet[static_cast<std::size_t>(k)] != y.stencil.tet[static_cast<std::size_t>(k)]) return false;
    return true;
}

Mesh3dOptions delaunay_options(double spacing) {
    Mesh3dOptions o;
    o.spacing = spacing;
    o.face_rule = FaceRule::delaunay;
    return o;
}

// Meshes with the Delaunay face rule and checks the mesh (conforming,
// positive, closed boundary) and the report's rule; the mesh in *out.
Mesh3dReport mesh_delaunay(const LevelSet3& f, const Mesh3dOptions& o, TetMesh* out = nullptr) {
    Mesh3dResult res = mesh3d(f, o);
    const Mesh3dReport r = res.report;
    TetMesh m = std::move(res.mesh);
    const TetMeshCheck c = check_tet_mesh(m);
    BOOST_TEST(c.ok, f.describe() << ": " << (c.problems.empty() ? "" : c.problems.front()));
    BOOST_TEST((r.face_rule == FaceRule::delaunay));
    if (out) *out = std::move(m);
    return r;
}

// The rule's sampled range at (0.2675, 0.39) (proofs/README.md, "Towards θmin
// ≥ 12°" (e): 11.787°–161.20°), with a margin.
void within_the_rules_range(const Mesh3dReport& r, const std::string& what) {
    BOOST_TEST(r.quality.min_dihedral_deg >= 11.7, what << ": " << r.quality.min_dihedral_deg);
    BOOST_TEST(r.quality.max_dihedral_deg <= 161.3, what << ": " << r.quality.max_dihedral_deg);
}

bool same_tets(const TetMesh& a, const TetMesh& b) { return a.tets == b.tets && a.vertices.size() == b.vertices.size(); }

// A level set whose sign is a ball's but whose cut points sit at chosen
// fractions: with max_ulps = 0 at 1/2 (exact ties on every face whose two
// edges to r have equal length); otherwise 3/8 from the + end on long edges
// and 1/2 on short ones (4 · 3/8 = 3 · 1/2: ties on the faces with a long and
// a short edge to r too), each moved by up to max_ulps ulps, differently per
// edge (near ties, decided by the exact fallback).
class TiedCuts final : public LevelSet3 {
public:
    explicit TiedCuts(int max_ulps) : ulps_(max_ulps) {}
    double value(double x, double y, double z) const override { return x * x + y * y + z * z - 0.81; }
    Box3 bounds() const override { return {-1, -1, -1, 1, 1, 1}; }
    double cut_parameter(Point3 a, Point3 b, double fa, double) const override {
        if (ulps_ == 0) return 0.5;
        const bool long_edge = (a.x != b.x) + (a.y != b.y) + (a.z != b.z) == 1;  // axis-parallel
        double u = !long_edge ? 0.5 : fa > 0 ? 0.375 : 0.625;  // from a; 3/8 from the + end
        const long h = std::lround(1e3 * (3 * a.x + 5 * a.y + 7 * a.z + 11 * b.x + 13 * b.y + 17 * b.z));
        const long k = ((h % (2 * ulps_ + 1)) + 2 * ulps_ + 1) % (2 * ulps_ + 1) - ulps_;
        for (long i = 0; i < std::labs(k); ++i) u = std::nextafter(u, k > 0 ? 1.0 : 0.0);
        return u;
    }
    std::string describe() const override { return "ball with tied cut points"; }

private:
    int ulps_;
};

}  // namespace

BOOST_AUTO_TEST_CASE(diagonal_plans_extend_the_parity_plans_and_keep_counts_and_points) {
    const auto parity = uniform3d::plans();
    const auto by_d = uniform3d::diagonal_plans();
    BOOST_REQUIRE(by_d.size() == 81u * uniform3d::diagonal_slots);
    int cyclic = 0;
    for (int code = 0; code < 81; ++code)
        for (int par = 0; par < 2; ++par) {
            const auto sign = signs_of(code);
            const uniform3d::Plan& p = parity[static_cast<std::size_t>(2 * code + par)];
            const uniform3d::Plan& q =
                by_d[static_cast<std::size_t>(code * uniform3d::diagonal_slots + uniform3d::diagonal_slot(bcc::parity_diagonals(sign, par)))];
            BOOST_TEST(!q.cyclic);
            BOOST_TEST(p.stencil.count == q.stencil.count);
            for (int k = 0; k < p.stencil.count; ++k) {
                BOOST_TEST(p.stencil.tet[static_cast<std::size_t>(k)] == q.stencil.tet[static_cast<std::size_t>(k)]);
                BOOST_TEST(p.face_on[static_cast<std::size_t>(k)] == q.face_on[static_cast<std::size_t>(k)]);
            }
            for (int slot = 0; slot < uniform3d::diagonal_slots; ++slot) {  // pass A counts with the parity plans
                const uniform3d::Plan& d = by_d[static_cast<std::size_t>(code * uniform3d::diagonal_slots + slot)];
                if (d.cyclic) {
                    cyclic += par == 0;
                    continue;
                }
                BOOST_TEST(d.stencil.count == p.stencil.count);
                BOOST_TEST(d.uses == p.uses);
                BOOST_TEST(d.quads == p.quads);
            }
        }
    BOOST_TEST(cyclic > 0);  // the n- = 3 prisms' cycles exist in the table, flagged
}

BOOST_AUTO_TEST_CASE(delaunay_choice_is_the_exact_rule_also_where_rounding_errs) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> frac(0.26, 0.74);
    std::uniform_int_distribution<int> pick(0, 80), step(-3, 3);
    int rounding_errs = 0, checked = 0;
    for (int trial = 0; trial < scaled(40000); ++trial) {
        const auto sign = signs_of(pick(rng));
        const int parity = trial & 1;
        const unsigned from_upper = static_cast<unsigned>(rng()) & 63u;
        std::array<double, 6> u{};
        // Near ties: local fractions a few ulps off 1/2, 3/8 and 5/8, where
        // |xr|² (1 − u) of a long and a short edge or of two short edges tie
        // (4 · 3/8 = 3 · 1/2, 3 · 1/2 = 3 · 1/2), or random ones; stored as
        // the window stores them (from the other end: 1 − x, rounded).
        constexpr std::array<double, 4> ties{0.5, 0.375, 0.625, 0.5};
        for (std::size_t e = 0; e < 6; ++e) {
            double x = trial % 4 == 3 ? frac(rng) : ties[static_cast<std::size_t>(rng() % 4)];
            for (int s = step(rng); s != 0; s += s > 0 ? -1 : 1) x = std::nextafter(x, s > 0 ? 1.0 : 0.0);
            u[e] = (from_upper >> e & 1u) ? 1 - x : x;
        }
        const bcc::Diagonals got = uniform3d::delaunay_choice(sign, parity, u, from_upper);
        const bcc::Diagonals want = exact_rule(sign, parity, u, from_upper);
        BOOST_TEST(same_diagonals(sign, got, want), "code " << sign[0] << sign[1] << sign[2] << sign[3] << " trial " << trial);
        rounding_errs += !same_diagonals(sign, rounded_rule(sign, parity, u, from_upper), want);
        ++checked;
    }
    BOOST_TEST(checked > 1000);
    BOOST_TEST(rounding_errs > 0);  // the fixture has cases that plain doubles decide wrongly
}

BOOST_AUTO_TEST_CASE(sphere_torus_and_quadrics_conform_within_the_rules_range_and_differ_from_parity) {
    for (const auto& [spec, s] : {std::pair<const char*, double>{"sphere:0.05,-0.02,0.01,1", 0.1}, {"torus:0,0,0,1,0.4", 0.08},
                                  {"ellipsoid:0.1,0,0,1.2,0.8,0.6", 0.07}}) {
        const auto f = parse_shape3(spec);
        TetMesh d, p;
        const Mesh3dReport r = mesh_delaunay(*f, delaunay_options(s), &d);
        within_the_rules_range(r, spec);
        Mesh3dOptions po = delaunay_options(s);
        po.face_rule = FaceRule::parity;
        po.alphas = bcc::delaunay_alphas;  // the same warping: only the diagonals differ
        p = mesh3d(*f, po).mesh;
        BOOST_TEST(d.vertices.size() == p.vertices.size(), spec);
        BOOST_TEST(!same_tets(d, p), spec << ": the Delaunay face rule changed nothing");
    }
    std::mt19937 rng(17);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int trial = 0; trial < scaled(6); ++trial) {  // ellipsoids in random orientations
        const double a = 1 + 0.3 * U(rng), b = 0.8 + 0.2 * U(rng), c = 0.6 + 0.2 * U(rng), t = 3 * U(rng), q = 3 * U(rng);
        FunctionLevelSet3 f(
            [=](double x, double y, double z) {
                const double x1 = std::cos(t) * x - std::sin(t) * y, y1 = std::sin(t) * x + std::cos(t) * y;
                const double y2 = std::cos(q) * y1 - std::sin(q) * z, z2 = std::sin(q) * y1 + std::cos(q) * z;
                return x1 * x1 / (a * a) + y2 * y2 / (b * b) + z2 * z2 / (c * c) - 1;
            },
            Box3{-1.4, -1.4, -1.4, 1.4, 1.4, 1.4}, "rotated ellipsoid");
        within_the_rules_range(mesh_delaunay(f, delaunay_options(0.09 + 0.02 * U(rng))), "ellipsoid " + std::to_string(trial));
    }
}

BOOST_AUTO_TEST_CASE(brain_crop_conforms_and_differs_from_parity) {
    const auto f = brain_crop_levelset();
    TetMesh d;
    const Mesh3dReport r = mesh_delaunay(*f, delaunay_options(1.5), &d);
    BOOST_TEST(r.tets > 1000);
    Mesh3dOptions po = delaunay_options(1.5);
    po.face_rule = FaceRule::parity;
    po.alphas = bcc::delaunay_alphas;
    BOOST_TEST(!same_tets(d, mesh3d(*f, po).mesh));
}

BOOST_AUTO_TEST_CASE(delaunay_blocks_merge_into_exactly_the_whole_mesh) {
    const auto f = parse_shape3("union(torus:0,0,0,1,0.35;sphere:0.3,0.2,0.1,0.6)");
    const Mesh3dOptions o = delaunay_options(0.11);
    const Lattice3 L = lattice3d(*f, o);
    const TetMesh whole = mesh3d(*f, o).mesh;
    std::vector<TetBlock> blocks;
    const std::int64_t cx = L.cubes[0] / 3, cz = L.cubes[2] / 2;
    for (const auto& [lo, hi] : {std::pair<std::array<std::int64_t, 3>, std::array<std::int64_t, 3>>{{0, 0, 0}, {cx, L.cubes[1], cz}},
                                 {{cx, 0, 0}, {L.cubes[0], L.cubes[1], cz}},
                                 {{0, 0, cz}, L.cubes}})
        blocks.push_back(mesh3d_block(*f, o, CubeRange{lo, hi}));
    const TetMesh merged = merge_tet_blocks(blocks);
    BOOST_TEST(merged.tets == whole.tets);
    BOOST_TEST(merged.boundary == whole.boundary);
    Mesh3dOptions two = o;
    two.threads = 2;
    BOOST_TEST(mesh3d(*f, two).mesh.tets == whole.tets);
}

// The failure prevented: a face quad split one way by one tetrahedron and the
// other way by its neighbour (a non-conforming mesh), where the Delaunay
// forms tie exactly (cut points at 1/2: cocircular quads, which must fall back
// to the parity rule, a rule of the face) or nearly (cut points a few ulps off
// 1/2, where each tetrahedron's rounded 1 − u could decide differently).
BOOST_AUTO_TEST_CASE(ties_and_near_ties_never_split_a_shared_face_two_ways) {
    const TiedCuts exact(0);
    TetMesh d;
    mesh_delaunay(exact, delaunay_options(0.2), &d);
    // At the midpoints every tie goes to parity and every other face agrees
    // with it (test_bcc_delaunay_rule: ties_fall_back_to_parity): the same mesh.
    Mesh3dOptions po = delaunay_options(0.2);
    po.face_rule = FaceRule::parity;
    po.alphas = bcc::delaunay_alphas;
    BOOST_TEST(same_tets(d, mesh3d(exact, po).mesh));
    for (int ulps : {1, 2, 4}) {
        const TiedCuts near(ulps);
        for (double s : {0.2, 0.13}) {
            TetMesh m;
            const Mesh3dReport r = mesh_delaunay(near, delaunay_options(s), &m);
            BOOST_TEST(r.tets > 0);
        }
    }
}

// A Delaunay mesh is never reported with proofs/bcc.cert's (parity) bounds,
// not even at that certificate's alphas; without proofs/bcc_delaunay.cert in
// the build it is uncertified, says why, and --verify checks nothing.
BOOST_AUTO_TEST_CASE(delaunay_mesh_is_never_reported_with_the_parity_certificate) {
    const auto f = parse_shape3("sphere:0,0,0,1");
    for (const bool parity_alphas : {false, true}) {
        Mesh3dOptions o = delaunay_options(0.15);
        o.verify = true;
        if (parity_alphas) o.alphas = bcc::parity_alphas;
        const Mesh3dReport r = mesh3d(*f, o).report;
        const auto claim = bcc_claim(FaceRule::delaunay);
        const bool own = bcc_certificate_applies(o.alphas_in_use(), FaceRule::delaunay);
        BOOST_TEST(r.certified == own);
        if (r.certified) {
            BOOST_TEST(r.certified_min_deg == claim->min_deg);
            BOOST_TEST(r.verified);
            continue;
        }
        BOOST_TEST(r.certified_min_deg == 0.0);
        BOOST_TEST(r.uncertified_tets == r.tets);
        BOOST_TEST(!r.verified);
        BOOST_TEST(r.uncertified_reason.find("bcc_delaunay.cert") != std::string::npos, r.uncertified_reason);
        const std::string json = to_json(r), text = to_text(r);
        BOOST_TEST(json.find("\"certified\": null") != std::string::npos);
        BOOST_TEST(json.find("\"face_rule\": \"delaunay\"") != std::string::npos);
        BOOST_TEST(text.find("certified: no (") != std::string::npos);
        BOOST_TEST(text.find("bcc.cert)") == std::string::npos);
    }
    // The default is the Delaunay face rule at its alphas, certified by
    // proofs/bcc_delaunay.cert; parity stays certified by proofs/bcc.cert.
    for (const auto [rule, name] : {std::pair{std::optional<FaceRule>{}, "bcc_delaunay.cert"},
                                    std::pair{std::optional<FaceRule>{FaceRule::parity}, "bcc.cert"}}) {
        Mesh3dOptions o;
        o.spacing = 0.15;
        if (rule) o.face_rule = *rule;
        const Mesh3dReport r = mesh3d(*f, o).report;
        BOOST_TEST((r.face_rule == (rule ? *rule : FaceRule::delaunay)));
        BOOST_TEST(r.certified == bcc_claim(r.face_rule).has_value());
        if (r.certified) BOOST_TEST(to_json(r).find(std::string("\"proofs/") + name + "\"") != std::string::npos);
    }
}
