// The 3D pipeline with several materials (pipeline/mesh3d.hpp: materials,
// MaterialShapes3, keep_background): the face rule follows the input, the
// options that do not apply are refused by name, the report gives per
// material its tetrahedra, volume and voxels, the interface faces and the
// junctions, certifies every tetrahedron but the junctions' (counted
// uncertified, with the reason), measures the quality without a level set,
// and names lost and misshapen labels in its warnings.
#define BOOST_TEST_MODULE pipeline3d_materials
#include <cmath>
#include <map>
#include <numbers>

#include "support.hpp"
#include "warpmesh/certify/bcc_certified.hpp"
#include "warpmesh/io/volume.hpp"
#include "warpmesh/pipeline/mesh3d.hpp"
#include "warpmesh/pipeline/mesh3d_options.hpp"
#include "warpmesh/post/tet_checks.hpp"
#include "warpmesh/report/report3d.hpp"

using namespace warpmesh;
using namespace warpmesh::testing;

namespace {

const char* nested = "1=sphere:0,0,0,1;2=sphere:0,0,0,0.5";

Mesh3dOptions spaced(double h) {
    Mesh3dOptions o;
    o.spacing = h;
    return o;
}

// The OptionError of f, naming `option`, whose message contains `needle`.
template <class F>
bool option_error(F&& f, const std::string& option, const std::string& needle) {
    try {
        f();
    } catch (const OptionError& e) {
        BOOST_TEST_MESSAGE(e.what());
        return e.option() == option && std::string(e.what()).find(needle) != std::string::npos;
    } catch (const std::exception& e) {
        BOOST_TEST_MESSAGE("not an OptionError: " << e.what());
        return false;
    }
    return false;
}

// A label volume of n^3 voxels (1 mm), every voxel `fill`.
Volume label_volume(int n, int fill = 0) {
    Volume v;
    v.dims = {n, n, n};
    v.values.assign(static_cast<std::size_t>(n) * n * n, fill);
    v.physical = true;
    v.source = "labels";
    return v;
}
double& at(Volume& v, int i, int j, int k) {
    return v.values[static_cast<std::size_t>(i + v.dims[0] * (j + v.dims[1] * k))];
}

const Material3Figures& material(const Mesh3dReport& r, std::int32_t tag) {
    for (const Material3Figures& m : r.materials->materials)
        if (m.tag == tag) return m;
    throw std::runtime_error("no material " + std::to_string(tag));
}

bool warned(const Mesh3dResult& r, const std::string& needle) {
    for (const std::string& w : r.warnings)
        if (w.find(needle) != std::string::npos) return true;
    return false;
}

}  // namespace

BOOST_AUTO_TEST_CASE(the_face_rule_follows_the_input) {
    Mesh3dOptions o;
    BOOST_TEST((o.face_rule_in_use() == default_face_rule));
    BOOST_TEST((o.face_rule_in_use(true) == FaceRule::parity));  // material shapes
    BOOST_TEST(o.alphas_in_use(true).long_num == face_rule_alphas(FaceRule::parity).long_num);
    BOOST_TEST(o.alphas_in_use(true).short_den == face_rule_alphas(FaceRule::parity).short_den);
    o.materials = "all";
    BOOST_TEST((o.face_rule_in_use() == FaceRule::parity));
    o.face_rule = FaceRule::delaunay;
    BOOST_TEST((o.face_rule_in_use() == FaceRule::delaunay));  // given: kept (validate refuses it)
    const Mesh3dResult r = mesh3d(MaterialShapes3{nested}, spaced(0.25));
    BOOST_TEST((r.report.face_rule == FaceRule::parity));
}

