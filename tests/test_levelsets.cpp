#define BOOST_TEST_MODULE levelsets
#include <boost/test/unit_test.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/mesh2d/lattice.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "support.hpp"
#include "without_range.hpp"

using namespace warpmesh;
namespace tt = boost::test_tools;

namespace {

using warpmesh::testing::input_error_containing;

const std::string data_dir = WARPMESH_TEST_DATA;
constexpr double pi = std::numbers::pi;

Image make_image(int w, int h, std::vector<std::uint16_t> px, int maxval = 255) {
    Image img;
    img.width = w, img.height = h, img.maxval = maxval, img.pixels = std::move(px), img.source = "test";
    return img;
}

// Root of f on a -> b by plain bisection (reference; assumes one sign change
// in the bracket it is given).
double bisect(const LevelSet& f, Vec2 a, Vec2 b, double fa) {
    double lo = 0, hi = 1;
    for (int i = 0; i < 200; ++i) {
        const double m = 0.5 * (lo + hi);
        const double g = f.value(a.x + m * (b.x - a.x), a.y + m * (b.y - a.y));
        if ((g < 0) == (fa < 0))
            lo = m;
        else
            hi = m;
    }
    return 0.5 * (lo + hi);
}

double value_at(const LevelSet& f, Vec2 a, Vec2 b, double u) {
    return f.value(a.x + u * (b.x - a.x), a.y + u * (b.y - a.y));
}

Lattice make_lattice(double x0, double y0, double s, std::int64_t nx, std::int64_t ny) {
    Lattice l;
    l.x0 = x0, l.y0 = y0, l.s = s, l.nx = nx, l.ny = ny;
    return l;
}

// Every cut edge of `lattice`: checks that cut_parameter returns u in (0, 1)
// with f(cut point) = 0 up to round-off, and that the edge's f restricted to
// [0, u) keeps the sign of fa (the first sign change is returned; for the
// bracketed root finder, used where no closed form exists, that holds on
// lattices fine enough to cross the level set at most once per edge).  Returns
// the number of cut edges.
int check_all_cuts(const LevelSet& f, const Lattice& lat, double tol) {
    std::vector<double> v(static_cast<std::size_t>(lat.point_count()));
    f.sample(lat, v);
    int cuts = 0;
    for (std::int64_t j = 0; j <= lat.ny; ++j)
        for (std::int64_t i = 0; i <= lat.nx; ++i)
            for (int axis = 0; axis < 2; ++axis) {
                if (axis == 0 ? i == lat.nx : j == lat.ny) continue;
                const std::int64_t p = lat.index(i, j), q = axis == 0 ? p + 1 : p + lat.points_x();
                const double fa = v[p], fb = v[q];
                if (!((fa < 0 && fb > 0) || (fa > 0 && fb < 0))) continue;
                ++cuts;
                const Vec2 a = lat.position(i, j), b = lat.position(i + (axis == 0), j + (axis == 1));
                const double u = f.cut_parameter(a, b, fa, fb);
                BOOST_REQUIRE(u > 0);
                BOOST_REQUIRE(u < 1);
                BOOST_TEST(std::abs(value_at(f, a, b, u)) <= tol);
                // (|f| <= tol is round-off noise: an endpoint can sit on the
                // level set to within an ulp.)
                for (double t : {0.25, 0.5, 0.75, 0.99}) {
                    const double g = value_at(f, a, b, u * t);
                    BOOST_TEST(!(((g < 0 && fa > 0) || (g > 0 && fa < 0)) && std::abs(g) > tol));
                }
            }
    return cuts;
}

}  // namespace

// ===========================================================================
// Threshold mode

BOOST_AUTO_TEST_SUITE(threshold)

// 3 x 2 image; rows top to bottom.  Pixel (c, r) sits at (c, 1 - r).
const std::vector<std::uint16_t> px{10, 20, 30,  //
                                    40, 50, 60};

BOOST_AUTO_TEST_CASE(values_and_orientation) {
    ImageLevelSetOptions o;
    o.iso = 35;
    const auto f = make_image_levelset(make_image(3, 2, px), o);
    const Box b = f->bounds();
    BOOST_TEST(b.xmin == 0.0);
    BOOST_TEST(b.ymin == 0.0);
    BOOST_TEST(b.xmax == 2.0);
    BOOST_TEST(b.ymax == 1.0);
    // Pixel centres: f = V - I exactly; the top row (r = 0) is at y = 1.
    BOOST_TEST(f->value(0, 1) == 35.0 - 10);
    BOOST_TEST(f->value(2, 1) == 35.0 - 30);
    BOOST_TEST(f->value(0, 0) == 35.0 - 40);
    BOOST_TEST(f->value(2, 0) == 35.0 - 60);
    // Bilinear in between.
    BOOST_TEST(f->value(0.5, 0.5) == 35 - (10 + 20 + 40 + 50) / 4.0, tt::tolerance(1e-14));
    BOOST_TEST(f->value(1.25, 0) == 35 - (0.75 * 50 + 0.25 * 60), tt::tolerance(1e-14));
    BOOST_TEST(f->value(1.5, 0.25) == 35 - (0.75 * 55 + 0.25 * 25), tt::tolerance(1e-14));  // rows y = 0, 1 at x = 1.5
    // Constant extension outside the pixel-centre box.
    BOOST_TEST(f->value(-3, 7) == f->value(0, 1));
    BOOST_TEST(f->value(9, -1) == f->value(2, 0));
    BOOST_TEST(std::isnan(f->value(std::nan(""), 0)));
    BOOST_TEST(!f->tags_regions());

    // inside = below flips the sign.
    o.inside_above = false;
    const auto g = make_image_levelset(make_image(3, 2, px), o);
    BOOST_TEST(g->value(0.5, 0.5) == -f->value(0.5, 0.5), tt::tolerance(1e-14));
    BOOST_TEST(g->value(1, 1) == 20.0 - 35);
}

BOOST_AUTO_TEST_CASE(default_iso_and_validation) {
    const auto f = make_image_levelset(make_image(3, 2, px, 100), ImageLevelSetOptions{});
    BOOST_TEST(f->value(0, 1) == 50.0 - 10);  // iso = maxval / 2
    ImageLevelSetOptions o;
    o.iso = std::numeric_limits<double>::infinity();
    BOOST_TEST(input_error_containing([&] { make_image_levelset(make_image(3, 2, px), o); }, "finite"));
    o.iso = std::nan("");
    BOOST_TEST(input_error_containing([&] { make_image_levelset(make_image(3, 2, px), o); }, "finite"));
    BOOST_TEST(input_error_containing([&] { make_image_levelset(make_image(3, 3, px), ImageLevelSetOptions{}); },
                                      "inconsistent"));
}

