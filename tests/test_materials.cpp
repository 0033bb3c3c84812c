// Multi-material meshes (materials.hpp): conformity and interfaces, the
// no-mixed-triangle property of the separating rule on thousands of random
// multi-material fields, equality with today's label mode for two materials,
// the fidelity and convergence order on analytic shapes, certification of the
// two-material squares, and the CLI's refusals.
#define BOOST_TEST_MODULE materials
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <sys/wait.h>
#include <unistd.h>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "certified_stage.hpp"
#include "label_images.hpp"
#include "same_mesh.hpp"
#include "support.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/mesh2d/graded.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "warpmesh/mesh2d/uniform.hpp"

using namespace warpmesh;
namespace fs = std::filesystem;
using warpmesh::testing::certified;
using warpmesh::testing::Certified;
using warpmesh::testing::scaled;
using warpmesh::testing::with_keys;

namespace {

constexpr double pi = 3.14159265358979323846;

// The random trials mesh thousands of tiny lattices: one thread each (a
// parallel region per pass would cost more than the mesh).
struct OneThread {
#ifdef _OPENMP
    int saved = omp_get_max_threads();
    OneThread() { omp_set_num_threads(1); }
    ~OneThread() { omp_set_num_threads(saved); }
#endif
};

// Random "power diagram" materials: phi_m = |p - c_m| - r_m, the nearest
// (most inside) disc wins; several materials meet at triple points.
class RandomDiscs final : public MaterialField {
public:
    RandomDiscs(std::mt19937& rng, int n, double size) {
        std::uniform_real_distribution<double> pos(0, size), rad(0, size / 3);
        for (int m = 0; m < n; ++m) c_.push_back({pos(rng), pos(rng), rad(rng)});
        size_ = size;
    }
    int count() const override { return static_cast<int>(c_.size()); }
    std::int32_t tag(int m) const override { return 10 + m; }  // tags != material numbers on purpose
    std::string name(int m) const override { return "disc_" + std::to_string(m); }
    Box bounds() const override { return {0, 0, size_, size_}; }
    std::string describe() const override { return "random discs"; }
    double phi(int m, double x, double y) const override {
        const auto& d = c_[static_cast<std::size_t>(m)];
        return std::hypot(x - d[0], y - d[1]) - d[2];
    }

private:
    std::vector<std::array<double, 3>> c_;
    double size_ = 1;
};

using warpmesh::testing::random_label_image;

// The properties every multi-material mesh must have:
//  * conforming and counter-clockwise (check_mesh), interfaces exactly the
//    interior edges between triangles of different regions (check_mesh);
//  * no triangle with two unwarped corners of different materials, and every
//    unwarped corner's material is its triangle's (checked from the mesh
//    alone: a vertex exactly at a lattice point is taken as unwarped);
//  * with the background kept, the only boundary is the lattice border.
void check_material_mesh(const MaterialField& f, const Lattice& l, const MaterialResult& r, bool keep, std::int64_t fans = 0) {
    const MeshCheck c = check_mesh(r.mesh);
    BOOST_REQUIRE_MESSAGE(c.ok(), (c.messages.empty() ? std::string("?") : c.messages[0]));
    BOOST_REQUIRE_EQUAL(r.mixed_triangles, 0);
    std::map<std::int32_t, int> material_of_tag;
    for (int m = 0; m < f.count(); ++m) material_of_tag[f.tag(m)] = m;
    for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t)
        for (const std::int32_t v : r.mesh.triangles[t]) {
            const Vec2 x = r.mesh.vertices[static_cast<std::size_t>(v)];
            const double fi = std::round((x.x - l.x0) / l.s), fj = std::round((x.y - l.y0) / l.s);
            const Vec2 p = l.position(static_cast<std::int64_t>(fi), static_cast<std::int64_t>(fj));
            if (p.x != x.x || p.y != x.y) continue;  // warped
            const int want = material_of_tag.at(r.mesh.region[t]);
            if (f.material_at(p.x, p.y) == want) continue;
            // A lattice point where two materials tie is on the interface:
            // it takes the tie rule's material (label_materials.cpp: the
            // nearest pixel's; shapes: the later) and warps by a zero-length slide.
            // (Looked for only on a mismatch: every material's phi at every
            // vertex would dominate the run time on the atlas.)
            std::vector<double> phi;
            for (int m = 0; m < f.count(); ++m) phi.push_back(f.phi(m, p.x, p.y));
            std::sort(phi.begin(), phi.end());
            if (phi.size() > 1 && phi[0] == phi[1]) continue;
            BOOST_REQUIRE_EQUAL(f.material_at(p.x, p.y), want);
        }
    if (keep) {
        BOOST_REQUIRE_EQUAL(static_cast<std::int64_t>(r.mesh.boundary.size()), 2 * (l.nx + l.ny));
        for (const auto tag : r.mesh.boundary_tag) BOOST_REQUIRE_EQUAL(tag, boundary_domain);
        std::int64_t total = 0;
        for (const auto& m : r.materials) total += m.triangles;
        if (!r.graded) BOOST_REQUIRE_EQUAL(total, 2 * l.nx * l.ny + 2 * fans);  // graded: fewer, coarse leaves inside materials; a fan: 4
        BOOST_REQUIRE_EQUAL(static_cast<std::int64_t>(r.mesh.triangles.size()), total);
    }
}

// Edges as pairs of vertex positions: (a, b, left tag, right tag), a < b
// (tags swapped with the direction); boundary edges (a, b, tag, -1) directed.
using EdgeKey = std::tuple<double, double, double, double, std::int32_t, std::int32_t>;
std::set<EdgeKey> interface_keys(const Mesh& m) {
    std::set<EdgeKey> out;
    for (std::size_t k = 0; k < m.interfaces.size(); ++k) {
        Vec2 a = m.vertices[static_cast<std::size_t>(m.interfaces[k][0])], b = m.vertices[static_cast<std::size_t>(m.interfaces[k][1])];
        std::int32_t l = m.interface_regions[k][0], r = m.interface_regions[k][1];
        if (std::tie(b.x, b.y) < std::tie(a.x, a.y)) std::swap(a, b), std::swap(l, r);
        out.insert({a.x, a.y, b.x, b.y, l, r});
    }
    return out;
}
std::set<EdgeKey> boundary_keys(const Mesh& m) {
    std::set<EdgeKey> out;
    for (std::size_t k = 0; k < m.boundary.size(); ++k) {
        const Vec2 a = m.vertices[static_cast<std::size_t>(m.boundary[k][0])], b = m.vertices[static_cast<std::size_t>(m.boundary[k][1])];
        out.insert({a.x, a.y, b.x, b.y, m.boundary_tag[k], -1});
    }
    return out;
}

