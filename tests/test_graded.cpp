// Tests of the graded mesher: the quadtree's invariants, conformity, the
// boundary and area against the uniform mesh at the same finest spacing, the
// angle bounds, determinism, and real images.
#define BOOST_TEST_MODULE graded
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <functional>
#include <map>
#include <numeric>
#include <random>
#include <string>
#include <tuple>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "warpmesh/certify/certified.hpp"
#include "warpmesh/mesh2d/graded.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "warpmesh/mesh2d/uniform.hpp"
#include "certified_stage.hpp"
#include "support.hpp"
#include "without_range.hpp"
#include "mesh2d/graded/point_set.hpp"
#include "mesh2d/graded/quadtree.hpp"
#include "mesh2d/graded/tiles.hpp"
#include "mesh2d/graded/triangulate_graded.hpp"

using namespace warpmesh;

namespace {

using Fn = std::function<double(double, double)>;

struct Lambda : LevelSet {
    Fn f;
    Box box;
    Lambda(Fn g, Box b) : f(std::move(g)), box(b) {}
    double value(double x, double y) const override { return f(x, y); }
    Box bounds() const override { return box; }
    std::string describe() const override { return "lambda"; }
};

Fn circle(double cx, double cy, double r) {
    return [=](double x, double y) { return std::hypot(x - cx, y - cy) - r; };
}
Fn ellipse(double cx, double cy, double a, double b) {
    return [=](double x, double y) { return std::min(a, b) * (std::hypot((x - cx) / a, (y - cy) / b) - 1); };
}
Fn unite(Fn a, Fn b) {
    return [=](double x, double y) { return std::min(a(x, y), b(x, y)); };
}
Fn subtract(Fn a, Fn b) {
    return [=](double x, double y) { return std::max(a(x, y), -b(x, y)); };
}

Lattice integer_lattice(std::int64_t nx, std::int64_t ny) {
    Lattice l;
    l.x0 = 0, l.y0 = 0, l.s = 1, l.nx = nx, l.ny = ny;
    return l;
}

using testing::boundary_coords;
double area(const Mesh& m) { return testing::mesh_area(m); }
std::array<double, 3> angles(const Mesh& m, std::size_t t) { return testing::triangle_angles_deg(m, t); }

// The quadtree of the graded mesh, rebuilt from the public stages.
struct Tree {
    TiledSigns signs;
    Quadtree tree;
    Leaves leaves;
};
Tree rebuild(const LevelSet& f, const Lattice& l, std::int64_t K, int buffer = 0) {
    Tree t;
    const auto values = sample_values(f, l);
    const auto signs = compute_signs(values);
    t.signs = tile_signs(l, signs);  // every tile sampled, from the uniform front end
    const auto warped = warp_points(l, find_cut_edges(f, l, values, signs));
    t.tree = build_quadtree(l, t.signs, warped, K, buffer);
    t.leaves = quadtree_leaves(t.tree);
    return t;
}

bool is_integer(double v) { return v == std::floor(v); }

// No mesh vertex lies strictly inside a triangle edge whose endpoints are
// lattice points (integer lattice); and every split side's midpoint is a
// vertex of triangles on both sides of the split side.
void check_no_hanging_vertices(const Mesh& m, const Tree& t) {
    std::map<std::pair<double, double>, std::int32_t> at;
    for (std::size_t v = 0; v < m.vertices.size(); ++v) at[{m.vertices[v].x, m.vertices[v].y}] = static_cast<std::int32_t>(v);
    std::int64_t hanging = 0;
    for (const auto& tri : m.triangles)
        for (int k = 0; k < 3; ++k) {
            const Vec2 a = m.vertices[static_cast<std::size_t>(tri[k])], b = m.vertices[static_cast<std::size_t>(tri[(k + 1) % 3])];
            if (!is_integer(a.x) || !is_integer(a.y) || !is_integer(b.x) || !is_integer(b.y)) continue;
            const auto dx = static_cast<std::int64_t>(b.x - a.x), dy = static_cast<std::int64_t>(b.y - a.y);
            const std::int64_t g = std::gcd(std::abs(dx), std::abs(dy));
            for (std::int64_t q = 1; q < g; ++q)
                if (at.count({a.x + static_cast<double>(dx / g * q), a.y + static_cast<double>(dy / g * q)})) ++hanging;
        }
    BOOST_TEST(hanging == 0);

    // Incident triangles of each vertex, by centroid.
    std::vector<std::vector<Vec2>> centroids(m.vertices.size());
    for (const auto& tri : m.triangles) {
        Vec2 c{0, 0};
        for (int k = 0; k < 3; ++k) {
            c.x += m.vertices[static_cast<std::size_t>(tri[k])].x / 3;
            c.y += m.vertices[static_cast<std::size_t>(tri[k])].y / 3;
        }
        for (int k = 0; k < 3; ++k) centroids[static_cast<std::size_t>(tri[k])].push_back(c);
    }
    std::int64_t split_sides = 0, bad = 0;
    for (const Leaf& leaf : t.leaves.coarse) {
        if (leaf.sign > 0) continue;
        const double w = std::ldexp(1.0, leaf.level), h = w / 2, i = leaf.i, j = leaf.j;
        // side: midpoint, and the normal pointing into the leaf
        const std::array<std::tuple<std::uint8_t, double, double, double, double>, 4> sides{
            {{side_bottom, i + h, j, 0, 1}, {side_right, i + w, j + h, -1, 0}, {side_top, i + h, j + w, 0, -1}, {side_left, i, j + h, 1, 0}}};
        for (const auto& [bit, mx, my, nx, ny] : sides) {
            if (!(leaf.split_sides & bit)) continue;
            ++split_sides;
            const auto it = at.find({mx, my});
            if (it == at.end()) {
                ++bad;
                continue;
            }
            bool in_leaf = false, in_neighbour = false;
            for (const Vec2& c : centroids[static_cast<std::size_t>(it->second)]) {
                const double side = (c.x - mx) * nx + (c.y - my) * ny;
                in_leaf = in_leaf || side > 0;
                in_neighbour = in_neighbour || side < 0;
            }
            if (!in_leaf || !in_neighbour) ++bad;
        }
    }
    BOOST_TEST(bad == 0);
}

struct Compared {
    std::size_t uniform_triangles = 0, graded_triangles = 0;
};

// The graded mesh against the uniform one on the same lattice.
Compared compare_with_uniform(const LevelSet& f, const Lattice& l, DiagonalRule rule, std::int64_t K,
                              bool integer_coordinates = true, int buffer = 0) {
    const UniformResult u = mesh_uniform(f, l, rule);
    const GradedResult g = mesh_graded(f, l, rule, K, {}, buffer);
    const MeshCheck chk = check_mesh(g.mesh);
    BOOST_TEST(chk.ok());
    for (const auto& msg : chk.messages) BOOST_TEST_MESSAGE(msg);

    const Tree t = rebuild(f, l, K, buffer);
    const QuadtreeCheck q = check_quadtree(t.tree, t.signs);
    BOOST_TEST(q.ok());
    for (const auto& msg : q.messages) BOOST_TEST_MESSAGE(msg);
    std::int64_t leaves = 0;
    for (auto c : g.leaves_per_level) leaves += c;
    std::int64_t finest = 0;  // the finest leaves, listed by their parents
    for_each_finest(t.leaves, [&](std::int64_t, std::int64_t) { ++finest; });
    BOOST_TEST(finest == t.leaves.finest);
    BOOST_TEST(g.leaves_per_level.at(0) == finest);
    BOOST_TEST(leaves == finest + static_cast<std::int64_t>(t.leaves.coarse.size()));
    // The range bounds only skip work: the same mesh, bit for bit, as with
    // every tile sampled.
    const GradedResult all = mesh_graded(testing::WithoutRange(f), l, rule, K, {}, buffer);
    BOOST_TEST(testing::same_mesh(all.mesh, g.mesh));
    BOOST_TEST(all.sampled_points >= l.point_count());  // tiles share their border points
    BOOST_TEST(g.sampled_points <= all.sampled_points);

    // Same boundary, same area.
    BOOST_TEST((boundary_coords(g.mesh) == boundary_coords(u.mesh)));
    const double ua = area(u.mesh), ga = area(g.mesh);
    BOOST_TEST(std::abs(ua - ga) <= 1e-9 * std::max(1.0, ua));
    BOOST_TEST(g.cut_edges == u.cut_edges);
    BOOST_TEST(g.stats.warped_squares == u.stats.warped_squares);
    BOOST_TEST(g.stats.forced_diagonals == u.stats.forced_diagonals);
    BOOST_TEST(g.mesh.triangles.size() <= u.mesh.triangles.size());

    // Angles: within the uniform mesh's range and the rule's certified theorem U;
    // triangles with three lattice-point vertices are template shapes.
    double umin = 180, umax = 0;
    for (std::size_t k = 0; k < u.mesh.triangles.size(); ++k)
        for (double a : angles(u.mesh, k)) umin = std::min(umin, a), umax = std::max(umax, a);
    const double eps = 1e-9;
    std::int64_t out_of_range = 0, bad_template = 0;
    for (std::size_t k = 0; k < g.mesh.triangles.size(); ++k) {
        const auto a = angles(g.mesh, k);
        bool lattice_only = integer_coordinates;
        for (int v = 0; v < 3; ++v) {
            const Vec2 p = g.mesh.vertices[static_cast<std::size_t>(g.mesh.triangles[k][v])];
            lattice_only = lattice_only && is_integer(p.x) && is_integer(p.y);
        }
        for (double x : a) {
            if (x < umin - eps || x > umax + eps || x > certified_theorem(rule).max_deg_any + eps) ++out_of_range;
            if (x < certified_theorem(rule).min_deg_any - eps) ++out_of_range;
            if (lattice_only && (x < 45 - eps || x > 90 + eps)) ++bad_template;
        }
    }
    BOOST_TEST(out_of_range == 0);
    BOOST_TEST(bad_template == 0);
    if (integer_coordinates) check_no_hanging_vertices(g.mesh, t);
    return {u.mesh.triangles.size(), g.mesh.triangles.size()};
}

}  // namespace

