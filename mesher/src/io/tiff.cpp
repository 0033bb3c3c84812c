// tiff.cpp — grayscale TIFF through libtiff (Debian's libtiff-dev), every
// page (directory) a slice: i = column, j = H - 1 - row, k = page.
//
// Read: 8- and 16-bit samples, unsigned or signed, one sample per pixel,
// min-is-black or min-is-white (inverted, so that bright stays high),
// stripped or tiled, any compression libtiff decodes; all pages of one size.
// Refused with a message: colour, palette (with or without its colour map),
// several samples per pixel, other bit depths and float samples, pages of
// different sizes, strips or tiles beyond the end of the file, and whatever
// libtiff refuses (its message is passed on).  The unit is the pixel
// (--pixel-size gives physical sizes): TIFF resolution tags are too often
// absent or meaningless to mesh in their units.
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <functional>

#include "volume_detail.hpp"

#ifdef WARPMESH_HAVE_TIFF
#include <tiffio.h>
#endif

namespace warpmesh {

bool tiff_supported() {
#ifdef WARPMESH_HAVE_TIFF
    return true;
#else
    return false;
#endif
}

#ifndef WARPMESH_HAVE_TIFF
Volume decode_tiff(std::span<const std::uint8_t>, const std::string& name, const VolumeLimits&) {
    volume_detail::fail("TIFF", name, "TIFF support was not compiled in (libtiff was not found at build time)");
}
#else
namespace {

using namespace volume_detail;

struct MemoryFile {
    std::span<const std::uint8_t> bytes;
    toff_t pos = 0;
    std::string error;    // libtiff's first error message
    std::string warning;  // and its first warning (it repairs some tags it finds wrong, and says so)
};

extern "C" tsize_t mem_read(thandle_t h, tdata_t buf, tsize_t n) {
    auto* f = static_cast<MemoryFile*>(h);
    if (n <= 0 || f->pos >= f->bytes.size()) return 0;
    const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(n), f->bytes.size() - f->pos);
    std::memcpy(buf, f->bytes.data() + f->pos, k);
    f->pos += k;
    return static_cast<tsize_t>(k);
}
extern "C" tsize_t mem_write(thandle_t, tdata_t, tsize_t) { return 0; }
extern "C" toff_t mem_seek(thandle_t h, toff_t off, int whence) {
    auto* f = static_cast<MemoryFile*>(h);
    const toff_t base = whence == SEEK_SET ? 0 : whence == SEEK_CUR ? f->pos : f->bytes.size();
    if (off > static_cast<toff_t>(1) << 62 || base + off > static_cast<toff_t>(1) << 62) return static_cast<toff_t>(-1);
    f->pos = base + off;
    return f->pos;
}
extern "C" int mem_close(thandle_t) { return 0; }
extern "C" toff_t mem_size(thandle_t h) { return static_cast<MemoryFile*>(h)->bytes.size(); }
extern "C" int mem_map(thandle_t, tdata_t*, toff_t*) { return 0; }
extern "C" void mem_unmap(thandle_t, tdata_t, toff_t) {}

// libtiff's first message of a kind, kept for ours.
void keep_first(std::string& into, const char* module, const char* fmt, va_list ap) {
    if (!into.empty()) return;
    char buf[512];
    std::vsnprintf(buf, sizeof buf, fmt, ap);
    into = std::string(module ? module : "libtiff") + ": " + buf;
}
extern "C" int on_error(TIFF*, void* user, const char* module, const char* fmt, va_list ap) {
    keep_first(static_cast<MemoryFile*>(user)->error, module, fmt, ap);
    return 1;
}
extern "C" int on_warning(TIFF*, void* user, const char* module, const char* fmt, va_list ap) {
    keep_first(static_cast<MemoryFile*>(user)->warning, module, fmt, ap);
    return 1;
}

struct Handles {
    TIFFOpenOptions* opts = nullptr;
    TIFF* tif = nullptr;
    ~Handles() {
        if (tif) TIFFClose(tif);
        if (opts) TIFFOpenOptionsFree(opts);
    }
};

// The PhotometricInterpretation stored in the current directory, read from
// the file itself: libtiff replaces a palette without its colour map by
// min-is-black, silently.  Classic TIFF: 12-byte entries after a 2-byte
// count; BigTIFF: 20-byte entries after an 8-byte count.  -1 if absent.
int stored_photometric(TIFF* tif, std::span<const std::uint8_t> b) {
    const bool big = TIFFIsBigTIFF(tif), little = b.size() > 1 && b[0] == 'I';
    auto get = [&](std::uint64_t at, int n) -> std::uint64_t {
        std::uint64_t v = 0;
        if (at > b.size() || static_cast<std::uint64_t>(n) > b.size() - at) return UINT64_MAX;
        for (int q = 0; q < n; ++q) v |= std::uint64_t{b[at + static_cast<std::uint64_t>(little ? q : n - 1 - q)]} << (8 * q);
        return v;
    };
    const std::uint64_t dir = TIFFCurrentDirOffset(tif), entries = get(dir, big ? 8 : 2);
    const std::uint64_t first = dir + (big ? 8 : 2), size = big ? 20 : 12;
    for (std::uint64_t e = 0; e < entries && e < 4096; ++e) {
        const std::uint64_t at = first + e * size;
        const std::uint64_t tag = get(at, 2);
        if (tag == UINT64_MAX) return -1;
        if (tag == TIFFTAG_PHOTOMETRIC) {
            const std::uint64_t v = get(at + (big ? 12 : 8), 2);
            return v == UINT64_MAX ? -1 : static_cast<int>(v);
        }
    }
    return -1;
}

// The current page's strips (or tiles) must lie within the file: libtiff
// would otherwise read a strip byte count past the end as a short strip, or
// replace it by an estimate.  A palette image without its colour map, which
// libtiff reads as gray, is refused like any palette image.
void check_page_data(TIFF* tif, const MemoryFile& mf, const std::string& page,
                     const std::function<void(const std::string&)>& bad) {
    std::uint16_t *red = nullptr, *green = nullptr, *blue = nullptr;
    if (stored_photometric(tif, mf.bytes) == PHOTOMETRIC_PALETTE && !TIFFGetField(tif, TIFFTAG_COLORMAP, &red, &green, &blue))
        bad(page + "a palette image without a colour map (its pixels are indices into a missing palette); only 8- "
                   "and 16-bit grayscale TIFF is read");
    if (mf.warning.find("StripByteCounts") != std::string::npos || mf.warning.find("TileByteCounts") != std::string::npos)
        bad(page + "its strip byte counts do not fit the file (" + mf.warning + ")");
    const std::uint32_t strips = TIFFNumberOfStrips(tif);
    for (std::uint32_t k = 0; k < strips; ++k) {
        int err = 0;
        const std::uint64_t off = TIFFGetStrileOffsetWithErr(tif, k, &err);
        const std::uint64_t count = TIFFGetStrileByteCountWithErr(tif, k, &err);
        if (err || off > mf.bytes.size() || count > mf.bytes.size() - off)
            bad(page + (TIFFIsTiled(tif) ? "tile " : "strip ") + std::to_string(k) + " at byte " + std::to_string(off) +
                " has a byte count of " + std::to_string(count) + ", beyond the end of the file (" +
                std::to_string(mf.bytes.size()) + " bytes): truncated or corrupt");
    }
}

}  // namespace

