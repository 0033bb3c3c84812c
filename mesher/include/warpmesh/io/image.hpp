// image.hpp — grayscale images as the mesher reads them (PGM, PNG).
//
// Every image is reduced to one channel of unsigned integer samples 0..maxval
// (maxval <= 65535), row-major with row 0 at the top, exactly as stored: no
// gamma correction, no rescaling of 16-bit data.  The conversions applied to
// PNG colour types are (see image_io.cpp for the reasons):
//
//   * gray, 1/2/4/8/16-bit   → the sample itself, maxval = 2^depth - 1;
//   * RGB(A), 8/16-bit       → ITU-R BT.601 luma of the stored values,
//                              Y = round(0.299 R + 0.587 G + 0.114 B)
//                              (integer arithmetic, halves rounded up);
//   * any alpha channel      → composited over white:
//                              v' = round((a v + (M - a) M) / M), M = maxval;
//                              the same for a tRNS transparent colour (a = 0);
//   * palette, all entries gray (R = G = B) → that gray level (then alpha, as
//                              above, from tRNS), maxval = 255;
//   * palette with colours   → the palette *index*, maxval = 2^depth - 1: a
//                              colour palette image is almost always a label
//                              map, and luma could merge distinct colours.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace warpmesh {

struct Image {
    int width = 0, height = 0;
    int maxval = 0;                      // 1..65535; every pixel is <= maxval
    std::vector<std::uint16_t> pixels;   // row-major, row 0 = top, width * height samples
    std::string source;                  // where it was read from (for messages)

    std::uint16_t at(int column, int row) const {
        return pixels[static_cast<std::size_t>(row) * static_cast<std::size_t>(width) +
                      static_cast<std::size_t>(column)];
    }
};

// Where the pixel centres lie: pixel (c, y), y = H - 1 - row, at
// (x0 + c sx, y0 + y sy); sx, sy > 0.  The default is pixel units.
struct PixelGeometry {
    double x0 = 0, y0 = 0, sx = 1, sy = 1;
    bool is_pixels() const { return x0 == 0 && y0 == 0 && sx == 1 && sy == 1; }
};

// Images with more pixels than this are refused before any pixel memory is
// allocated (2^28 pixels: 512 MiB of 16-bit samples).
inline constexpr std::uint64_t default_max_pixels = std::uint64_t{1} << 28;

// The memory the readers and the pipeline may use by default (the command
// line's --max-memory): 2 GiB.  Readers refuse a file larger than this, and
// a volume whose decoding would hold more (volume.hpp: VolumeLimits); mesh()
// refuses a lattice whose estimated peak is above it (pipeline.hpp:
// MeshOptions::max_memory).
inline constexpr std::uint64_t default_max_memory = std::uint64_t{1} << 31;

// Read a PGM (P2 ASCII or P5 binary, 8- or 16-bit) or — when built with
// libpng (WARPMESH_HAVE_PNG) — a PNG, recognised by its magic bytes, not its
// name.  Throws InputError naming the file and the problem: unreadable, not a
// regular file (a device, a FIFO), larger than max_bytes, unsupported
// format, malformed header, maxval 0 or > 65535, a sample above maxval, too
// many pixels, truncated data, corrupt PNG.
Image read_image(const std::string& path, std::uint64_t max_pixels = default_max_pixels,
                 std::uint64_t max_bytes = default_max_memory);

// The same from bytes in memory; `name` is used in messages and as `source`.
// max_bytes bounds the bytes held while decoding: `bytes` and the decoded
// samples (and PNG's raw rows).
Image decode_image(std::span<const std::uint8_t> bytes, const std::string& name,
                   std::uint64_t max_pixels = default_max_pixels, std::uint64_t max_bytes = default_max_memory);

// True when this build can read PNG files.
bool png_supported();

}  // namespace warpmesh
