// cut_points.cpp — stage 3: cut edges and their cut points.
//
// A lattice edge is cut when its endpoints have strictly opposite signs.  By
// continuity f has a zero on it; the cut point is that zero (the first one the
// root finder brackets, should there be several).
#include <algorithm>
#include <cmath>
#include <limits>

#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh {

std::vector<CutEdge> find_cut_edges(const LevelSet& f, const Lattice& lattice, std::span<const double> values,
                                    std::span<const std::int8_t> signs) {
    const std::int64_t nxp = lattice.points_x(), rows = lattice.ny + 1;
    std::vector<std::vector<CutEdge>> per_row(static_cast<std::size_t>(rows));
#pragma omp parallel for schedule(dynamic, 16)
    for (std::int64_t j = 0; j < rows; ++j) {
        auto& out = per_row[static_cast<std::size_t>(j)];
        for (std::int64_t i = 0; i < nxp; ++i) {
            const std::size_t p = static_cast<std::size_t>(lattice.index(i, j));
            if (signs[p] == 0) continue;
            if (i + 1 < nxp) append_cut_edge(f, lattice, i, j, 0, signs[p], signs[p + 1], values[p], values[p + 1], out);
            if (j < lattice.ny)
                append_cut_edge(f, lattice, i, j, 1, signs[p], signs[p + static_cast<std::size_t>(nxp)], values[p],
                                values[p + static_cast<std::size_t>(nxp)], out);
        }
    }
    std::vector<CutEdge> cuts;
    std::size_t total = 0;
    for (const auto& r : per_row) total += r.size();
    cuts.reserve(total);
    for (const auto& r : per_row) cuts.insert(cuts.end(), r.begin(), r.end());
    return cuts;
}

}  // namespace warpmesh