BOOST_AUTO_TEST_CASE(max_cell_must_be_a_power_of_two) {
    Lambda f(circle(8, 8, 5), {0, 0, 16, 16});
    const Lattice l = integer_lattice(16, 16);
    BOOST_CHECK_THROW(mesh_graded(f, l, DiagonalRule::maxmin, 3), std::invalid_argument);
    BOOST_CHECK_THROW(mesh_graded(f, l, DiagonalRule::maxmin, -2), std::invalid_argument);
    BOOST_CHECK_NO_THROW(mesh_graded(f, l, DiagonalRule::maxmin, 1));
    BOOST_CHECK_NO_THROW(mesh_graded(f, l, DiagonalRule::maxmin, 1024));
}

BOOST_AUTO_TEST_CASE(max_cell_one_is_the_uniform_mesh) {
    Lambda f(subtract(circle(30, 31, 24.3), ellipse(33, 29, 9.2, 5.1)), {0, 0, 64, 64});
    const Lattice l = integer_lattice(64, 64);
    for (auto rule : {DiagonalRule::maxmin, DiagonalRule::separating}) {
        const auto u = mesh_uniform(f, l, rule);
        const auto g = mesh_graded(f, l, rule, 1);
        BOOST_TEST(g.leaves_per_level.size() == 1u);
        // Same vertices in the same (point) order; same triangles as sets.
        BOOST_REQUIRE(g.mesh.vertices.size() == u.mesh.vertices.size());
        for (std::size_t v = 0; v < u.mesh.vertices.size(); ++v) {
            BOOST_TEST(g.mesh.vertices[v].x == u.mesh.vertices[v].x);
            BOOST_TEST(g.mesh.vertices[v].y == u.mesh.vertices[v].y);
        }
        auto sorted = [](Buffer<std::array<std::int32_t, 3>> t) {
            std::sort(t.begin(), t.end());
            return t;
        };
        BOOST_TEST((sorted(g.mesh.triangles) == sorted(u.mesh.triangles)));
    }
}

// --grading G (graded.hpp): the buffer n for G, and what it guarantees.
BOOST_AUTO_TEST_CASE(grading_maps_to_a_buffer_and_bad_values_are_refused) {
    BOOST_TEST(grading_buffer(2.0) == 0);
    BOOST_TEST(grading_buffer(1.9) == 2);
    BOOST_TEST(grading_buffer(1.5) == 2);
    BOOST_TEST(grading_buffer(1.414) == 2);  // √2, as typed
    BOOST_TEST(grading_buffer(1.41) == 3);
    BOOST_TEST(grading_buffer(1.26) == 3);  // 2^(1/3)
    BOOST_TEST(grading_buffer(1.1) == 8);
    for (double bad : {1.09, 1.0, 0.5, 2.01, 4.0, std::nan(""), HUGE_VAL})
        BOOST_CHECK_THROW(grading_buffer(bad), std::invalid_argument);
    Lambda f(circle(8, 8, 5), {0, 0, 16, 16});
    BOOST_CHECK_THROW(mesh_graded(f, integer_lattice(16, 16), DiagonalRule::separating, 0, {}, 9), std::invalid_argument);
    BOOST_CHECK_THROW(mesh_graded(f, integer_lattice(16, 16), DiagonalRule::separating, 0, {}, -1), std::invalid_argument);
}

// Every coarse inside leaf of width w is farther than n w (max-norm) from
// every critical point (zero-valued, or an endpoint of a cut edge) and from
// the lattice border; the mesh stays conforming, with the uniform boundary,
// template triangles inside; and a larger buffer never gives fewer triangles.
BOOST_AUTO_TEST_CASE(grading_buffer_keeps_coarse_leaves_n_widths_from_the_boundary) {
    Lambda f(subtract(unite(circle(70, 60, 52.5), ellipse(150, 50, 30, 12.3)), circle(60, 64, 9.7)), {0, 0, 190, 128});
    const Lattice l = integer_lattice(190, 128);
    std::size_t previous = 0;
    for (const int n : {0, 2, 3, 5, 8}) {
        BOOST_TEST_CONTEXT("buffer " << n) {
            const Compared c = compare_with_uniform(f, l, DiagonalRule::separating, 0, true, n);
            BOOST_TEST(c.graded_triangles >= previous);
            BOOST_TEST(c.graded_triangles < c.uniform_triangles);
            previous = c.graded_triangles;
            const Tree t = rebuild(f, l, 0, n);
            // Critical points, and a prefix-sum table of them.
            const std::int64_t px = l.nx + 1, py = l.ny + 1;
            std::vector<std::int64_t> sum(static_cast<std::size_t>((px + 1) * (py + 1)), 0);
            auto S = [&](std::int64_t x, std::int64_t y) -> std::int64_t& { return sum[static_cast<std::size_t>(x + y * (px + 1))]; };
            for (std::int64_t y = 0; y < py; ++y)
                for (std::int64_t x = 0; x < px; ++x) {
                    const int v = t.signs(x, y);
                    bool crit = v == 0;
                    for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
                        const std::int64_t a = x + dx, b = y + dy;
                        if (a >= 0 && b >= 0 && a < px && b < py) crit = crit || t.signs(a, b) == -v;
                    }
                    S(x + 1, y + 1) = S(x, y + 1) + S(x + 1, y) - S(x, y) + (crit ? 1 : 0);
                }
            auto count = [&](std::int64_t x0, std::int64_t y0, std::int64_t x1, std::int64_t y1) {  // points in [x0, x1] x [y0, y1]
                x0 = std::max<std::int64_t>(x0, 0), y0 = std::max<std::int64_t>(y0, 0);
                x1 = std::min(x1, px - 1), y1 = std::min(y1, py - 1);
                if (x0 > x1 || y0 > y1) return std::int64_t{0};
                return S(x1 + 1, y1 + 1) - S(x0, y1 + 1) - S(x1 + 1, y0) + S(x0, y0);
            };
            std::int64_t near = 0, inside_leaves = 0, max_level = 0;
            for (const Leaf& leaf : t.leaves.coarse) {
                if (leaf.sign > 0) continue;
                ++inside_leaves;
                const std::int64_t w = std::int64_t{1} << leaf.level, r = n * w;
                max_level = std::max<std::int64_t>(max_level, leaf.level);
                near += count(leaf.i - r, leaf.j - r, leaf.i + w + r, leaf.j + w + r) > 0;
            }
            BOOST_TEST(inside_leaves > 0);
            BOOST_TEST(max_level >= (n <= 3 ? 2 : 1));  // (the disc is 105 squares across: with n = 8 a leaf of 4 needs 32 all round)
            if (n > 0) {
                BOOST_TEST(near == 0);
            }
        }
    }
}

