// material_field.cpp — MaterialField's defaults and the analytic materials
// (--shapes), materials.hpp.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <set>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/levelset/shapes.hpp"

namespace warpmesh {

int MaterialField::material_at(double x, double y) const {
    double best = std::numeric_limits<double>::infinity();
    int pick = 0;
    // Ascending: an exact tie goes to the larger material number.  (Fields
    // whose numbers are label values override this with a geometric tie rule:
    // label_materials.cpp; for shapes the number is the spec's order.)
    for (int m = 0; m < count(); ++m) {
        const double v = phi(m, x, y);
        if (v <= best) best = v, pick = m;
    }
    return pick;
}

void MaterialField::sample_block(const Lattice& lattice, const PointBlock& b, std::span<std::uint16_t> out) const {
#pragma omp parallel for schedule(dynamic, 4) if (b.ni * b.nj >= 4096)
    for (std::int64_t j = 0; j < b.nj; ++j)
        for (std::int64_t i = 0; i < b.ni; ++i) {
            const Vec2 p = lattice.position(b.i0 + i, b.j0 + j);
            out[static_cast<std::size_t>(i + j * b.ni)] = static_cast<std::uint16_t>(material_at(p.x, p.y));
        }
}

namespace {

// phi_ma - phi_mb as a level set, for the bracketed root finder.
class Difference final : public LevelSet {
public:
    Difference(const MaterialField& f, int a, int b) : f_(f), a_(a), b_(b) {}
    double value(double x, double y) const override { return f_.phi(a_, x, y) - f_.phi(b_, x, y); }
    Box bounds() const override { return f_.bounds(); }
    std::string describe() const override { return "phi_a - phi_b"; }

private:
    const MaterialField& f_;
    int a_, b_;
};

}  // namespace

double MaterialField::cut_parameter(Vec2 a, Vec2 b, int ma, int mb) const {
    const Difference g(*this, ma, mb);
    const double ga = g.value(a.x, a.y), gb = g.value(b.x, b.y);
    // ma wins at a and mb at b, so ga <= 0 <= gb; an exact 0 is a tie at that end.
    if (!(ga < 0)) return std::numeric_limits<double>::denorm_min();
    if (!(gb > 0)) return 1 - std::numeric_limits<double>::epsilon() / 2;
    return bracketed_root(g, a, b, ga, gb);
}

namespace {

class ShapeMaterials final : public MaterialField {
public:
    ShapeMaterials(std::vector<std::int32_t> tags, std::vector<std::unique_ptr<Shape>> shapes, std::string spec)
        : tags_(std::move(tags)), shapes_(std::move(shapes)), spec_(std::move(spec)) {}
    int count() const override { return static_cast<int>(tags_.size()); }
    std::int32_t tag(int m) const override { return tags_[static_cast<std::size_t>(m)]; }
    std::string name(int m) const override { return m == 0 ? "background" : "material_" + std::to_string(tag(m)); }
    Box bounds() const override {
        Box b = shapes_[0]->bounds();
        for (const auto& s : shapes_) {
            const Box c = s->bounds();
            b = {std::min(b.xmin, c.xmin), std::min(b.ymin, c.ymin), std::max(b.xmax, c.xmax), std::max(b.ymax, c.ymax)};
        }
        return b;
    }
    std::string describe() const override { return "shapes " + spec_ + " (a later shape wins; outside all: background 0)"; }

    // phi_m = max(f_m, -f_k for k > m); phi_0 = max(-f_k).  (Shape k is material k.)
    double phi(int m, double x, double y) const override {
        double v = m == 0 ? -std::numeric_limits<double>::infinity() : shapes_[static_cast<std::size_t>(m - 1)]->value(x, y);
        for (std::size_t k = static_cast<std::size_t>(m); k < shapes_.size(); ++k) v = std::max(v, -shapes_[k]->value(x, y));
        return v;
    }
    // One evaluation per shape: the suffix maxima of -f give every phi_m.
    int material_at(double x, double y) const override {
        const std::size_t n = shapes_.size();
        double suffix = -std::numeric_limits<double>::infinity();  // max(-f_k, k > m)
        double best = std::numeric_limits<double>::infinity();
        int pick = 0;
        for (std::size_t k = n; k-- > 0;) {  // material k + 1, from the last
            const double f = shapes_[k]->value(x, y);
            const double v = std::max(f, suffix);
            if (v < best) best = v, pick = static_cast<int>(k + 1);  // descending: ties keep the later shape (spec order, not tags)
            suffix = std::max(suffix, -f);
        }
        if (suffix < best) pick = 0;
        return pick;
    }

private:
    std::vector<std::int32_t> tags_;
    std::vector<std::unique_ptr<Shape>> shapes_;
    std::string spec_;
};

}  // namespace

std::unique_ptr<MaterialField> parse_material_shapes(const std::string& spec) {
    std::vector<std::int32_t> tags{0};
    std::vector<std::unique_ptr<Shape>> shapes;
    for (auto& [tag, shape] : parse_tagged_shapes(spec, "1=circle:0,0,10;2=circle:6,0,8")) {
        tags.push_back(tag);
        shapes.push_back(parse_shape(shape));
    }
    return std::make_unique<ShapeMaterials>(std::move(tags), std::move(shapes), spec);
}

}  // namespace warpmesh
