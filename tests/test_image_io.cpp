#define BOOST_TEST_MODULE image_io
#include <boost/test/unit_test.hpp>

#include <array>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <unistd.h>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/io/image.hpp"
#include "support.hpp"

#ifdef WARPMESH_HAVE_PNG
#include <csetjmp>
#include <png.h>
#endif

using namespace warpmesh;
namespace fs = std::filesystem;

namespace {

using warpmesh::testing::input_error_containing;

const std::string data_dir = WARPMESH_TEST_DATA;

std::vector<std::uint8_t> bytes_of(const std::string& s) { return {s.begin(), s.end()}; }

Image decode(const std::vector<std::uint8_t>& b, std::uint64_t max_pixels = default_max_pixels) {
    return decode_image(b, "mem.pgm", max_pixels);
}
Image decode(const std::string& s, std::uint64_t max_pixels = default_max_pixels) {
    return decode(bytes_of(s), max_pixels);
}

std::string p5_header(int w, int h, int maxval) {
    return "P5\n" + std::to_string(w) + " " + std::to_string(h) + "\n" + std::to_string(maxval) + "\n";
}

fs::path temp_dir() {
    static const fs::path dir = [] {
        fs::path d = fs::temp_directory_path() / ("warpmesh_test_image_io_" + std::to_string(::getpid()));
        fs::create_directories(d);
        return d;
    }();
    return dir;
}

}  // namespace

// ---------------------------------------------------------------------------
// PGM

BOOST_AUTO_TEST_CASE(p2_ascii_with_comments) {
    const Image img = decode(
        "P2\n# a comment\n3 # trailing comment\n2\n# another one\n10\n"
        "0 1 2\n"
        "# comments in the raster are tolerated\n"
        "3\t4   10\n");
    BOOST_TEST(img.width == 3);
    BOOST_TEST(img.height == 2);
    BOOST_TEST(img.maxval == 10);
    const std::vector<std::uint16_t> want{0, 1, 2, 3, 4, 10};
    BOOST_TEST(img.pixels == want, boost::test_tools::per_element());
    BOOST_TEST(img.at(2, 1) == 10);  // column 2, row 1 (bottom row)
    BOOST_TEST(img.source == "mem.pgm");
}

BOOST_AUTO_TEST_CASE(p2_sixteen_bit) {
    const Image img = decode("P2 2 1 65535 65535 40000");
    BOOST_TEST(img.maxval == 65535);
    BOOST_TEST(img.pixels[0] == 65535);
    BOOST_TEST(img.pixels[1] == 40000);
}

BOOST_AUTO_TEST_CASE(p5_eight_bit) {
    std::string s = "P5\n# comment after the magic\n4 2\n255\n";
    const std::array<unsigned char, 8> px{0, 1, 127, 128, 200, 254, 255, 10};
    s.append(px.begin(), px.end());
    const Image img = decode(s);
    BOOST_TEST(img.width == 4);
    BOOST_TEST(img.height == 2);
    BOOST_TEST(img.maxval == 255);
    for (int k = 0; k < 8; ++k) BOOST_TEST(img.pixels[k] == px[k]);
    BOOST_TEST(img.at(0, 1) == 200);
}

BOOST_AUTO_TEST_CASE(p5_raster_may_start_with_whitespace_byte_values) {
    // The single whitespace after maxval is the only separator: a first
    // sample of 10 ('\n') or 32 (' ') is data, not whitespace.
    std::string s = p5_header(3, 1, 255);
    s += '\n';
    s += ' ';
    s += '\t';
    const Image img = decode(s);
    BOOST_TEST(img.pixels[0] == 10);
    BOOST_TEST(img.pixels[1] == 32);
    BOOST_TEST(img.pixels[2] == 9);
}

