// curves.hpp (internal) — the curves along which the optimisation pass
// (optimize.hpp) and its refinement (refine.hpp) slide boundary and
// interface vertices, and the per-region area budget of multi-material meshes.
//
// One region (optimize_mesh(Mesh&, const LevelSet&, ...)): every level-set
// boundary edge (tag 1) lies on f = 0, curve 0.  Interface edges (label
// mode's tagged regions of one level set) lie on no curve: their vertices
// stay put.
//
// Materials (optimize_mesh(Mesh&, const MaterialField&, ...)): region tags are
// the field's material tags (MaterialField::tag).  A level-set boundary edge
// separates its triangle's material m from the dropped background 0, so it
// lies on phi_m = phi_0; an interface edge between materials a and b on
// phi_a = phi_b.  Curve (a, b) is the level set g = phi_a - phi_b: negative on
// a's side.  A boundary edge's curve is (m, 0), negative inside its material
// as f is for one region (the refinement's boundary splits rely on it); an
// interface's is (min(a, b), max(a, b)), one curve whichever side is left
// (the sign does not matter there: the tangent is taken from g itself, and
// its zeros are found by zero_on_segment, whose point does not depend on g's
// sign).  Its cut_parameter is the field's (MaterialField::cut_parameter:
// exact on label images along the axes, a bracketed root elsewhere); its
// value is the field's phi, so a vertex projected onto it lies on the
// interface the mesher's cut points lie on.
//
// AreaBudget.  With reference areas (label images: pixel count x pixel area)
// every change of the pass must keep each region's area error |area -
// reference| at or below its value before the pass: so no label's area
// error grows.  Areas are tracked incrementally (the sum of the changes'
// signed areas); the only slack is rounding: 1e-13 of the region's reference
// area per change (an area-neutral junction move changes areas by ~1e-16),
// against the final check's 1e-9.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "warpmesh/levelset/levelset.hpp"
#include "warpmesh/core/mesh.hpp"

namespace warpmesh {

class MaterialField;

class SlideCurves {
public:
    static constexpr std::int32_t none = -1;
    explicit SlideCurves(const LevelSet& f) : single_(&f) {}
    explicit SlideCurves(const MaterialField& field);

    bool materials() const { return field_ != nullptr; }
    // The curve of a level-set boundary edge with `region` on its left; of an
    // interface edge with regions left, right (none for one region).
    std::int32_t boundary_curve(std::int32_t region) const;
    std::int32_t interface_curve(std::int32_t left, std::int32_t right) const;
    const LevelSet& curve(std::int32_t id) const { return single_ ? *single_ : *curves_[static_cast<std::size_t>(id)]; }
    // The reference area of a region tag, where the field knows it.
    std::optional<double> reference_area(std::int32_t region) const;

private:
    std::int32_t pair_curve(std::int32_t a, std::int32_t b) const;  // material numbers
    int material(std::int32_t region) const;

    const LevelSet* single_ = nullptr;
    const MaterialField* field_ = nullptr;
    std::vector<std::int32_t> material_of_tag_;  // region tag -> material number, -1: none
    // Created on first use (the pass is sequential).
    mutable std::map<std::pair<int, int>, std::int32_t> ids_;
    mutable std::vector<std::unique_ptr<LevelSet>> curves_;
};

// The zero of g on the segment between p and q, given g(p) = gp and g(q) =
// gq of strictly opposite signs: the root is searched from the endpoint that
// comes first in (x, y) order, whichever sign g has there, so the point
// depends on the segment and on g's zero set only, never on g's sign.  That
// is what keeps the pass independent of label numbers: the curve of two
// materials is phi_a - phi_b for material numbers a < b, which follow the
// label values, so renumbering the labels can reverse its sign; a search from
// the negative end then started from the other end and its point differed in
// the last bits, and so did every move and insertion after it (issue 50).
Vec2 zero_on_segment(const LevelSet& g, Vec2 p, Vec2 q, double gp, double gq);

// Per region tag: the signed area change of a move or a refined patch.
using AreaChange = std::vector<std::pair<std::int32_t, double>>;

class AreaBudget {
public:
    AreaBudget() = default;  // no reference areas: every change is allowed
    AreaBudget(const Mesh& mesh, const SlideCurves& curves);
    bool active() const { return !error_.empty(); }
    // Would every region's |area error| stay within its budget after `change`?
    // (strict: would no region's |area error| grow at all, up to rounding?)
    bool allows(const AreaChange& change, bool strict = false) const;
    void apply(const AreaChange& change);
    // How much area `region` may gain (grow) or lose within its budget now
    // (infinite without a reference).
    double room(std::int32_t region, bool grow) const;
    // Is that room none, up to rounding (1e-12 of the region's reference
    // area: what area-neutral moves, each allowed 1e-13 of it, may drift)?
    bool spent(std::int32_t region, bool grow) const;
    // Empty if no region of `now` (the budget of the mesh after the pass) has
    // a larger area error than its budget here (up to rounding: 1e-9 of the
    // region's reference area); else a message naming the first such region.
    std::string worse(const AreaBudget& now) const;

private:
    // Per region tag (index): the signed error area - reference now, and its
    // budget (|error| before the pass); NaN: no reference.
    std::vector<double> error_, budget_, reference_;
};

// Add `area` to region `region` in `change` (one entry per region).
inline void add_area(AreaChange& change, std::int32_t region, double area) {
    for (auto& [r, a] : change)
        if (r == region) {
            a += area;
            return;
        }
    change.emplace_back(region, area);
}

}  // namespace warpmesh
