// The 3D mesher (mesh3d.hpp): conformity and orientation on every shape and
// on random quadric and RBF level sets, measured dihedral angles inside the
// certified bounds (verify), identical output for any thread count, blocks
// that merge into exactly the whole mesh, label and grey volumes in physical
// units, and the bad inputs (empty region, coarse spacing, memory limit).
#define BOOST_TEST_MODULE mesh3d
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <numbers>
#include <random>

#include "brain_crop.hpp"
#include "support.hpp"
#include "warpmesh/certify/bcc_certified.hpp"
#include "warpmesh/mesh3d/generic_bcc_keys.hpp"
#include "warpmesh/pipeline/mesh3d.hpp"
#include "warpmesh/pipeline/mesh3d_options.hpp"
#include "warpmesh/post/tet_checks.hpp"
#include "mesh3d/uniform3d.hpp"
#include "warpmesh/io/volume.hpp"

using namespace warpmesh;
using namespace warpmesh::testing;

namespace {

// The face of f's domain box (0..5: x = xmin, x = xmax, y = ymin, ...) that
// holds the boundary face's three vertices, or -1.
int domain_face(const LevelSet3& f, const TetMesh& m, const std::array<std::int32_t, 3>& face) {
    const auto d = f.domain();
    if (!d) return -1;
    const std::array<double, 6> plane{d->xmin, d->xmax, d->ymin, d->ymax, d->zmin, d->zmax};
    for (int k = 0; k < 6; ++k) {
        bool all = true;
        for (const std::int32_t v : face) {
            const Point3 p = m.vertices[static_cast<std::size_t>(v)];
            const double x = k < 2 ? p.x : k < 4 ? p.y : p.z;
            all = all && std::abs(x - plane[static_cast<std::size_t>(k)]) <= 1e-9;
        }
        if (all) return k;
    }
    return -1;
}

// A face's area.
double face_area(const TetMesh& m, const std::array<std::int32_t, 3>& face) {
    const Point3 a = m.vertices[static_cast<std::size_t>(face[0])], b = m.vertices[static_cast<std::size_t>(face[1])],
                 c = m.vertices[static_cast<std::size_t>(face[2])];
    const double u[3] = {b.x - a.x, b.y - a.y, b.z - a.z}, w[3] = {c.x - a.x, c.y - a.y, c.z - a.z};
    return 0.5 * std::hypot(u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]);
}

Mesh3dReport mesh_checked(const LevelSet3& f, double spacing, TetMesh* out = nullptr) {
    Mesh3dOptions o;
    o.spacing = spacing;
    o.verify = true;  // throws std::logic_error if a certified tetrahedron leaves the claim
    Mesh3dResult res = mesh3d(f, o);
    const Mesh3dReport r = res.report;
    TetMesh m = std::move(res.mesh);
    const TetMeshCheck c = check_tet_mesh(m);
    BOOST_TEST(c.ok, f.describe() << ": " << (c.problems.empty() ? "" : c.problems.front()));
    BOOST_TEST(r.verified);
    BOOST_TEST(r.tets == static_cast<std::int64_t>(m.tets.size()));
    BOOST_TEST(r.certified_tets == r.tets);  // all-zero background tetrahedra are never output
    BOOST_TEST(r.uncertified_tets == 0);
    BOOST_TEST(r.quality.min_dihedral_deg >= r.certified_min_deg);
    BOOST_TEST(r.quality.max_dihedral_deg <= r.certified_max_deg);
    // Boundary faces on the level set, tagged 1, but where the input's domain
    // (a volume's hull) cut the region off: tagged 2, as 2D tags the image's border.
    for (std::size_t e = 0; e < m.boundary.size(); ++e)
        BOOST_TEST(m.boundary_tag[e] == (domain_face(f, m, m.boundary[e]) >= 0 ? boundary_domain : boundary_level_set));
    BOOST_TEST(r.quality.boundary_vertex_f_max < 1e-9 * std::max(1.0, spacing));
    if (out) *out = std::move(m);
    return r;
}

bool same(const TetMesh& a, const TetMesh& b) {
    if (a.vertices.size() != b.vertices.size() || a.tets.size() != b.tets.size() || a.boundary != b.boundary ||
        a.boundary_tag != b.boundary_tag)
        return false;
    for (std::size_t i = 0; i < a.vertices.size(); ++i)
        if (a.vertices[i].x != b.vertices[i].x || a.vertices[i].y != b.vertices[i].y || a.vertices[i].z != b.vertices[i].z) return false;
    for (std::size_t i = 0; i < a.tets.size(); ++i)
        if (a.tets[i] != b.tets[i] || a.region[i] != b.region[i]) return false;
    return true;
}

// A random quadric x^T A x + b.x − c (an ellipsoid, a hyperboloid or a
// cylinder piece) in the box [−1, 1]³, or a sum of Gaussian bumps minus a
// threshold (RBF): smooth level sets with every kind of local configuration.
std::unique_ptr<LevelSet3> random_level_set(std::mt19937& rng, int kind) {
    std::uniform_real_distribution<double> u(-1, 1);
    const Box3 box{-1, -1, -1, 1, 1, 1};
    if (kind == 0) {
        std::array<double, 10> c{};
        for (double& x : c) x = u(rng);
        c[0] = 1 + std::abs(c[0]);
        return std::make_unique<FunctionLevelSet3>(
            [c](double x, double y, double z) {
                const double q = c[0] * x * x + c[1] * y * y + c[2] * z * z + c[3] * x * y + c[4] * y * z + c[5] * x * z +
                                 0.3 * (c[6] * x + c[7] * y + c[8] * z);
                const double box_f = std::max({std::abs(x), std::abs(y), std::abs(z)}) - 0.9;
                return std::max(q - 0.3 - 0.2 * std::abs(c[9]), box_f);
            },
            box, "quadric");
    }
    std::vector<std::array<double, 4>> bumps(4);
    for (auto& b : bumps) b = {0.25 * u(rng), 0.25 * u(rng), 0.25 * u(rng), 4 + 4 * std::abs(u(rng))};
    return std::make_unique<FunctionLevelSet3>(
        [bumps](double x, double y, double z) {
            double s = 0;
            for (const auto& b : bumps) s += std::exp(-b[3] * ((x - b[0]) * (x - b[0]) + (y - b[1]) * (y - b[1]) + (z - b[2]) * (z - b[2])));
            return 0.5 - s;
        },
        Box3{-1.2, -1.2, -1.2, 1.2, 1.2, 1.2}, "rbf");
}

// The meshing stage's options of the pipeline's.
BccOptions stage(const Mesh3dOptions& o) {
    BccOptions b;
    b.face_rule = o.face_rule_in_use();
    b.alphas = o.alphas_in_use();
    b.threads = o.threads;
    return b;
}

// The lattice's cubes cut in eight blocks at cube indices `cut` (each in
// (0, L.cubes[a])), each meshed on its own (mesh3d_block).
std::vector<TetBlock> eight_blocks(const LevelSet3& f, const Mesh3dOptions& o, const Lattice3& L, const std::array<std::int64_t, 3>& cut) {
    std::vector<TetBlock> blocks;
    for (int b = 0; b < 8; ++b) {
        CubeRange r;
        for (std::size_t a = 0; a < 3; ++a) {
            const bool high = (b >> a) & 1;
            r.lo[a] = high ? cut[a] : 0;
            r.hi[a] = high ? L.cubes[a] : cut[a];
        }
        blocks.push_back(mesh_bcc_block(f, L, stage(o), r));
    }
    return blocks;
}

}  // namespace

BOOST_AUTO_TEST_CASE(shapes_conform_and_stay_within_the_certified_bounds) {
    const char* specs[] = {"sphere:0,0,0,1",
                           "ellipsoid:0.1,0,0,1.2,0.8,0.6",
                           "torus:0,0,0,1,0.4",
                           "box:-1,-0.7,-0.5,1,0.7,0.5",
                           "cylinder:-0.8,-0.3,-0.2,0.8,0.3,0.2,0.5",
                           "union(sphere:-0.5,0,0,0.7;sphere:0.5,0,0,0.7)",
                           "intersect(sphere:0,0,0,1;box:-0.6,-2,-2,0.6,2,2)",
                           "diff(sphere:0,0,0,1;cylinder:0,0,-2,0,0,2,0.4)"};
    for (const char* spec : specs) {
        const auto f = parse_shape3(spec);
        const Mesh3dReport r = mesh_checked(*f, 0.1);
        if (const auto v = f->exact_volume()) BOOST_TEST(std::abs(r.quality.volume - *v) < 0.03 * *v, spec << ": volume " << r.quality.volume << " vs " << *v);
        BOOST_TEST(r.warnings.size() <= 1u);
    }
}

BOOST_AUTO_TEST_CASE(lattice_points_exactly_on_the_level_set) {
    // The box's faces lie on lattice planes at this spacing (the lattice is
    // centred on the box): many points have f = 0 exactly and never move
    // (warp state `stay`, keys with 0s), and edges and corners give zero
    // vertices on three planes.
    const auto f = parse_shape3("box:-1,-1,-1,1,1,1");
    const Mesh3dReport r = mesh_checked(*f, 0.25);
    BOOST_TEST(std::abs(r.quality.volume - 8) < 1e-9, "volume " << r.quality.volume);
}

