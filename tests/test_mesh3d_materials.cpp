// Multi-material 3D meshes (mesh3d.hpp: mesh_bcc_materials;
// generic_bcc_materials.hpp): the stencils tile every background
// tetrahedron and both sides of an interface agree; meshes of nested and
// meeting shapes and of random label volumes are valid (orientation,
// conformity, boundary, interfaces exactly the faces between two regions);
// renumbering the labels gives the same mesh; per-material volumes follow
// the shapes and the voxels; blocks (mesh_bcc_materials_block) tiling the
// lattice in any way merge into exactly the whole mesh.
#define BOOST_TEST_MODULE mesh3d_materials
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include "support.hpp"
#include "warpmesh/certify/bcc_certified.hpp"
#include "warpmesh/io/volume.hpp"
#include "warpmesh/levelset/materials3.hpp"
#include "warpmesh/mesh3d/generic_bcc_materials.hpp"
#include "warpmesh/mesh3d/mesh3d.hpp"
#include "warpmesh/post/tet_checks.hpp"

using namespace warpmesh;

namespace {

// The parity rule at its certificate's alphas, every two-material
// tetrahedron verified against its side's key claim (a violation throws),
// all-zero background tetrahedra output when within the certificate's claim.
BccOptions parity_options() {
    static const BccKeyClaims claims = bcc_key_claims(FaceRule::parity);
    BccOptions o;
    o.face_rule = FaceRule::parity;
    o.alphas = face_rule_alphas(FaceRule::parity);
    o.verify = &claims;
    const BccClaim c = bcc_claim(FaceRule::parity).value();
    o.fill_claim = BccKeyClaim{c.cos2_min, c.cos2_max};
    return o;
}

// The dihedral extremes of the tetrahedra of `m` that are not junction ones
// are within the parity certificate's bounds (verify checks the
// two-material ones against their keys; this checks the filled all-zero ones
// too, from scratch).
void check_angles(const TetMesh& m, double min_deg, double max_deg, const std::string& what) {
    double lo = 180, hi = 0;
    for (std::size_t t = 0; t < m.tets.size(); ++t) {
        std::array<Point3, 4> p{};
        for (std::size_t k = 0; k < 4; ++k) p[k] = m.vertices[static_cast<std::size_t>(m.tets[t][k])];
        for (const double a : dihedral_angles_deg(p)) lo = std::min(lo, a), hi = std::max(hi, a);
    }
    BOOST_TEST(lo >= min_deg, what << ": min " << lo);
    BOOST_TEST(hi <= max_deg, what << ": max " << hi);
}

double tet_volume(const TetMesh& m, std::size_t t) {
    const auto& k = m.tets[t];
    const Point3 &a = m.vertices[static_cast<std::size_t>(k[0])], &b = m.vertices[static_cast<std::size_t>(k[1])],
                 &c = m.vertices[static_cast<std::size_t>(k[2])], &d = m.vertices[static_cast<std::size_t>(k[3])];
    const double ux = b.x - a.x, uy = b.y - a.y, uz = b.z - a.z, vx = c.x - a.x, vy = c.y - a.y, vz = c.z - a.z, wx = d.x - a.x,
                 wy = d.y - a.y, wz = d.z - a.z;
    return (ux * (vy * wz - vz * wy) - uy * (vx * wz - vz * wx) + uz * (vx * wy - vy * wx)) / 6;
}

std::map<std::int32_t, double> region_volumes(const TetMesh& m) {
    std::map<std::int32_t, double> v;
    for (std::size_t t = 0; t < m.tets.size(); ++t) v[m.region[t]] += tet_volume(m, t);
    return v;
}

void check_valid(const TetMesh& m, const std::string& what) {
    const TetMeshCheck c = check_tet_mesh(m);
    BOOST_TEST(c.ok, what << ": " << (c.problems.empty() ? "" : c.problems.front()));
}

// A label volume of random blobs (labels from `values`), n^3 voxels.
Volume random_labels(int n, const std::vector<int>& values, std::mt19937& rng) {
    Volume v;
    v.dims = {n, n, n};
    v.values.assign(static_cast<std::size_t>(n) * n * n, 0);
    std::uniform_real_distribution<double> pos(0, n - 1), rad(1.0, n / 3.0);
    for (int blob = 0; blob < 10; ++blob) {
        const double cx = pos(rng), cy = pos(rng), cz = pos(rng), r = rad(rng);
        const int label = values[static_cast<std::size_t>(blob) % values.size()];
        for (int k = 0; k < n; ++k)
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i)
                    if ((i - cx) * (i - cx) + (j - cy) * (j - cy) + (k - cz) * (k - cz) < r * r)
                        v.values[static_cast<std::size_t>(i + n * (j + n * k))] = label;
    }
    return v;
}