// A region that fills the lattice: the inside border squares are critical for
// the grading too, so leaves keep n widths from the lattice border.
BOOST_AUTO_TEST_CASE(grading_buffer_keeps_leaves_off_the_lattice_border) {
    Lambda f([](double, double) { return -1.0; }, {0, 0, 200, 150});
    const Lattice l = integer_lattice(200, 150);
    for (const int n : {2, 4}) {
        compare_with_uniform(f, l, DiagonalRule::separating, 0, true, n);
        const Tree t = rebuild(f, l, 0, n);
        std::int64_t bad = 0;
        for (const Leaf& leaf : t.leaves.coarse) {
            const std::int64_t w = std::int64_t{1} << leaf.level, r = n * w;
            // the border squares are finest: their inner sides lie 1 square in
            bad += leaf.i - r < 1 || leaf.j - r < 1 || leaf.i + w + r > l.nx - 1 || leaf.j + w + r > l.ny - 1;
        }
        BOOST_TEST(bad == 0);
    }
}

// max_cell_for_size: the largest power of two K with √2 K s <= H; H below
// √5 s (the warped band's longest possible edge) refused.
BOOST_AUTO_TEST_CASE(max_size_gives_the_largest_cell_whose_diagonal_fits) {
    BOOST_TEST(max_cell_for_size(std::sqrt(5.0), 1) == 1);
    BOOST_TEST(max_cell_for_size(2.9, 1) == 2);
    BOOST_TEST(max_cell_for_size(4 * std::sqrt(2.0), 1) == 4);
    BOOST_TEST(max_cell_for_size(0.4, 0.05) == 4);  // √2·4·0.05 = 0.283 <= 0.4 < 0.566
    BOOST_TEST(max_cell_for_size(1e300, 1) == std::int64_t{1} << 30);
    for (double bad : {2.2, 0.0, -1.0, std::nan(""), HUGE_VAL}) BOOST_CHECK_THROW(max_cell_for_size(bad, 1), std::invalid_argument);
}

// With max_cell_for_size(H, s) every triangle's longest edge is <= H: the
// band's (<= √5 s) and the templates' (<= √2 K s).
BOOST_AUTO_TEST_CASE(max_size_bounds_every_edge_of_the_graded_mesh) {
    const auto flower = parse_shape("flower:0.3,-0.2,60,22,9");
    const auto holes = parse_shape("diff(circle:0,0,70;union(rect:-20,-15,18,21;circle:40,10,9))");
    for (const LevelSet* f : {flower.get(), holes.get()})
        for (const double s : {1.0, 0.7})
            for (const double H : {std::sqrt(5.0) * s, 3.5 * s, 12.0 * s})
                for (const int n : {0, 3}) {
                    const Lattice l = lattice_around(f->bounds(), s);
                    const std::int64_t K = max_cell_for_size(H, s);
                    const auto g = testing::certified(mesh_graded(*f, l, DiagonalRule::separating, K, {true, false}, n), l,
                                                      DiagonalRule::separating, {true, true, false});
                    BOOST_TEST(check_mesh(g.mesh).ok());
                    BOOST_TEST(g.leaves_per_level.size() == static_cast<std::size_t>(std::countr_zero(static_cast<std::uint64_t>(K))) + 1);
                    double longest = 0;
                    for (const auto& t : g.mesh.triangles)
                        for (int k = 0; k < 3; ++k) {
                            const Vec2 a = g.mesh.vertices[static_cast<std::size_t>(t[k])], b = g.mesh.vertices[static_cast<std::size_t>(t[(k + 1) % 3])];
                            longest = std::max(longest, std::hypot(a.x - b.x, a.y - b.y));
                        }
                    BOOST_TEST(longest <= H * (1 + 1e-12), "longest " << longest << " H " << H << " s " << s);
                    BOOST_TEST(longest > H / 2.9);  // K is the largest that fits (coarsest leaves present)
                }
}

// Inside classes (quadtree.hpp; the per-material size caps of the
// multi-material mesher): random Voronoi "materials" on the lattice points,
// each with the code +1 (outside), -1 (inside) or an inside class -2 - L
// (L = 0 .. 5), and 0 at every point with a 4-neighbour of another material.
// Whatever the grading buffer, max cell and tile size, check_quadtree holds
// (no coarse leaf of a class above its level, critical squares finest, 2:1
// balance, each coarse leaf of one code), the leaves do not depend on the
// tile size (tiled and dense storage agree; the tiles of a class below the
// tiles' level are activated), and the classes do coarsen up to their level.
BOOST_AUTO_TEST_CASE(inside_classes_cap_their_leaves_whatever_the_tiles) {
    std::mt19937 rng(1818);
    std::int64_t at_cap = 0;
    for (int trial = 0; trial < warpmesh::testing::scaled(24); ++trial) {
        const Lattice l = integer_lattice(90 + 37 * (trial % 5), 70 + 23 * (trial % 3));
        const std::int64_t nxp = l.nx + 1, nyp = l.ny + 1;
        std::uniform_real_distribution<double> px(0, static_cast<double>(l.nx)), py(0, static_cast<double>(l.ny));
        std::uniform_int_distribution<int> kind(-1, 6);  // -1: outside, 0: inside, 1 .. 6: class L = kind - 1
        std::vector<std::array<double, 2>> seeds(static_cast<std::size_t>(3 + trial % 6));
        std::vector<std::int8_t> code(seeds.size());
        for (std::size_t k = 0; k < seeds.size(); ++k) {
            seeds[k] = {px(rng), py(rng)};
            const int c = kind(rng);
            code[k] = c < 0 ? std::int8_t{1} : c == 0 ? std::int8_t{-1} : inside_class(c - 1);
        }
        std::vector<int> mat(static_cast<std::size_t>(nxp * nyp));
        for (std::int64_t j = 0; j < nyp; ++j)
            for (std::int64_t i = 0; i < nxp; ++i) {
                double best = 1e300;
                for (std::size_t k = 0; k < seeds.size(); ++k) {
                    const double d = std::hypot(static_cast<double>(i) - seeds[k][0], static_cast<double>(j) - seeds[k][1]);
                    if (d < best) best = d, mat[static_cast<std::size_t>(i + j * nxp)] = static_cast<int>(k);
                }
            }
        std::vector<std::int8_t> sg(mat.size());
        for (std::int64_t j = 0; j < nyp; ++j)
            for (std::int64_t i = 0; i < nxp; ++i) {
                const int m = mat[static_cast<std::size_t>(i + j * nxp)];
                const auto other = [&](std::int64_t a, std::int64_t b) {
                    return a >= 0 && b >= 0 && a < nxp && b < nyp && mat[static_cast<std::size_t>(a + b * nxp)] != m;
                };
                const bool critical = other(i - 1, j) || other(i + 1, j) || other(i, j - 1) || other(i, j + 1);
                sg[static_cast<std::size_t>(i + j * nxp)] = critical ? std::int8_t{0} : code[static_cast<std::size_t>(m)];
            }
        const std::int64_t K = trial % 3 == 0 ? 0 : std::int64_t{1} << (3 + trial % 4);
        const int buffer = std::array<int, 3>{0, 2, 5}[static_cast<std::size_t>(trial % 3)];
        using Key = std::tuple<std::int32_t, std::int32_t, int, int>;
        std::vector<Key> first;
        for (const int tile_log : {2, 3, 4, 5, 7}) {
            BOOST_TEST_CONTEXT("trial " << trial << " lattice " << l.nx << " x " << l.ny << " K " << K << " buffer " << buffer
                                        << " tile_log " << tile_log) {
                const TiledSigns signs = tile_signs(l, sg, tile_log, /*sample_every_tile=*/false);
                const Quadtree tree = build_quadtree(l, signs, {}, K, buffer, /*classes=*/true);
                const QuadtreeCheck chk = check_quadtree(tree, signs);
                BOOST_TEST(chk.ok());
                for (const auto& msg : chk.messages) BOOST_TEST_MESSAGE(msg);
                const Leaves leaves = quadtree_leaves(tree);
                std::vector<Key> keys;
                for (const Leaf& leaf : leaves.coarse) {
                    keys.emplace_back(leaf.i, leaf.j, leaf.level, leaf.sign);
                    at_cap += tile_log == 4 && leaf.level == cap_level(leaf.sign);
                }
                for_each_finest(leaves, [&](std::int64_t i, std::int64_t j) {
                    keys.emplace_back(static_cast<std::int32_t>(i), static_cast<std::int32_t>(j), 0, 0);
                });
                std::sort(keys.begin(), keys.end());
                if (first.empty()) first = keys;
                BOOST_TEST((keys == first));
            }
        }
    }
    BOOST_TEST(at_cap > 100);  // the classes' leaves reach their level
}

