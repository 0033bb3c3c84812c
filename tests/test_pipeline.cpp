// Unit tests of the uniform pipeline's stages: cut points, warping, the
// diagonal rule and the triangulation of hand-made lattices.
#define BOOST_TEST_MODULE pipeline
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <tuple>

#include "support.hpp"
#include "warpmesh/core/memory.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/mesh2d/uniform.hpp"

using namespace warpmesh;

namespace {

// A level set given by a lambda; the lattice values can be overridden per point
// (to build exact sign patterns and cut positions).
struct Lambda : LevelSet {
    std::function<double(double, double)> f;
    Box box;
    explicit Lambda(std::function<double(double, double)> g, Box b = {0, 0, 1, 1}) : f(std::move(g)), box(b) {}
    double value(double x, double y) const override { return f(x, y); }
    Box bounds() const override { return box; }
    std::string describe() const override { return "lambda"; }
};

// Lattice values given directly, f piecewise linear along lattice edges: the
// cut parameter is exact linear interpolation.
struct Grid : LevelSet {
    Lattice lat;
    std::vector<double> v;
    Grid(std::int64_t nx, std::int64_t ny, std::vector<double> vals) : v(std::move(vals)) {
        lat.nx = nx, lat.ny = ny;
    }
    double value(double x, double y) const override {
        return v[static_cast<std::size_t>(lat.index(std::llround(x), std::llround(y)))];
    }
    double cut_parameter(Vec2, Vec2, double fa, double fb) const override { return fa / (fa - fb); }
    Box bounds() const override { return {0, 0, double(lat.nx), double(lat.ny)}; }
    std::string describe() const override { return "grid"; }
};

Choice choose(DiagonalRule rule, std::array<Warp, 4> w, std::array<double, 4> t, std::array<int, 4> sign) {
    std::array<CornerState, 4> s{};
    for (int k = 0; k < 4; ++k) s[k] = {static_cast<std::int8_t>(sign[k]), w[k]};
    return choose_diagonal(rule, generic_positions(w, t), s);
}

}  // namespace

BOOST_AUTO_TEST_CASE(bracketed_root_is_exact_on_a_line_and_close_on_a_circle) {
    Lambda line([](double x, double) { return x - 0.3; });
    const double u = bracketed_root(line, {0, 0}, {1, 0}, -0.3, 0.7);
    BOOST_TEST(std::abs(u - 0.3) < 1e-15);

    Lambda circle([](double x, double y) { return std::hypot(x, y) - 1; });
    // Edge from (0.5, 0.5) to (1.5, 0.5): root at x = sqrt(1 - 0.25).
    const double fa = circle.value(0.5, 0.5), fb = circle.value(1.5, 0.5);
    const double v = bracketed_root(circle, {0.5, 0.5}, {1.5, 0.5}, fa, fb);
    BOOST_TEST(std::abs(0.5 + v - std::sqrt(0.75)) < 1e-13);
}

BOOST_AUTO_TEST_CASE(bracketed_root_stays_strictly_inside_the_edge) {
    // The zero is within 1e-300 of the first endpoint: the cut point must still
    // not coincide with the lattice point.
    Lambda near([](double x, double) { return x - 1e-300; });
    const double u = bracketed_root(near, {0, 0}, {1, 0}, -1e-300, 1);
    BOOST_TEST(u > 0);
    BOOST_TEST(u < 1);
    Lambda far([](double x, double) { return x - (1 - 1e-17); });
    const double w = bracketed_root(far, {0, 0}, {1, 0}, far.value(0, 0), 1e-17);
    BOOST_TEST(w < 1);
}

BOOST_AUTO_TEST_CASE(zero_valued_points_have_no_cut_edges) {
    // 3x1 points: -1, 0, +1.  The zero point separates them: no cut edge.
    Grid g(2, 0, {-1, 0, 1});
    g.lat.ny = 0;
    const auto values = sample_values(g, g.lat);
    const auto signs = compute_signs(values);
    BOOST_TEST(signs[1] == 0);
    BOOST_TEST(find_cut_edges(g, g.lat, values, signs).empty());
}

