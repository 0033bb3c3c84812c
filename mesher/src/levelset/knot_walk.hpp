// knot_walk.hpp — the exact zero of a function that is piecewise linear along
// an axis-aligned segment with knots at the integers (a bilinear interpolant
// of per-pixel values restricted to a lattice edge).  Shared by the image
// level sets (image_levelset.cpp) and the label-image materials
// (materials/label_materials.cpp).  Private to mesher/src.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "warpmesh/core/mesh.hpp"

namespace warpmesh::knots {

// Keep a cut parameter in the open interval (0, 1), as the pipeline requires.
inline double open_unit(double u) {
    return std::clamp(u, std::numeric_limits<double>::denorm_min(), 1 - std::numeric_limits<double>::epsilon() / 2);
}

// g on the segment a → b along `axis` (0: x, 1: y), with g(a) = fa and g(b) =
// fb of strictly opposite signs, n the number of pixel centres along the axis
// (beyond [0, n-1] g is constant along the edge).  `g_at(x, y)` evaluates g.
// Walks the knots from a towards b, keeping (u_prev, g_prev) with g_prev of
// the sign of fa; the first knot where the sign flips closes the linear piece
// that holds the zero.
template <class G>
double zero_on_edge(Vec2 a, Vec2 b, int axis, int n, double fa, double fb, G&& g_at) {
    const double t0 = axis == 0 ? a.x : a.y, t1 = axis == 0 ? b.x : b.y;
    // Knots strictly inside the edge.
    const double lo = std::max(std::min(t0, t1), -1.0), hi = std::min(std::max(t0, t1), static_cast<double>(n));
    const std::int64_t kfirst = static_cast<std::int64_t>(std::floor(lo)) + 1;
    const std::int64_t klast = static_cast<std::int64_t>(std::ceil(hi)) - 1;
    const bool ascending = t1 > t0;
    double u_prev = 0, g_prev = fa;
    for (std::int64_t m = 0; m <= klast - kfirst; ++m) {
        const std::int64_t k = ascending ? kfirst + m : klast - m;
        if (k < 0 || k > n - 1) continue;
        const double kd = static_cast<double>(k);
        const double u = (kd - t0) / (t1 - t0);
        const double g = axis == 0 ? g_at(kd, a.y) : g_at(a.x, kd);
        if (g == 0) return open_unit(u);  // the zero sits exactly on a knot
        if ((g < 0) != (g_prev < 0)) return open_unit(u_prev + (u - u_prev) * (g_prev / (g_prev - g)));
        u_prev = u, g_prev = g;
    }
    return open_unit(u_prev + (1 - u_prev) * (g_prev / (g_prev - fb)));
}

}  // namespace warpmesh::knots