namespace {
// n uniform random samples in 0..maxval, seeded: the same image every run.
std::vector<std::uint16_t> random_pixels(std::size_t n, unsigned maxval, unsigned seed) {
    std::mt19937 rng(seed);
    std::vector<std::uint16_t> px(n);
    for (auto& v : px) v = static_cast<std::uint16_t>(rng() % (maxval + 1));
    return px;
}
}  // namespace

BOOST_AUTO_TEST_CASE(sample_matches_value_bitwise) {
    const std::vector<std::uint16_t> big = random_pixels(17 * 13, 999, 3);
    ImageLevelSetOptions o;
    o.iso = 437.25;
    const auto f = make_image_levelset(make_image(17, 13, big, 999), o);
    for (const Lattice& lat : {make_lattice(0, 0, 1, 16, 12), make_lattice(0, 0, 0.37, 43, 32),
                               make_lattice(-1.3, -0.7, 1.9, 11, 9), make_lattice(0, 0, 3, 5, 4)}) {
        std::vector<double> v(static_cast<std::size_t>(lat.point_count()));
        f->sample(lat, v);
        for (std::int64_t j = 0; j <= lat.ny; ++j)
            for (std::int64_t i = 0; i <= lat.nx; ++i) {
                const Vec2 p = lat.position(i, j);
                BOOST_REQUIRE(v[lat.index(i, j)] == f->value(p.x, p.y));
            }
    }
    // On the pixel-centre lattice the samples are the pixels themselves.
    const Lattice lat = make_lattice(0, 0, 1, 16, 12);
    std::vector<double> v(static_cast<std::size_t>(lat.point_count()));
    f->sample(lat, v);
    for (int r = 0; r < 13; ++r)
        for (int c = 0; c < 17; ++c) BOOST_REQUIRE(v[lat.index(c, 12 - r)] == 437.25 - big[r * 17 + c]);
}

BOOST_AUTO_TEST_CASE(cut_on_pixel_centre_lattice_is_linear_interpolation) {
    ImageLevelSetOptions o;
    o.iso = 23;
    const auto f = make_image_levelset(make_image(3, 2, px), o);
    // (0,1) → (1,1): values 13, 3 — same sign, no cut; (1,1) → (2,1): 3, -7.
    const double fa = f->value(1, 1), fb = f->value(2, 1);
    BOOST_TEST(fa == 3.0);
    BOOST_TEST(fb == -7.0);
    BOOST_TEST(f->cut_parameter({1, 1}, {2, 1}, fa, fb) == 0.3);  // 3 / (3 + 7), exactly as computed
    BOOST_TEST(f->cut_parameter({2, 1}, {1, 1}, fb, fa) == 0.7);
    // vertical: (0,1) → (0,0): 13 → -17
    BOOST_TEST(f->cut_parameter({0, 1}, {0, 0}, 13, -17) == 13.0 / 30.0);
    BOOST_TEST(f->cut_parameter({0, 0}, {0, 1}, -17, 13) == 17.0 / 30.0);
}

BOOST_AUTO_TEST_CASE(cut_on_non_integer_spacing_is_exact) {
    // Top row (y = 1): 0, 10, 0, 100; bottom row (y = 0): zeros.  Along y = 1,
    // I is piecewise linear with knots at x = 1, 2; f = 4 - I.
    ImageLevelSetOptions o;
    o.iso = 4;
    const auto f = make_image_levelset(make_image(4, 2, {0, 10, 0, 100, 0, 0, 0, 0}), o);
    BOOST_TEST(f->value(0.5, 1) == -1.0);  // I = 5
    // x = 1.5 (I = 5) → 2.0 (I = 0): zero where I = 4 on [1, 2], x = 1.6.
    BOOST_TEST(f->cut_parameter({1.5, 1}, {2.0, 1}, -1, 4) == 0.2, tt::tolerance(1e-15));
    // x = 0.2 (f = 2) → 2.6 (I = 60, f = -56) spans both knots; f = 2, -6, 4, -56
    // at 0.2, 1, 2, 2.6: three zeros.  The first from a is on [0.2, 1] where
    // I = 10 x = 4: x = 0.4.
    BOOST_TEST(f->value(2.6, 1) == -56.0, tt::tolerance(1e-14));
    const double u = f->cut_parameter({0.2, 1}, {2.6, 1}, 2, -56);
    BOOST_TEST(0.2 + u * 2.4 == 0.4, tt::tolerance(1e-14));
    // Reversed, the first zero from x = 2.6 is on [2, 2.6] where I = 100 (x - 2) = 4.
    const double r = f->cut_parameter({2.6, 1}, {0.2, 1}, -56, 2);
    BOOST_TEST(2.6 - r * 2.4 == 2.04, tt::tolerance(1e-14));
    // Inside a bilinear cell (y = 0.5), the pieces are still linear in x:
    // I(x, 0.5) = 5, 2.5 at x = 1, 1.5 → f = -1 at x = 1; f = 4 - 0.5 * 100 (x - 2) ...
    // Edge x = 1.5 (I = 2.5, f = 1.5) → 2.5 (I = 25, f = -21): knot 2 (I = 0, f = 4),
    // zero on [2, 2.5] where 50 (x - 2) = 4: x = 2.08.
    const double w = f->cut_parameter({1.5, 0.5}, {2.5, 0.5}, 1.5, -21);
    BOOST_TEST(1.5 + w == 2.08, tt::tolerance(1e-14));

    // Vertical edges: a 1-column image, rows (top to bottom) 90, 10, 30, i.e.
    // I = 30, 10, 90 at y = 0, 1, 2; f = 20 - I.
    ImageLevelSetOptions p;
    p.iso = 20;
    const auto g = make_image_levelset(make_image(1, 3, {90, 10, 30}), p);
    // y 0.25 → 0.9: f = -5 → 8, zero where I = 20: y = 0.5.
    const double uy = g->cut_parameter({0, 0.25}, {0, 0.9}, -5, 8);
    BOOST_TEST(0.25 + uy * 0.65 == 0.5, tt::tolerance(1e-14));
    // y 0.75 → 1.75 spans the knot y = 1 (f = 10): f = 5, 10, -50; zero on
    // [1, 1.75] where 10 + 80 (y - 1) = 20: y = 1.125.
    BOOST_TEST(g->cut_parameter({0, 0.75}, {0, 1.75}, 5, -50) == 0.375, tt::tolerance(1e-14));
}

