// volume_detail.hpp — what the volume readers (nrrd.cpp, nifti.cpp,
// tiff.cpp, volume_io.cpp, image_io.cpp) share: bounded reads of regular
// files, size checks before allocating, and raw samples of the eight
// supported types to doubles.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/io/volume.hpp"

namespace warpmesh::volume_detail {

[[noreturn]] inline void fail(const std::string& format, const std::string& name, const std::string& what) {
    throw InputError(format + " '" + name + "': " + what);
}

// The bytes of the regular file `path`, at most max_bytes of them.  Refused
// (InputError "<prefix>: ...", prefix e.g. "'a.nii'" or "image 'a.pgm'"): a
// directory, and anything that is not a regular file (a device such as
// /dev/zero, a FIFO, a socket: they may never end); a file larger than
// max_bytes, with `limit` (e.g. "--max-memory 2048 MB") naming the limit.
// Never reads more than max_bytes + 1 bytes, even if the file grows.
std::vector<std::uint8_t> read_regular_file(const std::string& prefix, const std::string& path,
                                            std::uint64_t max_bytes, const std::string& limit);

// The memory limit as the command line names it, for messages: "the
// --max-memory limit of 2048 MB".
std::string memory_limit_text(std::uint64_t max_bytes);

enum class Sample { i8, u8, i16, u16, i32, u32, f32, f64 };

inline std::size_t sample_bytes(Sample t) {
    switch (t) {
        case Sample::i8: case Sample::u8: return 1;
        case Sample::i16: case Sample::u16: return 2;
        case Sample::i32: case Sample::u32: case Sample::f32: return 4;
        case Sample::f64: return 8;
    }
    return 1;
}

// The voxel count of `dims` (each >= 1), refused above the limits — voxels
// (--max-pixels), and memory (--max-memory): the `held` bytes the reader
// already holds (the file, its inflated data) plus the decoded doubles and
// the raw samples — with the products computed without overflow.
inline std::uint64_t checked_voxels(const std::string& format, const std::string& name,
                                    std::span<const std::uint64_t> dims, std::size_t raw_bytes_per_voxel,
                                    const VolumeLimits& limits, std::uint64_t held = 0) {
    std::uint64_t n = 1;
    std::string shown;
    bool over = false;
    for (const std::uint64_t d : dims) {
        shown += (shown.empty() ? "" : " x ") + std::to_string(d);
        if (d == 0) fail(format, name, "malformed header: a zero size (" + shown + ")");
        if (!over && n > limits.max_voxels / d) over = true;
        if (!over) n *= d;
    }
    if (over || n > limits.max_voxels)
        fail(format, name, "dimensions " + shown + " exceed the limit of " + std::to_string(limits.max_voxels) +
                               " voxels (--max-pixels raises it)");
    // Decoded doubles, and the raw samples beside them while decoding.
    const std::uint64_t per = raw_bytes_per_voxel + sizeof(double);
    if (held > limits.max_bytes || n > (limits.max_bytes - held) / per)
        fail(format, name, "dimensions " + shown + " need about " + std::to_string((held + n * per) >> 20) +
                               " MB to read, more than " + memory_limit_text(limits.max_bytes));
    return n;
}

// The samples of one type S (a loop per type: the type's switch, the byte
// order and the finiteness test are out of the per-voxel work where they can
// be); all_int: every value is an integer (always, for integer types).
// Sample k of type S from `raw`, its bytes reversed when `swap`.
template <class S>
S sample_at(std::span<const std::uint8_t> raw, std::size_t k, bool swap) {
    std::uint8_t v[sizeof(S)];
    std::memcpy(v, raw.data() + k * sizeof(S), sizeof(S));
    if (swap) std::reverse(v, v + sizeof(S));
    S y;
    std::memcpy(&y, v, sizeof(S));
    return y;
}

template <class S>
void decode_as(const std::string& format, const std::string& name, std::span<const std::uint8_t> raw, bool swap,
               std::vector<double>& out, bool& all_int) {
    for (std::size_t k = 0; k < out.size(); ++k) {
        const double x = static_cast<double>(sample_at<S>(raw, k, swap));
        if constexpr (std::is_floating_point_v<S>) {
            if (!std::isfinite(x)) fail(format, name, "voxel " + std::to_string(k) + " is not a finite number (NaN or infinity)");
            all_int = all_int && x == std::floor(x);
        }
        out[k] = x;
    }
}

// Integer samples of type S as 16-bit labels, in place when `raw` is out's
// own memory (a sample read before its label is written); false (out
// partly written) if a value lies outside 0..65535.
template <class S>
bool decode_labels(std::span<const std::uint8_t> raw, bool swap, std::span<std::uint16_t> out) {
    bool in_range = true;
    for (std::size_t k = 0; k < out.size(); ++k) {
        const std::int64_t x = static_cast<std::int64_t>(sample_at<S>(raw, k, swap));
        in_range &= x >= 0 && x <= 65535;
        out[k] = static_cast<std::uint16_t>(x);
    }
    return in_range;
}

inline bool is_integer_sample(Sample t) { return t != Sample::f32 && t != Sample::f64; }

// n samples of type t from `raw` (at least n * sample_bytes(t) bytes), byte
// order swapped when `swap`, into v: integers in 0..65535 as v.labels (the
// label and material modes' range, 2 bytes a voxel), anything else as
// doubles in v.values.  Sets v.integer_valued; refuses NaN and infinities.
// `raw` may be v.labels' own memory (16-bit samples inflated there):
// decoded in place.
inline void decode_samples(const std::string& format, const std::string& name, std::span<const std::uint8_t> raw, Sample t,
                           bool swap, std::size_t n, Volume& v) {
    v.integer_valued = is_integer_sample(t);
    // A value out of range after an in-place decode: the raw samples are gone, so copy them first.
    std::vector<std::uint8_t> copy;
    if (v.integer_valued) {
        const bool in_place = !v.labels.empty() && raw.data() == reinterpret_cast<const std::uint8_t*>(v.labels.data());
        if (in_place && (t == Sample::i16 || t == Sample::u16)) {
            // 16-bit samples in place: the sign bits (of shorts) tell a
            // value out of range; in the host's order they are the labels.
            std::uint16_t signs = 0;
            for (std::size_t k = 0; k < n; ++k) signs |= v.labels[k];
            if (swap) signs = static_cast<std::uint16_t>(signs << 8 | signs >> 8);
            if (t == Sample::u16 || (signs & 0x8000) == 0) {
                if (swap)
                    for (std::size_t k = 0; k < n; ++k) v.labels[k] = static_cast<std::uint16_t>(v.labels[k] << 8 | v.labels[k] >> 8);
                return;
            }
            copy.assign(raw.begin(), raw.begin() + static_cast<std::ptrdiff_t>(2 * n)), raw = copy;
        }
        v.labels.resize(n);
        bool ok = false;
        switch (t) {
            case Sample::i8: ok = decode_labels<std::int8_t>(raw, swap, v.labels); break;
            case Sample::u8: ok = decode_labels<std::uint8_t>(raw, swap, v.labels); break;
            case Sample::i16: ok = decode_labels<std::int16_t>(raw, swap, v.labels); break;
            case Sample::u16: ok = decode_labels<std::uint16_t>(raw, swap, v.labels); break;
            case Sample::i32: ok = decode_labels<std::int32_t>(raw, swap, v.labels); break;
            case Sample::u32: ok = decode_labels<std::uint32_t>(raw, swap, v.labels); break;
            default: break;
        }
        if (ok) return;
        Buffer<std::uint16_t>().swap(v.labels);
    }
    v.values.resize(n);
    bool all_int = true;
    switch (t) {
        case Sample::i8: decode_as<std::int8_t>(format, name, raw, swap, v.values, all_int); break;
        case Sample::u8: decode_as<std::uint8_t>(format, name, raw, swap, v.values, all_int); break;
        case Sample::i16: decode_as<std::int16_t>(format, name, raw, swap, v.values, all_int); break;
        case Sample::u16: decode_as<std::uint16_t>(format, name, raw, swap, v.values, all_int); break;
        case Sample::i32: decode_as<std::int32_t>(format, name, raw, swap, v.values, all_int); break;
        case Sample::u32: decode_as<std::uint32_t>(format, name, raw, swap, v.values, all_int); break;
        case Sample::f32: decode_as<float>(format, name, raw, swap, v.values, all_int); break;
        case Sample::f64: decode_as<double>(format, name, raw, swap, v.values, all_int); break;
    }
    v.integer_valued = all_int;
}

inline bool host_is_little_endian() {
    const std::uint16_t one = 1;
    std::uint8_t b;
    std::memcpy(&b, &one, 1);
    return b == 1;
}

}  // namespace warpmesh::volume_detail
