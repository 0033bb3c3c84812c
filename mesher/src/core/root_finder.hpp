// root_finder.hpp — the bracketed root finder of every cut point, 2D and 3D.
//
// Illinois-modified regula falsi on g(u), u in [0, 1], given g(0) = g0 and
// g(1) = g1 of strictly opposite signs.
//
// Invariant: g(lo) has the sign of g0 and g(hi) the sign of g1, both non-zero,
// so [lo, hi] always brackets a sign change; a point where g is exactly 0 ends
// the search.  The Illinois step (halving the stale end's value) makes the
// convergence superlinear even where g is convex on the bracket; a bisection
// step every eighth iteration bounds the work on any continuous g.  The
// result is clamped to the open interval (0, 1): the cut point is never a
// lattice point, whose value is non-zero by assumption.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace warpmesh {

// u moved into the open interval (0, 1), where every cut parameter lies.
inline double inside_unit_interval(double u) {
    return std::clamp(u, std::numeric_limits<double>::denorm_min(), 1 - std::numeric_limits<double>::epsilon() / 2);
}

template <class G>
double bracketed_root_of(const G& g_at, double g0, double g1) {
    double lo = 0, hi = 1, glo = g0, ghi = g1;
    int kept = 0;  // +1: lo was kept by the last step, -1: hi was kept
    double u = lo + (hi - lo) * glo / (glo - ghi);
    for (int it = 0; it < 200 && hi - lo > 4 * std::numeric_limits<double>::epsilon(); ++it) {
        u = (it % 8 == 7) ? 0.5 * (lo + hi) : lo + (hi - lo) * glo / (glo - ghi);
        if (!(u > lo && u < hi)) u = 0.5 * (lo + hi);
        const double g = g_at(u);
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
    return inside_unit_interval(u);
}

}  // namespace warpmesh