BOOST_AUTO_TEST_CASE(random_quadrics_and_rbfs_conform_and_verify) {
    std::mt19937 rng(20261203);
    std::int64_t tets = 0, warped = 0;
    const int n = scaled(24);
    for (int i = 0; i < n; ++i) {
        const auto f = random_level_set(rng, i % 2);
        std::uniform_real_distribution<double> s(0.08, 0.16);
        try {
            const Mesh3dReport r = mesh_checked(*f, s(rng));
            tets += r.tets, warped += r.warped;
        } catch (const InputError& e) {  // an empty random region is fine; nothing else is
            BOOST_TEST(std::string(e.what()).find("empty") != std::string::npos, e.what());
        }
    }
    BOOST_TEST(tets > 1000 * n / 2);  // thousands of background configurations
    BOOST_TEST(warped > 100);
}

// The report's quality pass (tet_quality.cpp) takes the angle forms from
// eight cross products and skips √ away from the running extremes: its
// angles are those of bcc::dihedral_forms (the forms the proof bounds) to the
// last bit, its extremes those of every edge evaluated in full, and its
// radius ratio 3 r_in / R_circ the textbook one.
BOOST_AUTO_TEST_CASE(quality_pass_equals_the_angle_forms_at_every_edge) {
    const auto cos_of = [](double dot, double nn) { return nn > 0 ? std::clamp(dot / std::sqrt(nn), -1.0, 1.0) : 1.0; };
    const auto deg = [](double c) { return std::acos(c) * 180 / std::numbers::pi; };
    std::mt19937 rng(30);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int i = 0; i < 2000; ++i) {
        std::array<Point3, 4> p{};
        for (auto& x : p) x = {u(rng), u(rng), u(rng)};
        if (i % 4 == 0) p[3] = {p[0].x + 1e-7 * u(rng), p[1].y, p[2].z};  // near-degenerate shapes too
        const auto f = bcc::dihedral_forms<double>({{{p[0].x, p[0].y, p[0].z}, {p[1].x, p[1].y, p[1].z}, {p[2].x, p[2].y, p[2].z}, {p[3].x, p[3].y, p[3].z}}});
        const std::array<double, 6> a = dihedral_angles_deg(p);
        for (std::size_t k = 0; k < 6; ++k) BOOST_TEST(a[k] == deg(cos_of(f.dot[k], f.nn[k])));
        // r_in = 3V / (sum of face areas); R_circ from the circumcentre c, solving 2 (p_i − p_0)·c = |p_i|² − |p_0|².
        const auto sub = [](const Point3& x, const Point3& y) { return bcc::Vec<double>{x.x - y.x, x.y - y.y, x.z - y.z}; };
        const auto len = [](const bcc::Vec<double>& v) { return std::sqrt(bcc::dot(v, v)); };
        const bcc::Vec<double> e1 = sub(p[1], p[0]), e2 = sub(p[2], p[0]), e3 = sub(p[3], p[0]);
        const double det = bcc::dot(e1, bcc::cross(e2, e3));
        if (!(det > 1e-3)) {
            if (det <= 0) BOOST_TEST(radius_ratio(p) == 0.0);
            continue;
        }
        const double area = 0.5 * (len(bcc::cross(e1, e2)) + len(bcc::cross(e1, e3)) + len(bcc::cross(e2, e3)) +
                                    len(bcc::cross(sub(p[2], p[1]), sub(p[3], p[1]))));
        const bcc::Vec<double> rhs{0.5 * bcc::dot(e1, e1), 0.5 * bcc::dot(e2, e2), 0.5 * bcc::dot(e3, e3)};  // c relative to p0
        const auto c23 = bcc::cross(e2, e3), c31 = bcc::cross(e3, e1), c12 = bcc::cross(e1, e2);
        const bcc::Vec<double> c{(rhs[0] * c23[0] + rhs[1] * c31[0] + rhs[2] * c12[0]) / det, (rhs[0] * c23[1] + rhs[1] * c31[1] + rhs[2] * c12[1]) / det,
                                 (rhs[0] * c23[2] + rhs[1] * c31[2] + rhs[2] * c12[2]) / det};
        const double expected = 3 * (det / 2 / area) / len(c);
        BOOST_TEST(radius_ratio(p) == std::min(1.0, expected), boost::test_tools::tolerance(1e-9));
    }
    const char* specs[] = {"sphere:0.05,-0.02,0.01,1", "box:0,0,0,1,1,1", "torus:0,0,0,1,0.4"};
    for (const char* spec : specs) {
        Mesh3dOptions o;
        o.spacing = 0.1;
        const Mesh3dResult res = mesh3d(*parse_shape3(spec), o);
        const Mesh3dReport& r = res.report;
        const TetMesh& m = res.mesh;
        double cmax = -1, cmin = 1;
        for (const auto& t : m.tets) {
            std::array<bcc::Vec<double>, 4> q{};
            for (std::size_t k = 0; k < 4; ++k) {
                const Point3& x = m.vertices[static_cast<std::size_t>(t[k])];
                q[k] = {x.x, x.y, x.z};
            }
            const auto f = bcc::dihedral_forms<double>(q);
            for (std::size_t k = 0; k < 6; ++k) cmax = std::max(cmax, cos_of(f.dot[k], f.nn[k])), cmin = std::min(cmin, cos_of(f.dot[k], f.nn[k]));
        }
        BOOST_TEST(r.quality.min_dihedral_deg == deg(cmax), spec);
        BOOST_TEST(r.quality.max_dihedral_deg == deg(cmin), spec);
    }
}

// Stage 3's cut edges (found a row at a time with index steps) are the
// forward lattice edges inside the window whose endpoints have strictly
// opposite signs, in windows that start away from the lattice's origin too.
BOOST_AUTO_TEST_CASE(cut_edges_are_the_sign_changes_inside_the_window) {
    using namespace uniform3d;
    Lattice3 L;
    L.spacing = 0.1;
    L.cubes = {9, 7, 8};
    const FunctionLevelSet3 f([](double x, double y, double z) { return x + 0.3 * y - 0.2 * z - 0.4; }, {0, 0, 0, 1, 1, 1});
    std::mt19937 rng(3);
    for (const auto& [lo, hi] : {std::pair<bcc::Ivec, bcc::Ivec>{{0, 0, 0}, {18, 14, 16}}, {{2, 4, 2}, {12, 10, 14}}, {{4, 0, 6}, {6, 14, 8}}}) {
        Window w;
        w.grid = Grid::window(L, lo, hi);
        const std::size_t n = static_cast<std::size_t>(w.grid.count());
        w.sign.resize(n), w.value.resize(n);
        for (std::size_t p = 0; p < n; ++p) {
            w.sign[p] = static_cast<std::int8_t>(static_cast<int>(rng() % 3) - 1);
            w.value[p] = w.sign[p];
        }
        find_cuts(f, w);
        for (std::int64_t p = 0; p < w.grid.count(); ++p) {
            const bcc::Ivec q = w.grid.point(p);
            unsigned expected = 0;
            for (int s = 0; s < 7; ++s) {
                const bcc::Ivec r = bcc::add(q, bcc::neighbour_offsets[static_cast<std::size_t>(forward_direction[static_cast<std::size_t>(s)])]);
                if (w.grid.contains(r) && w.sign[static_cast<std::size_t>(p)] * w.sign[static_cast<std::size_t>(w.grid.index(r))] < 0) expected |= 1u << s;
            }
            BOOST_TEST(w.cut_mask[static_cast<std::size_t>(p)] == expected, "point " << q[0] << "," << q[1] << "," << q[2]);
        }
    }
}

BOOST_AUTO_TEST_CASE(output_is_identical_for_any_thread_count) {
    const auto f = parse_shape3("union(torus:0,0,0,1,0.35;sphere:0.3,0.2,0.1,0.6)");
    Mesh3dOptions o;
    o.spacing = 0.09;
    o.threads = 1;
    const TetMesh one = mesh3d(*f, o).mesh;
    o.threads = 2;
    const TetMesh two = mesh3d(*f, o).mesh;
    // Three threads: slabs split unevenly, more threads than the CI's two
    // cores.  (Not five: LLVM 14's OpenMP runtime leaks its thread table when
    // a team grows past its initial capacity, which LeakSanitizer reports.)
    o.threads = 3;
    const TetMesh three = mesh3d(*f, o).mesh;
    BOOST_TEST(same(one, two));
    BOOST_TEST(same(one, three));
}

BOOST_AUTO_TEST_CASE(blocks_merge_into_exactly_the_whole_mesh) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < scaled(4); ++trial) {
        const auto f = random_level_set(rng, trial % 2);
        Mesh3dOptions o;
        o.spacing = 0.11;
        const Lattice3 L = lattice3d(*f, o);
        TetMesh whole;
        try {
            whole = mesh3d(*f, o).mesh;
        } catch (const InputError&) {
            continue;
        }
        // Cut every axis at a random place (uneven blocks, some thin).
        std::array<std::int64_t, 3> cut{};
        for (std::size_t a = 0; a < 3; ++a) cut[a] = std::uniform_int_distribution<std::int64_t>(1, L.cubes[a] - 1)(rng);
        std::vector<TetBlock> blocks = eight_blocks(*f, o, L, cut);
        std::shuffle(blocks.begin(), blocks.end(), rng);
        const TetMesh merged = merge_tet_blocks(blocks);
        BOOST_TEST(same(merged, whole), "trial " << trial);
    }
}

