// invariant.cpp — the graded mesher's invariant, checked on the leaf list at
// run time (graded.hpp, "The invariant that makes the angle proof apply").
//
// A lattice point is critical when it is warped or zero-valued.  Every lattice
// square with a critical corner must be a finest leaf: then the triangulation
// sends it through the rule (its key is in the certificates), and no coarse
// template uses or straddles a point that moved.  A finest leaf never has a
// split side (nothing is finer than level 0), and Leaves records split sides
// for coarse leaves only, so "finest" is the whole condition on the list.
//
// Cost: one binary search in the leaf list per square around a warped point,
// and a scan of the sampled tiles' points for zeros (uniform tiles never hold
// a zero) — the order of the front end's own work.
#include <algorithm>

#include "warpmesh/mesh2d/graded.hpp"
#include "mesh2d/graded/quadtree.hpp"
#include "mesh2d/graded/tiles.hpp"

namespace warpmesh {

namespace {

// Whether lattice square (a, b) is a finest leaf of the list: its level-1
// parent (a >> 1, b >> 1) is among the split level-1 nodes of its row pair.
bool listed_finest(const Leaves& leaves, std::int64_t a, std::int64_t b) {
    const std::int64_t R = b >> 1;
    if (R >= leaves.row_pairs()) return false;
    const auto first = leaves.parents.begin() + leaves.pair_start[static_cast<std::size_t>(R)];
    const auto last = leaves.parents.begin() + leaves.pair_start[static_cast<std::size_t>(R) + 1];
    return std::binary_search(first, last, static_cast<std::int32_t>(a >> 1));
}

}  // namespace

CriticalSquaresCheck check_critical_squares_finest(const Leaves& leaves, const TiledSigns& signs,
                                                   std::span<const WarpedPoint> warped) {
    CriticalSquaresCheck out;
    const std::int64_t nx = signs.nx, ny = signs.ny;
    auto around = [&](std::int64_t i, std::int64_t j, const char* what) {
        ++out.critical_points;
        for (std::int64_t b = std::max<std::int64_t>(j - 1, 0); b <= std::min(j, ny - 1); ++b)
            for (std::int64_t a = std::max<std::int64_t>(i - 1, 0); a <= std::min(i, nx - 1); ++a) {
                ++out.squares;
                if (listed_finest(leaves, a, b)) continue;
                if (out.violations++ == 0)
                    out.first = "graded invariant violated: square (" + std::to_string(a) + ", " + std::to_string(b) +
                                ") has a " + what + " corner (" + std::to_string(i) + ", " + std::to_string(j) +
                                ") but is not a finest leaf";
            }
    };
    for (const WarpedPoint& w : warped) around(w.p % (nx + 1), w.p / (nx + 1), "warped");
    const std::int64_t T = signs.size();
    for (std::int64_t J = 0; J < signs.ty; ++J)
        for (std::int64_t I = 0; I < signs.tx; ++I) {
            const std::int32_t s = signs.slot[static_cast<std::size_t>(I + J * signs.tx)];
            if (s < 0) continue;
            for (std::int64_t j = J * T; j <= std::min((J + 1) * T, ny); ++j)
                for (std::int64_t i = I * T; i <= std::min((I + 1) * T, nx); ++i)
                    if (*signs.at(s, I, J, i, j) == 0) around(i, j, "zero-valued");
        }
    return out;
}

}  // namespace warpmesh