// Every array of two meshes equal (positions bit for bit).
bool identical(const TetMesh& a, const TetMesh& b, std::string& why) {
    const auto same_points = [](const Point3& p, const Point3& q) { return p.x == q.x && p.y == q.y && p.z == q.z; };
    if (a.vertices.size() != b.vertices.size()) return why = "vertex counts", false;
    for (std::size_t i = 0; i < a.vertices.size(); ++i)
        if (!same_points(a.vertices[i], b.vertices[i])) return why = "vertex " + std::to_string(i), false;
    if (a.tets.size() != b.tets.size()) return why = "tetrahedron counts", false;
    for (std::size_t t = 0; t < a.tets.size(); ++t)
        if (a.tets[t] != b.tets[t] || a.region[t] != b.region[t]) return why = "tetrahedron " + std::to_string(t), false;
    if (a.boundary != b.boundary || a.boundary_tag != b.boundary_tag) return why = "boundary", false;
    if (a.interfaces != b.interfaces || a.interface_regions != b.interface_regions) return why = "interfaces", false;
    if (a.region_names != b.region_names) return why = "region names", false;
    return true;
}

// The blocks of the lattice's cubes cut along each axis at `cuts[a]` (cube
// indices, ascending, inside (0, cubes[a])), each meshed on its own, in a
// shuffled order.
std::vector<TetBlock> material_blocks(const MaterialField3& f, const Lattice3& L, bool keep, const std::array<std::vector<std::int64_t>, 3>& cuts,
                                      std::mt19937& rng) {
    std::array<std::vector<std::int64_t>, 3> ends;
    for (std::size_t a = 0; a < 3; ++a) {
        ends[a] = {0};
        ends[a].insert(ends[a].end(), cuts[a].begin(), cuts[a].end());
        ends[a].push_back(L.cubes[a]);
    }
    std::vector<TetBlock> blocks;
    for (std::size_t k = 0; k + 1 < ends[2].size(); ++k)
        for (std::size_t j = 0; j + 1 < ends[1].size(); ++j)
            for (std::size_t i = 0; i + 1 < ends[0].size(); ++i) {
                const CubeRange r{{ends[0][i], ends[1][j], ends[2][k]}, {ends[0][i + 1], ends[1][j + 1], ends[2][k + 1]}};
                blocks.push_back(mesh_bcc_materials_block(f, L, parity_options(), keep, r));
            }
    std::shuffle(blocks.begin(), blocks.end(), rng);
    return blocks;
}

// The tilings the block tests use: 2x1x1, 2x2x2 at the middle, and uneven:
// random cuts, 1 or 2 a side, and a block one cube thick.
std::vector<std::array<std::vector<std::int64_t>, 3>> tilings(const Lattice3& L, std::mt19937& rng) {
    const auto mid = [&](std::size_t a) { return std::vector<std::int64_t>{L.cubes[a] / 2}; };
    std::vector<std::array<std::vector<std::int64_t>, 3>> out{{mid(0), {}, {}}, {mid(0), mid(1), mid(2)}};
    std::array<std::vector<std::int64_t>, 3> uneven;
    for (std::size_t a = 0; a < 3; ++a) {
        std::set<std::int64_t> c;
        const int n = std::uniform_int_distribution<int>(1, 2)(rng);
        for (int k = 0; k < n; ++k) c.insert(std::uniform_int_distribution<std::int64_t>(1, L.cubes[a] - 1)(rng));
        if (a == 0) c.insert(1);  // a block one cube thick
        uneven[a].assign(c.begin(), c.end());
    }
    out.push_back(uneven);
    return out;
}

