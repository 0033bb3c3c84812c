// The monotone optimisation pass (optimize.hpp): every accepted move and flip
// keeps its star's smallest angle, triangles stay above their certified
// values, boundary vertices stay on the level set (and border vertices on the
// border), the mesh stays valid, the result is the same for any thread count,
// and the targets on the benchmark domains.
#define BOOST_TEST_MODULE optimize
#include <boost/test/unit_test.hpp>

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <random>
#include <sstream>
#include <string>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "warpmesh/mesh2d/graded.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/post/optimize.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/post/quality.hpp"
#include "warpmesh/post/resolution.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "warpmesh/mesh2d/uniform.hpp"
#include "post/plane.hpp"
#include "warpmesh/core/errors.hpp"
#include "certified_stage.hpp"
#include "support.hpp"

using namespace warpmesh;
using warpmesh::testing::scaled;

namespace {

// A stage's mesh (the separating rule) with its certified cell data
// "certified_min_angle" (certified_stage.hpp).
template <class Result>
Mesh with_cells(Result r, const Lattice& lat) {
    return testing::certified(std::move(r), lat, DiagonalRule::separating, {true, true, false}).mesh;
}

OptimizeOptions at_spacing(double s) {
    OptimizeOptions o;
    o.spacing = s;
    return o;
}

Mesh uniform_mesh(const LevelSet& f, double s) {
    const Lattice lat = lattice_around(f.bounds(), s);
    return with_cells(mesh_uniform(f, lat, DiagonalRule::separating, testing::with_keys), lat);
}

const Buffer<double>* certified(const Mesh& m) {
    for (const auto& [name, v] : m.cell_data)
        if (name == "certified_min_angle") return &v;
    return nullptr;
}

double tri_min(const Mesh& m, const std::array<std::int32_t, 3>& t) {
    return triangle_angles(m.vertices[static_cast<std::size_t>(t[0])], m.vertices[static_cast<std::size_t>(t[1])],
                           m.vertices[static_cast<std::size_t>(t[2])])
        .min_deg;
}
double twice_area(const Mesh& m, const std::array<std::int32_t, 3>& t) {
    const Vec2 a = m.vertices[static_cast<std::size_t>(t[0])], b = m.vertices[static_cast<std::size_t>(t[1])],
               c = m.vertices[static_cast<std::size_t>(t[2])];
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

}  // namespace

// The pass evaluates the reported (exact) angles only on the triangles whose
// fast angle is within 3·fast_atan2_error_deg of the extreme one, and examines
// a flip only if the in-circle test says the opposite vertex is inside: both
// shortcuts rest on these bounds.
BOOST_AUTO_TEST_CASE(fast_angles_stay_within_their_stated_error_and_incircle_matches_the_max_min_flip) {
    using namespace plane;
    const double deg = 180 / std::numbers::pi;
    for (int i = 0; i <= 200000; ++i) {
        const double t = std::numbers::pi * i / 200000.0, y = std::sin(t), x = std::cos(t);
        BOOST_TEST_REQUIRE(std::abs(fast_atan2_deg(std::abs(y), x) - std::atan2(std::abs(y), x) * deg) <= fast_atan2_error_deg);
    }
    std::mt19937 rng(18);
    std::uniform_real_distribution<double> u(-1, 1);
    int flips_seen = 0;
    for (int i = 0; i < 20000; ++i) {
        Vec2 a{u(rng), u(rng)}, b{u(rng), u(rng)}, c{u(rng), u(rng)}, d{u(rng), u(rng)};
        if (cross(b - a, c - a) < 0) std::swap(b, c);
        if (!(cross(b - a, c - a) > 1e-3)) continue;
        const FastQ f = tri_fast(a, b, c);
        const TriangleAngles e = triangle_angles(a, b, c);
        BOOST_TEST_REQUIRE(std::abs(f.min_deg - e.min_deg) <= 3 * fast_atan2_error_deg);
        BOOST_TEST_REQUIRE(std::abs(f.max_deg - e.max_deg) <= 3 * fast_atan2_error_deg);
        // d beyond the edge a-b, quadrilateral a-d-b-c convex: the flip of a-b
        // raises the pair's smallest angle iff d is inside the circumcircle.
        if (!(cross(a - b, d - b) > 1e-3) || !(cross(a - c, d - c) > 1e-3) || !(cross(b - d, c - d) > 1e-3)) continue;
        const double old_min = std::min(e.min_deg, triangle_angles(b, a, d).min_deg);
        const double new_min = std::min(triangle_angles(c, a, d).min_deg, triangle_angles(d, b, c).min_deg);
        if (std::abs(new_min - old_min) < 1e-6) continue;
        BOOST_TEST_REQUIRE((incircle(a, b, c, d) > 0) == (new_min > old_min));
        ++flips_seen;
    }
    BOOST_TEST(flips_seen > 1000);
}

BOOST_AUTO_TEST_CASE(no_accepted_move_or_flip_lowers_its_stars_smallest_angle) {
    const auto f = parse_shape("flower:0,0,20,6,5");
    Mesh m = uniform_mesh(*f, 1);
    std::int64_t moves = 0, flips = 0, violations = 0;
    OptimizeOptions o;
    o.spacing = 1;
    o.observer = [&](const Mesh& after, const OptimizeEvent& e) {
        if (e.flip) {
            ++flips;
            // Both pairs as they stand (positions unchanged by a flip).
            const double before = std::min(tri_min(after, e.before[0]), tri_min(after, e.before[1]));
            const double now = std::min(tri_min(after, e.after[0]), tri_min(after, e.after[1]));
            violations += now < before || twice_area(after, e.after[0]) <= 0 || twice_area(after, e.after[1]) <= 0;
            return;
        }
        ++moves;
        // The star with the vertex at its old and its new position.
        Mesh old = after;
        old.vertices[static_cast<std::size_t>(e.vertex)] = e.from;
        double before = 1e9, now = 1e9;
        for (const std::size_t t : e.star) {
            before = std::min(before, tri_min(old, after.triangles[t]));
            now = std::min(now, tri_min(after, after.triangles[t]));
            violations += twice_area(after, after.triangles[t]) <= 0;
        }
        violations += now < before;
    };
    const OptimizeReport r = optimize_mesh(m, *f, o);
    BOOST_TEST(moves > 100);
    BOOST_TEST(moves == r.moves);
    BOOST_TEST(flips == r.flips);
    BOOST_TEST(violations == 0);
    BOOST_TEST(r.min_angle_after >= r.min_angle_before);
    BOOST_TEST(r.min_angle_after > r.min_angle_before + 3);  // it does something
}

BOOST_AUTO_TEST_CASE(optimised_mesh_is_valid_and_keeps_boundary_regions_and_certified_values) {
    for (const char* spec : {"ellipse:0,0,30,18", "annulus:0,0,10,25", "flower:0,0,20,6,5"})
        for (const bool graded : {false, true}) {
            BOOST_TEST_CONTEXT(spec << (graded ? " graded" : " uniform")) {
                const auto f = parse_shape(spec);
                const double s = 0.7;
                const Lattice lat = lattice_around(f->bounds(), s);
                Mesh m = graded ? with_cells(mesh_graded(*f, lat, DiagonalRule::separating, 0, testing::with_keys), lat)
                                : with_cells(mesh_uniform(*f, lat, DiagonalRule::separating, testing::with_keys), lat);
                const Mesh before = m;
                CertifiedSummary fid0, fid1;
                measure_fidelity(before, *f, s, fid0);
                const OptimizeReport r = optimize_mesh(m, *f, at_spacing(s));
                const MeshCheck c = check_mesh(m);
                BOOST_TEST(c.ok());
                BOOST_TEST(r.moves > 0);
                BOOST_TEST((m.boundary == before.boundary));
                BOOST_TEST((m.boundary_tag == before.boundary_tag));
                BOOST_TEST((m.region == before.region));
                BOOST_TEST(m.vertices.size() == before.vertices.size());
                // Every triangle at or above its certified value, which is at
                // or above the mesh's certified floor.
                const Buffer<double>& cert = *certified(m);
                const double floor = *std::min_element(certified(before)->begin(), certified(before)->end());
                BOOST_TEST(r.certified_floor == floor);
                std::int64_t below = 0;
                for (std::size_t t = 0; t < m.triangles.size(); ++t)
                    below += tri_min(m, m.triangles[t]) < cert[t] - 1e-7 || cert[t] < floor;
                BOOST_TEST(below == 0);
                // Boundary vertices on the level set stay on it; the boundary
                // is no farther from it than before.
                measure_fidelity(m, *f, s, fid1);
                BOOST_TEST(fid1.boundary_edges_off_levelset == fid0.boundary_edges_off_levelset);
                BOOST_TEST(fid1.max_boundary_distance <= fid0.max_boundary_distance);
                std::int64_t moved_off = 0, moved_boundary = 0;
                for (std::size_t e = 0; e < m.boundary.size(); ++e) {
                    const auto v = static_cast<std::size_t>(m.boundary[e][0]);
                    const Vec2 p = m.vertices[v], q = before.vertices[v];
                    if (p.x == q.x && p.y == q.y) continue;
                    ++moved_boundary;
                    moved_off += std::abs(f->value(p.x, p.y)) > 1e-9 * s;
                }
                BOOST_TEST(moved_boundary > 0);
                BOOST_TEST(moved_off == 0);
                BOOST_TEST(r.min_angle_after >= r.min_angle_before);
                BOOST_TEST(r.boundary_distance_after <= r.boundary_distance_before);
            }
        }
}

BOOST_AUTO_TEST_CASE(border_vertices_slide_along_the_lattice_border_only) {
    // A disc cut by the lattice's left border at x = -6: boundary tag 2 there.
    const Circle f(0, 0, 10);
    const Lattice lat = lattice_over(Box{-6, -12, 12, 12}, 0.75);
    Mesh m = with_cells(mesh_uniform(f, lat, DiagonalRule::separating, testing::with_keys), lat);
    const Mesh before = m;
    optimize_mesh(m, f, at_spacing(0.75));
    BOOST_TEST(check_mesh(m).ok());
    std::int64_t border = 0, off_line = 0, slid = 0;
    for (std::size_t e = 0; e < m.boundary.size(); ++e) {
        if (m.boundary_tag[e] != boundary_domain) continue;
        for (const std::int32_t v : m.boundary[e]) {
            ++border;
            off_line += m.vertices[static_cast<std::size_t>(v)].x != before.vertices[static_cast<std::size_t>(v)].x;
            slid += m.vertices[static_cast<std::size_t>(v)].y != before.vertices[static_cast<std::size_t>(v)].y;
        }
    }
    BOOST_TEST(border > 0);
    BOOST_TEST(slid > 0);  // some did move, along the line
    BOOST_TEST(off_line == 0);
}

BOOST_AUTO_TEST_CASE(same_result_for_any_thread_count) {
#ifdef _OPENMP
    const auto f = parse_shape("annulus:0,0,10,25");
    auto run = [&](int threads) {
        omp_set_num_threads(threads);
        Mesh m = uniform_mesh(*f, 0.5);
        optimize_mesh(m, *f, at_spacing(0.5));
        return m;
    };
    const Mesh a = run(1), b = run(2), c = run(3);
    omp_set_num_threads(omp_get_num_procs());
    for (const Mesh* x : {&b, &c}) {
        BOOST_TEST(x->vertices.size() == a.vertices.size());
        BOOST_TEST(std::equal(a.vertices.begin(), a.vertices.end(), x->vertices.begin(),
                              [](Vec2 p, Vec2 q) { return p.x == q.x && p.y == q.y; }));
        BOOST_TEST((x->triangles == a.triangles));
    }
#endif
}

BOOST_AUTO_TEST_CASE(a_disc_of_radius_one_at_spacing_one_is_unresolved_and_the_suggestion_resolves_it) {
    const Circle f(0, 0, 1);
    const Mesh coarse = uniform_mesh(f, 1);
    const ResolutionCheck r = check_resolution(coarse, 1);
    BOOST_TEST(r.unresolved == 1);
    BOOST_TEST(r.suggested_spacing > 0);
    BOOST_TEST(r.suggested_spacing < 0.5);
    const Mesh fine = uniform_mesh(f, r.suggested_spacing);
    BOOST_TEST(check_resolution(fine, r.suggested_spacing).unresolved == 0);
    // The benchmark domains at spacing 1 are resolved, the annulus's hole too.
    for (const char* spec : {"ellipse:0,0,100,60", "annulus:0,0,40,100", "flower:0,0,80,25,5"}) {
        const auto g = parse_shape(spec);
        const ResolutionCheck ok = check_resolution(uniform_mesh(*g, 1), 1);
        BOOST_TEST(ok.unresolved == 0);
        BOOST_TEST(ok.loops == (std::string(spec).starts_with("annulus") ? 2 : 1));
    }
}

BOOST_AUTO_TEST_CASE(optimised_benchmark_domains_reach_30_degrees_and_at_most_110) {
    // The issue's targets, uniform and graded, at spacings 1 and 0.5: measured,
    // not assumed — this fails if the pass stops reaching them.
    for (const char* spec : {"ellipse:0,0,100,60", "annulus:0,0,40,100", "flower:0,0,80,25,5"})
        for (const double s : {1.0, 0.5})
            for (const bool graded : {false, true}) {
                BOOST_TEST_CONTEXT(spec << " s = " << s << (graded ? " graded" : " uniform")) {
                    const auto f = parse_shape(spec);
                    const Lattice lat = lattice_around(f->bounds(), s);
                    Mesh m = graded ? mesh_graded(*f, lat, DiagonalRule::separating, 0).mesh
                                    : mesh_uniform(*f, lat, DiagonalRule::separating).mesh;
                    const OptimizeReport r = optimize_mesh(m, *f, at_spacing(s));
                    const QualityReport q = compute_quality(m);
                    BOOST_TEST(q.min_angle_deg >= 30);
                    BOOST_TEST(q.max_angle_deg <= 110);
                    if (!graded) BOOST_TEST(q.mean_min_angle_deg >= 45);
                    BOOST_TEST(q.min_angle_deg == r.min_angle_after);
                    BOOST_TEST(r.boundary_distance_after <= r.boundary_distance_before);
                }
            }
}

// --max-size with --optimize: the pass never makes an edge longer than the
// bound (OptimizeOptions::max_edge), graded and uniform, and still lifts the
// minimum angle.
BOOST_AUTO_TEST_CASE(optimised_graded_mesh_keeps_the_max_size) {
    const auto flower = parse_shape("flower:0,0,80,25,5");
    for (const double H : {std::sqrt(5.0), 3.0, 6.0})
        for (const bool graded : {true, false}) {
            MeshOptions o;
            o.graded = graded, o.max_size = H, o.optimize = true;
            const MeshResult r = mesh(*flower, o);
            double longest2 = 0;
            for (const auto& t : r.mesh.triangles)
                for (int k = 0; k < 3; ++k) {
                    const Vec2 a = r.mesh.vertices[static_cast<std::size_t>(t[k])], b = r.mesh.vertices[static_cast<std::size_t>(t[(k + 1) % 3])];
                    longest2 = std::max(longest2, (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y));
                }
            BOOST_TEST(longest2 <= H * H, "H " << H << " graded " << graded << " longest " << std::sqrt(longest2));
            BOOST_REQUIRE(r.report.optimize);
            BOOST_TEST(r.report.optimize->min_angle_after > r.report.optimize->min_angle_before + 5);
        }
}

// OptimizeOptions::max_edge bites: with a bound below some of the band's
// edges, the bounded pass creates no edge longer than it (stars with one are
// frozen), while the unbounded pass does create some (so the bound is what
// keeps --max-size).
BOOST_AUTO_TEST_CASE(max_edge_stops_moves_and_flips_that_lengthen_an_edge) {
    auto longer = [](const Mesh& m, double bound) {  // edges longer than bound (each counted from both sides)
        std::int64_t n = 0;
        for (const auto& t : m.triangles)
            for (int k = 0; k < 3; ++k) {
                const Vec2 a = m.vertices[static_cast<std::size_t>(t[k])], b = m.vertices[static_cast<std::size_t>(t[(k + 1) % 3])];
                n += (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y) > bound * bound;
            }
        return n;
    };
    std::int64_t bitten = 0;
    for (const char* spec : {"ellipse:0,0,30,18", "annulus:0,0,10,25", "flower:0,0,20,6,5"}) {
        const auto f = parse_shape(spec);
        // Just above the lattice's diagonals, below some band edges (at 1.05
        // times the diagonal the union-jack interior of issue 33 leaves the
        // free pass no edge to lengthen beyond it on these shapes).
        const double s = 0.7, bound = 1.01 * std::sqrt(2.0) * s;
        const Lattice lat = lattice_around(f->bounds(), s);
        const Mesh m0 = mesh_uniform(*f, lat, DiagonalRule::separating).mesh;
        Mesh free = m0, bounded = m0;
        optimize_mesh(free, *f, at_spacing(s));
        OptimizeOptions o = at_spacing(s);
        o.max_edge = bound;
        const OptimizeReport r = optimize_mesh(bounded, *f, o);
        BOOST_TEST_CONTEXT(spec << ": before " << longer(m0, bound) << ", bounded " << longer(bounded, bound) << ", free " << longer(free, bound)) {
            BOOST_TEST(longer(bounded, bound) <= longer(m0, bound));
            BOOST_TEST(r.moves > 0);
            BOOST_TEST(check_mesh(bounded).ok());
        }
        bitten += longer(free, bound) > longer(m0, bound);
    }
    BOOST_TEST(bitten > 0);
}

// --- local refinement (OptimizeOptions::refine_below_deg) ------------------------

namespace {

std::unique_ptr<LevelSet> atlas_slice(const char* name) {
    return make_image_levelset(read_image(std::string(WARPMESH_SOURCE_DIR "/mesher/examples/") + name), label_options("nonzero"));
}

// The pipeline's unoptimised mesh at spacing 1 (certified, with cell data)
// and its certified floor.
Mesh plain_mesh(const LevelSet& f, bool graded, double& floor) {
    MeshOptions o;
    o.graded = graded;
    MeshResult r = mesh(f, o);
    floor = *std::min_element(certified(r.mesh)->begin(), certified(r.mesh)->end());
    return std::move(r.mesh);
}

OptimizeOptions refining(double floor) {
    OptimizeOptions o = at_spacing(1);
    o.refine_below_deg = 30, o.certified_floor = floor;
    return o;
}

// Per vertex, its number of boundary edges.
std::vector<int> boundary_degree(const Mesh& m) {
    std::vector<int> d(m.vertices.size(), 0);
    for (const auto& e : m.boundary) ++d[static_cast<std::size_t>(e[0])], ++d[static_cast<std::size_t>(e[1])];
    return d;
}

}  // namespace

// The 1 px atlas slices, where moves and flips stop at 26.6-27.5 deg (one-pixel
// strips of boundary-only triangles): refinement lifts them to >= 28 deg and
// keeps every promise of the pass.
BOOST_AUTO_TEST_CASE(refinement_lifts_one_pixel_atlas_slices_above_28_degrees_and_keeps_the_mesh_valid) {
    for (const char* slice : {"brain_axial_s128_labels16.pgm", "abdomen_axial_z040_labels16.pgm"})
        for (const bool graded : {false, true}) {
            BOOST_TEST_CONTEXT(slice << (graded ? " graded" : " uniform")) {
                const auto f = atlas_slice(slice);
                double floor = 0;
                const Mesh before = plain_mesh(*f, graded, floor);
                Mesh m = before;
                OptimizeOptions o = refining(floor);
                std::int64_t violations = 0;  // moves of the refinement's sweeps too
                o.observer = [&](const Mesh& after, const OptimizeEvent& e) {
                    if (e.flip) return;
                    double was = 1e9, now = 1e9;
                    for (const std::size_t t : e.star) {
                        Vec2 p[3];
                        for (int k = 0; k < 3; ++k) {
                            const std::int32_t v = after.triangles[t][static_cast<std::size_t>(k)];
                            p[k] = v == e.vertex ? e.from : after.vertices[static_cast<std::size_t>(v)];
                        }
                        was = std::min(was, triangle_angles(p[0], p[1], p[2]).min_deg);
                        now = std::min(now, tri_min(after, after.triangles[t]));
                    }
                    violations += now < was;
                };
                const OptimizeReport r = optimize_mesh(m, *f, o);
                BOOST_TEST(violations == 0);
                BOOST_TEST(r.inserted_vertices > 0);
                BOOST_TEST(r.refined_triangles <= r.inserted_vertices);
                BOOST_TEST(m.vertices.size() == before.vertices.size() + static_cast<std::size_t>(r.inserted_vertices));
                const QualityReport q = compute_quality(m);
                BOOST_TEST(q.min_angle_deg >= 28);
                BOOST_TEST(q.min_angle_deg == r.min_angle_after);
                BOOST_TEST(r.min_angle_after > r.min_angle_before);
                BOOST_TEST(q.max_angle_deg <= std::max(110.0, r.max_angle_before));
                const MeshCheck c = check_mesh(m);
                BOOST_TEST(c.ok(), (c.messages.empty() ? "" : c.messages[0]));
                // Every triangle at or above its certified value, and that at or
                // above the floor; one region.
                const Buffer<double>& cert = *certified(m);
                BOOST_REQUIRE(cert.size() == m.triangles.size());
                std::int64_t below = 0;
                for (std::size_t t = 0; t < m.triangles.size(); ++t)
                    below += tri_min(m, m.triangles[t]) < cert[t] - 1e-7 || cert[t] < floor;
                BOOST_TEST(below == 0);
                BOOST_TEST(std::equal(before.region.begin(), before.region.end(), m.region.begin()));
                BOOST_TEST(std::all_of(m.region.begin() + static_cast<std::ptrdiff_t>(before.region.size()), m.region.end(),
                                       [&](std::int32_t g) { return std::find(before.region.begin(), before.region.end(), g) != before.region.end(); }));
                // No old vertex with more than two boundary edges (a pinch) or on
                // a border corner moved; new boundary vertices lie on f = 0 (tag 1)
                // and have exactly two boundary edges.
                const std::vector<int> deg0 = boundary_degree(before), deg = boundary_degree(m);
                std::int64_t pinch_moved = 0, new_off = 0, new_boundary = 0;
                for (std::size_t v = 0; v < before.vertices.size(); ++v)
                    pinch_moved += deg0[v] > 2 && (m.vertices[v].x != before.vertices[v].x || m.vertices[v].y != before.vertices[v].y);
                for (std::size_t e = 0; e < m.boundary.size(); ++e)
                    for (const std::int32_t v : m.boundary[e]) {
                        if (static_cast<std::size_t>(v) < before.vertices.size()) continue;
                        ++new_boundary;
                        const Vec2 p = m.vertices[static_cast<std::size_t>(v)];
                        new_off += deg[static_cast<std::size_t>(v)] != 2 ||
                                   (m.boundary_tag[e] == boundary_level_set && std::abs(f->value(p.x, p.y)) > 1e-9);
                    }
                BOOST_TEST(pinch_moved == 0);
                BOOST_TEST(new_boundary == 2 * r.boundary_splits);
                BOOST_TEST(new_off == 0);
                // The boundary: as many edges per tag as before plus one per split
                // (each split edge's halves keep its tag), and the same length of
                // border (tag 2) edges.
                BOOST_TEST(m.boundary.size() == before.boundary.size() + static_cast<std::size_t>(r.boundary_splits));
                BOOST_TEST(m.boundary_tag.size() == m.boundary.size());
                auto border_length = [](const Mesh& x) {
                    double l = 0;
                    for (std::size_t e = 0; e < x.boundary.size(); ++e)
                        if (x.boundary_tag[e] == boundary_domain) {
                            const Vec2 a = x.vertices[static_cast<std::size_t>(x.boundary[e][0])], b = x.vertices[static_cast<std::size_t>(x.boundary[e][1])];
                            l += std::hypot(a.x - b.x, a.y - b.y);
                        }
                    return l;
                };
                BOOST_TEST(border_length(m) == border_length(before), boost::test_tools::tolerance(1e-12));
                BOOST_TEST(r.boundary_distance_after <= r.boundary_distance_before);
            }
        }
}

BOOST_AUTO_TEST_CASE(refinement_gives_the_same_mesh_for_any_thread_count) {
#ifdef _OPENMP
    const auto f = atlas_slice("brain_axial_s128_labels16.pgm");
    auto run = [&](int threads) {
        omp_set_num_threads(threads);
        double floor = 0;
        Mesh m = plain_mesh(*f, false, floor);
        optimize_mesh(m, *f, refining(floor));
        return m;
    };
    const Mesh a = run(1), b = run(2);
    omp_set_num_threads(omp_get_num_procs());
    BOOST_TEST(b.vertices.size() == a.vertices.size());
    BOOST_TEST(std::equal(a.vertices.begin(), a.vertices.end(), b.vertices.begin(), b.vertices.end(),
                          [](Vec2 p, Vec2 q) { return p.x == q.x && p.y == q.y; }));
    BOOST_TEST((b.triangles == a.triangles));
    BOOST_TEST((b.boundary == a.boundary));
    BOOST_TEST((b.cell_data[0].second == a.cell_data[0].second));
#endif
}

// A pinch: two bars of a 10 x 9 image (threshold 128) joined by one pixel of
// value 128 whose neighbours above and below are inside, left and right
// outside — a saddle of the bilinear image on f = 0, so the mesh's vertex
// there has four boundary edges.  It must not move (only a vertex with
// exactly two boundary edges slides along the boundary), with or without
// refinement.
BOOST_AUTO_TEST_CASE(a_pinch_vertex_of_an_image_stays_put) {
    Image img;
    img.width = 10, img.height = 9, img.maxval = 255, img.source = "pinch";
    img.pixels.assign(90, 0);
    for (const int y : {1, 2, 3, 5, 6, 7})
        for (int x = 2; x <= 7; ++x) img.pixels[static_cast<std::size_t>(y * 10 + x)] = 255;
    img.pixels[4 * 10 + 4] = 128;
    ImageLevelSetOptions io;
    io.mode = ImageMode::threshold, io.iso = 128;
    const auto f = make_image_levelset(img, io);
    for (const bool refine : {false, true}) {
        BOOST_TEST_CONTEXT((refine ? "refining" : "no refinement")) {
            double floor = 0;
            const Mesh before = plain_mesh(*f, false, floor);
            const std::vector<int> deg0 = boundary_degree(before);
            std::size_t pinches = 0;
            for (const int d : deg0) pinches += d > 2;
            BOOST_REQUIRE(pinches >= 1);
            Mesh m = before;
            OptimizeOptions o = refining(floor);
            if (!refine) o.refine_below_deg = 0;
            const OptimizeReport r = optimize_mesh(m, *f, o);
            BOOST_TEST(r.moves > 0);
            BOOST_TEST(check_mesh(m).ok());
            for (std::size_t v = 0; v < before.vertices.size(); ++v)
                if (deg0[v] > 2) {
                    BOOST_TEST(m.vertices[v].x == before.vertices[v].x);
                    BOOST_TEST(m.vertices[v].y == before.vertices[v].y);
                }
        }
    }
}

// Refinement asked for more than the sweeps reach (a threshold of 44 deg on a
// disc cut by the lattice border at x = -6): boundary
// edges are split at points on f = 0 (a new vertex on a border edge would
// have to stay at x = -6), and the mesh stays valid, every triangle at or
// above its certified value, the boundary no farther from f = 0 than before.
BOOST_AUTO_TEST_CASE(refinement_splits_boundary_edges_on_the_level_set) {
    const Circle f(0, 0, 10);
    const double s = 0.7;
    const Lattice lat = lattice_over(Box{-6, -12, 12, 12}, s);
    const Mesh before = with_cells(mesh_uniform(f, lat, DiagonalRule::separating, testing::with_keys), lat);
    Mesh m = before;
    OptimizeOptions o = at_spacing(s);
    o.refine_below_deg = 44;
    const OptimizeReport r = optimize_mesh(m, f, o);
    BOOST_TEST(check_mesh(m).ok());
    BOOST_TEST(r.boundary_splits > 0);
    BOOST_TEST(r.inserted_vertices > r.boundary_splits);
    BOOST_TEST(r.min_angle_after >= r.min_angle_before);
    BOOST_TEST(r.boundary_distance_after <= r.boundary_distance_before);
    const Buffer<double>& cert = *certified(m);
    std::int64_t below = 0;
    for (std::size_t t = 0; t < m.triangles.size(); ++t) below += tri_min(m, m.triangles[t]) < cert[t] - 1e-7;
    BOOST_TEST(below == 0);
    std::int64_t off = 0;
    for (std::size_t e = 0; e < m.boundary.size(); ++e)
        for (const std::int32_t v : m.boundary[e]) {
            if (static_cast<std::size_t>(v) < before.vertices.size()) continue;
            const Vec2 p = m.vertices[static_cast<std::size_t>(v)];
            if (m.boundary_tag[e] == boundary_level_set) off += std::abs(f.value(p.x, p.y)) > 1e-9 * s;
            if (m.boundary_tag[e] == boundary_domain) off += p.x != -6;
        }
    BOOST_TEST(off == 0);
    BOOST_TEST(m.boundary.size() == before.boundary.size() + static_cast<std::size_t>(r.boundary_splits));
    BOOST_TEST(m.boundary_tag.size() == m.boundary.size());
}

// --max-size with refinement: a 1 px atlas slice (uniform and graded) under
// a size bound just above the warped band's sqrt(5) px still reaches 28 deg,
// and no edge is longer than the bound.
BOOST_AUTO_TEST_CASE(refinement_keeps_the_max_size) {
    const auto f = atlas_slice("brain_axial_s128_labels16.pgm");
    const double H = 2.3;
    for (const bool graded : {false, true}) {
        MeshOptions o;
        o.graded = graded, o.max_size = H, o.optimize = true;
        const MeshResult r = mesh(*f, o);
        BOOST_REQUIRE(r.report.optimize);
        BOOST_TEST(r.report.optimize->inserted_vertices > 0);
        BOOST_TEST(r.report.optimize->min_angle_after >= 28);
        double longest2 = 0;
        for (const auto& t : r.mesh.triangles)
            for (int k = 0; k < 3; ++k) {
                const Vec2 a = r.mesh.vertices[static_cast<std::size_t>(t[k])], b = r.mesh.vertices[static_cast<std::size_t>(t[(k + 1) % 3])];
                longest2 = std::max(longest2, (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y));
            }
        BOOST_TEST(longest2 <= H * H, "graded " << graded << " longest " << std::sqrt(longest2));
    }
}

// --- issue 27: the pass never folds the mesh, and keeps the certified maximum ------

namespace {

// The mesh before and after the pipeline's --optimize (certified, verified).
MeshResult optimised(const LevelSet& f, MeshOptions o) {
    o.optimize = true;
    return mesh(f, o);
}

// The largest and smallest angle over a mesh's triangles.
std::pair<double, double> extreme_angles(const Mesh& m) {
    double mn = 180, mx = 0;
    for (const auto& t : m.triangles) {
        const TriangleAngles a = triangle_angles(m.vertices[static_cast<std::size_t>(t[0])], m.vertices[static_cast<std::size_t>(t[1])],
                                                 m.vertices[static_cast<std::size_t>(t[2])]);
        mn = std::min(mn, a.min_deg), mx = std::max(mx, a.max_deg);
    }
    return {mn, mx};
}

// A random label image over labels 0..2 with blobs, salt and a checkerboard
// patch (saddles, where two boundary chains pass close by).
Image random_label_image(std::mt19937& rng) {
    std::uniform_int_distribution<int> side(6, 22), lab(0, 2), coin(0, 9);
    Image img;
    img.width = side(rng), img.height = side(rng), img.maxval = 2, img.source = "random labels";
    img.pixels.assign(static_cast<std::size_t>(img.width * img.height), 1);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            if (coin(rng) < 2) img.pixels[static_cast<std::size_t>(y * img.width + x)] = static_cast<std::uint16_t>(lab(rng));
    std::uniform_int_distribution<int> px(0, img.width - 4), py(0, img.height - 4);
    const int x0 = px(rng), y0 = py(rng);
    for (int y = y0; y < y0 + 4; ++y)
        for (int x = x0; x < x0 + 4; ++x) img.pixels[static_cast<std::size_t>(y * img.width + x)] = (x + y) % 2 ? 1 : 0;
    return img;
}

}  // namespace

// The issue's 10x12 label image: at the checkerboard saddle by x = 7.5 two
// boundary vertices on different boundary chains slid along f = 0 past each
// other (y 3 -> 3.6486 and 4 -> 3.6375), and one ended inside a triangle not
// in its star: every move was checked against its own star only.  Now a
// boundary vertex's move must keep the embedding, and the mesh is valid after
// every accepted move and flip, not only at the end.
BOOST_AUTO_TEST_CASE(issue27_optimize_saddle_fold_the_optimiser_never_folds_the_mesh) {
    const auto f = make_image_levelset(read_image(WARPMESH_TEST_DATA "/issue27_optimize_saddle_fold.pgm"), label_options("6"));
    double floor = 0;
    Mesh m = plain_mesh(*f, false, floor);
    BOOST_REQUIRE(check_mesh(m).ok());
    std::int64_t events = 0, invalid = 0;
    OptimizeOptions o = refining(floor);
    o.observer = [&](const Mesh& now, const OptimizeEvent&) {
        ++events;
        invalid += !check_mesh(now).ok();
    };
    const OptimizeReport r = optimize_mesh(m, *f, o);
    BOOST_TEST(events > 50);
    BOOST_TEST(invalid == 0);
    const MeshCheck c = check_mesh(m);
    BOOST_TEST(c.ok(), (c.messages.empty() ? std::string() : c.messages[0]));
    BOOST_TEST(r.min_angle_after > r.min_angle_before);
    // The command line's path: the pipeline's --optimize, certified.
    MeshOptions mo;
    const MeshResult res = optimised(*f, mo);
    BOOST_TEST(check_mesh(res.mesh).ok());
}

// check_mesh sees folds that orientation and conformity alone miss: a
// boundary vertex of one square moved into another square (every triangle
// still counter-clockwise, every edge still in one or two triangles).
BOOST_AUTO_TEST_CASE(check_mesh_finds_a_boundary_vertex_slid_into_another_part_of_the_mesh) {
    Mesh m;
    m.vertices = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {1.5, 0}, {2.5, 0}, {2.5, 1}, {1.5, 1}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
    m.region = {1, 1, 1, 1};
    m.boundary = {{0, 1}, {1, 2}, {2, 3}, {3, 0}, {4, 5}, {5, 6}, {6, 7}, {7, 4}};
    m.boundary_tag.assign(8, boundary_level_set);
    BOOST_REQUIRE(check_mesh(m).ok());
    m.vertices[1] = {2, 0.2};  // inside triangle (4, 5, 6)
    const MeshCheck c = check_mesh(m);
    BOOST_TEST(c.non_ccw == 0);
    BOOST_TEST(c.overfull_edges == 0);
    BOOST_TEST(!c.ok());
    BOOST_TEST(c.overlaps > 0);
    BOOST_TEST(c.crossing_boundary_edges > 0);
}

// Random label images with saddles, uniform and graded (with --grading and
// --max-size), through the pipeline's --optimize: every optimised mesh passes
// check_mesh (no fold), and no triangle leaves the certified [min, max].
BOOST_AUTO_TEST_CASE(random_label_images_with_saddles_optimise_to_valid_meshes_within_the_certified_bounds) {
    std::mt19937 rng(27);
    std::uniform_real_distribution<double> spacing(0.45, 1.6), grading(1.1, 2.0), size(2.3, 12);
    std::int64_t folded = 0, out_of_bounds = 0, meshes = 0;
    for (int i = 0; i < scaled(60); ++i) {
        const Image img = random_label_image(rng);
        const auto f = make_image_levelset(img, label_options(i % 2 ? "1" : "nonzero"));
        MeshOptions o;
        o.spacing = spacing(rng);
        o.graded = i % 3 == 0;
        if (o.graded) o.grading = grading(rng), o.max_size = size(rng) * o.spacing;
        MeshResult r;
        try {
            r = optimised(*f, o);
        } catch (const InputError&) {
            continue;  // an empty region at this spacing
        }
        ++meshes;
        const MeshCheck c = check_mesh(r.mesh);
        folded += !c.ok();
        BOOST_TEST(c.ok(), "image " << i << ": " << (c.messages.empty() ? std::string() : c.messages[0]));
        const auto [mn, mx] = extreme_angles(r.mesh);
        const bool in = mn >= r.certified.min_deg - 1e-9 && mx <= r.certified.max_deg + 1e-9;
        out_of_bounds += !in;
        BOOST_TEST(in, "image " << i << ": angles [" << mn << ", " << mx << "], certified [" << r.certified.min_deg << ", "
                                << r.certified.max_deg << "]");
    }
    BOOST_TEST(meshes >= scaled(60) / 2);
    BOOST_TEST(folded == 0);
    BOOST_TEST(out_of_bounds == 0);
}

// The issue's rectangle: the report certified a maximum of 91.00 deg and the
// optimised file had 93.77 deg.  The pass now keeps every triangle's largest
// angle at or below the certified maximum (rule (6)), on random rectangles,
// circles and ellipses at random non-dyadic spacings too.
BOOST_AUTO_TEST_CASE(issue27_optimised_mesh_keeps_the_certified_max_angle) {
    std::mt19937 rng(91);
    std::uniform_real_distribution<double> c(-10, 10), len(3, 15), spacing(0.2, 0.9);
    std::vector<std::pair<std::string, double>> cases{{"rect:-3.24713,10.227,11.1126,15.5342", 0.6103}};
    for (int i = 0; i < scaled(40); ++i) {
        const double x = c(rng), y = c(rng);
        std::ostringstream s;
        s.precision(6);
        if (i % 3 == 0) s << "rect:" << x << "," << y << "," << x + len(rng) << "," << y + len(rng);
        else if (i % 3 == 1) s << "circle:" << x << "," << y << "," << 0.5 * len(rng);
        else s << "ellipse:" << x << "," << y << "," << 0.5 * len(rng) << "," << 0.5 * len(rng);
        cases.emplace_back(s.str(), spacing(rng));
    }
    for (const auto& [spec, s] : cases) {
        BOOST_TEST_CONTEXT(spec << " --spacing " << s) {
            const auto f = parse_shape(spec);
            MeshOptions o;
            o.spacing = s;
            const MeshResult r = optimised(*f, o);
            const auto [mn, mx] = extreme_angles(r.mesh);
            BOOST_TEST(mx <= r.certified.max_deg);
            BOOST_TEST(mn >= r.certified.min_deg);
            BOOST_TEST(check_mesh(r.mesh).ok());
            BOOST_REQUIRE(r.report.optimize);
            BOOST_TEST(r.report.optimize->max_angle_after <= r.certified.max_deg);
        }
    }
}
