// The optimisation pass on multi-material meshes (optimize.hpp:
// optimize_mesh(Mesh&, const MaterialField&, ...); issue 28 item 1): on
// random label images (blobs, salt and checkerboard patches: junctions and
// saddles), atlas-like images and analytic materials, uniform and graded,
// background dropped and kept:
//  * the mesh stays valid (check_mesh) and the minimum angle never falls;
//  * every accepted move keeps its star's smallest angle;
//  * junction vertices (three or more materials, the dropped background
//    counted) move only under the same rule (star minimum kept, areas within
//    budget) and are never removed; interface vertices stay on their
//    interface (phi_a = phi_b);
//  * Mesh::interfaces is exactly the set of edges between triangles of
//    different regions, with the right regions on its sides, and new
//    interface vertices (refinement's splits) lie on their interface;
//  * no label's area error against its pixel count grows;
//  * the targets on the bundled atlas slice.
#define BOOST_TEST_MODULE optimize_materials
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <set>
#include <string>

#include "warpmesh/io/image.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/post/optimize.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/post/quality.hpp"
#include "label_images.hpp"
#include "support.hpp"

using namespace warpmesh;
using warpmesh::testing::scaled;

namespace {

Image blank(int w, int h) {
    Image img;
    img.width = w, img.height = h, img.maxval = 255, img.source = "test";
    img.pixels.assign(static_cast<std::size_t>(w * h), 0);
    return img;
}

// Nearest-seed blobs of labels 0..labels, with salt (single pixels: saddles
// and one-pixel materials) and now and then a checkerboard patch.
Image random_labels(std::mt19937& rng, int w, int h, int labels) {
    Image img = warpmesh::testing::random_label_image(rng, w, h, labels);
    std::uniform_int_distribution<int> lab(0, labels), px(0, w - 1), py(0, h - 1);
    std::uniform_real_distribution<double> u(0, 1);
    for (auto& p : img.pixels)
        if (u(rng) < 0.04) p = static_cast<std::uint16_t>(lab(rng));
    if (u(rng) < 0.3) {
        const int x0 = px(rng) % std::max(1, w - 4), y0 = py(rng) % std::max(1, h - 4);
        for (int y = y0; y < std::min(h, y0 + 4); ++y)
            for (int x = x0; x < std::min(w, x0 + 4); ++x) img.pixels[static_cast<std::size_t>(y * w + x)] = static_cast<std::uint16_t>((x + y) % 2 ? 1 : labels);
    }
    return img;
}

// Atlas-like: nested rings of tissue (like skull, cortex, white matter) with
// a one-pixel-wide layer and two small nuclei.
Image atlas_like(int w, int h) {
    Image img = blank(w, h);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            const double x = (c - w / 2.0) / (w / 2.2), y = (r - h / 2.0) / (h / 2.6), d = std::hypot(x, y);
            std::uint16_t l = d < 0.35 ? 4 : d < 0.7 ? 3 : d < 0.78 ? 2 : d < 1 ? 1 : 0;
            if (std::hypot(x - 0.2, y + 0.1) < 0.12) l = 5;
            if (std::hypot(x + 0.3, y - 0.15) < 0.1) l = 6;
            img.pixels[static_cast<std::size_t>(r * w + c)] = l;
        }
    return img;
}

using Edge = std::pair<std::int32_t, std::int32_t>;
Edge key(std::int32_t a, std::int32_t b) { return a < b ? Edge{a, b} : Edge{b, a}; }

// The edges between triangles of different regions, as (edge, {left, right}) with a < b and left the region of
// the triangle that runs a -> b.
std::map<Edge, std::array<std::int32_t, 2>> edges_between_regions(const Mesh& m) {
    std::map<Edge, std::vector<std::pair<bool, std::int32_t>>> by_edge;  // (runs a -> b with a < b, region)
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (int k = 0; k < 3; ++k) {
            const std::int32_t a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
            by_edge[key(a, b)].push_back({a < b, m.region[t]});
        }
    std::map<Edge, std::array<std::int32_t, 2>> out;
    for (const auto& [e, sides] : by_edge)
        if (sides.size() == 2 && sides[0].second != sides[1].second)
            out[e] = sides[0].first ? std::array{sides[0].second, sides[1].second} : std::array{sides[1].second, sides[0].second};
    return out;
}