// The graded multi-material mesh against the uniform one on the same lattice:
// the properties of every multi-material mesh; the finest band is the
// uniform mesh's (the same warped squares, diagonals overridden, junctions,
// keyed squares and certified bounds; the same interface and boundary edges,
// as vertex positions); the coarse leaves tile exactly the rest of each
// material (the same per-material areas and perimeters, to rounding), with
// no more triangles; and the band invariant was checked (verify).
void check_graded_against_uniform(const MaterialField& f, const Lattice& l, const Certified<MaterialResult>& g,
                                  const Certified<MaterialResult>& u, bool keep) {
    BOOST_REQUIRE(g.graded);
    check_material_mesh(f, l, g, keep);
    BOOST_REQUIRE_GE(g.invariant_squares, 0);
    BOOST_REQUIRE_EQUAL(g.warped_squares, u.warped_squares);
    BOOST_REQUIRE_EQUAL(g.forced_diagonals, u.forced_diagonals);
    BOOST_REQUIRE_EQUAL(g.centroid_triangles, u.centroid_triangles);
    BOOST_REQUIRE_EQUAL(g.junction_squares, u.junction_squares);
    BOOST_REQUIRE_EQUAL(g.certified.keyed_squares, u.certified.keyed_squares);
    if (u.certified.available) {
        BOOST_REQUIRE(g.certified.verified);
        BOOST_REQUIRE_EQUAL(g.certified.min_deg, u.certified.min_deg);
    }
    BOOST_REQUIRE(interface_keys(g.mesh) == interface_keys(u.mesh));
    BOOST_REQUIRE(boundary_keys(g.mesh) == boundary_keys(u.mesh));
    BOOST_REQUIRE_LE(g.mesh.triangles.size(), u.mesh.triangles.size());
    BOOST_REQUIRE(g.mesh.region_names == u.mesh.region_names);
    const double scale = (l.nx * l.s) * (l.ny * l.s);
    for (std::size_t m = 0; m < u.materials.size(); ++m) {
        BOOST_REQUIRE_LE(g.materials[m].triangles, u.materials[m].triangles);
        BOOST_REQUIRE_SMALL(g.materials[m].area - u.materials[m].area, 1e-9 * scale);
        BOOST_REQUIRE_SMALL(g.materials[m].perimeter - u.materials[m].perimeter, 1e-9 * scale);
    }
}

// The longest edge of each region tag's triangles.
std::map<std::int32_t, double> longest_edge_per_tag(const Mesh& m) {
    std::map<std::int32_t, double> out;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const Vec2 a = m.vertices[static_cast<std::size_t>(m.triangles[t][k])];
            const Vec2 b = m.vertices[static_cast<std::size_t>(m.triangles[t][(k + 1) % 3])];
            double& l = out[m.region[t]];
            l = std::max(l, std::hypot(b.x - a.x, b.y - a.y));
        }
    return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(random_discs_give_conforming_meshes_without_mixed_triangles) {
    const OneThread one;
    std::mt19937 rng(15);
    std::uniform_real_distribution<double> spacing(0.35, 1.3);
    std::int64_t junctions = 0, centroid = 0, interfaces = 0, graded_tris = 0, uniform_tris = 0, coarse = 0;
    for (int trial = 0; trial < scaled(3000); ++trial) {
        const RandomDiscs f(rng, 2 + trial % 5, 8);
        const Lattice l = lattice_over(f.bounds(), spacing(rng));
        const bool keep = trial % 2 == 0;
        const auto r = certified(mesh_materials(f, l, {keep, DiagonalRule::separating, with_keys}), l, DiagonalRule::separating);
        check_material_mesh(f, l, r, keep);
        junctions += r.junction_squares;
        centroid += r.centroid_triangles;
        interfaces += static_cast<std::int64_t>(r.mesh.interfaces.size());
        // The same field graded (max cell 0, 2, 4, 8 in turn).
        const std::int64_t max_cell = trial % 4 ? std::int64_t{1} << (trial % 4) : 0;
        const auto g = certified(mesh_materials_graded(f, l, {keep, DiagonalRule::separating, with_keys}, max_cell), l, DiagonalRule::separating);
        check_graded_against_uniform(f, l, g, r, keep);
        graded_tris += static_cast<std::int64_t>(g.mesh.triangles.size());
        uniform_tris += static_cast<std::int64_t>(r.mesh.triangles.size());
        coarse += g.leaves_per_level.size() > 1 ? g.leaves_per_level[1] : 0;
    }
    // The trials must have exercised what they test.
    BOOST_TEST(junctions > scaled(100));
    BOOST_TEST(interfaces > scaled(10000));
    BOOST_TEST(coarse > scaled(1000));  // the graded meshes did coarsen
    BOOST_TEST(graded_tris < uniform_tris);
    BOOST_TEST_MESSAGE("junction squares " << junctions << ", centroid-material triangles " << centroid);
}