// Blocks of f's mesh on L, tiled every way, with the background dropped and
// kept, merge into exactly mesh_bcc_materials' mesh.
void check_blocks_merge(const MaterialField3& f, const Lattice3& L, std::mt19937& rng, const std::string& what) {
    for (const bool keep : {false, true}) {
        const TetMesh whole = mesh_bcc_materials(f, L, parity_options(), keep).mesh;
        for (const auto& cuts : tilings(L, rng)) {
            const std::vector<TetBlock> blocks = material_blocks(f, L, keep, cuts, rng);
            const TetMesh merged = merge_tet_blocks(blocks);
            std::string why;
            BOOST_TEST(identical(merged, whole, why), what << (keep ? ", background kept" : "") << ", " << blocks.size()
                                                           << " blocks: " << why);
        }
    }
}

}  // namespace

// Both sides of a two-material background tetrahedron share their inside
// quad's diagonal under the parity rule (generic_bcc_materials.hpp, k = 2):
// for every (2,2) sign pattern and parity bit.
BOOST_AUTO_TEST_CASE(two_material_prisms_agree_on_their_shared_quad) {
    for (int a = 0; a < 4; ++a)
        for (int b = a + 1; b < 4; ++b)
            for (int parity = 0; parity < 2; ++parity) {
                std::array<int, 4> sign{1, 1, 1, 1};
                sign[static_cast<std::size_t>(a)] = sign[static_cast<std::size_t>(b)] = -1;
                std::array<int, 4> other{};
                for (std::size_t i = 0; i < 4; ++i) other[i] = -sign[i];
                std::array<int, 2> r{};
                for (int i = 0, n = 0; i < 4; ++i)
                    if (sign[static_cast<std::size_t>(i)] > 0) r[static_cast<std::size_t>(n++)] = i;
                const auto diagonal = [&](const bcc::Stencil& s) {  // 1: cut(a,r0)–cut(b,r1), 0: the other
                    const int p = bcc::cut_point(a, r[0]), q = bcc::cut_point(b, r[1]);
                    for (int t = 0; t < s.count; ++t) {
                        const auto& k = s.tet[static_cast<std::size_t>(t)];
                        if (std::count(k.begin(), k.end(), p) && std::count(k.begin(), k.end(), q)) return 1;
                    }
                    return 0;
                };
                BOOST_TEST(diagonal(bcc::stencil(sign, parity)) == diagonal(bcc::stencil(other, parity)), a << b << " parity " << parity);
            }
}

// Every junction stencil tiles the reference tetrahedron: positive
// tetrahedra whose volumes add up to the whole.
BOOST_AUTO_TEST_CASE(junction_stencils_tile_the_tetrahedron) {
    const auto vol6 = [](const bcc::OutTet& t) {
        return bcc::orientation({bcc::reference_point15(t[0]), bcc::reference_point15(t[1]), bcc::reference_point15(t[2]),
                                 bcc::reference_point15(t[3])});
    };
    const long whole = bcc::orientation({bcc::reference_point15(0), bcc::reference_point15(1), bcc::reference_point15(2),
                                         bcc::reference_point15(3)});
    int patterns = 0;
    for (int code = 0; code < 625; ++code) {
        std::array<int, 4> letter{};
        for (int i = 0, c = code; i < 4; ++i, c /= 5) letter[static_cast<std::size_t>(i)] = c % 5 - 1;
        // Letters as letters_of gives them: first appearance order.
        if (bcc::letter_count(letter) < 3) continue;
        std::array<int, 4> canon = bcc::letters_of(letter, {letter[0] < 0, letter[1] < 0, letter[2] < 0, letter[3] < 0});
        if (canon != letter) continue;
        for (int parity = 0; parity < 2; ++parity) {
            const bcc::MaterialStencil s = bcc::junction_stencil(letter, parity);
            long sum = 0;
            for (int t = 0; t < s.count; ++t) {
                const long v = vol6(s.tet[static_cast<std::size_t>(t)].tet);
                BOOST_TEST(v > 0);
                sum += v;
            }
            BOOST_TEST(sum == whole, "letters " << code << " parity " << parity);
            ++patterns;
        }
    }
    BOOST_TEST(patterns > 0);
}

