// image_io.cpp — PGM and PNG readers.
//
// Hostile input is the norm here: every size is checked before it is used,
// the pixel count is bounded before anything is allocated, and libpng errors
// come back through setjmp/longjmp in functions that hold no C++ objects, so
// no destructor is ever skipped.  Every failure is an InputError that names
// the file.
#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "volume_detail.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/io/image.hpp"

#ifdef WARPMESH_HAVE_PNG
#include <csetjmp>
#include <png.h>
#endif

namespace warpmesh {
namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what) {
    throw InputError("image '" + name + "': " + what);
}

// The limits of one decoding: pixels (--max-pixels), and memory
// (--max-memory): the file's bytes, held while decoding, plus per_pixel
// bytes a pixel (the 16-bit samples and any raw rows) within max_bytes.
struct Limits {
    std::uint64_t max_pixels, max_bytes, held;
};

void check_pixel_count(const std::string& name, std::uint64_t w, std::uint64_t h, const Limits& limits,
                       std::uint64_t per_pixel) {
    if (w == 0 || h == 0)
        fail(name, "malformed header: zero width or height (" + std::to_string(w) + " x " + std::to_string(h) + ")");
    // w, h < 2^32 each, so the product cannot overflow 64 bits.
    if (w > 0x7fffffffu || h > 0x7fffffffu || w * h > limits.max_pixels)
        fail(name, "dimensions " + std::to_string(w) + " x " + std::to_string(h) + " exceed the limit of " +
                       std::to_string(limits.max_pixels) + " pixels (--max-pixels raises it)");
    if (limits.held > limits.max_bytes || w * h > (limits.max_bytes - limits.held) / per_pixel)
        fail(name, "dimensions " + std::to_string(w) + " x " + std::to_string(h) + " need about " +
                       std::to_string((limits.held + w * h * per_pixel) >> 20) + " MB to read, more than the "
                       "--max-memory limit of " + std::to_string(limits.max_bytes >> 20) + " MB");
}

// ---------------------------------------------------------------------------
// PGM (Netpbm "portable graymap").  Header: magic, width, height, maxval as
// ASCII decimals separated by whitespace, with '#' comments running to the end
// of a line anywhere before maxval.  P5: exactly one whitespace byte after
// maxval, then width*height samples, 1 byte each if maxval < 256, else 2 bytes
// big-endian.  P2: the samples as ASCII decimals.
class PgmCursor {
public:
    PgmCursor(std::span<const std::uint8_t> b, const std::string& name) : b_(b), name_(name) {}

