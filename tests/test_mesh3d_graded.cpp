// Graded 3D meshes (issue 48): the balanced octree over the BCC lattice
// (mesh3d/graded.hpp, src/mesh3d/graded/octree3.hpp), its templates
// (mesh3d/generic_octree.hpp), --max-size and --grading, through the pipeline.
#define BOOST_TEST_MODULE mesh3d_graded
#include <algorithm>
#include <map>
#include <cmath>
#include <set>
#include <tuple>
#include <utility>

#include "brain_crop.hpp"
#include "support.hpp"
#include "mesh3d/graded/octree3.hpp"
#include "mesh3d/uniform3d.hpp"
#include "warpmesh/certify/bcc_certified.hpp"
#include "warpmesh/mesh3d/graded.hpp"
#include "warpmesh/pipeline/mesh3d.hpp"
#include "warpmesh/pipeline/mesh3d_options.hpp"
#include "warpmesh/post/tet_checks.hpp"

using namespace warpmesh;
using warpmesh::testing::throws_containing;

namespace {

using Triangle = std::array<std::tuple<double, double, double>, 3>;

// The boundary as a set of triangles by their vertices' coordinates (sorted).
std::set<Triangle> boundary_of(const TetMesh& m) {
    std::set<Triangle> s;
    for (const auto& f : m.boundary) {
        Triangle t{};
        for (std::size_t k = 0; k < 3; ++k) {
            const Point3& p = m.vertices[static_cast<std::size_t>(f[k])];
            t[k] = {p.x, p.y, p.z};
        }
        std::sort(t.begin(), t.end());
        s.insert(t);
    }
    return s;
}

// The interfaces as a set of (triangle, its two regions).
std::set<std::pair<Triangle, std::array<std::int32_t, 2>>> interfaces_of(const TetMesh& m) {
    std::set<std::pair<Triangle, std::array<std::int32_t, 2>>> s;
    for (std::size_t i = 0; i < m.interfaces.size(); ++i) {
        Triangle t{};
        for (std::size_t k = 0; k < 3; ++k) {
            const Point3& p = m.vertices[static_cast<std::size_t>(m.interfaces[i][k])];
            t[k] = {p.x, p.y, p.z};
        }
        std::sort(t.begin(), t.end());
        std::array<std::int32_t, 2> r = m.interface_regions[i];
        std::sort(r.begin(), r.end());
        s.insert({t, r});
    }
    return s;
}

double longest_edge_by_hand(const TetMesh& m) {
    double l = 0;
    for (const auto& t : m.tets)
        for (std::size_t i = 0; i < 4; ++i)
            for (std::size_t j = i + 1; j < 4; ++j) {
                const Point3 a = m.vertices[static_cast<std::size_t>(t[i])], b = m.vertices[static_cast<std::size_t>(t[j])];
                l = std::max(l, std::hypot(a.x - b.x, a.y - b.y, a.z - b.z));
            }
    return l;
}

// The uniform and the graded mesh of `in`, both verified; the graded one
// conforming (every tetrahedron positively oriented), with the uniform
// one's boundary triangle for triangle and fewer tetrahedra.
std::pair<Mesh3dResult, Mesh3dResult> uniform_and_graded(const Mesh3dInput& in, Mesh3dOptions o, const std::string& what) {
    o.verify = true;
    Mesh3dResult u = mesh3d(in, o);
    o.graded = true;
    Mesh3dResult g = mesh3d(in, o);
    const TetMeshCheck c = check_tet_mesh(g.mesh);
    BOOST_TEST(c.ok, what << ": " << (c.problems.empty() ? std::string() : c.problems.front()));
    BOOST_TEST(c.inverted == 0, what);
    BOOST_TEST((boundary_of(g.mesh) == boundary_of(u.mesh)), what);
    BOOST_TEST(g.report.tets < u.report.tets, what);
    return {std::move(u), std::move(g)};
}

// A graded mesh against the uniform one at the same spacing: as above, and
// the same volume (the finest band is the uniform lattice's, the inside only
// coarser), the stencils' tetrahedra certified and verified, and the
// report's figures.
void check_against_uniform(const Mesh3dInput& in, const Mesh3dOptions& o, const std::string& what) {
    const auto [u, g] = uniform_and_graded(in, o, what);
    BOOST_TEST(std::abs(g.report.quality.volume - u.report.quality.volume) < 1e-9 * u.report.quality.volume, what);
    BOOST_REQUIRE(g.report.graded.has_value());
    const Graded3Figures& f = *g.report.graded;
    BOOST_TEST(f.template_tets > 0, what);
    BOOST_TEST(f.leaves_per_level.size() >= 2u);
    BOOST_TEST(f.leaves_per_level[1] > 0, what);
    // proofs/bcc_graded.cert: no template below the uniform floor or above its
    // ceiling, so the graded theorem is the uniform one; every tetrahedron verified.
    BOOST_TEST(f.templates_certified);
    BOOST_TEST(f.template_min_deg >= u.report.certified_min_deg);
    BOOST_TEST(f.template_max_deg <= u.report.certified_max_deg);
    BOOST_TEST(g.report.certified);
    BOOST_TEST(g.report.certified_min_deg == u.report.certified_min_deg);
    BOOST_TEST(g.report.certified_max_deg == u.report.certified_max_deg);
    BOOST_TEST(g.report.uncertified_tets == 0);
    BOOST_TEST(g.report.verified);
    BOOST_TEST(g.report.quality.min_dihedral_deg >= std::min(u.report.quality.min_dihedral_deg, 30.0) - 1e-9, what);
    BOOST_TEST(g.report.quality.max_dihedral_deg <= std::max(u.report.quality.max_dihedral_deg, 135.0) + 1e-9, what);
    BOOST_TEST(std::abs(f.longest_edge - longest_edge_by_hand(g.mesh)) < 1e-12);
}

}  // namespace

