// volume_fixtures.hpp — small NRRD, NIfTI-1/2 and TIFF files made in memory by
// the tests (no committed binaries): every sample type, both byte orders,
// gzip, and hand-set geometry.  Written from the format specifications
// (teem's NRRD format page, nifti1.h / nifti2.h, libtiff's writer), not from
// the readers under test.
#pragma once

#include <tiffio.h>
#include <zlib.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace warpmesh::testing {

using Bytes = std::vector<std::uint8_t>;

enum class T { i8, u8, i16, u16, i32, u32, f32, f64 };
inline const char* nrrd_type(T t) {
    static const char* names[] = {"int8", "uchar", "short", "unsigned short", "int", "uint32", "float", "double"};
    return names[static_cast<int>(t)];
}
inline int nifti_code(T t) {
    static const int codes[] = {256, 2, 4, 512, 8, 768, 16, 64};
    return codes[static_cast<int>(t)];
}
inline std::size_t type_bytes(T t) {
    static const std::size_t b[] = {1, 1, 2, 2, 4, 4, 4, 8};
    return b[static_cast<int>(t)];
}

// The raw bytes of a value of type t (little-endian unless big).
inline void put(Bytes& out, T t, double v, bool big) {
    std::uint8_t b[8];
    switch (t) {
        case T::i8: { auto x = static_cast<std::int8_t>(v); std::memcpy(b, &x, 1); break; }
        case T::u8: { auto x = static_cast<std::uint8_t>(v); std::memcpy(b, &x, 1); break; }
        case T::i16: { auto x = static_cast<std::int16_t>(v); std::memcpy(b, &x, 2); break; }
        case T::u16: { auto x = static_cast<std::uint16_t>(v); std::memcpy(b, &x, 2); break; }
        case T::i32: { auto x = static_cast<std::int32_t>(v); std::memcpy(b, &x, 4); break; }
        case T::u32: { auto x = static_cast<std::uint32_t>(v); std::memcpy(b, &x, 4); break; }
        case T::f32: { auto x = static_cast<float>(v); std::memcpy(b, &x, 4); break; }
        case T::f64: std::memcpy(b, &v, 8); break;
    }
    const std::size_t n = type_bytes(t);
    for (std::size_t q = 0; q < n; ++q) out.push_back(big ? b[n - 1 - q] : b[q]);  // x86: native is little
}

