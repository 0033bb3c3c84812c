// Multi-material meshes in physical units (issue 27 item 7, issue 28 item 3):
// `--units mm` used to be ignored with `--materials` (a NIfTI slice came out
// in pixel units, exit 0), and --slices, --pixel-size and --points-3d were
// refused.  The label materials now take the slice's pixel geometry, as the
// single-region path does (test_volume_io.cpp): these tests apply that path's
// checks to materials — a NIfTI with a permuted sform is placed per the sform
// in millimetres, per-label areas equal pixel counts x pixel area within the
// discretisation error, pixel units reproduce the old meshes bit for bit —
// and run the command line's --materials with --slice, --slices (one summary,
// warnings naming their slices), --units, --pixel-size and --points-3d.
#define BOOST_TEST_MODULE materials_units
#include <boost/test/unit_test.hpp>

#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "support.hpp"
#include "volume_fixtures.hpp"
#include "without_range.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/post/quality.hpp"
#include "warpmesh/io/volume.hpp"
#include "warpmesh/pipeline/slices.hpp"

namespace fs = std::filesystem;
using namespace warpmesh;
using namespace warpmesh::testing;

namespace {

// Three labelled blobs in a dims[0] x dims[1] x dims[2] volume (index i
// fastest): an ellipsoid of label 2, a ball of label 7 inside it, and a box
// of label 40 apart; 0 elsewhere.
std::vector<double> blobs(const std::array<int, 3>& d) {
    std::vector<double> v;
    for (int k = 0; k < d[2]; ++k)
        for (int j = 0; j < d[1]; ++j)
            for (int i = 0; i < d[0]; ++i) {
                const double x = (i - 0.4 * d[0]) / (0.3 * d[0]), y = (j - 0.45 * d[1]) / (0.32 * d[1]),
                             z = (k - 0.5 * d[2]) / (0.45 * d[2]);
                const double bx = i - 0.42 * d[0], by = j - 0.45 * d[1];
                const bool box = i > 0.78 * d[0] && i < 0.95 * d[0] && j > 0.2 * d[1] && j < 0.7 * d[1];
                v.push_back(bx * bx + by * by < 0.02 * d[0] * d[1] && x * x + y * y + z * z < 1 ? 7
                            : x * x + y * y + z * z < 1                                         ? 2
                            : box                                                               ? 40
                                                                                                : 0);
            }
    return v;
}

// Area of the triangles of each region tag.
std::map<std::int32_t, double> area_by_tag(const Mesh& m) {
    std::map<std::int32_t, double> a;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const Vec2 p = m.vertices[static_cast<std::size_t>(m.triangles[t][0])],
                   q = m.vertices[static_cast<std::size_t>(m.triangles[t][1])],
                   r = m.vertices[static_cast<std::size_t>(m.triangles[t][2])];
        a[m.region[t]] += 0.5 * ((q.x - p.x) * (r.y - p.y) - (q.y - p.y) * (r.x - p.x));
    }
    return a;
}

struct Run {
    int code;
    std::string out, err;
};
Run run(const std::string& args, const fs::path& dir) {
    const std::string cmd = "cd '" + dir.string() + "' && '" WARPMESH_EXE "' mesh " + args + " >'" +
                            (dir / "stdout.txt").string() + "' 2>'" + (dir / "stderr.txt").string() + "'";
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "stdout.txt"), slurp(dir / "stderr.txt")};
}

void write(const fs::path& path, const Bytes& b) {
    std::ofstream out(path, std::ios::binary);
    out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

}  // namespace