BOOST_AUTO_TEST_CASE(cut_exact_on_random_images_and_lattices) {
    const std::vector<std::uint16_t> img = random_pixels(23 * 19, 255, 11);
    ImageLevelSetOptions o;
    o.iso = 127.5;
    const auto f = make_image_levelset(make_image(23, 19, img), o);
    int cuts = 0;
    for (const Lattice& lat : {make_lattice(0, 0, 1, 22, 18), make_lattice(0, 0, 0.43, 51, 41),
                               make_lattice(0.11, 0.27, 2.35, 9, 7), make_lattice(0, 0, 4, 5, 4)})
        cuts += check_all_cuts(*f, lat, 1e-11);
    BOOST_TEST(cuts > 500);
    // Where the edge spans a single linear piece, it agrees with the bracketed
    // root finder and with bisection.
    const Lattice lat = make_lattice(0, 0, 1, 22, 18);
    std::vector<double> v(static_cast<std::size_t>(lat.point_count()));
    f->sample(lat, v);
    int compared = 0;
    for (std::int64_t j = 0; j <= lat.ny; ++j)
        for (std::int64_t i = 0; i < lat.nx; ++i) {
            const double fa = v[lat.index(i, j)], fb = v[lat.index(i + 1, j)];
            if (!(fa * fb < 0)) continue;
            const Vec2 a = lat.position(i, j), b = lat.position(i + 1, j);
            const double u = f->cut_parameter(a, b, fa, fb);
            BOOST_TEST(u == fa / (fa - fb));
            BOOST_TEST(u == bracketed_root(*f, a, b, fa, fb), tt::tolerance(1e-9));
            BOOST_TEST(u == bisect(*f, a, b, fa), tt::tolerance(1e-12));
            ++compared;
        }
    BOOST_TEST(compared > 50);
}

BOOST_AUTO_TEST_CASE(real_16_bit_image) {
    const Image cc = read_image(data_dir + "/CorpusCallosumMeanShape_phi16.pgm");
    ImageLevelSetOptions o;
    o.iso = 10000;  // phi = 0
    o.inside_above = false;
    const auto f = make_image_levelset(cc, o);
    int inside = 0;
    for (int r = 0; r < cc.height; ++r)
        for (int c = 0; c < cc.width; ++c) {
            const double v = f->value(c, cc.height - 1 - r);
            BOOST_REQUIRE(v == static_cast<double>(cc.at(c, r)) - 10000);
            inside += v < 0;
        }
    BOOST_TEST(inside > 20);
    BOOST_TEST(check_all_cuts(*f, make_lattice(0, 0, 0.7, 81, 42), 1e-9) > 50);
}

BOOST_AUTO_TEST_SUITE_END()

// ===========================================================================
// Label mode

BOOST_AUTO_TEST_SUITE(label)

ImageLevelSetOptions labels(std::vector<int> l) {
    ImageLevelSetOptions o;
    o.mode = ImageMode::label;
    o.labels = std::move(l);
    return o;
}

BOOST_AUTO_TEST_CASE(edt_values_single_pixel) {
    std::vector<std::uint16_t> px(7 * 7, 0);
    px[3 * 7 + 3] = 5;  // centre pixel (3, 3) → point (3, 3)
    const auto f = make_image_levelset(make_image(7, 7, px), labels({5}));
    BOOST_TEST(f->value(3, 3) == -0.5);                          // inside, d_out = 1
    BOOST_TEST(f->value(4, 3) == 0.5);                           // 4-neighbour, d_in = 1
    BOOST_TEST(f->value(4, 4) == std::sqrt(2.0) - 0.5);          // diagonal
    BOOST_TEST(f->value(5, 4) == std::sqrt(5.0) - 0.5);
    BOOST_TEST(f->value(0, 0) == std::sqrt(18.0) - 0.5);
    BOOST_TEST(f->value(3.5, 3) == 0.0);                         // the boundary is midway
    BOOST_TEST(f->cut_parameter({3, 3}, {4, 3}, -0.5, 0.5) == 0.5);
    BOOST_TEST(f->cut_parameter({3, 2}, {3, 3}, 0.5, -0.5) == 0.5);
    BOOST_TEST(f->tags_regions());
    BOOST_TEST(f->region_at(3.2, 2.9) == 5);
    BOOST_TEST(f->region_at(0, 0) == 5);  // the nearest region pixel's label
}

BOOST_AUTO_TEST_CASE(edt_values_block_and_all_inside) {
    std::vector<std::uint16_t> px(9 * 8, 1);
    for (int r = 2; r < 7; ++r)
        for (int c = 2; c < 7; ++c) px[r * 9 + c] = 2;  // 5 x 5 block
    const auto f = make_image_levelset(make_image(9, 8, px), labels({2}));
    auto* img = dynamic_cast<const ImageField*>(f.get());
    BOOST_REQUIRE(img);
    BOOST_TEST(img->pixel_value(4, 4) == -2.5);  // centre: 3 pixels from the outside
    BOOST_TEST(img->pixel_value(2, 2) == -0.5);
    BOOST_TEST(img->pixel_value(0, 0) == std::sqrt(8.0) - 0.5);
    BOOST_TEST(img->pixel_value(4, 0) == 1.5);

    const auto all = make_image_levelset(make_image(3, 2, {7, 7, 7, 7, 7, 7}), labels({7}));
    for (double x : {0.0, 1.5, 2.0})
        for (double y : {0.0, 0.5, 1.0}) {
            BOOST_TEST(all->value(x, y) < 0);
            BOOST_TEST(std::isfinite(all->value(x, y)));
        }
}

