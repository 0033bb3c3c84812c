// The rhombic lattice (`--lattice rhombic`, rhombic.hpp): its
// geometry pinned — the unwarped interior is equilateral, the metric's forms
// are the physical angles up to the factor sqrt 3, the rule takes the short
// diagonal on the unwarped rhombus, the mesh is valid with its boundary on the
// level set — and that it is certified by its own certificates.  (The square
// lattice, LatticeMetric::square, is pinned byte for byte by the golden tests.)
#define BOOST_TEST_MODULE uniform_rhombic
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <random>

#include <sys/wait.h>

#include "warpmesh/certify/certified.hpp"
#include "warpmesh/mesh2d/generic_square.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "support.hpp"
#include "mesh2d/uniform/rhombic.hpp"

using namespace warpmesh;

namespace {

MeshOptions rhombic_options(double spacing) {
    MeshOptions o;
    o.spacing = spacing;
    o.lattice = LatticeMetric::rhombic;
    return o;
}

double length(Vec2 a, Vec2 b) { return std::hypot(a.x - b.x, a.y - b.y); }

}  // namespace

BOOST_AUTO_TEST_CASE(rhombic_unwarped_interior_triangles_are_equilateral_with_edge_the_spacing) {
    const auto f = parse_shape("circle:0.3,-0.2,10");
    for (DiagonalRule rule : {DiagonalRule::separating, DiagonalRule::maxmin}) {
        MeshOptions o = rhombic_options(1);
        o.rule = rule;
        const MeshResult r = mesh(*f, o);
        BOOST_TEST(check_mesh(r.mesh).ok());
        std::int64_t interior = 0;
        for (const auto& t : r.mesh.triangles) {
            const Vec2 a = r.mesh.vertices[static_cast<std::size_t>(t[0])], b = r.mesh.vertices[static_cast<std::size_t>(t[1])],
                       c = r.mesh.vertices[static_cast<std::size_t>(t[2])];
            const double cx = (a.x + b.x + c.x) / 3 - 0.3, cy = (a.y + b.y + c.y) / 3 + 0.2;
            if (std::hypot(cx, cy) > 10 - 3) continue;  // the boundary band: warped corners
            ++interior;
            BOOST_TEST(std::abs(length(a, b) - 1) < 1e-12);
            BOOST_TEST(std::abs(length(b, c) - 1) < 1e-12);
            BOOST_TEST(std::abs(length(c, a) - 1) < 1e-12);
        }
        // The disc of radius 7 holds about 2 pi 49 / sqrt 3 = 178 unit equilateral triangles.
        BOOST_TEST(interior > 150);
        // Separating: the boundary vertices lie on the circle (its exact cut
        // points, mapped by P).  (Max-min may cut a corner through an inside point.)
        if (rule == DiagonalRule::separating)
            for (const auto& e : r.mesh.boundary) {
                const Vec2 v = r.mesh.vertices[static_cast<std::size_t>(e[0])];
                BOOST_TEST(std::abs(std::hypot(v.x - 0.3, v.y + 0.2) - 10) < 1e-9);
            }
        BOOST_TEST(std::abs(testing::mesh_area(r.mesh) - M_PI * 100) < 0.01 * M_PI * 100);
    }
}