BOOST_AUTO_TEST_CASE(fully_inside_lattice_keeps_a_finest_border_and_coarsens_inside) {
    Lambda f([](double, double) { return -1.0; }, {0, 0, 64, 64});
    const Lattice l = integer_lattice(64, 64);
    const auto g = mesh_graded(f, l, DiagonalRule::maxmin, 0);
    BOOST_TEST(check_mesh(g.mesh).ok());
    for (auto tag : g.mesh.boundary_tag) BOOST_TEST(tag == boundary_domain);
    BOOST_TEST(g.mesh.boundary.size() == 4u * 64u);  // every border square is finest
    BOOST_TEST(g.leaves_per_level.size() == 7u);
    BOOST_TEST(g.leaves_per_level[4] > 0);  // 16 x 16 leaves inside
    BOOST_TEST(std::abs(area(g.mesh) - 64.0 * 64.0) < 1e-9);
    compare_with_uniform(f, l, DiagonalRule::maxmin, 0);
}

BOOST_AUTO_TEST_CASE(a_tiny_hole_inside_a_big_cell_is_found) {
    // A hole around one lattice point deep inside a disc: the point is
    // outside, its four neighbours inside; the pyramid must not coarsen over it.
    Lambda f(subtract(circle(64, 64, 60), circle(41, 77, 0.3)), {0, 0, 128, 128});
    const Lattice l = integer_lattice(128, 128);
    const auto r = compare_with_uniform(f, l, DiagonalRule::maxmin, 0);
    BOOST_TEST(r.graded_triangles * 3 < r.uniform_triangles);
    const Tree t = rebuild(f, l, 0);
    BOOST_TEST(t.tree.is_finest(41, 77));
    BOOST_TEST(t.tree.is_finest(40, 76));
}

BOOST_AUTO_TEST_CASE(non_power_of_two_lattices_and_max_cells) {
    Lambda f(unite(circle(40, 20, 17.5), ellipse(75, 18, 20, 8.3)), {0, 0, 100, 37});
    for (std::int64_t K : {0, 2, 4, 8, 32})
        for (auto rule : {DiagonalRule::maxmin, DiagonalRule::separating})
            compare_with_uniform(f, integer_lattice(100, 37), rule, K);
    // Degenerate lattices: one row, one column.
    compare_with_uniform(f, integer_lattice(100, 1), DiagonalRule::maxmin, 0);
    compare_with_uniform(f, integer_lattice(1, 37), DiagonalRule::maxmin, 0);
}

BOOST_AUTO_TEST_CASE(random_analytic_shapes) {
    std::mt19937 rng(20240521);
    std::uniform_real_distribution<double> U(0, 1);
    for (int seed = 0; seed < 60; ++seed) {
        const std::int64_t nx = 40 + static_cast<std::int64_t>(U(rng) * 120), ny = 40 + static_cast<std::int64_t>(U(rng) * 120);
        const double X = static_cast<double>(nx), Y = static_cast<double>(ny), R = std::min(X, Y) / 2;
        auto rand_circle = [&](double scale) {
            return circle(X * (0.2 + 0.6 * U(rng)), Y * (0.2 + 0.6 * U(rng)), R * scale * (0.3 + 0.7 * U(rng)));
        };
        Fn shape;
        switch (seed % 4) {
            case 0: shape = rand_circle(1.0); break;
            case 1:
                shape = ellipse(X * (0.3 + 0.4 * U(rng)), Y * (0.3 + 0.4 * U(rng)), R * (0.3 + 0.8 * U(rng)),
                                R * (0.2 + 0.7 * U(rng)));
                break;
            case 2: {  // annulus, possibly cut by the border
                const double cx = X * (0.2 + 0.6 * U(rng)), cy = Y * (0.2 + 0.6 * U(rng)), r2 = R * (0.5 + 0.6 * U(rng));
                shape = subtract(circle(cx, cy, r2), circle(cx + U(rng), cy - U(rng), r2 * (0.2 + 0.5 * U(rng))));
                break;
            }
            default: shape = subtract(unite(rand_circle(0.8), rand_circle(0.8)), rand_circle(0.4)); break;
        }
        Lambda f(shape, {0, 0, X, Y});
        const std::int64_t K = std::array<std::int64_t, 4>{0, 4, 8, 2}[static_cast<std::size_t>(seed % 4)];
        const auto rule = seed % 2 ? DiagonalRule::separating : DiagonalRule::maxmin;
        BOOST_TEST_CONTEXT("seed " << seed << " lattice " << nx << "x" << ny << " K " << K) {
            compare_with_uniform(f, integer_lattice(nx, ny), rule, K);
        }
    }
}

BOOST_AUTO_TEST_CASE(zero_valued_points_and_forced_diagonals_match_the_uniform_mesh) {
    // f = x + y - 21 vanishes exactly at lattice points: squares with A < 0,
    // D > 0 and B = C = 0, where the separating rule forces BC on an
    // unwarped square.  Plus a circle through lattice points (radius 5 about
    // an integer centre: (3, 4) offsets are exact zeros).
    Lambda line([](double x, double y) { return x + y - 21.0; }, {0, 0, 48, 40});
    Lambda round(circle(20, 20, 5), {0, 0, 48, 40});
    for (auto rule : {DiagonalRule::maxmin, DiagonalRule::separating})
        for (const LevelSet* f : {static_cast<const LevelSet*>(&line), static_cast<const LevelSet*>(&round)})
            compare_with_uniform(*f, integer_lattice(48, 40), rule, 0);
    const auto g = mesh_graded(line, integer_lattice(48, 40), DiagonalRule::separating, 0);
    BOOST_TEST(g.stats.forced_diagonals > 0);
}

BOOST_AUTO_TEST_CASE(non_integer_spacing_and_offset) {
    // Lattice points are not integers here: the template check is off, the
    // rest (boundary and area equal to the uniform mesh's) holds exactly.
    Lambda f(subtract(circle(0.31, -0.2, 1.17), ellipse(0.1, -0.1, 0.4, 0.23)), {-1.0, -1.5, 1.6, 1.1});
    const Lattice l = lattice_over(f.bounds(), 0.013);
    for (auto rule : {DiagonalRule::maxmin, DiagonalRule::separating}) compare_with_uniform(f, l, rule, 0, false);
}

