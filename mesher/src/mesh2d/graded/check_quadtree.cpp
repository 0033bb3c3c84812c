// check_quadtree.cpp — the quadtree's invariants checked from scratch
// (check_quadtree in quadtree.hpp): for the tests, and asserted by
// build_quadtree in debug builds.
#include <cstdlib>
#include <string>

#include "mesh2d/graded/quadtree.hpp"

namespace warpmesh {

QuadtreeCheck check_quadtree(const Quadtree& t, const TiledSigns& signs) {
    QuadtreeCheck r;
    auto note = [&r](std::string m) {
        if (r.messages.size() < 10) r.messages.push_back(std::move(m));
    };
    const std::int64_t nx = t.nx, ny = t.ny;
    auto sgn = [&](std::int64_t i, std::int64_t j) { return signs(i, j); };
    // Leaf level of every square, by painting the leaves.
    std::vector<std::int8_t> level(static_cast<std::size_t>(nx * ny), -1);
    const Leaves leaves = quadtree_leaves(t);
    for_each_finest(leaves, [&](std::int64_t i, std::int64_t j) {
        if (i >= nx || j >= ny) {
            ++r.untiled;
            note("finest leaf (" + std::to_string(i) + ", " + std::to_string(j) + ") outside the lattice");
            return;
        }
        auto& v = level[static_cast<std::size_t>(i + j * nx)];
        if (v >= 0) ++r.untiled;
        v = 0;
    });
    for (const Leaf& leaf : leaves.coarse) {
        const std::int64_t w = std::int64_t{1} << leaf.level;
        if (leaf.i + w > nx || leaf.j + w > ny) {
            ++r.untiled;
            note("leaf at (" + std::to_string(leaf.i) + ", " + std::to_string(leaf.j) + ") leaves the lattice");
            continue;
        }
        for (std::int64_t j = leaf.j; j < leaf.j + w; ++j)
            for (std::int64_t i = leaf.i; i < leaf.i + w; ++i) {
                auto& v = level[static_cast<std::size_t>(i + j * nx)];
                if (v >= 0) ++r.untiled;
                v = leaf.level;
            }
        bool good = leaf.level >= 1 && leaf.sign != 0;
        for (std::int64_t j = leaf.j; j <= leaf.j + w; ++j)
            for (std::int64_t i = leaf.i; i <= leaf.i + w; ++i) good = good && sgn(i, j) == leaf.sign;
        if (leaf.level > cap_level(leaf.sign)) {
            ++r.over_cap;
            note("coarse leaf at (" + std::to_string(leaf.i) + ", " + std::to_string(leaf.j) + ") of level " +
                 std::to_string(leaf.level) + " is above its class's level " + std::to_string(cap_level(leaf.sign)));
        }
        if (!good) {
            ++r.bad_sign;
            note("coarse leaf at (" + std::to_string(leaf.i) + ", " + std::to_string(leaf.j) + ") has a point of another sign");
        }
    }
    auto lv = [&](std::int64_t i, std::int64_t j) { return level[static_cast<std::size_t>(i + j * nx)]; };
    for (std::int64_t j = 0; j < ny; ++j)
        for (std::int64_t i = 0; i < nx; ++i) {
            const int l = lv(i, j);
            if (l < 0) {
                ++r.untiled;
                continue;
            }
            if ((i + 1 < nx && std::abs(l - lv(i + 1, j)) >= 2) || (j + 1 < ny && std::abs(l - lv(i, j + 1)) >= 2)) {
                ++r.unbalanced;
                note("leaves at square (" + std::to_string(i) + ", " + std::to_string(j) + ") are not 2:1 balanced");
            }
            if (l == 0) continue;
            bool critical = false, inside = false;
            for (int c = 0; c < 4; ++c) {
                const std::int64_t pi = i + (c & 1), pj = j + (c >> 1);
                const int s = sgn(pi, pj);
                inside = inside || s <= 0;
                critical = critical || s == 0 || (pi > 0 && sgn(pi - 1, pj) == -s) || (pi < nx && sgn(pi + 1, pj) == -s) ||
                           (pj > 0 && sgn(pi, pj - 1) == -s) || (pj < ny && sgn(pi, pj + 1) == -s);
            }
            if (critical) {
                ++r.coarse_critical;
                note("square (" + std::to_string(i) + ", " + std::to_string(j) + ") has a critical corner but is in a leaf of level " +
                     std::to_string(l));
            }
            if (inside && (i == 0 || j == 0 || i == nx - 1 || j == ny - 1)) {
                ++r.coarse_border;
                note("inside border square (" + std::to_string(i) + ", " + std::to_string(j) + ") is in a coarse leaf");
            }
        }
    return r;
}

}  // namespace warpmesh