namespace {

// The report of a mesh as JSON, its meshing time left out (the merge's is 0).
std::string report_json(Mesh3dReport r) {
    r.seconds = 0;
    return to_json(r);
}

// A random partition of the box [0, n): 0 to 2 random cuts along every axis.
std::vector<CubeRange> random_partition(const std::array<std::int64_t, 3>& n, std::mt19937& rng) {
    std::array<std::vector<std::int64_t>, 3> cuts;
    for (std::size_t a = 0; a < 3; ++a) {
        std::set<std::int64_t> c{0, n[a]};
        const int k = std::uniform_int_distribution<int>(0, 2)(rng);
        for (int i = 0; i < k; ++i) c.insert(std::uniform_int_distribution<std::int64_t>(1, n[a] - 1)(rng));
        cuts[a].assign(c.begin(), c.end());
    }
    std::vector<CubeRange> out;
    for (std::size_t z = 0; z + 1 < cuts[2].size(); ++z)
        for (std::size_t y = 0; y + 1 < cuts[1].size(); ++y)
            for (std::size_t x = 0; x + 1 < cuts[0].size(); ++x)
                out.push_back({{cuts[0][x], cuts[1][y], cuts[2][z]}, {cuts[0][x + 1], cuts[1][y + 1], cuts[2][z + 1]}});
    return out;
}

}  // namespace

// Issue 49 (a merge that cannot lose a piece): a random partition's blocks
// merge into mesh3d's mesh and report (face rule, certified bounds and
// counts, volume, dihedral extremes, non-manifold counts, boundary
// fidelity); with any block dropped, given twice or shifted by a cube the
// merge is refused, naming what is wrong; so are an empty list and blocks of
// another spacing, face rule or input.
BOOST_AUTO_TEST_CASE(merge_refuses_a_lost_repeated_or_shifted_block_and_reports_as_mesh3d) {
    std::mt19937 rng(49);
    const auto torus = parse_shape3("torus:0,0,0,1,0.4");
    for (int trial = 0; trial < scaled(3); ++trial) {
        Mesh3dOptions o;
        o.spacing = 0.17;
        if (trial == 1) o.face_rule = FaceRule::parity;
        const Mesh3dResult whole = mesh3d(*torus, o);
        const Lattice3 L = lattice3d(*torus, o);
        std::vector<CubeRange> ranges;
        while (ranges.size() < 2) ranges = random_partition(L.cubes, rng);
        std::vector<TetBlock> blocks;
        for (const CubeRange& r : ranges) blocks.push_back(mesh3d_block(*torus, o, r));
        std::shuffle(blocks.begin(), blocks.end(), rng);
        const Mesh3dResult merged = merge_mesh3d_blocks(blocks);
        BOOST_TEST(same(merged.mesh, whole.mesh), "trial " << trial);
        BOOST_TEST(report_json(merged.report) == report_json(whole.report), "trial " << trial);
        BOOST_TEST(merged.report.quality.volume > 0);
        BOOST_TEST(merged.report.certified);
        BOOST_TEST(merged.warnings == whole.warnings);

        const std::size_t k = std::uniform_int_distribution<std::size_t>(0, blocks.size() - 1)(rng);
        std::vector<TetBlock> dropped = blocks;
        dropped.erase(dropped.begin() + static_cast<std::ptrdiff_t>(k));
        BOOST_TEST(input_error_containing([&] { merge_mesh3d_blocks(dropped); }, "are in no block"));
        std::vector<TetBlock> twice = blocks;
        twice.push_back(blocks[k]);
        BOOST_TEST(input_error_containing([&] { merge_mesh3d_blocks(twice); }, "given twice"));
        // Shifted by one cube along an axis where it fits in the lattice.
        CubeRange r = blocks[k].range;
        std::size_t a = 0;
        while (r.hi[a] == L.cubes[a] && r.lo[a] == 0) ++a;
        const std::int64_t step = r.hi[a] < L.cubes[a] ? 1 : -1;
        r.lo[a] += step, r.hi[a] += step;
        std::vector<TetBlock> shifted = blocks;
        shifted[k] = mesh3d_block(*torus, o, r);
        BOOST_TEST(input_error_containing([&] { merge_mesh3d_blocks(shifted); }, "overlap in the cubes"));
    }
    BOOST_TEST(input_error_containing([&] { merge_mesh3d_blocks({}); }, "no blocks to merge"));
    Mesh3dOptions o;
    o.spacing = 0.17;
    const Lattice3 L = lattice3d(*torus, o);
    const std::int64_t half = L.cubes[0] / 2;
    const CubeRange left{{0, 0, 0}, {half, L.cubes[1], L.cubes[2]}}, right{{half, 0, 0}, L.cubes};
    // Another face rule, another spacing, another shape on the same lattice.
    Mesh3dOptions parity = o;
    parity.face_rule = FaceRule::parity;
    BOOST_TEST(input_error_containing([&] { merge_mesh3d_blocks(std::vector{mesh3d_block(*torus, o, left), mesh3d_block(*torus, parity, right)}); },
                                      "face rules parity and delaunay"));
    Mesh3dOptions finer = o;
    finer.spacing = 0.16;
    BOOST_TEST(input_error_containing([&] { merge_mesh3d_blocks(std::vector{mesh3d_block(*torus, o, left), mesh3d_block(*torus, finer, right)}); },
                                      "different meshes: lattices spacing 0.16"));
    const auto thinner = parse_shape3("torus:0,0,0,1,0.39");
    BOOST_TEST(lattice3d(*thinner, o).cubes == L.cubes);
    BOOST_TEST(input_error_containing([&] { merge_mesh3d_blocks(std::vector{mesh3d_block(*torus, o, left), mesh3d_block(*thinner, o, right)}); },
                                      "different inputs"));
    // The stage's merge makes the same checks (blocks not from the pipeline).
    const std::vector<TetBlock> one{mesh_bcc_block(*torus, L, stage(o), left)};
    BOOST_TEST(throws_containing<std::invalid_argument>([&] { merge_tet_blocks(one); }, "the cubes [(" + std::to_string(half)));
}

namespace {

// A physical volume of `dims` voxels of `spacing` mm at `origin`, its index
// axes permuted and flipped (i along +y, j along −x, k along +z); values 0.
Volume oriented_volume(const std::array<std::int64_t, 3>& dims, const Vec3& spacing, const Vec3& origin, const std::string& source) {
    Volume v;
    v.dims = dims, v.spacing = spacing, v.origin = origin;
    v.axes = {{{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}}};
    v.physical = true;
    v.source = source;
    v.values.resize(static_cast<std::size_t>(v.voxel_count()));
    return v;
}

// The voxels [box[0], box[1]) (i, j, k) of v as a part of it (Volume::is_part).
Volume part_of(const Volume& v, const std::array<std::array<std::int64_t, 3>, 2>& box) {
    Volume p;
    p.spacing = v.spacing, p.origin = v.origin, p.axes = v.axes, p.physical = v.physical, p.source = v.source;
    p.part_offset = box[0], p.whole_dims = v.dims;
    for (std::size_t a = 0; a < 3; ++a) p.dims[a] = box[1][a] - box[0][a];
    p.values.resize(static_cast<std::size_t>(p.voxel_count()));
    for (std::int64_t k = 0, q = 0; k < p.dims[2]; ++k)
        for (std::int64_t j = 0; j < p.dims[1]; ++j)
            for (std::int64_t i = 0; i < p.dims[0]; ++i, ++q)
                p.values[static_cast<std::size_t>(q)] = v.at(box[0][0] + i, box[0][1] + j, box[0][2] + k);
    return p;
}

// The block r from its part alone: the voxels block_voxels names, read again
// with twice the halo while the part is too small (mesh3d_block_read's loop).
TetBlock block_of_part(const Volume& v, const Mesh3dOptions& o, const CubeRange& r, const LabelRegionFacts& region, std::int64_t& least) {
    const Volume geometry = part_of(v, {{{0, 0, 0}, {1, 1, 1}}});
    for (std::int64_t halo = 2;; halo *= 2) {
        const Volume part = part_of(v, block_voxels(std::cref(geometry), o, r, halo, &region));
        try {
            TetBlock b = mesh3d_block(std::cref(part), o, r, &region);
            least = std::min(least, part.voxel_count());
            return b;
        } catch (const InputError& e) {
            if (std::string(e.what()).find("too small") == std::string::npos || halo > 64) throw;
        }
    }
}

}  // namespace