// Nested spheres: two materials, the inner sphere's volume and the shell's
// near the exact ones, every interface face between the two.
BOOST_AUTO_TEST_CASE(nested_spheres_are_two_conforming_materials) {
    const auto f = parse_material_shapes3("1=sphere:0,0,0,1;2=sphere:0,0,0,0.5");
    const Lattice3 L = lattice3_for(f->bounds(), 0.08, f->describe());
    const BccMesh m = mesh_bcc_materials(*f, L, parity_options(), false);
    check_valid(m.mesh, "nested spheres");
    BOOST_TEST(m.verified);
    const BccClaim claim = bcc_claim(FaceRule::parity).value();
    check_angles(m.mesh, claim.min_deg, claim.max_deg, "nested spheres");
    const auto v = region_volumes(m.mesh);
    BOOST_TEST(v.size() == 2u);
    const double inner = 4.0 / 3 * std::numbers::pi * 0.125, shell = 4.0 / 3 * std::numbers::pi - inner;
    BOOST_TEST(std::abs(v.at(2) - inner) < 0.02 * inner);
    BOOST_TEST(std::abs(v.at(1) - shell) < 0.02 * shell);
    BOOST_TEST(!m.mesh.interfaces.empty());
    for (const auto& r : m.mesh.interface_regions) BOOST_TEST(((r[0] == 1 && r[1] == 2) || (r[0] == 2 && r[1] == 1)));
    BOOST_TEST(m.junction_background_tets == 0);
    // The background kept: a third region, tag 0, filling the lattice.
    const BccMesh k = mesh_bcc_materials(*f, L, parity_options(), true);
    check_valid(k.mesh, "nested spheres, background kept");
    BOOST_TEST(region_volumes(k.mesh).count(0) == 1u);
}

// Three boxes and a sphere meeting along lines and at points: junctions.
BOOST_AUTO_TEST_CASE(meeting_shapes_make_valid_junctions) {
    const auto f = parse_material_shapes3(
        "1=box:-1,-1,-1,0.03,1,1;2=box:0.03,-1,-1,1,0.013,1;3=box:0.03,0.013,-1,1,1,1;4=sphere:0.03,0.013,0.2,0.4");
    const Lattice3 L = lattice3_for(f->bounds(), 0.1, f->describe());
    for (const bool keep : {false, true}) {
        const BccMesh m = mesh_bcc_materials(*f, L, parity_options(), keep);
        check_valid(m.mesh, keep ? "meeting shapes, background kept" : "meeting shapes");
        BOOST_TEST(m.junction_background_tets > 0);
        BOOST_TEST(region_volumes(m.mesh).size() == (keep ? 5u : 4u));
    }
}