BOOST_AUTO_TEST_CASE(closer_endpoint_warps) {
    // Row of 2 points: -1 then +3: cut at u = 1/4 from the first, which moves +x.
    Grid g(1, 0, {-1, 3});
    const auto values = sample_values(g, g.lat);
    const auto signs = compute_signs(values);
    const auto cuts = find_cut_edges(g, g.lat, values, signs);
    BOOST_REQUIRE_EQUAL(cuts.size(), 1u);
    BOOST_TEST(cuts[0].u == 0.25);
    auto w = warp_points(g.lat, cuts);
    BOOST_REQUIRE_EQUAL(w.size(), 1u);
    BOOST_TEST(w[0].p == 0);
    BOOST_TEST((w[0].dir == Warp::px));
    BOOST_TEST(w[0].t == 0.25);

    // -3 then +1: cut at u = 3/4; the second point moves -x by 1/4.
    Grid h(1, 0, {-3, 1});
    const auto hv = sample_values(h, h.lat);
    const auto hs = compute_signs(hv);
    w = warp_points(h.lat, find_cut_edges(h, h.lat, hv, hs));
    BOOST_REQUIRE_EQUAL(w.size(), 1u);
    BOOST_TEST(w[0].p == 1);
    BOOST_TEST((w[0].dir == Warp::mx));
    BOOST_TEST(w[0].t == 0.25);
}

BOOST_AUTO_TEST_CASE(tie_at_half_moves_the_inside_endpoint) {
    for (double sign : {1.0, -1.0}) {
        Grid g(1, 0, {sign * 1, -sign * 1});  // cut exactly at the midpoint
        const auto v = sample_values(g, g.lat);
        const auto s = compute_signs(v);
        const auto w = warp_points(g.lat, find_cut_edges(g, g.lat, v, s));
        BOOST_REQUIRE_EQUAL(w.size(), 1u);
        BOOST_TEST(w[0].t == 0.5);
        BOOST_TEST(s[static_cast<std::size_t>(w[0].p)] == -1);  // the inside endpoint moved
    }
}

BOOST_AUTO_TEST_CASE(a_point_closer_to_several_cut_points_takes_the_nearest) {
    // 2x2 points; point 0 is inside; its +x neighbour cut at 0.4, its +y at 0.2.
    // values: p0 = -1, p1 = 1.5 (u = 1/2.5 = 0.4), p2 = 4 (u = 0.2), p3 = 1.
    Grid g(1, 1, {-1, 1.5, 4, 1});
    const auto v = sample_values(g, g.lat);
    const auto s = compute_signs(v);
    const auto cuts = find_cut_edges(g, g.lat, v, s);
    BOOST_REQUIRE_EQUAL(cuts.size(), 2u);
    const auto w = warp_points(g.lat, cuts);
    BOOST_REQUIRE_EQUAL(w.size(), 1u);
    BOOST_TEST((w[0].dir == Warp::py));
    BOOST_TEST(std::abs(w[0].t - 0.2) < 1e-15);

    // Equal distances: +x wins over +y.
    Grid e(1, 1, {-1, 3, 3, 1});
    const auto ev = sample_values(e, e.lat);
    const auto es = compute_signs(ev);
    const auto ew = warp_points(e.lat, find_cut_edges(e, e.lat, ev, es));
    BOOST_REQUIRE_EQUAL(ew.size(), 1u);
    BOOST_TEST((ew[0].dir == Warp::px));
}

// The warp's merge of its four candidate lists against the rule written out
// directly: every candidate, sorted by (point, distance, direction), the
// first of each point kept.  Random grids with many ties (distances 1/2, equal
// distances from two sides) and zero-valued points.
BOOST_AUTO_TEST_CASE(warp_merge_matches_the_rule_on_random_grids) {
    std::mt19937 rng(11);
    for (int trial = 0; trial < 200; ++trial) {
        const std::int64_t nx = 1 + trial % 9, ny = 1 + (trial / 9) % 7;
        std::vector<double> v(static_cast<std::size_t>((nx + 1) * (ny + 1)));
        for (auto& x : v) x = std::array<double, 6>{-2, -1, 1, 2, 0, -1}[rng() % 6];
        Grid g(nx, ny, v);
        const auto values = sample_values(g, g.lat);
        const auto signs = compute_signs(values);
        const auto cuts = find_cut_edges(g, g.lat, values, signs);
        std::vector<WarpedPoint> ref;
        for (const CutEdge& e : cuts) {
            const std::int64_t q = e.p + (e.axis == 0 ? 1 : g.lat.points_x());
            if (e.u < 0.5 || (e.u == 0.5 && signs[static_cast<std::size_t>(e.p)] < 0))
                ref.push_back({e.p, e.axis == 0 ? Warp::px : Warp::py, e.u});
            else
                ref.push_back({q, e.axis == 0 ? Warp::mx : Warp::my, 1 - e.u});
        }
        std::sort(ref.begin(), ref.end(), [](const WarpedPoint& a, const WarpedPoint& b) {
            return std::tie(a.p, a.t, a.dir) < std::tie(b.p, b.t, b.dir);
        });
        ref.erase(std::unique(ref.begin(), ref.end(), [](const WarpedPoint& a, const WarpedPoint& b) { return a.p == b.p; }),
                  ref.end());
        const auto w = warp_points(g.lat, cuts);
        BOOST_TEST_REQUIRE(w.size() == ref.size());
        for (std::size_t k = 0; k < w.size(); ++k)
            BOOST_TEST((w[k].p == ref[k].p && w[k].dir == ref[k].dir && w[k].t == ref[k].t), "trial " << trial << " point " << k);
    }
}

