// grading.hpp — the grading option's one meaning, for the 2D quadtree
// (mesh2d/graded.hpp) and the 3D octree (mesh3d/graded.hpp).
//
// G in [1.1, 2] bounds how fast leaf sizes grow away from the boundary:
// grading_buffer(G) = n is 0 for G = 2 (the plain 2:1-balanced tree: at
// least one leaf of width w before one of width 2w), else the smallest
// n >= 2 with n >= 1 / log2(G) - 0.01 (the tolerance lets 1.414 mean √2),
// at most max_grading_buffer: a cell of level l >= 1 is coarsenable only if
// every cell of its level within n cells (max norm) is too, so on any
// straight path from the boundary at least n leaves of width <= w come
// before one of width 2w — a growth of at most 2^(1/n) <= G per leaf on
// average.  Throws std::invalid_argument outside [1.1, 2].
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace warpmesh {

inline constexpr int max_grading_buffer = 8;
inline constexpr double min_grading = 1.1, max_grading = 2.0;

inline int grading_buffer(double grading) {
    if (!(grading >= min_grading && grading <= max_grading))
        throw std::invalid_argument("grading must be between 1.1 and 2, got " + std::to_string(grading));
    if (grading == max_grading) return 0;
    const double n = std::ceil(1 / std::log2(grading) - 0.01);
    return static_cast<int>(std::min<double>(max_grading_buffer, std::max(2.0, n)));
}

}  // namespace warpmesh