BOOST_AUTO_TEST_CASE(p5_sixteen_bit_big_endian) {
    std::string s = p5_header(3, 1, 65535);
    const unsigned char px[] = {0x01, 0x02, 0xff, 0xff, 0x00, 0x07};
    s.append(std::begin(px), std::end(px));
    const Image img = decode(s);
    BOOST_TEST(img.maxval == 65535);
    BOOST_TEST(img.pixels[0] == 0x0102);
    BOOST_TEST(img.pixels[1] == 0xffff);
    BOOST_TEST(img.pixels[2] == 7);

    // maxval 256..65535 means two bytes per sample even when small
    std::string t = p5_header(2, 1, 1000);
    const unsigned char q[] = {0x03, 0xe8, 0x00, 0x01};
    t.append(std::begin(q), std::end(q));
    const Image m = decode(t);
    BOOST_TEST(m.pixels[0] == 1000);
    BOOST_TEST(m.pixels[1] == 1);
}

BOOST_AUTO_TEST_CASE(pgm_trailing_data_is_ignored) {
    std::string s = p5_header(2, 1, 255) + "ab" + "P5 junk";
    BOOST_TEST(decode(s).pixels[1] == 'b');
}

BOOST_AUTO_TEST_CASE(pgm_truncated) {
    BOOST_TEST(input_error_containing([] { decode(p5_header(4, 2, 255) + "1234567"); }, "truncated"));
    BOOST_TEST(input_error_containing([] { decode(p5_header(2, 2, 65535) + "1234567"); }, "truncated"));
    BOOST_TEST(input_error_containing([] { decode("P5\n4 2\n255"); }, "truncated"));
    BOOST_TEST(input_error_containing([] { decode("P2\n3 2\n9\n1 2 3 4 5"); }, "truncated"));
    BOOST_TEST(input_error_containing([] { decode("P5\n4 "); }, "malformed header"));
    BOOST_TEST(input_error_containing([] { decode("P5\n"); }, "malformed header"));
    BOOST_TEST(input_error_containing([] { decode("P2"); }, "malformed header"));
}

BOOST_AUTO_TEST_CASE(pgm_bad_header) {
    BOOST_TEST(input_error_containing([] { decode("P5\n4 x2\n255\n"); }, "malformed header"));
    BOOST_TEST(input_error_containing([] { decode("P5\n-4 2\n255\n"); }, "malformed header"));
    BOOST_TEST(input_error_containing([] { decode("P5\n4.5 2\n255\n"); }, "malformed header"));
    BOOST_TEST(input_error_containing([] { decode("P5\n0 2\n255\n"); }, "zero width"));
    BOOST_TEST(input_error_containing([] { decode("P5\n99999999999999999999 2\n255\n"); }, "malformed header"));
    BOOST_TEST(input_error_containing([] { decode("P5x 4 2 255\n"); }, "malformed header"));
    BOOST_TEST(input_error_containing([] { decode("P2\n2 1\n9\n1 x\n"); }, "malformed pixel data"));
}

BOOST_AUTO_TEST_CASE(pgm_bad_maxval) {
    BOOST_TEST(input_error_containing([] { decode(p5_header(1, 1, 0) + "a"); }, "maxval 0"));
    BOOST_TEST(input_error_containing([] { decode(p5_header(1, 1, 65536) + "ab"); }, "maxval 65536"));
    BOOST_TEST(input_error_containing([] { decode("P5 1 1 4294967296 ab"); }, "maxval"));
    // samples above maxval
    BOOST_TEST(input_error_containing([] { decode(p5_header(2, 1, 100) + "\x10\xc8"); }, "above maxval"));
    BOOST_TEST(input_error_containing([] { decode("P2 2 1 100 5 101"); }, "above maxval"));
    BOOST_TEST(input_error_containing([] { decode(p5_header(1, 1, 300) + "\x01\x2d"); }, "above maxval"));
}

