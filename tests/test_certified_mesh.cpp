// Meshes checked against the certificates: every triangle of a warped square
// lies in its key's certified interval (verify), the reported guarantee is the
// min over the triangles' bounds, and flat refinement removes sub-18.43° bounds.
#define BOOST_TEST_MODULE certified_mesh
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "certified_stage.hpp"
#include "witness_image.hpp"
#include "warpmesh/certify/certified.hpp"
#include "warpmesh/mesh2d/graded.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "warpmesh/mesh2d/uniform.hpp"

using namespace warpmesh;
using warpmesh::testing::certified, warpmesh::testing::with_keys;

namespace {
const Buffer<double>& cell(const Mesh& m) {
    for (const auto& [name, v] : m.cell_data)
        if (name == "certified_min_angle") return v;
    BOOST_FAIL("no certified_min_angle");
    static Buffer<double> none;
    return none;
}
std::string random_shape(std::mt19937& rng, int it) {
    std::uniform_real_distribution<double> u(0, 1);
    std::ostringstream spec;
    spec.precision(17);
    const double cx = u(rng), cy = u(rng);
    switch (it % 3) {
        case 0: spec << "flower:" << cx << "," << cy << "," << 5 + 5 * u(rng) << "," << 1 + 3 * u(rng) << "," << 3 + it % 5; break;
        case 1: spec << "ellipse:" << cx << "," << cy << "," << 2 + 10 * u(rng) << "," << 1 + 5 * u(rng); break;
        default: spec << "union(circle:" << cx << "," << cy << ",4;circle:" << cx + 5 << "," << cy + 1 << ",3)"; break;
    }
    return spec.str();
}
}  // namespace

BOOST_AUTO_TEST_CASE(random_levelsets_verify_and_guarantee) {
    std::mt19937 rng(777);
    std::uniform_real_distribution<double> u(0, 1);
    std::int64_t nonflat = 0;
    for (int it = 0; it < 30; ++it) {
        const auto f = parse_shape(random_shape(rng, it));
        const Lattice lat = lattice_around(f->bounds(), 0.4 + 2.0 * u(rng));  // coarse: non-flat stencils occur
        for (DiagonalRule r : {DiagonalRule::maxmin, DiagonalRule::separating})
            for (int graded = 0; graded < 2; ++graded) {
                Mesh mesh;
                CertifiedSummary c;
                try {
                    if (graded) {
                        auto res = certified(mesh_graded(*f, lat, r, 0, with_keys), lat, r);
                        mesh = std::move(res.mesh);
                        c = res.certified;
                    } else {
                        auto res = certified(mesh_uniform(*f, lat, r, with_keys), lat, r);
                        mesh = std::move(res.mesh);
                        c = res.certified;
                    }
                } catch (const std::exception& e) {
                    BOOST_FAIL("shape " << it << " rule " << int(r) << " graded " << graded << ": " << e.what());
                }
                BOOST_REQUIRE(c.available);
                BOOST_TEST(c.verified);
                if (mesh.triangles.empty()) continue;
                const auto& v = cell(mesh);
                BOOST_REQUIRE(v.size() == mesh.triangles.size());
                BOOST_TEST(c.min_deg == *std::min_element(v.begin(), v.end()));
                BOOST_TEST(c.min_deg >= certified_theorem(r).min_deg_any);
                BOOST_TEST(c.flat_squares + c.nonflat_squares == c.keyed_squares);
                if (c.nonflat_squares == 0 && c.keyed_squares > 0)
                    BOOST_TEST(c.keyed_min_deg >= certified_theorem(r).min_deg_flat);
                nonflat += c.nonflat_squares;
            }
    }
    BOOST_TEST(nonflat > 0);  // the coarse spacings do exercise non-flat stencils
}

// A coarse shape where a non-flat square's key certifies less than atan(1/3);
// refining (as --guarantee flat does) removes every non-flat square and the
// guarantee rises to theorem F.
BOOST_AUTO_TEST_CASE(nonflat_low_bound_removed_by_refinement) {
    const double flat_deg = certified_theorem(DiagonalRule::maxmin).min_deg_flat;
    std::mt19937 rng(4242);
    std::uniform_real_distribution<double> u(0, 1);
    bool found = false;
    for (int it = 0; it < 400 && !found; ++it) {
        const std::string spec = random_shape(rng, it);
        const auto f = parse_shape(spec);
        double s = 0.5 + 2.5 * u(rng);
        const auto mesh_at = [&](double spacing) {
            const Lattice lat = lattice_around(f->bounds(), spacing);
            return certified(mesh_uniform(*f, lat, DiagonalRule::maxmin, with_keys), lat, DiagonalRule::maxmin);
        };
        auto res = mesh_at(s);
        if (!(res.certified.nonflat_squares > 0 && res.certified.keyed_min_deg < flat_deg - 1e-6)) continue;
        found = true;
        BOOST_TEST_MESSAGE(spec << " at spacing " << s << ": certified " << res.certified.keyed_min_deg
                                << " deg, non-flat " << res.certified.nonflat_keys.front());
        for (int ref = 0; ref < 6 && res.certified.nonflat_squares > 0; ++ref) {
            s /= 2;
            res = mesh_at(s);
        }
        BOOST_TEST(res.certified.nonflat_squares == 0);
        BOOST_TEST(res.certified.keyed_min_deg >= flat_deg);
        BOOST_TEST(res.certified.min_deg >= flat_deg);
    }
    BOOST_TEST(found, "no coarse shape with a non-flat sub-18.43 deg key found");
}