BOOST_AUTO_TEST_CASE(edt_matches_brute_force) {
    std::mt19937 rng(5);
    const int W = 31, H = 23;
    std::vector<std::uint16_t> px(W * H);
    for (auto& v : px) v = static_cast<std::uint16_t>(rng() % 10 < 7 ? 0 : 1 + rng() % 3);
    const auto f = make_image_levelset(make_image(W, H, px), labels({1, 3}));
    const auto* img = dynamic_cast<const ImageField*>(f.get());
    BOOST_REQUIRE(img);
    auto in = [&](int c, int r) { return px[r * W + c] == 1 || px[r * W + c] == 3; };
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c) {
            long best = 1L << 40;
            for (int r2 = 0; r2 < H; ++r2)
                for (int c2 = 0; c2 < W; ++c2)
                    if (in(c2, r2) != in(c, r))
                        best = std::min(best, long(c - c2) * (c - c2) + long(r - r2) * (r - r2));
            const double want = in(c, r) ? -(std::sqrt(double(best)) - 0.5) : std::sqrt(double(best)) - 0.5;
            BOOST_REQUIRE(img->pixel_value(c, r) == want);
        }
    // region_at at a region pixel's centre gives its own label; at any point
    // it gives a label in the set.
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c) {
            if (in(c, r)) BOOST_REQUIRE(f->region_at(c, H - 1 - r) == px[r * W + c]);
            const int t = f->region_at(c + 0.3, H - 1 - r - 0.6);
            BOOST_REQUIRE((t == 1 || t == 3));
        }
    BOOST_TEST(check_all_cuts(*f, make_lattice(0, 0, 1, W - 1, H - 1), 1e-12) > 100);
    BOOST_TEST(check_all_cuts(*f, make_lattice(0, 0, 1.7, 17, 12), 1e-12) > 20);
}

// region_in's contract (levelset.hpp): where it answers, `within` holds the
// box and region_at gives its tag at every point of `within` — probed at its
// corners, at random points and at centroids of random triangles in the box;
// and it answers for most small boxes inside a labelled area.
BOOST_AUTO_TEST_CASE(region_in_agrees_with_region_at) {
    std::mt19937 rng(11);
    const int W = 23, H = 17;
    std::vector<std::uint16_t> px(static_cast<std::size_t>(W * H));
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)  // blobs of labels 7 and 9, and random pixels of 0, 7, 9, 12
            px[static_cast<std::size_t>(r * W + c)] = static_cast<std::uint16_t>(
                c > 15 ? std::array{0, 7, 9, 12}[rng() % 4] : (c / 4 + r / 5) % 3 == 0 ? 0 : (c < 8 ? 7 : 9));
    const auto f = make_image_levelset(make_image(W, H, px), label_options("nonzero"));
    std::uniform_real_distribution<double> pos(-1.0, W + 1.0), size(0.0, 2.5), unit(0.0, 1.0);  // boxes over up to 3 x 3 cells
    int answered = 0, inside_small = 0;
    for (int n = 0; n < 20000; ++n) {
        const double x0 = pos(rng), y0 = pos(rng) * H / W, w = size(rng), h = size(rng);
        const Box box{x0, y0, x0 + w, y0 + h};
        const std::optional<RegionCell> cell = f->region_in(box);
        if (!cell) continue;
        ++answered;
        BOOST_REQUIRE(cell->holds(box));
        const Box& in = cell->within;
        for (double x : {in.xmin, in.xmax})
            for (double y : {in.ymin, in.ymax}) BOOST_REQUIRE(f->region_at(x, y) == cell->region);
        for (int k = 0; k < 4; ++k) {
            const double x = in.xmin + unit(rng) * (in.xmax - in.xmin), y = in.ymin + unit(rng) * (in.ymax - in.ymin);
            BOOST_REQUIRE(f->region_at(x, y) == cell->region);
            Vec2 v[3];
            for (auto& p : v) p = {box.xmin + unit(rng) * w, box.ymin + unit(rng) * h};
            BOOST_REQUIRE(f->region_at((v[0].x + v[1].x + v[2].x) / 3, (v[0].y + v[1].y + v[2].y) / 3) == cell->region);
        }
    }
    // A box well inside a cell whose four pixels (y up) share a nonzero label
    // is answered, with that label.
    auto label = [&](int c, int y) { return px[static_cast<std::size_t>((H - 1 - y) * W + c)]; };
    int cells = 0;
    for (int y = 0; y + 1 < H; ++y)
        for (int c = 0; c + 1 < W; ++c) {
            const int l = label(c, y);
            if (l == 0 || label(c + 1, y) != l || label(c, y + 1) != l || label(c + 1, y + 1) != l) continue;
            ++cells;
            const double x0 = c + 0.5 * unit(rng), y0 = y + 0.5 * unit(rng);
            const std::optional<RegionCell> cell = f->region_in({x0, y0, x0 + 0.4, y0 + 0.4});
            inside_small += cell && cell->region == l;
        }
    BOOST_TEST(answered > 1000);
    BOOST_TEST(cells > 20);
    BOOST_TEST(inside_small == cells);
    // Level sets without region tags answer nothing.
    BOOST_TEST(!parse_shape("circle:0,0,1")->region_in({0, 0, 0.1, 0.1}).has_value());
}

BOOST_AUTO_TEST_CASE(thin_line_survives) {
    std::vector<std::uint16_t> px(9 * 5, 0);
    for (int c = 1; c < 8; ++c) px[2 * 9 + c] = 1;  // a one-pixel-wide line
    const auto f = make_image_levelset(make_image(9, 5, px), label_options("nonzero"));
    for (int c = 1; c < 8; ++c) BOOST_TEST(f->value(c, 2) == -0.5);
    BOOST_TEST(f->value(4, 1) == 0.5);
    BOOST_TEST(f->value(4, 2.5) == 0.0);
}

BOOST_AUTO_TEST_CASE(missing_labels) {
    const Image img = make_image(3, 1, {0, 4, 9});
    BOOST_TEST(input_error_containing([&] { make_image_levelset(img, labels({5, 6})); }, "{5, 6} is present"));
    BOOST_TEST(input_error_containing([&] { make_image_levelset(img, labels({5})); }, "labels present: 0, 4, 9"));
    BOOST_TEST(input_error_containing([&] { make_image_levelset(make_image(2, 1, {0, 0}), label_options("nonzero")); },
                                      "no nonzero pixels"));
    BOOST_TEST(input_error_containing([&] { make_image_levelset(img, labels({})); }, "at least one label"));
    BOOST_TEST(input_error_containing([&] { make_image_levelset(img, labels({70000})); }, "70000"));
    // Some present is fine.
    BOOST_TEST(make_image_levelset(img, labels({5, 9}))->value(2, 0) == -0.5);
}