BOOST_AUTO_TEST_CASE(graded_meshes_conform_and_keep_the_uniform_boundary) {
    Mesh3dOptions o;
    o.spacing = 0.1;
    for (const char* spec : {"sphere:0,0,0,1", "torus:0,0,0,1,0.45", "diff(sphere:0,0,0,1;cylinder:0,0,-2,0,0,2,0.4)"})
        check_against_uniform(Shape3{spec}, o, spec);
    // The bundled crop of the brain atlas, every label as one region, below its voxel size.
    Mesh3dOptions v;
    v.labels = "nonzero";
    v.spacing = 0.6;
    check_against_uniform(VolumeFile{std::string(WARPMESH_TEST_DATA) + "/brain_crop22_labels.nrrd"}, v, "brain crop");
}

// The octree itself: 2:1 balanced across faces and edges, and every active
// background tetrahedron (recounted here from the window's signs) between
// two finest leaves.
BOOST_AUTO_TEST_CASE(octree_is_balanced_and_finest_wherever_a_point_could_warp) {
    const auto f = parse_shape3("union(sphere:-0.4,0,0,0.7;torus:0.3,0,0,0.8,0.25)");
    const Lattice3 L = lattice3_for(*f, 0.05);
    for (const int buffer : {0, 2}) {
        uniform3d::Window w;
        w.grid = uniform3d::Grid::whole(L);
        uniform3d::prepare_window(*f, BccOptions{}, w);
        const graded3::Octree3 t = graded3::build_octree3(w, 30, buffer);
        BOOST_TEST(t.leaves_per_level.size() >= 4u);
        std::int64_t unbalanced = 0, coarse_critical = 0;  // (coarse_critical: active tetrahedra not between finest cubes)
        for (std::int64_t z = 0; z < L.cubes[2]; ++z)
            for (std::int64_t y = 0; y < L.cubes[1]; ++y)
                for (std::int64_t x = 0; x < L.cubes[0]; ++x)
                    for (int dz = -1; dz <= 1; ++dz)
                        for (int dy = -1; dy <= 1; ++dy)
                            for (int dx = -1; dx <= 1; ++dx) {
                                const int n = std::abs(dx) + std::abs(dy) + std::abs(dz);
                                const graded3::Cube q{x + dx, y + dy, z + dz};
                                if (n == 0 || n == 3 || !t.contains(q)) continue;
                                unbalanced += std::abs(t.level_at({x, y, z}) - t.level_at(q)) > 1;
                            }
        // Every active background tetrahedron (a zero vertex, or two of
        // opposite signs, after warping) lies between two finest cubes.
        std::int64_t active = 0;
        for (std::int64_t z = 0; z < L.cubes[2]; ++z)
            for (std::int64_t y = 0; y < L.cubes[1]; ++y)
                for (std::int64_t x = 0; x < L.cubes[0]; ++x)
                    for (int index = 0; index < 12; ++index) {
                        graded3::Cube below{x, y, z};
                        below[static_cast<std::size_t>(index / 4)] -= 1;
                        if (!t.contains(below)) continue;
                        const auto tet = bcc::background_tet({static_cast<int>(2 * x), static_cast<int>(2 * y), static_cast<int>(2 * z)}, index);
                        int lo = 1, hi = -1;
                        for (const bcc::Ivec& q : tet) {
                            const int sg = w.sign[static_cast<std::size_t>(w.grid.index(q))];
                            lo = std::min(lo, sg), hi = std::max(hi, sg);
                        }
                        if (lo == hi && lo != 0) continue;  // one strict sign: whole or nothing
                        ++active;
                        coarse_critical += t.level_at({x, y, z}) != 0 || t.level_at(below) != 0;
                    }
        BOOST_TEST(active > 1000);
        BOOST_TEST(unbalanced == 0);
        BOOST_TEST(coarse_critical == 0);
    }
}

