// levelset.cpp — the defaults of LevelSet (levelset.hpp): sampling a block of
// lattice points, the bracketed cut parameter, the range that knows nothing.
#include <limits>

#include "warpmesh/levelset/levelset.hpp"
#include "core/root_finder.hpp"

namespace warpmesh {

// The bracketed root finder (root_finder.hpp) on g(u) = f(a + u (b - a)).
double bracketed_root(const LevelSet& f, Vec2 a, Vec2 b, double fa, double fb) {
    return bracketed_root_of([&](double u) { return f.value(a.x + u * (b.x - a.x), a.y + u * (b.y - a.y)); }, fa, fb);
}

double LevelSet::cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const {
    return bracketed_root(*this, a, b, fa, fb);
}

void LevelSet::sample_block(const Lattice& lattice, const PointBlock& b, std::span<double> out) const {
    auto row = [&](std::int64_t j) {
        for (std::int64_t i = 0; i < b.ni; ++i) {
            const Vec2 p = lattice.position(b.i0 + i, b.j0 + j);
            out[static_cast<std::size_t>(i + j * b.ni)] = value(p.x, p.y);
        }
    };
    // A small block (a tile of the graded front end) is sampled here: a
    // parallel region costs microseconds even with a false `if`, as much as
    // the block's points.
    if (b.ni * b.nj < 4096) {
        for (std::int64_t j = 0; j < b.nj; ++j) row(j);
        return;
    }
#pragma omp parallel for schedule(static)
    for (std::int64_t j = 0; j < b.nj; ++j) row(j);
}

void LevelSet::sample(const Lattice& lattice, std::span<double> out) const {
    sample_block(lattice, {0, 0, lattice.points_x(), lattice.ny + 1}, out);
}

Range LevelSet::range(const Box&) const {
    constexpr double inf = std::numeric_limits<double>::infinity();
    return {-inf, inf};
}

}  // namespace warpmesh
