#define BOOST_TEST_MODULE write_png
#include <boost/test/unit_test.hpp>

// The PNG writer: the written file is decoded with libpng and checked — size,
// white background, light fill inside triangles, red boundary, y up (by a
// cell-data colouring that is low at the bottom), the legend, the dispatcher,
// and atomic failure (nothing under the name, no temporary left behind).

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "support.hpp"
#include "warpmesh/core/mesh.hpp"
#include "warpmesh/io/writers.hpp"

#ifdef WARPMESH_HAVE_PNG
#include <png.h>
#endif

namespace fs = std::filesystem;
using namespace warpmesh;

namespace {

struct TempDir : warpmesh::testing::TempDir {
    TempDir() : warpmesh::testing::TempDir("warpmesh-png") {}
};

// n x n unit squares on [0, n]^2, two CCW triangles each; the whole outer
// boundary is tagged level set (1) except the bottom side, tagged 2 (lattice
// border).  Cell data "height": the y of the triangle's centroid.
Mesh grid(int n) {
    Mesh m;
    auto id = [&](int i, int j) { return static_cast<std::int32_t>(i + j * (n + 1)); };
    for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) m.vertices.push_back({static_cast<double>(i), static_cast<double>(j)});
    std::vector<double> height;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
            m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
            height.push_back(j + 1.0 / 3);
            height.push_back(j + 2.0 / 3);
        }
    m.region.assign(m.triangles.size(), 1);
    for (int i = 0; i < n; ++i) {
        m.boundary.push_back({id(i, 0), id(i + 1, 0)}), m.boundary_tag.push_back(boundary_domain);
        m.boundary.push_back({id(n, i), id(n, i + 1)}), m.boundary_tag.push_back(boundary_level_set);
        m.boundary.push_back({id(n - i, n), id(n - i - 1, n)}), m.boundary_tag.push_back(boundary_level_set);
        m.boundary.push_back({id(0, n - i), id(0, n - i - 1)}), m.boundary_tag.push_back(boundary_level_set);
    }
    m.cell_data.emplace_back("height", Buffer<double>(height.begin(), height.end()));
    return m;
}

#ifdef WARPMESH_HAVE_PNG

struct Decoded {
    int w = 0, h = 0;
    std::vector<unsigned char> rgb;
    std::array<int, 3> at(int x, int y) const {
        const std::size_t i = 3 * (static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x));
        return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
};

// Decode with libpng's simplified API into 8-bit RGB.
Decoded decode(const std::string& path) {
    png_image image{};
    image.version = PNG_IMAGE_VERSION;
    BOOST_REQUIRE(png_image_begin_read_from_file(&image, path.c_str()) != 0);
    image.format = PNG_FORMAT_RGB;
    Decoded d;
    d.w = static_cast<int>(image.width), d.h = static_cast<int>(image.height);
    d.rgb.resize(PNG_IMAGE_SIZE(image));
    BOOST_REQUIRE(png_image_finish_read(&image, nullptr, d.rgb.data(), 0, nullptr) != 0);
    return d;
}

bool white(std::array<int, 3> c) { return c[0] == 255 && c[1] == 255 && c[2] == 255; }
bool reddish(std::array<int, 3> c) { return c[0] > 170 && c[1] < 110 && c[2] < 110; }
bool bluish(std::array<int, 3> c) { return c[2] > 150 && c[0] < 110; }

// Pixel centre of mesh point (x, y) for a square [0, n]^2 mesh drawn with
// long side L: the writer's mapping (margin max(6, round(0.015 L))).
struct Map {
    double margin, s, n;
    Map(int L, int n_) : margin(std::max(6L, std::lround(0.015 * L))), s((L - 2 * margin) / n_), n(n_) {}
    int col(double x) const { return static_cast<int>(std::floor(margin + x * s)); }
    int row(double y) const { return static_cast<int>(std::floor(margin + (n - y) * s)); }
};

#endif

}  // namespace

