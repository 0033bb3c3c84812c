// rhombic.cpp — the rhombic lattice's level set g = f∘P and its
// output map (rhombic.hpp).
#include "rhombic.hpp"

#include <algorithm>

namespace warpmesh {

double RhombicLevelSet::value(double x, double y) const {
    const Vec2 p = rhombic_map({x, y});
    const double v = f_.value(p.x, p.y);
    if (!clip_) return v;
    const double d = std::max({box_.xmin - p.x, p.x - box_.xmax, box_.ymin - p.y, p.y - box_.ymax});
    return std::max(v, d);
}

Box RhombicLevelSet::bounds() const {
    const Vec2 c[4] = {rhombic_unmap({box_.xmin, box_.ymin}), rhombic_unmap({box_.xmax, box_.ymin}),
                       rhombic_unmap({box_.xmin, box_.ymax}), rhombic_unmap({box_.xmax, box_.ymax})};
    Box b{c[0].x, c[0].y, c[0].x, c[0].y};
    for (const Vec2& v : c) {
        b.xmin = std::min(b.xmin, v.x), b.xmax = std::max(b.xmax, v.x);
        b.ymin = std::min(b.ymin, v.y), b.ymax = std::max(b.ymax, v.y);
    }
    return b;
}

// P is linear: the zero of f on P a .. P b is at the same parameter (the
// input's exact roots, e.g. circles, carry over); a clipped image's g is
// a max of two functions: the bracketed root finder on g itself.
double RhombicLevelSet::cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const {
    if (clip_) return bracketed_root(*this, a, b, fa, fb);
    return f_.cut_parameter(rhombic_map(a), rhombic_map(b), fa, fb);
}

std::int32_t RhombicLevelSet::region_at(double x, double y) const {
    const Vec2 p = rhombic_map({x, y});
    return f_.region_at(p.x, p.y);
}

void map_rhombic(Mesh& mesh) {
    const std::int64_t n = static_cast<std::int64_t>(mesh.vertices.size());
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < n; ++k) mesh.vertices[static_cast<std::size_t>(k)] = rhombic_map(mesh.vertices[static_cast<std::size_t>(k)]);
}

}  // namespace warpmesh