// Random label volumes: valid meshes at several spacings; renumbering the
// labels gives the same mesh with its regions renumbered.
BOOST_AUTO_TEST_CASE(random_label_volumes_mesh_validly_and_ignore_label_numbers) {
    std::mt19937 rng(7);
    for (int trial = 0; trial < 12; ++trial) {
        const Volume v = random_labels(14, {3, 17, 5, 900}, rng);
        Volume w = v;
        const std::map<int, int> bijection{{0, 0}, {3, 61}, {17, 2}, {5, 40000}, {900, 8}};
        for (double& x : w.values) x = bijection.at(static_cast<int>(x));
        // Spacings on and off the voxels; trials 0 and 3 put lattice points on
        // voxel centres and cell centres (exact ties between materials).
        const double spacing = trial % 3 == 0 ? 1.0 : trial % 3 == 1 ? 0.7 : 1.3;
        const bool at_min = trial % 6 == 0 || trial % 6 == 3 || trial % 6 == 4;
        for (const bool keep : {false, true}) {
            const auto f = make_volume_materials3(v, "all"), g = make_volume_materials3(w, "all");
            const Lattice3 L = lattice3_for(f->bounds(), trial == 3 ? 0.5 : spacing, f->describe(), at_min);
            const BccMesh a = mesh_bcc_materials(*f, L, parity_options(), keep);
            const BccMesh b = mesh_bcc_materials(*g, L, parity_options(), keep);
            check_valid(a.mesh, "random labels " + std::to_string(trial));
            if (a.junction_tets == 0) {
                const BccClaim claim = bcc_claim(FaceRule::parity).value();
                check_angles(a.mesh, claim.min_deg, claim.max_deg, "random labels " + std::to_string(trial));
            }
            BOOST_TEST(a.mesh.tets.size() == b.mesh.tets.size());
            BOOST_TEST(a.mesh.vertices.size() == b.mesh.vertices.size());
            bool same = a.mesh.tets.size() == b.mesh.tets.size() && a.mesh.vertices.size() == b.mesh.vertices.size();
            for (std::size_t t = 0; same && t < a.mesh.tets.size(); ++t)
                same = a.mesh.tets[t] == b.mesh.tets[t] && bijection.at(a.mesh.region[t]) == b.mesh.region[t];
            for (std::size_t i = 0; same && i < a.mesh.vertices.size(); ++i)
                same = a.mesh.vertices[i].x == b.mesh.vertices[i].x && a.mesh.vertices[i].y == b.mesh.vertices[i].y &&
                       a.mesh.vertices[i].z == b.mesh.vertices[i].z;
            BOOST_TEST(same, "trial " << trial << " keep " << keep);
        }
    }
}

// Per-label volumes follow the voxels: a ball of one label in a block of
// another.
BOOST_AUTO_TEST_CASE(label_volumes_follow_the_voxel_counts) {
    Volume v;
    const int n = 24;
    v.dims = {n, n, n};
    v.values.assign(static_cast<std::size_t>(n) * n * n, 0);
    for (int k = 2; k < n - 2; ++k)
        for (int j = 2; j < n - 2; ++j)
            for (int i = 2; i < n - 2; ++i) {
                const double r2 = (i - 11.5) * (i - 11.5) + (j - 11.5) * (j - 11.5) + (k - 11.5) * (k - 11.5);
                v.values[static_cast<std::size_t>(i + n * (j + n * k))] = r2 < 36 ? 7 : 4;
            }
    const auto f = make_volume_materials3(v, "all");
    const Lattice3 L = lattice3_for(f->bounds(), 1.0, f->describe());
    const BccMesh m = mesh_bcc_materials(*f, L, parity_options(), false);
    check_valid(m.mesh, "ball in a block");
    const auto vol = region_volumes(m.mesh);
    for (const int label : {4, 7}) {
        const int mi = label == 4 ? 1 : 2;
        const double ref = *f->reference_volume(mi);
        BOOST_TEST(std::abs(vol.at(label) - ref) < 0.05 * ref, "label " << label << ": " << vol.at(label) << " vs " << ref);
    }
}

// Planes through the lattice near its points make all-zero background
// tetrahedra (four warped vertices): the flat ones are left out, counted,
// the others output within the claim; without a fill claim, all are left out.
BOOST_AUTO_TEST_CASE(all_zero_tetrahedra_are_filled_only_within_the_claim) {
    const auto f = parse_material_shapes3("1=box:-1,-1,-1,0.03,1,1;2=box:0.03,-1,-1,1,0.013,1;3=box:0.03,0.013,-1,1,1,1");
    const Lattice3 L = lattice3_for(f->bounds(), 0.05, f->describe());
    const BccMesh m = mesh_bcc_materials(*f, L, parity_options(), false);
    check_valid(m.mesh, "three boxes");
    BOOST_TEST(m.all_zero_left_out + m.all_zero_filled > 0);
    BccOptions none = parity_options();
    none.fill_claim.reset();
    const BccMesh n = mesh_bcc_materials(*f, L, none, false);
    check_valid(n.mesh, "three boxes, no fill");
    BOOST_TEST(n.all_zero_filled == 0);
    BOOST_TEST(n.all_zero_left_out == m.all_zero_left_out + m.all_zero_filled);
    BOOST_TEST(n.mesh.tets.size() + static_cast<std::size_t>(m.all_zero_filled) == m.mesh.tets.size());
}