BOOST_AUTO_TEST_CASE(cli_guarantee_flat) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("warpmesh_cert_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string report = (dir / "r.json").string();
    const std::string cmd = std::string(WARPMESH_EXE) +
                            " mesh --shape ellipse:0.83394607101968854,0.51418896218051124,8.6396592053008217,1.7641549835951533 --spacing 2.77624 --diagonal maxmin --guarantee flat --quiet"
                            " --verify --report " + report + " -o " + (dir / "m.svg").string() +
                            " --svg-color certified 2>" + (dir / "err.txt").string();
    BOOST_REQUIRE(std::system(cmd.c_str()) == 0);
    std::ifstream in(report);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string j = ss.str();
    BOOST_TEST(j.find("\"certified\": {") != std::string::npos);
    BOOST_TEST(j.find("\"nonflat_squares\": 0") != std::string::npos, j.substr(j.find("\"certified\"")));
    BOOST_TEST(j.find("\"verified\": true") != std::string::npos);
    fs::remove_all(dir);
}

// A 16-bit test image that realises, up to rounding of the pixel values, the
// prover's 15° witness (key -R+U-L-R) in lattice square (2, 2).  Lattice on
// the pixel centres, threshold mode, so every cut point is exact linear
// interpolation; f = pixel − 30000, inside below.  With A = (2,2), B = (3,2),
// C = (2,3), D = (3,3):
//   A = −a, B = +a        the cut on AB is at exactly 1/2: A (f < 0) warps +x;
//   D = −d                B's nearer cut point is on BD at t = a/(a+d) ≈ 0.13397
//                         (the witness's 73653313183/2^39): B warps +y;
//   C = −c, (1,3) = +c    C warps −x by 1/2;  D = −d, (4,3) = +d: D warps +x by 1/2.
// The other neighbours of the four corners are on their corner's side, so no
// other cut edge competes.  The stencil is not flat: (1,3) and (4,3) are
// outside, (2,3) and (3,3) between them inside.
BOOST_AUTO_TEST_CASE(witness_image_below_atan_one_third_and_guarantee_flat) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() / ("warpmesh_witness_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path img = dir / "witness.pgm";
    warpmesh::testing::write_witness_image(img);
    auto run = [&](const std::string& extra, const std::string& name) {
        const std::string report = (dir / (name + ".json")).string();
        const std::string cmd = std::string(WARPMESH_EXE) + " mesh " + img.string() +
                                " --iso 30000 --inside below --diagonal maxmin --verify --quiet --report " + report +
                                " -o " + (dir / (name + ".svg")).string() + " " + extra + " 2>" +
                                (dir / (name + ".err")).string();
        BOOST_REQUIRE(std::system(cmd.c_str()) == 0);
        std::ifstream in(report);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    };
    auto number = [](const std::string& j, const std::string& key) {
        const auto at = j.find("\"" + key + "\": ");
        BOOST_REQUIRE(at != std::string::npos);
        return std::stod(j.substr(at + key.size() + 4));
    };
    const double flat_deg = certified_theorem(DiagonalRule::maxmin).min_deg_flat;

    const std::string j = run("", "coarse");
    // The measured minimum angle is below the paper's bound (it is 15.000…°) …
    BOOST_TEST(number(j, "min_angle_deg") < 15.01);
    // … and the mesher knows: square (2, 2) is reported non-flat with its key,
    // and the certified guarantee is the U bound, below the measured angle.
    BOOST_TEST(j.find("{\"i\": 2, \"j\": 2, \"key\": \"-R+U-L-R\"}") != std::string::npos);
    const auto cert = j.substr(j.find("\"certified\": {"));
    BOOST_TEST(number(cert, "min_angle_deg") < 15.0);
    BOOST_TEST(number(cert, "min_angle_deg") <= number(j, "min_angle_deg"));
    std::ifstream svg(dir / "coarse.svg");
    std::stringstream svgs;
    svgs << svg.rdbuf();
    BOOST_TEST(svgs.str().find("<g id=\"marked\"") != std::string::npos);  // non-flat squares outlined

    // --guarantee flat: the spacing is halved until no sub-atan(1/3) bound is
    // left (a few squares at pixel-value kinks may stay non-flat, with keys
    // whose own bounds are at least the flat theorem's).
    const std::string g = run("--guarantee flat --min-spacing 0.01", "flat");
    const auto gcert = g.substr(g.find("\"certified\": {"));
    BOOST_TEST(number(gcert, "min_angle_deg") >= flat_deg);
    BOOST_TEST(number(g, "min_angle_deg") >= flat_deg);
    BOOST_TEST(g.find("\"-R+U-L-R\"") == std::string::npos);
    fs::remove_all(dir);
}