BOOST_AUTO_TEST_CASE(huge_dimensions_refused_before_allocation) {
    // 2^31-1 squared pixels of 16 bits would be 2^63 bytes: reaching the
    // allocation would throw bad_alloc/length_error, not InputError.
    BOOST_TEST(input_error_containing([] { decode("P5\n2147483647 2147483647\n65535\n"); }, "exceed"));
    BOOST_TEST(input_error_containing([] { decode("P2\n100000 100000\n255\n"); }, "exceed"));
    BOOST_TEST(input_error_containing([] { decode("P5\n4294967295 1\n255\n"); }, "exceed"));
    // an explicit limit
    BOOST_TEST(input_error_containing([] { decode(p5_header(4, 4, 255) + std::string(16, 'a'), 15); }, "limit of 15"));
    BOOST_TEST(decode(p5_header(4, 4, 255) + std::string(16, 'a'), 16).pixels.size() == 16u);
}

BOOST_AUTO_TEST_CASE(unsupported_and_garbage) {
    BOOST_TEST(input_error_containing([] { decode(std::string()); }, "empty file"));
    BOOST_TEST(input_error_containing([] { decode("P6\n1 1\n255\nabc"); }, "Netpbm P6"));
    BOOST_TEST(input_error_containing([] { decode("P1\n1 1\n1"); }, "Netpbm P1"));
    BOOST_TEST(input_error_containing([] { decode("\xff\xd8\xff\xe0 jfif"); }, "JPEG"));
    BOOST_TEST(input_error_containing([] { decode("GIF89a..."); }, "GIF"));
    BOOST_TEST(input_error_containing([] { decode(std::string("MM\0*rest", 8)); }, "TIFF"));
    BOOST_TEST(input_error_containing([] { decode("hello world"); }, "unsupported format"));
    BOOST_TEST(input_error_containing([] { decode("\x89PNG\r\n\x1a\n"); }, "PNG"));
}

BOOST_AUTO_TEST_CASE(message_names_the_file) {
    try {
        decode_image(bytes_of("P5 0 0 255\n"), "some/dir/name.pgm");
        BOOST_FAIL("no exception");
    } catch (const InputError& e) {
        BOOST_TEST(std::string(e.what()).find("some/dir/name.pgm") != std::string::npos);
    }
}

BOOST_AUTO_TEST_CASE(unreadable_files) {
    BOOST_TEST(input_error_containing([] { read_image(data_dir + "/does-not-exist.pgm"); }, "does-not-exist.pgm"));
    BOOST_TEST(input_error_containing([] { read_image(data_dir + "/does-not-exist.pgm"); }, "cannot open"));
    BOOST_TEST(input_error_containing([] { read_image(data_dir); }, "directory"));
    const fs::path empty = temp_dir() / "empty.pgm";
    std::ofstream(empty).close();
    BOOST_TEST(input_error_containing([&] { read_image(empty.string()); }, "empty file"));
}

BOOST_AUTO_TEST_CASE(real_files) {
    const Image k1 = read_image(data_dir + "/K1_small.pgm");
    BOOST_TEST(k1.width == 92);
    BOOST_TEST(k1.height == 91);
    BOOST_TEST(k1.maxval == 255);
    BOOST_TEST(k1.source == data_dir + "/K1_small.pgm");
    // The file as shipped, with XV comment lines in its header, has the same pixels.
    const Image k1o = read_image(data_dir + "/K1_small_orig.pgm");
    BOOST_TEST(k1o.width == 92);
    BOOST_TEST(k1o.height == 91);
    BOOST_TEST((k1o.pixels == k1.pixels));

    const Image cc = read_image(data_dir + "/CorpusCallosumMeanShape_phi16.pgm");
    BOOST_TEST(cc.width == 58);
    BOOST_TEST(cc.height == 31);
    BOOST_TEST(cc.maxval == 65535);
    int below = 0, above = 0;
    for (auto v : cc.pixels) (v < 10000 ? below : above)++;
    BOOST_TEST(below > 0);   // inside the corpus callosum (phi < 0)
    BOOST_TEST(above > below);
    BOOST_TEST(*std::max_element(cc.pixels.begin(), cc.pixels.end()) > 255);  // really 16-bit data

    const Image ab = read_image(data_dir + "/abdomen_axial_z024_labels16.pgm");
    BOOST_TEST(ab.width == 256);
    BOOST_TEST(ab.height == 256);
    BOOST_TEST(std::count(ab.pixels.begin(), ab.pixels.end(), 3) > 1000);  // liver

    const Image horse = read_image(data_dir + "/horse_binary.pgm");
    BOOST_TEST(horse.width == 400);
    BOOST_TEST(horse.height == 328);
    BOOST_TEST(std::all_of(horse.pixels.begin(), horse.pixels.end(), [](auto v) { return v == 0 || v == 255; }));

    const Image v = read_image(data_dir + "/VentricleModel.pgm");
    BOOST_TEST(v.width == 181);
    BOOST_TEST(v.height == 217);
}

