// shape_materials3.cpp — analytic 3D materials (materials3.hpp:
// parse_material_shapes3): shape k is material k + 1, a later shape wins.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "../core/root_finder.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/levelset/materials3.hpp"
#include "warpmesh/levelset/shapes.hpp"  // parse_tagged_shapes

namespace warpmesh {
namespace {

class ShapeMaterials3 final : public MaterialField3 {
public:
    ShapeMaterials3(std::vector<std::int32_t> tags, std::vector<std::unique_ptr<LevelSet3>> shapes, std::string spec)
        : tags_(std::move(tags)), shapes_(std::move(shapes)), spec_(std::move(spec)) {}
    int count() const override { return static_cast<int>(tags_.size()); }
    std::int32_t tag(int m) const override { return tags_[static_cast<std::size_t>(m)]; }
    std::string name(int m) const override { return m == 0 ? "background" : "material_" + std::to_string(tag(m)); }
    Box3 bounds() const override {
        Box3 b = shapes_[0]->bounds();
        for (const auto& s : shapes_) {
            const Box3 c = s->bounds();
            b = {std::min(b.xmin, c.xmin), std::min(b.ymin, c.ymin), std::min(b.zmin, c.zmin),
                 std::max(b.xmax, c.xmax), std::max(b.ymax, c.ymax), std::max(b.zmax, c.zmax)};
        }
        return b;
    }
    std::string describe() const override { return "shapes " + spec_ + " (a later shape wins; outside all: background 0)"; }

    // phi_m = max(f_m, −f_k for k > m); phi_0 = max(−f_k).
    double phi(int m, Point3 p) const {
        double v = m == 0 ? -std::numeric_limits<double>::infinity() : shapes_[static_cast<std::size_t>(m - 1)]->value(p.x, p.y, p.z);
        for (std::size_t k = static_cast<std::size_t>(m); k < shapes_.size(); ++k) v = std::max(v, -shapes_[k]->value(p.x, p.y, p.z));
        return v;
    }
    // One evaluation per shape: the suffix maxima of −f give every phi_m.
    int material_at(Point3 p) const override {
        double suffix = -std::numeric_limits<double>::infinity();  // max(−f_k, k > m)
        double best = std::numeric_limits<double>::infinity();
        int pick = 0;
        for (std::size_t k = shapes_.size(); k-- > 0;) {  // material k + 1, from the last
            const double f = shapes_[k]->value(p.x, p.y, p.z);
            if (!std::isfinite(f)) throw InputError("shape " + shapes_[k]->describe() + " is not finite at some lattice point");
            const double v = std::max(f, suffix);
            if (v < best) best = v, pick = static_cast<int>(k + 1);  // descending: a tie keeps the later shape
            suffix = std::max(suffix, -f);
        }
        return suffix < best ? 0 : pick;
    }
    double cut_parameter(Point3 a, Point3 b, int ma, int mb) const override {
        const auto g = [&](double u) {
            const Point3 x{a.x + u * (b.x - a.x), a.y + u * (b.y - a.y), a.z + u * (b.z - a.z)};
            return phi(ma, x) - phi(mb, x);
        };
        const double g0 = g(0), g1 = g(1);
        if (!(g0 < 0)) return inside_unit_interval(0);  // a tie at a: the cut is at a
        if (!(g1 > 0)) return inside_unit_interval(1);
        return bracketed_root_of(g, g0, g1);
    }

private:
    std::vector<std::int32_t> tags_;
    std::vector<std::unique_ptr<LevelSet3>> shapes_;
    std::string spec_;
};

}  // namespace

std::unique_ptr<MaterialField3> parse_material_shapes3(const std::string& spec) {
    std::vector<std::int32_t> tags{0};
    std::vector<std::unique_ptr<LevelSet3>> shapes;
    for (auto& [tag, shape] : parse_tagged_shapes(spec, "1=sphere:0,0,0,1;2=box:-1,-1,-1,0,0,0")) {
        tags.push_back(tag);
        shapes.push_back(parse_shape3(shape));
    }
    return std::make_unique<ShapeMaterials3>(std::move(tags), std::move(shapes), spec);
}

}  // namespace warpmesh