// Issue 49, item 1, one region: blocks that each read only their part of a
// label volume (block_voxels) merge into exactly mesh3d's mesh and report,
// given the whole region's facts from a reduction over a random tiling of
// the volume (region_part_voxels, region_part_facts, merge_region_facts).
// The volume has a sheet two voxels thick (the field's minimum is above
// −cap: cut_parameter's switch between the cubic path and the root finder
// moves with it), a region against the volume's edge, anisotropic voxels
// (the band's voxels beyond the region's box are within cap) and a flipped,
// permuted orientation.  Refused: a part without the facts, a part's own
// facts, facts of another band, a tiling with a part lost or repeated, a
// part too small for the facts it gives.
BOOST_AUTO_TEST_CASE(one_region_blocks_that_read_only_their_part_merge_into_the_whole_mesh) {
    Volume v = oriented_volume({26, 22, 18}, {1.0, 0.8, 1.3}, {4, -5, 3}, "parts.nrrd");
    for (std::int64_t k = 0, q = 0; k < 18; ++k)
        for (std::int64_t j = 0; j < 22; ++j)
            for (std::int64_t i = 0; i < 26; ++i, ++q) {
                const double x = (i - 17) * 1.0, y = (j - 11) * 0.8, z = (k - 8) * 1.3;
                const bool sheet = (i == 7 || i == 8) && j > 3 && j < 19 && k > 2 && k < 16;
                v.values[static_cast<std::size_t>(q)] = sheet ? 3 : x * x + y * y + z * z < 30 ? 5 : (k < 2 && i > 12 ? 3 : 0);
            }
    Mesh3dOptions o;
    o.labels = "3,5";
    o.spacing = 1.1;
    const Mesh3dResult whole = mesh3d(std::cref(v), o);
    const Volume geometry = part_of(v, {{{0, 0, 0}, {1, 1, 1}}});
    std::mt19937 rng(491);
    for (int trial = 0; trial < scaled(2); ++trial) {
        std::vector<LabelRegionFacts> facts;
        std::vector<CubeRange> tiling;
        while (tiling.size() < 2) tiling = random_partition(v.dims, rng);
        for (const CubeRange& own : tiling) {
            const Volume part = part_of(v, region_part_voxels(std::cref(geometry), o, {own.lo, own.hi}));
            facts.push_back(region_part_facts(std::cref(part), o, {own.lo, own.hi}));
        }
        std::shuffle(facts.begin(), facts.end(), rng);
        const LabelRegionFacts region = merge_region_facts(facts);
        const Lattice3 L = lattice3d(std::cref(geometry), o, &region);
        BOOST_TEST(L.cubes == whole.lattice.cubes);
        std::vector<TetBlock> blocks;
        std::int64_t least = v.voxel_count();
        for (const CubeRange& r : random_partition(L.cubes, rng)) blocks.push_back(block_of_part(v, o, r, region, least));
        const Mesh3dResult merged = merge_mesh3d_blocks(blocks);
        BOOST_TEST(same(merged.mesh, whole.mesh), "trial " << trial);
        BOOST_TEST(report_json(merged.report) == report_json(whole.report), "trial " << trial);
        BOOST_TEST(merged.warnings == whole.warnings);
        // Lost and repeated parts of the reduction.
        std::vector<LabelRegionFacts> lost(facts.begin() + 1, facts.end()), twice = facts;
        twice.push_back(facts.back());
        BOOST_TEST(input_error_containing([&] { merge_region_facts(lost); }, "a part is missing"));
        BOOST_TEST(input_error_containing([&] { merge_region_facts(twice); }, "or a part is given twice"));
        BOOST_TEST(input_error_containing([&] { mesh3d_block(std::cref(geometry), o, {{0, 0, 0}, {1, 1, 1}}, &facts[0]); },
                                          "merge the parts' facts first"));
    }
    const Volume half = part_of(v, {{{0, 0, 0}, {13, 22, 18}}});
    BOOST_TEST(input_error_containing([&] { mesh3d_block(std::cref(half), o, {{0, 0, 0}, {2, 2, 2}}); }, "needs the whole region's facts"));
    BOOST_TEST(input_error_containing([&] { region_part_facts(std::cref(half), o, {{{0, 0, 0}, {13, 22, 18}}}); },
                                      "does not hold the voxels within"));
    Mesh3dOptions wider = o;
    wider.band = 5;
    const LabelRegionFacts region = merge_region_facts(std::vector{region_part_facts(std::cref(v), o, {{{0, 0, 0}, v.dims}})});
    BOOST_TEST(input_error_containing([&] { mesh3d_block(std::cref(half), wider, {{0, 0, 0}, {2, 2, 2}}, &region); }, "band 4"));
    BOOST_TEST(input_error_containing([&] { mesh3d_block(std::cref(v), o, {{0, 0, 0}, {2, 2, 2}}, &region); }, "apply to a part"));
    // The field's minimum carried, not −cap (what a rule independent of the
    // data would take): −cap moves cut points of the thin sheet.
    LabelRegionFacts capped = region;
    capped.lowest = -4 * 1.3;
    const std::array<std::int64_t, 3> L{whole.lattice.cubes};
    std::vector<TetBlock> blocks;
    std::int64_t least = v.voxel_count();
    const std::int64_t cut = whole.lattice.cubes[0] / 4;
    for (const CubeRange& r : {CubeRange{{0, 0, 0}, {cut, L[1], L[2]}}, CubeRange{{cut, 0, 0}, L}})
        blocks.push_back(block_of_part(v, o, r, capped, least));
    BOOST_TEST(!same(merge_mesh3d_blocks(blocks).mesh, whole.mesh));
    BOOST_TEST(least < v.voxel_count());  // the first block read a part
}

BOOST_AUTO_TEST_CASE(label_volume_in_physical_units) {
    // A ball of label 3 (radius 6 mm) and a slab of label 5 in a 24 x 20 x 16
    // volume with anisotropic spacing and a flipped, permuted orientation.
    Volume v = oriented_volume({24, 20, 16}, {1.0, 1.25, 1.5}, {10, -5, 3}, "ball.nrrd");
    for (std::int64_t k = 0; k < 16; ++k)
        for (std::int64_t j = 0; j < 20; ++j)
            for (std::int64_t i = 0; i < 24; ++i) {
                const double x = (i - 11.5) * 1.0, y = (j - 9.5) * 1.25, z = (k - 7.5) * 1.5;
                v.values[static_cast<std::size_t>(i + 24 * (j + 20 * k))] = x * x + y * y + z * z < 36 ? 3 : (k < 2 ? 5 : 0);
            }
    VolumeLevelSet3Options lo;
    lo.mode.mode = ImageMode::label;
    lo.mode.labels = {3};
    const auto ball = make_volume_levelset3(v, lo);
    TetMesh m;
    const Mesh3dReport r = mesh_checked(*ball, 0.8, &m);
    const double exact = 4.0 / 3.0 * std::numbers::pi * 216;
    BOOST_TEST(std::abs(r.quality.volume - exact) < 0.15 * exact, "volume " << r.quality.volume);
    // The ball's centre in physical coordinates: origin + 11.5 a0 + 9.5 * 1.25 a1 + 7.5 * 1.5 a2.
    Point3 c{0, 0, 0};
    for (const Point3& p : m.vertices) c = {c.x + p.x, c.y + p.y, c.z + p.z};
    const double n = static_cast<double>(m.vertices.size());
    BOOST_TEST(std::abs(c.x / n - (10 - 9.5 * 1.25)) < 0.3);
    BOOST_TEST(std::abs(c.y / n - (-5 + 11.5)) < 0.3);
    BOOST_TEST(std::abs(c.z / n - (3 + 7.5 * 1.5)) < 0.3);
    // Label 5 fills the two lowest voxel layers, up to the volume's edge: the
    // region is closed at the voxel centres' hull, whose faces are tagged
    // boundary_domain (issue 50: they were tagged boundary_level_set, while 2D
    // tags the image's border domain_border), every other face level set
    // (mesh_checked).  The hull's face z = 3 under the slab is covered, but
    // for the rim where the slab's level set meets it: the hull is 23 mm (y)
    // by 23.75 mm (x).
    lo.mode.labels = {5};
    const auto slab = make_volume_levelset3(v, lo);
    TetMesh s;
    mesh_checked(*slab, 0.6, &s);
    std::array<double, 6> area{};
    for (std::size_t e = 0; e < s.boundary.size(); ++e)
        if (const int k = domain_face(*slab, s, s.boundary[e]); k >= 0) area[static_cast<std::size_t>(k)] += face_area(s, s.boundary[e]);
    BOOST_TEST(area[4] > 0.9 * 23 * 23.75, "z = 3: " << area[4]);
    BOOST_TEST(area[4] <= 23 * 23.75);
    BOOST_TEST(area[5] == 0);  // the slab's top is inside the volume
    for (std::size_t k = 0; k < 4; ++k) BOOST_TEST(area[k] > 0);  // its sides reach the volume's sides
    lo.mode.labels = {9};
    BOOST_TEST(throws_containing([&] { make_volume_levelset3(v, lo); }, "the region is empty"));
    // Issue 50: a listed label absent from the volume was ignored when
    // another label filled the region (--label 3,9 meshed label 3 alone).
    lo.mode.labels = {3, 9};
    BOOST_TEST(throws_containing([&] { make_volume_levelset3(v, lo); }, "no voxel has the label(s) 9 (of 3,9)"));
    // Grey mode: the same ball as values 0..100, inside above 50.
    for (double& x : v.values) x = x == 3 ? 100 : 0;
    VolumeLevelSet3Options go;
    go.mode.iso = 50;
    const auto grey = make_volume_levelset3(v, go);
    const Mesh3dReport g = mesh_checked(*grey, 0.8);
    BOOST_TEST(std::abs(g.quality.volume - exact) < 0.2 * exact, "volume " << g.quality.volume);
}