BOOST_AUTO_TEST_CASE(nested_spheres_report_each_material_and_are_certified) {
    const Mesh3dResult r = mesh3d(MaterialShapes3{nested}, spaced(0.1));
    const TetMeshCheck c = check_tet_mesh(r.mesh);
    BOOST_TEST(c.ok, (c.problems.empty() ? "" : c.problems.front()));
    const Mesh3dReport& rep = r.report;
    BOOST_REQUIRE(rep.materials.has_value());
    BOOST_TEST(rep.materials->materials.size() == 2u);
    const Material3Figures &shell = material(rep, 1), &core = material(rep, 2);
    BOOST_TEST(shell.name == "material_1");
    BOOST_TEST(shell.tets + core.tets == rep.tets);
    BOOST_TEST(std::abs(shell.volume + core.volume - rep.quality.volume) < 1e-9 * rep.quality.volume);
    const double inner = 4.0 / 3 * std::numbers::pi / 8, whole = 4.0 / 3 * std::numbers::pi;
    BOOST_TEST(std::abs(core.volume - inner) < 0.03 * inner);
    BOOST_TEST(std::abs(shell.volume - (whole - inner)) < 0.03 * whole);
    BOOST_TEST(!shell.reference_volume.has_value());  // analytic: no voxels
    BOOST_TEST(rep.materials->interface_faces == static_cast<std::int64_t>(r.mesh.interfaces.size()));
    BOOST_TEST(rep.materials->interface_faces > 0);
    BOOST_TEST(rep.materials->junction_tets == 0);
    // The parity certificate covers every tetrahedron; the quality is measured without a level set.
    BOOST_TEST(rep.certified);
    BOOST_TEST(rep.certified_tets == rep.tets);
    BOOST_TEST(rep.uncertified_tets == 0);
    BOOST_TEST(rep.uncertified_reason.empty());
    BOOST_TEST(rep.certified_min_deg <= rep.quality.min_dihedral_deg);
    BOOST_TEST(rep.quality.max_dihedral_deg <= rep.certified_max_deg);
    BOOST_TEST(rep.quality.radius_ratio_min > 0);
    BOOST_TEST(std::isnan(rep.quality.boundary_vertex_f_max));
    BOOST_TEST(r.warnings.empty());
    const std::string json = to_json(rep), text = to_text(rep);
    BOOST_TEST(json.find("\"materials\": [{\"tag\": 1, \"name\": \"material_1\", \"tetrahedra\": ") != std::string::npos);
    BOOST_TEST(json.find("\"interface_faces\": " + std::to_string(rep.materials->interface_faces)) != std::string::npos);
    BOOST_TEST(json.find("\"uncertified_reason\": null") != std::string::npos);
    BOOST_TEST(text.find("  2 material_2: " + std::to_string(core.tets) + " tetrahedra") != std::string::npos);
    BOOST_TEST(text.find("face rule: parity") != std::string::npos);
    // The background kept: region 0 as well, covering the lattice.
    Mesh3dOptions keep = spaced(0.25);
    keep.keep_background = true;
    const Mesh3dResult k = mesh3d(MaterialShapes3{nested}, keep);
    BOOST_TEST(k.report.materials->materials.front().tag == 0);
    BOOST_TEST(k.report.materials->materials.front().tets > 0);
}