    static bool space(std::uint8_t c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f'; }
    static bool digit(std::uint8_t c) { return c >= '0' && c <= '9'; }

    void skip_space_and_comments() {
        while (pos_ < b_.size()) {
            if (space(b_[pos_])) {
                ++pos_;
            } else if (b_[pos_] == '#') {
                while (pos_ < b_.size() && b_[pos_] != '\n' && b_[pos_] != '\r') ++pos_;
            } else {
                break;
            }
        }
    }

    // A decimal after optional whitespace/comments.  `what` names it in
    // errors; values above `limit` are refused without overflowing.
    std::uint64_t number(const char* what, std::uint64_t limit, bool in_header) {
        skip_space_and_comments();
        if (pos_ >= b_.size())
            fail(name_, in_header ? std::string("malformed header: file ends before the ") + what
                                  : std::string("truncated data: file ends before ") + what);
        if (!digit(b_[pos_]))
            fail(name_, std::string(in_header ? "malformed header" : "malformed pixel data") + ": expected " + what +
                            ", found byte 0x" + hex(b_[pos_]) + " at offset " + std::to_string(pos_));
        std::uint64_t v = 0;
        while (pos_ < b_.size() && digit(b_[pos_])) {
            v = v * 10 + (b_[pos_] - '0');
            if (v > limit)
                fail(name_, std::string(in_header ? "malformed header: " : "malformed pixel data: ") + what +
                                " exceeds " + std::to_string(limit));
            ++pos_;
        }
        if (pos_ < b_.size() && !space(b_[pos_]) && !(in_header && b_[pos_] == '#'))
            fail(name_, std::string(in_header ? "malformed header" : "malformed pixel data") + ": junk after " +
                            what + " at offset " + std::to_string(pos_));
        return v;
    }

    std::size_t pos() const { return pos_; }
    void advance(std::size_t n) { pos_ += n; }

    static std::string hex(std::uint8_t c) {
        const char* d = "0123456789abcdef";
        return {d[c >> 4], d[c & 15]};
    }

private:
    std::span<const std::uint8_t> b_;
    const std::string& name_;
    std::size_t pos_ = 2;  // after the magic
};

Image read_pgm(std::span<const std::uint8_t> bytes, const std::string& name, const Limits& limits) {
    const bool ascii = bytes[1] == '2';
    PgmCursor cur(bytes, name);
    const std::uint64_t w = cur.number("width", 0xffffffffu, true);
    const std::uint64_t h = cur.number("height", 0xffffffffu, true);
    const std::uint64_t maxval = cur.number("maxval", 0xffffffffu, true);
    if (maxval == 0 || maxval > 65535)
        fail(name, "malformed header: maxval " + std::to_string(maxval) + " is not in 1..65535");
    check_pixel_count(name, w, h, limits, sizeof(std::uint16_t));

    Image img;
    img.width = static_cast<int>(w);
    img.height = static_cast<int>(h);
    img.maxval = static_cast<int>(maxval);
    img.source = name;
    const std::size_t n = static_cast<std::size_t>(w * h);
    // Sample k (row-major, top row first) of either encoding.
    const auto store = [&](std::size_t k, std::uint64_t v) {
        if (v > maxval)
            fail(name, "sample " + std::to_string(k) + " (row " + std::to_string(k / w) + ", column " +
                           std::to_string(k % w) + ") is " + std::to_string(v) + ", above maxval " +
                           std::to_string(maxval));
        img.pixels[k] = static_cast<std::uint16_t>(v);
    };

    if (ascii) {
        img.pixels.resize(n);
        for (std::size_t k = 0; k < n; ++k) {
            cur.skip_space_and_comments();
            if (cur.pos() >= bytes.size())
                fail(name, "truncated data: expected " + std::to_string(n) + " samples, found " + std::to_string(k));
            store(k, cur.number("a sample", 0xffffffffu, false));
        }
        return img;
    }

    // P5: a single whitespace byte separates maxval from the raster.
    if (cur.pos() >= bytes.size()) fail(name, "truncated data: no pixel data after the header");
    cur.advance(1);
    const std::size_t bpp = maxval < 256 ? 1 : 2;
    const std::size_t have = bytes.size() - cur.pos();
    if (have / bpp < n)
        fail(name, "truncated data: expected " + std::to_string(n * bpp) + " bytes of pixel data, found " +
                       std::to_string(have));
    img.pixels.resize(n);
    const std::uint8_t* p = bytes.data() + cur.pos();
    for (std::size_t k = 0; k < n; ++k) {
        store(k, bpp == 1 ? p[k] : (unsigned{p[2 * k]} << 8 | p[2 * k + 1]));
    }
    // Trailing bytes are allowed: a PGM file may hold several images; we take the first.
    return img;
}

// ---------------------------------------------------------------------------
// Conversions to one channel (documented in image.hpp).

// BT.601 luma with integer rounding: the weights sum to 1000, so the result
// never exceeds the inputs' maximum.
constexpr unsigned luma(unsigned r, unsigned g, unsigned b) { return (299 * r + 587 * g + 114 * b + 500) / 1000; }

// v composited with opacity a (0 = transparent) over white, all in 0..m.
// Transparent regions read as background: scanned or drawn figures sit on
// white paper, and the shared test images were prepared the same way.
constexpr unsigned over_white(unsigned v, unsigned a, unsigned m) {
    return static_cast<unsigned>((std::uint64_t{a} * v + std::uint64_t{m - a} * m + m / 2) / m);
}

#ifdef WARPMESH_HAVE_PNG
// ---------------------------------------------------------------------------
// PNG through libpng's classic API.  The simplified png_image API would
// convert 16-bit gray to linear light and RGB with sRGB-aware weights; we
// want the stored samples, so the conversions are done here.

struct PngSource {
    const std::uint8_t* data;
    std::size_t size;
    std::size_t pos;
    char error[256];    // libpng's message, when it gave up
    char warning[160];  // libpng's first warning: often the detail behind a
                        // generic error ("Invalid bit depth in IHDR")
};

extern "C" void png_read_from_memory(png_structp png, png_bytep out, png_size_t n) {
    auto* src = static_cast<PngSource*>(png_get_io_ptr(png));
    if (n > src->size - src->pos) png_error(png, "truncated file (unexpected end of data)");
    std::memcpy(out, src->data + src->pos, n);
    src->pos += n;
}

extern "C" void png_error_to_jmp(png_structp png, png_const_charp msg) {
    auto* src = static_cast<PngSource*>(png_get_error_ptr(png));
    std::snprintf(src->error, sizeof src->error, src->warning[0] ? "%s (libpng warned: %s)" : "%s",
                  msg ? msg : "libpng error", src->warning);
    png_longjmp(png, 1);
}

// Warnings do not stop reading; the first is kept for the error message.
extern "C" void png_ignore_warning(png_structp png, png_const_charp msg) {
    auto* src = static_cast<PngSource*>(png_get_error_ptr(png));
    if (src && !src->warning[0] && msg) std::snprintf(src->warning, sizeof src->warning, "%s", msg);
}

struct PngHeader {
    png_uint_32 width, height;
    int depth, color_type, interlace;
    png_size_t rowbytes;
    int passes;
    png_colorp palette;
    int palette_size;
    png_bytep trans_alpha;
    int trans_count;
    png_color_16p trans_color;
};

// Stage 1: signature, IHDR and the chunks before IDAT.  Only C objects live
// in this frame, so longjmp'ing back into it is well defined.
bool png_read_header(png_structp png, png_infop info, PngHeader* h) {
    if (setjmp(png_jmpbuf(png))) return false;
    png_read_info(png, info);
    int compression = 0, filter = 0;
    png_get_IHDR(png, info, &h->width, &h->height, &h->depth, &h->color_type, &h->interlace, &compression, &filter);
    return true;
}

// Stage 2: set the transforms.  None changes the sample values: sub-byte
// samples are unpacked (not scaled) to one byte each, 16-bit samples stay
// big-endian.
bool png_prepare(png_structp png, png_infop info, PngHeader* h) {
    if (setjmp(png_jmpbuf(png))) return false;
    if (h->depth < 8) png_set_packing(png);
    h->passes = png_set_interlace_handling(png);
    png_read_update_info(png, info);
    h->rowbytes = png_get_rowbytes(png, info);
    return true;
}

// Stage 3: the rows (all passes, for interlaced images) and the end chunks.
bool png_read_rows(png_structp png, const PngHeader* h, png_bytepp rows) {
    if (setjmp(png_jmpbuf(png))) return false;
    for (int pass = 0; pass < h->passes; ++pass)
        for (png_uint_32 y = 0; y < h->height; ++y) png_read_row(png, rows[y], nullptr);
    png_read_end(png, nullptr);
    return true;
}

bool png_read_extras(png_structp png, png_infop info, PngHeader* h) {
    if (setjmp(png_jmpbuf(png))) return false;
    h->palette = nullptr, h->palette_size = 0, h->trans_alpha = nullptr, h->trans_count = 0, h->trans_color = nullptr;
    if (png_get_valid(png, info, PNG_INFO_PLTE)) png_get_PLTE(png, info, &h->palette, &h->palette_size);
    if (png_get_valid(png, info, PNG_INFO_tRNS)) png_get_tRNS(png, info, &h->trans_alpha, &h->trans_count, &h->trans_color);
    return true;
}

struct PngHandles {
    png_structp png = nullptr;
    png_infop info = nullptr;
    ~PngHandles() {
        if (png) png_destroy_read_struct(&png, info ? &info : nullptr, nullptr);
    }
};

Image read_png(std::span<const std::uint8_t> bytes, const std::string& name, const Limits& limits) {
    PngSource src{bytes.data(), bytes.size(), 0, {}, {}};
    PngHandles hd;
    hd.png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &src, png_error_to_jmp, png_ignore_warning);
    if (!hd.png) fail(name, "cannot initialise libpng");
    hd.info = png_create_info_struct(hd.png);
    if (!hd.info) fail(name, "cannot initialise libpng");
    png_set_read_fn(hd.png, &src, png_read_from_memory);
    // Our own pixel limit applies (below, before allocating); lift libpng's
    // 1,000,000-per-side default so that the message is ours.
    png_set_user_limits(hd.png, 0x7fffffff, 0x7fffffff);

