// slice.cpp — from a volume to the level set of one of its slices, in
// millimetres or pixels (the conventions are in volume.hpp).
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/core/memory.hpp"
#include "warpmesh/post/quality.hpp"
#include "warpmesh/io/volume.hpp"

namespace warpmesh {
namespace {

constexpr const char* axis_names = "ijk";

int axis_of(const std::string& text, const std::string& what) {
    if (text.size() < 2 || text[1] != '=' || (text[0] != 'i' && text[0] != 'j' && text[0] != 'k'))
        throw InputError("bad " + what + " '" + text + "': expected AXIS=INDEX with AXIS i, j or k (e.g. k=60" +
                         (what == "--slices" ? std::string(", or k=0:113 for slices 0 to 112") : std::string()) + ")");
    return text[0] - 'i';
}

std::int64_t index_of(const std::string& whole, std::string_view t, const std::string& what) {
    std::int64_t v = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
    if (t.empty() || ec != std::errc{} || end != t.data() + t.size() || v < 0)
        throw InputError("bad " + what + " '" + whole + "': '" + std::string(t) + "' is not a slice index (0, 1, ...)");
    return v;
}

Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

}  // namespace

SliceSpec parse_slice(const std::string& text) {
    const int axis = axis_of(text, "--slice");
    return {axis, index_of(text, std::string_view(text).substr(2), "--slice")};
}

SliceRange parse_slice_range(const std::string& text) {
    const int axis = axis_of(text, "--slices");
    const std::string_view rest = std::string_view(text).substr(2);
    const std::size_t colon = rest.find(':');
    if (colon == std::string_view::npos) {
        const std::int64_t k = index_of(text, rest, "--slices");
        return {axis, k, k + 1};
    }
    const std::int64_t a = index_of(text, rest.substr(0, colon), "--slices");
    const std::int64_t b = index_of(text, rest.substr(colon + 1), "--slices");
    if (b <= a) throw InputError("bad --slices '" + text + "': the range FIRST:END (END excluded) is empty");
    return {axis, a, b};
}

void set_pixel_size(Volume& volume, std::span<const double> size) {
    if (size.empty() || size.size() > 3) throw InputError("--pixel-size expects SX[,SY[,SZ]]");
    for (std::size_t a = 0; a < 3; ++a) {
        const double s = size[std::min(a, size.size() - 1)];
        if (!(s > 1e-12 && s < 1e12)) throw InputError("--pixel-size: " + std::to_string(s) + " is not a positive size");
        volume.spacing[a] = s;
    }
    volume.physical = true;
}

namespace {

// The slice a SliceOptions::slice names, checked: its normal axis n, in-plane
// axes a < b, size W x H, and name for messages.
struct CheckedSlice {
    SliceSpec spec;
    int n, a, b;
    std::int64_t W, H;
    std::string name;
};

CheckedSlice check_slice(const Volume& v, const std::optional<SliceSpec>& slice) {
    const bool one_slice = v.dims[2] == 1;
    if (!slice && !one_slice)
        throw InputError("'" + v.source + "' is a volume of " + std::to_string(v.dims[0]) + " x " +
                         std::to_string(v.dims[1]) + " x " + std::to_string(v.dims[2]) +
                         " voxels: choose a slice with --slice k=INDEX (or i=, j=), or several with --slices k=FIRST:END");
    const SliceSpec spec = slice.value_or(SliceSpec{2, 0});
    const int n = spec.axis;
    if (n < 0 || n > 2) throw InputError("slice axis must be i, j or k");
    if (spec.index < 0 || spec.index >= v.dims[n])
        throw InputError("slice " + std::string(1, axis_names[n]) + "=" + std::to_string(spec.index) + " is outside '" +
                         v.source + "' (" + axis_names[n] + " = 0.." + std::to_string(v.dims[n] - 1) + ")");
    const int a = n == 0 ? 1 : 0, b = n == 2 ? 1 : 2;  // in-plane axes, a < b
    const std::int64_t W = v.dims[a], H = v.dims[b];
    const std::string name = slice ? v.source + " slice " + axis_names[n] + "=" + std::to_string(spec.index) : v.source;
    if (W < 2 || H < 2)
        throw InputError("'" + name + "': the slice is " + std::to_string(W) + " x " + std::to_string(H) +
                         " pixels; at least 2 x 2 are needed for one lattice square");
    if (W > 0x7fffffff || H > 0x7fffffff) throw InputError("'" + name + "': slice too large");
    return {spec, n, a, b, W, H, name};
}

}  // namespace

namespace {

// The slice's values, y-up: pixel (ia, ib) at ia + W ib.
std::vector<double> slice_values(const Volume& v, const CheckedSlice& c) {
    std::vector<double> values(static_cast<std::size_t>(c.W * c.H));
    std::array<std::int64_t, 3> ijk{};
    ijk[static_cast<std::size_t>(c.n)] = c.spec.index;
    for (std::int64_t ib = 0; ib < c.H; ++ib)
        for (std::int64_t ia = 0; ia < c.W; ++ia) {
            ijk[static_cast<std::size_t>(c.a)] = ia, ijk[static_cast<std::size_t>(c.b)] = ib;
            values[static_cast<std::size_t>(ia + c.W * ib)] = v.at(ijk[0], ijk[1], ijk[2]);
        }
    return values;
}

// Where the checked slice lies (volume.hpp): in millimetres, pixel (ia, ib)
// at (x0 + ia sa, y0 + ib sb), x0 and y0 the origin's components along the
// in-plane axes, and the plane's origin the 3D point of (0, 0); in pixels,
// at (ia, ib), the plane's axes scaled by the pixel sizes.
SlicePlacement placement(const Volume& v, const CheckedSlice& c, Units units, bool slice_given) {
    SlicePlacement out;
    out.physical = units == Units::physical && v.physical;
    out.units = out.physical ? "mm" : "pixels";
    out.placed = slice_given || out.physical || !(v.format == "PGM" || v.format == "PNG");
    const Vec3 &da = v.axes[static_cast<std::size_t>(c.a)], &db = v.axes[static_cast<std::size_t>(c.b)],
               &dn = v.axes[static_cast<std::size_t>(c.n)];
    const double sa = v.spacing[static_cast<std::size_t>(c.a)], sb = v.spacing[static_cast<std::size_t>(c.b)],
                 sn = v.spacing[static_cast<std::size_t>(c.n)];
    const double depth = static_cast<double>(c.spec.index) * sn;
    Vec3 base;
    for (int k = 0; k < 3; ++k) base[k] = v.origin[k] + depth * dn[k];
    if (out.physical) {
        out.geometry = {dot(v.origin, da), dot(v.origin, db), sa, sb};
        for (int k = 0; k < 3; ++k) base[k] -= out.geometry.x0 * da[k] + out.geometry.y0 * db[k];
        out.plane = {base, da, db, cross(da, db)};
        out.pixel_min = std::min(sa, sb);
    } else {
        out.plane = {base, {sa * da[0], sa * da[1], sa * da[2]}, {sb * db[0], sb * db[1], sb * db[2]}, cross(da, db)};
        out.pixel_min = 1;
    }
    return out;
}

}  // namespace

SlicePlacement place_slice(const Volume& v, const std::optional<SliceSpec>& slice, Units units) {
    return placement(v, check_slice(v, slice), units, slice.has_value());
}

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

std::string slice_file_name(const std::string& pattern, std::int64_t index) {
    auto bad = [&](const std::string& why) {
        return InputError("bad output pattern '" + pattern + "': " + why +
                          " (--slices writes one file per slice: give one %d field, e.g. out_%03d.vtu)");
    };
    std::string out;
    int fields = 0;
    for (std::size_t p = 0; p < pattern.size(); ++p) {
        if (pattern[p] != '%') {
            out += pattern[p];
            continue;
        }
        if (p + 1 < pattern.size() && pattern[p + 1] == '%') {
            out += '%', ++p;
            continue;
        }
        std::size_t q = p + 1;
        const bool zero = q < pattern.size() && pattern[q] == '0';
        if (zero) ++q;
        int width = 0;
        while (q < pattern.size() && pattern[q] >= '0' && pattern[q] <= '9' && width < 100) width = width * 10 + (pattern[q++] - '0');
        if (q >= pattern.size() || pattern[q] != 'd' || width >= 20)
            throw bad("'%' must start %d, %Nd, %0Nd (N < 20) or %%");
        if (++fields > 1) throw bad("more than one %d field");
        std::string digits = std::to_string(index);
        if (static_cast<int>(digits.size()) < width) digits.insert(0, static_cast<std::size_t>(width) - digits.size(), zero ? '0' : ' ');
        out += digits;
        p = q;
    }
    if (fields == 0) throw bad("no %d field");
    return out;
}

}  // namespace warpmesh