// Junctions (three or four materials meet) are certified by
// proofs/bcc_junctions.cert where the build has it, and verified; their
// tetrahedra are within the bounds as measured.  Without it they are
// counted uncertified, with the reason.
BOOST_AUTO_TEST_CASE(junction_tetrahedra_are_certified_by_their_own_certificate) {
    Mesh3dOptions o = spaced(0.1);
    o.verify = true;  // every tetrahedron against its key, junctions' included (a violation throws std::logic_error)
    const Mesh3dResult r = mesh3d(
        MaterialShapes3{"1=box:-1,-1,-1,0.03,1,1;2=box:0.03,-1,-1,1,0.013,1;3=box:0.03,0.013,-1,1,1,1;4=sphere:0.03,0.013,0.2,0.4"}, o);
    const Mesh3dReport& rep = r.report;
    BOOST_TEST(rep.verified);
    BOOST_TEST(check_tet_mesh(r.mesh).ok);
    BOOST_TEST(rep.materials->junction_background_tets > 0);
    BOOST_TEST(rep.materials->junction_tets > 0);
    BOOST_TEST(rep.certified);
    const auto theorem = bcc_junction_certified_theorem();
    BOOST_TEST(rep.materials->junctions_certified == theorem.has_value());
    if (theorem) {
        BOOST_TEST(rep.uncertified_tets == 0);
        BOOST_TEST(rep.certified_tets == rep.tets);
        BOOST_TEST(rep.uncertified_reason.empty());
        BOOST_TEST(rep.certified_min_deg == std::min(theorem->min_deg, bcc_claim(FaceRule::parity)->min_deg));
        BOOST_TEST(to_json(rep).find("\"certified\": true, \"certificate\": \"proofs/bcc_junctions.cert\"") != std::string::npos);
        BOOST_TEST(to_text(rep).find("certified by proofs/bcc_junctions.cert") != std::string::npos);
    } else {
        BOOST_TEST(rep.uncertified_tets == rep.materials->junction_tets);
        BOOST_TEST(rep.certified_tets == rep.tets - rep.materials->junction_tets);
        BOOST_TEST(rep.uncertified_reason.find("junction tetrahedra") != std::string::npos);
        BOOST_TEST(warned(r, "are not certified"));
    }
    // Every tetrahedron, junctions and filled all-zero ones included, within the certified bounds.
    BOOST_TEST(rep.materials->all_zero_filled + r.report.all_zero_left_out > 0);
    BOOST_TEST(to_json(rep).find("\"all_zero_filled\": " + std::to_string(rep.materials->all_zero_filled)) != std::string::npos);
    double lo = 180, hi = 0;
    for (std::size_t t = 0; t < r.mesh.tets.size(); ++t) {
        std::array<Point3, 4> p{};
        for (std::size_t k = 0; k < 4; ++k) p[k] = r.mesh.vertices[static_cast<std::size_t>(r.mesh.tets[t][k])];
        for (const double a : dihedral_angles_deg(p)) lo = std::min(lo, a), hi = std::max(hi, a);
    }
    BOOST_TEST_MESSAGE("dihedral angles " << lo << " .. " << hi << " (junctions included)");
    BOOST_TEST(rep.certified_min_deg <= lo);
    BOOST_TEST(hi <= rep.certified_max_deg);
}

// A label volume: voxel counts and their volume per label; a label of one
// voxel is lost and named, a thin plate of more than 1000 voxels loses more
// than 5 % of its volume and is named; the background's voxels never warn.
BOOST_AUTO_TEST_CASE(label_volumes_report_voxels_and_name_lost_and_thin_labels) {
    Volume v = label_volume(40);
    v.spacing = {0.5, 0.5, 0.5};
    for (int k = 4; k < 36; ++k)
        for (int j = 4; j < 36; ++j)
            for (int i = 4; i < 20; ++i) at(v, i, j, k) = 3;  // a block: 16 x 32 x 32
    for (int k = 4; k < 36; ++k)
        for (int j = 4; j < 36; ++j) at(v, 26, j, k) = 8;  // a plate one voxel thick: 1024 voxels
    at(v, 33, 33, 33) = 11;                                 // one voxel
    Mesh3dOptions o;
    o.materials = "all";
    o.spacing = 1.0;  // two voxels
    const Mesh3dResult r = mesh3d(std::cref(v), o);
    const Mesh3dReport& rep = r.report;
    BOOST_TEST(check_tet_mesh(r.mesh).ok);
    BOOST_TEST(*material(rep, 3).voxels == 16 * 32 * 32);
    BOOST_TEST(*material(rep, 3).reference_volume == 16 * 32 * 32 * 0.125);
    BOOST_TEST(std::abs(material(rep, 3).volume / *material(rep, 3).reference_volume - 1) < 0.05);
    BOOST_TEST(*material(rep, 8).voxels == 1024);
    BOOST_TEST(material(rep, 11).tets == 0);
    BOOST_TEST(warned(r, "material 11 (label_11) got no tetrahedron"));
    const Material3Figures& plate = material(rep, 8);
    const bool plate_off = plate.tets > 0 && std::abs(plate.volume / *plate.reference_volume - 1) > 0.05;
    BOOST_TEST((plate_off || plate.tets == 0), "the plate: " << plate.volume << " of " << *plate.reference_volume);
    BOOST_TEST(warned(r, plate.tets == 0 ? "material 8 (label_8) got no tetrahedron" : "material 8 (label_8): the mesh's volume"));
    BOOST_TEST(!warned(r, "material 3 "));
    BOOST_TEST(to_json(rep).find("\"materials_without_tetrahedra\": [" + std::string(plate.tets == 0 ? "8, 11" : "11") + "]") !=
               std::string::npos);
    // Planar interfaces a quarter spacing off lattice planes would be
    // flattened into voids: at twice the voxel size the lattice is centred,
    // and the block and the plate keep their faces with the background.
    BOOST_TEST(rep.materials->all_zero_voids == 0);
    // At the voxel size (the default) a lattice corner sits on a voxel
    // centre (two cubes in from the lattice's corner: voxel 0's, at x = 0),
    // so the voxel interfaces lie on lattice planes: no voids either.
    Mesh3dOptions d;
    d.materials = "3,8";
    const Mesh3dResult at = mesh3d(std::cref(v), d);
    BOOST_TEST(at.lattice.spacing == 0.5);
    BOOST_TEST(at.lattice.origin.x == -2 * 0.5);
    BOOST_TEST(mesh3d(std::cref(v), o).lattice.origin.x != -2 * 1.0);  // twice the voxel size: centred
    BOOST_TEST(at.report.materials->all_zero_voids == 0);
    BOOST_TEST(check_tet_mesh(at.mesh).ok);
    BOOST_TEST(std::abs(material(at.report, 3).volume / *material(at.report, 3).reference_volume - 1) < 0.05);
    // Only some labels: the others join the background; the background kept never warns of its volume.
    o.materials = "3,11";
    o.keep_background = true;
    const Mesh3dResult s = mesh3d(std::cref(v), o);
    BOOST_TEST(s.report.materials->materials.size() == 3u);  // background, 3, 11
    BOOST_TEST(!warned(s, "background"));
    BOOST_TEST(material(s.report, 0).tets > 0);
}

