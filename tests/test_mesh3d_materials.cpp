// Multi-material 3D meshes (mesh3d.hpp: mesh_bcc_materials;
// generic_bcc_materials.hpp): the stencils tile every background
// tetrahedron and both sides of an interface agree; meshes of nested and
// meeting shapes and of random label volumes are valid (orientation,
// conformity, boundary, interfaces exactly the faces between two regions);
// renumbering the labels gives the same mesh; per-material volumes follow
// the shapes and the voxels.
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
