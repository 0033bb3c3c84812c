// Golden 3D meshes: the library's output on a small sphere and on a crop of
// the SPL brain atlas (tests/data/brain_crop22_labels.nrrd, label 26, read by
// the NRRD reader in millimetres), pinned in tests/expected/mesh3d_*.txt.
// The text is the mesh itself, in the mesher's order (vertices numbered by
// lattice position, so the order is part of what is pinned): every vertex in
// shortest round-trip form (equal text means bit-identical doubles), every
// tetrahedron, every boundary face with its tag, and the report's counts and
// measured dihedral extremes.  Each case is pinned under both face rules:
// the default (the Delaunay face rule, `NAME.txt`) and the parity rule
// (`NAME_parity.txt`; its meshes predate the Delaunay rule and have not
// changed since).  A change of the meshes is made on purpose:
//   WARPMESH_REGEN_GOLDEN3D=1 build/tests/test_mesh3d_golden
// rewrites the files; commit the diff with the reason.
#define BOOST_TEST_MODULE mesh3d_golden
#include <charconv>
#include <cstdlib>
#include <optional>

#include "brain_crop.hpp"
#include "support.hpp"
#include "warpmesh/pipeline/mesh3d.hpp"
#include "warpmesh/post/tet_checks.hpp"
#include "warpmesh/io/volume.hpp"

using namespace warpmesh;
using namespace warpmesh::testing;

namespace {

std::string num(double v) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string canonical(const TetMesh& m, const Mesh3dReport& r) {
    std::ostringstream s;
    s << "tets " << r.tets << " vertices " << r.vertices << " boundary " << r.boundary_faces << " cut_points " << r.cut_points
      << " warped " << r.warped << " all_zero_left_out " << r.all_zero_left_out << "\n";
    char angles[96];
    std::snprintf(angles, sizeof angles, "dihedral %.9f %.9f\n", r.quality.min_dihedral_deg, r.quality.max_dihedral_deg);
    s << angles;
    for (const Point3& p : m.vertices) s << "v " << num(p.x) << ' ' << num(p.y) << ' ' << num(p.z) << '\n';
    for (const auto& t : m.tets) s << "t " << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
    for (std::size_t i = 0; i < m.boundary.size(); ++i)
        s << "b " << m.boundary[i][0] << ' ' << m.boundary[i][1] << ' ' << m.boundary[i][2] << ' ' << m.boundary_tag[i] << '\n';
    return s.str();
}

void compare_rule(const std::string& name, const LevelSet3& f, double spacing, std::optional<FaceRule> rule) {
    Mesh3dOptions o;
    o.spacing = spacing;
    if (rule) o.face_rule = *rule;
    o.verify = true;
    const Mesh3dResult res = mesh3d(f, o);
    const TetMesh& m = res.mesh;
    const Mesh3dReport& r = res.report;
    BOOST_TEST(check_tet_mesh(m).ok);
    const std::string text = canonical(m, r);
    const std::string path = std::string(WARPMESH_SOURCE_DIR) + "/tests/expected/" + name + ".txt";
    if (std::getenv("WARPMESH_REGEN_GOLDEN3D")) {
        std::ofstream(path, std::ios::binary) << text;
        BOOST_TEST_MESSAGE("rewrote " << path);
        return;
    }
    const std::string expected = slurp(path);
    if (text == expected) return;
    std::istringstream a(text), b(expected);
    std::string la, lb;
    int line = 1;
    while (std::getline(a, la) && std::getline(b, lb) && la == lb) ++line;
    BOOST_ERROR(name << " differs from " << path << " at line " << line << ": got '" << la << "', expected '" << lb << "'");
}
void compare(const std::string& name, const LevelSet3& f, double spacing) {
    compare_rule(name, f, spacing, std::nullopt);
    compare_rule(name + "_parity", f, spacing, FaceRule::parity);
}

}  // namespace

BOOST_AUTO_TEST_CASE(golden_sphere) { compare("mesh3d_sphere_s03", *parse_shape3("sphere:0.05,-0.02,0.01,1"), 0.3); }

BOOST_AUTO_TEST_CASE(golden_brain_crop_label26) {
    compare("mesh3d_brain_crop22_label26_s15", *brain_crop_levelset(26), 1.5);
}