// The NIfTI of test_volume_io's sform test (rows (-2,0,0), (0,0,3), (0,2,0):
// i along -x at 2 mm, j along +z at 2 mm... rather 3 mm, k along +y), with
// labels: for a slice along every axis, each pixel centre's material is its
// voxel's label and lies at the voxel's sform position; the mesh's
// coordinates are millimetres in the slice's frame (inside its pixel-centre
// box); each label's area is its pixel count times the pixel area within
// the discretisation error; and the mesh is where the single-region path
// puts the same labels.
BOOST_AUTO_TEST_CASE(nifti_permuted_sform_materials_are_placed_in_millimetres) {
    Nifti n;
    n.type = T::u8, n.dim = {3, 36, 30, 24, 1, 1, 1, 1};
    n.sform_code = 2;
    n.srow = {{{-2, 0, 0, 90}, {0, 0, 3, -120}, {0, 2, 0, -70}}};
    n.values = blobs({36, 30, 24});
    const Volume v = decode_volume(nifti(n), "sform.nii");
    int slices = 0;
    for (int axis = 0; axis < 3; ++axis) {
        const std::int64_t m = v.dims[static_cast<std::size_t>(axis)] / 2;
        SliceOptions o;
        o.slice = SliceSpec{axis, m};
        o.materials = "all";
        const LoadedSlice s = load_slice(v, o);
        BOOST_REQUIRE(s.materials);
        BOOST_TEST(!s.f);
        BOOST_TEST(s.physical);
        BOOST_TEST(s.units == "mm");
        // The same placement as the single-region path's.
        SliceOptions one = o;
        one.materials.reset();
        one.levelset = label_options("nonzero");
        const LoadedSlice single = load_slice(v, one);
        BOOST_TEST((s.plane.origin == single.plane.origin && s.plane.x_axis == single.plane.x_axis &&
                    s.plane.y_axis == single.plane.y_axis));
        BOOST_TEST((s.materials->bounds().xmin == single.f->bounds().xmin &&
                    s.materials->bounds().ymax == single.f->bounds().ymax));
        const PixelGeometry g = s.geometry;
        const int a = axis == 0 ? 1 : 0, b = axis == 2 ? 1 : 2;
        double worst = 0;
        int wrong = 0;
        std::map<std::int32_t, std::int64_t> pixels;
        for (int ib = 0; ib < s.height; ++ib)
            for (int ia = 0; ia < s.width; ++ia) {
                std::array<std::int64_t, 3> ijk{m, m, m};
                ijk[static_cast<std::size_t>(a)] = ia, ijk[static_cast<std::size_t>(b)] = ib;
                // The pixel centre in the slice's frame, back in 3D, against
                // the sform applied to (i, j, k).
                const double x = g.x0 + ia * g.sx, y = g.y0 + ib * g.sy;
                const Vec3 p = s.plane.point(x, y);
                for (int r = 0; r < 3; ++r) {
                    const auto& row = n.srow[static_cast<std::size_t>(r)];
                    const double want = row[0] * ijk[0] + row[1] * ijk[1] + row[2] * ijk[2] + row[3];
                    worst = std::max(worst, std::abs(p[r] - want));
                }
                const auto label = static_cast<std::int32_t>(v.at(ijk[0], ijk[1], ijk[2]));
                wrong += s.materials->tag(s.materials->material_at(x, y)) != label;
                ++pixels[label];
            }
        BOOST_TEST_CONTEXT("slice " << "ijk"[axis] << "=" << m) {
            BOOST_TEST(worst < 1e-9);
            BOOST_TEST(wrong == 0);
            MeshOptions mo;
            mo.spacing = s.pixel_min;  // the CLI's default
            const MeshResult r = mesh(*s.materials, mo);
            const Box box = s.materials->bounds();
            for (const Vec2 p : r.mesh.vertices)
                BOOST_TEST((p.x >= box.xmin - 1e-9 && p.x <= box.xmax + 1e-9 && p.y >= box.ymin - 1e-9 &&
                            p.y <= box.ymax + 1e-9));
            const double pixel_area = g.sx * g.sy;
            for (const auto& [tag, area] : area_by_tag(r.mesh)) {
                const double want_area = static_cast<double>(pixels[tag]) * pixel_area;
                // The interfaces pass midway between pixel centres of different
                // labels, cutting the corners of staircase outlines: at most
                // about a quarter pixel per boundary pixel, bounded here by 5 %
                // of these blobs' areas (>= 60 pixels each).
                BOOST_TEST(std::abs(area - want_area) < 0.05 * want_area + 2 * pixel_area,
                           "label " << tag << ": area " << area << " mm^2, pixels x pixel area " << want_area);
                for (int q = 1; q < s.materials->count(); ++q)
                    if (s.materials->tag(q) == tag) BOOST_TEST(*s.materials->reference_area(q) == want_area);
            }
            BOOST_TEST(area_by_tag(r.mesh).size() == pixels.size() - pixels.count(0));  // every label, no background
            BOOST_TEST(area_by_tag(r.mesh).size() >= 2u);
            ++slices;
        }
    }
    BOOST_TEST(slices == 3);
}

