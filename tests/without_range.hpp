// without_range.hpp — a level set that forwards everything to another except
// range(): it knows no bound, so the graded mesher samples every tile
// (src/mesh2d/graded/tiles.hpp).  Meshes made through it are the reference the range-bounded
// front end must reproduce exactly.
#pragma once

#include "warpmesh/levelset/levelset.hpp"

namespace warpmesh::testing {

class WithoutRange final : public LevelSet {
public:
    explicit WithoutRange(const LevelSet& f) : f_(f) {}
    double value(double x, double y) const override { return f_.value(x, y); }
    Box bounds() const override { return f_.bounds(); }
    double cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const override { return f_.cut_parameter(a, b, fa, fb); }
    void sample_block(const Lattice& l, const PointBlock& b, std::span<double> out) const override {
        f_.sample_block(l, b, out);
    }
    bool tags_regions() const override { return f_.tags_regions(); }
    std::int32_t region_at(double x, double y) const override { return f_.region_at(x, y); }
    std::optional<double> exact_area() const override { return f_.exact_area(); }
    std::string describe() const override { return f_.describe() + " (no range bound)"; }

private:
    const LevelSet& f_;
};

// Whether two meshes are the same, bit for bit.
inline bool same_mesh(const Mesh& a, const Mesh& b) {
    auto same_vertices = [&] {
        if (a.vertices.size() != b.vertices.size()) return false;
        for (std::size_t k = 0; k < a.vertices.size(); ++k)
            if (a.vertices[k].x != b.vertices[k].x || a.vertices[k].y != b.vertices[k].y) return false;
        return true;
    };
    return same_vertices() && a.triangles == b.triangles && a.boundary == b.boundary &&
           a.boundary_tag == b.boundary_tag && a.region == b.region;
}

}  // namespace warpmesh::testing