BOOST_AUTO_TEST_CASE(rhombic_metric_forms_are_sqrt3_times_the_physical_cotangents) {
    std::mt19937 rng(33);
    std::uniform_real_distribution<double> u(-2, 2);
    for (int k = 0; k < 100; ++k) {
        const std::array<Point<double>, 3> p{{{u(rng), u(rng)}, {u(rng), u(rng)}, {u(rng), u(rng)}}};
        const TriangleForms<double> f = triangle_forms(p[0], p[1], p[2], LatticeMetric::rhombic);
        const TriangleForms<double> s = triangle_forms(p[0], p[1], p[2]);
        BOOST_TEST(f.cross == s.cross);  // the lattice cross product; the physical one is (sqrt 3 / 2) of it
        std::array<Vec2, 3> q{};
        for (int i = 0; i < 3; ++i) q[static_cast<std::size_t>(i)] = rhombic_map({p[static_cast<std::size_t>(i)].x, p[static_cast<std::size_t>(i)].y});
        for (int i = 0; i < 3; ++i) {
            const Vec2 o = q[static_cast<std::size_t>(i)], a = q[static_cast<std::size_t>((i + 1) % 3)], b = q[static_cast<std::size_t>((i + 2) % 3)];
            const double dot = (a.x - o.x) * (b.x - o.x) + (a.y - o.y) * (b.y - o.y);
            const double cross = (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
            BOOST_TEST(std::abs(cross - std::sqrt(3.0) / 2 * f.cross) < 1e-12);
            BOOST_TEST(std::abs(f.dot[static_cast<std::size_t>(i)] - 2 * dot) < 1e-12);  // dot / cross = sqrt 3 cot
        }
    }
}

BOOST_AUTO_TEST_CASE(rhombic_rule_takes_the_short_diagonal_on_the_unwarped_rhombus_whatever_the_tie_break) {
    const std::array<Warp, 4> stay{};
    const auto p = generic_positions<double>(stay, {0, 0, 0, 0});
    const std::array<CornerState, 4> inside{{{-1, Warp::stay}, {-1, Warp::stay}, {-1, Warp::stay}, {-1, Warp::stay}}};
    for (DiagonalRule rule : {DiagonalRule::maxmin, DiagonalRule::separating})
        for (TieBreak tie : {TieBreak::ad, TieBreak::bc, TieBreak::either}) {
            const Choice r = choose_diagonal(rule, p, inside, tie, LatticeMetric::rhombic);
            BOOST_TEST((r.bc && !r.ad));
            const Choice s = choose_diagonal(rule, p, inside, tie);  // the square: a tie, the tie-break decides
            BOOST_TEST(s.bc == (tie != TieBreak::ad));
            BOOST_TEST(s.ad == (tie != TieBreak::bc));
        }
    BOOST_TEST((unwarped_diagonal(LatticeMetric::rhombic, TieBreak::ad) == Diagonal::BC));
    BOOST_TEST((unwarped_diagonal(LatticeMetric::square, TieBreak::ad) == Diagonal::AD));
    BOOST_TEST((unwarped_diagonal(LatticeMetric::square, TieBreak::bc) == Diagonal::BC));
}

// The worst configuration the sampling of prover/tools/explore_rhombic.py
// finds for the separating rule (flat-compatible key -L-s+s-U, A and D slid by
// 1/2): B and C stay with different signs, so the rule forces the long
// diagonal AD, and the triangle ADC has angles 10.89° and 158.21° — what a
// rhombic certificate of the separating rule could at best claim.
BOOST_AUTO_TEST_CASE(rhombic_separating_worst_sampled_configuration_is_the_forced_long_diagonal) {
    const std::array<CornerState, 4> cs{{{-1, Warp::mx}, {-1, Warp::stay}, {1, Warp::stay}, {-1, Warp::py}}};
    const std::array<Warp, 4> w{Warp::mx, Warp::stay, Warp::stay, Warp::py};
    const auto p = generic_positions<double>(w, {0.5, 0, 0, 0.5});
    const Choice ch = choose_diagonal(DiagonalRule::separating, p, cs, TieBreak::ad, LatticeMetric::rhombic);
    BOOST_TEST((ch.ad && !ch.bc));
    const TriangleForms<double> f = triangle_forms(p[A], p[D], p[C], LatticeMetric::rhombic);
    auto deg = [&](int i) { return std::atan2(std::sqrt(3.0) * f.cross, f.dot[static_cast<std::size_t>(i)]) * 180 / M_PI; };
    BOOST_TEST(std::abs(deg(0) - 10.8933946) < 1e-6);   // at A: 40.8934° - 30°
    BOOST_TEST(std::abs(deg(2) - 158.2132107) < 1e-6);  // at C
    // Max-min alone would take BC here.
    BOOST_TEST(choose_diagonal(DiagonalRule::maxmin, p, cs, TieBreak::ad, LatticeMetric::rhombic).bc);
}

// Issue 33: the rhombic lattice is certified by its own certificates
// (proofs/rhombic_<rule>.cert): the report's bounds are the rhombic theorem's,
// every triangle verified in lattice coordinates, the physical angles of the
// mapped mesh inside the certified interval; what it does not cover is refused.
BOOST_AUTO_TEST_CASE(issue33_rhombic_is_certified_by_its_own_certificates) {
    const auto f = parse_shape("flower:0,0,8,2,5");
    for (DiagonalRule rule : {DiagonalRule::separating, DiagonalRule::maxmin}) {
        MeshOptions o = rhombic_options(0.5);
        o.rule = rule;
        o.verify = true;
        const MeshResult r = mesh(*f, o);
        BOOST_REQUIRE(r.certified.available);
        BOOST_TEST(r.certified.verified);
        BOOST_TEST(r.certified.keyed_squares > 100);
        const CertifiedTheorem th = certified_theorem(rule, LatticeMetric::rhombic);
        BOOST_TEST(r.certified.min_deg >= th.min_deg_any);
        BOOST_TEST(r.certified.max_deg <= th.max_deg_any);
        BOOST_TEST(r.report.quality.min_angle_deg >= r.certified.min_deg - 1e-9);
        BOOST_TEST(r.report.quality.max_angle_deg <= r.certified.max_deg + 1e-9);
        const std::string text = to_text(r), json = to_json(r);
        BOOST_TEST(text.find(std::string("proofs/rhombic_") + (rule == DiagonalRule::maxmin ? "maxmin" : "separating") +
                             ".cert, every triangle verified") != std::string::npos,
                   text);
        BOOST_TEST(r.mesh.cell_data.size() == 1u);  // certified_min_angle
        for (const auto& w : r.warnings) BOOST_TEST(w.find("uncertified") == std::string::npos, w);
        BOOST_TEST(json.find("\"certified\": null") == std::string::npos, json);
        BOOST_TEST(json.find("\"lattice_metric\": \"rhombic\"") != std::string::npos, json);
    }
    // The library's words (the CLI prints --graded, --diagonal fan, --lattice rhombic).
    const auto f2 = parse_shape("circle:0,0,5");
    for (auto [set, what] : {std::pair<void (*)(MeshOptions&), const char*>{[](MeshOptions& o) { o.graded = true; }, "graded=true"},
                             {[](MeshOptions& o) { o.rule = DiagonalRule::fan; }, "rule=fan"},
                             {[](MeshOptions& o) { o.max_size = 10; }, "max_size"}}) {
        MeshOptions o = rhombic_options(1);
        set(o);
        BOOST_TEST(testing::input_error_containing([&] { mesh(*f2, o); }, std::string(what) + " is not available with lattice=rhombic"));
    }
    const auto field = parse_material_shapes("1=circle:0,0,5;2=circle:3,0,3");
    BOOST_TEST(testing::input_error_containing([&] { mesh(*field, rhombic_options(1)); }, "lattice=rhombic is not available"));
}

// --guarantee flat on the rhombic lattice: the spacing is halved until every
// warped square's stencil is flat, and the mesh then carries the rhombic F
// theorem (max-min: 13.8978 deg, above its U 12.8294 deg).
BOOST_AUTO_TEST_CASE(issue33_rhombic_guarantee_flat_reaches_the_flat_theorem) {
    const auto f = parse_shape("circle:0.3,0.1,6");
    MeshOptions o = rhombic_options(2);
    o.rule = DiagonalRule::maxmin;
    o.guarantee = Guarantee::flat;
    o.verify = true;
    const MeshResult r = mesh(*f, o);
    BOOST_REQUIRE(r.certified.available);
    BOOST_TEST(r.certified.nonflat_squares == 0);
    BOOST_TEST(r.certified.verified);
    BOOST_TEST(r.certified.min_deg >= certified_theorem(DiagonalRule::maxmin, LatticeMetric::rhombic).min_deg_flat);
    BOOST_TEST(r.report.quality.min_angle_deg >= r.certified.min_deg - 1e-9);
}

// The command line: --verify and --svg-color certified work on the rhombic
// lattice; what it does not cover is refused (exit 2, nothing written).
BOOST_AUTO_TEST_CASE(issue33_rhombic_cli_verifies) {
    testing::TempDir dir("warpmesh-rhombic");
    const std::string exe = WARPMESH_EXE, out = dir.file("m.vtu"), err = dir.file("err.txt"), svg = dir.file("m.svg");
    auto run = [&](const std::string& extra) {
        const std::string cmd = "'" + exe + "' mesh --shape circle:0,0,5 --spacing 0.5 --lattice rhombic -o '" + out +
                                "' --quiet " + extra + " 2> '" + err + "'";
        const int status = std::system(cmd.c_str());
        return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    };
    BOOST_TEST(run("--verify") == 0);
    BOOST_TEST(std::filesystem::exists(out));
    BOOST_TEST(testing::slurp(err).find("uncertified") == std::string::npos, testing::slurp(err));
    BOOST_TEST(run("--diagonal maxmin --verify --also '" + svg + "' --svg-color certified") == 0, testing::slurp(err));
    BOOST_TEST(std::filesystem::exists(svg));
    std::filesystem::remove(out);
    BOOST_TEST(run("--graded") == 2);
    BOOST_TEST(!std::filesystem::exists(out));
}