BOOST_AUTO_TEST_CASE(disc_on_a_1024_lattice_has_at_least_three_times_fewer_triangles) {
    Lambda f(circle(512, 512, 460.5), {0, 0, 1024, 1024});
    const Lattice l = integer_lattice(1024, 1024);
    const auto u = mesh_uniform(f, l, DiagonalRule::maxmin);
    const auto g = mesh_graded(f, l, DiagonalRule::maxmin, 0);
    BOOST_TEST(check_mesh(g.mesh).ok());
    BOOST_TEST_MESSAGE("disc 1024^2: uniform " << u.mesh.triangles.size() << " triangles, graded "
                                               << g.mesh.triangles.size());
    BOOST_TEST(g.mesh.triangles.size() * 3 <= u.mesh.triangles.size());
    BOOST_TEST((boundary_coords(g.mesh) == boundary_coords(u.mesh)));
    BOOST_TEST(std::abs(area(g.mesh) - area(u.mesh)) < 1e-6);
}

#ifdef _OPENMP
BOOST_AUTO_TEST_CASE(output_is_independent_of_the_thread_count) {
    Lambda f(subtract(circle(300, 260, 230), circle(280, 300, 70.2)), {0, 0, 600, 520});
    const Lattice l = integer_lattice(600, 520);
    const int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    const auto a = mesh_graded(f, l, DiagonalRule::separating, 0);
    omp_set_num_threads(std::max(2, saved));
    const auto b = mesh_graded(f, l, DiagonalRule::separating, 0);
    omp_set_num_threads(saved);
    BOOST_REQUIRE(a.mesh.vertices.size() == b.mesh.vertices.size());
    for (std::size_t v = 0; v < a.mesh.vertices.size(); ++v) {
        BOOST_TEST(a.mesh.vertices[v].x == b.mesh.vertices[v].x);
        BOOST_TEST(a.mesh.vertices[v].y == b.mesh.vertices[v].y);
    }
    BOOST_TEST((a.mesh.triangles == b.mesh.triangles));
    BOOST_TEST((a.mesh.boundary == b.mesh.boundary));
    BOOST_TEST((a.mesh.boundary_tag == b.mesh.boundary_tag));
    BOOST_TEST((a.leaves_per_level == b.leaves_per_level));
}
#endif