// Volume cut points solve the trilinear interpolant's cubic per voxel cell
// (volume_levelset3.cpp): each is a zero of f, and where an edge crosses the
// level set several times, the one in the first cell (from the edge's lower
// endpoint) where f changes sign.
BOOST_AUTO_TEST_CASE(volume_cut_point_is_a_zero_in_the_first_cell_where_f_changes_sign) {
    // Label 1 in the slabs i = 1..11 and i = 14, 15 of a 24 x 12 x 12 volume:
    // along x, f's zeros are at the midpoints 11.5, 13.5, 15.5 (f antisymmetric
    // about them, the spacing being the same on every axis).
    Volume v;
    v.dims = {24, 12, 12};
    v.values.assign(static_cast<std::size_t>(v.voxel_count()), 0);
    for (std::int64_t k = 0; k < 12; ++k)
        for (std::int64_t j = 0; j < 12; ++j)
            for (std::int64_t i = 0; i < 24; ++i)
                if ((i >= 1 && i <= 11) || i == 14 || i == 15) v.values[static_cast<std::size_t>(i + 24 * (j + 12 * k))] = 1;
    v.source = "slabs";
    VolumeLevelSet3Options o;
    o.mode.mode = ImageMode::label;
    o.mode.labels = {1};
    const auto f = make_volume_levelset3(v, o);
    // From deep in the first slab (x = 6, f = −4) to just past the second (x =
    // 16.75, f = 1.25), at y = 5.3, z = 6.1, away from the hull: three zeros,
    // 11.5 first (regula falsi on f alone, whose first step lands in the second
    // slab, reached 15.5).
    const Point3 a{6, 5.3, 6.1}, b{16.75, 5.3, 6.1};
    const double fa = f->value(a.x, a.y, a.z), fb = f->value(b.x, b.y, b.z);
    BOOST_REQUIRE(fa < 0);
    BOOST_REQUIRE(fb > 0);
    BOOST_TEST(std::abs(a.x + f->cut_parameter(a, b, fa, fb) * (b.x - a.x) - 11.5) < 1e-12);
    // Random segments in a random label volume and a grey one: every cut
    // parameter lies in (0, 1) and is a zero of f, also near the hull (the
    // generic root finder there).
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(0, 1);
    for (double& x : v.values) x = u(rng) < 0.4 ? 1 : 0;
    v.spacing = {1.0, 0.8, 1.3};
    for (int mode = 0; mode < 2; ++mode) {
        VolumeLevelSet3Options m;
        if (mode == 0) m = o;
        else m.mode.iso = 0.5;
        const auto g = make_volume_levelset3(v, m);
        int cut = 0;
        for (int trial = 0; trial < scaled(4000); ++trial) {
            const Point3 p{23 * u(rng), 11 * 0.8 * u(rng), 11 * 1.3 * u(rng)};
            const Point3 q{p.x + 6 * (u(rng) - 0.5), p.y + 6 * (u(rng) - 0.5), p.z + 6 * (u(rng) - 0.5)};
            const double gp = g->value(p.x, p.y, p.z), gq = g->value(q.x, q.y, q.z);
            if (!(gp * gq < 0)) continue;
            ++cut;
            const double t = g->cut_parameter(p, q, gp, gq);
            BOOST_TEST((t > 0 && t < 1));
            const double at = g->value(p.x + t * (q.x - p.x), p.y + t * (q.y - p.y), p.z + t * (q.z - p.z));
            BOOST_TEST(std::abs(at) < 1e-12 * (mode == 0 ? 1 : 100), "f = " << at << " at the cut point, mode " << mode);
        }
        BOOST_TEST(cut > scaled(4000) / 10);
    }
}

// The label distance field's transforms start from the region's surface
// voxels only and drop distances beyond the band (volume_levelset3.cpp): at
// every voxel centre the field must still be the signed distance to the
// nearest voxel centre of the other class, minus half the smallest spacing,
// clamped to the band — here against brute force, with anisotropic spacing.
BOOST_AUTO_TEST_CASE(label_distance_field_is_the_clamped_signed_distance) {
    Volume v;
    v.dims = {22, 20, 18};
    v.spacing = {1.0, 0.8, 1.3};
    v.source = "blobs";
    v.values.assign(static_cast<std::size_t>(v.voxel_count()), 0);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(0, 1);
    for (int b = 0; b < 8; ++b) {
        const double cx = 5 + 12 * u(rng), cy = 5 + 6 * u(rng), cz = 5 + 13 * u(rng), r = 1 + 3 * u(rng);
        for (std::int64_t k = 0; k < 18; ++k)
            for (std::int64_t j = 0; j < 20; ++j)
                for (std::int64_t i = 0; i < 22; ++i)
                    if (std::hypot(i - cx, 0.8 * j - cy, 1.3 * k - cz) < r) v.values[static_cast<std::size_t>(i + 22 * (j + 20 * k))] = 1;
    }
    VolumeLevelSet3Options o;
    o.mode.mode = ImageMode::label;
    o.mode.labels = {1};
    const auto f = make_volume_levelset3(v, o);
    const double c = 0.5 * 0.8, cap = o.band * 1.3;
    int checked = 0;
    for (std::int64_t k = 0; k < 18; ++k)
        for (std::int64_t j = 0; j < 20; ++j)
            for (std::int64_t i = 0; i < 22; ++i) {
                // away from the hull, where f is the interpolant itself
                const double box = std::max({(std::abs(i - 10.5) - 10.5) * 1.0, (std::abs(j - 9.5) - 9.5) * 0.8, (std::abs(k - 8.5) - 8.5) * 1.3});
                if (box > -cap) continue;
                const bool in = v.at(i, j, k) == 1;
                double d2 = std::numeric_limits<double>::infinity();
                for (std::int64_t kk = 0; kk < 18; ++kk)
                    for (std::int64_t jj = 0; jj < 20; ++jj)
                        for (std::int64_t ii = 0; ii < 22; ++ii)
                            if ((v.at(ii, jj, kk) == 1) != in)
                                d2 = std::min(d2, std::pow(ii - i, 2) + std::pow(0.8 * (jj - j), 2) + std::pow(1.3 * (kk - k), 2));
                const double want = std::clamp(in ? -(std::sqrt(d2) - c) : std::sqrt(d2) - c, -cap, cap);
                const double got = f->value(static_cast<double>(i), 0.8 * static_cast<double>(j), 1.3 * static_cast<double>(k));
                BOOST_TEST(std::abs(got - want) < 1e-5, "voxel " << i << "," << j << "," << k << ": " << got << " against " << want);
                checked += std::abs(want) < cap;
            }
    BOOST_TEST(checked > 100);
}

// Issue 49 (fixed costs follow the region): the labels stay 16-bit
// (Volume::labels) up to the region's mask, and the transforms run plane by
// plane through a ring of the band's reach (first, slabs of 64 planes with a
// halo).  A tall volume (150 planes; a ring of 15 here, wrapped ten times)
// must still give the clamped signed distance at every voxel centre, and the
// same field and mesh from its labels as from the same samples as doubles.
BOOST_AUTO_TEST_CASE(issue49_label_field_is_the_same_across_slabs_and_from_16_bit_labels) {
    Volume v;
    v.dims = {9, 8, 150};
    v.spacing = {1.0, 1.0, 0.6};
    v.physical = true;
    v.source = "tube";
    v.labels.assign(static_cast<std::size_t>(v.voxel_count()), 0);
    for (std::int64_t k = 3; k < 146; ++k)
        for (std::int64_t j = 0; j < 8; ++j)
            for (std::int64_t i = 0; i < 9; ++i)
                if (std::hypot(i - 4 - 1.5 * std::sin(0.1 * static_cast<double>(k)), j - 3.5) < 2.2 + std::cos(0.07 * static_cast<double>(k)))
                    v.labels[static_cast<std::size_t>(i + 9 * (j + 8 * k))] = 7;
    Volume d = v;  // the same samples as doubles
    samples_to_values(d);
    BOOST_TEST(d.labels.empty());
    VolumeLevelSet3Options o;
    o.mode.mode = ImageMode::label;
    o.mode.labels = {7};
    const auto f = make_volume_levelset3(v, o), g = make_volume_levelset3(d, o);
    const double c = 0.3, cap = o.band * 1.0;
    const std::int64_t reach = static_cast<std::int64_t>(std::ceil((cap + c) / 0.6));
    int checked = 0;
    for (std::int64_t k = 0; k < 150; ++k)
        for (std::int64_t j = 0; j < 8; ++j)
            for (std::int64_t i = 0; i < 9; ++i) {
                const bool in = v.at(i, j, k) == 7;
                double d2 = std::numeric_limits<double>::infinity();  // nearer than cap + c, else clamped anyway
                for (std::int64_t kk = std::max<std::int64_t>(0, k - reach); kk < std::min<std::int64_t>(150, k + reach + 1); ++kk)
                    for (std::int64_t jj = 0; jj < 8; ++jj)
                        for (std::int64_t ii = 0; ii < 9; ++ii)
                            if ((v.at(ii, jj, kk) == 7) != in)
                                d2 = std::min(d2, std::pow(ii - i, 2) + std::pow(jj - j, 2) + std::pow(0.6 * (kk - k), 2));
                // f = max(the field, the box distance to the voxel centres' hull)
                const double hull = std::max({std::abs(i - 4.0) - 4.0, std::abs(j - 3.5) - 3.5, 0.6 * (std::abs(k - 74.5) - 74.5)});
                const double want = std::max(hull, std::clamp(in ? -(std::sqrt(d2) - c) : std::sqrt(d2) - c, -cap, cap));
                const double x = static_cast<double>(i), y = static_cast<double>(j), z = 0.6 * static_cast<double>(k);
                const double got = f->value(x, y, z);
                BOOST_TEST(std::abs(got - want) < 1e-5, "voxel " << i << "," << j << "," << k << ": " << got << " against " << want);
                BOOST_TEST(got == g->value(x, y, z));
                checked += std::abs(want) < cap;
            }
    BOOST_TEST(checked > 1000);
    Mesh3dOptions m;
    m.labels = "7";
    m.spacing = 0.9;
    const Mesh3dResult a = mesh3d(std::cref(v), m), b = mesh3d(std::cref(d), m);
    BOOST_TEST(a.mesh.tets.size() > 1000u);
    BOOST_TEST(same(a.mesh, b.mesh));
}

