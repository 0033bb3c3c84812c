// Degenerate geometry, at library level: lattice points exactly on the level
// set, cut points exactly at s/2, shapes thinner than the spacing, components
// touching at a point, one-pixel and whole-image regions, the smallest images,
// constant images, non-finite values.  Each case either gives a valid mesh —
// check_mesh ok, every angle within the certified theorem U,
// for both diagonal rules, uniform and graded — or a clear InputError.
//
// The last cases replay the fuzzers' seed corpus and every crash they found
// (tests/fuzz/regressions/) through the fuzz targets' own checks.
#define BOOST_TEST_MODULE degenerate
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "fuzz/fuzz_checks.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/mesh2d/graded.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/mesh2d/lattice.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/certify/certified.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "warpmesh/mesh2d/uniform.hpp"
#include "support.hpp"

using namespace warpmesh;
namespace fs = std::filesystem;

namespace {

// Every angle of every mesh lies in the certified theorem U (proofs/*.cert,
// compiled in) — the wider of the two rules', as expect_valid does not know the rule.
double min_deg() {
    return std::min(certified_theorem(DiagonalRule::maxmin).min_deg_any, certified_theorem(DiagonalRule::separating).min_deg_any);
}
double max_deg() {
    return std::max(certified_theorem(DiagonalRule::maxmin).max_deg_any, certified_theorem(DiagonalRule::separating).max_deg_any);
}
constexpr double slack = 1e-6;

struct Lambda : LevelSet {
    std::function<double(double, double)> f;
    Box box;
    Lambda(std::function<double(double, double)> g, Box b) : f(std::move(g)), box(b) {}
    double value(double x, double y) const override { return f(x, y); }
    Box bounds() const override { return box; }
    std::string describe() const override { return "lambda"; }
};

double area(const Mesh& m) { return testing::mesh_area(m); }

// check_mesh, array sizes, tags and the angle bounds.
void expect_valid(const Mesh& m, const std::string& what) {
    BOOST_TEST_CONTEXT(what) {
        const MeshCheck c = check_mesh(m);
        BOOST_TEST(c.ok(), (c.messages.empty() ? std::string() : c.messages[0]));
        BOOST_TEST(m.region.size() == m.triangles.size());
        BOOST_TEST(m.boundary_tag.size() == m.boundary.size());
        for (std::int32_t t : m.boundary_tag) BOOST_TEST((t == boundary_level_set || t == boundary_domain));
        const testing::AngleRange r = testing::angle_range_deg(m);
        const double lo = r.min, hi = r.max;
        if (!m.triangles.empty()) {
            BOOST_TEST(lo >= min_deg() - slack);
            BOOST_TEST(hi <= max_deg() + slack);
        }
    }
}

// Meshes f on the lattice with both rules, uniform and graded (K = 0 and 2);
// every mesh must be valid and the graded ones must cover the uniform area.
// Returns the separating-rule uniform mesh.
Mesh mesh_all_ways(const LevelSet& f, const Lattice& l, const std::string& what) {
    Mesh result;
    for (DiagonalRule rule : {DiagonalRule::separating, DiagonalRule::maxmin}) {
        const std::string r = what + (rule == DiagonalRule::separating ? " [separating" : " [maxmin");
        Mesh u = mesh_uniform(f, l, rule).mesh;
        expect_valid(u, r + ", uniform]");
        for (std::int64_t K : {0, 2}) {
            const Mesh g = mesh_graded(f, l, rule, K).mesh;
            expect_valid(g, r + ", graded K=" + std::to_string(K) + "]");
            BOOST_TEST(area(g) == area(u), boost::test_tools::tolerance(1e-9));
            BOOST_TEST(g.boundary.size() == u.boundary.size());
        }
        if (rule == DiagonalRule::separating) result = std::move(u);
    }
    return result;
}

Mesh mesh_shape(const std::string& spec, double s) {
    const auto f = parse_shape(spec);
    return mesh_all_ways(*f, lattice_around(f->bounds(), s), spec + " s=" + std::to_string(s));
}

Lattice integer_lattice(double x0, double y0, std::int64_t nx, std::int64_t ny, double s = 1) {
    Lattice l;
    l.x0 = x0, l.y0 = y0, l.s = s, l.nx = nx, l.ny = ny;
    return l;
}

Image image(int w, int h, std::vector<std::uint16_t> px, int maxval = 255) {
    Image img;
    img.width = w, img.height = h, img.maxval = maxval, img.pixels = std::move(px), img.source = "test";
    BOOST_REQUIRE(img.pixels.size() == static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    return img;
}

ImageLevelSetOptions threshold(double iso, bool above = true) {
    ImageLevelSetOptions o;
    o.mode = ImageMode::threshold, o.iso = iso, o.inside_above = above;
    return o;
}

ImageLevelSetOptions labels(std::vector<int> l) {
    ImageLevelSetOptions o;
    o.mode = ImageMode::label, o.labels = std::move(l);
    return o;
}

// The CLI's way: the lattice over the image, spacing s.
Mesh mesh_image(const Image& img, const ImageLevelSetOptions& o, double s, const std::string& what) {
    const auto f = make_image_levelset(img, o);
    return mesh_all_ways(*f, lattice_over(f->bounds(), s), what + " s=" + std::to_string(s));
}

std::int64_t count_tag(const Mesh& m, std::int32_t tag) {
    return std::count(m.boundary_tag.begin(), m.boundary_tag.end(), tag);
}

std::vector<std::uint8_t> read_bytes(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Regular files in dir (none if it does not exist), sorted, dotfiles skipped.
std::vector<fs::path> files_in(const fs::path& dir) {
    std::vector<fs::path> out;
    if (!fs::is_directory(dir)) return out;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.is_regular_file() && e.path().filename().string()[0] != '.') out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
}

}  // namespace

// --- lattice points exactly on the level set -------------------------------------

BOOST_AUTO_TEST_CASE(rectangle_aligned_with_the_lattice) {
    // Every rectangle side runs through lattice points: f = 0 there, no cut
    // edge touches them, nothing warps; the mesh is the rectangle exactly.
    for (double s : {1.0, 0.5, 0.25}) {
        const Mesh m = mesh_shape("rect:0,0,4,3", s);
        BOOST_TEST(area(m) == 12.0, boost::test_tools::tolerance(1e-12));
        const auto f = parse_shape("rect:0,0,4,3");
        for (const auto& e : m.boundary)
            for (std::int32_t v : e) {
                const Vec2 p = m.vertices[static_cast<std::size_t>(v)];
                BOOST_TEST(f->value(p.x, p.y) == 0.0);
            }
    }
    // A unit lattice square exactly.
    const Mesh one = mesh_shape("rect:0,0,1,1", 1);
    BOOST_TEST(one.triangles.size() == 2u);
}

BOOST_AUTO_TEST_CASE(circle_through_lattice_points) {
    // x^2 + y^2 = 25 passes through (±5, 0), (±3, ±4), (±4, ±3), (0, ±5).
    const Mesh m = mesh_shape("circle:0,0,5", 1);
    BOOST_TEST(!m.triangles.empty());
    for (double s : {0.5, 0.25}) mesh_shape("circle:0,0,5", s);
    // Centre on a lattice point, radius a whole number of spacings.
    mesh_shape("circle:0,0,2", 1);
    mesh_shape("annulus:0,0,2,5", 1);
    mesh_shape("ellipse:0,0,4,2", 1);
}

BOOST_AUTO_TEST_CASE(every_lattice_point_on_the_level_set) {
    // f = 0 on a whole lattice: everything is "inside" (f <= 0), nothing is cut.
    const Lambda zero([](double, double) { return 0.0; }, {0, 0, 4, 3});
    const Mesh m = mesh_all_ways(zero, integer_lattice(0, 0, 4, 3), "f = 0");
    BOOST_TEST(m.triangles.size() == 24u);
    BOOST_TEST(count_tag(m, boundary_domain) == 14);
    // Lines of zeros: f = y - 2 on the integer lattice, f = sin-like stripes.
    const Lambda line([](double, double y) { return y - 2; }, {0, 0, 5, 5});
    const Mesh half = mesh_all_ways(line, integer_lattice(0, 0, 5, 5), "f = y - 2");
    BOOST_TEST(area(half) == 10.0, boost::test_tools::tolerance(1e-12));
    // Columns of zeros at even x, inside to the left of x = 3, outside beyond.
    const Lambda stripes([](double x, double) { return std::fmod(x, 2.0) == 0 ? 0.0 : (x < 3 ? -1.0 : 1.0); },
                         {0, 0, 6, 3});
    mesh_all_ways(stripes, integer_lattice(0, 0, 6, 3), "zero columns");
    // A diagonal line of zeros through lattice points.
    const Lambda diag([](double x, double y) { return x - y; }, {0, 0, 5, 5});
    mesh_all_ways(diag, integer_lattice(0, 0, 5, 5), "f = x - y");
}

// --- cut points exactly at s/2 ----------------------------------------------------

BOOST_AUTO_TEST_CASE(cut_points_exactly_at_half_spacing) {
    // Rectangle sides halfway between lattice points: every cut edge is cut at
    // u = 1/2 exactly, and the endpoint with f < 0 warps (the tie rule).  A
    // corner point, e.g. (1, 1), is the closer endpoint of two cut edges at
    // equal distance and takes the first (+x, -x, +y, -y): (1, 1) -> (0.5, 1),
    // and the boundary runs on to (2, 0.5), cutting the corner off by a
    // triangle of area 3/8: 6 - 4 * 3/8.
    const auto f = parse_shape("rect:0.5,0.5,3.5,2.5");
    const Mesh m = mesh_all_ways(*f, integer_lattice(-1, -1, 6, 5), "rect at half spacings");
    BOOST_TEST(area(m) == 4.5, boost::test_tools::tolerance(1e-12));
    // The same on an image: 0 / 255 neighbours with iso 127.5.
    std::vector<std::uint16_t> px(64, 0);
    for (int r = 2; r < 6; ++r)
        for (int c = 2; c < 6; ++c) px[static_cast<std::size_t>(r * 8 + c)] = 255;
    // The block's pixel centres span [2, 5]^2; the level set is the square
    // [1.5, 5.5]^2 (area 16) less the same corner cuts.
    const Mesh im = mesh_image(image(8, 8, px), threshold(127.5), 1, "block, iso 127.5");
    BOOST_TEST(area(im) == 14.5, boost::test_tools::tolerance(1e-12));
    // Label mode: a 4-adjacent inside/outside pair is -1/2 / +1/2, the cut is at
    // 1/2 on every boundary edge.
    std::vector<std::uint16_t> lab(64, 1);
    for (int r = 2; r < 6; ++r)
        for (int c = 2; c < 6; ++c) lab[static_cast<std::size_t>(r * 8 + c)] = 2;
    const Mesh lm = mesh_image(image(8, 8, lab), labels({2}), 1, "label block");
    BOOST_TEST(area(lm) == area(im), boost::test_tools::tolerance(1e-12));
    // A circle whose cut points on the axes fall at s/2 exactly.
    mesh_shape("circle:0,0,2.5", 1);
    mesh_shape("circle:0.5,0.5,3", 1);
}

// --- thin shapes -----------------------------------------------------------------

BOOST_AUTO_TEST_CASE(shapes_thinner_than_the_spacing) {
    // Nothing or a valid sliver-free mesh; never an invalid one.
    for (const char* spec : {"rect:0,0,10,0.1", "rect:0.05,0.3,10.05,0.45", "ellipse:0,0,10,0.2", "annulus:0,0,5,5.1",
                             "rect:0,0,0.01,0.01", "circle:0.5,0.5,0.3", "flower:0,0,5,4.9,7",
                             "diff(circle:0,0,5;circle:0,0,4.9)"})
        for (double s : {1.0, 0.5, 0.3}) {
            const Mesh m = mesh_shape(spec, s);
            BOOST_TEST(area(m) >= 0.0);
        }
    // A one-pixel-thick line in an image, threshold and label mode.
    std::vector<std::uint16_t> px(100, 0);
    for (int c = 1; c < 9; ++c) px[static_cast<std::size_t>(50 + c)] = 255;
    for (double s : {1.0, 0.5, 0.75, 2.0}) {
        mesh_image(image(10, 10, px), threshold(127), s, "thin line");
        mesh_image(image(10, 10, px), labels({255}), s, "thin label line");
    }
}

// --- touching components ------------------------------------------------------------

BOOST_AUTO_TEST_CASE(components_touching_at_a_point) {
    // Two squares sharing a corner that is a lattice point (f = 0 there), and
    // that is not one.
    mesh_shape("union(rect:0,0,2,2;rect:2,2,4,4)", 1);
    mesh_shape("union(rect:0,0,2,2;rect:2,2,4,4)", 0.5);
    mesh_shape("union(rect:0,0,2.5,2.5;rect:2.5,2.5,5,5)", 1);
    mesh_shape("union(rect:0.3,0.3,2.3,2.3;rect:2.3,2.3,4.3,4.3)", 1);
    // Two tangent circles, tangent at a lattice point and off the lattice.
    mesh_shape("union(circle:-2,0,2;circle:2,0,2)", 1);
    mesh_shape("union(circle:-2,0,2;circle:2,0,2)", 0.5);
    mesh_shape("union(circle:-2.2,0.3,2;circle:1.8,0.3,2)", 0.7);
    // A hole tangent to the outer boundary.
    mesh_shape("diff(circle:0,0,5;circle:2,0,3)", 1);
    // Diagonal pixel neighbours in an image (a checkerboard is the extreme).
    std::vector<std::uint16_t> checker(64);
    for (int r = 0; r < 8; ++r)
        for (int c = 0; c < 8; ++c) checker[static_cast<std::size_t>(r * 8 + c)] = (r + c) % 2 ? 255 : 0;
    for (double s : {1.0, 0.5}) {
        mesh_image(image(8, 8, checker), threshold(127), s, "checkerboard");
        mesh_image(image(8, 8, checker), threshold(127.5), s, "checkerboard iso 127.5");
        mesh_image(image(8, 8, checker), labels({255}), s, "checkerboard labels");
    }
}

// --- small regions and images -------------------------------------------------------

BOOST_AUTO_TEST_CASE(one_pixel_region) {
    std::vector<std::uint16_t> px(49, 0);
    px[24] = 255;
    for (double s : {1.0, 0.5, 0.25, 0.3}) {
        mesh_image(image(7, 7, px), threshold(127), s, "one pixel");
        mesh_image(image(7, 7, px), labels({255}), s, "one labelled pixel");
    }
    // At spacing 1 the single pixel's lattice point warps and no triangle has
    // three inside corners: an empty (valid) mesh, which the CLI refuses as
    // "region is empty".
    const auto f = make_image_levelset(image(7, 7, px), labels({255}));
    BOOST_TEST(mesh_uniform(*f, lattice_over(f->bounds(), 1), DiagonalRule::separating).mesh.triangles.empty());
    // A one-pixel region in a corner of the image.
    std::vector<std::uint16_t> corner(49, 0);
    corner[0] = 255;
    for (double s : {1.0, 0.5}) mesh_image(image(7, 7, corner), threshold(127), s, "corner pixel");
}

BOOST_AUTO_TEST_CASE(region_filling_the_whole_image) {
    // Every lattice point inside: the plain lattice, closed by the lattice
    // border, every boundary edge tagged 2 (domain border).
    const Image full = image(6, 5, std::vector<std::uint16_t>(30, 200));
    for (double s : {1.0, 0.5}) {
        const Mesh m = mesh_image(full, threshold(100), s, "full image");
        BOOST_TEST(area(m) == 20.0, boost::test_tools::tolerance(1e-12));
        BOOST_TEST(count_tag(m, boundary_domain) == static_cast<std::int64_t>(m.boundary.size()));
        BOOST_TEST(count_tag(m, boundary_level_set) == 0);
    }
    const Mesh lm = mesh_image(full, labels({200}), 1, "full label image");
    BOOST_TEST(count_tag(lm, boundary_level_set) == 0);
}

BOOST_AUTO_TEST_CASE(region_touching_the_border_gets_tag_2_there_only) {
    // Left half of the image bright: the lattice border closes the region on
    // the left, top and bottom (tag 2); the level set x = 4.5 is tag 1.
    std::vector<std::uint16_t> px;
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 10; ++c) px.push_back(c < 5 ? 255 : 0);
    const auto f = make_image_levelset(image(10, 6, px), threshold(127.5));
    const Mesh m = mesh_all_ways(*f, lattice_over(f->bounds(), 1), "left half");
    BOOST_TEST(count_tag(m, boundary_domain) > 0);
    BOOST_TEST(count_tag(m, boundary_level_set) > 0);
    for (std::size_t e = 0; e < m.boundary.size(); ++e) {
        const Vec2 a = m.vertices[static_cast<std::size_t>(m.boundary[e][0])];
        const Vec2 b = m.vertices[static_cast<std::size_t>(m.boundary[e][1])];
        const bool on_border = (a.x == 0 && b.x == 0) || (a.y == 0 && b.y == 0) || (a.y == 5 && b.y == 5);
        BOOST_TEST(m.boundary_tag[e] == (on_border ? boundary_domain : boundary_level_set));
        if (!on_border) BOOST_TEST((a.x == 4.5 && b.x == 4.5));
    }
    // The shape path adds a margin: its meshes never reach the border.
    const Mesh c = mesh_shape("circle:0,0,3", 1);
    BOOST_TEST(count_tag(c, boundary_domain) == 0);
}