    PngHeader h{};
    if (!png_read_header(hd.png, hd.info, &h)) fail(name, std::string("corrupt PNG: ") + src.error);
    // The 16-bit samples and the raw rows (up to 8 bytes a pixel: RGBA, 16-bit).
    check_pixel_count(name, h.width, h.height, limits, sizeof(std::uint16_t) + 8);
    if (!png_read_extras(hd.png, hd.info, &h)) fail(name, std::string("corrupt PNG: ") + src.error);
    if (!png_prepare(hd.png, hd.info, &h)) fail(name, std::string("corrupt PNG: ") + src.error);

    const std::size_t w = h.width, hh = h.height;
    const int ct = h.color_type;
    const int channels = ct == PNG_COLOR_TYPE_GRAY || ct == PNG_COLOR_TYPE_PALETTE ? 1
                         : ct == PNG_COLOR_TYPE_GRAY_ALPHA                      ? 2
                         : ct == PNG_COLOR_TYPE_RGB                             ? 3
                                                                                : 4;
    const std::size_t bytes_per_sample = h.depth == 16 ? 2 : 1;
    if (h.rowbytes != w * channels * bytes_per_sample) fail(name, "unexpected PNG row layout");
    std::vector<png_byte> raw(h.rowbytes * hh);
    std::vector<png_bytep> rows(hh);
    for (std::size_t y = 0; y < hh; ++y) rows[y] = raw.data() + y * h.rowbytes;
    if (!png_read_rows(hd.png, &h, rows.data())) fail(name, std::string("corrupt PNG: ") + src.error);

