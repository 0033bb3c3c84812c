// resolution.hpp — is the lattice fine enough for the input?
//
// A lattice of spacing s cannot represent a part of the region, or a hole,
// that is only a square or two across: a disc of radius 1 at s = 1 becomes a
// 4-triangle diamond.  "Resolved" is defined on the mesh's boundary loops
// (the outline of each connected component and of each hole): a loop of
// enclosed area A and length P has the width 4A/P (the diameter of a disc,
// twice the width of a long strip), and it is resolved when that width is at
// least `min_squares` lattice squares.  The check cannot see parts that
// vanished altogether (smaller than a square); those lower the area, not the
// loop count.
//
// `finest` is the input's own resolution (1 for images: a spacing below a
// pixel adds no detail; 0 for analytic shapes).  A suggestion is never below
// it, and at a spacing <= finest nothing is reported unresolved: a label
// image's one-pixel islands are as resolved as the data allows.
#pragma once

#include <cstdint>

#include <optional>
#include <string>

#include "warpmesh/core/mesh.hpp"
#include "warpmesh/core/tet_mesh.hpp"
#include "warpmesh/levelset/levelset3.hpp"

namespace warpmesh {

struct ResolutionCheck {
    std::int64_t loops = 0;       // closed boundary loops (components and holes)
    std::int64_t unresolved = 0;  // loops narrower than min_squares squares
    double narrowest = 0;         // the smallest loop width 4A/P (mesh units; 0 without loops)
    // A spacing at which the narrowest loop would be min_squares squares
    // across (narrowest / min_squares, rounded down to two significant
    // digits, at least `finest`); 0 when every loop is resolved.
    double suggested_spacing = 0;
};

inline constexpr double default_min_squares_across = 4;

ResolutionCheck check_resolution(const Mesh& mesh, double spacing, double finest = 0,
                                 double min_squares = default_min_squares_across);

// 3D: a closed boundary component (boundary_level_set faces joined by
// shared vertices) of area A enclosing the volume V has the width 6V/A (a
// sphere's diameter); it is resolved at 4 spacings across, and f's
// feature_size() (when known) at 2.  f.resolution() plays `finest`.  The
// warning names the spacing that resolves the input.
struct ResolutionCheck3 {
    double narrowest_width = 0;     // the narrowest component's 6V/A (0 without one)
    double suggested_spacing = 0;   // 0: resolved
    std::optional<std::string> warning;
};
ResolutionCheck3 check_resolution3(const TetMesh& mesh, const LevelSet3& f, double spacing);
// The same from f's feature_size() and resolution() (merged blocks: no f).
ResolutionCheck3 check_resolution3(const TetMesh& mesh, double feature_size, double resolution, double spacing);

}  // namespace warpmesh