// Pixel units are what they always were: the materials of a volume's slice
// in Units::pixels give bit for bit the mesh of make_label_materials on the
// slice's image (the old path), and of a PGM read as a one-slice volume.
BOOST_AUTO_TEST_CASE(materials_in_pixel_units_are_unchanged_bit_for_bit) {
    Nrrd n;
    n.type = T::u16, n.sizes = {40, 32, 3};
    n.extra = "space directions: (0.7,0,0) (0,1.3,0) (0,0,2)\nspace origin: (5,6,7)\n";
    n.values = blobs({40, 32, 3});
    const Volume v = decode_volume(nrrd(n), "v.nrrd");
    SliceOptions o;
    o.slice = SliceSpec{2, 1};
    o.units = Units::pixels;
    o.materials = "all";
    const LoadedSlice s = load_slice(v, o);
    BOOST_TEST(s.geometry.is_pixels());
    const auto old = make_label_materials(slice_image(v, o.slice), "all");
    BOOST_TEST(old->describe() == s.materials->describe());
    for (const bool graded : {false, true}) {
        MeshOptions mo;
        mo.graded = graded;
        const MeshResult a = mesh(*old, mo), b = mesh(*s.materials, mo);
        BOOST_TEST(same_mesh(a.mesh, b.mesh));
        BOOST_TEST(a.mesh.interfaces == b.mesh.interfaces);
    }
    // In millimetres the anisotropic pixels (0.7 x 1.3 mm) change the mesh,
    // the labels' areas scale by the pixel area, graded or not.
    o.units = Units::physical;
    const LoadedSlice mm = load_slice(v, o);
    BOOST_TEST(mm.geometry.sx == 0.7);
    BOOST_TEST(mm.geometry.sy == 1.3);
    MeshOptions mo;
    mo.spacing = 0.7;
    const auto uniform = area_by_tag(mesh(*mm.materials, mo).mesh);
    mo.graded = true;
    const auto graded = area_by_tag(mesh(*mm.materials, mo).mesh);
    const auto px = area_by_tag(mesh(*old, MeshOptions{}).mesh);
    for (const auto& [tag, area] : uniform) {
        BOOST_TEST(std::abs(graded.at(tag) - area) < 1e-9 * area, "label " << tag);
        BOOST_TEST(std::abs(area - px.at(tag) * 0.7 * 1.3) < 0.05 * area, "label " << tag);
    }
}