#ifdef WARPMESH_HAVE_PNG

BOOST_AUTO_TEST_CASE(size_background_fill_boundary) {
    TempDir dir;
    const Mesh m = grid(4);
    PngOptions o;
    o.long_side_px = 400;
    const std::string path = dir.file("grid.png");
    write_png(m, path, o);
    const Decoded d = decode(path);
    BOOST_TEST(d.w == 400);
    BOOST_TEST(d.h == 400);
    // Background: the corners, outside the mesh.
    BOOST_TEST(white(d.at(0, 0)));
    BOOST_TEST(white(d.at(399, 399)));
    BOOST_TEST(white(d.at(2, 200)));
    // The fill: the centroid of the lower-right triangle of square (1, 1) —
    // light blue-grey, not white, not dark.
    const Map map(400, 4);
    const auto fill = d.at(map.col(1 + 2.0 / 3), map.row(1 + 1.0 / 3));
    BOOST_TEST(!white(fill));
    BOOST_TEST(fill[2] > 200);
    BOOST_TEST(fill[0] > 180);
    // The boundary: the reddest pixel near the right side (x = 4, level set)
    // at mid-height is red; near the bottom side (lattice border) blue.
    auto best = [&](int c0, int c1, int r0, int r1, auto score) {
        std::array<int, 3> b = d.at(c0, r0);
        for (int r = r0; r <= r1; ++r)
            for (int c = c0; c <= c1; ++c)
                if (score(d.at(c, r)) > score(b)) b = d.at(c, r);
        return b;
    };
    const auto red = best(map.col(4) - 2, map.col(4) + 2, map.row(2.5), map.row(2.5),
                          [](std::array<int, 3> c) { return c[0] - c[1] - c[2]; });
    BOOST_TEST(reddish(red), "right side " << red[0] << "," << red[1] << "," << red[2]);
    const auto left = best(map.col(0) - 2, map.col(0) + 2, map.row(1.5), map.row(1.5),
                           [](std::array<int, 3> c) { return c[0] - c[1] - c[2]; });
    BOOST_TEST(reddish(left));
    const auto blue = best(map.col(2.5), map.col(2.5), map.row(0) - 2, map.row(0) + 2,
                           [](std::array<int, 3> c) { return c[2] - c[0]; });
    BOOST_TEST(bluish(blue), "bottom side " << blue[0] << "," << blue[1] << "," << blue[2]);
    // An interior edge (the vertical line x = 2) is darker than the fill.
    const auto edge = best(map.col(2) - 1, map.col(2) + 1, map.row(2.5), map.row(2.5),
                           [](std::array<int, 3> c) { return -(c[0] + c[1] + c[2]); });
    BOOST_TEST(edge[0] + edge[1] + edge[2] < fill[0] + fill[1] + fill[2] - 60);
    // Anti-aliasing: somewhere along the boundary there are intermediate
    // shades between red and white (not only the two colours).
    bool intermediate = false;
    for (int c = map.col(4) - 4; c <= map.col(4) + 4; ++c) {
        const auto p = d.at(c, map.row(2.5));
        if (!white(p) && !reddish(p) && p[0] > 200 && p[1] > 110 && p[1] < 250) intermediate = true;
    }
    BOOST_TEST(intermediate);
}

BOOST_AUTO_TEST_CASE(y_up_and_cell_data_legend) {
    TempDir dir;
    const Mesh m = grid(6);
    PngOptions o;
    o.long_side_px = 300;
    o.color_by_cell_data = "height";
    o.draw_edges = false;
    const std::string path = dir.file("height.png");
    write_png(m, path, o);
    const Decoded d = decode(path);
    BOOST_TEST(d.h == 300);
    BOOST_TEST(d.w > 300);  // the legend adds columns on the right
    const Map map(300, 6);
    // Low values (bottom of the mesh, y small) are red, high (top) green: so
    // the top rows of the picture must be green, i.e. y points up.
    const auto top = d.at(map.col(3.3), map.row(5.5));
    const auto bottom = d.at(map.col(3.3), map.row(0.5));
    BOOST_TEST(top[1] > top[0]);        // green
    BOOST_TEST(bottom[0] > bottom[1]);  // red
    // The legend: some non-white pixels right of the mesh, among them
    // both ends of the colour ramp.
    bool green = false, redp = false;
    for (int y = 0; y < d.h; ++y)
        for (int x = 300; x < d.w; ++x) {
            const auto p = d.at(x, y);
            if (p[1] > 130 && p[0] < 60) green = true;
            if (p[0] > 190 && p[1] < 80) redp = true;
        }
    BOOST_TEST(green);
    BOOST_TEST(redp);
}