BOOST_AUTO_TEST_CASE(pgm_mutations_never_crash) {
    // Random byte mutations of a valid file: each decode either succeeds
    // (with a consistent image) or throws InputError.
    std::string base = "P5\n# c\n6 5\n255\n";
    for (int k = 0; k < 30; ++k) base += static_cast<char>(k * 7);
    std::mt19937 rng(12345);
    int ok = 0, refused = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        std::vector<std::uint8_t> s = bytes_of(base);
        const int edits = 1 + static_cast<int>(rng() % 4);
        for (int e = 0; e < edits; ++e) {
            const auto at = static_cast<std::ptrdiff_t>(rng() % s.size());
            switch (rng() % 3) {
                case 0: s[at] = static_cast<std::uint8_t>(rng()); break;
                case 1: s.erase(s.begin() + at, s.begin() + std::min<std::ptrdiff_t>(at + 1 + rng() % 3, s.size())); break;
                default: s.insert(s.begin() + at, static_cast<std::uint8_t>("0123456789 #\n"[rng() % 13])); break;
            }
            if (s.empty()) s.push_back('P');
        }
        try {
            const Image img = decode(s, 1u << 20);
            BOOST_REQUIRE(img.pixels.size() == static_cast<std::size_t>(img.width) * img.height);
            for (auto v : img.pixels) BOOST_REQUIRE(v <= img.maxval);
            ++ok;
        } catch (const InputError&) {
            ++refused;
        }
    }
    BOOST_TEST(ok > 0);
    BOOST_TEST(refused > 0);
}

// ---------------------------------------------------------------------------
// PNG

#ifdef WARPMESH_HAVE_PNG
namespace {

struct PngSpec {
    int width = 0, height = 0, depth = 8, color_type = PNG_COLOR_TYPE_GRAY;
    bool interlace = false;
    std::vector<std::uint8_t> raw;  // packed rows exactly as PNG stores them
    std::vector<png_color> palette;
    std::vector<png_byte> trans_alpha;  // palette tRNS
    bool gray_key = false;
    png_uint_16 key = 0;  // gray tRNS key
};

extern "C" void append_to_vector(png_structp png, png_bytep data, png_size_t n) {
    auto* out = static_cast<std::vector<std::uint8_t>*>(png_get_io_ptr(png));
    out->insert(out->end(), data, data + n);
}
extern "C" void flush_nothing(png_structp) {}

// Encodes `spec` in memory with libpng.  Returns false if libpng refused.
bool encode_png_c(const PngSpec* spec, std::vector<std::uint8_t>* out, png_bytepp rows) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
    png_infop info = png_create_info_struct(png);
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, out, append_to_vector, flush_nothing);
    png_set_IHDR(png, info, spec->width, spec->height, spec->depth, spec->color_type,
                 spec->interlace ? PNG_INTERLACE_ADAM7 : PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
                 PNG_FILTER_TYPE_DEFAULT);
    if (!spec->palette.empty())
        png_set_PLTE(png, info, const_cast<png_colorp>(spec->palette.data()), static_cast<int>(spec->palette.size()));
    if (!spec->trans_alpha.empty())
        png_set_tRNS(png, info, const_cast<png_bytep>(spec->trans_alpha.data()),
                     static_cast<int>(spec->trans_alpha.size()), nullptr);
    png_color_16 key{};
    key.gray = spec->key;
    if (spec->gray_key) png_set_tRNS(png, info, nullptr, 0, &key);
    png_write_info(png, info);
    png_write_image(png, rows);
    png_write_end(png, nullptr);
    png_destroy_write_struct(&png, &info);
    return true;
}

