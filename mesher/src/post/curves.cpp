// curves.cpp — the optimisation pass's slide curves and area budget
// (curves.hpp).
#include "curves.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "plane.hpp"
#include "warpmesh/mesh2d/materials.hpp"

namespace warpmesh {

namespace {

// g = phi_a - phi_b of a material field (curves.hpp).
class PairCurve final : public LevelSet {
public:
    PairCurve(const MaterialField& f, int a, int b) : f_(f), a_(a), b_(b) {}
    double value(double x, double y) const override { return f_.phi(a_, x, y) - f_.phi(b_, x, y); }
    Box bounds() const override { return f_.bounds(); }
    // fa < 0 < fb: a's phi is the smaller at `a`, b's at `b`; fa > 0 > fb:
    // the other way round (the field's search starts at `a` either way).
    double cut_parameter(Vec2 a, Vec2 b, double fa, double) const override {
        return fa < 0 ? f_.cut_parameter(a, b, a_, b_) : f_.cut_parameter(a, b, b_, a_);
    }
    std::string describe() const override { return "phi_" + std::to_string(a_) + " - phi_" + std::to_string(b_); }

private:
    const MaterialField& f_;
    int a_, b_;
};

}  // namespace

Vec2 zero_on_segment(const LevelSet& g, Vec2 p, Vec2 q, double gp, double gq) {
    using namespace plane;
    if (q.x < p.x || (q.x == p.x && q.y < p.y)) std::swap(p, q), std::swap(gp, gq);
    return p + g.cut_parameter(p, q, gp, gq) * (q - p);
}

SlideCurves::SlideCurves(const MaterialField& field) : field_(&field) {
    for (int m = 0; m < field.count(); ++m) {
        const std::int32_t t = field.tag(m);
        if (t < 0) continue;
        if (static_cast<std::size_t>(t) >= material_of_tag_.size()) material_of_tag_.resize(static_cast<std::size_t>(t) + 1, -1);
        material_of_tag_[static_cast<std::size_t>(t)] = m;
    }
}

int SlideCurves::material(std::int32_t region) const {
    return region >= 0 && static_cast<std::size_t>(region) < material_of_tag_.size() ? material_of_tag_[static_cast<std::size_t>(region)] : -1;
}

std::int32_t SlideCurves::pair_curve(std::int32_t a, std::int32_t b) const {
    if (a < 0 || b < 0 || a == b) return none;
    const auto [it, added] = ids_.try_emplace({a, b}, static_cast<std::int32_t>(curves_.size()));
    if (added) curves_.push_back(std::make_unique<PairCurve>(*field_, a, b));
    return it->second;
}

std::int32_t SlideCurves::boundary_curve(std::int32_t region) const {
    if (single_) return 0;
    return pair_curve(material(region), 0);  // the dropped background is material 0
}

std::int32_t SlideCurves::interface_curve(std::int32_t left, std::int32_t right) const {
    if (single_) return none;
    // One curve per pair, whichever side is left: phi_a - phi_b with a < b.
    const int a = material(left), b = material(right);
    return pair_curve(std::min(a, b), std::max(a, b));
}

std::optional<double> SlideCurves::reference_area(std::int32_t region) const {
    const int m = material(region);
    if (!field_ || m < 0) return std::nullopt;
    return field_->reference_area(m);
}

AreaBudget::AreaBudget(const Mesh& mesh, const SlideCurves& curves) {
    if (!curves.materials()) return;
    std::vector<double> area;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        const auto r = static_cast<std::size_t>(mesh.region[t]);
        if (r >= area.size()) area.resize(r + 1, 0.0);
        const Vec2 a = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][0])];
        const Vec2 b = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][1])];
        const Vec2 c = mesh.vertices[static_cast<std::size_t>(mesh.triangles[t][2])];
        area[r] += 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    }
    const double nan = std::numeric_limits<double>::quiet_NaN();
    bool any = false;
    error_.assign(area.size(), nan), budget_.assign(area.size(), nan), reference_.assign(area.size(), nan);
    for (std::size_t r = 0; r < area.size(); ++r)
        if (const auto ref = curves.reference_area(static_cast<std::int32_t>(r))) {
            reference_[r] = *ref;
            error_[r] = area[r] - *ref;
            budget_[r] = std::abs(error_[r]);
            any = true;
        }
    if (!any) error_.clear(), budget_.clear(), reference_.clear();
}

bool AreaBudget::allows(const AreaChange& change, bool strict) const {
    for (const auto& [r, a] : change) {
        if (r < 0 || static_cast<std::size_t>(r) >= error_.size() || std::isnan(error_[static_cast<std::size_t>(r)])) continue;
        const auto i = static_cast<std::size_t>(r);
        // Rounding of an area-neutral move (a junction's, Optimizer) is
        // allowed, 1e-13 of the reference per move: far below the final
        // check's 1e-9 after any number of moves the pass makes.
        if (std::abs(error_[i] + a) > (strict ? std::abs(error_[i]) : budget_[i]) + 1e-13 * std::abs(reference_[i])) return false;
    }
    return true;
}

void AreaBudget::apply(const AreaChange& change) {
    for (const auto& [r, a] : change)
        if (r >= 0 && static_cast<std::size_t>(r) < error_.size()) error_[static_cast<std::size_t>(r)] += a;
}

double AreaBudget::room(std::int32_t region, bool grow) const {
    const auto r = static_cast<std::size_t>(region);
    if (region < 0 || r >= error_.size() || std::isnan(error_[r])) return std::numeric_limits<double>::infinity();
    return grow ? budget_[r] - error_[r] : budget_[r] + error_[r];
}

bool AreaBudget::spent(std::int32_t region, bool grow) const {
    const auto r = static_cast<std::size_t>(region);
    if (region < 0 || r >= error_.size() || std::isnan(error_[r])) return false;
    return budget_[r] <= 1e-12 * std::abs(reference_[r]) && room(region, grow) <= 1e-12 * std::abs(reference_[r]);
}

std::string AreaBudget::worse(const AreaBudget& now) const {
    for (std::size_t r = 0; r < budget_.size() && r < now.budget_.size(); ++r)
        if (now.budget_[r] > budget_[r] + 1e-9 * std::abs(reference_[r]) + 1e-12)
            return "the area error of region " + std::to_string(r) + " grew from " + std::to_string(budget_[r]) + " to " +
                   std::to_string(now.budget_[r]) + " (a bug of the pass: nothing written; please report the input)";
    return {};
}

}  // namespace warpmesh