// The fan rule with materials (issue 28 item 2): on random discs and label
// images every mesh is conforming with no mixed triangle, every fan is one
// material (so the interfaces are the separating rule's wherever no fan is
// taken), the graded mesh keeps the uniform band, fans included, and the
// certified floor is the fan rule's 18.4349 deg, junction squares included,
// every triangle verified against it.
BOOST_AUTO_TEST_CASE(fan_rule_with_materials_is_conforming_and_certified_at_18_4) {
    const OneThread one;
    std::mt19937 rng(2828);
    std::uniform_real_distribution<double> spacing(0.35, 1.3);
    std::int64_t fans = 0, junctions = 0, fan_cases = 0;
    for (int trial = 0; trial < scaled(600); ++trial) {
        std::unique_ptr<MaterialField> owned;
        std::optional<RandomDiscs> discs;
        const MaterialField* f = nullptr;
        if (trial % 2 == 0) {
            discs.emplace(rng, 2 + trial % 5, 8);
            f = &*discs;
        } else {
            try {
                owned = make_label_materials(random_label_image(rng, 5 + trial % 6, 4 + trial % 7, 2 + trial % 4), "all");
            } catch (const InputError&) {  // only label 0 drawn
                continue;
            }
            f = owned.get();
        }
        const Lattice l = lattice_over(f->bounds(), trial % 4 == 1 ? 1.0 : spacing(rng));
        const auto sep = certified(mesh_materials(*f, l, {true, DiagonalRule::separating, with_keys}), l, DiagonalRule::separating);
        const auto r = certified(mesh_materials(*f, l, {true, DiagonalRule::fan, with_keys}), l, DiagonalRule::fan);
        const auto n = static_cast<std::int64_t>(r.mesh.vertices.size() - sep.mesh.vertices.size());  // the fans' centres
        BOOST_TEST_CONTEXT("trial " << trial << " spacing " << l.s) {
            check_material_mesh(*f, l, r, true, n);
            BOOST_REQUIRE(r.certified.verified);
            BOOST_REQUIRE_GE(r.certified.min_deg, 18.4349);
            if (r.junction_squares > 0) BOOST_REQUIRE_GE(certified_junction_theorem(DiagonalRule::fan).min_deg_any, 18.4349);
            for (const auto& e : r.junction_examples) BOOST_REQUIRE_GE(e.min_deg, 18.4349);
            // Without a fan the rule is the separating rule: the same mesh.
            if (n == 0) {
                BOOST_REQUIRE(r.mesh.triangles == sep.mesh.triangles);
                BOOST_REQUIRE(r.mesh.region == sep.mesh.region);
            }
            const auto g = certified(mesh_materials_graded(*f, l, {trial % 3 == 0, DiagonalRule::fan, with_keys}, 4), l, DiagonalRule::fan);
            const auto u = trial % 3 == 0 ? r : certified(mesh_materials(*f, l, {false, DiagonalRule::fan, with_keys}), l, DiagonalRule::fan);
            check_graded_against_uniform(*f, l, g, u, trial % 3 == 0);
        }
        fans += n;
        fan_cases += n > 0;
        junctions += r.junction_squares;
    }
    // (Random fields rarely have a square below atan(1/3), so the fans are
    // few or none here: test_fan_rule.cpp realises one on purpose.)
    BOOST_TEST_MESSAGE("fans " << fans << " in " << fan_cases << " meshes, junction squares " << junctions);
    BOOST_TEST(junctions > scaled(100));
}

BOOST_AUTO_TEST_CASE(random_label_images_give_conforming_meshes_without_mixed_triangles) {
    const OneThread one;
    std::mt19937 rng(1515);
    const std::array<double, 4> spacings{1.0, 0.5, 0.37, 1.6};
    std::int64_t junctions = 0;
    for (int trial = 0; trial < scaled(1500); ++trial) {
        const Image img = random_label_image(rng, 5 + trial % 6, 4 + trial % 7, 2 + trial % 4);
        std::unique_ptr<MaterialField> f;
        try {
            f = make_label_materials(img, "all");
        } catch (const InputError&) {  // only label 0 drawn
            continue;
        }
        const Lattice l = lattice_over(f->bounds(), spacings[static_cast<std::size_t>(trial % 4)]);
        const bool keep = trial % 3 != 0;
        const auto r = certified(mesh_materials(*f, l, {keep, DiagonalRule::separating, with_keys}), l, DiagonalRule::separating);
        check_material_mesh(*f, l, r, keep);
        junctions += r.junction_squares;
        const auto g = certified(mesh_materials_graded(*f, l, {keep, DiagonalRule::separating, with_keys}, 0), l, DiagonalRule::separating);
        check_graded_against_uniform(*f, l, g, r, keep);
    }
    BOOST_TEST(junctions > scaled(50));
}

// For two materials (one label and the background) the multi-material mesher
// is today's label mode: same vertices, same triangles in the same order, same
// tags, the same boundary (as a set) — the generalised rule reduces to the
// certified two-material rule.  (Where a lattice point lies exactly on the
// interface — label mode's zero-valued points, e.g. midway between pixel
// centres at spacing 1/2 — the two differ by design: label mode keeps such a
// point as an inside point, the materials give it the larger material and a
// zero-length warp.  Spacings that put no point there are used.)
BOOST_AUTO_TEST_CASE(two_materials_reproduce_label_mode_exactly) {
    const OneThread one;
    std::mt19937 rng(7);
    for (int trial = 0; trial < scaled(60); ++trial) {
        Image img = random_label_image(rng, 12, 10, 1);
        bool any = false;
        for (auto v : img.pixels) any = any || v == 1;
        if (!any) continue;
        for (const double s : {1.0, 0.6180339887, 0.3819660113, 1.4142135623}) {
            const auto f = make_label_materials(img, "1");
            const auto g = make_image_levelset(img, label_options("1"));
            const Lattice l = lattice_over(f->bounds(), s);
            const MaterialResult a = mesh_materials(*f, l, {false, DiagonalRule::separating, {}});
            const UniformResult b = mesh_uniform(*g, l, DiagonalRule::separating);
            warpmesh::testing::require_same_points_and_triangles(a.mesh, b.mesh, [](std::int32_t t) { return t; });
            auto edges = [](const Mesh& m) {
                std::set<std::array<std::int32_t, 3>> e;
                for (std::size_t k = 0; k < m.boundary.size(); ++k) e.insert({m.boundary[k][0], m.boundary[k][1], m.boundary_tag[k]});
                return e;
            };
            BOOST_REQUIRE(edges(a.mesh) == edges(b.mesh));
            BOOST_REQUIRE(a.mesh.interfaces.empty());
        }
    }
}