std::vector<std::uint8_t> encode_png(const PngSpec& spec) {
    const std::size_t rowbytes = spec.raw.size() / spec.height;
    std::vector<png_bytep> rows(spec.height);
    for (int y = 0; y < spec.height; ++y) rows[y] = const_cast<png_bytep>(spec.raw.data()) + y * rowbytes;
    std::vector<std::uint8_t> out;
    BOOST_REQUIRE(encode_png_c(&spec, &out, rows.data()));
    return out;
}

Image decode_png(const std::vector<std::uint8_t>& b, std::uint64_t max_pixels = default_max_pixels) {
    return decode_image(b, "mem.png", max_pixels);
}

std::uint32_t crc32(const std::uint8_t* p, std::size_t n) {
    std::uint32_t c = 0xffffffffu;
    for (std::size_t i = 0; i < n; ++i) {
        c ^= p[i];
        for (int k = 0; k < 8; ++k) c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1)));
    }
    return ~c;
}

void put_be32(std::uint8_t* p, std::uint32_t v) {
    p[0] = static_cast<std::uint8_t>(v >> 24), p[1] = static_cast<std::uint8_t>(v >> 16);
    p[2] = static_cast<std::uint8_t>(v >> 8), p[3] = static_cast<std::uint8_t>(v);
}

}  // namespace

