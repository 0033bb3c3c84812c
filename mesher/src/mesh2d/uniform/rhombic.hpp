// rhombic.hpp — the 60-degree rhombic lattice
// (MeshOptions::lattice = LatticeMetric::rhombic, `--lattice rhombic`).
//
// The rhombic lattice is the square lattice under the linear map
//
//        P(x, y) = (x + y/2, (sqrt 3 / 2) y),
//
// which keeps every lattice edge's length (P(1, 0) and P(0, 1) are unit
// vectors 60 degrees apart) and splits each unwarped square, by its short
// diagonal BC, into two equilateral triangles.  Under P the whole uniform
// pipeline runs unchanged in lattice coordinates on g = f∘P: the cut points
// (P is linear, so a zero of f on the segment P a .. P b is at the same
// parameter), the warps (the closer endpoint of a cut edge and the nearest
// cut point of a point compare distances along lattice edges, which P
// scales by 1) and the topology.  Two things change: the diagonal rule
// compares the angles of the metric G = Pᵀ P (LatticeMetric::rhombic in
// generic_square.hpp), and the output vertices are mapped by P.
//
// Certified by its own certificates, proofs/rhombic_maxmin.cert and
// proofs/rhombic_separating.cert (the same configuration space as the
// square's, in lattice coordinates, measured in the metric G; proofs/README.md,
// "The rhombic lattice"): the pipeline certifies and verifies the mesh in
// lattice coordinates, before the map by P.
#pragma once

#include <cmath>

#include "warpmesh/levelset/levelset.hpp"
#include "warpmesh/core/mesh.hpp"

namespace warpmesh {

inline constexpr double rhombic_height = 0.86602540378443864676;  // sqrt(3) / 2

// P and its inverse.
inline Vec2 rhombic_map(Vec2 v) { return {v.x + 0.5 * v.y, rhombic_height * v.y}; }
inline Vec2 rhombic_unmap(Vec2 v) { return {v.x - 0.5 * v.y / rhombic_height, v.y / rhombic_height}; }

// g = f∘P in lattice coordinates.  An input whose bounds are its domain (an
// image) is clipped to that box, g = max(f∘P, d∘P) with d the box's signed
// distance (max-norm), since the lattice over P⁻¹(box) covers more than the
// box; g's bounds are then never the domain, and the lattice has a margin
// (so the image's border is meshed as level-set boundary, tag 1, not as
// boundary_domain, and the box's corners are cut like any corner of f).
class RhombicLevelSet final : public LevelSet {
public:
    explicit RhombicLevelSet(const LevelSet& f) : f_(f), clip_(f.bounds_are_domain()), box_(f.bounds()) {}
    double value(double x, double y) const override;
    Box bounds() const override;  // the box around P⁻¹(f.bounds())
    double cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const override;
    bool tags_regions() const override { return f_.tags_regions(); }
    std::int32_t region_at(double x, double y) const override;
    std::optional<double> exact_area() const override { return clip_ ? std::nullopt : f_.exact_area(); }
    std::string describe() const override { return f_.describe() + " on the rhombic lattice"; }

private:
    const LevelSet& f_;
    bool clip_;
    Box box_;
};

// Every vertex by P (lattice coordinates to physical ones); P has positive
// determinant, so triangles stay counter-clockwise and the boundary oriented.
void map_rhombic(Mesh& mesh);

}  // namespace warpmesh