BOOST_AUTO_TEST_CASE(bad_input_empty_region_coarse_spacing_memory_limit) {
    Mesh3dOptions o;
    o.spacing = 0.1;
    const FunctionLevelSet3 nothing([](double, double, double) { return 1.0; }, {-1, -1, -1, 1, 1, 1});
    BOOST_TEST(throws_containing([&] { mesh3d(nothing, o); }, "the region is empty"));
    BOOST_TEST(throws_containing([&] { parse_shape3("intersect(sphere:0,0,0,1;sphere:5,0,0,1)"); }, "the region is empty"));
    BOOST_TEST(throws_containing([&] { parse_shape3("sphere:0,0,0"); }, "sphere takes 4 numbers"));
    BOOST_TEST(throws_containing([&] { parse_shape3("torus:0,0,0,1,2"); }, "0 < r < R"));
    o.spacing = -1;
    // The library's words (OptionError naming the option; the CLI prints --spacing).
    BOOST_TEST(throws_containing([&] { mesh3d(*parse_shape3("sphere:0,0,0,1"), o); }, "spacing must be positive and finite (got -1)"));
    // Coarse: a sphere of radius 1 at spacing 0.7 (less than 4 cubes across).
    o.spacing = 0.7;
    const Mesh3dReport r = mesh3d(*parse_shape3("union(sphere:0,0,0,3;sphere:6,0,0,1)"), o).report;
    BOOST_REQUIRE(!r.warnings.empty());
    bool named = false;
    for (const auto& w : r.warnings) named = named || (w.find("too coarse") != std::string::npos && w.find("--spacing 0.") != std::string::npos);
    BOOST_TEST(named, r.warnings.front());
    BOOST_TEST(r.suggested_spacing > 0);
    BOOST_TEST(r.suggested_spacing <= 0.5);
    // Label mode on values that are not labels: named, whichever voxel has it.
    for (const double bad : {1.5, -1.0, 70000.0, std::numeric_limits<double>::quiet_NaN()})
        for (const std::size_t at : {std::size_t{0}, std::size_t{7 * 6 * 5 - 1}}) {
            Volume v;
            v.dims = {7, 6, 5};
            v.source = "bad labels";
            v.values.assign(7 * 6 * 5, 0);
            v.values[100] = 1;
            v.values[at] = bad;
            VolumeLevelSet3Options lo;
            lo.mode.mode = ImageMode::label;
            lo.mode.label_nonzero = true;
            BOOST_TEST(throws_containing([&] { make_volume_levelset3(v, lo); }, "integer voxel values in 0..65535"), bad);
        }
    // Memory: a lattice of ~10^9 points is refused before it is allocated.
    o.spacing = 0.002;
    o.max_memory = std::uint64_t{256} << 20;
    BOOST_TEST(throws_containing([&] { mesh3d(*parse_shape3("sphere:0,0,0,1"), o); }, "more than the max_memory limit of 256 MB"));
}

BOOST_AUTO_TEST_CASE(key_lookup_finds_certified_keys_and_refuses_impossible_ones) {
    const std::array<bcc::Ivec, 4> p = bcc::background_tet({4, 2, 6}, 5);
    std::string code;
    // One outside vertex, nothing warped: a certified key.
    const bcc::Config key = bcc::key_of(p, {-1, -1, -1, 1}, {bcc::stay, bcc::stay, bcc::stay, bcc::stay});
    code = bcc::code_of(key);
    const std::optional<BccKeyBound> bound = bcc_certified_bound(key, FaceRule::parity);
    BOOST_TEST(bound.has_value(), code);
    BOOST_TEST(bound->min_deg >= bcc_certified_theorem()->min_deg);
    // Vertices 0 and 1 warped towards each other along their common edge:
    // excluded by the consistency rules (proofs/README.md), so no key.
    const int d01 = bcc::direction_of(bcc::sub(p[1], p[0])), d10 = bcc::direction_of(bcc::sub(p[0], p[1]));
    const bcc::Config impossible = bcc::key_of(p, {0, 0, -1, 1}, {d01, d10, bcc::stay, bcc::stay});
    BOOST_TEST(!bcc_certified_bound(impossible, FaceRule::parity).has_value(), bcc::code_of(impossible));
}

// --verify's per-key test (key_claim_holds) accepts the background
// tetrahedron itself (dihedral angles 60° and 90°) under the theorem's claim
// and rejects it under a claim tighter than its 60°, a sliver (near 0°) and
// an inverted tetrahedron.
BOOST_AUTO_TEST_CASE(key_claim_test_accepts_the_background_tet_and_rejects_slivers) {
    const auto& r = bcc::reference_tet;
    std::array<Point3, 4> q{};
    for (std::size_t k = 0; k < 4; ++k) q[k] = {double(r[k][0]), double(r[k][1]), double(r[k][2])};
    const BccKeyBound t = *bcc_certified_theorem();
    const double c_min = std::ldexp(double(t.cmin_num), -40), c_max = std::ldexp(double(t.cmax_num), -40);
    BOOST_TEST(uniform3d::key_claim_holds(q, c_min, c_max));
    BOOST_TEST(!uniform3d::key_claim_holds(q, 0.117, c_max));  // θmin = 70° (cos² 70° < 0.117): its 60° fails
    std::array<Point3, 4> flat = q;
    flat[3] = {1, 1, -0.999};  // c1 almost onto c0: a sliver
    BOOST_TEST(!uniform3d::key_claim_holds(flat, c_min, c_max));
    std::array<Point3, 4> inverted = q;
    std::swap(inverted[2], inverted[3]);
    BOOST_TEST(!uniform3d::key_claim_holds(inverted, c_min, c_max));
}

// The whole background tetrahedra (four − vertices) skip the key lookup in
// --verify: they are checked against the claim of the all-− key, looked up
// once (tets3.cpp).  That claim accepts the background tetrahedron (60°,
// 90°), and a minimum claim tightened past its 60° rejects it.
BOOST_AUTO_TEST_CASE(whole_background_tet_key_claim_accepts_it_and_a_tighter_one_rejects_it) {
    const std::array<bcc::Ivec, 4> p = bcc::background_tet({2, 4, 6}, 7);
    std::string code;
    const bcc::Config key = bcc::key_of(p, {-1, -1, -1, -1}, {bcc::stay, bcc::stay, bcc::stay, bcc::stay});
    code = bcc::code_of(key);
    const std::optional<BccKeyBound> b = bcc_certified_bound(key, FaceRule::parity);
    BOOST_REQUIRE(b.has_value());
    BOOST_TEST(code == "-,-,-,-/0");
    std::array<Point3, 4> q{};
    for (std::size_t k = 0; k < 4; ++k) q[k] = {0.05 * p[k][0] - 1, 0.05 * p[k][1] + 0.3, 0.05 * p[k][2] + 2};  // at spacing 0.1
    const double c_min = std::ldexp(double(b->cmin_num), -40), c_max = std::ldexp(double(b->cmax_num), -40);
    BOOST_TEST(uniform3d::key_claim_holds(q, c_min, c_max));
    BOOST_TEST(b->min_deg <= 60.0);
    BOOST_TEST(b->max_deg >= 90.0);
    BOOST_TEST(!uniform3d::key_claim_holds(q, 0.24, c_max));  // θmin above 60° (cos² 60° = 0.25)
}

// Issue 30: a background tetrahedron whose four vertices were all warped onto
// the level set ("all-zero") was output when f < 0 at its centroid, outside
// proofs/bcc.cert (its space, four independent warps of up to α of an edge,
// holds almost flat and inverted tetrahedra): on this crop of the SPL brain
// atlas (label 26, spacing 1.5 mm, the golden mesh) 28 tetrahedra were
// output that way and counted as uncertified.  Now none is: every tetrahedron
// is certified and verified, none has its four vertices on the level set
// (every stencil tetrahedron has a − vertex), and the mesh stays conforming,
// its boundary on the level set, closed and outward.
BOOST_AUTO_TEST_CASE(issue30_all_zero_tet_uncertified) {
    const auto f = brain_crop_levelset();
    TetMesh m;
    const Mesh3dReport r = mesh_checked(*f, 1.5, &m);  // verified, conforming, certified, within the bounds
    BOOST_TEST(r.all_zero_left_out > 0);               // the case occurs here
    int on_level_set = 0;
    for (const auto& t : m.tets) {
        int on = 0;
        for (std::int32_t i : t) {
            const Point3& x = m.vertices[static_cast<std::size_t>(i)];
            on += std::abs(f->value(x.x, x.y, x.z)) < 1e-9;
        }
        on_level_set += on == 4;
    }
    BOOST_TEST(on_level_set == 0);
    // Closed and oriented: each directed boundary edge is matched by its reverse.
    std::map<std::pair<std::int32_t, std::int32_t>, int> edges;
    for (const auto& b : m.boundary)
        for (std::size_t k = 0; k < 3; ++k) ++edges[{b[k], b[(k + 1) % 3]}];
    for (const auto& [e, n] : edges) {
        const auto back = edges.find({e.second, e.first});
        BOOST_TEST((back != edges.end() && back->second == n), "boundary edge " << e.first << "-" << e.second);
    }
}