BOOST_AUTO_TEST_CASE(max_size_holds_on_every_tetrahedron) {
    const double s = 0.05;
    Mesh3dOptions o;
    o.spacing = s;
    o.graded = true;
    o.quality = false;
    // The bound is exact for exact coordinates; a level-l leaf's long edges
    // are 2^l s exactly, here up to rounding.
    const auto within = [](double edge, double h) { return edge <= h * (1 + 1e-12); };
    const Mesh3dResult free = mesh3d(Shape3{"sphere:0,0,0,1"}, o);
    BOOST_TEST(!within(longest_edge_by_hand(free.mesh), 4 * s));  // uncapped, it has larger cells
    std::int64_t previous = free.report.tets;
    for (const double h : {7.9 * s, 4 * s, 2.5 * s, 2 * s}) {
        o.max_size = h;
        const Mesh3dResult r = mesh3d(Shape3{"sphere:0,0,0,1"}, o);
        BOOST_TEST(check_tet_mesh(r.mesh).ok);
        BOOST_TEST(within(longest_edge_by_hand(r.mesh), h), "max size " << h << ": " << longest_edge_by_hand(r.mesh));
        BOOST_TEST(r.report.graded->max_size == h);
        BOOST_TEST(r.report.tets >= previous);  // a smaller cap, no fewer tetrahedra
        previous = r.report.tets;
    }
    BOOST_TEST(previous > free.report.tets);
    // Several materials: the cap on every tetrahedron of every material.
    const MaterialShapes3 two{"1=sphere:0,0,0,1;2=sphere:0.1,0,0,0.4"};
    o.max_size.reset();
    BOOST_TEST(!within(longest_edge_by_hand(mesh3d(two, o).mesh), 3.9 * s));  // uncapped: cells of 4 cubes
    o.max_size = 3.9 * s;
    const Mesh3dResult m = mesh3d(two, o);
    BOOST_TEST(check_tet_mesh(m.mesh).ok);
    BOOST_TEST(within(longest_edge_by_hand(m.mesh), 3.9 * s), longest_edge_by_hand(m.mesh));
    o.max_size = 1.99 * s;
    BOOST_TEST(throws_containing<OptionError>([&] { mesh3d(Shape3{"sphere:0,0,0,1"}, o); }, "max_size 0.0995 is below 2 * spacing = 0.1"));
    BOOST_TEST(max_level_for_size(4 * s, s) == 2);
    BOOST_TEST(max_level_for_size(3.99 * s, s) == 1);
}

