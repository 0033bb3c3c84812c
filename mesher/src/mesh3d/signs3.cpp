// signs3.cpp — stage 2: f and its sign at every point of a window (step 1 of
// generic_bcc.hpp's contract), in parallel over the z planes.
#include <cmath>

#include "uniform3d.hpp"
#include "warpmesh/core/errors.hpp"

namespace warpmesh::uniform3d {

void sample_signs(const LevelSet3& f, Window& w) {
    const Grid& g = w.grid;
    const std::size_t n = static_cast<std::size_t>(g.count());
    w.value.resize(n);  // every element written below
    w.sign.resize(n);
    const int planes = g.hi[2] - g.lo[2] + 1;
    bool finite = true;
#pragma omp parallel for schedule(dynamic, 1) reduction(&& : finite)
    for (int z = 0; z < planes; ++z) {
        const int zz = g.lo[2] + z, odd = zz & 1;
        std::int64_t at = g.plane_start[static_cast<std::size_t>(z)];
        for (int y = g.lo[1] + odd; y <= g.hi[1] - odd; y += 2)
            for (int x = g.lo[0] + odd; x <= g.hi[0] - odd; x += 2, ++at) {
                const Point3 p = g.lattice.position({x, y, zz});
                const double v = f.value(p.x, p.y, p.z);
                finite = finite && std::isfinite(v);
                w.value[static_cast<std::size_t>(at)] = v;
                w.sign[static_cast<std::size_t>(at)] = static_cast<std::int8_t>(v < 0 ? -1 : v > 0 ? 1 : 0);
            }
    }
    if (!finite) throw InputError("the level set " + f.describe() + " is not finite at some lattice point");
}

}  // namespace warpmesh::uniform3d
