// lattice.cpp — stage 1: the lattice and the values of f at its points.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh {

namespace {

std::string short_number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

// Positive and finite, and within 1e-100 .. 1e100: beyond, the triangle areas
// (products of two lengths) underflow to 0 or overflow, and the mesh
// degenerates although every coordinate is representable.
void check_spacing(double s) {
    if (!(s > 0) || !std::isfinite(s)) throw InputError("lattice spacing must be a positive finite number");
    if (s < 1e-100 || s > 1e100)
        throw InputError("lattice spacing " + short_number(s) +
                         " is outside 1e-100 .. 1e100, where triangle areas would underflow or overflow "
                         "(scale the region instead)");
}

// A number of squares along one axis, refused (before any conversion that
// could overflow) when it is not finite, negative (an inverted box) or
// absurdly large.
std::int64_t checked_count(double n) {
    if (!(n >= 0 && n <= max_lattice_squares_per_axis))
        throw InputError("the lattice would have " + short_number(n) +
                         " squares along one axis (at most 2^32; use a larger spacing)");
    return static_cast<std::int64_t>(n);
}

// Lattice points are computed as x0 + i s in doubles; far from the origin
// relative to s they round onto each other and the mesh degenerates (zero-area
// triangles).  Refuse lattices whose coordinates exceed 2^32 spacings: then
// positions are exact to about 2^-20 s, far below what the angles notice.
void check_resolution(const Lattice& l) {
    const double m = std::max({std::abs(l.x0), std::abs(l.y0), std::abs(l.x0 + static_cast<double>(l.nx) * l.s),
                               std::abs(l.y0 + static_cast<double>(l.ny) * l.s)});
    if (!std::isfinite(m) || m > l.s * 4294967296.0)
        throw InputError("lattice spacing " + short_number(l.s) + " is too small for coordinates as large as " +
                         short_number(m) +
                         ": lattice points would round onto each other (coordinates must stay within 2^32 "
                         "spacings of the origin; move the region nearer the origin or use a larger spacing)");
}

}  // namespace

Lattice lattice_over(const Box& box, double s) {
    check_spacing(s);
    Lattice l;
    l.s = s;
    l.x0 = box.xmin;
    l.y0 = box.ymin;
    // Whole squares that fit in the box; at least one so that the lattice is
    // never empty.  (floor with a relative tolerance, so that a box of width
    // exactly k s is not cut to k - 1 squares by round-off.)
    auto squares = [s](double w) {
        const double n = std::floor(w / s * (1 + 1e-12));
        return checked_count(std::max(1.0, n));
    };
    l.nx = squares(box.xmax - box.xmin);
    l.ny = squares(box.ymax - box.ymin);
    check_resolution(l);
    return l;
}

Lattice lattice_around(const Box& box, double s) {
    check_spacing(s);
    Lattice l;
    l.s = s;
    l.x0 = box.xmin - s;
    l.y0 = box.ymin - s;
    l.nx = checked_count(std::ceil((box.xmax - box.xmin) / s)) + 2;
    l.ny = checked_count(std::ceil((box.ymax - box.ymin) / s)) + 2;
    check_resolution(l);
    return l;
}

Buffer<double> sample_values(const LevelSet& f, const Lattice& lattice) {
    Buffer<double> values(static_cast<std::size_t>(lattice.point_count()));  // every element written by f.sample
    f.sample(lattice, values);
    // A NaN has no sign and would silently drop out of every comparison below:
    // refuse it here, once, with the place it occurred.
    std::int64_t bad = -1;
#pragma omp parallel for reduction(max : bad)
    for (std::int64_t k = 0; k < static_cast<std::int64_t>(values.size()); ++k)
        if (!std::isfinite(values[static_cast<std::size_t>(k)])) bad = std::max(bad, k);
    if (bad >= 0) throw_non_finite(lattice, bad);
    return values;
}

void throw_non_finite(const Lattice& lattice, std::int64_t p) {
    const std::int64_t i = p % lattice.points_x(), j = p / lattice.points_x();
    const Vec2 x = lattice.position(i, j);
    throw InputError("level set value is not finite at lattice point (" + std::to_string(i) + ", " + std::to_string(j) +
                     ") = (" + std::to_string(x.x) + ", " + std::to_string(x.y) + ")");
}

}  // namespace warpmesh
