// fuzz_volume_checks.hpp — what the volume-reader fuzz targets check, shared
// with tests/test_volume_io.cpp, which replays their seeds and regressions.
//
// Every input must either decode into a consistent Volume — dimensions within
// the (small) limits, one finite value per voxel, positive spacings, finite
// origin, axis-aligned orthonormal axes — or throw an InputError that names
// the input.  A decoded volume's first slice is then turned into a level set
// (threshold mode, in mm) to exercise the slicing code too.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/io/volume.hpp"
#include "warpmesh/pipeline/slices.hpp"

namespace warpmesh::fuzz {

// Small limits: no input can make a reader allocate much.
inline constexpr VolumeLimits fuzz_volume_limits{std::uint64_t{1} << 16, std::uint64_t{1} << 22};

[[noreturn]] inline void volume_violation(const std::string& what) {
    std::fprintf(stderr, "fuzz invariant violated: %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

inline void check_volume(const Volume& v) {
    std::uint64_t n = 1;
    for (const auto d : v.dims) {
        if (d < 1) volume_violation("a dimension below 1");
        n *= static_cast<std::uint64_t>(d);
        if (n > fuzz_volume_limits.max_voxels) volume_violation("more voxels than the limit");
    }
    // The samples are the 16-bit labels or the doubles, never both (volume.hpp).
    if (!v.values.empty() && !v.labels.empty()) volume_violation("samples both as labels and as doubles");
    if (v.values.size() + v.labels.size() != n) volume_violation("value count differs from the dimensions");
    for (const double x : v.values)
        if (!std::isfinite(x)) volume_violation("a non-finite value");
    for (int a = 0; a < 3; ++a) {
        if (!(v.spacing[a] > 0) || !std::isfinite(v.spacing[a])) volume_violation("a spacing not positive and finite");
        if (!std::isfinite(v.origin[a])) volume_violation("a non-finite origin");
        int ones = 0;
        for (int c = 0; c < 3; ++c) {
            const double e = v.axes[a][c];
            if (e != 0 && e != 1 && e != -1) volume_violation("an axis that is not axis-aligned");
            ones += e != 0;
        }
        if (ones != 1) volume_violation("an axis that is not a unit vector");
        for (int b = a + 1; b < 3; ++b)
            if (v.axes[a][0] * v.axes[b][0] + v.axes[a][1] * v.axes[b][1] + v.axes[a][2] * v.axes[b][2] != 0)
                volume_violation("two axes not orthogonal");
    }
    try {
        SliceOptions o;
        o.slice = SliceSpec{2, 0};
        const LoadedSlice s = load_slice(v, o);
        const Box b = s.f->bounds();
        if (!(b.xmin <= b.xmax && b.ymin <= b.ymax)) volume_violation("slice bounds inverted");
        (void)s.f->value((b.xmin + b.xmax) / 2, (b.ymin + b.ymax) / 2);
    } catch (const InputError&) {
    }
}

template <class Decode>
void check_volume_reader(std::span<const std::uint8_t> bytes, Decode&& decode) {
    Volume v;
    try {
        v = decode(bytes);
    } catch (const InputError& e) {
        if (std::string(e.what()).find("fuzz-input") == std::string::npos)
            volume_violation(std::string("an InputError does not name the input: ") + e.what());
        return;
    }
    check_volume(v);
}

inline void check_nrrd_reader(std::span<const std::uint8_t> bytes) {
    // No directory: a detached header's data file is refused, not looked up.
    check_volume_reader(bytes, [](auto b) { return decode_nrrd(b, "fuzz-input", fuzz_volume_limits, ""); });
}
inline void check_nifti_reader(std::span<const std::uint8_t> bytes) {
    check_volume_reader(bytes, [](auto b) { return decode_nifti(b, "fuzz-input", fuzz_volume_limits); });
}
inline void check_tiff_reader(std::span<const std::uint8_t> bytes) {
    check_volume_reader(bytes, [](auto b) { return decode_tiff(b, "fuzz-input", fuzz_volume_limits); });
}

}  // namespace warpmesh::fuzz