std::map<Edge, std::array<std::int32_t, 2>> listed_interfaces(const Mesh& m) {
    std::map<Edge, std::array<std::int32_t, 2>> out;
    for (std::size_t k = 0; k < m.interfaces.size(); ++k) {
        const auto [a, b] = m.interfaces[k];
        const auto lr = m.interface_regions[k];
        out[key(a, b)] = a < b ? lr : std::array{lr[1], lr[0]};
    }
    return out;
}

// Vertices where three or more materials meet (a level-set boundary edge
// counts the dropped background), and crossings of interfaces (more than two
// interface edges: a checkerboard saddle of two materials).
std::set<std::int32_t> junctions(const Mesh& m) {
    std::map<std::int32_t, int> interface_edges;
    for (const auto& e : m.interfaces) ++interface_edges[e[0]], ++interface_edges[e[1]];
    std::map<std::int32_t, std::set<std::int32_t>> around;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
        for (const std::int32_t v : m.triangles[t]) around[v].insert(m.region[t]);
    for (std::size_t e = 0; e < m.boundary.size(); ++e)
        if (m.boundary_tag[e] == boundary_level_set)
            for (const std::int32_t v : m.boundary[e]) around[v].insert(-1);
    std::set<std::int32_t> out;
    for (const auto& [v, r] : around)
        if (r.size() >= 3) out.insert(v);
    for (const auto& [v, n] : interface_edges)
        if (n > 2) out.insert(v);
    return out;
}

std::map<std::int32_t, double> areas(const Mesh& m) {
    std::map<std::int32_t, double> out;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
        const Vec2 a = m.vertices[static_cast<std::size_t>(m.triangles[t][0])], b = m.vertices[static_cast<std::size_t>(m.triangles[t][1])],
                   c = m.vertices[static_cast<std::size_t>(m.triangles[t][2])];
        out[m.region[t]] += 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    }
    return out;
}

double star_min(const Mesh& m, std::span<const std::size_t> star, std::int32_t v, Vec2 at) {
    double mn = 180;
    for (const std::size_t t : star) {
        Vec2 x[3];
        for (int k = 0; k < 3; ++k) x[k] = m.triangles[t][k] == v ? at : m.vertices[static_cast<std::size_t>(m.triangles[t][k])];
        mn = std::min(mn, triangle_min_angle(x[0], x[1], x[2]));
    }
    return mn;
}

struct Outcome {
    double min_before = 0, min_after = 0, max_after = 0;
    std::int64_t moves = 0, interface_moves = 0, junction_moves = 0, interface_splits = 0, removals = 0;
};

