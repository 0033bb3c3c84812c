// cut_points.cpp — stage 3: cut edges and their cut points.
//
// A lattice edge is cut when its endpoints have strictly opposite signs.  By
// continuity f has a zero on it; the cut point is that zero (the first one the
// root finder brackets, should there be several).
#include <algorithm>
#include <cmath>
#include <limits>

#include "warpmesh/lattice.hpp"

namespace warpmesh {

// Illinois-modified regula falsi on g(u) = f(a + u (b - a)), u in [0, 1].
//
// Invariant: g(lo) has the sign of fa and g(hi) the sign of fb, both non-zero,
// so [lo, hi] always brackets a sign change; a point where g is exactly 0 ends
// the search.  The Illinois step (halving the stale end's value) makes the
// convergence superlinear even where g is convex on the bracket; a bisection
// step every eighth iteration bounds the work on any continuous g.  The result is clamped to the open
// interval (0, 1): the cut point is never a lattice point, whose value is
// non-zero by assumption.
double bracketed_root(const LevelSet& f, Vec2 a, Vec2 b, double fa, double fb) {
    double lo = 0, hi = 1, glo = fa, ghi = fb;
    int kept = 0;  // +1: lo was kept by the last step, -1: hi was kept
    double u = lo + (hi - lo) * glo / (glo - ghi);
    for (int it = 0; it < 200 && hi - lo > 4 * std::numeric_limits<double>::epsilon(); ++it) {
        u = (it % 8 == 7) ? 0.5 * (lo + hi) : lo + (hi - lo) * glo / (glo - ghi);
        if (!(u > lo && u < hi)) u = 0.5 * (lo + hi);
        const double g = f.value(a.x + u * (b.x - a.x), a.y + u * (b.y - a.y));
        if (g == 0 || !std::isfinite(g)) break;  // exactly on the level set (or f failed: stay in the bracket)
        if ((g < 0) == (glo < 0)) {
            lo = u, glo = g;
            if (kept == -1) ghi *= 0.5;  // hi kept twice in a row: Illinois halving
            kept = -1;
        } else {
            hi = u, ghi = g;
            if (kept == 1) glo *= 0.5;
            kept = 1;
        }
        u = lo + (hi - lo) * glo / (glo - ghi);
        if (!(u >= lo && u <= hi)) u = 0.5 * (lo + hi);
    }
    constexpr double tiny = std::numeric_limits<double>::denorm_min();
    return std::clamp(u, tiny, 1 - std::numeric_limits<double>::epsilon() / 2);
}

double LevelSet::cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const {
    return bracketed_root(*this, a, b, fa, fb);
}

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