// ---- fidelity on analytic shapes ---------------------------------------------------
// Circle 1: centre (0, 0), radius 10; circle 2 (later, wins): centre
// (7.3, 0.9), radius 6.2 — placed so that the triple points, where the circles
// cross, are not lattice points.  Interfaces: 1|0 the arc of circle 1 outside
// circle 2; 2|0 the arc of circle 2 outside circle 1; 2|1 the arc of circle 2
// inside circle 1.
namespace fidelity {

struct Arc {
    double cx, cy, r, a0, a1;  // angles a0 .. a1 (radians, a0 < a1)
    double distance(double x, double y) const {
        double a = std::atan2(y - cy, x - cx);
        while (a < a0) a += 2 * pi;
        if (a <= a1) return std::abs(std::hypot(x - cx, y - cy) - r);
        return std::min(std::hypot(x - cx - r * std::cos(a0), y - cy - r * std::sin(a0)),
                        std::hypot(x - cx - r * std::cos(a1), y - cy - r * std::sin(a1)));
    }
    Vec2 at(double u) const { const double a = a0 + u * (a1 - a0); return {cx + r * std::cos(a), cy + r * std::sin(a)}; }
};

double segment_distance(Vec2 p, Vec2 a, Vec2 b) {
    const double dx = b.x - a.x, dy = b.y - a.y, L = dx * dx + dy * dy;
    const double u = L > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / L, 0.0, 1.0) : 0;
    return std::hypot(p.x - a.x - u * dx, p.y - a.y - u * dy);
}

struct Row {
    double s, area_err1, area_err2, hausdorff, hausdorff_smooth;
};

Row measure(double s) {
    const auto f = parse_material_shapes("1=circle:0,0,10;2=circle:7.3,0.9,6.2");
    const Lattice l = lattice_around(f->bounds(), s);
    const MaterialResult r = mesh_materials(*f, l, {true, DiagonalRule::separating, {}});
    BOOST_REQUIRE(check_mesh(r.mesh).ok());
    const double cx = 7.3, cy = 0.9, d = std::hypot(cx, cy), r1 = 10, r2 = 6.2;
    const double phi = std::atan2(cy, cx), b1 = std::acos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1)),
                 b2 = std::acos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2)), psi = phi + pi;
    const std::map<std::pair<int, int>, Arc> arcs{{{1, 0}, {0, 0, r1, phi + b1, phi + 2 * pi - b1}},
                                                 {{2, 0}, {cx, cy, r2, psi + b2, psi + 2 * pi - b2}},
                                                 {{2, 1}, {cx, cy, r2, psi - b2, psi + b2}}};
    const std::array<Vec2, 2> triple{{{r1 * std::cos(phi + b1), r1 * std::sin(phi + b1)}, {r1 * std::cos(phi - b1), r1 * std::sin(phi - b1)}}};
    // Exact areas: circle 2 whole; circle 1 minus the lens.
    const double lens = r1 * r1 * std::acos((d * d + r1 * r1 - r2 * r2) / (2 * d * r1)) +
                        r2 * r2 * std::acos((d * d + r2 * r2 - r1 * r1) / (2 * d * r2)) -
                        0.5 * std::sqrt((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2));
    Row row{s, std::abs(r.materials[1].area - (pi * r1 * r1 - lens)), std::abs(r.materials[2].area - pi * r2 * r2), 0, 0};
    auto near_triple = [&](Vec2 p) {
        return std::min(std::hypot(p.x - triple[0].x, p.y - triple[0].y), std::hypot(p.x - triple[1].x, p.y - triple[1].y)) < 3 * s;
    };
    for (const auto& [pair, arc] : arcs) {
        std::vector<std::array<Vec2, 2>> segs;
        for (std::size_t k = 0; k < r.mesh.interfaces.size(); ++k) {
            const auto& lr = r.mesh.interface_regions[k];
            if (std::minmax(lr[0], lr[1]) != std::minmax(pair.first, pair.second)) continue;
            segs.push_back({r.mesh.vertices[static_cast<std::size_t>(r.mesh.interfaces[k][0])],
                            r.mesh.vertices[static_cast<std::size_t>(r.mesh.interfaces[k][1])]});
        }
        BOOST_REQUIRE(!segs.empty());
        for (const auto& e : segs)  // mesh → curve
            for (int q = 0; q <= 4; ++q) {
                const Vec2 p{e[0].x + q / 4.0 * (e[1].x - e[0].x), e[0].y + q / 4.0 * (e[1].y - e[0].y)};
                const double dist = arc.distance(p.x, p.y);
                row.hausdorff = std::max(row.hausdorff, dist);
                if (!near_triple(p)) row.hausdorff_smooth = std::max(row.hausdorff_smooth, dist);
            }
        for (int q = 0; q <= 1500; ++q) {  // curve → mesh
            const Vec2 p = arc.at(q / 1500.0);
            double best = 1e300;
            for (const auto& e : segs) best = std::min(best, segment_distance(p, e[0], e[1]));
            row.hausdorff = std::max(row.hausdorff, best);
            if (!near_triple(p)) row.hausdorff_smooth = std::max(row.hausdorff_smooth, best);
        }
    }
    return row;
}

}  // namespace fidelity