namespace {

// A mesh of tetrahedra whose boundary is every face in one tetrahedron
// (outward), as check_tet_mesh wants it.
TetMesh with_boundary(std::vector<Point3> points, std::vector<std::array<std::int32_t, 4>> tets) {
    TetMesh m;
    m.vertices.assign(points.begin(), points.end());
    m.tets.assign(tets.begin(), tets.end());
    m.region.assign(tets.size(), 1);
    std::map<std::array<std::int32_t, 3>, std::pair<int, std::array<std::int32_t, 3>>> faces;
    for (const auto& t : tets)
        for (const auto& f : {std::array<int, 3>{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}) {
            const std::array<std::int32_t, 3> o{t[static_cast<std::size_t>(f[0])], t[static_cast<std::size_t>(f[1])], t[static_cast<std::size_t>(f[2])]};
            std::array<std::int32_t, 3> key = o;
            std::sort(key.begin(), key.end());
            auto& [n, oriented] = faces[key];
            ++n, oriented = o;
        }
    for (const auto& [key, face] : faces)
        if (face.first == 1) m.boundary.push_back(face.second), m.boundary_tag.push_back(boundary_level_set);
    return m;
}

// The boundary's non-manifold edges and vertices counted another way: edges
// by a map of their boundary triangles; a vertex is non-manifold when it
// ends such an edge or its boundary triangles fall into more than one fan
// (triangles joined across their edges at the vertex).
std::pair<std::int64_t, std::int64_t> nonmanifold_by_maps(const TetMesh& m) {
    std::map<std::pair<std::int32_t, std::int32_t>, int> edges;
    std::map<std::int32_t, std::vector<std::size_t>> around;
    for (std::size_t i = 0; i < m.boundary.size(); ++i)
        for (std::size_t k = 0; k < 3; ++k) {
            const std::int32_t a = m.boundary[i][k], b = m.boundary[i][(k + 1) % 3];
            ++edges[{std::min(a, b), std::max(a, b)}];
            around[a].push_back(i);
        }
    std::set<std::int32_t> bad;
    std::int64_t bad_edges = 0;
    for (const auto& [e, n] : edges)
        if (n > 2) ++bad_edges, bad.insert(e.first), bad.insert(e.second);
    for (const auto& [v, tris] : around) {
        std::vector<std::size_t> fan(tris.size());
        std::iota(fan.begin(), fan.end(), 0);
        const auto root = [&](std::size_t x) {
            while (fan[x] != x) x = fan[x];
            return x;
        };
        for (std::size_t i = 0; i < tris.size(); ++i)
            for (std::size_t j = 0; j < i; ++j) {
                int shared = 0;
                for (std::int32_t a : m.boundary[tris[i]])
                    for (std::int32_t b : m.boundary[tris[j]]) shared += a == b;
                if (shared >= 2) fan[root(i)] = root(j);
            }
        std::size_t fans = 0;
        for (std::size_t i = 0; i < tris.size(); ++i) fans += root(i) == i;
        if (fans > 1) bad.insert(v);
    }
    return {bad_edges, static_cast<std::int64_t>(bad.size())};
}

}  // namespace

// Issue 30, "boundary closed and oriented": with the all-zero background
// tetrahedra left out the boundary stays closed and outward, but it need not
// be a manifold surface.  The checker and the report count its edges in more
// than two boundary triangles and its vertices that are not one disc: two
// tetrahedra sharing an edge give one such edge (four boundary triangles)
// and two such vertices, two sharing a vertex one vertex, and on the brain
// crop the report's counts are those found by maps of the boundary.
BOOST_AUTO_TEST_CASE(issue30_nonmanifold_boundary_edges_counted) {
    const Point3 o{0, 0, 0}, z{0, 0, 1}, x{1, 0, 0}, y{0, 1, 0}, mx{-1, 0, 0}, my{0, -1, 0}, mz{0, 0, -1};
    const TetMesh one = with_boundary({o, x, y, z}, {{0, 1, 2, 3}});
    const TetMesh edge = with_boundary({o, z, x, y, mx, my}, {{0, 2, 3, 1}, {0, 4, 5, 1}});
    const TetMesh vertex = with_boundary({o, x, y, z, mx, my, mz}, {{0, 1, 2, 3}, {0, 5, 4, 6}});
    for (const TetMesh* m : {&one, &edge, &vertex}) {
        const TetMeshCheck c = check_tet_mesh(*m);
        BOOST_TEST(c.ok, (c.problems.empty() ? "" : c.problems.front()));
    }
    BOOST_TEST(check_tet_mesh(one).nonmanifold_boundary_edges == 0);
    BOOST_TEST(check_tet_mesh(one).nonmanifold_boundary_vertices == 0);
    BOOST_TEST(check_tet_mesh(edge).nonmanifold_boundary_edges == 1);
    BOOST_TEST(check_tet_mesh(edge).nonmanifold_boundary_vertices == 2);
    BOOST_TEST(check_tet_mesh(vertex).nonmanifold_boundary_edges == 0);
    BOOST_TEST(check_tet_mesh(vertex).nonmanifold_boundary_vertices == 1);
    for (const TetMesh* m : {&one, &edge, &vertex}) {
        const auto [e, v] = nonmanifold_by_maps(*m);
        BOOST_TEST(nonmanifold_boundary(*m).edges == e);
        BOOST_TEST(nonmanifold_boundary(*m).vertices == v);
    }
    const auto f = brain_crop_levelset();
    for (const double spacing : {1.0, 1.5, 2.0}) {
        TetMesh m;
        const Mesh3dReport r = mesh_checked(*f, spacing, &m);
        const auto [e, nv] = nonmanifold_by_maps(m);
        BOOST_TEST(r.nonmanifold_boundary_edges == e, "spacing " << spacing);
        BOOST_TEST(r.nonmanifold_boundary_vertices == nv, "spacing " << spacing);
        BOOST_TEST(check_tet_mesh(m).nonmanifold_boundary_edges == e);
        BOOST_TEST_MESSAGE("brain crop, spacing " << spacing << ": " << e << " non-manifold boundary edges, " << nv << " vertices, "
                                                  << r.all_zero_left_out << " all-zero left out");
    }
}

// check_tet_mesh finds each broken invariant and names the element: two
// tetrahedra sharing a face, in two regions with their interface listed,
// then one thing broken at a time.
BOOST_AUTO_TEST_CASE(check_tet_mesh_names_each_broken_invariant) {
    const Point3 o{0, 0, 0}, x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1}, mz{0, 0, -1};
    TetMesh good = with_boundary({o, x, y, z, mz}, {{0, 1, 2, 3}, {0, 2, 1, 4}});
    good.region = {1, 2};
    good.interfaces = {{0, 2, 1}};  // out of tetrahedron 0 (region 1)
    good.interface_regions = {{1, 2}};
    BOOST_TEST(check_tet_mesh(good).ok);
    const auto finds = [](const TetMesh& m, const std::string& what) {
        const TetMeshCheck c = check_tet_mesh(m);
        bool named = false;
        for (const auto& p : c.problems) named = named || p.find(what) != std::string::npos;
        BOOST_TEST(!c.ok, what);
        BOOST_TEST(named, what << (c.problems.empty() ? "" : ", first problem: " + c.problems.front()));
        return c;
    };
    TetMesh m = good;
    std::swap(m.tets[0][0], m.tets[0][1]);
    BOOST_TEST(finds(m, "tetrahedron 0 is not positively oriented").inverted == 1);
    m = good;
    m.boundary.pop_back(), m.boundary_tag.pop_back();
    BOOST_TEST(finds(m, "has one tetrahedron but is listed 0 times as boundary").boundary_mismatch == 1);
    m = good;
    std::swap(m.boundary[0][1], m.boundary[0][2]);
    BOOST_TEST(finds(m, "is not oriented outward").boundary_mismatch == 1);
    m = good;
    m.tets.push_back(m.tets[1]), m.region.push_back(2);
    BOOST_TEST(finds(m, "(0, 1, 2) is in 3 tetrahedra").nonmanifold_faces >= 1);
    m = good;
    m.interface_regions[0] = {2, 1};
    BOOST_TEST(finds(m, "interface face 0 has the wrong regions or orientation").interface_mismatch == 1);
    m = good;
    m.vertices.push_back({5, 5, 5});
    BOOST_TEST(finds(m, "vertex 5 is in no tetrahedron").unused_vertices == 1);
}

BOOST_AUTO_TEST_CASE(region_at_the_lattice_upper_corner_leaves_no_isolated_vertex) {
    // A region reaching the lattice's upper corner (z > 0.3 reaches the top
    // of the lattice): its cubes there are whole (all 12 points inside), and
    // a whole cube's pass A marked all 8 of its corners, also the corner
    // m + (2, 2, 2), which none of its 12 tetrahedra uses; at the lattice's
    // upper corner no cube above uses it either, so the mesh had a vertex in
    // no tetrahedron (check_tet_mesh: "vertex ... is in no tetrahedron").
    const FunctionLevelSet3 upper([](double, double, double z) { return 0.3 - z; }, {-1, -1, -1, 1, 1, 1}, "z > 0.3");
    Mesh3dOptions o;
    o.spacing = 0.15;
    const TetMesh m = mesh3d(upper, o).mesh;
    const TetMeshCheck c = check_tet_mesh(m);
    BOOST_TEST(c.ok, (c.problems.empty() ? "" : c.problems.front()));
    BOOST_TEST(c.unused_vertices == 0);
    // Blocks agree, the upper block holding the corner.
    const Lattice3 L = lattice3d(upper, o);
    const std::array<std::int64_t, 3> cut{L.cubes[0] / 2, L.cubes[1] / 2, L.cubes[2] / 2};
    BOOST_TEST(same(merge_tet_blocks(eight_blocks(upper, o, L, cut)), m));
}