    Image img;
    img.width = static_cast<int>(w);
    img.height = static_cast<int>(hh);
    img.source = name;
    img.pixels.resize(w * hh);
    const unsigned m = (1u << h.depth) - 1;  // the largest sample value
    auto sample = [&](std::size_t k, int ch) -> unsigned {
        const std::size_t i = k * channels + ch;
        return bytes_per_sample == 1 ? raw[i] : (unsigned{raw[2 * i]} << 8 | raw[2 * i + 1]);
    };

    if (ct == PNG_COLOR_TYPE_PALETTE) {
        bool gray_palette = h.palette_size > 0;
        for (int i = 0; i < h.palette_size; ++i)
            gray_palette = gray_palette && h.palette[i].red == h.palette[i].green && h.palette[i].green == h.palette[i].blue;
        img.maxval = gray_palette ? 255 : static_cast<int>(m);
        for (std::size_t k = 0; k < w * hh; ++k) {
            const unsigned idx = raw[k];
            if (!gray_palette) {
                img.pixels[k] = static_cast<std::uint16_t>(idx);
                continue;
            }
            if (idx >= static_cast<unsigned>(h.palette_size))
                fail(name, "corrupt PNG: palette index " + std::to_string(idx) + " out of range (palette has " +
                               std::to_string(h.palette_size) + " entries)");
            const unsigned a = static_cast<int>(idx) < h.trans_count && h.trans_alpha ? h.trans_alpha[idx] : 255u;
            img.pixels[k] = static_cast<std::uint16_t>(over_white(h.palette[idx].red, a, 255));
        }
        return img;
    }