BOOST_AUTO_TEST_CASE(two_by_two_image) {
    // The smallest image the CLI accepts: one lattice square at spacing 1.
    for (const auto& px : {std::vector<std::uint16_t>{255, 0, 0, 0}, std::vector<std::uint16_t>{255, 255, 0, 0},
                           std::vector<std::uint16_t>{255, 0, 0, 255}, std::vector<std::uint16_t>{255, 255, 255, 255},
                           std::vector<std::uint16_t>{0, 0, 0, 0}})
        for (double s : {1.0, 0.5, 0.3, 2.0, 10.0}) {
            mesh_image(image(2, 2, px), threshold(127), s, "2x2");
            mesh_image(image(2, 2, px), threshold(255), s, "2x2 iso on a value");
        }
    const auto f = make_image_levelset(image(2, 2, {255, 255, 255, 255}), threshold(127));
    const Lattice l = lattice_over(f->bounds(), 1);
    BOOST_TEST(l.nx == 1);
    BOOST_TEST(l.ny == 1);
    BOOST_TEST(mesh_uniform(*f, l, DiagonalRule::separating).mesh.triangles.size() == 2u);
}

BOOST_AUTO_TEST_CASE(one_by_n_image) {
    // The CLI refuses images narrower than 2 x 2 (test_cli_errors).  The library
    // does not crash on them: the lattice over a 1-pixel-wide image is one
    // square wide, f is constant across it, and the mesh is valid.
    for (const auto& [w, h] : {std::pair{1, 5}, std::pair{5, 1}, std::pair{1, 1}}) {
        std::vector<std::uint16_t> px(static_cast<std::size_t>(w * h), 0);
        px[0] = 255;
        mesh_image(image(w, h, px), threshold(127), 1, "1xN");
        mesh_image(image(w, h, px), labels({255}), 0.5, "1xN labels");
    }
}

