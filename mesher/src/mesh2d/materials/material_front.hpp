// material_front.hpp — the stages the uniform (mesh_materials.cpp) and
// graded (mesh_materials_graded.cpp) multi-material meshers share.  Private
// to mesher/src.
//
//   material_front     materials per lattice point → cut edges → warp
//                      (materials.hpp, steps 1 - 3);
//   material_diagonal  a warped square's diagonal by the rule the prover
//                      certifies, on its material corners;
//   warped_square      a warped square's diagonal, its two triangles'
//                      materials and areas (both meshers' inner loop);
//   record_material_keys  what the certification reads: the keyed squares'
//                      stencils (one or two materials) or junction keys,
//                      junction squares listed;
//   finish_materials   per-material statistics and region names.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "warpmesh/core/buffer.hpp"
#include "warpmesh/mesh2d/materials.hpp"

#include "mesh2d/square_code.hpp"

namespace warpmesh {

struct MaterialFront {
    std::int64_t nxp = 0;                 // lattice points a row
    Buffer<std::uint16_t> mat;            // the material of every lattice point
    std::vector<WarpedPoint> warped;      // sorted by point
    Buffer<std::uint8_t> moved;           // 1 at the warped points
    std::int64_t cut_edges = 0, third_material_edges = 0;

    // The warp record of a warped point p.
    const WarpedPoint& warp_of(std::int64_t p) const {
        return *std::lower_bound(warped.begin(), warped.end(), p, [](const WarpedPoint& w, std::int64_t q) { return w.p < q; });
    }
    // The position of lattice point p = (i, j) as a mesh vertex: warped points
    // moved by the affine map of generic_positions, scaled by s (the same
    // doubles in both meshers).
    Vec2 position(const Lattice& lattice, std::int64_t p, std::int64_t i, std::int64_t j) const {
        Vec2 x = lattice.position(i, j);
        if (moved[static_cast<std::size_t>(p)]) {
            const WarpedPoint& wp = warp_of(p);
            x.x += warp_dx(wp.dir) * wp.t * lattice.s;
            x.y += warp_dy(wp.dir) * wp.t * lattice.s;
        }
        return x;
    }
    Vec2 position(const Lattice& lattice, std::int64_t p) const { return position(lattice, p, p % nxp, p / nxp); }
};

// Throws InputError for DiagonalRule::maxmin or a material count outside 1 .. 65536.
void check_material_options(const MaterialField& field, const MaterialOptions& options);

// Steps 1 - 3 of materials.hpp, timed into r.times.sample, .cut_points,
// .warp; also sets r.cut_edges, r.third_material_edges, r.warped_points.
MaterialFront material_front(const MaterialField& field, const Lattice& lattice, MaterialResult& r);

// What the rule takes on the warped square with these material corners and
// slide lengths, with the square's tie-break `tie` (union_jack: as the
// two-phase meshers): AD, BC or (fan rule) the centroid fan; `forced`: the
// separating rule overrode max-min.
SquareSplit material_split(DiagonalRule rule, const std::array<MaterialCorner, 4>& cs, const std::array<double, 4>& t, bool& forced,
                           TieBreak tie);

// A warped square (corners p = A, B, C, D; A at lattice (i, j)): its code
// (rule_bit, and bc_bit when the rule takes BC), each triangle's material —
// the common material of its unwarped corners (materials.hpp: the separating
// rule leaves no triangle with two unwarped corners of different materials;
// `mixed` counts violations, which must be none), or the material at its
// centroid when all three corners moved (`by_centroid`) — and twice each
// triangle's signed area.  The fan rule's centroid fan (fan_bit; its
// staying corners share one material, generic_square.hpp's all_inside):
// all four triangles take that material, or the material at the centre when
// every corner moved (4 `by_centroid`); material[0] = material[1] is it and
// area2[0] + area2[1] twice the square's area (the fan's four triangles
// tile the same quadrilateral as a diagonal's two).
struct WarpedSquare {
    std::uint8_t code = square_code::rule_bit;
    bool forced = false;  // the separating rule overrode max-min
    std::array<int, 2> material{};
    std::array<double, 2> area2{};
    int mixed = 0, by_centroid = 0;
};
inline WarpedSquare warped_square(const MaterialFront& front, const Lattice& lattice, const MaterialField& field,
                                  DiagonalRule rule, const std::array<std::int64_t, 4>& p, std::int64_t i, std::int64_t j) {
    WarpedSquare w;
    std::array<MaterialCorner, 4> cs{};
    std::array<double, 4> t{};
    std::array<Vec2, 4> x{};
    for (std::size_t q = 0; q < 4; ++q) {
        cs[q].material = front.mat[static_cast<std::size_t>(p[q])];
        if (front.moved[static_cast<std::size_t>(p[q])]) {
            const WarpedPoint& wp = front.warp_of(p[q]);
            cs[q].warp = wp.dir, t[q] = wp.t;
        }
        x[q] = front.position(lattice, p[q], i + static_cast<std::int64_t>(q & 1), j + static_cast<std::int64_t>(q >> 1));
    }
    const SquareSplit split = material_split(rule, cs, t, w.forced, union_jack(i, j));
    if (split == SquareSplit::bc) w.code |= square_code::bc_bit;
    if (split == SquareSplit::fan) {
        w.code |= square_code::fan_bit;
        int m = -1;
        for (const MaterialCorner& mc : cs)
            if (mc.warp == Warp::stay) m = mc.material;
        if (m < 0) {
            const Vec2 c = square_code::fan_centre_position(x);
            m = field.material_at(c.x, c.y);
            w.by_centroid = 4;
        }
        w.material = {m, m};
    }
    for (int k = 0; k < 2; ++k) {
        const auto tri = square_code::triangle_of(w.code, k);
        int m = -1;
        for (int v : tri) {
            const MaterialCorner& mc = cs[static_cast<std::size_t>(v)];
            if (mc.warp != Warp::stay) continue;
            if (m >= 0 && m != mc.material) ++w.mixed;
            m = mc.material;
        }
        const Vec2 &a = x[static_cast<std::size_t>(tri[0])], &b = x[static_cast<std::size_t>(tri[1])],
                   &e = x[static_cast<std::size_t>(tri[2])];
        if (split == SquareSplit::fan) m = w.material[static_cast<std::size_t>(k)];
        if (m < 0) {
            m = field.material_at((a.x + b.x + e.x) / 3, (a.y + b.y + e.y) / 3);
            ++w.by_centroid;
        }
        w.material[static_cast<std::size_t>(k)] = m;
        w.area2[static_cast<std::size_t>(k)] = (b.x - a.x) * (e.y - a.y) - (b.y - a.y) * (e.x - a.x);
    }
    return w;
}

// What the certification reads of r.mesh (materials.hpp, "Certification"):
// fills r.keys, r.junction_squares, r.junction_examples (their bounds left to
// the certification).  `keyed`: the finest warped squares that emit a
// triangle, with their triangles.
void record_material_keys(MaterialResult& r, const Lattice& lattice, const MaterialFront& front, std::vector<KeyedSquare> keyed,
                          const MaterialField& field);

// r.materials from the per-material triangle counts, doubled areas and
// perimeters of the full tiling; region names of the output materials with
// triangles.
void finish_materials(MaterialResult& r, const MaterialField& field, bool drop, std::span<const std::int64_t> triangles,
                      std::span<const double> area2, std::span<const double> perimeter);

}  // namespace warpmesh