BOOST_AUTO_TEST_CASE(real_images) {
    auto path = [](const char* name) { return (std::filesystem::path(WARPMESH_TEST_DATA) / name).string(); };
    ImageLevelSetOptions thr;
    thr.mode = ImageMode::threshold;
    for (const char* name : {"horse_binary.pgm", "K1_small.pgm", "VentricleModel.pgm"}) {
        const Image img = read_image(path(name));
        const auto f = make_image_levelset(img, thr);
        BOOST_TEST_CONTEXT(name) {
            // Spacing 1 on the pixel-centre box: integer lattice points.
            const Lattice l = lattice_over(f->bounds(), 1.0);
            for (std::int64_t K : {0, 8}) compare_with_uniform(*f, l, DiagonalRule::maxmin, K);
            compare_with_uniform(*f, lattice_over(f->bounds(), 0.37), DiagonalRule::separating, 0, false);
        }
    }
    // Label image, several regions: region tags as in the uniform mesh.
    ImageLevelSetOptions lab;
    lab.mode = ImageMode::label;
    lab.labels = {3, 4, 13};
    const auto f = make_image_levelset(read_image(path("abdomen_axial_z024_labels16.pgm")), lab);
    const Lattice l = lattice_over(f->bounds(), 1.0);
    compare_with_uniform(*f, l, DiagonalRule::separating, 0);
    const auto g = mesh_graded(*f, l, DiagonalRule::separating, 0);
    std::map<std::int32_t, double> by_region_g, by_region_u;
    for (std::size_t t = 0; t < g.mesh.triangles.size(); ++t) by_region_g[g.mesh.region[t]] += cross2(g.mesh, t);
    const auto u = mesh_uniform(*f, l, DiagonalRule::separating);
    for (std::size_t t = 0; t < u.mesh.triangles.size(); ++t) by_region_u[u.mesh.region[t]] += cross2(u.mesh, t);
    BOOST_TEST(by_region_g.size() == by_region_u.size());
    BOOST_TEST(by_region_g.size() >= 2u);
    // Every tag is the level set's region at the triangle's centroid, warped
    // vertices included (spacing 0.37: few lattice points on pixel centres).
    for (const double s : {1.0, 0.37}) {
        const auto m = mesh_graded(*f, lattice_over(f->bounds(), s), DiagonalRule::separating, 0).mesh;
        std::int64_t wrong = 0;
        for (std::size_t t = 0; t < m.triangles.size(); ++t) {
            const auto& tri = m.triangles[t];
            const Vec2 &a = m.vertices[static_cast<std::size_t>(tri[0])], &b = m.vertices[static_cast<std::size_t>(tri[1])],
                       &c = m.vertices[static_cast<std::size_t>(tri[2])];
            wrong += m.region[t] != f->region_at((a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3);
        }
        BOOST_TEST(wrong == 0, "spacing " << s << ": " << wrong << " of " << m.triangles.size() << " tags differ");
    }
}

// The tiled front end finds the uniform front end's cut edges and warped
// points, for tiles of 4 to 128 squares (rows of up to 129 points: several
// 64-point chunks of the cut-edge scan), and its signs are those of every
// lattice point.
BOOST_AUTO_TEST_CASE(tiled_front_end_matches_the_uniform_one_for_any_tile_size) {
    for (const std::string spec : {"flower:0.3,-0.2,60,22,9", "diff(circle:0,0,70;rect:-20,-15,18,21)"}) {
        const auto f = parse_shape(spec);
        const Lattice l = lattice_around(f->bounds(), 0.61);
        const WarpedLattice u = warp_lattice(*f, l);
        for (const int tile_log : {2, 4, 6, 7}) {
            BOOST_TEST_CONTEXT(spec << " tile_log " << tile_log) {
                const TiledFront t = warp_tiles(*f, l, tile_log);
                BOOST_TEST(t.cut_edges == u.cut_edges);
                BOOST_REQUIRE(t.warped.size() == u.warped.size());
                for (std::size_t k = 0; k < u.warped.size(); ++k) {
                    BOOST_REQUIRE(t.warped[k].p == u.warped[k].p);
                    BOOST_REQUIRE(t.warped[k].dir == u.warped[k].dir);
                    BOOST_REQUIRE(t.warped[k].t == u.warped[k].t);
                }
                std::int64_t wrong = 0;
                for (std::int64_t j = 0; j <= l.ny; ++j)
                    for (std::int64_t i = 0; i <= l.nx; ++i) wrong += t.signs(i, j) != u.signs[static_cast<std::size_t>(l.index(i, j))];
                BOOST_TEST(wrong == 0);
            }
        }
    }
}

// The quadtree, its leaf list and the triangulation work per tile below the
// tiles' level (rows of a tile's nodes as words of bits): the graded mesh
// must not depend on the tile size — the same vertices, and the same
// triangles (with their tags) and boundary edges up to order — and the tree
// must pass its checks, for tiles of 4 to 128 squares; larger tiles are refused.
BOOST_AUTO_TEST_CASE(graded_mesh_does_not_depend_on_the_tile_size) {
    struct Canonical {
        std::vector<std::array<std::int32_t, 4>> triangles;  // rotated to the smallest id first, and the tag
        std::vector<std::array<std::int32_t, 3>> boundary;
    };
    auto canonical = [](const Mesh& m) {
        Canonical c;
        for (std::size_t k = 0; k < m.triangles.size(); ++k) {
            auto t = m.triangles[k];
            std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
            c.triangles.push_back({t[0], t[1], t[2], m.region[k]});
        }
        for (std::size_t k = 0; k < m.boundary.size(); ++k) c.boundary.push_back({m.boundary[k][0], m.boundary[k][1], m.boundary_tag[k]});
        std::sort(c.triangles.begin(), c.triangles.end());
        std::sort(c.boundary.begin(), c.boundary.end());
        return c;
    };
    const std::vector<std::uint16_t> px = [] {  // labels 3 and 5 in blobs, with a hole
        std::vector<std::uint16_t> v(61 * 47, 0);
        for (int r = 0; r < 47; ++r)
            for (int c = 0; c < 61; ++c) {
                const double x = c - 30, y = r - 23, d = x * x / 700 + y * y / 380;
                if (d < 1 && (x - 6) * (x - 6) + y * y > 30) v[static_cast<std::size_t>(r * 61 + c)] = x < 0.3 * y ? 3 : 5;
            }
        return v;
    }();
    Image img;
    img.width = 61, img.height = 47, img.maxval = 255, img.pixels = px, img.source = "blobs";
    const auto image = make_image_levelset(img, label_options("nonzero"));
    const auto flower = parse_shape("flower:0.3,-0.2,60,22,9");
    const auto holes = parse_shape("diff(circle:0,0,70;union(rect:-20,-15,18,21;circle:40,10,9))");
    struct Case {
        const LevelSet* f;
        double s;
        std::int64_t K;
        int buffer = 0;  // grading
    };
    for (const Case& c : {Case{flower.get(), 0.61, 0}, Case{holes.get(), 0.37, 0}, Case{holes.get(), 0.37, 8},
                          Case{image.get(), 0.13, 0}, Case{holes.get(), 0.37, 0, 3}, Case{flower.get(), 0.61, 16, 8},
                          Case{image.get(), 0.13, 0, 2}}) {
        const Lattice l = lattice_around(c.f->bounds(), c.s);
        auto mesh = [&](int tile_log) {
            const TiledFront front = warp_tiles(*c.f, l, tile_log);
            const Quadtree tree = build_quadtree(l, front.signs, front.warped, c.K, c.buffer);
            const QuadtreeCheck chk = check_quadtree(tree, front.signs);
            BOOST_TEST(chk.ok());
            for (const auto& msg : chk.messages) BOOST_TEST_MESSAGE(msg);
            return triangulate_graded(*c.f, l, front.signs, tree, quadtree_leaves(tree, nullptr, true), front.warped,
                                      DiagonalRule::separating);
        };
        const Mesh want = mesh(default_tile_log);
        const Canonical cw = canonical(want);
        BOOST_TEST(cw.triangles.size() > 1000u);
        for (const int tile_log : {2, 3, 5, 6, 7}) {
            BOOST_TEST_CONTEXT("lattice " << l.nx << " x " << l.ny << " K " << c.K << " buffer " << c.buffer << " tile_log " << tile_log) {
                const Mesh got = mesh(tile_log);
                BOOST_REQUIRE(got.vertices.size() == want.vertices.size());
                std::int64_t moved = 0;
                for (std::size_t k = 0; k < want.vertices.size(); ++k)
                    moved += got.vertices[k].x != want.vertices[k].x || got.vertices[k].y != want.vertices[k].y;
                BOOST_TEST(moved == 0);
                const Canonical cg = canonical(got);
                BOOST_TEST((cg.triangles == cw.triangles));
                BOOST_TEST((cg.boundary == cw.boundary));
            }
        }
        BOOST_CHECK_THROW(build_quadtree(l, warp_tiles(*c.f, l, 8).signs, {}, c.K), std::invalid_argument);
    }
}

// The tiled front end with range bounds (tiles.hpp) on every kind of level set
// that has them: parsed shapes of each kind and CSG, threshold and label
// images, at spacings and offsets that put tile borders anywhere.  The mesh
// must be the one with every tile sampled, bit for bit, while most tiles of a
// large lattice are skipped.
BOOST_AUTO_TEST_CASE(range_bounds_skip_tiles_and_change_nothing) {
    std::mt19937 rng(77);
    std::uniform_real_distribution<double> U(0, 1);
    const std::vector<std::string> shapes = {
        "circle:0.3,-0.2,40.7", "ellipse:3,1,50,21.5", "annulus:0,0,12.25,45", "flower:1,2,30,12,7",
        "flower:0,0,40,-15,3", "rect:-30.5,-12,41,33.3", "union(circle:-20,0,18;circle:15,4,22)",
        "intersect(circle:0,0,40;rect:-50,-10,50,25)", "diff(ellipse:0,0,48,30;circle:5,3,11;annulus:0,0,20,22)",
        "diff(flower:0,0,36,10,5;circle:0,0,9.5)"};
    for (const auto& spec : shapes)
        for (int trial = 0; trial < 3; ++trial) {
            const auto f = parse_shape(spec);
            const double s = 0.35 + 1.4 * U(rng);
            Box b = f->bounds();
            b.xmin -= 3 * s * U(rng), b.ymin -= 3 * s * U(rng);
            const Lattice l = lattice_around(b, s);
            const auto rule = trial % 2 ? DiagonalRule::separating : DiagonalRule::maxmin;
            const std::int64_t K = std::array<std::int64_t, 3>{0, 4, 16}[static_cast<std::size_t>(trial)];
            const GradedResult g = mesh_graded(*f, l, rule, K), all = mesh_graded(testing::WithoutRange(*f), l, rule, K);
            BOOST_TEST_CONTEXT(spec << " s " << s << " K " << K) {
                BOOST_TEST(testing::same_mesh(g.mesh, all.mesh));
                BOOST_TEST(g.sampled_points <= all.sampled_points);
                BOOST_TEST(check_mesh(g.mesh).ok());
            }
        }
    auto path = [](const char* name) { return (std::filesystem::path(WARPMESH_TEST_DATA) / name).string(); };
    ImageLevelSetOptions thr, lab;
    thr.mode = ImageMode::threshold;
    lab.mode = ImageMode::label;
    lab.labels = {3, 4, 13};
    const auto horse = make_image_levelset(read_image(path("horse_binary.pgm")), thr);
    const auto abdomen = make_image_levelset(read_image(path("abdomen_axial_z024_labels16.pgm")), lab);
    for (const LevelSet* f : {horse.get(), abdomen.get()})
        for (double s : {1.0, 0.37, 2.5}) {
            const Lattice l = lattice_over(f->bounds(), s);
            const GradedResult g = mesh_graded(*f, l, DiagonalRule::separating, 0),
                               all = mesh_graded(testing::WithoutRange(*f), l, DiagonalRule::separating, 0);
            BOOST_TEST_CONTEXT(f->describe() << " s " << s) {
                BOOST_TEST(testing::same_mesh(g.mesh, all.mesh));
                BOOST_TEST(g.sampled_points < all.sampled_points);
            }
        }
    // A large disc: f is evaluated near the circle only.
    const auto disc = parse_shape("circle:0,0,1000");
    const Lattice l = lattice_around(disc->bounds(), 1.0);
    const GradedResult g = mesh_graded(*disc, l, DiagonalRule::maxmin, 0);
    BOOST_TEST_MESSAGE("disc r = 1000: " << g.sampled_points << " evaluations for " << l.point_count() << " points");
    BOOST_TEST(g.sampled_points * 10 < l.point_count());
}

// A range bound that is not conservative is caught, not trusted: where a
// sampled tile shares points with a tile the bound called uniform, the
// sampled signs must agree (fill_rings).  The half-plane f = x - 32.5 (or
// y - 32.5) on a 128 x 128 lattice of 16 x 16 tiles; the lying bound calls
// every box with x >= 30 positive, so tile 2 (x in [32, 48]) is uniform +1
// while tile 1 samples its last column, x = 32 — which tile 2 owns — as -1.
// Across a tile's column and across its row; the honest bound passes.
BOOST_AUTO_TEST_CASE(a_range_bound_that_is_not_conservative_is_caught) {
    class HalfPlane final : public LevelSet {
    public:
        HalfPlane(bool along_y, bool lie) : along_y_(along_y), lie_(lie) {}
        double value(double x, double y) const override { return (along_y_ ? y : x) - 32.5; }
        Box bounds() const override { return {0, 0, 128, 128}; }
        Range range(const Box& b) const override {
            const double lo = along_y_ ? b.ymin : b.xmin, hi = along_y_ ? b.ymax : b.xmax;
            if (lie_ && lo >= 30) return {1, 2};
            return {lo - 32.5, hi - 32.5};
        }
        std::string describe() const override { return "half-plane"; }

    private:
        bool along_y_, lie_;
    };
    const Lattice l = lattice_over({0, 0, 128, 128}, 1.0);
    BOOST_TEST_REQUIRE(l.nx == 128);
    for (const bool along_y : {false, true}) {
        BOOST_CHECK_NO_THROW(warp_tiles(HalfPlane(along_y, false), l));
        BOOST_CHECK_THROW(warp_tiles(HalfPlane(along_y, true), l), std::logic_error);
    }
}

// The blocked point set: ranks in point (row-major) order, across blocks of
// 256 points x 128 rows, against a plain sorted list.
BOOST_AUTO_TEST_CASE(point_set_ranks_follow_point_order_across_blocks) {
    std::mt19937 rng(3);
    for (const auto& size : {std::pair<std::int64_t, std::int64_t>{1, 1}, {64, 3}, {257, 129}, {1000, 700}, {3, 1000}}) {
        const std::int64_t w = size.first, h = size.second;  // not a structured binding: lambdas below capture them
        PointSet set(w, h);
        std::vector<std::int64_t> members;  // i + j w
        for (int k = 0; k < 3000; ++k) {
            const std::int64_t i = static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(w)),
                               j = static_cast<std::int64_t>(rng() % static_cast<std::uint64_t>(h));
            // Some with neighbours in the same call: i + 5 (often the same
            // word) and i + 63 (the next word unless i is a word's first).
            const bool run = k % 3 == 0;
            const std::uint64_t rel = 1 | (run && i + 5 < w ? std::uint64_t{1} << 5 : 0) | (run && i + 63 < w ? std::uint64_t{1} << 63 : 0);
            if (k % 2) set.insert_bits<false>(i, j, rel);
            else set.insert_bits<true>(i, j, rel);
            for (int q = 0; q < 64; ++q)
                if ((rel >> q) & 1) members.push_back(i + q + j * w);
        }
        std::sort(members.begin(), members.end());
        members.erase(std::unique(members.begin(), members.end()), members.end());
        set.finish();
        BOOST_TEST(set.count == static_cast<std::int64_t>(members.size()));
        for (std::size_t r = 0; r < members.size(); ++r) {
            const std::int64_t i = members[r] % w, j = members[r] / w;
            BOOST_TEST_REQUIRE(set.contains(i, j));
            BOOST_TEST_REQUIRE(set.rank(i, j) == static_cast<std::int64_t>(r));
        }
        // Word by word in point order: each member once, with its rank.
        std::vector<std::int64_t> seen;
        for (std::int64_t j = 0; j < h; ++j)
            set.for_each_word_in_row(j, [&](std::size_t wd, std::int64_t i0, std::uint64_t bits, std::int64_t r0) {
                for (std::int64_t r = r0; bits; bits &= bits - 1, ++r) {
                    const int b = std::countr_zero(bits);
                    BOOST_TEST_REQUIRE(r == static_cast<std::int64_t>(seen.size()));
                    BOOST_TEST_REQUIRE(set.rank_in_word(wd, b) == r);
                    seen.push_back(i0 + b + j * w);
                }
            });
        BOOST_TEST((seen == members));
        // Runs (i + q, j), q < n: membership bits, including runs that
        // straddle two words or blocks; and the ranks of runs' members.
        for (std::int64_t j = 0; j < h; ++j)
            for (std::int64_t i = 0; i + 1 < w; ++i) {
                for (const int n : {2, 3, 64}) {
                    if (i + n > w) continue;
                    std::uint64_t want = 0;
                    for (int q = 0; q < n; ++q) want |= static_cast<std::uint64_t>(set.contains(i + q, j)) << q;
                    BOOST_TEST_REQUIRE(set.members(i, j, n) == want);
                }
                for (int n = 1; n <= 3 && i + n <= w; ++n) {  // ranks of runs' members
                    const std::uint64_t bits = set.members(i, j, n);
                    const auto ranks = set.rank_run(i, j, n);
                    for (int q = 0; q < n; ++q)
                        if ((bits >> q) & 1) BOOST_TEST_REQUIRE(ranks[static_cast<std::size_t>(q)] == set.rank(i + q, j));
                }
            }
        std::int64_t absent = 0;
        for (std::int64_t k = 0; k < std::min<std::int64_t>(w * h, 20000); ++k)
            absent += !std::binary_search(members.begin(), members.end(), k) && set.contains(k % w, k / w);
        BOOST_TEST(absent == 0);
    }
}

