// load_slice.cpp — from a volume to the level set (or the material field) of
// one of its slices, placed as io/slice.cpp places it (pipeline/slices.hpp).
#include <string>

#include "io/slice_detail.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/core/memory.hpp"
#include "warpmesh/pipeline/slices.hpp"

namespace warpmesh {
namespace {

using slice_detail::CheckedSlice;
using slice_detail::check_slice;
using slice_detail::placement;
using slice_detail::slice_values;

}  // namespace

Image slice_image(const Volume& v, const std::optional<SliceSpec>& slice) {
    const CheckedSlice c = check_slice(v, slice);
    Image img = label_image(static_cast<int>(c.W), static_cast<int>(c.H), slice_values(v, c), c.name, "a label slice");
    if (v.maxval >= 0) img.maxval = v.maxval;
    return img;
}

LoadedSlice load_slice(const Volume& v, const SliceOptions& options) {
    const CheckedSlice c = check_slice(v, options.slice);
    // Materials: make_label_materials makes the same admission check.
    if (!options.materials) {
        const FieldKind kind = options.levelset.mode == ImageMode::label ? FieldKind::label : FieldKind::threshold;
        check_memory(static_cast<std::uint64_t>(c.W * c.H) * field_bytes_per_pixel(kind), options.max_memory,
                     "the level set of '" + c.name + "'",
                     std::to_string(c.W) + " x " + std::to_string(c.H) + " pixels at " +
                         std::to_string(field_bytes_per_pixel(kind)) + " bytes each",
                     "crop or downsample the image");
    }
    LoadedSlice out;
    static_cast<SlicePlacement&>(out) = placement(v, c, options.units, options.slice.has_value());
    out.width = static_cast<int>(c.W), out.height = static_cast<int>(c.H);
    out.slice = c.spec;
    out.format = v.format;
    const std::vector<double> values = slice_values(v, c);
    if (options.materials) {
        Image img = label_image(out.width, out.height, values, c.name, "--materials");
        if (v.maxval >= 0) img.maxval = v.maxval;
        out.materials = make_label_materials(img, *options.materials, out.geometry, options.max_memory);
    } else {
        ImageLevelSetOptions lo = options.levelset;
        lo.geometry = out.geometry;
        out.f = make_raster_levelset(out.width, out.height, values, c.name, lo, v.maxval);
    }
    return out;
}

LoadedSlice load_level_set(const std::string& path, const SliceOptions& options, const VolumeLimits& limits) {
    return load_slice(read_volume(path, limits), options);
}

}  // namespace warpmesh