BOOST_AUTO_TEST_CASE(constant_images) {
    const Image c = image(5, 4, std::vector<std::uint16_t>(20, 100));
    // Above the iso value everywhere: the whole lattice.
    BOOST_TEST(area(mesh_image(c, threshold(50), 1, "constant, inside")) == 12.0, boost::test_tools::tolerance(1e-12));
    // Below everywhere: nothing.
    BOOST_TEST(mesh_image(c, threshold(150), 1, "constant, outside").triangles.empty());
    // Exactly the iso value: f = 0 everywhere, {f <= 0} is everything.
    BOOST_TEST(area(mesh_image(c, threshold(100), 0.5, "constant, on the level set")) == 12.0,
               boost::test_tools::tolerance(1e-12));
    // Label mode: the only label is everything; any other label is absent.
    BOOST_TEST(area(mesh_image(c, labels({100}), 1, "constant label")) == 12.0, boost::test_tools::tolerance(1e-12));
    BOOST_CHECK_THROW(make_image_levelset(c, labels({7})), InputError);
    ImageLevelSetOptions nz;
    nz.mode = ImageMode::label, nz.label_nonzero = true;
    BOOST_CHECK_THROW(make_image_levelset(image(3, 3, std::vector<std::uint16_t>(9, 0)), nz), InputError);
}