BOOST_AUTO_TEST_CASE(dispatcher_and_min_angle_colouring) {
    TempDir dir;
    const Mesh m = grid(3);
    WriteOptions wo;
    wo.png.long_side_px = 120;
    write_mesh(m, dir.file("a.PNG"), wo);
    BOOST_TEST(decode(dir.file("a.PNG")).w == 120);
    BOOST_CHECK_NO_THROW(check_output_path(dir.file("b.png")));
    wo.svg.color_by_min_angle = true;  // --svg-color minangle colours the PNG too
    write_mesh(m, dir.file("c.png"), wo);
    const Decoded d = decode(dir.file("c.png"));
    BOOST_TEST(d.w > 120);  // with a legend
    // Right isosceles triangles: minimum angle 45° → 0.75 of the ramp, between
    // yellow and green.
    const Map map(120, 3);
    const auto p = d.at(map.col(1 + 2.0 / 3), map.row(1 + 1.0 / 3));
    BOOST_TEST(p[1] > p[0]);
    BOOST_TEST(p[1] > p[2]);
}

BOOST_AUTO_TEST_CASE(atomic_failures) {
    TempDir dir;
    const Mesh m = grid(2);
    // A missing directory: OutputError naming the path, no file.
    const std::string bad = dir.file("no-such-dir/x.png");
    try {
        write_png(m, bad);
        BOOST_FAIL("no exception");
    } catch (const OutputError& e) {
        BOOST_TEST(std::string(e.what()).find(bad) != std::string::npos);
    }
    BOOST_TEST(!fs::exists(bad));
    BOOST_CHECK_THROW(check_output_path(bad), OutputError);
    // A failure during rendering (unknown cell data): nothing under the name,
    // no temporary left, an existing file untouched.
    const std::string path = dir.file("keep.png");
    write_png(m, path);
    const auto before = fs::file_size(path);
    PngOptions o;
    o.color_by_cell_data = "no-such-array";
    BOOST_CHECK_THROW(write_png(m, path, o), OutputError);
    BOOST_TEST(fs::file_size(path) == before);
    BOOST_TEST(dir.entries() == 1U);
    BOOST_CHECK_THROW(write_png(m, dir.file("fresh.png"), o), OutputError);
    BOOST_TEST(!fs::exists(dir.file("fresh.png")));
    BOOST_TEST(dir.entries() == 1U);
    // Bad options.
    PngOptions tiny;
    tiny.long_side_px = 4;
    BOOST_CHECK_THROW(write_png(m, dir.file("tiny.png"), tiny), OutputError);
    BOOST_TEST(dir.entries() == 1U);
    // Inconsistent mesh arrays.
    Mesh broken = m;
    broken.region.pop_back();
    BOOST_CHECK_THROW(write_png(broken, dir.file("broken.png")), OutputError);
    BOOST_TEST(dir.entries() == 1U);
}

#else

BOOST_AUTO_TEST_CASE(without_libpng_png_output_is_refused) {
    TempDir dir;
    BOOST_CHECK_THROW(write_png(grid(2), dir.file("x.png")), OutputError);
    BOOST_CHECK_THROW(check_output_path(dir.file("x.png")), OutputError);
    BOOST_TEST(dir.entries() == 0U);
}

#endif