BOOST_AUTO_TEST_CASE(analytic_materials_converge) {
    std::vector<fidelity::Row> rows;
    for (const double s : {1.0, 0.5, 0.25, 0.125, 0.0625}) rows.push_back(fidelity::measure(s));
    auto order = [&](double fidelity::Row::*field) {
        return std::log((rows.front().*field) / (rows.back().*field)) / std::log(rows.front().s / rows.back().s);
    };
    BOOST_TEST_MESSAGE("| spacing | area error 1 | area error 2 | Hausdorff (all) | Hausdorff (>= 3 s from triple points) |");
    char line[200];
    for (const auto& r : rows) {
        std::snprintf(line, sizeof line, "| %g | %.3g | %.3g | %.3g | %.3g |", r.s, r.area_err1, r.area_err2, r.hausdorff, r.hausdorff_smooth);
        BOOST_TEST_MESSAGE(line);
    }
    std::snprintf(line, sizeof line, "| order | %.2f | %.2f | %.2f | %.2f |", order(&fidelity::Row::area_err1),
                  order(&fidelity::Row::area_err2), order(&fidelity::Row::hausdorff), order(&fidelity::Row::hausdorff_smooth));
    BOOST_TEST_MESSAGE(line);
    // Two-material interfaces: vertices on the curve, chords between them: second order.
    BOOST_TEST(order(&fidelity::Row::hausdorff_smooth) > 1.7);
    // At the triple points the warped lattice only approximates the junction: first order.
    BOOST_TEST(order(&fidelity::Row::hausdorff) > 0.8);
    BOOST_TEST(rows.back().hausdorff < 0.1);
    BOOST_TEST(order(&fidelity::Row::area_err2) > 1.5);
    BOOST_TEST(order(&fidelity::Row::area_err1) > 1.5);
}

// Every warped square is looked up and verified: those with at most two
// materials by their sign keys, the junction squares (3 or 4 materials) by
// their junction keys (proofs/materials.cert).  The mesh's certified floor
// includes the junction squares, and no triangle is left without a bound.
BOOST_AUTO_TEST_CASE(junction_squares_are_certified_and_verified) {
    const auto f = parse_material_shapes("1=circle:0,0,10;2=circle:7.3,0.9,6.2");
    const Lattice l = lattice_around(f->bounds(), 0.5);
    const auto r = certified(mesh_materials(*f, l, {false, DiagonalRule::separating, with_keys}), l, DiagonalRule::separating);
    BOOST_REQUIRE(certified_table_available());
    BOOST_REQUIRE(certified_junction_key_count() > 0);
    BOOST_REQUIRE(r.certified.available);
    BOOST_TEST(r.certified.verified);
    BOOST_TEST(r.certified.keyed_squares > 100);
    BOOST_TEST(r.junction_squares >= 1);  // where the three materials meet
    BOOST_TEST(r.certified.junction_squares == r.junction_squares);
    BOOST_TEST(r.junction_examples.size() == static_cast<std::size_t>(std::min<std::int64_t>(r.junction_squares, 20)));
    double junction_floor = 180;
    for (const auto& e : r.junction_examples) {
        std::set<std::int32_t> tags(e.tags.begin(), e.tags.end());
        BOOST_TEST(tags.size() >= 3u);
        BOOST_TEST(e.pattern.size() == 8u);
        BOOST_TEST(e.min_deg > 14.99);
        BOOST_TEST(e.max_deg < 180);
        BOOST_TEST(e.min_deg >= certified_junction_theorem().min_deg_any);
        junction_floor = std::min(junction_floor, e.min_deg);
    }
    // Every triangle carries its square's bound (no 0 = "no bound"), and the
    // mesh's floor is at most every junction square's.
    const auto& cell = r.mesh.cell_data.at(0).second;
    for (std::size_t k = 0; k < cell.size(); ++k) BOOST_REQUIRE(cell[k] > 14.99);
    BOOST_TEST(r.certified.min_deg <= junction_floor);
    BOOST_TEST(r.certified.min_deg > 14.99);
}

// Every label of the brain-atlas slice, graded: the finest band along every
// interface is the uniform mesh's, the materials' interiors are coarser.
BOOST_AUTO_TEST_CASE(graded_atlas_slice_keeps_the_uniform_band_and_coarsens_inside) {
    const Image img = read_image(WARPMESH_SOURCE_DIR "/mesher/examples/brain_axial_s128_labels16.pgm");
    const auto f = make_label_materials(img, "all");
    for (const double s : {1.0, 0.5}) {
        if (s < 1 && warpmesh::testing::test_scale() < 1) continue;  // the finer lattice only at full scale
        const Lattice l = lattice_over(f->bounds(), s);
        const auto u = certified(mesh_materials(*f, l, {false, DiagonalRule::separating, with_keys}), l, DiagonalRule::separating);
        const auto g = certified(mesh_materials_graded(*f, l, {false, DiagonalRule::separating, with_keys}, 0), l, DiagonalRule::separating);
        check_graded_against_uniform(*f, l, g, u, false);
        BOOST_TEST_MESSAGE("atlas s = " << s << ": uniform " << u.mesh.triangles.size() << ", graded " << g.mesh.triangles.size()
                                        << " triangles");
        // Thin structures: little interior at s = 1 (28128 against 30590), more at s = 1/2 (93488 against 131060).
        BOOST_TEST(g.mesh.triangles.size() < u.mesh.triangles.size());
        if (s < 1) BOOST_TEST(g.mesh.triangles.size() * 5 < u.mesh.triangles.size() * 4);  // at least 20 % fewer
        const auto gk = certified(mesh_materials_graded(*f, l, {true, DiagonalRule::separating, {true, false}}, 8), l,
                                  DiagonalRule::separating, {true, true, false});
        BOOST_TEST(gk.leaves_per_level.size() == 4u);  // max cell 8: levels 0 .. 3
        check_material_mesh(*f, l, gk, true);
    }
}

