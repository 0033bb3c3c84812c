// volume.hpp — 3D scalar volumes (NRRD, NIfTI-1/2, TIFF; PGM/PNG as one
// slice) and where their 2D slices lie (the slices' level sets and material
// fields, load_slice: pipeline/slices.hpp).
//
// Geometry.  Voxel (i, j, k) sits at the physical point
//
//     P(i, j, k) = origin + i spacing[0] axes[0] + j spacing[1] axes[1] + k spacing[2] axes[2],
//
// axes[a] the unit direction of index axis a.  Only axis-aligned
// orientations are accepted: each axes[a] is +-e_x, +-e_y or +-e_z, the three
// a permutation (so permuted and flipped orientations are fine, oblique and
// sheared ones are refused by the readers).  Images (PGM, PNG, TIFF) have
// i = column, j = H - 1 - row (j points up, as in image_levelset.hpp),
// k = page, origin 0, axes the identity, spacing 1 and `physical` false
// (their unit is the pixel).
//
// Slices.  A slice fixes one index axis n at index m; its in-plane axes are
// a < b of the other two (slice k: (i, j); slice j: (i, k); slice i: (j, k)).
// In physical units its 2D point (x, y) is
//
//     x = origin . axes[a] + ia spacing[a],   y = origin . axes[b] + ib spacing[b]
//
// (physical distances along the two index axes, origin included) and lies at
// the 3D point plane.origin + x plane.x_axis + y plane.y_axis.  In pixel
// units x = ia, y = ib.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "warpmesh/core/buffer.hpp"
#include "warpmesh/core/memory.hpp"
#include "warpmesh/core/mesh.hpp"
#include "warpmesh/io/image.hpp"

namespace warpmesh {

using Vec3 = std::array<double, 3>;

struct Volume {
    std::array<std::int64_t, 3> dims{1, 1, 1};  // voxels along i, j, k (each >= 1)
    // The samples, index i + dims[0] (j + dims[1] k): as 16-bit labels when
    // every one is an integer in 0..65535 (the label and material modes'
    // range; the readers keep integer files so, 2 bytes a voxel, and `values`
    // is then empty), else as doubles in `values`.  Read them with value()
    // and at(), which see either.
    std::vector<double> values;
    Buffer<std::uint16_t> labels;  // (buffer.hpp: written whole by the reader, not zero-filled first)
    Vec3 spacing{1, 1, 1};                      // > 0: mm for physical volumes, else pixels
    Vec3 origin{0, 0, 0};                       // physical position of voxel (0, 0, 0)
    std::array<Vec3, 3> axes{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}};
    bool physical = false;                      // spacing and origin are in mm
    bool integer_valued = true;                 // every value is an integer
    int maxval = -1;                            // PGM/PNG: the image's maxval (else -1)
    std::string format;                         // "NRRD", "NIfTI-1", "NIfTI-2", "TIFF", "PGM", "PNG"
    std::string space;                          // the file's space or coordinate code, if any
    std::string source;                         // file name, for messages
    // What the reader accepted but a user should hear about (e.g. a NIfTI
    // scl_slope that is NaN, read as no scaling), one line each.
    std::vector<std::string> warnings;
    // A part of a larger volume (a block's region, pipeline/mesh3d.hpp): its
    // voxel (i, j, k) is the whole volume's (i, j, k) + part_offset, the
    // whole has whole_dims voxels, and origin is the whole's voxel (0, 0, 0).
    // whole_dims all 0: the volume is whole.
    std::array<std::int64_t, 3> part_offset{0, 0, 0}, whole_dims{0, 0, 0};
    bool is_part() const { return whole_dims[0] > 0; }

    std::int64_t voxel_count() const { return dims[0] * dims[1] * dims[2]; }
    double value(std::size_t q) const { return labels.empty() ? values[q] : labels[q]; }
    double at(std::int64_t i, std::int64_t j, std::int64_t k) const {
        return value(static_cast<std::size_t>(i + dims[0] * (j + dims[1] * k)));
    }
};

// Volumes with more voxels than max_voxels (the command line's
// --max-pixels) are refused before anything is allocated, and so are those
// whose reading would hold more than max_bytes (--max-memory): the file's
// bytes, its inflated data (gzip) and the decoded doubles (8 bytes a voxel)
// together.  Only regular files are read, and none larger than max_bytes.
struct VolumeLimits {
    std::uint64_t max_voxels = std::uint64_t{1} << 28;
    std::uint64_t max_bytes = default_max_memory;
};

// Read a volume or image, recognised by its content (NRRD magic, NIfTI
// sizeof_hdr, gzip, TIFF, PGM, PNG), not its name; a .nhdr's detached data
// file is read relative to the header's directory.  Throws InputError naming
// the file and the problem (malformed or truncated header or data, an
// unsupported type, encoding or dimension, an oblique orientation, too many
// voxels).
Volume read_volume(const std::string& path, const VolumeLimits& limits = {});
// The same from bytes in memory (a detached NRRD header's data file is then
// looked up relative to `dir`, or refused when `dir` is empty).
Volume decode_volume(std::span<const std::uint8_t> bytes, const std::string& name, const VolumeLimits& limits = {},
                     const std::string& dir = {});