BOOST_AUTO_TEST_CASE(region_cut_off_by_the_lattice_is_closed_by_domain_faces) {
    // A half-space reaches the lattice's edge: the boundary there is the
    // lattice's cut-off (boundary_domain), and the whole boundary stays closed
    // and outward (check_tet_mesh); the plane part is on the level set.
    const FunctionLevelSet3 half([](double, double, double z) { return z - 0.3; }, {-1, -1, -1, 1, 1, 1}, "z < 0.3");
    Mesh3dOptions o;
    o.spacing = 0.15;
    o.verify = true;
    const Mesh3dResult res = mesh3d(half, o);
    const Mesh3dReport& r = res.report;
    const TetMesh& m = res.mesh;
    const TetMeshCheck c = check_tet_mesh(m);
    BOOST_TEST(c.ok, (c.problems.empty() ? "" : c.problems.front()));
    std::int64_t level = 0, domain = 0;
    for (std::size_t i = 0; i < m.boundary.size(); ++i) {
        const bool on_plane = std::abs(m.vertices[static_cast<std::size_t>(m.boundary[i][0])].z - 0.3) < 1e-12 &&
                              std::abs(m.vertices[static_cast<std::size_t>(m.boundary[i][1])].z - 0.3) < 1e-12 &&
                              std::abs(m.vertices[static_cast<std::size_t>(m.boundary[i][2])].z - 0.3) < 1e-12;
        if (m.boundary_tag[i] == boundary_level_set) {
            ++level;
            BOOST_TEST(on_plane);
        } else {
            ++domain;
        }
    }
    BOOST_TEST(level > 0);
    BOOST_TEST(domain > 0);
    // Blocks agree there too.
    const Lattice3 L = lattice3d(half, o);
    std::vector<TetBlock> blocks;
    const std::int64_t cut = L.cubes[2] / 3;
    blocks.push_back(mesh3d_block(half, o, {{0, 0, 0}, {L.cubes[0], L.cubes[1], cut}}));
    blocks.push_back(mesh3d_block(half, o, {{0, 0, cut}, L.cubes}));
    BOOST_TEST(same(merge_tet_blocks(blocks), m));
}

// The option `band` (issue 46's demonstration of an option added through the
// 3D table: the entry, its use in the pipeline, this test).  The label
// distance is exact within `band` voxels of the boundary and clamped beyond;
// the cut points lie within a voxel of the boundary, so every band of 2 or
// more gives the same mesh, and the table refuses a narrower one.
BOOST_AUTO_TEST_CASE(band_option_keeps_the_mesh_and_is_checked_by_the_table) {
    const std::string crop = std::string(WARPMESH_TEST_DATA) + "/brain_crop22_labels.nrrd";
    Mesh3dOptions o;
    o.labels = "26";
    o.spacing = 1.5;
    const Mesh3dResult four = mesh3d(VolumeFile{crop}, o);
    GivenOptions given;
    mesh3d_option_table().set(o, given, "band", "2");
    const Mesh3dResult two = mesh3d(VolumeFile{crop}, o);
    BOOST_TEST(two.mesh.vertices.size() == four.mesh.vertices.size());
    BOOST_TEST((two.mesh.tets == four.mesh.tets));
    BOOST_TEST(throws_containing([&] { mesh3d_option_table().set(o, given, "band", "1"); }, "band must be 2 to 1000 voxels (got 1)"));
    o.band = 1;  // set directly: validate refuses it as well
    BOOST_TEST(throws_containing([&] { mesh3d(VolumeFile{crop}, o); }, "band must be 2 to 1000 voxels (got 1)"));
}

// Issue 50: what a volume's mesh silently lost or guessed is said.  The
// bundled crop's label 26 (868 voxels of 1 mm³) keeps its volume within 5 %
// at the voxel size and loses 16 % at spacing 3; the crop meshed with neither
// labels nor iso is thresholded at a guessed iso, and its narrowest part is
// below a voxel, which the coarse-spacing warning no longer promises to
// resolve at the voxel size ("--spacing 1 resolves it" contradicted it).
BOOST_AUTO_TEST_CASE(volume_warnings_name_lost_volume_a_guessed_iso_and_the_voxel_limit) {
    const std::string crop = std::string(WARPMESH_TEST_DATA) + "/brain_crop22_labels.nrrd";
    const auto warned = [](const Mesh3dResult& r, const std::string& words) {
        return std::any_of(r.warnings.begin(), r.warnings.end(), [&](const std::string& w) { return w.find(words) != std::string::npos; });
    };
    Mesh3dOptions o;
    o.labels = "26";
    o.spacing = 1;
    BOOST_TEST(!warned(mesh3d(VolumeFile{crop}, o), "the region's voxels'"));
    o.spacing = 3;
    BOOST_TEST(warned(mesh3d(VolumeFile{crop}, o), "% below the region's voxels' (868): parts thinner than about the spacing 3 are lost"));
    o.labels.reset();
    o.spacing = 2;
    const Mesh3dResult guessed = mesh3d(VolumeFile{crop}, o);
    BOOST_TEST(warned(guessed, "neither labels nor iso given: threshold mode"));
    BOOST_TEST(warned(guessed, "that is below the input's resolution, 1 (its voxel size): --spacing 1, the finest"));
    BOOST_TEST(!warned(guessed, "resolves it"));
}

// Issue 50: --manifold makes the boundary manifold where parts touch only at
// a vertex or along an edge, by giving each part its own copy of the shared
// vertices; no tetrahedron moves, so the certified bounds hold as they are.
BOOST_AUTO_TEST_CASE(issue50_manifold_splits_the_boundarys_nonmanifold_vertices) {
    const Point3 o{0, 0, 0}, z{0, 0, 1}, x{1, 0, 0}, y{0, 1, 0}, mx{-1, 0, 0}, my{0, -1, 0}, mz{0, 0, -1};
    TetMesh edge = with_boundary({o, z, x, y, mx, my}, {{0, 2, 3, 1}, {0, 4, 5, 1}});
    TetMesh vertex = with_boundary({o, x, y, z, mx, my, mz}, {{0, 1, 2, 3}, {0, 5, 4, 6}});
    BOOST_TEST(split_nonmanifold_vertices(edge) == 2);  // both ends of the shared edge
    BOOST_TEST(split_nonmanifold_vertices(vertex) == 1);
    for (const TetMesh* m : {&edge, &vertex}) {
        const TetMeshCheck c = check_tet_mesh(*m);
        BOOST_TEST(c.ok, (c.problems.empty() ? "" : c.problems.front()));
        BOOST_TEST(c.nonmanifold_boundary_edges == 0);
        BOOST_TEST(c.nonmanifold_boundary_vertices == 0);
    }
    // A label volume whose parts touch along a voxel edge (two blocks
    // diagonal to each other) and at a voxel corner (a third block).
    Volume v;
    v.dims = {14, 14, 14};
    v.spacing = {1, 1, 1};
    v.origin = {0, 0, 0};
    v.axes = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    v.source = "contacts";
    v.values.assign(14 * 14 * 14, 0);
    const auto set = [&](int i0, int i1, int j0, int j1, int k0, int k1) {
        for (int k = k0; k < k1; ++k)
            for (int j = j0; j < j1; ++j)
                for (int i = i0; i < i1; ++i) v.values[static_cast<std::size_t>(i + 14 * (j + 14 * k))] = 1;
    };
    set(2, 6, 2, 6, 2, 8), set(6, 10, 6, 10, 2, 8), set(10, 13, 10, 13, 8, 12);
    Mesh3dOptions mo;
    mo.labels = "1";
    mo.verify = true;
    const Mesh3dResult plain = mesh3d(std::cref(v), mo);
    mo.manifold = true;
    const Mesh3dResult split = mesh3d(std::cref(v), mo);
    BOOST_TEST(plain.report.nonmanifold_boundary_edges > 0);
    BOOST_TEST(plain.report.nonmanifold_boundary_vertices > 0);
    BOOST_TEST(!plain.report.manifold_added_vertices.has_value());
    BOOST_TEST(split.report.nonmanifold_boundary_edges == 0);
    BOOST_TEST(split.report.nonmanifold_boundary_vertices == 0);
    BOOST_TEST(*split.report.manifold_added_vertices > 0);
    BOOST_TEST(split.mesh.vertices.size() == plain.mesh.vertices.size() + static_cast<std::size_t>(*split.report.manifold_added_vertices));
    const TetMeshCheck c = check_tet_mesh(split.mesh);
    BOOST_TEST(c.ok, (c.problems.empty() ? "" : c.problems.front()));
    // Every tetrahedron where it was: the same corners, so the same shape and certified bounds.
    BOOST_REQUIRE(split.mesh.tets.size() == plain.mesh.tets.size());
    for (std::size_t t = 0; t < plain.mesh.tets.size(); ++t)
        for (std::size_t k = 0; k < 4; ++k) {
            const Point3 a = plain.mesh.vertices[static_cast<std::size_t>(plain.mesh.tets[t][k])];
            const Point3 b = split.mesh.vertices[static_cast<std::size_t>(split.mesh.tets[t][k])];
            BOOST_TEST((a.x == b.x && a.y == b.y && a.z == b.z));
        }
    BOOST_TEST(split.report.certified_min_deg == plain.report.certified_min_deg);
    BOOST_TEST(split.report.verified);
    BOOST_TEST(split.report.quality.min_dihedral_deg == plain.report.quality.min_dihedral_deg);
    BOOST_TEST(split.mesh.boundary.size() == plain.mesh.boundary.size());
    BOOST_TEST(to_json(split.report).find("\"manifold_added_vertices\": ") != std::string::npos);
    // Blocks share their vertices by key: refused there.
    BOOST_TEST(throws_containing([&] { mesh3d_block(std::cref(v), mo, CubeRange{{0, 0, 0}, {1, 1, 1}}); }, "manifold"));
}