BOOST_AUTO_TEST_CASE(label_lists) {
    BOOST_TEST(parse_label_list("3") == std::vector<int>{3});
    BOOST_TEST(parse_label_list("52, 51") == (std::vector<int>{51, 52}));
    BOOST_TEST(parse_label_list("1-3,7,2") == (std::vector<int>{1, 2, 3, 7}));
    BOOST_TEST(parse_label_list("0,65535") == (std::vector<int>{0, 65535}));
    for (const char* bad : {"", " ", "a", "3,", ",3", "-1", "65536", "5-2", "1-", "3 4", "1.5", "nonzero"})
        BOOST_TEST(input_error_containing([&] { parse_label_list(bad); }, "bad label list"), "spec " << bad);
    const auto nz = label_options("nonzero");
    BOOST_TEST((nz.mode == ImageMode::label));
    BOOST_TEST(nz.label_nonzero);
    const auto l = label_options("51,52");
    BOOST_TEST(!l.label_nonzero);
    BOOST_TEST(l.labels == (std::vector<int>{51, 52}));
}

BOOST_AUTO_TEST_CASE(real_label_image) {
    const Image ab = read_image(data_dir + "/abdomen_axial_z024_labels16.pgm");
    const auto f = make_image_levelset(ab, labels({3, 4}));  // liver, spleen
    int liver = 0, spleen = 0;
    for (int r = 0; r < ab.height; ++r)
        for (int c = 0; c < ab.width; ++c) {
            const int v = ab.at(c, r);
            const double x = c, y = ab.height - 1 - r;
            if (v == 3 || v == 4) {
                BOOST_REQUIRE(f->value(x, y) <= -0.5);
                BOOST_REQUIRE(f->region_at(x, y) == v);
                (v == 3 ? liver : spleen)++;
            } else {
                BOOST_REQUIRE(f->value(x, y) >= 0.5);
            }
        }
    BOOST_TEST(liver > 1000);
    BOOST_TEST(spleen > 100);
    BOOST_TEST(f->describe().find("labels {3, 4}") != std::string::npos);
    BOOST_TEST(input_error_containing([&] { make_image_levelset(ab, labels({9999})); }, "labels present: 0, "));
    BOOST_TEST(check_all_cuts(*f, make_lattice(0, 0, 2.5, 102, 102), 1e-11) > 100);
}

BOOST_AUTO_TEST_SUITE_END()

// ===========================================================================
// Analytic shapes

BOOST_AUTO_TEST_SUITE(shapes)

// Area of {f <= 0} by midpoint sampling on a grid of spacing h over bounds().
double sampled_area(const LevelSet& f, double h) {
    const Box b = f.bounds();
    double n = 0;
    for (double y = b.ymin + h / 2; y < b.ymax; y += h)
        for (double x = b.xmin + h / 2; x < b.xmax; x += h) n += f.value(x, y) <= 0;
    return n * h * h;
}

// Every point with f <= 0 on a grid over a box 1.5 times larger lies in bounds().
bool bounds_contain_region(const LevelSet& f) {
    const Box b = f.bounds();
    const double w = b.xmax - b.xmin, h = b.ymax - b.ymin;
    for (int j = 0; j <= 200; ++j)
        for (int i = 0; i <= 200; ++i) {
            const double x = b.xmin - w / 4 + 1.5 * w * i / 200, y = b.ymin - h / 4 + 1.5 * h * j / 200;
            if (f.value(x, y) <= 0 && (x < b.xmin || x > b.xmax || y < b.ymin || y > b.ymax)) return false;
        }
    return true;
}

BOOST_AUTO_TEST_CASE(signs_and_values) {
    const Circle c(1, 2, 3);
    BOOST_TEST(c.value(1, 2) == -3.0);
    BOOST_TEST(c.value(4, 2) == 0.0);
    BOOST_TEST(c.value(1, 7) == 2.0);
    const Ellipse e(0, 0, 4, 1);
    BOOST_TEST(e.value(0, 0) < 0);
    BOOST_TEST(e.value(4, 0) == 0.0);
    BOOST_TEST(e.value(3.9, 0) < 0);
    BOOST_TEST(e.value(0, 1.01) > 0);
    BOOST_TEST(e.value(0, 2) == 1.0);  // |grad f| = 1 along the minor axis
    const Annulus a(0, 0, 1, 2);
    BOOST_TEST(a.value(0, 0) == 1.0);
    BOOST_TEST(a.value(1.5, 0) == -0.5);
    BOOST_TEST(a.value(0, -3) == 1.0);
    const Flower fl(0, 0, 2, 0.5, 5);
    BOOST_TEST(fl.value(2.49, 0) < 0);   // r(0) = 2.5
    BOOST_TEST(fl.value(2.51, 0) > 0);
    BOOST_TEST(fl.value(-1.6, 0) > 0);   // r(pi) = 2 - 0.5 = 1.5 for odd k
    const Rectangle r(0, 0, 2, 1);
    BOOST_TEST(r.value(1, 0.5) == -0.5);
    BOOST_TEST(r.value(3, 0.5) == 1.0);
    const auto u = parse_shape("union(circle:0,0,1;circle:3,0,1)");
    BOOST_TEST(u->value(3, 0) == -1.0);
    BOOST_TEST(u->value(1.5, 0) == 0.5);
    const auto d = parse_shape("diff(circle:0,0,2;circle:0,0,1)");
    BOOST_TEST(d->value(0, 0) == 1.0);
    BOOST_TEST(d->value(1.5, 0) == -0.5);
    const auto i = parse_shape("intersect(rect:0,0,2,2;circle:0,0,1)");
    BOOST_TEST(i->value(0.5, 0.5) < 0);
    BOOST_TEST(i->value(-0.5, 0.5) > 0);
    BOOST_TEST(i->bounds().xmin == 0.0);
    BOOST_TEST(i->bounds().xmax == 1.0);
}