// --- invalid values and lattices --------------------------------------------------------

BOOST_AUTO_TEST_CASE(non_finite_values_are_an_input_error) {
    const Lattice l = integer_lattice(0, 0, 4, 4);
    const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
    for (double bad : {nan, inf, -inf}) {
        const Lambda f([bad](double x, double y) { return x == 2 && y == 3 ? bad : x - 2.5; }, {0, 0, 4, 4});
        BOOST_CHECK_THROW(sample_values(f, l), InputError);
        BOOST_CHECK_THROW(mesh_uniform(f, l, DiagonalRule::separating), InputError);
        BOOST_CHECK_THROW(mesh_graded(f, l, DiagonalRule::maxmin, 0), InputError);
        try {
            sample_values(f, l);
        } catch (const InputError& e) {
            BOOST_TEST(std::string(e.what()).find("not finite at lattice point (2, 3)") != std::string::npos);
        }
        try {  // the graded front end names the same point
            mesh_graded(f, l, DiagonalRule::maxmin, 0);
        } catch (const InputError& e) {
            BOOST_TEST(std::string(e.what()).find("not finite at lattice point (2, 3)") != std::string::npos);
        }
    }
    // A non-finite iso value.
    const Image img = image(2, 2, {0, 1, 2, 3});
    BOOST_CHECK_THROW(make_image_levelset(img, threshold(nan)), InputError);
    BOOST_CHECK_THROW(make_image_levelset(img, threshold(inf)), InputError);
    // Shapes whose parameters are not finite.
    for (const char* spec : {"circle:0,0,nan", "circle:inf,0,1", "rect:0,0,1,nan", "ellipse:0,0,1e999,1"})
        BOOST_CHECK_THROW(parse_shape(spec), InputError);
}