BOOST_AUTO_TEST_CASE(grading_widens_the_fine_cells) {
    Mesh3dOptions o;
    o.spacing = 0.06;
    o.graded = true;
    o.quality = false;
    const Mesh3dResult two = mesh3d(Shape3{"sphere:0,0,0,1"}, o);
    o.grading = 1.5;
    const Mesh3dResult gentle = mesh3d(Shape3{"sphere:0,0,0,1"}, o);
    BOOST_TEST(check_tet_mesh(gentle.mesh).ok);
    BOOST_TEST(gentle.report.graded->grading_buffer == 2);
    BOOST_TEST(gentle.report.graded->leaves_per_level[0] > two.report.graded->leaves_per_level[0]);
    BOOST_TEST(gentle.report.tets > two.report.tets);
    BOOST_TEST((boundary_of(gentle.mesh) == boundary_of(two.mesh)));
    o.graded = false;
    BOOST_TEST(throws_containing<OptionError>([&] { mesh3d(Shape3{"sphere:0,0,0,1"}, o); }, "grading applies to graded meshes"));
    o.graded = true;
    o.grading = 2.5;
    BOOST_TEST(throws_containing<OptionError>([&] { mesh3d(Shape3{"sphere:0,0,0,1"}, o); }, "grading must be between 1.1 and 2"));
}

namespace {

// The graded mesh of `in` with 1 and with 2 threads: the same tetrahedra,
// regions, boundary and interfaces.
void check_thread_count_changes_nothing(const Mesh3dInput& in, Mesh3dOptions o) {
    o.graded = true;
    o.threads = 1;
    const Mesh3dResult one = mesh3d(in, o);
    o.threads = 2;
    const Mesh3dResult two = mesh3d(in, o);
    BOOST_TEST((one.mesh.tets == two.mesh.tets));
    BOOST_TEST((one.mesh.region == two.mesh.region));
    BOOST_TEST((one.mesh.boundary == two.mesh.boundary));
    BOOST_TEST((one.mesh.interfaces == two.mesh.interfaces));
}

}  // namespace

BOOST_AUTO_TEST_CASE(graded_output_is_identical_for_any_thread_count_and_refuses_blocks) {
    Mesh3dOptions o;
    o.spacing = 0.07;
    check_thread_count_changes_nothing(Shape3{"torus:0,0,0,1,0.4"}, o);
    o.spacing = 0.1;
    check_thread_count_changes_nothing(MaterialShapes3{"1=sphere:0,0,0,1;2=sphere:0.2,0,0,0.5;3=sphere:-0.3,0.1,0,0.4"}, o);
    o.graded = true;
    BOOST_TEST(throws_containing<OptionError>([&] { mesh3d_block(Shape3{"sphere:0,0,0,1"}, o, {{0, 0, 0}, {2, 2, 2}}); },
                                              "not available in blocks"));
}