// The command line: --materials with --slice in mm (the default for NRRD) or
// --units pixels, --pixel-size, --points-3d, and --slices (parallel, one file
// per slice, one summary; a warning repeated by several slices is printed
// once, naming them).
BOOST_AUTO_TEST_CASE(cli_materials_with_units_slices_pixel_size_and_points_3d) {
    TempDir dir("warpmesh-materials-units");
    Nrrd n;
    n.type = T::u16, n.sizes = {40, 32, 4};
    n.extra = "space directions: (0.5,0,0) (0,1.5,0) (0,0,2)\nspace origin: (1,2,3)\n";
    n.values = blobs({40, 32, 4});
    // Slice 3 is empty; a one-voxel label 9 in slices 0 and 1, which a coarse
    // spacing loses (a warning per slice).
    for (int j = 0; j < 32; ++j)
        for (int i = 0; i < 40; ++i) n.values[static_cast<std::size_t>(i + 40 * (j + 32 * 3))] = 0;
    for (int k = 0; k < 2; ++k) n.values[static_cast<std::size_t>(3 + 40 * (3 + 32 * k))] = 9;
    write(dir.path / "v.nrrd", nrrd(n));

    Run r = run("v.nrrd --materials all --slice k=1 -o mm.vtu --points-3d mm.csv --report mm.json", dir.path);
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    std::string report = slurp(dir.path / "mm.json");
    BOOST_TEST(report.find("\"units\": \"mm\"") != std::string::npos, report);
    BOOST_TEST(report.find("\"axis\": \"k\", \"index\": 1") != std::string::npos);
    BOOST_TEST(report.find("\"origin\": [0, 0, 5]") != std::string::npos, report);  // 3 + 1 * 2 mm
    BOOST_TEST(report.find("\"spacing\": 0.5") != std::string::npos);            // the smaller pixel size
    BOOST_TEST(report.find("pixel 0.5 x 1.5, origin (1, 2)") != std::string::npos);
    const std::string csv = slurp(dir.path / "mm.csv");
    std::istringstream lines(csv);
    std::string line;
    std::getline(lines, line);
    BOOST_TEST(line == "x,y,z");
    int points = 0, off_plane = 0;
    while (std::getline(lines, line)) {
        ++points;
        off_plane += line.substr(line.rfind(',') + 1) != "5";
    }
    BOOST_TEST(points > 100);
    BOOST_TEST(off_plane == 0);
    BOOST_TEST(report.find("\"vertices\": " + std::to_string(points)) != std::string::npos);

    r = run("v.nrrd --materials all --slice k=1 --units pixels -o px.vtu --report px.json --quiet", dir.path);
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    BOOST_TEST(slurp(dir.path / "px.json").find("\"units\": \"pixels\"") != std::string::npos);
    r = run("v.nrrd --materials 2,7 --slice k=1 --pixel-size 0.25 -o ps.vtu --report ps.json --quiet", dir.path);
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    report = slurp(dir.path / "ps.json");
    BOOST_TEST(report.find("pixel 0.25 x 0.25") != std::string::npos, report);
    BOOST_TEST(report.find("\"spacing\": 0.25") != std::string::npos);

    // --slices: one file per slice, the empty slice skipped, one summary;
    // label 9 is lost at spacing 2 mm in slices 0 and 1: one warning line.
    r = run("v.nrrd --materials all --slices k=0:4 --spacing 2 -o 'out_%d.vtu' --points-3d 'p_%d.csv' --report sum.json",
            dir.path);
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    for (int k = 0; k < 3; ++k) {
        BOOST_TEST(fs::exists(dir.path / ("out_" + std::to_string(k) + ".vtu")), k);
        BOOST_TEST(fs::exists(dir.path / ("p_" + std::to_string(k) + ".csv")), k);
    }
    BOOST_TEST(!fs::exists(dir.path / "out_3.vtu"));
    const std::string sum = slurp(dir.path / "sum.json");
    BOOST_TEST(sum.find("\"meshed\": 3, \"skipped\": 1") != std::string::npos, sum);
    BOOST_TEST(sum.find("no label other than 0") != std::string::npos, sum);
    BOOST_TEST(r.out.find("3 of 4 slices meshed") != std::string::npos, r.out);
    BOOST_TEST(r.err.find("warning: slices k=0, 1: ") != std::string::npos, r.err);
    BOOST_TEST(r.err.find("label_9") != std::string::npos, r.err);
    std::size_t warnings = 0;
    for (std::size_t at = 0; (at = r.err.find("warning:", at)) != std::string::npos; ++at) ++warnings;
    BOOST_TEST(warnings == 1u, r.err);
    BOOST_TEST(sum.find("\"warnings\": [") != std::string::npos, sum);
}