// ---------------------------------------------------------------------------
// The fan rule (--diagonal fan) in the graded mesher.  A fan square has four
// inside corners and a warped one, so it is a finest leaf and gets the
// uniform mesh's centroid fan.  Random 16-bit discs holding perturbed copies
// of the 15-degree witness (fan squares) and a noisy rim; the disc's inside
// coarsens between them.
namespace {

// A disc (inside: darker than 30000) with a noisy rim, holding copies of the
// separating rule's 15-degree witness (the 16-bit pattern of test_fan_rule.cpp
// and test_certified_mesh.cpp, key -R+U-L-R with t = (1/2, 0.134, 1/2, 1/2)),
// each perturbed by a few percent, flipped and transposed at random: squares
// whose diagonals both fall below atan(1/3), where the fan rule takes the fan.
Image witness_disc(std::mt19937& rng, int W, int H) {
    std::uniform_real_distribution<double> U(0, 1);
    constexpr int iso = 30000;
    const double cx = W * (0.45 + 0.1 * U(rng)), cy = H * (0.45 + 0.1 * U(rng)), R = std::min(W, H) * (0.38 + 0.08 * U(rng));
    std::vector<double> v(static_cast<std::size_t>(W) * static_cast<std::size_t>(H));
    std::vector<bool> pattern(v.size(), false);
    auto at = [&](int c, int r) -> double& { return v[static_cast<std::size_t>(r * W + c)]; };
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c) at(c, r) = iso + std::clamp(2000 * (std::hypot(c - cx, r - cy) - R), -10000.0, 10000.0);
    constexpr int step = 7;
    for (int oy = 0; oy + step <= H; oy += step)
        for (int ox = 0; ox + step <= W; ox += step) {
            if (std::hypot(ox + step / 2.0 - cx, oy + step / 2.0 - cy) > R - 6 || U(rng) < 0.3) continue;
            auto jiggle = [&](int x) { return static_cast<int>(std::lround(x * (0.98 + 0.04 * U(rng)))); };
            const int a = jiggle(2680), d = jiggle(17324), c = jiggle(5000);
            const bool fx = U(rng) < 0.5, fy = U(rng) < 0.5, tr = U(rng) < 0.5;
            auto put = [&](int x, int y, int f) {  // pattern coordinates 1 .. 4
                if (tr) std::swap(x, y);
                if (fx) x = 5 - x;
                if (fy) y = 5 - y;
                at(ox + x, oy + y) = iso + f;
            };
            for (int y = 0; y < 6; ++y)
                for (int x = 0; x < 6; ++x) at(ox + x, oy + y) = iso - 10000, pattern[static_cast<std::size_t>((oy + y) * W + ox + x)] = true;
            put(2, 2, -a), put(3, 2, +a), put(2, 3, -c), put(3, 3, -d);
            put(1, 3, +c), put(4, 3, +d);
            put(1, 2, -a), put(2, 1, -a), put(2, 4, -c), put(3, 4, -d), put(4, 2, +a), put(3, 1, +a);
        }
    Image img;
    img.width = W, img.height = H, img.maxval = 65535, img.source = "witness disc";
    img.pixels.resize(v.size());
    for (std::size_t k = 0; k < v.size(); ++k) {
        const double noise = pattern[k] ? 0 : 3000 * (2 * U(rng) - 1);
        img.pixels[k] = static_cast<std::uint16_t>(std::clamp(v[k] + noise, 0.0, 65535.0));
    }
    return img;
}