Volume decode_tiff(std::span<const std::uint8_t> bytes, const std::string& name, const VolumeLimits& limits) {
    MemoryFile mf{bytes, 0, {}, {}};
    auto bad = [&](const std::string& what) {
        fail("TIFF", name, what + (mf.error.empty() ? std::string() : " (" + mf.error + ")"));
    };
    Handles h;
    h.opts = TIFFOpenOptionsAlloc();
    if (!h.opts) bad("cannot initialise libtiff");
    TIFFOpenOptionsSetErrorHandlerExtR(h.opts, on_error, &mf);
    TIFFOpenOptionsSetWarningHandlerExtR(h.opts, on_warning, &mf);
    TIFFOpenOptionsSetMaxSingleMemAlloc(h.opts, static_cast<tmsize_t>(std::min<std::uint64_t>(limits.max_bytes, 1u << 30)));
    const std::uint64_t held = bytes.size();  // the file, in memory while decoding
    h.tif = TIFFClientOpenExt(name.c_str(), "rm", &mf, mem_read, mem_write, mem_seek, mem_close, mem_size, mem_map,
                              mem_unmap, h.opts);
    if (!h.tif) bad("corrupt or unsupported TIFF");
    TIFF* tif = h.tif;

    // Pass 1: every page's layout, before allocating the voxels.
    std::uint32_t W = 0, H = 0;
    std::uint64_t pages = 0;
    std::uint16_t bits = 0;
    do {
        std::uint32_t w = 0, hh = 0;
        std::uint16_t spp = 1, bps = 1, photo = 0, fmt = SAMPLEFORMAT_UINT, planar = PLANARCONFIG_CONTIG;
        if (!TIFFGetField(tif, TIFFTAG_IMAGEWIDTH, &w) || !TIFFGetField(tif, TIFFTAG_IMAGELENGTH, &hh))
            bad("page " + std::to_string(pages) + " has no image width or length");
        TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLESPERPIXEL, &spp);
        TIFFGetFieldDefaulted(tif, TIFFTAG_BITSPERSAMPLE, &bps);
        TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &fmt);
        TIFFGetFieldDefaulted(tif, TIFFTAG_PLANARCONFIG, &planar);
        if (!TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &photo)) photo = PHOTOMETRIC_MINISBLACK;
        const std::string page = "page " + std::to_string(pages) + ": ";
        check_page_data(tif, mf, page, bad);
        if (spp != 1 || (photo != PHOTOMETRIC_MINISBLACK && photo != PHOTOMETRIC_MINISWHITE))
            bad(page + "not grayscale (" + std::to_string(spp) + " samples per pixel, photometric " +
                std::to_string(photo) + "); only 8- and 16-bit grayscale TIFF is read");
        if (bps != 8 && bps != 16) bad(page + std::to_string(bps) + "-bit samples; only 8- and 16-bit grayscale TIFF is read");
        if (fmt != SAMPLEFORMAT_UINT && fmt != SAMPLEFORMAT_INT)
            bad(page + "floating-point or other sample format " + std::to_string(fmt) + "; only integer samples are read");
        if (pages == 0) W = w, H = hh, bits = bps;
        if (w != W || hh != H || bps != bits)
            bad(page + std::to_string(w) + " x " + std::to_string(hh) + " at " + std::to_string(bps) +
                " bits, unlike page 0 (" + std::to_string(W) + " x " + std::to_string(H) + " at " + std::to_string(bits) +
                " bits): a multi-page TIFF is read as a volume of equal pages");
        ++pages;
        const std::uint64_t dims[3] = {W, H, pages};
        checked_voxels("TIFF", name, dims, bits / 8, limits, held);
    } while (TIFFReadDirectory(tif));
    if (!mf.error.empty()) bad("corrupt TIFF directory after page " + std::to_string(pages - 1));

    // Pass 2: the samples.
    Volume v;
    v.format = "TIFF";
    v.source = name;
    v.dims = {W, H, static_cast<std::int64_t>(pages)};
    const std::size_t plane = static_cast<std::size_t>(W) * H;
    v.values.resize(plane * pages);
    const std::size_t bpp = bits / 8;
    if (!TIFFSetDirectory(tif, 0)) bad("cannot read page 0");
    for (std::uint64_t p = 0; p < pages; ++p) {
        if (p > 0 && !TIFFReadDirectory(tif)) bad("cannot read page " + std::to_string(p));
        std::uint16_t photo = PHOTOMETRIC_MINISBLACK, fmt = SAMPLEFORMAT_UINT;
        TIFFGetField(tif, TIFFTAG_PHOTOMETRIC, &photo);
        TIFFGetFieldDefaulted(tif, TIFFTAG_SAMPLEFORMAT, &fmt);
        const bool is_signed = fmt == SAMPLEFORMAT_INT;
        const bool invert = photo == PHOTOMETRIC_MINISWHITE;
        double* out = v.values.data() + plane * p;
        auto put = [&](std::uint32_t row, std::uint32_t col, const std::uint8_t* s) {
            double x;
            if (bpp == 1) {
                x = is_signed ? static_cast<double>(static_cast<std::int8_t>(s[0])) : s[0];
                if (invert) x = (is_signed ? 127.0 : 255.0) - x;
            } else {
                std::uint16_t u;
                std::memcpy(&u, s, 2);  // libtiff returns native byte order
                x = is_signed ? static_cast<double>(static_cast<std::int16_t>(u)) : u;
                if (invert) x = (is_signed ? 32767.0 : 65535.0) - x;
            }
            out[static_cast<std::size_t>(H - 1 - row) * W + col] = x;
        };
        if (TIFFIsTiled(tif)) {
            std::uint32_t tw = 0, th = 0;
            TIFFGetField(tif, TIFFTAG_TILEWIDTH, &tw);
            TIFFGetField(tif, TIFFTAG_TILELENGTH, &th);
            const tmsize_t ts = TIFFTileSize(tif);
            if (tw == 0 || th == 0 || ts <= 0 || static_cast<std::uint64_t>(ts) < std::uint64_t{tw} * th * bpp)
                bad("page " + std::to_string(p) + ": bad tile layout");
            std::vector<std::uint8_t> buf(static_cast<std::size_t>(ts));
            for (std::uint32_t y0 = 0; y0 < H; y0 += th)
                for (std::uint32_t x0 = 0; x0 < W; x0 += tw) {
                    if (TIFFReadTile(tif, buf.data(), x0, y0, 0, 0) < 0)
                        bad("page " + std::to_string(p) + ": cannot decode the tile at (" + std::to_string(x0) + ", " +
                            std::to_string(y0) + ")");
                    for (std::uint32_t y = y0; y < std::min(H, y0 + th); ++y)
                        for (std::uint32_t x = x0; x < std::min(W, x0 + tw); ++x)
                            put(y, x, buf.data() + (static_cast<std::size_t>(y - y0) * tw + (x - x0)) * bpp);
                }
        } else {
            const tmsize_t ss = TIFFScanlineSize(tif);
            if (ss <= 0 || static_cast<std::uint64_t>(ss) < std::uint64_t{W} * bpp) bad("page " + std::to_string(p) + ": bad strip layout");
            std::vector<std::uint8_t> buf(static_cast<std::size_t>(ss));
            for (std::uint32_t y = 0; y < H; ++y) {
                if (TIFFReadScanline(tif, buf.data(), y, 0) < 0)
                    bad("page " + std::to_string(p) + ": cannot decode row " + std::to_string(y));
                for (std::uint32_t x = 0; x < W; ++x) put(y, x, buf.data() + static_cast<std::size_t>(x) * bpp);
            }
        }
    }
    return v;
}
#endif

}  // namespace warpmesh