inline Bytes gzip(const Bytes& in) {
    z_stream zs{};
    if (deflateInit2(&zs, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::runtime_error("zlib");
    Bytes out(deflateBound(&zs, static_cast<uLong>(in.size())) + 32);
    zs.next_in = const_cast<Bytef*>(in.data());
    zs.avail_in = static_cast<uInt>(in.size());
    zs.next_out = out.data();
    zs.avail_out = static_cast<uInt>(out.size());
    if (deflate(&zs, Z_FINISH) != Z_STREAM_END) throw std::runtime_error("zlib");
    out.resize(zs.total_out);
    deflateEnd(&zs);
    return out;
}

inline Bytes text(const std::string& s) { return Bytes(s.begin(), s.end()); }
inline Bytes operator+(Bytes a, const Bytes& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
}

inline Bytes samples(T t, const std::vector<double>& values, bool big) {
    Bytes b;
    for (double v : values) put(b, t, v, big);
    return b;
}

// An attached NRRD: the header lines given (after the magic), a blank line,
// then the samples, raw or gzip.
struct Nrrd {
    T type = T::u8;
    std::array<int, 3> sizes{2, 2, 1};
    int dimension = 3;
    std::string encoding = "raw";
    bool big = false;
    std::string extra;  // more header lines, each ending in \n
    std::vector<double> values;
};
inline std::string nrrd_header(const Nrrd& n) {
    std::string h = "NRRD0004\n# made by the warpmesh tests\ntype: " + std::string(nrrd_type(n.type)) +
                    "\ndimension: " + std::to_string(n.dimension) + "\nsizes:";
    for (int a = 0; a < n.dimension; ++a) h += " " + std::to_string(n.sizes[static_cast<std::size_t>(a)]);
    h += "\nencoding: " + n.encoding + "\n";
    if (type_bytes(n.type) > 1) h += std::string("endian: ") + (n.big ? "big" : "little") + "\n";
    return h + n.extra;
}
inline Bytes nrrd_data(const Nrrd& n) {
    Bytes raw = samples(n.type, n.values, n.big);
    return n.encoding == "gzip" ? gzip(raw) : raw;
}
inline Bytes nrrd(const Nrrd& n) { return text(nrrd_header(n) + "\n") + nrrd_data(n); }

// A single-file NIfTI-1 (348-byte header) or NIfTI-2 (540) with vox_offset
// 352 / 544 (the 4-byte extension flag, zero, in between).
struct Nifti {
    int version = 1;
    T type = T::u8;
    std::array<std::int64_t, 8> dim{3, 2, 2, 1, 1, 1, 1, 1};
    std::array<double, 8> pixdim{1, 1, 1, 1, 0, 0, 0, 0};
    double slope = 0, inter = 0;
    int qform_code = 0, sform_code = 0;
    std::array<double, 3> quatern{0, 0, 0}, qoffset{0, 0, 0};
    std::array<std::array<double, 4>, 3> srow{};
    bool big = false;
    std::string magic;  // default "n+1" / "n+2"
    std::vector<double> values;
};
inline Bytes nifti(const Nifti& n) {
    const bool v2 = n.version == 2;
    const std::size_t hdr = v2 ? 540 : 348, off = hdr + 4;
    Bytes h(off, 0);
    auto at = [&](std::size_t pos, T t, double v) {
        Bytes b;
        put(b, t, v, n.big);
        std::copy(b.begin(), b.end(), h.begin() + static_cast<std::ptrdiff_t>(pos));
    };
    auto i64 = [&](std::size_t pos, std::int64_t v) {
        std::uint8_t b[8];
        std::memcpy(b, &v, 8);
        for (int q = 0; q < 8; ++q) h[pos + static_cast<std::size_t>(q)] = n.big ? b[7 - q] : b[q];
    };
    const T real = v2 ? T::f64 : T::f32;
    const std::size_t rb = v2 ? 8 : 4;
    at(0, T::i32, static_cast<double>(hdr));
    const std::string magic = n.magic.empty() ? (v2 ? std::string("n+2\0\r\n\032\n", 8) : std::string("n+1\0", 4)) : n.magic;
    std::memcpy(h.data() + (v2 ? 4 : 344), magic.data(), std::min<std::size_t>(magic.size(), v2 ? 8 : 4));
    at(v2 ? 12 : 70, T::i16, nifti_code(n.type));
    at(v2 ? 14 : 72, T::i16, static_cast<double>(8 * type_bytes(n.type)));
    for (std::size_t q = 0; q < 8; ++q) {
        if (v2) i64(16 + 8 * q, n.dim[q]);
        else at(40 + 2 * q, T::i16, static_cast<double>(n.dim[q]));
        at((v2 ? 104 : 76) + rb * q, real, n.pixdim[q]);
    }
    if (v2) i64(168, static_cast<std::int64_t>(off));
    else at(108, T::f32, static_cast<double>(off));
    at(v2 ? 176 : 112, real, n.slope);
    at(v2 ? 184 : 116, real, n.inter);
    at(v2 ? 344 : 252, v2 ? T::i32 : T::i16, n.qform_code);
    at(v2 ? 348 : 254, v2 ? T::i32 : T::i16, n.sform_code);
    for (std::size_t q = 0; q < 3; ++q) {
        at((v2 ? 352 : 256) + rb * q, real, n.quatern[q]);
        at((v2 ? 376 : 268) + rb * q, real, n.qoffset[q]);
        for (std::size_t c = 0; c < 4; ++c) at((v2 ? 400 : 280) + rb * (4 * q + c), real, n.srow[q][c]);
    }
    return h + samples(n.type, n.values, n.big);
}

// A TIFF file through libtiff: one page per entry of `pages` (row-major
// samples, row 0 at the top), 8 or 16 bits, optionally tiled or min-is-white.
struct Tiff {
    int width = 2, height = 2, bits = 8;
    std::vector<std::vector<double>> pages;
    bool tiled = false, min_is_white = false, rgb = false, deflate = false;
};
inline Bytes tiff_file(const Tiff& t, const std::filesystem::path& path) {
    TIFF* tif = TIFFOpen(path.c_str(), "w");
    if (!tif) throw std::runtime_error("TIFFOpen");
    for (const auto& page : t.pages) {
        const int spp = t.rgb ? 3 : 1;
        TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, t.width);
        TIFFSetField(tif, TIFFTAG_IMAGELENGTH, t.height);
        TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, t.bits);
        TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, spp);
        TIFFSetField(tif, TIFFTAG_PLANARCONFIG, PLANARCONFIG_CONTIG);
        TIFFSetField(tif, TIFFTAG_PHOTOMETRIC,
                     t.rgb ? PHOTOMETRIC_RGB : t.min_is_white ? PHOTOMETRIC_MINISWHITE : PHOTOMETRIC_MINISBLACK);
        TIFFSetField(tif, TIFFTAG_COMPRESSION, t.deflate ? COMPRESSION_ADOBE_DEFLATE : COMPRESSION_NONE);
        if (t.pages.size() > 1) TIFFSetField(tif, TIFFTAG_SUBFILETYPE, FILETYPE_PAGE);
        const std::size_t bpp = static_cast<std::size_t>(t.bits / 8 * spp);
        auto sample = [&](int r, int c, std::uint8_t* out) {
            for (int s = 0; s < spp; ++s) {
                const double v = page[static_cast<std::size_t>(r * t.width + c)];
                if (t.bits == 8) out[s] = static_cast<std::uint8_t>(v);
                else { const auto u = static_cast<std::uint16_t>(v); std::memcpy(out + 2 * s, &u, 2); }
            }
        };
        if (t.tiled) {
            TIFFSetField(tif, TIFFTAG_TILEWIDTH, 16);
            TIFFSetField(tif, TIFFTAG_TILELENGTH, 16);
            Bytes buf(static_cast<std::size_t>(TIFFTileSize(tif)));
            for (int y0 = 0; y0 < t.height; y0 += 16)
                for (int x0 = 0; x0 < t.width; x0 += 16) {
                    std::fill(buf.begin(), buf.end(), 0);
                    for (int y = y0; y < std::min(t.height, y0 + 16); ++y)
                        for (int x = x0; x < std::min(t.width, x0 + 16); ++x)
                            sample(y, x, buf.data() + static_cast<std::size_t>((y - y0) * 16 + (x - x0)) * bpp);
                    TIFFWriteTile(tif, buf.data(), static_cast<std::uint32_t>(x0), static_cast<std::uint32_t>(y0), 0, 0);
                }
        } else {
            TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, 3);
            Bytes row(static_cast<std::size_t>(t.width) * bpp);
            for (int r = 0; r < t.height; ++r) {
                for (int c = 0; c < t.width; ++c) sample(r, c, row.data() + static_cast<std::size_t>(c) * bpp);
                TIFFWriteScanline(tif, row.data(), static_cast<std::uint32_t>(r), 0);
            }
        }
        TIFFWriteDirectory(tif);
    }
    TIFFClose(tif);
    std::ifstream in(path, std::ios::binary);
    return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace warpmesh::testing