BOOST_AUTO_TEST_CASE(options_that_do_not_apply_to_several_materials_are_refused_by_name) {
    const Volume v = [] {
        Volume w = label_volume(8, 0);
        for (int k = 2; k < 6; ++k) at(w, 3, 3, k) = 2;
        return w;
    }();
    Mesh3dOptions o;
    o.materials = "all";
    o.labels = "2";
    BOOST_TEST(option_error([&] { validate(std::cref(v), o); }, "materials", "excludes labels, iso and inside"));
    o.labels.reset(), o.iso = 1;
    BOOST_TEST(option_error([&] { validate(std::cref(v), o); }, "materials", "excludes labels"));
    o.iso.reset(), o.materials = "2,x";
    BOOST_TEST(option_error([&] { validate(std::cref(v), o); }, "materials", "expects all or a label list"));
    o.materials = "all", o.face_rule = FaceRule::delaunay;
    BOOST_TEST(option_error([&] { validate(std::cref(v), o); }, "face_rule", "face_rule=delaunay is not available with several materials"));
    // keep_background with one region; materials on a shape.
    Mesh3dOptions one = spaced(0.3);
    one.keep_background = true;
    BOOST_TEST(option_error([&] { validate(Shape3{"sphere:0,0,0,1"}, one); }, "background", "applies to several materials"));
    Mesh3dOptions shape = spaced(0.3);
    shape.materials = "all";
    BOOST_TEST(input_error_containing([&] { validate(Shape3{"sphere:0,0,0,1"}, shape); }, "materials apply to volumes"));
    BOOST_TEST(input_error_containing([&] { validate(MaterialShapes3{nested}, shape); }, "materials apply to volumes"));
    // Material shapes need a spacing and take the volume options nowhere.
    BOOST_TEST(input_error_containing([&] { validate(MaterialShapes3{nested}, Mesh3dOptions{}); }, "spacing is required"));
    Mesh3dOptions iso = spaced(0.3);
    iso.iso = 1;
    BOOST_TEST(input_error_containing([&] { validate(MaterialShapes3{nested}, iso); }, "apply to volumes"));
    BOOST_TEST(input_error_containing([&] { mesh3d(MaterialShapes3{"1=sphere:0,0,0,1;1=sphere:0,0,0,2"}, spaced(0.3)); },
                                      "tag 1 is given twice"));
}