// The triangles with a vertex off the integer lattice (warped points, fan
// centres: the boundary band's triangles), by coordinates, each rotated to
// its smallest vertex, sorted.
std::vector<std::array<double, 6>> band_triangles(const Mesh& m) {
    std::vector<std::array<double, 6>> out;
    for (const auto& tri : m.triangles) {
        std::array<std::pair<double, double>, 3> v;
        bool band = false;
        for (int k = 0; k < 3; ++k) {
            const Vec2 p = m.vertices[static_cast<std::size_t>(tri[k])];
            v[static_cast<std::size_t>(k)] = {p.x, p.y};
            band = band || !is_integer(p.x) || !is_integer(p.y);
        }
        if (!band) continue;
        std::rotate(v.begin(), std::min_element(v.begin(), v.end()), v.end());
        out.push_back({v[0].first, v[0].second, v[1].first, v[1].second, v[2].first, v[2].second});
    }
    std::sort(out.begin(), out.end());
    return out;
}

double min_angle(const Mesh& m) {
    double a = 180;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (double x : angles(m, t)) a = std::min(a, x);
    return a;
}

// The level set of witness_disc: f = pixel - 30000, inside below.
std::unique_ptr<LevelSet> witness_levelset(std::mt19937& rng, int W, int H) {
    ImageLevelSetOptions o;
    o.iso = 30000;
    o.inside_above = false;
    return make_image_levelset(witness_disc(rng, W, H), o);
}

}  // namespace

BOOST_AUTO_TEST_CASE(fan_rule_graded_mesh_has_the_uniform_fans) {
    std::mt19937 rng(20261202);
    std::int64_t total_fans = 0;
    for (int seed = 0; seed < 12; ++seed) {
        const int W = 40 + static_cast<int>(rng() % 90), H = 40 + static_cast<int>(rng() % 90);
        const auto f = witness_levelset(rng, W, H);
        const Lattice l = lattice_over(f->bounds(), 1.0);  // pixel centres: integer lattice points
        const std::int64_t K = seed % 3 == 0 ? 4 : 0;
        BOOST_TEST_CONTEXT("seed " << seed << " image " << W << "x" << H << " K " << K) {
            // Conformity, no hanging vertex, the quadtree, the same boundary
            // and area as the uniform fan mesh, angles within the fan theorem.
            compare_with_uniform(*f, l, DiagonalRule::fan, K);
            const UniformResult u = mesh_uniform(*f, l, DiagonalRule::fan);
            const UniformResult usep = mesh_uniform(*f, l, DiagonalRule::separating);
            const auto g = testing::certified(mesh_graded(*f, l, DiagonalRule::fan, K, testing::with_keys), l, DiagonalRule::fan);
            const GradedResult gsep = mesh_graded(*f, l, DiagonalRule::separating, K);
            // The same fans: as many centres, and the same band triangles.
            const std::int64_t fans = static_cast<std::int64_t>(u.mesh.vertices.size() - usep.mesh.vertices.size());
            BOOST_TEST(static_cast<std::int64_t>(g.mesh.vertices.size() - gsep.mesh.vertices.size()) == fans);
            BOOST_TEST(static_cast<std::int64_t>(g.mesh.triangles.size() - gsep.mesh.triangles.size()) == 2 * fans);
            total_fans += fans;
            BOOST_TEST((band_triangles(g.mesh) == band_triangles(u.mesh)));
            // --verify: every keyed square's triangles (4 for a fan) checked
            // against its key of fan.cert, the graded invariant checked.
            BOOST_TEST(g.certified.verified);
            BOOST_TEST(g.invariant_squares > 0);
            BOOST_TEST(g.certified.min_deg >= certified_theorem(DiagonalRule::fan).min_deg_any);
            BOOST_TEST(g.certified.min_deg >= 18.4349);
            BOOST_TEST(min_angle(g.mesh) >= 18.4349);
            BOOST_TEST(min_angle(g.mesh) == min_angle(u.mesh));
            // Without the fans the same images fall below atan(1/3).
            if (fans > 0) BOOST_TEST(min_angle(gsep.mesh) < 18.4349);
        }
    }
    BOOST_TEST_MESSAGE("fan squares over the witness discs: " << total_fans);
    BOOST_TEST(total_fans >= 50);  // the test exercises the fan, many times
}

#ifdef _OPENMP
BOOST_AUTO_TEST_CASE(fan_centres_do_not_depend_on_the_thread_count) {
    // The fan centres are numbered in the leaves' canonical order, after the
    // lattice points' vertices: the same mesh with 1 and 2 threads.
    std::mt19937 rng(7);
    const auto f = witness_levelset(rng, 600, 520);
    const Lattice l = lattice_over(f->bounds(), 1.0);
    const int saved = omp_get_max_threads();
    omp_set_num_threads(1);
    const auto a = mesh_graded(*f, l, DiagonalRule::fan, 0);
    omp_set_num_threads(std::max(2, saved));
    const auto b = mesh_graded(*f, l, DiagonalRule::fan, 0);
    omp_set_num_threads(saved);
    const auto sep = mesh_graded(*f, l, DiagonalRule::separating, 0);
    BOOST_TEST(a.mesh.vertices.size() > sep.mesh.vertices.size() + 100);  // many fans
    BOOST_REQUIRE(a.mesh.vertices.size() == b.mesh.vertices.size());
    std::int64_t moved = 0;
    for (std::size_t v = 0; v < a.mesh.vertices.size(); ++v)
        moved += a.mesh.vertices[v].x != b.mesh.vertices[v].x || a.mesh.vertices[v].y != b.mesh.vertices[v].y;
    BOOST_TEST(moved == 0);
    BOOST_TEST((a.mesh.triangles == b.mesh.triangles));
    BOOST_TEST((a.mesh.boundary == b.mesh.boundary));
}
#endif

BOOST_AUTO_TEST_CASE(fan_centres_do_not_depend_on_the_tile_size) {
    // Nor on the tiles of the front end and the quadtree: the same vertices
    // (fan centres included) and triangles for tiles of 4 to 128 squares.
    std::mt19937 rng(11);
    const auto f = witness_levelset(rng, 300, 260);
    const Lattice l = lattice_over(f->bounds(), 1.0);
    auto mesh = [&](int tile_log) {
        const TiledFront front = warp_tiles(*f, l, tile_log);
        const Quadtree tree = build_quadtree(l, front.signs, front.warped, 0);
        return triangulate_graded(*f, l, front.signs, tree, quadtree_leaves(tree, nullptr, true), front.warped,
                                  DiagonalRule::fan);
    };
    const Mesh want = mesh(default_tile_log);
    BOOST_TEST(want.vertices.size() > mesh_graded(*f, l, DiagonalRule::separating, 0).mesh.vertices.size() + 50);  // fans
    for (const int tile_log : {2, 3, 5, 7}) {
        const Mesh got = mesh(tile_log);
        BOOST_REQUIRE(got.vertices.size() == want.vertices.size());
        std::int64_t moved = 0;
        for (std::size_t k = 0; k < want.vertices.size(); ++k)
            moved += got.vertices[k].x != want.vertices[k].x || got.vertices[k].y != want.vertices[k].y;
        BOOST_TEST(moved == 0, "tile_log " << tile_log);
        BOOST_TEST((band_triangles(got) == band_triangles(want)), "tile_log " << tile_log);
    }
}
