// signs.cpp — stage 2: the sign of f at each lattice point.
//
// A value of exactly 0 gets sign 0: the point is on the level set.  No edge
// touching it is a cut edge (cut edges need strictly opposite signs), it never
// warps, and it counts as inside for output.
#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh {

Buffer<std::int8_t> compute_signs(std::span<const double> values) {
    Buffer<std::int8_t> signs(values.size());  // every element written below
    const std::int64_t n = static_cast<std::int64_t>(values.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < n; ++k) {
        const double v = values[static_cast<std::size_t>(k)];
        signs[static_cast<std::size_t>(k)] = static_cast<std::int8_t>((v > 0) - (v < 0));
    }
    return signs;
}

}  // namespace warpmesh
