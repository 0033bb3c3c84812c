// The graded mesher's run-time invariant check (check_critical_squares_finest):
// it passes on real leaf lists, and it catches a leaf list in which a square
// with a warped or zero-valued corner is not a finest leaf (the list is
// corrupted by hand, as a broken quadtree would leave it).
#define BOOST_TEST_MODULE graded_invariant
#include <boost/test/unit_test.hpp>

#include <algorithm>

#include "warpmesh/mesh2d/graded.hpp"
#include "warpmesh/levelset/shapes.hpp"
#include "mesh2d/graded/quadtree.hpp"
#include "mesh2d/graded/tiles.hpp"

using namespace warpmesh;

namespace {

Lattice integer_lattice(std::int64_t n) {
    Lattice l;
    l.x0 = 0, l.y0 = 0, l.s = 1, l.nx = n, l.ny = n;
    return l;
}

// Removes lattice square (a, b)'s level-1 parent from the finest leaves, as
// if the quadtree had left the square inside a coarse leaf.
void drop_parent(Leaves& leaves, std::int64_t a, std::int64_t b) {
    const std::size_t R = static_cast<std::size_t>(b >> 1);
    const auto first = leaves.parents.begin() + leaves.pair_start[R];
    const auto last = leaves.parents.begin() + leaves.pair_start[R + 1];
    const auto it = std::find(first, last, static_cast<std::int32_t>(a >> 1));
    BOOST_REQUIRE(it != last);
    leaves.parents.erase(it);
    for (std::size_t r = R + 1; r < leaves.pair_start.size(); ++r) --leaves.pair_start[r];
}

}  // namespace

BOOST_AUTO_TEST_CASE(square_with_warped_corner_left_coarse_is_detected) {
    const Lattice l = integer_lattice(64);
    const Circle f(30.3, 33.7, 17.2);
    const TiledFront front = warp_tiles(f, l);
    const Quadtree tree = build_quadtree(l, front.signs, front.warped, 0);
    Leaves leaves = quadtree_leaves(tree, nullptr, true);
    const CriticalSquaresCheck ok = check_critical_squares_finest(leaves, front.signs, front.warped);
    BOOST_TEST(ok.ok());
    BOOST_TEST(ok.critical_points >= static_cast<std::int64_t>(front.warped.size()));
    BOOST_REQUIRE(!front.warped.empty());
    const WarpedPoint& w = front.warped[front.warped.size() / 2];
    drop_parent(leaves, w.p % (l.nx + 1), w.p / (l.nx + 1));
    const CriticalSquaresCheck bad = check_critical_squares_finest(leaves, front.signs, front.warped);
    BOOST_TEST(bad.violations > 0);
    BOOST_TEST(bad.first.find("warped corner") != std::string::npos, bad.first);
}

BOOST_AUTO_TEST_CASE(square_with_zero_corner_left_coarse_is_detected) {
    // f = 0 on the rectangle's sides (lattice lines): zero-valued points, no cut edge, no warp.
    const Lattice l = integer_lattice(64);
    const Rectangle f(20, 10, 44, 50);
    const TiledFront front = warp_tiles(f, l);
    BOOST_TEST(front.warped.empty());
    const Quadtree tree = build_quadtree(l, front.signs, front.warped, 0);
    Leaves leaves = quadtree_leaves(tree, nullptr, true);
    const CriticalSquaresCheck ok = check_critical_squares_finest(leaves, front.signs, front.warped);
    BOOST_TEST(ok.ok());
    BOOST_TEST(ok.critical_points >= 2 * (24 + 40));  // the rectangle's boundary points
    drop_parent(leaves, 19, 40);
    const CriticalSquaresCheck bad = check_critical_squares_finest(leaves, front.signs, front.warped);
    BOOST_TEST(bad.violations > 0);
    BOOST_TEST(bad.first.find("zero-valued corner") != std::string::npos, bad.first);
}

// The pipeline asks for the check with --verify (KeyOptions::check_invariant).
BOOST_AUTO_TEST_CASE(verify_runs_the_invariant_check) {
    const Lattice l = integer_lattice(64);
    const Circle f(30.3, 33.7, 17.2);
    const GradedResult with = mesh_graded(f, l, DiagonalRule::maxmin, 0, KeyOptions{true, true});
    BOOST_TEST(with.invariant_squares > 0);
    const GradedResult without = mesh_graded(f, l, DiagonalRule::maxmin, 0, KeyOptions{true, false});
    BOOST_TEST(without.invariant_squares == -1);
}
