// The fan rule (--diagonal fan) on the image that realises the prover's 15°
// witness of the separating rule (key -R+U-L-R, see test_certified_mesh.cpp,
// which builds the same image): the witness square gets the centroid fan, the
// mesh keeps every angle at or above atan(1/3) up to 5.5e-6 deg (the certified
// floor, fan.cert), and --verify checks every triangle against its key; the
// graded mesher gives the same fan (test_graded.cpp compares graded and
// uniform fan meshes on random level sets).
#define BOOST_TEST_MODULE fan_rule
#include <boost/test/unit_test.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "witness_image.hpp"
#include "warpmesh/certified.hpp"
#include "warpmesh/image.hpp"
#include "warpmesh/image_levelset.hpp"
#include "warpmesh/lattice.hpp"
#include "warpmesh/mesh_checks.hpp"
#include "warpmesh/uniform.hpp"

namespace fs = std::filesystem;
using namespace warpmesh;

namespace {

double number(const std::string& j, const std::string& key) {
    const auto at = j.find("\"" + key + "\": ");
    BOOST_REQUIRE(at != std::string::npos);
    return std::stod(j.substr(at + key.size() + 4));
}

}  // namespace

BOOST_AUTO_TEST_CASE(witness_image_keeps_atan_one_third_with_the_fan_rule) {
    const fs::path dir = fs::temp_directory_path() / ("warpmesh_fan_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path img = dir / "witness.pgm";
    warpmesh::testing::write_witness_image(img);
    auto run = [&](const std::string& rule) {
        const std::string report = (dir / (rule + ".json")).string();
        const std::string cmd = std::string(WARPMESH_EXE) + " mesh " + img.string() +
                                " --iso 30000 --inside below --verify --quiet --diagonal " + rule + " --report " +
                                report + " -o " + (dir / (rule + ".vtu")).string() + " 2>" +
                                (dir / (rule + ".err")).string();
        BOOST_REQUIRE(std::system(cmd.c_str()) == 0);
        std::ifstream in(report);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    };
    const std::string sep = run("separating"), fan = run("fan");
    BOOST_TEST(number(sep, "min_angle_deg") < 15.01);  // the witness, realised
    const double floor_deg = certified_theorem(DiagonalRule::fan).min_deg_any;
    BOOST_TEST(floor_deg >= 18.4349);  // the unconditional theorem, to 4 decimals
    BOOST_TEST(number(fan, "min_angle_deg") >= floor_deg);
    BOOST_TEST(number(fan, "min_angle_deg") >= 18.4349);
    const auto cert = fan.substr(fan.find("\"certified\": {"));
    BOOST_TEST(number(cert, "min_angle_deg") >= 18.4349);
    BOOST_TEST(cert.find("\"verified\": true") != std::string::npos);
    // The witness square's two triangles became the four of its fan, with one
    // new vertex; every other square is triangulated as by the separating rule.
    BOOST_TEST(number(fan, "triangles") == number(sep, "triangles") + 2);
    BOOST_TEST(number(fan, "vertices") == number(sep, "vertices") + 1);
    fs::remove_all(dir);
}

BOOST_AUTO_TEST_CASE(fan_mesh_is_conforming_with_its_boundary_on_the_level_set) {
    // Through the library: the same image, spacing 1 on the pixel centres.
    const fs::path dir = fs::temp_directory_path() / ("warpmesh_fan_lib_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path img = dir / "witness.pgm";
    warpmesh::testing::write_witness_image(img);
    ImageLevelSetOptions o;
    o.iso = 30000;
    o.inside_above = false;
    const auto f = make_image_levelset(read_image(img.string()), o);
    const Lattice lattice = lattice_over(f->bounds(), 1.0);
    const UniformResult sep = mesh_uniform(*f, lattice, DiagonalRule::separating);
    const UniformResult fan = mesh_uniform(*f, lattice, DiagonalRule::fan);
    const MeshCheck chk = check_mesh(fan.mesh);  // orientation, conformity, boundary loops
    BOOST_TEST(chk.ok(), (chk.messages.empty() ? "" : chk.messages.front()));
    BOOST_TEST(fan.mesh.vertices.size() == sep.mesh.vertices.size() + 1);  // one fan centre
    BOOST_TEST(fan.mesh.boundary == sep.mesh.boundary);  // the fan square is interior to the region
    // Every vertex on a level-set boundary edge is on the level set (a cut
    // point or a zero of f): the centre never is a boundary vertex.
    for (std::size_t e = 0; e < fan.mesh.boundary.size(); ++e) {
        if (fan.mesh.boundary_tag[e] != boundary_level_set) continue;
        for (std::int32_t v : fan.mesh.boundary[e]) {
            const auto x = fan.mesh.vertices[static_cast<std::size_t>(v)];
            BOOST_TEST(std::abs(f->value(x.x, x.y)) <= 1e-3,  // f is in pixel-value units (10^4)
                       "vertex " << v << " at " << x.x << "," << x.y);
        }
    }
    fs::remove_all(dir);
}

// The graded mesher takes the fan rule too (the fan square is a finest leaf,
// triangulated as in the uniform mesh): on the witness image, through the
// CLI with --verify (every triangle against its key of fan.cert, and the
// graded invariant), the same fan and the same floor as the uniform mesh.
BOOST_AUTO_TEST_CASE(graded_mesh_takes_the_fan_rule_on_the_witness_image) {
    const fs::path dir = fs::temp_directory_path() / ("warpmesh_fan_graded_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path img = dir / "witness.pgm";
    warpmesh::testing::write_witness_image(img);
    auto run = [&](const std::string& name, const std::string& args) {
        const std::string report = (dir / (name + ".json")).string();
        const std::string cmd = std::string(WARPMESH_EXE) + " mesh " + img.string() +
                                " --iso 30000 --inside below --verify --quiet " + args + " --report " + report +
                                " -o " + (dir / (name + ".vtu")).string() + " 2>" + (dir / (name + ".err")).string();
        BOOST_REQUIRE_MESSAGE(std::system(cmd.c_str()) == 0, cmd);
        std::ifstream in(report);
        std::stringstream ss;
        ss << in.rdbuf();
        return ss.str();
    };
    const std::string gsep = run("graded_sep", "--graded --diagonal separating");
    const std::string gfan = run("graded_fan", "--graded --diagonal fan");
    const std::string ufan = run("uniform_fan", "--diagonal fan");
    BOOST_TEST(number(gsep, "min_angle_deg") < 15.01);  // the witness, in the graded mesh too
    BOOST_TEST(number(gfan, "min_angle_deg") >= certified_theorem(DiagonalRule::fan).min_deg_any);
    BOOST_TEST(number(gfan, "min_angle_deg") >= 18.4349);
    BOOST_TEST(number(gfan, "min_angle_deg") == number(ufan, "min_angle_deg"));  // the fan's own angle
    const auto cert = gfan.substr(gfan.find("\"certified\": {"));
    BOOST_TEST(number(cert, "min_angle_deg") >= 18.4349);
    BOOST_TEST(cert.find("\"verified\": true") != std::string::npos);
    BOOST_TEST(number(gfan, "triangles") == number(gsep, "triangles") + 2);  // one fan: 4 triangles for 2
    BOOST_TEST(number(gfan, "vertices") == number(gsep, "vertices") + 1);   // and its centre
    fs::remove_all(dir);
}

BOOST_AUTO_TEST_CASE(fan_rule_refused_for_several_materials) {
    // Multi-material meshes: the fan is certified for two phases only — a
    // clear error naming the rule and a non-zero exit, no file.
    const fs::path dir = fs::temp_directory_path() / ("warpmesh_fan_refuse_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path out = dir / "materials.vtu";
    const std::string cmd = std::string(WARPMESH_EXE) + " mesh " + WARPMESH_TEST_DATA +
                            "/abdomen_axial_z024_labels16.pgm --materials all --diagonal fan -o " + out.string() +
                            " 2>" + (dir / "materials.err").string();
    BOOST_TEST(std::system(cmd.c_str()) != 0);
    BOOST_TEST(!fs::exists(out));
    std::ifstream err(dir / "materials.err");
    std::stringstream ss;
    ss << err.rdbuf();
    BOOST_TEST(ss.str().find("--diagonal fan") != std::string::npos, ss.str());
    BOOST_TEST(ss.str().find("materials") != std::string::npos, ss.str());
    fs::remove_all(dir);
}