// Mesh `field` (pipeline, certified), optimise it with an observer and check every property of the file's
// header; returns the figures.
Outcome optimise_and_check(const MaterialField& field, double spacing, bool graded, bool keep, const std::string& what) {
    MeshOptions o;
    o.spacing = spacing, o.graded = graded, o.keep_background = keep;
    MeshResult r = mesh(field, o);
    Mesh& m = r.mesh;
    std::set<std::int32_t> fixed = junctions(m);
    const auto area_before = areas(m);
    std::map<std::int32_t, int> material_of;
    for (int k = 0; k < field.count(); ++k) material_of[field.tag(k)] = k;
    const auto interfaces_before = listed_interfaces(m);
    std::size_t vertices_before = m.vertices.size();

    Outcome out;
    OptimizeOptions oo;
    oo.spacing = r.lattice.s, oo.refine_below_deg = 30;
    oo.certified_floor = r.certified.min_deg, oo.certified_max = r.certified.max_deg;
    oo.observer = [&](const Mesh& now, const OptimizeEvent& ev) {
        if (!ev.renumbered.empty()) {  // interior vertices removed: renumber what we track
            ++out.removals;
            std::set<std::int32_t> f;
            for (const std::int32_t v : fixed) {
                const std::int32_t n = ev.renumbered[static_cast<std::size_t>(v)];
                BOOST_REQUIRE_MESSAGE(n >= 0, what << ": junction vertex " << v << " removed");
                f.insert(n);
            }
            fixed = f;
            vertices_before = static_cast<std::size_t>(
                std::count_if(ev.renumbered.begin(), ev.renumbered.begin() + static_cast<std::ptrdiff_t>(vertices_before),
                              [](std::int32_t n) { return n >= 0; }));
            return;
        }
        if (ev.flip) return;
        ++out.moves;
        out.junction_moves += fixed.count(ev.vertex);
        BOOST_REQUIRE_MESSAGE(star_min(now, ev.star, ev.vertex, ev.to) >= star_min(now, ev.star, ev.vertex, ev.from) - 1e-12,
                              what << ": a move lowered its star's minimum angle");
        std::set<std::int32_t> regions;
        for (const std::size_t t : ev.star) regions.insert(now.region[t]);
        const int a = material_of.at(*regions.begin()), b = material_of.at(*regions.rbegin());
        // An interface vertex on phi_a = phi_b stays on it (one off it, a
        // third material's cut point, moves as a junction does).
        if (regions.size() == 2 && !fixed.count(ev.vertex) && std::abs(field.phi(a, ev.from.x, ev.from.y) - field.phi(b, ev.from.x, ev.from.y)) <= 1e-9 * spacing) {
            ++out.interface_moves;
            BOOST_REQUIRE_SMALL(field.phi(a, ev.to.x, ev.to.y) - field.phi(b, ev.to.x, ev.to.y), 1e-9 * spacing);
        }
    };
    const OptimizeReport rep = optimize_mesh(m, field, oo);
    out.interface_splits = rep.interface_splits;
    out.min_before = rep.min_angle_before, out.min_after = rep.min_angle_after, out.max_after = rep.max_angle_after;

    const MeshCheck c = check_mesh(m);
    BOOST_REQUIRE_MESSAGE(c.ok(), what << ": " << (c.messages.empty() ? std::string("?") : c.messages[0]));
    BOOST_REQUIRE_GE(rep.min_angle_after, rep.min_angle_before);
    const auto listed = listed_interfaces(m);
    BOOST_REQUIRE_MESSAGE(listed == edges_between_regions(m), what << ": interfaces are not the edges between regions");
    // Interfaces are never flipped or crossed; refinement may split them, at
    // points on their curve: every interface edge lies along an old one (its
    // ends on the old chain's curve) with the same regions.
    std::map<std::array<std::int32_t, 2>, int> pairs_before, pairs_after;
    for (const auto& [e, lr] : interfaces_before) ++pairs_before[lr];
    for (const auto& [e, lr] : listed) ++pairs_after[lr];
    for (const auto& [lr, n] : pairs_after) BOOST_REQUIRE_GE(n, pairs_before[lr]);
    for (const auto& [e, lr] : listed)
        for (const std::int32_t v : {e.first, e.second})
            if (static_cast<std::size_t>(v) >= vertices_before) {
                const Vec2 p = m.vertices[static_cast<std::size_t>(v)];
                BOOST_REQUIRE_SMALL(field.phi(material_of.at(lr[0]), p.x, p.y) - field.phi(material_of.at(lr[1]), p.x, p.y), 1e-9 * spacing);
            }
    const auto area_after = areas(m);
    for (const auto& [tag, a0] : area_before) {
        const int k = material_of.at(tag);
        const auto ref = field.reference_area(k);
        if (!ref) continue;
        BOOST_REQUIRE_MESSAGE(std::abs(area_after.at(tag) - *ref) <= std::abs(a0 - *ref) + 1e-9 * *ref,
                              what << ": label " << tag << " area error " << a0 - *ref << " -> " << area_after.at(tag) - *ref);
    }
    return out;
}

}  // namespace

BOOST_AUTO_TEST_CASE(random_label_images_keep_validity_interfaces_junctions_and_areas) {
    std::mt19937 rng(2028);
    std::uniform_int_distribution<int> size(8, 22), labels(2, 5);
    std::int64_t moves = 0, interface_moves = 0, junction_moves = 0, interface_splits = 0, removals = 0;
    for (int c = 0; c < scaled(40); ++c) {
        const Image img = random_labels(rng, size(rng), size(rng), labels(rng));
        const auto field = make_label_materials(img, "all");
        const double s = c % 3 == 0 ? 0.5 : 1;
        const Outcome o = optimise_and_check(*field, s, c % 4 == 1, c % 5 == 2, "random case " + std::to_string(c));
        moves += o.moves, interface_moves += o.interface_moves, interface_splits += o.interface_splits;
        junction_moves += o.junction_moves;
        removals += o.removals;
    }
    BOOST_TEST_MESSAGE("moves " << moves << ", of interface vertices " << interface_moves << ", of junctions " << junction_moves << "; interface splits "
                                << interface_splits << "; removal rounds " << removals);
    BOOST_REQUIRE_GT(interface_moves, 0);  // interface vertices do slide
    BOOST_REQUIRE_GT(junction_moves, 0);   // and junctions move
    // Vertex removal runs under the same checks (12 rounds over the 40 cases,
    // 1 over the sanitizer build's 10).
    if (scaled(40) >= 10) BOOST_REQUIRE_GT(removals, 0);
}