BOOST_AUTO_TEST_CASE(png_gray8_and_file) {
    PngSpec s;
    s.width = 3, s.height = 2;
    s.raw = {0, 100, 255, 7, 8, 9};
    const auto png = encode_png(s);
    const Image img = decode_png(png);
    BOOST_TEST(img.width == 3);
    BOOST_TEST(img.height == 2);
    BOOST_TEST(img.maxval == 255);
    const std::vector<std::uint16_t> want{0, 100, 255, 7, 8, 9};
    BOOST_TEST(img.pixels == want, boost::test_tools::per_element());

    // through a file, detected by magic bytes despite the misleading name
    const fs::path path = temp_dir() / "gray8.pgm";
    std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(png.data()), png.size());
    const Image f = read_image(path.string());
    BOOST_TEST(f.pixels == want, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(png_gray16_keeps_raw_samples) {
    PngSpec s;
    s.width = 2, s.height = 1, s.depth = 16;
    s.raw = {0x12, 0x34, 0xff, 0xfe};
    const Image img = decode_png(encode_png(s));
    BOOST_TEST(img.maxval == 65535);
    BOOST_TEST(img.pixels[0] == 0x1234);
    BOOST_TEST(img.pixels[1] == 0xfffe);
}

BOOST_AUTO_TEST_CASE(png_gray_sub_byte_depths) {
    PngSpec s;
    s.width = 10, s.height = 1, s.depth = 1;
    s.raw = {0b10110000, 0b01000000};  // 1 0 1 1 0 0 0 0 | 0 1
    const Image one = decode_png(encode_png(s));
    BOOST_TEST(one.maxval == 1);
    const std::vector<std::uint16_t> want1{1, 0, 1, 1, 0, 0, 0, 0, 0, 1};
    BOOST_TEST(one.pixels == want1, boost::test_tools::per_element());

    PngSpec f;
    f.width = 3, f.height = 1, f.depth = 4;
    f.raw = {0xf3, 0xa0};
    const Image four = decode_png(encode_png(f));
    BOOST_TEST(four.maxval == 15);
    const std::vector<std::uint16_t> want4{15, 3, 10};
    BOOST_TEST(four.pixels == want4, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(png_rgb_luma) {
    PngSpec s;
    s.width = 5, s.height = 1, s.color_type = PNG_COLOR_TYPE_RGB;
    s.raw = {255, 0, 0, 0, 255, 0, 0, 0, 255, 10, 20, 30, 255, 255, 255};
    const Image img = decode_png(encode_png(s));
    BOOST_TEST(img.maxval == 255);
    // round(0.299 R + 0.587 G + 0.114 B)
    const std::vector<std::uint16_t> want{76, 150, 29, 18, 255};
    BOOST_TEST(img.pixels == want, boost::test_tools::per_element());

    PngSpec t = s;
    t.depth = 16;
    t.raw.clear();
    for (unsigned v : {65535u, 0u, 0u, 1000u, 1000u, 1000u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u, 0u})
        t.raw.push_back(static_cast<std::uint8_t>(v >> 8)), t.raw.push_back(static_cast<std::uint8_t>(v));
    const Image img16 = decode_png(encode_png(t));
    BOOST_TEST(img16.maxval == 65535);
    BOOST_TEST(img16.pixels[0] == 19595);  // 0.299 * 65535 = 19594.965
    BOOST_TEST(img16.pixels[1] == 1000);
}

BOOST_AUTO_TEST_CASE(png_alpha_composited_over_white) {
    PngSpec s;
    s.width = 3, s.height = 1, s.color_type = PNG_COLOR_TYPE_RGB_ALPHA;
    s.raw = {0, 0, 0, 0, /**/ 0, 0, 0, 255, /**/ 0, 0, 0, 128};
    const Image img = decode_png(encode_png(s));
    BOOST_TEST(img.pixels[0] == 255);  // transparent → white
    BOOST_TEST(img.pixels[1] == 0);    // opaque black
    BOOST_TEST(img.pixels[2] == 127);  // round(127 * 255 / 255) = 127

    PngSpec g;
    g.width = 2, g.height = 1, g.depth = 16, g.color_type = PNG_COLOR_TYPE_GRAY_ALPHA;
    g.raw = {0x10, 0x00, 0xff, 0xff, /**/ 0x10, 0x00, 0x00, 0x00};
    const Image ga = decode_png(encode_png(g));
    BOOST_TEST(ga.maxval == 65535);
    BOOST_TEST(ga.pixels[0] == 0x1000);
    BOOST_TEST(ga.pixels[1] == 65535);

    PngSpec k;  // gray with a tRNS key colour
    k.width = 3, k.height = 1;
    k.raw = {5, 6, 5};
    k.gray_key = true, k.key = 5;
    const Image kk = decode_png(encode_png(k));
    const std::vector<std::uint16_t> want{255, 6, 255};
    BOOST_TEST(kk.pixels == want, boost::test_tools::per_element());
}

BOOST_AUTO_TEST_CASE(png_palette) {
    // A colour palette: the index is kept (label maps).
    PngSpec s;
    s.width = 4, s.height = 1, s.color_type = PNG_COLOR_TYPE_PALETTE;
    s.palette = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {9, 9, 9}};
    s.raw = {3, 0, 2, 1};
    const Image idx = decode_png(encode_png(s));
    BOOST_TEST(idx.maxval == 255);
    const std::vector<std::uint16_t> want{3, 0, 2, 1};
    BOOST_TEST(idx.pixels == want, boost::test_tools::per_element());

    PngSpec s2 = s;  // 2-bit indices
    s2.depth = 2;
    s2.raw = {0b11001001};
    const Image idx2 = decode_png(encode_png(s2));
    BOOST_TEST(idx2.maxval == 3);
    BOOST_TEST(idx2.pixels == want, boost::test_tools::per_element());

    // An all-gray palette: the gray level, with tRNS alpha over white.
    PngSpec g;
    g.width = 3, g.height = 1, g.color_type = PNG_COLOR_TYPE_PALETTE;
    g.palette = {{200, 200, 200}, {10, 10, 10}, {0, 0, 0}};
    g.trans_alpha = {255, 255, 0};
    g.raw = {1, 0, 2};
    const Image gray = decode_png(encode_png(g));
    BOOST_TEST(gray.maxval == 255);
    const std::vector<std::uint16_t> wantg{10, 200, 255};
    BOOST_TEST(gray.pixels == wantg, boost::test_tools::per_element());

    // An index beyond a gray palette is refused, not read out of bounds.
    PngSpec bad = g;
    bad.raw = {1, 0, 7};
    bad.trans_alpha.clear();
    const auto enc = [&] {
        std::vector<std::uint8_t> out;
        std::vector<png_bytep> rows{bad.raw.data()};
        return encode_png_c(&bad, &out, rows.data()) ? out : std::vector<std::uint8_t>{};
    }();
    if (!enc.empty()) {
        BOOST_TEST(input_error_containing([&] { decode_png(enc); }, "mem.png"));
    }
}

BOOST_AUTO_TEST_CASE(png_interlaced_equals_plain) {
    PngSpec s;
    s.width = 11, s.height = 9;
    for (int k = 0; k < 99; ++k) s.raw.push_back(static_cast<std::uint8_t>(k * 37 % 251));
    PngSpec i = s;
    i.interlace = true;
    const Image a = decode_png(encode_png(s)), b = decode_png(encode_png(i));
    BOOST_TEST(a.pixels == b.pixels, boost::test_tools::per_element());
    BOOST_TEST(a.pixels[98] == 98 * 37 % 251);
}

BOOST_AUTO_TEST_CASE(png_corrupt) {
    PngSpec s;
    s.width = 16, s.height = 16;
    for (int k = 0; k < 256; ++k) s.raw.push_back(static_cast<std::uint8_t>(k));
    const auto good = encode_png(s);
    BOOST_TEST(decode_png(good).pixels[255] == 255);

    auto truncated = good;
    truncated.resize(good.size() / 2);
    BOOST_TEST(input_error_containing([&] { decode_png(truncated); }, "mem.png"));
    truncated.resize(20);  // inside IHDR
    BOOST_TEST(input_error_containing([&] { decode_png(truncated); }, "truncated"));

    auto crc = good;
    crc[good.size() - 20] ^= 0x55;  // inside IDAT (or its CRC)
    BOOST_TEST(input_error_containing([&] { decode_png(crc); }, "corrupt PNG"));

    // IHDR claiming 2^30 x 2^30 pixels (with a valid CRC): refused by the
    // pixel limit before anything is allocated.
    auto huge = good;
    put_be32(&huge[16], 1u << 30);
    put_be32(&huge[20], 1u << 30);
    put_be32(&huge[29], crc32(&huge[12], 17));
    BOOST_TEST(input_error_containing([&] { decode_png(huge); }, "exceed"));
    // and an explicit limit
    BOOST_TEST(input_error_containing([&] { decode_png(good, 255); }, "limit of 255"));
}

BOOST_AUTO_TEST_CASE(png_mutations_never_crash) {
    PngSpec s;
    s.width = 7, s.height = 5, s.color_type = PNG_COLOR_TYPE_RGB_ALPHA;
    for (int k = 0; k < 7 * 5 * 4; ++k) s.raw.push_back(static_cast<std::uint8_t>(k * 13));
    const auto good = encode_png(s);
    std::mt19937 rng(777);
    int ok = 0, refused = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        auto b = good;
        const int edits = 1 + static_cast<int>(rng() % 3);
        for (int e = 0; e < edits; ++e) {
            const std::size_t at = 8 + rng() % (b.size() - 8);  // keep the signature
            if (rng() % 4 == 0)
                b.resize(at);
            else
                b[at] ^= static_cast<std::uint8_t>(1 + rng() % 255);
            if (b.size() <= 8) break;
        }
        try {
            const Image img = decode_png(b, 1u << 16);
            BOOST_REQUIRE(img.pixels.size() == static_cast<std::size_t>(img.width) * img.height);
            for (auto v : img.pixels) BOOST_REQUIRE(v <= img.maxval);
            ++ok;
        } catch (const InputError&) {
            ++refused;
        }
    }
    BOOST_TEST(refused > 0);
    BOOST_TEST_MESSAGE("mutated PNGs: " << ok << " decoded, " << refused << " refused");
}
#else
BOOST_AUTO_TEST_CASE(png_not_supported_message) {
    BOOST_TEST(!png_supported());
    BOOST_TEST(input_error_containing([] { decode("\x89PNG\r\n\x1a\nrest"); }, "PNG support"));
}
#endif