// Bad input: label 0 listed, absent labels named, non-integer labels.
BOOST_AUTO_TEST_CASE(bad_material_volumes_are_refused_by_name) {
    Volume v;
    v.dims = {3, 3, 3};
    v.values.assign(27, 0);
    v.values[13] = 5;
    v.source = "tiny.nrrd";
    BOOST_CHECK_EXCEPTION(make_volume_materials3(v, "0,5"), InputError,
                          [](const InputError& e) { return std::string(e.what()).find("label 0 is the background") != std::string::npos; });
    BOOST_CHECK_EXCEPTION(make_volume_materials3(v, "5,6"), InputError,
                          [](const InputError& e) { return std::string(e.what()).find("not present in the volume: 6") != std::string::npos; });
    v.values[0] = 2.5;
    BOOST_CHECK_EXCEPTION(make_volume_materials3(v, "all"), InputError,
                          [](const InputError& e) { return std::string(e.what()).find("voxel (0, 0, 0) is 2.5") != std::string::npos; });
    BOOST_CHECK_THROW(parse_material_shapes3("1=sphere:0,0,0,1;1=sphere:0,0,0,2"), InputError);
    const auto f = parse_material_shapes3("1=sphere:0,0,0,1");
    BOOST_CHECK_THROW(mesh_bcc_materials(*f, lattice3_for(f->bounds(), 0.2, "s"), BccOptions{}, false), InputError);  // Delaunay
}

// Blocks merge into exactly the whole multi-material mesh: nested spheres,
// meeting shapes with junctions, random label volumes.
BOOST_AUTO_TEST_CASE(material_blocks_merge_into_exactly_the_whole_mesh) {
    std::mt19937 rng(47);
    const auto spheres = parse_material_shapes3("1=sphere:0,0,0,1;2=sphere:0,0,0,0.5");
    check_blocks_merge(*spheres, lattice3_for(spheres->bounds(), 0.15, spheres->describe()), rng, "nested spheres");
    const auto meeting = parse_material_shapes3(
        "1=box:-1,-1,-1,0.03,1,1;2=box:0.03,-1,-1,1,0.013,1;3=box:0.03,0.013,-1,1,1,1;4=sphere:0.03,0.013,0.2,0.4");
    const Lattice3 L = lattice3_for(meeting->bounds(), 0.1, meeting->describe());
    BOOST_TEST(mesh_bcc_materials(*meeting, L, parity_options(), false).junction_tets > 0);
    check_blocks_merge(*meeting, L, rng, "meeting shapes");
    for (int trial = 0; trial < testing::scaled(4); ++trial) {
        const Volume v = random_labels(14, {3, 17, 5, 900}, rng);
        const auto f = make_volume_materials3(v, "all");
        // Even trials: lattice points on the voxel centres (exact ties between materials).
        const double spacing = trial % 2 == 0 ? 1.0 : 0.7;
        check_blocks_merge(*f, lattice3_for(f->bounds(), spacing, f->describe(), trial % 2 == 0), rng, "random labels " + std::to_string(trial));
    }
}