BOOST_AUTO_TEST_CASE(atlas_like_images_are_lifted) {
    const Image img = atlas_like(48, 40);
    const auto field = make_label_materials(img, "all");
    for (const bool graded : {false, true})
        for (const bool keep : {false, true}) {
            const Outcome o = optimise_and_check(*field, 1, graded, keep, "atlas-like");
            BOOST_TEST_MESSAGE("atlas-like graded " << graded << " keep " << keep << ": min " << o.min_before << " -> "
                                                    << o.min_after << ", max " << o.max_after);
            BOOST_REQUIRE_GT(o.min_after, o.min_before);
            BOOST_REQUIRE_GT(o.interface_moves, 0);
        }
}

BOOST_AUTO_TEST_CASE(analytic_materials_slide_along_their_interfaces) {
    const auto field = parse_material_shapes("1=circle:0,0,10;2=circle:6,1,7;3=ellipse:-4,-3,4,2.5");
    for (const double s : {1.0, 0.5}) {
        const Outcome o = optimise_and_check(*field, s, false, s == 0.5, "shapes");
        BOOST_TEST_MESSAGE("shapes s=" << s << ": min " << o.min_before << " -> " << o.min_after << ", max " << o.max_after);
        BOOST_REQUIRE_GT(o.min_after, 30);
        BOOST_REQUIRE_GT(o.interface_moves, 0);
    }
}

// Issue 28: at the tip of a one-pixel label of the brain slice (a crop,
// tests/data/issue28_optimize_strip_tip.pgm) an interior vertex's edge split
// a junction's 36.87° corner into two 18.43° angles, which no move, flip or
// Steiner point lifts; the pass removes that vertex (src/post/remove.hpp) and
// the crop reaches the 1 px target, uniform and graded, with every property
// of optimise_and_check (junctions never removed, interfaces exact, areas no worse).
BOOST_AUTO_TEST_CASE(issue28_optimize_strip_tip) {
    const Image img = read_image(std::string(WARPMESH_SOURCE_DIR) + "/tests/data/issue28_optimize_strip_tip.pgm");
    const auto field = make_label_materials(img, "all");
    for (const bool graded : {false, true}) {
        const Outcome o = optimise_and_check(*field, 1, graded, false, "strip tip");
        BOOST_TEST_MESSAGE("strip tip graded " << graded << ": min " << o.min_before << " -> " << o.min_after << ", max "
                                               << o.max_after << ", removals " << o.removals);
        BOOST_REQUIRE_GT(o.removals, 0);
        BOOST_REQUIRE_GE(o.min_after, 28.0);
        BOOST_REQUIRE_LE(o.max_after, 110.0);
    }
    MeshOptions o;  // the pipeline's --optimize
    o.spacing = 1, o.optimize = true;
    const MeshResult r = mesh(*field, o);
    BOOST_REQUIRE(r.report.optimize);
    BOOST_REQUIRE_GT(r.report.optimize->removed_vertices, 0);
    BOOST_REQUIRE_GE(r.report.optimize->min_angle_after, 28.0);
    BOOST_REQUIRE_EQUAL(r.mesh.triangles.size(), static_cast<std::size_t>(r.report.optimize->triangles));
}

// Issue 28: a one-pixel sliver of label 1029 between two junctions on the
// dropped background's boundary (a 14x12 crop of the brain slice at x 118,
// row 212: tests/data/issue28_optimize_junction_sliver.pgm) kept 18.43° and
// 135° at 1 px: its interface vertex slides along a curve on which no
// position helps, and the junctions were fixed.  Junctions now move under
// the same rule (star minimum kept, every label's area error within its
// budget, the embedding test on their boundary edges): 18.43° -> 20.15°
// (the labels of the crop have little room in their budgets; on the whole
// slice, where they have more, no triangle stays below 30°).
BOOST_AUTO_TEST_CASE(issue28_optimize_junction_sliver) {
    const Image img = read_image(std::string(WARPMESH_SOURCE_DIR) + "/tests/data/issue28_optimize_junction_sliver.pgm");
    const auto field = make_label_materials(img, "all");
    for (const bool graded : {false, true}) {
        const Outcome o = optimise_and_check(*field, 1, graded, false, "junction sliver");
        BOOST_TEST_MESSAGE("junction sliver graded " << graded << ": min " << o.min_before << " -> " << o.min_after << ", max "
                                                     << o.max_after << ", junction moves " << o.junction_moves);
        BOOST_REQUIRE_GT(o.junction_moves, 0);
        BOOST_REQUIRE_LT(o.min_before, 18.44);
        BOOST_REQUIRE_GT(o.min_after, 20.0);
        BOOST_REQUIRE_LT(o.max_after, 132.0);
    }
}

