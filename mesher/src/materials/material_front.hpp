// material_front.hpp — the stages the uniform (mesh_materials.cpp) and
// graded (mesh_materials_graded.cpp) multi-material meshers share.  Private
// to mesher/src.
//
//   material_front     materials per lattice point → cut edges → warp
//                      (materials.hpp, steps 1 - 3);
//   material_diagonal  a warped square's diagonal by the rule the prover
//                      certifies, on its material corners;
//   material_squares   the certification post-pass: the keyed squares with
//                      one or two materials looked up, junction squares listed;
//   finish_materials   per-material statistics and region names.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "warpmesh/buffer.hpp"
#include "warpmesh/materials.hpp"

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

// Steps 1 - 3 of materials.hpp, timed into times.sample, .cut_points, .warp.
MaterialFront material_front(const MaterialField& field, const Lattice& lattice, PhaseTimes& times);

// Whether the rule takes BC on the warped square with these material corners
// and slide lengths; `forced`: the separating rule overrode max-min.
bool material_diagonal_bc(DiagonalRule rule, const std::array<MaterialCorner, 4>& cs, const std::array<double, 4>& t, bool& forced);

// The certification post-pass (materials.hpp, "Certification") on r.mesh:
// fills r.certified, r.junction_squares, r.junction_examples, r.times.certify.
// `keyed`: the finest warped squares that emit a triangle, with their triangles.
void certify_material_mesh(MaterialResult& r, const Lattice& lattice, const MaterialFront& front,
                           std::span<const KeyedSquare> keyed, const MaterialOptions& options, const MaterialField& field);

// r.materials from the per-material triangle counts, doubled areas and
// perimeters of the full tiling; region names of the output materials with
// triangles.
void finish_materials(MaterialResult& r, const MaterialField& field, bool drop, std::span<const std::int64_t> triangles,
                      std::span<const double> area2, std::span<const double> perimeter);

}  // namespace warpmesh