BOOST_AUTO_TEST_CASE(absurd_lattices_are_an_input_error) {
    const Box unit{0, 0, 1, 1};
    for (double s : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        BOOST_CHECK_THROW(lattice_over(unit, s), InputError);
        BOOST_CHECK_THROW(lattice_around(unit, s), InputError);
    }
    // Spacings so small or large that triangle areas (products of two
    // lengths) would underflow or overflow: a 1e-300 square has area 0.
    BOOST_CHECK_THROW(lattice_over(Box{0, 0, 1e-300, 1e-300}, 1e-301), InputError);
    BOOST_CHECK_THROW(lattice_around(Box{-1e300, -1e300, 1e300, 1e300}, 1e300), InputError);
    // Still fine at small scales well inside the limit.
    mesh_shape("circle:0,0,1e-50", 1e-51);
    // So many squares per axis that the count would not even convert: refused
    // before any conversion (undefined behaviour otherwise).
    BOOST_CHECK_THROW(lattice_over(unit, 1e-300), InputError);
    BOOST_CHECK_THROW(lattice_around(unit, 1e-300), InputError);
    BOOST_CHECK_THROW(lattice_around(Box{-1e308, -1e308, 1e308, 1e308}, 1), InputError);
    // Far from the origin relative to the spacing, lattice points would round
    // onto each other (this used to give zero-area triangles).
    BOOST_CHECK_THROW(lattice_around(Box{1e300 - 1, 1e300 - 1, 1e300 + 1, 1e300 + 1}, 1), InputError);
    BOOST_CHECK_THROW(lattice_around(Box{1e15, -3, 1e15 + 6, 3}, 0.1), InputError);
    try {
        lattice_around(Box{1e15, -3, 1e15 + 6, 3}, 0.1);
    } catch (const InputError& e) {
        BOOST_TEST(std::string(e.what()).find("too small for coordinates") != std::string::npos);
    }
    // Still fine well inside the limit, and the mesh is valid.
    mesh_shape("circle:1e6,-1e6,3", 0.1);
}