// A block's window grows by its halo until it decides the block's points as
// the whole lattice does: blocks one cube thick along planes of warped
// points and all-zero background tetrahedra (filled and left out) merge
// into the whole mesh; a block's keys are sorted and it has a region per
// tetrahedron.
BOOST_AUTO_TEST_CASE(thin_material_blocks_along_junction_planes_merge_exactly) {
    const auto f = parse_material_shapes3(
        "1=box:-1,-1,-1,0.03,1,1;2=box:0.03,-1,-1,1,0.013,1;3=box:0.03,0.013,-1,1,1,1;4=sphere:0.03,0.013,0.2,0.4");
    const Lattice3 L = lattice3_for(f->bounds(), 0.05, f->describe());
    const BccMesh whole = mesh_bcc_materials(*f, L, parity_options(), false);
    BOOST_TEST(whole.all_zero_filled > 0);
    BOOST_TEST(whole.all_zero_left_out > 0);
    BOOST_TEST(whole.junction_tets > 0);
    const std::int64_t x = static_cast<std::int64_t>((0.03 - L.origin.x) / L.spacing), y = static_cast<std::int64_t>((0.013 - L.origin.y) / L.spacing);
    std::vector<TetBlock> blocks;
    const std::array<std::int64_t, 5> xs{0, x, x + 1, x + 2, L.cubes[0]}, ys{0, y, y + 1, y + 2, L.cubes[1]};
    for (std::size_t i = 0; i + 1 < xs.size(); ++i)
        for (std::size_t j = 0; j + 1 < ys.size(); ++j)
            blocks.push_back(mesh_bcc_materials_block(*f, L, parity_options(), false, {{xs[i], ys[j], 0}, {xs[i + 1], ys[j + 1], L.cubes[2]}}));
    for (const TetBlock& b : blocks) {
        BOOST_TEST(std::is_sorted(b.vertex_key.begin(), b.vertex_key.end()));
        BOOST_TEST(std::is_sorted(b.tet_key.begin(), b.tet_key.end()));
        BOOST_TEST(b.region.size() == b.tets.size());
        BOOST_TEST(b.region_names == whole.mesh.region_names);
    }
    std::string why;
    BOOST_TEST(identical(merge_tet_blocks(blocks), whole.mesh, why), why);
}

// A block outside the lattice is refused; so are blocks of different meshes
// in one merge, and one-region blocks keep their one region.
BOOST_AUTO_TEST_CASE(material_blocks_outside_the_lattice_are_refused) {
    const auto f = parse_material_shapes3("1=sphere:0,0,0,1;2=sphere:0,0,0,0.5");
    const Lattice3 L = lattice3_for(f->bounds(), 0.2, f->describe());
    const auto refused = [&](const CubeRange& r) {
        BOOST_CHECK_EXCEPTION(mesh_bcc_materials_block(*f, L, parity_options(), false, r), InputError, [](const InputError& e) {
            return std::string(e.what()).find("not a range of the lattice's cubes") != std::string::npos;
        });
    };
    refused({{0, 0, 0}, {L.cubes[0] + 1, L.cubes[1], L.cubes[2]}});
    refused({{-1, 0, 0}, {2, 2, 2}});
    refused({{3, 0, 0}, {2, 2, 2}});
    BOOST_CHECK_THROW(mesh_bcc_materials_block(*f, L, BccOptions{}, false, {{0, 0, 0}, L.cubes}), InputError);  // Delaunay
    const CubeRange all{{0, 0, 0}, L.cubes};
    const std::vector<TetBlock> mixed{mesh_bcc_materials_block(*f, L, parity_options(), false, {{0, 0, 0}, {L.cubes[0] / 2, L.cubes[1], L.cubes[2]}}),
                                      mesh_bcc_materials_block(*f, L, parity_options(), true, {{L.cubes[0] / 2, 0, 0}, L.cubes})};
    BOOST_CHECK_THROW(merge_tet_blocks(mixed), std::invalid_argument);
    const auto ball = parse_shape3("sphere:0,0,0,1");
    BccOptions one;
    const std::vector<TetBlock> single{mesh_bcc_block(*ball, L, one, all)};
    const TetMesh m = merge_tet_blocks(single);
    BOOST_TEST(m.region_names.empty());
    BOOST_TEST(m.interfaces.empty());
    BOOST_TEST(std::all_of(m.region.begin(), m.region.end(), [](std::int32_t r) { return r == 1; }));
}
