// lattice3.cpp — stage 1: the BCC lattice over the level set's box, and the
// point numbering every later stage and the output use (mesh3d.hpp: (z, y, x)
// order of doubled coordinates).
#include <cmath>
#include <limits>

#include "uniform3d.hpp"
#include "warpmesh/core/errors.hpp"

namespace warpmesh {

std::int64_t Lattice3::point_count() const {
    return (cubes[0] + 1) * (cubes[1] + 1) * (cubes[2] + 1) + cubes[0] * cubes[1] * cubes[2];
}

std::int64_t Lattice3::point_index(const bcc::Ivec& q) const {
    return uniform3d::Grid::whole(*this).index(q);
}

Lattice3 lattice3_for(const LevelSet3& f, double spacing) { return lattice3_for(f.bounds(), spacing, f.describe()); }

Lattice3 lattice3_for(const Box3& b, double spacing, const std::string& what, bool at_min) {
    if (!(spacing > 0 && std::isfinite(spacing)))
        throw OptionError("spacing", "{spacing} must be a positive number (got " + std::to_string(spacing) + ")");
    if (!std::isfinite(b.xmin + b.xmax + b.ymin + b.ymax + b.zmin + b.zmax) || !(b.xmin <= b.xmax) ||
        !(b.ymin <= b.ymax) || !(b.zmin <= b.zmax))
        throw InputError("the bounding box of " + what + " is not finite");
    Lattice3 L;
    L.spacing = spacing;
    const double lo[3] = {b.xmin, b.ymin, b.zmin}, hi[3] = {b.xmax, b.ymax, b.zmax};
    double origin[3];
    std::int64_t total = 1;
    for (int a = 0; a < 3; ++a) {
        const double n = std::ceil((hi[a] - lo[a]) / spacing) + 4;  // two cubes of margin each side
        if (!(n <= 1 << 20)) throw OptionError("spacing", "the 3D lattice is too large: " + std::to_string(n) + " cubes along one axis at {spacing} " + std::to_string(spacing) + "; choose a larger {spacing}");
        L.cubes[static_cast<std::size_t>(a)] = static_cast<std::int64_t>(n);
        origin[a] = at_min ? lo[a] - 2 * spacing : 0.5 * (lo[a] + hi[a]) - 0.5 * n * spacing;
        total *= static_cast<std::int64_t>(n) + 1;
        if (total > (std::int64_t{1} << 40)) total = std::int64_t{1} << 40;
    }
    L.origin = {origin[0], origin[1], origin[2]};
    if (L.point_count() >= std::numeric_limits<std::int32_t>::max())
        throw OptionError("spacing", "the 3D lattice has more than 2^31 points at {spacing} " + std::to_string(spacing) +
                                     "; choose a larger {spacing} (or mesh in blocks: mesh3d_block)");
    return L;
}

namespace uniform3d {

Grid Grid::window(const Lattice3& lattice, const bcc::Ivec& lo, const bcc::Ivec& hi) {
    Grid g;
    g.lattice = lattice;
    g.lo = lo, g.hi = hi;
    g.corner_w = (hi[0] - lo[0]) / 2 + 1, g.corner_h = (hi[1] - lo[1]) / 2 + 1;
    g.centre_w = (hi[0] - lo[0]) / 2, g.centre_h = (hi[1] - lo[1]) / 2;
    const int planes = hi[2] - lo[2] + 1;
    g.plane_start.resize(static_cast<std::size_t>(planes) + 1);
    std::int64_t at = 0;
    for (int z = 0; z < planes; ++z) {
        g.plane_start[static_cast<std::size_t>(z)] = at;
        at += (z % 2 == 0) ? g.corner_w * g.corner_h : g.centre_w * g.centre_h;
    }
    g.plane_start[static_cast<std::size_t>(planes)] = at;
    return g;
}

Grid Grid::whole(const Lattice3& lattice) {
    return window(lattice, {0, 0, 0},
                  {static_cast<int>(2 * lattice.cubes[0]), static_cast<int>(2 * lattice.cubes[1]),
                   static_cast<int>(2 * lattice.cubes[2])});
}

bcc::Ivec Grid::point(std::int64_t index) const {
    const auto z = static_cast<int>(std::upper_bound(plane_start.begin(), plane_start.end(), index) - plane_start.begin()) - 1;
    return point_in_plane(z, index);
}

bcc::Ivec Grid::point_in_plane(int z, std::int64_t index) const {
    const std::int64_t r = index - plane_start[static_cast<std::size_t>(z)];
    const int zz = lo[2] + z;
    if (z % 2 == 0)
        return {lo[0] + 2 * static_cast<int>(r % corner_w), lo[1] + 2 * static_cast<int>(r / corner_w), zz};
    return {lo[0] + 1 + 2 * static_cast<int>(r % centre_w), lo[1] + 1 + 2 * static_cast<int>(r / centre_w), zz};
}

}  // namespace uniform3d
}  // namespace warpmesh
