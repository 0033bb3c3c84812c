// lattice.cpp — stage 1: the lattice and the values of f at its points.
#include <cmath>
#include <string>

#include "warpmesh/errors.hpp"
#include "warpmesh/lattice.hpp"

namespace warpmesh {

Lattice lattice_over(const Box& box, double s) {
    if (!(s > 0) || !std::isfinite(s)) throw InputError("lattice spacing must be a positive finite number");
    Lattice l;
    l.s = s;
    l.x0 = box.xmin;
    l.y0 = box.ymin;
    // Whole squares that fit in the box; at least one so that the lattice is
    // never empty.  (floor with a relative tolerance, so that a box of width
    // exactly k s is not cut to k - 1 squares by round-off.)
    auto squares = [s](double w) {
        const double n = std::floor(w / s * (1 + 1e-12));
        return static_cast<std::int64_t>(std::max(1.0, n));
    };
    l.nx = squares(box.xmax - box.xmin);
    l.ny = squares(box.ymax - box.ymin);
    return l;
}

Lattice lattice_around(const Box& box, double s) {
    if (!(s > 0) || !std::isfinite(s)) throw InputError("lattice spacing must be a positive finite number");
    Lattice l;
    l.s = s;
    l.x0 = box.xmin - s;
    l.y0 = box.ymin - s;
    l.nx = static_cast<std::int64_t>(std::ceil((box.xmax - box.xmin) / s)) + 2;
    l.ny = static_cast<std::int64_t>(std::ceil((box.ymax - box.ymin) / s)) + 2;
    return l;
}

void LevelSet::sample(const Lattice& lattice, std::span<double> out) const {
    const std::int64_t nxp = lattice.points_x(), rows = lattice.ny + 1;
#pragma omp parallel for schedule(static)
    for (std::int64_t j = 0; j < rows; ++j)
        for (std::int64_t i = 0; i < nxp; ++i) {
            const Vec2 p = lattice.position(i, j);
            out[static_cast<std::size_t>(lattice.index(i, j))] = value(p.x, p.y);
        }
}

std::vector<double> sample_values(const LevelSet& f, const Lattice& lattice) {
    std::vector<double> values(static_cast<std::size_t>(lattice.point_count()));
    f.sample(lattice, values);
    // A NaN has no sign and would silently drop out of every comparison below:
    // refuse it here, once, with the place it occurred.
    std::int64_t bad = -1;
#pragma omp parallel for reduction(max : bad)
    for (std::int64_t k = 0; k < static_cast<std::int64_t>(values.size()); ++k)
        if (!std::isfinite(values[static_cast<std::size_t>(k)])) bad = std::max(bad, k);
    if (bad >= 0) {
        const std::int64_t i = bad % lattice.points_x(), j = bad / lattice.points_x();
        const Vec2 p = lattice.position(i, j);
        throw InputError("level set value is not finite at lattice point (" + std::to_string(i) + ", " +
                                 std::to_string(j) + ") = (" + std::to_string(p.x) + ", " + std::to_string(p.y) +
                                 ")");
    }
    return values;
}

}  // namespace warpmesh