BOOST_AUTO_TEST_CASE(exact_cut_points) {
    const Circle c(0, 0, 1.5);
    BOOST_TEST(c.cut_parameter({0, 0}, {2, 0}, -1.5, 0.5) == 0.75);
    BOOST_TEST(c.cut_parameter({2, 0}, {0, 0}, 0.5, -1.5) == 0.25);
    BOOST_TEST(c.cut_parameter({0, -1}, {0, 2}, c.value(0, -1), 0.5) == 2.5 / 3, tt::tolerance(1e-15));
    const Ellipse e(1, 1, 2, 0.5);
    BOOST_TEST(e.cut_parameter({1, 1}, {1, 2}, e.value(1, 1), e.value(1, 2)) == 0.5, tt::tolerance(1e-15));
    // Annulus: from inside the ring across the hole and out: the first sign
    // change (entering the hole at x = -1) is returned, not a later one.
    const Annulus a(0, 0, 1, 2);
    BOOST_TEST(a.cut_parameter({-1.5, 0}, {2.5, 0}, -0.5, 0.5) == 0.125);
    // Here regula falsi's first step lands in the ring beyond the hole and a
    // plain root finder converges to x = 2; the first zero is still x = -1.
    BOOST_TEST(a.cut_parameter({-1.5, 0}, {2.1, 0}, -0.5, 0.1) == 0.5 / 3.6, tt::tolerance(1e-15));
    const Rectangle r(0.25, 0, 1, 1);
    BOOST_TEST(r.cut_parameter({0, 0.5}, {0.5, 0.5}, 0.25, -0.25) == 0.5);
    BOOST_TEST(r.cut_parameter({0.5, -1}, {0.5, 0.5}, 1, -0.5) == 2.0 / 3.0, tt::tolerance(1e-15));
}

BOOST_AUTO_TEST_CASE(cut_points_on_lattices) {
    // Every cut edge of several lattices: the cut point is a zero of f, the
    // first from a; for the closed-form shapes it matches the bracketed root
    // wherever the edge has a single crossing.
    for (const char* spec : {"circle:0.3,-0.2,2.7", "ellipse:0,0,3,1.3", "annulus:0.1,0.2,1.1,2.9",
                             "rect:-1.3,-0.45,2.2,1.7", "flower:0,0,2,0.7,5",
                             "diff(union(circle:0,0,2;ellipse:2,0,1.5,0.8);circle:0.5,0.3,0.6)",
                             "intersect(rect:-2,-2,1,1;annulus:0,0,0.7,2.4)"}) {
        const auto s = parse_shape(spec);
        const Box b = s->bounds();
        int cuts = 0;
        for (double h : {0.37, 0.1, 0.0731}) {
            const Lattice lat = make_lattice(b.xmin - h, b.ymin - h, h, std::int64_t((b.xmax - b.xmin) / h) + 3,
                                             std::int64_t((b.ymax - b.ymin) / h) + 3);
            cuts += check_all_cuts(*s, lat, 1e-12);
            std::vector<double> v(static_cast<std::size_t>(lat.point_count()));
            s->sample(lat, v);
            for (std::int64_t j = 0; j <= lat.ny; ++j)
                for (std::int64_t i = 0; i < lat.nx; ++i) {
                    const double fa = v[lat.index(i, j)], fb = v[lat.index(i + 1, j)];
                    // Skip endpoints on the level set to round-off (there the
                    // zero is ill-conditioned, e.g. an edge tangent to a circle).
                    if (!(fa * fb < 0) || std::min(std::abs(fa), std::abs(fb)) < 1e-9) continue;
                    const Vec2 pa = lat.position(i, j), pb = lat.position(i + 1, j);
                    BOOST_TEST(std::abs(s->cut_parameter(pa, pb, fa, fb) - bracketed_root(*s, pa, pb, fa, fb)) < 1e-9);
                }
        }
        BOOST_TEST(cuts > 50, spec);
    }
}

BOOST_AUTO_TEST_CASE(exact_areas) {
    BOOST_TEST(*Circle(0, 0, 2).exact_area() == 4 * pi);
    BOOST_TEST(*Ellipse(0, 0, 3, 2).exact_area() == 6 * pi);
    BOOST_TEST(*Annulus(0, 0, 1, 2).exact_area() == 3 * pi);
    BOOST_TEST(*Flower(0, 0, 2, 1, 4).exact_area() == 4.5 * pi);
    BOOST_TEST(*Rectangle(0, 0, 2, 3).exact_area() == 6.0);
    BOOST_TEST(*parse_shape("union(circle:0,0,1;circle:3,0,1)")->exact_area() == 2 * pi);
    BOOST_TEST(*parse_shape("diff(circle:0,0,1;rect:5,5,6,6)")->exact_area() == pi);
    BOOST_TEST(!parse_shape("union(circle:0,0,1;circle:1,0,1)")->exact_area());
    BOOST_TEST(!parse_shape("diff(circle:0,0,2;circle:0,0,1)")->exact_area());
    // The formulas against sampling (midpoint rule, h = 0.004: error ~ perimeter * h).
    for (const char* spec : {"circle:0.1,0.2,1.3", "ellipse:0,0,2,0.7", "annulus:0,0,0.5,1.2",
                             "flower:0,0,1,0.6,3", "flower:0,0,1,-0.3,7", "rect:-0.4,0.1,1.3,0.9",
                             "union(circle:0,0,1;union(circle:3,0,1;rect:5,3,6,4))"}) {
        const auto s = parse_shape(spec);
        BOOST_REQUIRE(s->exact_area());
        BOOST_TEST(sampled_area(*s, 0.004) == *s->exact_area(), tt::tolerance(0.01));
        BOOST_TEST(bounds_contain_region(*s), spec);
    }
}

BOOST_AUTO_TEST_CASE(bounds_are_tight_enough_and_contain) {
    const Box c = Circle(1, 2, 3).bounds();
    BOOST_TEST(c.xmin == -2.0);
    BOOST_TEST(c.xmax == 4.0);
    BOOST_TEST(c.ymin == -1.0);
    BOOST_TEST(c.ymax == 5.0);
    const Box u = parse_shape("union(circle:0,0,1;rect:2,2,3,4)")->bounds();
    BOOST_TEST(u.xmin == -1.0);
    BOOST_TEST(u.ymax == 4.0);
    for (const char* spec : {"diff(circle:0,0,2;circle:1,0,1)", "intersect(circle:0,0,2;circle:1,0,1.5)",
                             "flower:1,1,3,2.5,2"})
        BOOST_TEST(bounds_contain_region(*parse_shape(spec)), spec);
}