// Issue 28's last unmet target (>= 35 deg at 2 px): on the SPL sagittal slice
// l112 a junction of labels 4096 and 4076 on the dropped background (a 2 px
// lattice corner; 33.69 deg before the pass) stopped at 34.64 deg.  Label
// 4096's area was exact before the pass (budget 0), and the earlier
// area-neutral moves left it 1e-14 px^2 of rounding "room": area_neutral then
// counted two short labels (4096 and 4076) and left the ascent direction to
// the line search, which 4096's budget refused at every step.  The last
// sweeps (Optimizer::retry_junctions) count such room as none and project the
// direction for 4096: 34.64 -> 35.77 deg on this crop (rows 216..255,
// columns 64..255 of the slice; 35.13 deg on the whole slice), with no
// label's area error grown and interfaces exactly the edges between labels.
BOOST_AUTO_TEST_CASE(issue28_sagittal_2px_budget) {
    const Image img = read_image(std::string(WARPMESH_SOURCE_DIR) + "/tests/data/issue28_sagittal_2px_budget.pgm");
    const auto field = make_label_materials(img, "all");
    std::map<std::int32_t, int> material_of;
    for (int k = 0; k < field->count(); ++k) material_of[field->tag(k)] = k;
    for (const bool graded : {false, true}) {
        MeshOptions o;
        o.spacing = 2, o.graded = graded;
        const auto before = areas(mesh(*field, o).mesh);
        o.optimize = true;
        const MeshResult r = mesh(*field, o);
        BOOST_REQUIRE(r.report.optimize);
        BOOST_TEST_MESSAGE("sagittal crop graded " << graded << ": min " << r.report.optimize->min_angle_before << " -> "
                                                   << r.report.optimize->min_angle_after << ", max " << r.report.optimize->max_angle_after);
        BOOST_REQUIRE_GE(r.report.optimize->min_angle_after, 35.0);
        BOOST_REQUIRE_LE(r.report.optimize->max_angle_after, 110.0);
        const MeshCheck c = check_mesh(r.mesh);
        BOOST_REQUIRE_MESSAGE(c.ok(), (c.messages.empty() ? std::string("?") : c.messages[0]));
        BOOST_REQUIRE(listed_interfaces(r.mesh) == edges_between_regions(r.mesh));
        const auto after = areas(r.mesh);
        for (const auto& [tag, a0] : before) {
            const auto ref = field->reference_area(material_of.at(tag));
            if (!ref) continue;
            BOOST_REQUIRE_MESSAGE(std::abs(after.at(tag) - *ref) <= std::abs(a0 - *ref) + 1e-9 * *ref,
                                  "label " << tag << " area error " << a0 - *ref << " -> " << after.at(tag) - *ref);
        }
    }
}

// The bundled brain slice (every label, 1 and 2 pixels) against issue 28's targets.
BOOST_AUTO_TEST_CASE(atlas_slice_targets) {
    const Image img = read_image(std::string(WARPMESH_SOURCE_DIR) + "/mesher/examples/brain_axial_s128_labels16.pgm");
    const auto field = make_label_materials(img, "all");
    for (const double s : {2.0, 1.0}) {
        MeshOptions o;
        o.spacing = s, o.optimize = true;
        const MeshResult r = mesh(*field, o);
        BOOST_REQUIRE(r.report.optimize);
        BOOST_TEST_MESSAGE("brain s=" << s << ": min " << r.report.optimize->min_angle_before << " -> " << r.report.optimize->min_angle_after
                                      << ", max " << r.report.optimize->max_angle_before << " -> " << r.report.optimize->max_angle_after);
        // Issue 28's targets: 28 deg at 1 px, 35 deg at 2 px, maximum <= 110 deg
        // (reached with junction moves, refinement below 35 deg and the area
        // budget kept for the worst stars: 30.45 and 35.05 deg, 109.5 and
        // 104.8 deg).
        BOOST_REQUIRE_GE(r.report.optimize->min_angle_after, s == 1 ? 28.0 : 35.0);
        BOOST_REQUIRE_LE(r.report.optimize->max_angle_after, 110.0);
        // At 1 px the vertex removal (src/post/remove.hpp) lifts the pairs at
        // one-pixel tips.
        if (s == 1) BOOST_REQUIRE_GT(r.report.optimize->removed_vertices, 0);
    }
}