// Blocks of several materials through the pipeline: the lattice mesh3d uses,
// and blocks tiling it merge into exactly mesh3d's mesh.
BOOST_AUTO_TEST_CASE(material_blocks_merge_into_the_pipeline_mesh) {
    const std::string nested = "1=sphere:0,0,0,1;2=sphere:0,0,0,0.5";
    const Mesh3dOptions o = spaced(0.3);
    const Mesh3dResult whole = mesh3d(MaterialShapes3{nested}, o);
    const Lattice3 L = lattice3d(MaterialShapes3{nested}, o);
    BOOST_TEST(L.cubes == whole.lattice.cubes);
    BOOST_TEST(L.origin.x == whole.lattice.origin.x);
    const std::int64_t half = L.cubes[0] / 2;
    const std::vector<TetBlock> blocks{mesh3d_block(MaterialShapes3{nested}, o, CubeRange{{0, 0, 0}, {half, L.cubes[1], L.cubes[2]}}),
                                       mesh3d_block(MaterialShapes3{nested}, o, CubeRange{{half, 0, 0}, L.cubes})};
    const Mesh3dResult merged = merge_mesh3d_blocks(blocks);
    bool same = merged.mesh.tets.size() == whole.mesh.tets.size() && merged.mesh.vertices.size() == whole.mesh.vertices.size();
    for (std::size_t t = 0; same && t < whole.mesh.tets.size(); ++t)
        same = merged.mesh.tets[t] == whole.mesh.tets[t] && merged.mesh.region[t] == whole.mesh.region[t];
    BOOST_TEST(same);
    BOOST_TEST(merged.mesh.interfaces.size() == whole.mesh.interfaces.size());
    BOOST_TEST(merged.mesh.region_names.size() == whole.mesh.region_names.size());
    // The merged mesh's report is mesh3d's (its meshing time aside):
    // materials, junctions, certification, quality; here and with
    // junctions, where three balls meet.
    for (const std::string spec : {nested, std::string("1=sphere:0,0,0,1;2=sphere:0.9,0,0,0.6;3=sphere:0.5,0.5,0,0.5")}) {
        const Mesh3dResult one = mesh3d(MaterialShapes3{spec}, o);
        const Lattice3 M = lattice3d(MaterialShapes3{spec}, o);
        const std::int64_t cut = M.cubes[2] / 3;
        const std::vector<TetBlock> parts{mesh3d_block(MaterialShapes3{spec}, o, CubeRange{{0, 0, cut}, M.cubes}),
                                          mesh3d_block(MaterialShapes3{spec}, o, CubeRange{{0, 0, 0}, {M.cubes[0], M.cubes[1], cut}})};
        Mesh3dReport a = merge_mesh3d_blocks(parts).report, b = one.report;
        a.seconds = b.seconds = 0;
        BOOST_TEST(to_json(a) == to_json(b), spec);
        if (spec != nested) BOOST_TEST(a.materials->junction_tets > 0);
    }
}

// The quality without a level set is the quality with one, the boundary's
// fidelity aside; the regions' volumes add up to it.
BOOST_AUTO_TEST_CASE(quality_without_a_level_set_and_region_volumes) {
    const auto f = parse_shape3("torus:0,0,0,1,0.4");
    const Mesh3dResult r = mesh3d(std::cref(*f), spaced(0.1));
    const TetQuality a = measure_quality3(r.mesh, *f), b = measure_quality3(r.mesh);
    BOOST_TEST(a.min_dihedral_deg == b.min_dihedral_deg);
    BOOST_TEST(a.max_dihedral_deg == b.max_dihedral_deg);
    BOOST_TEST(a.volume == b.volume);
    BOOST_TEST((a.radius_ratio_histogram == b.radius_ratio_histogram));
    BOOST_TEST(std::isnan(b.boundary_centroid_f_max));
    BOOST_TEST(a.boundary_vertex_f_max < 1e-6);
    const auto regions = measure_regions3(r.mesh);
    BOOST_TEST(regions.size() == 1u);
    BOOST_TEST(regions.front().tag == 1);
    BOOST_TEST(regions.front().tets == static_cast<std::int64_t>(r.mesh.tets.size()));
    BOOST_TEST(std::abs(regions.front().volume - a.volume) < 1e-12 * a.volume);
}