// --- the fuzzers' seeds and regressions --------------------------------------------------

BOOST_AUTO_TEST_CASE(fuzz_image_reader_seeds_and_regressions) {
    const fs::path dir = fs::path(WARPMESH_SOURCE_DIR) / "tests" / "fuzz";
    std::size_t n = 0;
    for (const char* sub : {"corpus/image_reader", "regressions/image_reader"})
        for (const auto& p : files_in(dir / sub)) {
            BOOST_TEST_MESSAGE("replaying " << p);
            const auto bytes = read_bytes(p);
            fuzz::check_image_reader(bytes);  // aborts on a violation
            ++n;
        }
    BOOST_TEST(n >= 5u);
    // The seeds decode.
    for (const auto& p : files_in(dir / "corpus/image_reader")) {
        const auto bytes = read_bytes(p);
        BOOST_CHECK_NO_THROW(decode_image(bytes, p.string(), fuzz::fuzz_max_pixels));
    }
}

BOOST_AUTO_TEST_CASE(fuzz_pipeline_seeds_and_regressions) {
    const fs::path dir = fs::path(WARPMESH_SOURCE_DIR) / "tests" / "fuzz";
    std::size_t n = 0, meshed = 0;
    for (const char* sub : {"corpus/pipeline", "regressions/pipeline"})
        for (const auto& p : files_in(dir / sub)) {
            BOOST_TEST_MESSAGE("replaying " << p);
            const auto bytes = read_bytes(p);
            fuzz::PipelineCase c;
            if (fuzz::decode_pipeline_case(bytes, c)) meshed += fuzz::run_pipeline_case(c);  // aborts on a violation
            ++n;
        }
    BOOST_TEST(n >= 5u);
    BOOST_TEST(meshed >= 5u);
}
