// square_keys.hpp — the names of the generic square's configurations and the
// flatness of their sign stencils: what the 2D certificates are keyed by,
// shared by the mesher's certification (certify/certified.hpp) and the 2D
// prover (prover/src/keys.cpp, junction_keys.cpp).  The independent checker
// (checker/checker.cpp) has its own copies, on purpose.
#pragma once

#include <array>
#include <cstdint>
#include <string>

#include "warpmesh/mesh2d/generic_square.hpp"

namespace warpmesh {

// ---- key codes -----------------------------------------------------------------
// The key code of a square's corner states, e.g. "-R+U-L-R": per corner
// A, B, C, D its sign (- 0 +) and its warp (s R L U D: stay, +x, -x, +y, -y).
std::string key_code(const std::array<CornerState, 4>& corners);

// Junction keys (multi-material squares whose corners carry 3 or 4
// materials; proofs/README.md, "Junction keys"): `corners[c].material`
// is corner c's material class, the letters 0..3 in order of first appearance
// A, B, C, D, and the code is letters and warps, e.g. "aRaUbscs".
std::string junction_key_code(const std::array<MaterialCorner, 4>& corners);
// The corners' material classes in first-appearance order (materials → 0..3),
// warps kept: the key of a square with materials `corners`.
std::array<MaterialCorner, 4> junction_letters(const std::array<MaterialCorner, 4>& corners);

// ---- flatness ----------------------------------------------------------------
// The 12-point stencil of square (i, j), in the order
//   A, B, C, D, A:(-1,0), A:(0,-1), B:(2,0), B:(1,-1), C:(-1,1), C:(0,2), D:(2,1), D:(1,2)
// (offsets from A).  True iff some affine a x + b y + c has exactly these signs
// (0 = on the line).  Exact (integer) test, cached.
inline constexpr std::array<std::array<int, 2>, 12> stencil_offsets{{{0, 0}, {1, 0}, {0, 1}, {1, 1},
                                                                     {-1, 0}, {0, -1}, {2, 0}, {1, -1},
                                                                     {-1, 1}, {0, 2}, {2, 1}, {1, 2}}};
bool stencil_is_flat(const std::array<std::int8_t, 12>& signs);
// The sign given a stencil point outside the lattice: such a stencil is not
// flat (certification counts the square as non-flat).
inline constexpr std::int8_t off_lattice = 9;
// True iff some affine a x + b y + c has the signs `signs[q]` at the stencil
// points q in `known` (bit q), whatever its signs elsewhere.  `known` must
// contain the four corners (bits 0-3; else std::invalid_argument).  The
// prover's flat-compatible keys: the corners' signs and the outside
// neighbours of the outward slides.  stencil_admits_flat(s, 0xfff) ==
// stencil_is_flat(s).
bool stencil_admits_flat(const std::array<std::int8_t, 12>& signs, std::uint16_t known);

}  // namespace warpmesh