BOOST_AUTO_TEST_CASE(parse_and_describe) {
    BOOST_TEST(parse_shape("circle:0,0,1")->describe() == "circle:0,0,1");
    BOOST_TEST(parse_shape("  ellipse: 1.5 , -2, 3e0,+4 ")->describe() == "ellipse:1.5,-2,3,4");
    BOOST_TEST(parse_shape("rectangle:0,0,1,2")->describe() == "rect:0,0,1,2");
    BOOST_TEST(parse_shape("union(circle:0,0,1;circle:3,0,1;circle:6,0,1)")->describe() ==
               "union(union(circle:0,0,1;circle:3,0,1);circle:6,0,1)");
    BOOST_TEST(parse_shape("diff( intersect(rect:0,0,4,4 ; circle:2,2,2) ; circle:2,2,1 )")->describe() ==
               "diff(intersect(rect:0,0,4,4;circle:2,2,2);circle:2,2,1)");
    // The description parses back to the same shape.
    const std::string spec = "diff(union(flower:0,0,2,0.5,3;annulus:5,0,1,2);rect:-1,-1,1,1)";
    BOOST_TEST(parse_shape(parse_shape(spec)->describe())->describe() == parse_shape(spec)->describe());
}

BOOST_AUTO_TEST_CASE(parse_errors) {
    const std::vector<std::pair<std::string, std::string>> cases{
        {"", "empty shape"},
        {"circle", "not a shape"},
        {"circle:0,0", "takes 3 numbers"},
        {"circle:0,0,1,2", "takes 3 numbers"},
        {"circle:0,0,-1", "radius must be positive"},
        {"circle:0,0,0", "radius must be positive"},
        {"circle:0,0,nan", "finite"},
        {"circle:0,0,inf", "finite"},
        {"circle:0,0,1e999", "not a number"},
        {"circle:0,0,1x", "'1x' is not a number"},
        {"circle:0,,1", "'' is not a number"},
        {"ellipse:0,0,1,-2", "semi-axes"},
        {"annulus:0,0,2,1", "0 < r1 < r2"},
        {"annulus:0,0,0,1", "0 < r1 < r2"},
        {"flower:0,0,1,0.5,2.5", "integer"},
        {"flower:0,0,1,0.5,0", "integer"},
        {"flower:0,0,1,1.5,3", "|b| < a"},
        {"rect:1,0,0,1", "x0 < x1"},
        {"blob:1,2", "unknown shape 'blob'"},
        {"union(circle:0,0,1)", "at least two shapes"},
        {"union(circle:0,0,1;circle:3,0,1", "unbalanced"},
        {"union(circle:0,0,1;circle:3,0,1))", "unexpected text"},
        {"union(circle:0,0,1;circle:3,0,1)x", "unexpected text"},
        {"merge(circle:0,0,1;circle:3,0,1)", "unknown operation"},
        {"union(circle:0,0,1;circle:3,0)", "takes 3 numbers"},
        {"union(circle:0,0,1;)", "empty shape"},
        {"intersect(circle:0,0,1;circle:5,5,1)", "empty"},
    };
    for (const auto& c : cases) {
        const std::string spec = c.first, needle = c.second;  // captured below: not a structured binding (clang 14)
        BOOST_TEST(input_error_containing([&] { parse_shape(spec); }, needle), "spec '" << spec << "'");
        BOOST_TEST(input_error_containing([&] { parse_shape(spec); }, "shape '" + spec + "'"), "spec '" << spec << "'");
    }
}

// Issue 27 item 4: union(circle:0,0,5;intersect(circle:20,0,1;circle:-20,0,1))
// was refused ("bounding boxes are disjoint") though it is the circle.  An
// empty sub-expression is the empty set: union and diff with it give the
// other operand (the very same mesh as the circle alone); only a shape that
// is empty as a whole is refused, as "the region is empty".
BOOST_AUTO_TEST_CASE(csg_with_an_empty_part_is_not_refused_as_disjoint) {
    const std::string empty = "intersect(circle:20,0,1;circle:-20,0,1)";
    MeshOptions o;
    o.spacing = 0.5;
    const MeshResult circle = mesh(*parse_shape("circle:0,0,5"), o);
    for (const std::string& spec : {"union(circle:0,0,5;" + empty + ")", "union(" + empty + ";circle:0,0,5)",
                                   "diff(circle:0,0,5;" + empty + ")", "union(circle:0,0,5;diff(" + empty + ";circle:0,0,1))",
                                   "union(circle:0,0,5;intersect(" + empty + ";circle:0,0,1))"}) {
        const auto s = parse_shape(spec);
        BOOST_TEST(s->describe() == "circle:0,0,5", spec);
        BOOST_TEST(*s->exact_area() == 25 * pi, spec);
        const MeshResult r = mesh(*s, o);
        BOOST_TEST(warpmesh::testing::same_mesh(r.mesh, circle.mesh), spec);
    }
    // An empty part inside a larger expression is dropped, the rest kept.
    BOOST_TEST(parse_shape("diff(union(rect:0,0,4,4;" + empty + ");circle:2,2,1)")->describe() ==
               "diff(rect:0,0,4,4;circle:2,2,1)");
    // Empty wholes: refused with "the region is empty", naming the empty part.
    for (const std::string& spec : {empty, "intersect(circle:0,0,5;" + empty + ")", "diff(" + empty + ";circle:0,0,5)",
                                   "union(" + empty + ";" + empty + ")"}) {
        BOOST_TEST(input_error_containing([&] { parse_shape(spec); }, "the region is empty"), spec);
        BOOST_TEST(input_error_containing([&] { parse_shape(spec); }, empty + " is empty"), spec);
    }
    // Touching boxes are not disjoint: the (degenerate) intersection stays a
    // shape, as before.
    BOOST_TEST(parse_shape("intersect(rect:0,0,1,1;rect:1,0,2,1)")->describe() == "intersect(rect:0,0,1,1;rect:1,0,2,1)");
}