// Size control of graded multi-material meshes on random fields: a global
// max cell K, a grading buffer n and per-material caps K_m (max_cell_of).
// Every mesh has the properties of a graded multi-material mesh against the
// uniform one (check_graded_against_uniform: conforming, no mixed triangle,
// the band invariant checked, the same interfaces and boundary edges as
// vertex positions — the caps add no critical point, so the band is
// unchanged); every triangle of material m has its longest edge at most
// max(√2 min(K_m, K) s, √5 s), every triangle at most max(√2 K s, √5 s); a
// capped material has at least the uncapped mesh's triangles (the capped
// tree refines the uncapped one).
BOOST_AUTO_TEST_CASE(random_graded_sized_materials_respect_every_cap_and_keep_the_band) {
    const OneThread one;
    std::mt19937 rng(18);
    std::uniform_real_distribution<double> spacing(0.2, 0.9);
    std::int64_t refined = 0, capped_materials = 0;
    for (int trial = 0; trial < scaled(300); ++trial) {
        const RandomDiscs f(rng, 2 + trial % 4, 16);
        const Lattice l = lattice_over(f.bounds(), spacing(rng));
        const bool keep = trial % 3 == 0;
        const MaterialOptions o{keep, DiagonalRule::separating, with_keys};
        const std::int64_t K = trial % 5 ? std::int64_t{1} << (2 + trial % 4) : 0;  // 0, 8, 16, 32, 4
        const int buffer = std::array<int, 4>{0, 2, 3, 8}[static_cast<std::size_t>(trial % 4)];
        std::vector<std::int64_t> caps(static_cast<std::size_t>(f.count()));
        std::uniform_int_distribution<int> pick(0, 3);
        for (std::size_t m = keep ? 0 : 1; m < caps.size(); ++m) {
            const int c = pick(rng);
            caps[m] = c == 0 ? 0 : std::int64_t{1} << (c - 1);  // 0 (none), 1, 2, 4
        }
        BOOST_TEST_CONTEXT("trial " << trial << " s " << l.s << " K " << K << " buffer " << buffer) {
            const auto u = certified(mesh_materials(f, l, o), l, o.rule);
            const auto g0 = certified(mesh_materials_graded(f, l, o, K, buffer), l, o.rule);
            const auto g = certified(mesh_materials_graded(f, l, o, K, buffer, caps), l, o.rule);
            check_graded_against_uniform(f, l, g0, u, keep);
            check_graded_against_uniform(f, l, g, u, keep);
            const auto longest = longest_edge_per_tag(g.mesh);
            const double band = std::sqrt(5.0) * l.s * (1 + 1e-12);
            for (int m = keep ? 0 : 1; m < f.count(); ++m) {
                const auto it = longest.find(f.tag(m));
                if (it == longest.end()) continue;
                const std::int64_t Km = caps[static_cast<std::size_t>(m)] == 0 ? K
                                        : K == 0                           ? caps[static_cast<std::size_t>(m)]
                                                                           : std::min(K, caps[static_cast<std::size_t>(m)]);
                if (Km != 0) BOOST_REQUIRE_LE(it->second, std::max(std::sqrt(2.0) * static_cast<double>(Km) * l.s * (1 + 1e-12), band));
                if (caps[static_cast<std::size_t>(m)] != 0) {
                    ++capped_materials;
                    BOOST_REQUIRE_GE(g.materials[static_cast<std::size_t>(m)].triangles, g0.materials[static_cast<std::size_t>(m)].triangles);
                    refined += g.materials[static_cast<std::size_t>(m)].triangles > g0.materials[static_cast<std::size_t>(m)].triangles;
                }
            }
        }
    }
    BOOST_TEST_MESSAGE("capped materials " << capped_materials << ", of which refined by their cap " << refined);
    BOOST_TEST(capped_materials > scaled(300));
    BOOST_TEST(refined > scaled(50));  // the caps did refine (many random materials are too thin for their cap to bind)
}

// Issue 18: --max-size and --grading were silently ignored by graded
// multi-material meshes (mesh(MaterialField) dropped them).  Now every
// triangle's longest edge is at most max_size there, a grading below 2 adds
// triangles, the report names them, and max_size_of caps one material.
BOOST_AUTO_TEST_CASE(graded_materials_honour_max_size_grading_and_max_size_of) {
    const auto f = parse_material_shapes("1=circle:0,0,30;2=circle:20,0,14;3=rect:-6,-6,6,40");
    MeshOptions o;
    o.spacing = 0.5, o.graded = true;
    const MeshResult plain = mesh(*f, o);
    const auto longest_plain = longest_edge_per_tag(plain.mesh);
    double top = 0;
    for (const auto& [tag, l] : longest_plain) top = std::max(top, l);
    BOOST_TEST(top > 5.0);  // without a bound the interiors coarsen beyond it (cells of 8 squares)
    o.max_size = 3;
    const MeshResult sized = mesh(*f, o);
    for (const auto& [tag, l] : longest_edge_per_tag(sized.mesh)) BOOST_TEST(l <= 3 * (1 + 1e-12), "tag " << tag << ": " << l);
    BOOST_TEST(to_json(sized).find("\"max_size\": 3") != std::string::npos);
    o.max_size = 0, o.grading = 1.2;
    const MeshResult graded = mesh(*f, o);
    BOOST_TEST(graded.mesh.triangles.size() > plain.mesh.triangles.size());
    BOOST_TEST(to_json(graded).find("\"grading_buffer\": 4") != std::string::npos);
    o.grading = 2, o.max_size_of = {{1, 2.5}};
    const MeshResult capped = mesh(*f, o);
    const auto longest = longest_edge_per_tag(capped.mesh);
    BOOST_TEST(longest.at(1) <= 2.5);
    BOOST_TEST(longest.at(2) <= longest_plain.at(2));  // the capped tree refines the plain one
    BOOST_TEST(interface_keys(capped.mesh) == interface_keys(plain.mesh));
    BOOST_TEST(boundary_keys(capped.mesh) == boundary_keys(plain.mesh));
    const std::string json = to_json(capped);
    BOOST_TEST(json.find("\"max_size_of\": [{\"tag\": 1, \"max_size\": 2.5, \"max_cell\": 2}]") != std::string::npos, json.substr(0, 600));
    BOOST_TEST(json.find("\"longest_edge\": ") != std::string::npos);
    BOOST_TEST(to_text(capped).find("(max size 2.5)") != std::string::npos);
    BOOST_TEST(to_json(plain).find("longest_edge") == std::string::npos);  // default reports unchanged
    // Refusals: a tag that is no material, the dropped background, one region.
    o.max_size_of = {{4, 3}};
    BOOST_CHECK_THROW(mesh(*f, o), InputError);
    o.max_size_of = {{0, 3}};
    BOOST_CHECK_THROW(mesh(*f, o), InputError);
    o.keep_background = true;
    BOOST_TEST(mesh(*f, o).mesh.triangles.size() > 0u);
    o.max_size_of = {{1, 3}, {1, 4}};
    BOOST_CHECK_THROW(validate(o), InputError);
    o.max_size_of = {{1, 1}};  // below √5 spacing
    BOOST_CHECK_THROW(validate(o), InputError);
    o.max_size_of = {{1, 3}};
    BOOST_CHECK_THROW(mesh(*parse_shape("circle:0,0,3"), o), InputError);
}