BOOST_AUTO_TEST_CASE(diagonal_rule_on_the_unit_square_takes_AD) {
    const std::array<Warp, 4> none{};
    const Choice c = choose(DiagonalRule::maxmin, none, {0, 0, 0, 0}, {-1, -1, -1, -1});
    BOOST_TEST(c.ad);
    BOOST_TEST(!c.bc);
}

BOOST_AUTO_TEST_CASE(diagonal_rule_maximises_the_minimum_angle) {
    // D slides -x by 1/2 to (0.5, 1): AD gives triangle (A, B, D') with a thin
    // angle at A? Compare with brute force angles.
    auto min_angle = [](std::array<Point<double>, 4> p, Diagonal d) {
        double m = 180;
        for (auto tri : diagonal_triangles(d))
            for (int k = 0; k < 3; ++k) {
                auto o = p[tri[k]], q = p[tri[(k + 1) % 3]], r = p[tri[(k + 2) % 3]];
                double ux = q.x - o.x, uy = q.y - o.y, vx = r.x - o.x, vy = r.y - o.y;
                m = std::min(m, std::atan2(std::abs(ux * vy - uy * vx), ux * vx + uy * vy) * 180 / M_PI);
            }
        return m;
    };
    int bc_taken = 0;
    for (int w0 = 0; w0 < 5; ++w0)
        for (int w3 = 0; w3 < 5; ++w3)
            for (double t : {0.1, 0.3, 0.5}) {
                std::array<Warp, 4> w{static_cast<Warp>(w0), Warp::stay, Warp::stay, static_cast<Warp>(w3)};
                std::array<double, 4> tt{t, 0, 0, 0.5 - t / 2};
                const auto p = generic_positions(w, tt);
                const Choice c = choose(DiagonalRule::maxmin, w, tt, {1, -1, -1, 1});
                BOOST_TEST((c.ad != c.bc));
                const double ad = min_angle(p, Diagonal::AD), bc = min_angle(p, Diagonal::BC);
                if (c.bc) {
                    ++bc_taken;
                    BOOST_TEST(bc > ad);
                } else {
                    BOOST_TEST(ad >= bc - 1e-12);
                }
            }
    BOOST_TEST(bc_taken > 0);
}

BOOST_AUTO_TEST_CASE(an_inverted_triangle_never_wins) {
    // Corners pushed so that diagonal BC's triangle (A, B, C) is inverted:
    // B slides -x by 1/2 to (0.5, 0), C slides -... use an artificial geometry.
    std::array<Point<double>, 4> p{{{0, 0}, {1, 0}, {1.2, 0.5}, {1, 1}}};  // C right of the line B-D
    std::array<CornerState, 4> s{};
    const auto q = diagonal_quality(p, Diagonal::BC);
    BOOST_TEST((q.valid == Truth::no));
    const Choice c = choose_diagonal(DiagonalRule::maxmin, p, s);
    BOOST_TEST(c.ad);
    BOOST_TEST(!c.bc);
}

BOOST_AUTO_TEST_CASE(separating_rule_forces_the_diagonal_through_the_boundary) {
    // A stays inside, D stays outside; B and C slid outward by 1/2 to (1, -1/2)
    // and (-1/2, 1).  Max-min takes AD (smallest angle 45 deg); the separating
    // rule forces BC through the two boundary points, whose triangle (A, B', C')
    // has angles atan(1/3), atan(1/3) and 143.13 deg: the separating rule's
    // extreme configuration.
    const std::array<Warp, 4> w{Warp::stay, Warp::my, Warp::mx, Warp::stay};
    const std::array<double, 4> t{0, 0.5, 0.5, 0};
    const std::array<int, 4> sg{-1, -1, -1, 1};
    const Choice mm = choose(DiagonalRule::maxmin, w, t, sg);
    const Choice sep = choose(DiagonalRule::separating, w, t, sg);
    BOOST_TEST(sep.bc);
    BOOST_TEST(!sep.ad);
    BOOST_TEST(mm.ad);
    BOOST_TEST(!mm.bc);
    // A zero-valued corner does not trigger the rule.
    const Choice z = choose(DiagonalRule::separating, w, t, {0, 1, 1, 1});
    BOOST_TEST(z.ad == mm.ad);
}