namespace {

// A random CSG tree over circles and rectangles with integer parameters (so
// that the spec is its own describe()), and an independent membership test:
// set operations on the primitives' exact interiors.
struct CsgTree {
    std::string spec;
    std::function<bool(double, double)> inside;
};

CsgTree random_csg(std::mt19937& rng, int depth) {
    std::uniform_int_distribution<int> centre(-20, 20), size(1, 8), coin(0, 2);
    if (depth == 0 || coin(rng) == 0) {
        const int x = centre(rng), y = centre(rng), r = size(rng);
        if (coin(rng) == 0) {
            const int w = size(rng);
            return {"rect:" + std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(x + w) + "," +
                        std::to_string(y + r),
                    [=](double px, double py) { return px > x && px < x + w && py > y && py < y + r; }};
        }
        return {"circle:" + std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(r),
                [=](double px, double py) { return (px - x) * (px - x) + (py - y) * (py - y) < r * r; }};
    }
    const CsgTree a = random_csg(rng, depth - 1), b = random_csg(rng, depth - 1);
    switch (coin(rng)) {
        case 0: return {"union(" + a.spec + ";" + b.spec + ")", [=](double x, double y) { return a.inside(x, y) || b.inside(x, y); }};
        case 1:
            return {"intersect(" + a.spec + ";" + b.spec + ")",
                    [=](double x, double y) { return a.inside(x, y) && b.inside(x, y); }};
        default: return {"diff(" + a.spec + ";" + b.spec + ")", [=](double x, double y) { return a.inside(x, y) && !b.inside(x, y); }};
    }
}

}  // namespace

// Random CSG trees, many with empty parts: parse_shape refuses exactly the
// shapes whose set is empty (with "the region is empty", never "disjoint"),
// and an accepted shape's f is negative exactly at the points of the set
// (away from the boundary) and its bounds contain them; mesh() meshes it or
// finds it empty at this spacing, and never refuses it as disjoint.
BOOST_AUTO_TEST_CASE(random_csg_with_empty_parts_is_the_set_it_names) {
    std::mt19937 rng(27);
    const int trials = warpmesh::testing::scaled(400);
    int simplified = 0, refused = 0, meshed = 0;
    for (int t = 0; t < trials; ++t) {
        const CsgTree tree = random_csg(rng, 3);
        std::vector<Vec2> in;  // grid points (off the integers) inside the set
        for (double y = -29.93; y < 30; y += 0.61)
            for (double x = -29.97; x < 30; x += 0.59)
                if (tree.inside(x, y)) in.push_back({x, y});
        std::unique_ptr<Shape> s;
        try {
            s = parse_shape(tree.spec);
        } catch (const InputError& e) {
            const std::string m = e.what();
            BOOST_TEST(m.find("the region is empty") != std::string::npos, tree.spec << ": " << m);
            BOOST_TEST(in.empty(), tree.spec << ": refused, but " << in.size() << " grid points are inside");
            ++refused;
            continue;
        }
        simplified += s->describe() != tree.spec;
        const Box b = s->bounds();
        BOOST_TEST_REQUIRE((b.xmin <= b.xmax && b.ymin <= b.ymax), tree.spec);
        int wrong = 0, outside_bounds = 0;
        for (double y = -29.93; y < 30; y += 0.61)
            for (double x = -29.97; x < 30; x += 0.59) {
                const double f = s->value(x, y);
                if (std::abs(f) > 1e-9) wrong += (f < 0) != tree.inside(x, y);
            }
        for (const Vec2 p : in) outside_bounds += p.x < b.xmin || p.x > b.xmax || p.y < b.ymin || p.y > b.ymax;
        BOOST_TEST(wrong == 0, tree.spec);
        BOOST_TEST(outside_bounds == 0, tree.spec);
        if (t % 8 == 0) {
            MeshOptions o;
            o.spacing = 0.5;
            o.verify = false;
            try {
                meshed += !mesh(*s, o).mesh.triangles.empty();
            } catch (const InputError& e) {
                BOOST_TEST(std::string(e.what()).find("region is empty at this spacing") != std::string::npos,
                           tree.spec << ": " << e.what());
            }
        }
    }
    // The trials exercised what they test.
    BOOST_TEST(simplified > trials / 10, simplified << " of " << trials << " trees had an empty part dropped");
    BOOST_TEST(refused > trials / 40, refused << " of " << trials << " trees were empty as a whole");
    BOOST_TEST(meshed > trials / 40, meshed << " meshed");
}

BOOST_AUTO_TEST_SUITE_END()

// range(box) bounds every value value() computes in the box — for every
// shape kind, CSG, and both image modes — and is not vacuous far from the
// boundary.
BOOST_AUTO_TEST_CASE(range_bounds_contain_the_values) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> U(0, 1);
    std::vector<std::unique_ptr<LevelSet>> fs;
    for (const char* spec : {"circle:1,2,30", "ellipse:0,0,40,12", "annulus:0,0,10,35", "flower:0,0,30,10,6",
                             "flower:2,-1,25,-9,11", "rect:-20,-5,30,15", "union(circle:-20,0,18;circle:15,4,22)",
                             "intersect(circle:0,0,40;rect:-50,-10,50,25)", "diff(ellipse:0,0,48,30;circle:5,3,11)"})
        fs.push_back(parse_shape(spec));
    ImageLevelSetOptions thr, lab;
    lab.mode = ImageMode::label;
    lab.label_nonzero = true;
    const Image img = read_image(data_dir + "/abdomen_axial_z024_labels16.pgm");
    fs.push_back(make_image_levelset(img, lab));
    fs.push_back(make_image_levelset(read_image(data_dir + "/K1_small.pgm"), thr));
    for (const auto& f : fs) {
        const Box all = f->bounds();
        const double W = all.xmax - all.xmin, H = all.ymax - all.ymin;
        int decided = 0;
        for (int trial = 0; trial < 400; ++trial) {
            const double w = W * std::pow(U(rng), 3) * 0.5, h = H * std::pow(U(rng), 3) * 0.5;
            const double x0 = all.xmin - 0.2 * W + 1.4 * W * U(rng), y0 = all.ymin - 0.2 * H + 1.4 * H * U(rng);
            const Range r = f->range({x0, y0, x0 + w, y0 + h});
            decided += r.lo > 0 || r.hi < 0;
            bool inside = true;
            for (int a = 0; a <= 12; ++a)
                for (int b = 0; b <= 12; ++b) {
                    const double v = f->value(x0 + w * a / 12, y0 + h * b / 12);
                    inside = inside && v >= r.lo && v <= r.hi;
                }
            BOOST_TEST(inside, f->describe() << " box " << x0 << " " << y0 << " " << w << " " << h);
        }
        BOOST_TEST(decided > 100, f->describe() << ": only " << decided << " of 400 boxes decided");
    }
}