namespace {

// Several materials (issue 48, item 5): every cube whose 15 points are not
// unwarped and of one material is finest, so the interfaces, the boundary
// and every material's volume are the uniform multi-material mesh's (the
// same finest cells, the inside of each material only coarser); every
// tetrahedron is positively oriented and verified (junctions and two-sided
// stencils against their keys, templates against proofs/bcc_graded.cert),
// and the certified bounds are the uniform theorem's joined to the
// templates'.
void check_materials_against_uniform(const Mesh3dInput& in, const Mesh3dOptions& o, const std::string& what) {
    const auto [u, g] = uniform_and_graded(in, o, what);
    BOOST_TEST((interfaces_of(g.mesh) == interfaces_of(u.mesh)), what);
    BOOST_TEST(!g.mesh.interfaces.empty(), what);
    const std::vector<RegionMeasure> ru = measure_regions3(u.mesh), rg = measure_regions3(g.mesh);
    BOOST_REQUIRE(ru.size() == rg.size());
    for (std::size_t k = 0; k < ru.size(); ++k) {
        BOOST_TEST(rg[k].tag == ru[k].tag);
        BOOST_TEST(std::abs(rg[k].volume - ru[k].volume) < 1e-9 * ru[k].volume, what << " tag " << ru[k].tag);
    }
    BOOST_REQUIRE(g.report.graded.has_value());
    BOOST_REQUIRE(g.report.materials.has_value());
    const Graded3Figures& f = *g.report.graded;
    BOOST_TEST(f.template_tets > 0, what);
    BOOST_TEST(g.report.materials->junction_tets == u.report.materials->junction_tets, what);
    BOOST_TEST(g.report.certified);
    BOOST_TEST(g.report.verified);
    BOOST_TEST(g.report.uncertified_tets == u.report.uncertified_tets);
    BOOST_TEST(g.report.certified_min_deg == std::min(u.report.certified_min_deg, f.template_min_deg));
    BOOST_TEST(g.report.certified_max_deg == std::max(u.report.certified_max_deg, f.template_max_deg));
}

}  // namespace

BOOST_AUTO_TEST_CASE(graded_materials_keep_the_uniform_interfaces_and_volumes) {
    Mesh3dOptions o;
    o.spacing = 0.1;
    check_materials_against_uniform(MaterialShapes3{"1=sphere:0,0,0,1;2=sphere:0,0,0,0.5"}, o, "nested spheres");
    // Junctions: four materials, three boxes and a ball.
    const char* boxes = "1=box:-1,-1,-1,0.03,1,1;2=box:0.03,-1,-1,1,0.013,1;3=box:0.03,0.013,-1,1,1,1;4=sphere:0.03,0.013,0.2,0.4";
    check_materials_against_uniform(MaterialShapes3{boxes}, o, "junctions");
    o.keep_background = true;
    o.spacing = 0.125;
    check_materials_against_uniform(MaterialShapes3{"1=sphere:0,0,0,1;2=sphere:0,0,0,0.5"}, o, "background kept");
    // The bundled crop of the brain atlas, every label its own material.
    Mesh3dOptions v;
    v.materials = "all";
    check_materials_against_uniform(VolumeFile{std::string(WARPMESH_TEST_DATA) + "/brain_crop22_labels.nrrd"}, v, "brain crop");
}

// Relabelling the materials (the same shapes under other tags) changes only
// the regions' tags: the same tetrahedra, the coarse cells where they were.
BOOST_AUTO_TEST_CASE(graded_materials_do_not_depend_on_the_tags) {
    Mesh3dOptions o;
    o.spacing = 0.1;
    o.graded = true;
    const Mesh3dResult a = mesh3d(MaterialShapes3{"1=sphere:0,0,0,1;2=sphere:0.2,0,0,0.5;3=sphere:-0.3,0.1,0,0.4"}, o);
    const Mesh3dResult b = mesh3d(MaterialShapes3{"7=sphere:0,0,0,1;3=sphere:0.2,0,0,0.5;5=sphere:-0.3,0.1,0,0.4"}, o);
    BOOST_TEST((a.mesh.vertices.size() == b.mesh.vertices.size()));
    BOOST_TEST((a.mesh.tets == b.mesh.tets));
    BOOST_TEST((a.report.graded->leaves_per_level == b.report.graded->leaves_per_level));
    const std::map<std::int32_t, std::int32_t> to{{1, 7}, {2, 3}, {3, 5}};
    std::int64_t mismatched = 0;
    for (std::size_t t = 0; t < a.mesh.region.size() && t < b.mesh.region.size(); ++t) mismatched += to.at(a.mesh.region[t]) != b.mesh.region[t];
    BOOST_TEST(mismatched == 0);
    BOOST_TEST((a.mesh.interfaces == b.mesh.interfaces));
}