BOOST_AUTO_TEST_CASE(maxmin_is_refused_with_materials) {
    const auto f = parse_material_shapes("1=circle:0,0,3");
    const Lattice l = lattice_around(f->bounds(), 0.5);
    BOOST_CHECK_THROW(mesh_materials(*f, l, {false, DiagonalRule::maxmin, {}}), InputError);
    BOOST_CHECK_THROW(mesh_materials_graded(*f, l, {false, DiagonalRule::maxmin, {}}, 0), InputError);
    BOOST_CHECK_THROW(mesh_materials_graded(*f, l, {false, DiagonalRule::separating, {}}, 3), std::invalid_argument);
    const std::vector<std::int64_t> bad_cap{0, 3}, short_caps{0};
    BOOST_CHECK_THROW(mesh_materials_graded(*f, l, {false, DiagonalRule::separating, {}}, 0, 0, bad_cap), std::invalid_argument);
    BOOST_CHECK_THROW(mesh_materials_graded(*f, l, {false, DiagonalRule::separating, {}}, 0, 0, short_caps), std::invalid_argument);
    BOOST_CHECK_THROW(mesh_materials_graded(*f, l, {false, DiagonalRule::separating, {}}, 0, 9), std::invalid_argument);
}

BOOST_AUTO_TEST_CASE(label_lists_are_checked) {
    Image img;
    img.width = 4, img.height = 3, img.maxval = 255, img.source = "tiny";
    img.pixels = {0, 1, 1, 0, 0, 7, 7, 0, 0, 0, 0, 0};
    BOOST_CHECK_THROW(make_label_materials(img, "1,9"), InputError);    // 9 absent
    BOOST_CHECK_THROW(make_label_materials(img, "0,1"), InputError);    // 0 is the background
    BOOST_CHECK_THROW(make_label_materials(img, "x"), InputError);
    try {
        make_label_materials(img, "1,9,12");
        BOOST_FAIL("absent labels accepted");
    } catch (const InputError& e) {
        BOOST_TEST(std::string(e.what()).find("9, 12") != std::string::npos);
    }
    const auto f = make_label_materials(img, "all");
    BOOST_TEST(f->count() == 3);
    BOOST_TEST(f->tag(2) == 7);
    BOOST_TEST(*f->reference_area(1) == 2.0);
    BOOST_CHECK_THROW(parse_material_shapes("1=circle:0,0,1;1=circle:2,0,1"), InputError);
    BOOST_CHECK_THROW(parse_material_shapes("0=circle:0,0,1"), InputError);
    BOOST_CHECK_THROW(parse_material_shapes("circle:0,0,1"), InputError);
    BOOST_CHECK_NO_THROW(parse_material_shapes("3=union(circle:0,0,1;circle:1,0,1);4=rect:0,0,1,1"));
}

