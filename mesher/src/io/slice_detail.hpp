// slice_detail.hpp (internal) — a slice of a volume checked, its values and
// its placement: the steps place_slice (io/slice.cpp) and load_slice and
// slice_image (pipeline/load_slice.cpp) share.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "warpmesh/io/volume.hpp"

namespace warpmesh::slice_detail {

// The axes' names, "ijk"[axis].
inline constexpr const char* axis_names = "ijk";

// The slice a SliceOptions::slice names, checked: its normal axis n, in-plane
// axes a < b, size W x H, and name for messages.
struct CheckedSlice {
    SliceSpec spec;
    int n, a, b;
    std::int64_t W, H;
    std::string name;
};
CheckedSlice check_slice(const Volume& v, const std::optional<SliceSpec>& slice);

// The slice's values, y-up: pixel (ia, ib) at ia + W ib.
std::vector<double> slice_values(const Volume& v, const CheckedSlice& c);

// Where the checked slice lies (volume.hpp): in millimetres, pixel (ia, ib)
// at (x0 + ia sa, y0 + ib sb), x0 and y0 the origin's components along the
// in-plane axes, and the plane's origin the 3D point of (0, 0); in pixels,
// at (ia, ib), the plane's axes scaled by the pixel sizes.
SlicePlacement placement(const Volume& v, const CheckedSlice& c, Units units, bool slice_given);

}  // namespace warpmesh::slice_detail
