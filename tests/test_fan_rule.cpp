// The fan rule (--diagonal fan) on the image that realises the prover's 15°
// witness of the separating rule (key -R+U-L-R, see test_certified_mesh.cpp,
// which builds the same image): the witness square gets the centroid fan, the
// mesh keeps every angle at or above atan(1/3) up to 5.5e-6 deg (the certified
// floor, fan.cert), and --verify checks every triangle against its key; the
// graded mesher gives the same fan (test_graded.cpp compares graded and
// uniform fan meshes on random level sets).
#define BOOST_TEST_MODULE fan_rule
#include <boost/test/unit_test.hpp>

#include <cmath>
#include <cstdlib>
#include <memory>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "certified_stage.hpp"
#include "witness_image.hpp"
#include "warpmesh/certify/certified.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/mesh2d/lattice.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/post/quality.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/mesh2d/uniform.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"

namespace fs = std::filesystem;
using namespace warpmesh;

namespace {

double number(const std::string& j, const std::string& key) {
    const auto at = j.find("\"" + key + "\": ");
    BOOST_REQUIRE(at != std::string::npos);
    return std::stod(j.substr(at + key.size() + 4));
}

// The witness image written into dir, as the level set f = pixel - 30000,
// inside below.
std::unique_ptr<LevelSet> witness_levelset(const fs::path& dir) {
    fs::create_directories(dir);
    const fs::path img = dir / "witness.pgm";
    warpmesh::testing::write_witness_image(img);
    ImageLevelSetOptions o;
    o.iso = 30000;
    o.inside_above = false;
    return make_image_levelset(read_image(img.string()), o);
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
    const auto f = witness_levelset(dir);
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

BOOST_AUTO_TEST_CASE(fan_rule_was_refused_for_several_materials_and_now_certifies_them) {
    // Issue 28: --diagonal fan was refused with materials ("certified for two
    // phases only").  Now the CLI meshes every label of an atlas slice with
    // it, verified, at the fan rule's unconditional floor, junctions included.
    const fs::path dir = fs::temp_directory_path() / ("warpmesh_fan_materials_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const fs::path out = dir / "materials.vtu", report = dir / "materials.json";
    const std::string cmd = std::string(WARPMESH_EXE) + " mesh " + WARPMESH_TEST_DATA +
                            "/abdomen_axial_z024_labels16.pgm --materials all --diagonal fan --verify --quiet -o " +
                            out.string() + " --report " + report.string();
    BOOST_REQUIRE(std::system(cmd.c_str()) == 0);
    BOOST_TEST(fs::exists(out));
    std::ifstream in(report);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string json = ss.str(), cert = json.substr(json.find("\"certified\": {"));
    BOOST_TEST(json.find("\"rule\": \"fan\"") != std::string::npos);
    BOOST_TEST(number(cert, "min_angle_deg") >= 18.4349);
    BOOST_TEST(number(cert, "junction_squares") > 0);
    BOOST_TEST(cert.find("\"verified\": true") != std::string::npos);
    fs::remove_all(dir);
}

// The fan rule with materials (issue 28 item 2).  The witness image's level
// set as two materials — material 1 where f < 0, the background where f > 0
// (phi_1 = f, phi_0 = -f: the interface is f = 0) — and a third material, a
// disc in the image's right part, so that junction squares occur too.  The
// separating rule realises the 15 deg witness; the fan rule takes the fan
// there (one new vertex, one material), keeps every angle >= 18.4349 deg,
// certified and verified with the junction squares, and the graded mesh has
// the same band, fan included.
namespace {
class WitnessMaterials final : public MaterialField {
public:
    explicit WitnessMaterials(std::unique_ptr<LevelSet> f) : f_(std::move(f)) {}
    int count() const override { return 3; }
    std::int32_t tag(int m) const override { return m; }
    std::string name(int m) const override { return m == 0 ? "background" : "material_" + std::to_string(m); }
    Box bounds() const override { return f_->bounds(); }
    bool bounds_are_domain() const override { return true; }
    std::string describe() const override { return "the fan witness as materials"; }
    double phi(int m, double x, double y) const override {
        const double disc = std::hypot(x - 4.9, y - 6.6) - 1.3;  // material 2, over the others
        if (m == 2) return disc;
        const double v = f_->value(x, y) / 10000;
        return std::max(m == 1 ? v : -v, -disc);
    }

private:
    std::unique_ptr<LevelSet> f_;
};
}  // namespace

BOOST_AUTO_TEST_CASE(fan_rule_with_materials_lifts_the_witness_and_its_junctions) {
    const fs::path dir = fs::temp_directory_path() / ("warpmesh_fan_mat_" + std::to_string(::getpid()));
    const WitnessMaterials f(witness_levelset(dir));
    const Lattice lattice = lattice_over(f.bounds(), 1.0);
    using testing::certified, testing::with_keys;
    const auto sep = certified(mesh_materials(f, lattice, {true, DiagonalRule::separating, with_keys}), lattice, DiagonalRule::separating);
    const auto fan = certified(mesh_materials(f, lattice, {true, DiagonalRule::fan, with_keys}), lattice, DiagonalRule::fan);
    BOOST_TEST(sep.certified.min_deg < 15.01);
    BOOST_TEST(compute_quality(sep.mesh).min_angle_deg < 15.01);  // the witness, realised with materials
    BOOST_TEST(fan.junction_squares > 0);
    BOOST_TEST(fan.certified.verified);
    BOOST_TEST(fan.certified.min_deg >= 18.4349);
    BOOST_TEST(compute_quality(fan.mesh).min_angle_deg >= 18.4349);
    BOOST_TEST(fan.mesh.vertices.size() == sep.mesh.vertices.size() + 1);  // one fan centre
    BOOST_TEST(fan.mesh.triangles.size() == sep.mesh.triangles.size() + 2);
    const MeshCheck chk = check_mesh(fan.mesh);
    BOOST_TEST(chk.ok(), (chk.messages.empty() ? "" : chk.messages.front()));
    BOOST_TEST(fan.mesh.interfaces.size() == sep.mesh.interfaces.size());  // the fan is inside material 1
    for (const bool keep : {true, false}) {
        const auto u = certified(mesh_materials(f, lattice, {keep, DiagonalRule::fan, with_keys}), lattice, DiagonalRule::fan);
        const auto g = certified(mesh_materials_graded(f, lattice, {keep, DiagonalRule::fan, with_keys}, 4), lattice, DiagonalRule::fan);
        BOOST_TEST(g.mesh.vertices.size() <= u.mesh.vertices.size());
        BOOST_TEST(check_mesh(g.mesh).ok());
        BOOST_TEST(g.certified.min_deg == u.certified.min_deg);
        BOOST_TEST(g.junction_squares == u.junction_squares);
        BOOST_TEST(g.mesh.interfaces.size() == u.mesh.interfaces.size());
        BOOST_TEST(g.mesh.boundary.size() == u.mesh.boundary.size());
        BOOST_TEST(compute_quality(g.mesh).min_angle_deg >= 18.4349);
    }
    fs::remove_all(dir);
}

// Issue 50: the fan rule is the default (the paper's bound on every input,
// several materials included); before, the default was the separating rule
// and the witness came out at 15 deg with default options.  The rhombic
// lattice, which has no fan rule, defaults to separating; fan is refused there
// only when asked for.
BOOST_AUTO_TEST_CASE(issue50_the_default_rule_is_the_fan_rule_and_separating_on_the_rhombic_lattice) {
    const fs::path dir = fs::temp_directory_path() / ("warpmesh_fan_default_" + std::to_string(::getpid()));
    const auto f = witness_levelset(dir);
    MeshOptions o;  // the defaults
    BOOST_TEST(!o.rule.has_value());
    BOOST_TEST((rule_of(o) == DiagonalRule::fan));
    const MeshResult one = mesh(*f, o);
    BOOST_TEST((one.report.lattice.rule == DiagonalRule::fan));
    BOOST_TEST(one.certified.min_deg >= 18.4349);
    BOOST_TEST(compute_quality(one.mesh).min_angle_deg >= 18.4349);  // the witness square takes its fan
    const WitnessMaterials field(witness_levelset(dir));
    const MeshResult several = mesh(field, o);
    BOOST_TEST((several.report.lattice.rule == DiagonalRule::fan));
    BOOST_TEST(several.certified.min_deg >= 18.4349);
    BOOST_TEST(compute_quality(several.mesh).min_angle_deg >= 18.4349);
    o.lattice = LatticeMetric::rhombic;
    BOOST_TEST((rule_of(o) == DiagonalRule::separating));
    BOOST_TEST((mesh(*f, o).report.lattice.rule == DiagonalRule::separating));
    o.rule = DiagonalRule::fan;
    BOOST_CHECK_THROW(mesh(*f, o), OptionError);
    o.lattice = LatticeMetric::square, o.rule = DiagonalRule::separating;  // by name, as before
    BOOST_TEST(mesh(*f, o).certified.min_deg < 15.01);
    fs::remove_all(dir);
}