// ---- the command line ----------------------------------------------------------------
namespace {

struct Run {
    int code;
    std::string out, err;
};

Run run(const std::string& args) {
    const fs::path dir = fs::temp_directory_path() / ("wm_materials_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    const std::string cmd = "cd '" + dir.string() + "' && '" WARPMESH_EXE "' " + args + " > out.txt 2> err.txt";
    const int status = std::system(cmd.c_str());
    Run r{WEXITSTATUS(status), testing::slurp(dir / "out.txt"), testing::slurp(dir / "err.txt")};
    return r;
}

fs::path write_pgm(const std::string& name, int w, int h, const std::vector<int>& px) {
    const fs::path dir = fs::temp_directory_path() / ("wm_materials_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    std::ofstream o(dir / name);
    o << "P2\n" << w << " " << h << "\n255\n";
    for (int v : px) o << v << "\n";
    return dir / name;
}

}  // namespace

// --materials with --slice: a slice of a label volume is meshed as the same
// slice saved as a 2D label image (pixel units; y upwards along the volume's j).
BOOST_AUTO_TEST_CASE(cli_meshes_materials_of_a_volume_slice_as_the_same_label_image) {
    const int W = 13, H = 11, D = 3;
    auto label = [](int i, int j, int k) {
        const int d2 = (i - 6) * (i - 6) + (j - 4) * (j - 4);
        return d2 < 4 + 3 * k ? 7 : d2 < 16 + 4 * k ? 3 : (i > 9 && k == 1) ? 12 : 0;
    };
    const fs::path dir = fs::temp_directory_path() / ("wm_materials_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    {
        std::ofstream o(dir / "labels.nrrd", std::ios::binary);
        o << "NRRD0004\ntype: uchar\ndimension: 3\nsizes: " << W << " " << H << " " << D << "\nencoding: raw\n\n";
        for (int k = 0; k < D; ++k)
            for (int j = 0; j < H; ++j)
                for (int i = 0; i < W; ++i) o.put(static_cast<char>(label(i, j, k)));
    }
    std::vector<int> px;  // slice k = 1, row 0 at the top: j = H - 1 - row
    for (int r = 0; r < H; ++r)
        for (int i = 0; i < W; ++i) px.push_back(label(i, H - 1 - r, 1));
    const fs::path pgm = write_pgm("slice1.pgm", W, H, px);
    for (const std::string graded : {"", " --graded"}) {
        Run a = run("mesh '" + (dir / "labels.nrrd").string() + "' --slice k=1 --materials all --spacing 0.5" + graded +
                    " --verify -o vol.node --quiet");
        BOOST_TEST_REQUIRE(a.code == 0, a.err);
        Run b = run("mesh '" + pgm.string() + "' --materials all --spacing 0.5" + graded + " --verify -o img.node --quiet");
        BOOST_TEST_REQUIRE(b.code == 0, b.err);
        for (const char* ext : {".node", ".ele", ".poly"}) {
            const std::string va = testing::slurp(dir / (std::string("vol") + ext)), vb = testing::slurp(dir / (std::string("img") + ext));
            BOOST_TEST(!va.empty());
            BOOST_TEST((va == vb), ext << graded << " differs");
        }
    }
    const Run r = run("mesh '" + (dir / "labels.nrrd").string() + "' --materials all -o m.vtu");
    BOOST_TEST(r.code != 0);
    BOOST_TEST(r.err.find("choose a slice") != std::string::npos, r.err);
    // --slices with --materials (refused before issue 27): one mesh per slice.
    const Run s = run("mesh '" + (dir / "labels.nrrd").string() + "' --slices k=0:2 --materials all -o m%d.vtu --quiet");
    BOOST_TEST(s.code == 0, s.err);
    BOOST_TEST(fs::exists(dir / "m0.vtu"));
    BOOST_TEST(fs::exists(dir / "m1.vtu"));
}

BOOST_AUTO_TEST_CASE(cli_meshes_materials_and_refuses_bad_input) {
    std::vector<int> px(12 * 10, 0);
    for (int r = 2; r < 8; ++r)
        for (int c = 2; c < 10; ++c) px[static_cast<std::size_t>(r * 12 + c)] = c < 6 ? 3 : 5;
    px[0] = 9;  // a one-pixel label in the corner: lost at spacing 4
    const fs::path img = write_pgm("labels.pgm", 12, 10, px);
    const std::string in = "'" + img.string() + "'";

    Run r = run("mesh " + in + " --materials all -o m.vtu --report m.json");
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    BOOST_TEST(r.out.find("junction squares") != std::string::npos);
    BOOST_TEST(r.out.find("uncertified") == std::string::npos, r.out);
    BOOST_TEST(r.out.find("label_5") != std::string::npos);
    const std::string json = testing::slurp(img.parent_path() / "m.json");
    BOOST_TEST(json.find("\"materials\": [") != std::string::npos);
    BOOST_TEST(json.find("\"pixel_area\"") != std::string::npos);
    BOOST_TEST(json.find("\"junction_squares\": {") != std::string::npos);
    BOOST_TEST(json.find("uncertified") == std::string::npos);

    // The brain-atlas slice, every label: its triple junctions are certified and
    // verified (--verify is the default; a violation or an unknown key exits 3).
    r = run("mesh '" WARPMESH_SOURCE_DIR "/mesher/examples/brain_axial_s128_labels16.pgm' --materials all --spacing 1 "
            "--verify -o brain.vtu --report brain.json");
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    const std::string brain = testing::slurp(img.parent_path() / "brain.json");
    BOOST_TEST(brain.find("\"junction_squares\": {\"count\": 0") == std::string::npos);
    BOOST_TEST(brain.find("\"certified\": true") != std::string::npos);
    BOOST_TEST(brain.find("\"verified\": true") != std::string::npos);
    BOOST_TEST(r.out.find("every triangle verified") != std::string::npos, r.out);

    r = run("mesh " + in + " --materials all --spacing 4 -o m.vtu --quiet --report lost.json");
    BOOST_TEST(r.code == 0);
    BOOST_TEST(r.err.find("material 9 (label_9) got no triangle") != std::string::npos, r.err);
    BOOST_TEST(testing::slurp(img.parent_path() / "lost.json").find("\"materials_without_triangles\": [9]") != std::string::npos);

    auto refused = [&](const std::string& args, int code, const std::string& needle) {
        const Run x = run(args);
        BOOST_TEST(x.code == code, args << ": exit " << x.code);
        BOOST_TEST(x.err.find(needle) != std::string::npos, args << ": " << x.err);
    };
    refused("mesh " + in + " --materials 3,4,6 -o m.vtu", 1, "not present in the image: 4, 6");
    refused("mesh " + in + " --materials 0,3 -o m.vtu", 1, "label 0 is the background");
    refused("mesh " + in + " --materials all --graded --max-cell 3 -o m.vtu", 2, "--max-cell must be a power of two");
    refused("mesh " + in + " --materials all --diagonal maxmin -o m.vtu", 1, "--diagonal maxmin cannot mesh several materials");
    refused("mesh " + in + " --materials all --label 3 -o m.vtu", 2, "--materials applies to a label image");
    refused("mesh " + in + " --background keep -o m.vtu", 2, "--background applies to --materials");
    refused("mesh --shapes '1=circle:0,0,3;1=circle:1,0,2' -o m.vtu", 1, "given twice");
    refused("mesh --shapes '1=circle:0,0,3' --shape circle:0,0,1 -o m.vtu", 2, "exactly one of");
    r = run("mesh --shapes '1=circle:0,0,10;2=circle:6,0,8;3=rect:-2,-2,2,12' --background keep --spacing 0.5 -o s.msh");
    BOOST_TEST(r.code == 0, r.err);
    // Graded, with the band invariant and every keyed triangle verified: the atlas slice, every label.
    r = run("mesh '" WARPMESH_SOURCE_DIR "/mesher/examples/brain_axial_s128_labels16.pgm' --materials all --graded --verify "
            "-o atlas.vtu --report atlas.json");
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    const std::string atlas = testing::slurp(img.parent_path() / "atlas.json");
    BOOST_TEST(atlas.find("\"graded\": true") != std::string::npos);
    BOOST_TEST(atlas.find("\"leaves_per_level\": [") != std::string::npos);
    BOOST_TEST(atlas.find("\"verified\": true") != std::string::npos, atlas.substr(0, 2000));
    // Pictures coloured by region, interfaces drawn.
    r = run("mesh --shapes '1=circle:0,0,10;2=circle:6,0,8' --spacing 0.5 --svg-color region -o s.svg --also s.png --quiet");
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    const std::string svg = testing::slurp(img.parent_path() / "s.svg");
    BOOST_TEST(svg.find("<g id=\"interfaces\"") != std::string::npos);
    std::set<std::string> fills;
    for (std::size_t at = 0; (at = svg.find("<polygon", at)) != std::string::npos; ++at) {
        const std::size_t f = svg.find("fill=\"#", at);
        fills.insert(svg.substr(f, 14));
    }
    BOOST_TEST(fills.size() == 2u);  // the two materials (the background is dropped)
}