    img.maxval = static_cast<int>(m);
    // A tRNS chunk in a gray or RGB image names one fully transparent colour.
    const bool has_key = h.trans_color != nullptr && (ct == PNG_COLOR_TYPE_GRAY || ct == PNG_COLOR_TYPE_RGB);
    for (std::size_t k = 0; k < w * hh; ++k) {
        unsigned v = 0, a = m;
        switch (ct) {
            case PNG_COLOR_TYPE_GRAY:
                v = sample(k, 0);
                if (has_key && v == h.trans_color->gray) a = 0;
                break;
            case PNG_COLOR_TYPE_GRAY_ALPHA:
                v = sample(k, 0), a = sample(k, 1);
                break;
            case PNG_COLOR_TYPE_RGB: {
                const unsigned r = sample(k, 0), g = sample(k, 1), b = sample(k, 2);
                v = luma(r, g, b);
                if (has_key && r == h.trans_color->red && g == h.trans_color->green && b == h.trans_color->blue) a = 0;
                break;
            }
            default:  // RGBA
                v = luma(sample(k, 0), sample(k, 1), sample(k, 2)), a = sample(k, 3);
                break;
        }
        img.pixels[k] = static_cast<std::uint16_t>(a == m ? v : over_white(v, a, m));
    }
    return img;
}
#endif  // WARPMESH_HAVE_PNG

bool starts_with(std::span<const std::uint8_t> b, std::string_view magic) {
    return b.size() >= magic.size() && std::equal(magic.begin(), magic.end(), b.begin(),
                                                  [](char c, std::uint8_t u) { return static_cast<std::uint8_t>(c) == u; });
}

}  // namespace

bool png_supported() {
#ifdef WARPMESH_HAVE_PNG
    return true;
#else
    return false;
#endif
}

Image decode_image(std::span<const std::uint8_t> bytes, const std::string& name, std::uint64_t max_pixels,
                   std::uint64_t max_bytes) {
    if (bytes.empty()) fail(name, "empty file");
    const Limits limits{max_pixels, max_bytes, bytes.size()};
    if (starts_with(bytes, "P2") || starts_with(bytes, "P5")) {
        if (bytes.size() < 3 || (!PgmCursor::space(bytes[2]) && bytes[2] != '#'))
            fail(name, "malformed header: no whitespace after the magic number");
        return read_pgm(bytes, name, limits);
    }
    if (starts_with(bytes, "\x89PNG\r\n\x1a\n")) {
#ifdef WARPMESH_HAVE_PNG
        return read_png(bytes, name, limits);
#else
        fail(name, "PNG support was not compiled in (libpng was not found at build time); convert to PGM");
#endif
    }
    if (bytes.size() >= 2 && bytes[0] == 'P' && bytes[1] >= '1' && bytes[1] <= '7')
        fail(name, std::string("unsupported format: Netpbm P") + static_cast<char>(bytes[1]) +
                       " (only grayscale PGM, P2 or P5, is read; convert to PGM)");
    const char* kind = starts_with(bytes, "\xff\xd8\xff")                                ? "JPEG"
                       : starts_with(bytes, "GIF8")                                      ? "GIF"
                       : starts_with(bytes, "BM")                                        ? "BMP"
                       : starts_with(bytes, "II*") || starts_with(bytes, std::string_view("MM\0*", 4)) ? "TIFF"
                                                                                         : nullptr;
    fail(name, std::string("unsupported format") + (kind ? std::string(" (looks like ") + kind + ")" : "") +
                   "; expected PGM (P2/P5) or PNG");
}

Image read_image(const std::string& path, std::uint64_t max_pixels, std::uint64_t max_bytes) {
    const std::vector<std::uint8_t> bytes = volume_detail::read_regular_file(
        "image '" + path + "'", path, max_bytes, volume_detail::memory_limit_text(max_bytes));
    return decode_image(bytes, path, max_pixels, max_bytes);
}

}  // namespace warpmesh