BOOST_AUTO_TEST_CASE(isolated_inside_point_gives_no_triangle_and_a_valid_empty_mesh) {
    // 3x3 points, the centre inside, the rest outside.
    Grid g(2, 2, {1, 1, 1, 1, -1, 1, 1, 1, 1});
    const auto r = mesh_uniform(g, g.lat, DiagonalRule::separating);
    BOOST_TEST(r.mesh.triangles.empty());
    BOOST_TEST(r.mesh.vertices.empty());
    BOOST_TEST(r.warped_points == 1);
}

BOOST_AUTO_TEST_CASE(fully_inside_lattice_is_the_plain_lattice_with_domain_boundary) {
    Grid g(3, 2, std::vector<double>(12, -1.0));
    const auto r = mesh_uniform(g, g.lat, DiagonalRule::maxmin);
    BOOST_TEST(r.mesh.triangles.size() == 12u);
    BOOST_TEST(r.mesh.vertices.size() == 12u);
    BOOST_TEST(r.mesh.boundary.size() == 10u);
    for (auto tag : r.mesh.boundary_tag) BOOST_TEST(tag == boundary_domain);
    const auto chk = check_mesh(r.mesh);
    BOOST_TEST(chk.ok());
}

BOOST_AUTO_TEST_CASE(non_finite_values_are_refused) {
    Lambda nan([](double x, double) { return x > 0.5 ? std::nan("") : -1.0; }, {0, 0, 1, 1});
    Lattice l = lattice_over(nan.bounds(), 1);
    BOOST_CHECK_THROW(sample_values(nan, l), std::runtime_error);
}

BOOST_AUTO_TEST_CASE(mesh_check_detects_broken_meshes) {
    Mesh m;
    m.vertices = {{0, 0}, {1, 0}, {0, 1}, {1, 1}};
    m.triangles = {{0, 1, 3}, {0, 3, 2}};
    m.boundary = {{0, 1}, {1, 3}, {3, 2}, {2, 0}};
    m.boundary_tag = {1, 1, 1, 1};
    m.region = {1, 1};
    BOOST_TEST(check_mesh(m).ok());
    Mesh flipped = m;
    std::swap(flipped.triangles[1][1], flipped.triangles[1][2]);
    BOOST_TEST(!check_mesh(flipped).ok());
    Mesh missing = m;
    missing.boundary.pop_back();
    missing.boundary_tag.pop_back();
    BOOST_TEST(!check_mesh(missing).ok());
    Mesh extra = m;
    extra.vertices.push_back({5, 5});
    BOOST_TEST(!check_mesh(extra).ok());
}

BOOST_AUTO_TEST_CASE(separating_rule_applies_to_unwarped_squares_with_zero_corners) {
    // A inside, B and C exactly on the level set, D outside, nothing warps.
    // The separating rule must still take BC, emitting triangle (A, B, C) with
    // its boundary edge BC on the level set; max-min takes AD (a tie on the
    // unit square), whose triangles both touch D: nothing is emitted.
    Grid g(1, 1, {-1, 0, 0, 1});
    const auto sep = mesh_uniform(g, g.lat, DiagonalRule::separating);
    BOOST_TEST(sep.warped_points == 0);
    BOOST_REQUIRE_EQUAL(sep.mesh.triangles.size(), 1u);
    BOOST_TEST(check_mesh(sep.mesh).ok());
    const auto mm = mesh_uniform(g, g.lat, DiagonalRule::maxmin);
    BOOST_TEST(mm.mesh.triangles.empty());
}

// Issue 50: --max-memory did not count --optimize (`--shape circle:0,0,1
// --spacing 0.000471 --optimize` was admitted at an estimated 1940 MB under
// the default 2048 MB and peaked at 2383 MB).  Now the admission of a uniform
// mesh counts the pass (optimize_bytes_per_square), and the pass is admitted
// again on the mesh's triangles before it starts.  A limit that admits the
// mesh without the pass refuses it with the pass, naming the option.  The
// limit bounds what the call needs above its own baseline (memory.hpp), so
// it holds no term for what the test process is already resident at: under
// AddressSanitizer that is tens of MB of shadow memory, which made such a
// term admit the pass (the failure this test met in CI's sanitizer stage).
BOOST_AUTO_TEST_CASE(max_memory_counts_the_optimisation_pass) {
    const auto f = parse_shape("circle:0,0,1");
    MeshOptions o;
    o.spacing = 0.004;  // about 250 000 lattice squares
    const std::uint64_t squares = 520 * 520;
    o.max_memory = squares * (mesh_bytes_per_square(false, false) + optimize_bytes_per_square(false) / 2);
    o.optimize = true;
    BOOST_TEST(testing::throws_containing([&] { mesh(*f, o); }, "max_memory limit of"));
    BOOST_TEST(testing::throws_containing([&] { mesh(*f, o); }, "the optimisation pass included"));
    o.optimize = false;
    BOOST_TEST(mesh(*f, o).mesh.triangles.size() > 0);
}