// The format readers (one file each in src/io/), used by decode_volume.
Volume decode_nrrd(std::span<const std::uint8_t> bytes, const std::string& name, const VolumeLimits& limits,
                   const std::string& dir);
Volume decode_nifti(std::span<const std::uint8_t> bytes, const std::string& name, const VolumeLimits& limits);
Volume decode_tiff(std::span<const std::uint8_t> bytes, const std::string& name, const VolumeLimits& limits);
bool tiff_supported();

// The samples as doubles in `values` (labels moved there, and freed).
void samples_to_values(Volume& volume);

// gzip/zlib data, inflated to at most max_out bytes (stops there: callers ask
// for what they need).  Throws InputError naming `name` on corrupt data.
std::vector<std::uint8_t> gunzip(std::span<const std::uint8_t> in, std::size_t max_out, const std::string& name);
// The same, for data whose size a header gives: inflates at most `expected`
// bytes (fewer: the caller reports the truncation) and throws InputError if
// the stream holds more.
std::vector<std::uint8_t> gunzip_exact(std::span<const std::uint8_t> in, std::size_t expected, const std::string& name);
// The same into the caller's buffer: inflates at most out.size() bytes and
// returns how many (fewer: truncated); throws InputError if the stream holds more.
std::size_t gunzip_exact_into(std::span<const std::uint8_t> in, std::span<std::uint8_t> out, const std::string& name);

// Axis-aligned directions: the unit vector +-e_p nearest to d, if d is
// within 1e-6 (relative) of it; else nullopt (oblique).
std::optional<Vec3> axis_aligned(const Vec3& d);

// ---------------------------------------------------------------------------
// Slices.

struct SliceSpec {
    int axis = 2;            // 0 = i, 1 = j, 2 = k
    std::int64_t index = 0;  // 0 <= index < dims[axis]
};

// "k=60" → {2, 60}.  Throws InputError on anything else.
SliceSpec parse_slice(const std::string& text);
// "k=0:113" → axis 2, indices [0, 113) (first:end, end exclusive; "k=5" is
// the one slice 5).  Throws InputError on anything else.
struct SliceRange {
    int axis = 2;
    std::int64_t first = 0, end = 1;
};
SliceRange parse_slice_range(const std::string& text);

// Where a slice's 2D coordinates lie in 3D: P(x, y) = origin + x x_axis + y y_axis.
struct SlicePlane {
    Vec3 origin{0, 0, 0}, x_axis{1, 0, 0}, y_axis{0, 1, 0}, normal{0, 0, 1};
    Vec3 point(double x, double y) const {
        return {origin[0] + x * x_axis[0] + y * y_axis[0], origin[1] + x * x_axis[1] + y * y_axis[1],
                origin[2] + x * x_axis[2] + y * y_axis[2]};
    }
};

enum class Units { physical, pixels };

// Where a slice lies in the chosen units.
struct SlicePlacement {
    // Pixel (ia, ib) of the slice at (x0 + ia sx, y0 + ib sy): the physical
    // pixel sizes and the origin's in-plane components in millimetres, the
    // identity (pixel units) otherwise.
    PixelGeometry geometry;
    SlicePlane plane;           // the 2D point (x, y) at plane.point(x, y) in 3D
    bool physical = false;      // coordinates in mm (else pixels)
    double pixel_min = 1;       // the smaller in-plane pixel size, in the slice's units
    std::string units;          // "mm" or "pixels"
    // Whether a report should say where the slice is: false for a plain
    // image in pixel units (its report stays what it always was).
    bool placed = false;
};

// The placement of a slice as load_slice (pipeline/slices.hpp) places it (no
// values are read).
// Throws InputError as load_slice for the slice.
SlicePlacement place_slice(const Volume& volume, const std::optional<SliceSpec>& slice, Units units);

// The output name of slice `index` from a pattern with exactly one printf
// integer field, %d, %Nd or %0Nd (N < 20), and any number of %% (a '%').
// Throws InputError for a pattern without such a field, with several, or
// with any other '%'.
std::string slice_file_name(const std::string& pattern, std::int64_t index);

// A slice mesh's vertices at their 3D positions, plane.point(x, y): a CSV
// file "x,y,z" with one line per vertex, in the mesh's vertex order (the
// order of every mesh file written).  Written atomically; throws OutputError.
void write_points_3d(const Mesh& mesh, const SlicePlane& plane, const std::string& path);

// Replace a volume's spacing by a user-given pixel size (--pixel-size
// SX[,SY[,SZ]]; missing entries repeat the last), making it physical (mm).
// Throws InputError for a size that is not positive and finite.
void set_pixel_size(Volume& volume, std::span<const double> size);

}  // namespace warpmesh
