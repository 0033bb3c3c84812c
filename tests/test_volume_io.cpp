// Volume readers (NRRD, NIfTI-1/2, TIFF) and slices in physical units.
//
// Every fixture is generated here (volume_fixtures.hpp): each sample type in
// both byte orders, raw and gzip, attached and detached NRRD headers, the
// NIfTI geometry paths (pixdim only, qform, sform — permuted and flipped),
// scl_slope / scl_inter, multi-page, tiled and min-is-white TIFF; then
// truncated and hostile headers, each refused with a message that names the
// problem.  The slice tests check that a slice's 2D coordinates are the
// physical ones (every pixel centre maps back to its voxel's 3D position),
// that an anisotropic slice is meshed in millimetres (area = pixel count x
// sx x sy), that pixel units reproduce the image level set bit for bit, and
// the CLI's --slice / --slices / --units / --pixel-size / --points-3d.
#define BOOST_TEST_MODULE volume_io
#include <boost/test/unit_test.hpp>

#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <set>
#include <sstream>

#include "fuzz/fuzz_volume_checks.hpp"
#include "support.hpp"
#include "volume_fixtures.hpp"
#include "warpmesh/io/image.hpp"
#include "warpmesh/pipeline/mesh2d.hpp"
#include "warpmesh/post/quality.hpp"
#include "warpmesh/pipeline/slices.hpp"
#include "warpmesh/mesh2d/uniform.hpp"
#include "warpmesh/mesh2d/graded.hpp"
#include "warpmesh/io/volume.hpp"
#include "without_range.hpp"

namespace fs = std::filesystem;
using namespace warpmesh;
using namespace warpmesh::testing;

namespace {

Volume decode(const Bytes& b, const std::string& name = "test-input", const std::string& dir = "") {
    return decode_volume(b, name, VolumeLimits{}, dir);
}

// The InputError message of f(), or "" if it does not throw one.
std::string error_of(const std::function<void()>& f) {
    try {
        f();
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}
bool refused_with(const Bytes& b, const std::string& words) {
    const std::string m = error_of([&] { decode(b); });
    if (m.find(words) == std::string::npos || m.find("test-input") == std::string::npos) {
        BOOST_TEST_MESSAGE("message: '" << m << "', expected to contain '" << words << "'");
        return false;
    }
    return true;
}

std::vector<double> values_for(T t, std::size_t n) {
    std::vector<double> v(n);
    for (std::size_t k = 0; k < n; ++k) {
        const double x = static_cast<double>(k * 37 % 101);
        switch (t) {
            case T::i8: v[k] = x - 60; break;
            case T::u8: v[k] = x * 2; break;
            case T::i16: v[k] = x * 300 - 15000; break;
            case T::u16: v[k] = x * 600; break;
            case T::i32: v[k] = x * 20000000 - 1000000000; break;
            case T::u32: v[k] = x * 40000000; break;
            case T::f32: v[k] = x * 0.25 - 3.5; break;
            case T::f64: v[k] = x / 3 - 7; break;
        }
    }
    return v;
}

constexpr T all_types[] = {T::i8, T::u8, T::i16, T::u16, T::i32, T::u32, T::f32, T::f64};

// A scratch directory that files can be written into.
struct Dir : TempDir {
    Dir() : TempDir("warpmesh-volume") {}
    fs::path write(const std::string& name, const Bytes& b) const {
        std::ofstream out(path / name, std::ios::binary);
        out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
        return path / name;
    }
};

bool same_values(const Volume& v, const std::vector<double>& want) {
    if (v.values.size() + v.labels.size() != want.size() || (!v.values.empty() && !v.labels.empty())) return false;
    for (std::size_t k = 0; k < want.size(); ++k)
        if (v.value(k) != want[k]) return false;
    return true;
}

// Whether a reader must keep these samples as 16-bit labels: integers in 0..65535.
bool label_range(const std::vector<double>& x) {
    return std::all_of(x.begin(), x.end(), [](double y) { return y >= 0 && y <= 65535 && y == std::floor(y); });
}

}  // namespace

// --- NRRD ----------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(nrrd_every_type_encoding_and_byte_order_round_trips) {
    for (T t : all_types)
        for (const char* enc : {"raw", "gzip"})
            for (bool big : {false, true}) {
                Nrrd n;
                n.type = t, n.sizes = {3, 4, 5}, n.encoding = enc, n.big = big;
                n.values = values_for(t, 60);
                const Volume v = decode(nrrd(n));
                BOOST_TEST_CONTEXT(nrrd_type(t) << " " << enc << (big ? " big" : " little")) {
                    BOOST_TEST(v.format == "NRRD");
                    BOOST_TEST((v.dims == std::array<std::int64_t, 3>{3, 4, 5}));
                    BOOST_TEST(same_values(v, n.values));
                    BOOST_TEST(v.integer_valued == (t != T::f32 && t != T::f64));
                    // Integer labels stay 2 bytes a voxel (issue 49: no doubles for a label volume).
                    BOOST_TEST(!v.labels.empty() == (v.integer_valued && label_range(n.values)));
                    BOOST_TEST(v.values.empty() == !v.labels.empty());
                    BOOST_TEST(!v.physical);  // no spacings, no directions
                }
            }
}

// 16-bit gzip samples are inflated into the labels' own memory and decoded
// there; a negative short among them falls back to doubles from a copy.
BOOST_AUTO_TEST_CASE(nrrd_16_bit_labels_decode_in_place_and_fall_back_to_doubles) {
    for (T t : {T::i16, T::u16})
        for (bool big : {false, true})
            for (bool negative : {false, true}) {
                Nrrd n;
                n.type = t, n.sizes = {5, 4, 3}, n.encoding = "gzip", n.big = big;
                n.values.assign(60, 0);
                for (std::size_t k = 0; k < 60; ++k) n.values[k] = static_cast<double>(k * 541 % 4101);
                if (negative && t == T::i16) n.values[37] = -2;
                const Volume v = decode(nrrd(n));
                BOOST_TEST_CONTEXT(nrrd_type(t) << (big ? " big" : " little") << (negative ? " negative" : "")) {
                    BOOST_TEST(same_values(v, n.values));
                    BOOST_TEST(v.labels.empty() == (negative && t == T::i16));
                }
            }
}

BOOST_AUTO_TEST_CASE(nrrd_ascii_2d_and_spacings) {
    const Bytes b = text("NRRD0001\ntype: float\ndimension: 2\nsizes: 3 2\nspacings: 0.5 2\nencoding: ascii\n\n"
                         "1 2 3\n4.5 5 6\n");
    const Volume v = decode(b);
    BOOST_TEST((v.dims == std::array<std::int64_t, 3>{3, 2, 1}));
    BOOST_TEST(same_values(v, {1, 2, 3, 4.5, 5, 6}));
    BOOST_TEST(v.spacing[0] == 0.5);
    BOOST_TEST(v.spacing[1] == 2);
    BOOST_TEST(v.physical);
}

BOOST_AUTO_TEST_CASE(nrrd_space_directions_permuted_and_flipped) {
    // Like the SPL brain atlas: i along +y, j along -z, k along +x.
    Nrrd n;
    n.type = T::i16, n.sizes = {2, 3, 4}, n.encoding = "gzip";
    n.values = values_for(T::i16, 24);
    n.extra = "space: left-posterior-superior\nspace directions: (0,1.5,0) (0,0,-2) (0.5,0,0)\n"
              "space origin: (-10,20,30.5)\n";
    const Volume v = decode(nrrd(n));
    BOOST_TEST(v.physical);
    BOOST_TEST(v.space == "left-posterior-superior");
    BOOST_TEST((v.spacing == Vec3{1.5, 2, 0.5}));
    BOOST_TEST((v.axes[0] == Vec3{0, 1, 0}));
    BOOST_TEST((v.axes[1] == Vec3{0, 0, -1}));
    BOOST_TEST((v.axes[2] == Vec3{1, 0, 0}));
    BOOST_TEST((v.origin == Vec3{-10, 20, 30.5}));
}

BOOST_AUTO_TEST_CASE(nrrd_detached_header_reads_its_data_file) {
    Dir dir;
    Nrrd n;
    n.type = T::u16, n.sizes = {4, 3, 2}, n.encoding = "gzip", n.big = true;
    n.values = values_for(T::u16, 24);
    dir.write("data.raw.gz", nrrd_data(n));
    n.extra = "data file: data.raw.gz\n";
    const fs::path header = dir.write("vol.nhdr", text(nrrd_header(n)));
    const Volume v = read_volume(header.string());
    BOOST_TEST(same_values(v, n.values));
    // Byte skip -1: the raw data ends the file, after a preamble.
    Nrrd r;
    r.type = T::u8, r.sizes = {2, 2, 1};
    r.values = {1, 2, 3, 4};
    dir.write("pre.raw", text("some preamble") + nrrd_data(r));
    r.extra = "data file: pre.raw\nbyte skip: -1\n";
    BOOST_TEST(same_values(read_volume(dir.write("pre.nhdr", text(nrrd_header(r))).string()), r.values));
    // From memory the detached file cannot be looked up: refused, not guessed.
    BOOST_TEST(refused_with(text(nrrd_header(n)), "detached data file"));
    r.extra = "data file: missing.raw\n";
    const std::string missing = error_of([&] { read_volume(dir.write("m.nhdr", text(nrrd_header(r))).string()); });
    BOOST_TEST(missing.find("data file") != std::string::npos);
    BOOST_TEST(missing.find("cannot open") != std::string::npos);
}

// Issue 27 item 3: a detached data file on a device was read without end
// (11.7 GB resident at 60 s on /dev/zero).  Now only regular files of the
// size the header implies are read.
BOOST_AUTO_TEST_CASE(nrrd_detached_data_file_on_a_device_fifo_or_of_the_wrong_size_is_refused) {
    Dir dir;
    Nrrd r;
    r.type = T::u8, r.sizes = {4, 4, 1};
    r.values = std::vector<double>(16, 3);
    auto refused = [&](const std::string& extra, std::initializer_list<const char*> words) {
        r.extra = extra;
        const std::string m = error_of([&] { read_volume(dir.write("d.nhdr", text(nrrd_header(r))).string()); });
        BOOST_TEST_INFO("message: " << m);
        BOOST_TEST(!m.empty());
        for (const char* w : words) BOOST_TEST(m.find(w) != std::string::npos, "'" << w << "' in '" << m << "'");
    };
    refused("data file: /dev/zero\n", {"/dev/zero", "is a device, not a regular file"});
    refused("data file: /dev/urandom\n", {"/dev/urandom", "is a device"});
    const fs::path fifo = dir.path / "pipe";
    BOOST_REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
    refused("data file: pipe\n", {"pipe", "FIFO"});  // never opened: opening a FIFO would block
    dir.write("long.raw", Bytes(17, 3));
    refused("data file: long.raw\n", {"long.raw", "17 bytes, more than the 16"});
    dir.write("short.raw", Bytes(15, 3));
    refused("data file: short.raw\n", {"short.raw", "truncated", "15 bytes"});
    // The right size is read, and so is a longer file with byte skip -1 (its last 16 bytes).
    dir.write("ok.raw", Bytes(16, 3));
    r.extra = "data file: ok.raw\n";
    BOOST_TEST(same_values(read_volume(dir.write("ok.nhdr", text(nrrd_header(r))).string()), r.values));
    // gzip data that inflates to more than the header implies: refused, attached or detached.
    Nrrd g = r;
    g.encoding = "gzip", g.extra = "";
    g.values.push_back(3);
    g.sizes = {17, 1, 1};
    const Bytes longer = gzip(samples(T::u8, g.values, false));
    g.sizes = {4, 4, 1};
    BOOST_TEST(refused_with(text(nrrd_header(g) + "\n") + longer, "inflates to more than the 16 bytes"));
    dir.write("long.raw.gz", longer);
    g.extra = "data file: long.raw.gz\n";
    BOOST_TEST(error_of([&] { read_volume(dir.write("g.nhdr", text(nrrd_header(g))).string()); })
                   .find("inflates to more than") != std::string::npos);
    // The file named on the command line must be a regular file too.
    BOOST_TEST(error_of([] { read_volume("/dev/zero"); }).find("is a device") != std::string::npos);
}

// Issue 27 item 6: 'spacings: nan' was read as 1 mm.  All nan: no physical
// size (pixels, as a TIFF); a mix: refused, naming the axis.
BOOST_AUTO_TEST_CASE(nrrd_spacings_nan_is_no_physical_size_not_1_mm) {
    Nrrd n;
    n.type = T::u8, n.sizes = {2, 2, 2};
    n.values = std::vector<double>(8, 1);
    n.extra = "spacings: nan nan nan\n";
    const Volume v = decode(nrrd(n));
    BOOST_TEST(!v.physical);
    n.extra = "spacings: NaN NaN NaN\n";
    BOOST_TEST(!decode(nrrd(n)).physical);
    n.extra = "spacings: 0.5 0.5 nan\n";
    BOOST_TEST(refused_with(nrrd(n), "axis 2 has no spacing (nan)"));
    n.extra = "spacings: 0.5 0.5 2\n";
    BOOST_TEST(decode(nrrd(n)).physical);
}

// Issue 27 item 6: a 32-bit label 70 000 was reported as "not an integer in
// 0..65535"; it is an integer, out of range, and the message says so.
BOOST_AUTO_TEST_CASE(label_70000_is_reported_out_of_range_not_as_a_non_integer) {
    Nrrd n;
    n.type = T::u32, n.sizes = {2, 2, 1};
    n.values = {0, 1, 70000, 1};
    const Volume v = decode(nrrd(n));
    const std::string m = error_of([&] { slice_image(v, std::nullopt); });
    BOOST_TEST(m.find("label 70000, out of range: labels are 0..65535") != std::string::npos, m);
    BOOST_TEST(m.find("not an integer") == std::string::npos, m);
    SliceOptions so;
    so.levelset = label_options("1");
    const std::string l = error_of([&] { load_slice(v, so); });
    BOOST_TEST(l.find("label 70000, out of range") != std::string::npos, l);
    n.type = T::f32, n.values = {0, 1, 2.5, 1};
    BOOST_TEST(error_of([&] { slice_image(decode(nrrd(n)), std::nullopt); }).find("2.5, not an integer") != std::string::npos);
}

BOOST_AUTO_TEST_CASE(nrrd_oblique_unsupported_and_truncated_inputs_are_refused) {
    Nrrd n;
    n.type = T::i16, n.sizes = {4, 4, 2};
    n.values = values_for(T::i16, 32);
    auto with = [&](const std::string& extra) {
        Nrrd m = n;
        m.extra = extra;
        return nrrd(m);
    };
    BOOST_TEST(refused_with(with("space directions: (0.7,0.7,0) (-0.7,0.7,0) (0,0,1)\n"), "oblique"));
    BOOST_TEST(refused_with(with("space directions: (1,0,0) none (0,0,1)\n"), "none"));
    BOOST_TEST(refused_with(with("space directions: (1,0,0) (2,0,0) (0,0,1)\n"), "share a direction"));
    Bytes full = nrrd(n);
    BOOST_TEST(refused_with(Bytes(full.begin(), full.end() - 1), "truncated data"));
    Nrrd g = n;
    g.encoding = "gzip";
    Bytes gz = nrrd(g);
    BOOST_TEST(refused_with(Bytes(gz.begin(), gz.end() - 20), "truncated data"));
    Bytes corrupt = gz;
    for (std::size_t k = corrupt.size() - 30; k < corrupt.size() - 10; ++k) corrupt[k] ^= 0x5a;
    BOOST_TEST(!error_of([&] { decode(corrupt); }).empty());
    // Sizes whose product overflows 64 bits, or only exceeds the limit:
    // refused before anything is allocated.
    BOOST_TEST(refused_with(text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4294967296 4294967296 4294967296\n"
                                 "encoding: raw\n\n"),
                            "exceed the limit"));
    BOOST_TEST(refused_with(text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 100000 100000 1\nencoding: gzip\n\nxx"),
                            "exceed the limit"));
    BOOST_TEST(refused_with(text("NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1000 1000 10\nencoding: gzip\n\nxx"),
                            "cannot hold"));
    BOOST_TEST(refused_with(text("NRRD0004\ntype: uchar\ndimension: 4\nsizes: 1 1 1 1\nencoding: raw\n\nx"), "dimension 4"));
    BOOST_TEST(refused_with(text("NRRD0004\ntype: long long\ndimension: 2\nsizes: 1 1\nencoding: raw\n\nxxxxxxxx"),
                            "unsupported type"));
    BOOST_TEST(refused_with(text("NRRD0004\ntype: uchar\ndimension: 2\nsizes: 1 1\nencoding: bzip2\n\nx"),
                            "unsupported encoding"));
    BOOST_TEST(refused_with(text("NRRD0004\ntype: short\ndimension: 2\nsizes: 1 1\nencoding: raw\n\nxx"), "endian"));
    BOOST_TEST(refused_with(text("NRRD0004\ntype: uchar\ndimension: 2\nsizes: 2 2\nencoding: raw\n"), "no blank line"));
    BOOST_TEST(refused_with(text("NRRD0004\ntype: uchar\ndimension: 2\nsizes: 2 x\nencoding: raw\n\nxxxx"), "size"));
    BOOST_TEST(refused_with(text("NRRD0004\ntype: uchar\nsizes: 2 2\nencoding: raw\n\nxxxx"), "no 'dimension'"));
    BOOST_TEST(refused_with(text("NRRD0009\n"), "magic"));
    BOOST_TEST(refused_with(text("NRRD0004\ntype: float\ndimension: 2\nsizes: 2 1\nencoding: ascii\n\n1 nan"),
                            "malformed ascii"));
    Nrrd f;
    f.type = T::f32, f.sizes = {2, 1, 1}, f.values = {1, NAN};
    BOOST_TEST(refused_with(nrrd(f), "not a finite number"));
}

// --- NIfTI -----------------------------------------------------------------------

// Issue 50: a volume with more data than its header implies was read
// silently (the extra bytes ignored), though the dims or the type must then
// be wrong and the voxels misread.  Raw and ascii NRRD with attached data and
// uncompressed NIfTI are refused, naming the byte counts; gzip was already.
BOOST_AUTO_TEST_CASE(more_data_than_the_header_implies_is_refused) {
    Nrrd n;
    n.type = T::i16, n.sizes = {4, 4, 2};
    n.values = values_for(T::i16, 32);
    Bytes raw = nrrd(n);
    BOOST_TEST(error_of([&] { decode(raw); }).empty());
    raw.push_back(0), raw.push_back(0);
    BOOST_TEST(refused_with(raw, "more than the 64 bytes of voxels"));
    BOOST_TEST(error_of([&] { decode(text("NRRD0001\ntype: float\ndimension: 2\nsizes: 3 2\nencoding: ascii\n\n"
                                           "1 2 3\n4.5 5 6\n \n")); }).empty());
    BOOST_TEST(refused_with(text("NRRD0001\ntype: float\ndimension: 2\nsizes: 3 2\nencoding: ascii\n\n1 2 3\n4.5 5 6 7\n"),
                            "more ascii data than the 6 values"));
    Nifti m;
    m.type = T::u8, m.dim = {3, 2, 2, 2, 1, 1, 1, 1};
    m.values = values_for(T::u8, 8);
    Bytes nii = nifti(m);
    BOOST_TEST(error_of([&] { decode(nii); }).empty());
    nii.push_back(7);
    BOOST_TEST(refused_with(nii, "the header implies (vox_offset, dims and datatype)"));
}

BOOST_AUTO_TEST_CASE(nifti_1_and_2_every_type_byte_order_and_gzip) {
    for (int version : {1, 2})
        for (T t : all_types)
            for (bool big : {false, true})
                for (bool gz : {false, true}) {
                    Nifti n;
                    n.version = version, n.type = t, n.big = big;
                    n.dim = {3, 3, 4, 5, 1, 1, 1, 1};
                    n.pixdim = {1, 0.5, 0.75, 2, 0, 0, 0, 0};
                    n.values = values_for(t, 60);
                    const Bytes b = gz ? gzip(nifti(n)) : nifti(n);
                    const Volume v = decode(b);
                    BOOST_TEST_CONTEXT("NIfTI-" << version << " " << nifti_code(t) << (big ? " big" : "") << (gz ? " gz" : "")) {
                        BOOST_TEST(v.format == (version == 1 ? "NIfTI-1" : "NIfTI-2"));
                        BOOST_TEST((v.dims == std::array<std::int64_t, 3>{3, 4, 5}));
                        BOOST_TEST(same_values(v, n.values));
                        BOOST_TEST((v.spacing == Vec3{0.5, 0.75, 2}));  // pixdim only: identity axes
                        BOOST_TEST((v.axes[0] == Vec3{1, 0, 0}));
                        BOOST_TEST(v.physical);
                    }
                }
}

BOOST_AUTO_TEST_CASE(nifti_scl_slope_and_inter_scale_the_values) {
    Nifti n;
    n.type = T::i16, n.dim = {2, 3, 2, 1, 1, 1, 1, 1};
    n.values = {0, 1, 2, 3, 4, -5};
    n.slope = 0.5, n.inter = 10;
    const Volume v = decode(nifti(n));
    BOOST_TEST(same_values(v, {10, 10.5, 11, 11.5, 12, 7.5}));
    BOOST_TEST(!v.integer_valued);
    n.slope = 0;  // 0 means "no scaling"
    BOOST_TEST(same_values(decode(nifti(n)), n.values));
}

// Issue 27 item 6: a NaN or infinite scl_slope was silently read as no
// scaling.  It still is (as nibabel reads it), with a warning; a valid slope
// beside a non-finite scl_inter is refused.
BOOST_AUTO_TEST_CASE(nifti_scl_slope_nan_or_inf_warns_and_scl_inter_nan_is_refused) {
    Nifti n;
    n.type = T::i16, n.dim = {2, 3, 2, 1, 1, 1, 1, 1};
    n.values = {0, 1, 2, 3, 4, -5};
    for (const double slope : {std::nan(""), HUGE_VAL, -HUGE_VAL})
        for (const int version : {1, 2}) {
            n.version = version, n.slope = slope, n.inter = 3;
            const Volume v = decode(nifti(n));
            BOOST_TEST(same_values(v, n.values));
            BOOST_REQUIRE(v.warnings.size() == 1u);
            BOOST_TEST(v.warnings[0].find("scl_slope is") != std::string::npos);
            BOOST_TEST(v.warnings[0].find("no scaling") != std::string::npos);
        }
    n.version = 1, n.slope = 2;
    n.inter = std::nan("");
    BOOST_TEST(refused_with(nifti(n), "scl_inter is NaN"));
    n.inter = HUGE_VAL;
    BOOST_TEST(refused_with(nifti(n), "scl_inter is infinite"));
    n.slope = 1, n.inter = 0;
    BOOST_TEST(decode(nifti(n)).warnings.empty());
}

// Issue 27 item 3: gzip data is inflated only up to the size the header
// implies; a longer stream is refused.
BOOST_AUTO_TEST_CASE(nifti_gzip_that_inflates_to_more_than_the_header_implies_is_refused) {
    Nifti n;
    n.type = T::u8, n.dim = {2, 3, 2, 1, 1, 1, 1, 1};
    n.values = {0, 1, 2, 3, 4, 5};
    Bytes raw = nifti(n);
    BOOST_TEST(same_values(decode(gzip(raw)), n.values));
    raw.push_back(7);
    BOOST_TEST(refused_with(gzip(raw), "inflates to more than"));
}

BOOST_AUTO_TEST_CASE(nifti_permuted_flipped_sform_is_read_and_sliced_in_place) {
    // The example: sform rows (-2,0,0), (0,0,3), (0,2,0).  Columns:
    // i along -x (2 mm), j along +z (2 mm... row 2 col 1 = 2), k along +y (3 mm).
    Nifti n;
    n.type = T::u8, n.dim = {3, 4, 3, 5, 1, 1, 1, 1};
    n.sform_code = 2;
    n.srow = {{{-2, 0, 0, 90}, {0, 0, 3, -120}, {0, 2, 0, -70}}};
    n.values = values_for(T::u8, 60);
    const Volume v = decode(gzip(nifti(n)));
    BOOST_TEST((v.axes[0] == Vec3{-1, 0, 0}));
    BOOST_TEST((v.axes[1] == Vec3{0, 0, 1}));
    BOOST_TEST((v.axes[2] == Vec3{0, 1, 0}));
    BOOST_TEST((v.spacing == Vec3{2, 2, 3}));
    BOOST_TEST((v.origin == Vec3{90, -120, -70}));
    // Every slice along every axis: the pixel centre (x, y) of in-plane
    // pixel (ia, ib) lies at the voxel's position by the sform, and f there
    // has the sign of the voxel's membership.
    for (int axis = 0; axis < 3; ++axis)
        for (std::int64_t m = 0; m < v.dims[static_cast<std::size_t>(axis)]; ++m) {
            SliceOptions o;
            o.slice = SliceSpec{axis, m};
            o.levelset = label_options("1-150");
            const LoadedSlice s = load_slice(v, o);
            const auto* img = dynamic_cast<const ImageField*>(s.f.get());
            BOOST_REQUIRE(img);
            const PixelGeometry g = img->geometry();
            const int a = axis == 0 ? 1 : 0, b = axis == 2 ? 1 : 2;
            double worst = 0;
            int wrong_sign = 0;
            for (int ib = 0; ib < s.height; ++ib)
                for (int ia = 0; ia < s.width; ++ia) {
                    std::array<std::int64_t, 3> ijk{};
                    ijk[static_cast<std::size_t>(axis)] = m, ijk[static_cast<std::size_t>(a)] = ia,
                                                    ijk[static_cast<std::size_t>(b)] = ib;
                    Vec3 want;  // the sform applied to (i, j, k)
                    for (int r = 0; r < 3; ++r)
                        want[r] = n.srow[r][0] * ijk[0] + n.srow[r][1] * ijk[1] + n.srow[r][2] * ijk[2] + n.srow[r][3];
                    const double x = g.x0 + ia * g.sx, y = g.y0 + ib * g.sy;
                    const Vec3 p = s.plane.point(x, y);
                    for (int r = 0; r < 3; ++r) worst = std::max(worst, std::abs(p[r] - want[r]));
                    const double value = v.at(ijk[0], ijk[1], ijk[2]);
                    wrong_sign += (s.f->value(x, y) < 0) != (value >= 1 && value <= 150);
                }
            BOOST_TEST(worst < 1e-9, "slice " << "ijk"[axis] << "=" << m);
            BOOST_TEST(wrong_sign == 0, "slice " << "ijk"[axis] << "=" << m);
        }
}

BOOST_AUTO_TEST_CASE(nifti_qform_rotation_by_180_degrees_and_qfac) {
    Nifti n;
    n.type = T::u8, n.dim = {3, 2, 2, 2, 1, 1, 1, 1};
    n.values = values_for(T::u8, 8);
    n.qform_code = 1;
    n.quatern = {0, 0, 1};  // 180 degrees about z: R = diag(-1, -1, 1)
    n.qoffset = {5, 6, 7};
    n.pixdim = {-1, 1.5, 2.5, 3, 0, 0, 0, 0};  // qfac = -1 flips k
    const Volume v = decode(nifti(n));
    BOOST_TEST((v.axes[0] == Vec3{-1, 0, 0}));
    BOOST_TEST((v.axes[1] == Vec3{0, -1, 0}));
    BOOST_TEST((v.axes[2] == Vec3{0, 0, -1}));
    BOOST_TEST((v.spacing == Vec3{1.5, 2.5, 3}));
    BOOST_TEST((v.origin == Vec3{5, 6, 7}));
}

BOOST_AUTO_TEST_CASE(nifti_oblique_4d_pairs_and_truncated_files_are_refused) {
    Nifti n;
    n.type = T::u8, n.dim = {3, 2, 2, 2, 1, 1, 1, 1};
    n.values = values_for(T::u8, 8);
    Nifti o = n;
    o.sform_code = 1;
    o.srow = {{{0.9, -0.4, 0, 0}, {0.4, 0.9, 0, 0}, {0, 0, 1, 0}}};
    BOOST_TEST(refused_with(nifti(o), "oblique"));
    BOOST_TEST(refused_with(nifti(o), "sform column 0"));
    Nifti q = n;
    q.qform_code = 1;
    q.quatern = {0, 0, 0.2};  // a rotation about z by about 23 degrees
    BOOST_TEST(refused_with(nifti(q), "oblique"));
    Nifti t = n;
    t.dim = {4, 2, 2, 1, 2, 1, 1, 1};
    BOOST_TEST(refused_with(nifti(t), "dim[4] = 2"));
    Nifti p = n;
    p.magic = std::string("ni1\0", 4);
    BOOST_TEST(refused_with(nifti(p), "pair"));
    Nifti c = n;
    const Bytes good = nifti(c);
    BOOST_TEST(refused_with(Bytes(good.begin(), good.end() - 1), "truncated data"));
    BOOST_TEST(refused_with(Bytes(good.begin(), good.begin() + 200), "truncated header"));
    BOOST_TEST(refused_with(gzip(Bytes(good.begin(), good.end() - 3)), "truncated data"));
    Bytes wrongtype = good;
    wrongtype[70] = 128;  // RGB24
    BOOST_TEST(refused_with(wrongtype, "unsupported datatype 128"));
    Bytes huge = good;
    huge[42] = 0xff, huge[43] = 0x7f, huge[44] = 0xff, huge[45] = 0x7f;  // 32767 x 32767 x 2
    BOOST_TEST(refused_with(huge, "exceed the limit"));
    Bytes negative = good;
    negative[42] = 0xff, negative[43] = 0xff;  // dim[1] = -1
    BOOST_TEST(refused_with(negative, "dim[1]"));
}

// --- TIFF ------------------------------------------------------------------------

BOOST_AUTO_TEST_CASE(tiff_8_and_16_bit_multipage_tiled_and_min_is_white) {
    BOOST_REQUIRE(tiff_supported());
    Dir dir;
    for (int bits : {8, 16})
        for (bool tiled : {false, true})
            for (bool deflate : {false, true}) {
                Tiff t;
                t.width = 19, t.height = 21, t.bits = bits, t.tiled = tiled, t.deflate = deflate;
                for (int p = 0; p < 3; ++p) {
                    std::vector<double> page(static_cast<std::size_t>(t.width * t.height));
                    for (std::size_t k = 0; k < page.size(); ++k) page[k] = static_cast<double>((k * 7 + static_cast<std::size_t>(p) * 13) % (bits == 8 ? 256 : 65536));
                    t.pages.push_back(page);
                }
                const Volume v = decode(tiff_file(t, dir.path / "t.tif"));
                BOOST_TEST_CONTEXT(bits << " bits" << (tiled ? " tiled" : "") << (deflate ? " deflate" : "")) {
                    BOOST_TEST(v.format == "TIFF");
                    BOOST_TEST((v.dims == std::array<std::int64_t, 3>{19, 21, 3}));
                    BOOST_TEST(!v.physical);
                    bool same = true;
                    for (int p = 0; p < 3; ++p)
                        for (int r = 0; r < t.height; ++r)
                            for (int c = 0; c < t.width; ++c)  // j = H - 1 - row
                                same = same && v.at(c, t.height - 1 - r, p) == t.pages[static_cast<std::size_t>(p)][static_cast<std::size_t>(r * t.width + c)];
                    BOOST_TEST(same);
                }
            }
    Tiff w;
    w.pages = {{0, 10, 200, 255}}, w.min_is_white = true;
    BOOST_TEST(same_values(decode(tiff_file(w, dir.path / "w.tif")), {55, 0, 255, 245}));  // rows swapped (j up), inverted
}

BOOST_AUTO_TEST_CASE(tiff_colour_mixed_pages_and_truncated_files_are_refused) {
    Dir dir;
    Tiff rgb;
    rgb.rgb = true, rgb.pages = {{1, 2, 3, 4}};
    BOOST_TEST(refused_with(tiff_file(rgb, dir.path / "rgb.tif"), "not grayscale"));
    // Two pages of different sizes, written page by page.
    TIFF* tif = TIFFOpen((dir.path / "mixed.tif").c_str(), "w");
    for (int size : {4, 5}) {
        TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, size);
        TIFFSetField(tif, TIFFTAG_IMAGELENGTH, size);
        TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 8);
        TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
        TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
        std::vector<std::uint8_t> row(static_cast<std::size_t>(size), 7);
        for (int r = 0; r < size; ++r) TIFFWriteScanline(tif, row.data(), static_cast<std::uint32_t>(r), 0);
        TIFFWriteDirectory(tif);
    }
    TIFFClose(tif);
    std::ifstream in(dir.path / "mixed.tif", std::ios::binary);
    const Bytes mixed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    BOOST_TEST(refused_with(mixed, "unlike page 0"));
    Tiff t;
    t.width = 40, t.height = 40;
    t.pages = {std::vector<double>(1600, 9)};
    const Bytes good = tiff_file(t, dir.path / "g.tif");
    BOOST_TEST(!error_of([&] { decode(Bytes(good.begin(), good.begin() + 900)); }).empty());
    BOOST_TEST(refused_with(Bytes(good.begin(), good.begin() + 6), "TIFF"));
}

// A one-strip 8-bit 4 x 4 grayscale little-endian TIFF with the value of a
// one-valued tag of its first directory replaced (classic TIFF: 12-byte
// entries; SHORT values in the first two bytes of the value field).
Bytes tiff_with_tag(const fs::path& path, std::uint16_t tag, std::uint32_t value) {
    TIFF* tif = TIFFOpen(path.c_str(), "w");
    TIFFSetField(tif, TIFFTAG_IMAGEWIDTH, 4);
    TIFFSetField(tif, TIFFTAG_IMAGELENGTH, 4);
    TIFFSetField(tif, TIFFTAG_BITSPERSAMPLE, 8);
    TIFFSetField(tif, TIFFTAG_SAMPLESPERPIXEL, 1);
    TIFFSetField(tif, TIFFTAG_ROWSPERSTRIP, 4);
    TIFFSetField(tif, TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK);
    std::vector<std::uint8_t> row(4, 9);
    for (std::uint32_t r = 0; r < 4; ++r) TIFFWriteScanline(tif, row.data(), r, 0);
    TIFFClose(tif);
    std::ifstream in(path, std::ios::binary);
    Bytes b((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    BOOST_REQUIRE(b.size() > 8 && b[0] == 'I');
    auto u16 = [&](std::size_t at) { return static_cast<std::uint32_t>(b[at] | b[at + 1] << 8); };
    const std::size_t ifd = u16(4) | u16(6) << 16;
    for (std::size_t e = 0; e < u16(ifd); ++e) {
        const std::size_t at = ifd + 2 + 12 * e;
        if (u16(at) != tag) continue;
        BOOST_REQUIRE(u16(at + 4) == 1u);  // one value
        for (int q = 0; q < (u16(at + 2) == 3 ? 2 : 4); ++q) b[at + 8 + static_cast<std::size_t>(q)] = static_cast<std::uint8_t>(value >> (8 * q));
        return b;
    }
    BOOST_FAIL("tag not found");
    return b;
}

// Issue 27 item 6: a palette image without a colour map was read as gray
// (libtiff repairs the tag with a warning); a strip byte count beyond the
// end of the file was accepted.  Both are refused, naming the problem.
BOOST_AUTO_TEST_CASE(tiff_palette_without_colour_map_and_strip_beyond_the_file_are_refused) {
    Dir dir;
    BOOST_TEST(same_values(decode(tiff_with_tag(dir.path / "ok.tif", TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_MINISBLACK)),
                           std::vector<double>(16, 9)));
    BOOST_TEST(refused_with(tiff_with_tag(dir.path / "p.tif", TIFFTAG_PHOTOMETRIC, PHOTOMETRIC_PALETTE),
                            "palette image without a colour map"));
    BOOST_TEST(refused_with(tiff_with_tag(dir.path / "s.tif", TIFFTAG_STRIPBYTECOUNTS, 1000000), "strip"));
}

// --- geometry of image level sets and slices ------------------------------------------------

// A label image with an ellipse of label 3 and a smaller disc of label 5.
Volume ellipse_volume(int w, int h, Vec3 spacing) {
    Volume v;
    v.dims = {w, h, 1};
    v.values.resize(static_cast<std::size_t>(w * h));
    for (int j = 0; j < h; ++j)
        for (int i = 0; i < w; ++i) {
            const double x = (i - w / 2.0) / (w / 3.0), y = (j - h / 2.0) / (h / 3.0);
            const double dx = i - w * 0.6, dy = j - h * 0.55;
            v.values[static_cast<std::size_t>(i + w * j)] = dx * dx + dy * dy < 16 ? 5 : x * x + y * y < 1 ? 3 : 0;
        }
    v.spacing = spacing;
    v.origin = {12.5, -40, 3};
    v.physical = true;
    v.format = "NRRD";
    v.source = "ellipse";
    return v;
}

BOOST_AUTO_TEST_CASE(anisotropic_slice_is_meshed_in_millimetres) {
    // 0.9375 x 1.5 mm pixels, as in the SPL abdominal atlas's (i, k) slices.
    const Volume v = ellipse_volume(90, 60, {0.9375, 1.5, 2});
    std::int64_t inside = 0;
    for (double x : v.values) inside += x != 0;
    SliceOptions o;
    o.slice = SliceSpec{2, 0};
    o.levelset = label_options("nonzero");
    const LoadedSlice s = load_slice(v, o);
    BOOST_TEST(s.physical);
    BOOST_TEST(s.pixel_min == 0.9375);
    const Box b = s.f->bounds();
    BOOST_TEST(b.xmin == 12.5);
    BOOST_TEST(b.ymin == -40);
    BOOST_TEST(b.xmax == 12.5 + 89 * 0.9375);
    BOOST_TEST(b.ymax == -40 + 59 * 1.5);
    for (const double spacing : {0.9375, 0.5}) {
        const Lattice lattice = lattice_over(b, spacing);
        const UniformResult r = mesh_uniform(*s.f, lattice, DiagonalRule::separating);
        const QualityReport q = compute_quality(r.mesh);
        // The boundary passes midway between inside and outside pixels: the
        // area is the pixels' (in mm^2) up to the corners the mesh cuts.
        const double pixels = static_cast<double>(inside) * 0.9375 * 1.5;
        BOOST_TEST_CONTEXT("spacing " << spacing) {
            BOOST_TEST(std::abs(q.area - pixels) < 0.03 * pixels, "area " << q.area << " mm^2, pixels " << pixels);
            BOOST_TEST(q.nonpositive_triangles == 0);
            BOOST_TEST(q.triangles_by_region.count(3) == 1);
            BOOST_TEST(q.triangles_by_region.count(5) == 1);
        }
        // Graded: the range bounds and region cells in millimetres change
        // nothing (same mesh as with every tile sampled).
        const GradedResult g = mesh_graded(*s.f, lattice, DiagonalRule::separating, 0);
        const GradedResult ref = mesh_graded(WithoutRange(*s.f), lattice, DiagonalRule::separating, 0);
        BOOST_TEST(same_mesh(g.mesh, ref.mesh));
        BOOST_TEST(std::abs(compute_quality(g.mesh).area - q.area) < 1e-6 * q.area);
    }
    // Pixel units: the same slice, x = i, y = j; the area in pixels.
    o.units = Units::pixels;
    const LoadedSlice p = load_slice(v, o);
    const UniformResult r = mesh_uniform(*p.f, lattice_over(p.f->bounds(), 1.0), DiagonalRule::separating);
    const double px_area = compute_quality(r.mesh).area;
    BOOST_TEST(std::abs(px_area - static_cast<double>(inside)) < 0.03 * static_cast<double>(inside));
}

BOOST_AUTO_TEST_CASE(pixel_units_reproduce_the_image_level_set_bit_for_bit) {
    // A PGM read as a one-slice volume gives the very mesh the image path gives.
    std::string pgm = "P2\n23 17\n255\n";
    std::mt19937 rng(7);
    for (int k = 0; k < 23 * 17; ++k) pgm += std::to_string(rng() % 4 == 0 ? 200 : rng() % 60) + " ";
    const Bytes bytes = text(pgm);
    const Image img = decode_image(bytes, "p.pgm");
    const Volume v = decode(bytes, "p.pgm");
    for (const bool label : {false, true}) {
        ImageLevelSetOptions io;
        if (label) io = label_options("200");
        else io.iso = 100;
        const auto f = make_image_levelset(img, io);
        SliceOptions so;
        so.levelset = io;
        const LoadedSlice s = load_slice(v, so);
        BOOST_TEST(!s.placed);
        BOOST_TEST(s.f->describe() == f->describe());
        for (const double spacing : {1.0, 0.37, 2.5}) {
            const Lattice l = lattice_over(f->bounds(), spacing);
            BOOST_TEST(same_mesh(mesh_uniform(*f, l, DiagonalRule::separating).mesh,
                                 mesh_uniform(*s.f, l, DiagonalRule::separating).mesh));
            BOOST_TEST(same_mesh(mesh_graded(*f, l, DiagonalRule::maxmin, 0).mesh, mesh_graded(*s.f, l, DiagonalRule::maxmin, 0).mesh));
        }
    }
}

BOOST_AUTO_TEST_CASE(slice_choice_and_label_values_are_checked) {
    Nrrd n;
    n.type = T::f32, n.sizes = {3, 3, 2}, n.values = values_for(T::f32, 18);
    const Volume v = decode(nrrd(n));
    SliceOptions o;
    BOOST_TEST(error_of([&] { load_slice(v, o); }).find("--slice k=INDEX") != std::string::npos);
    o.slice = SliceSpec{2, 2};
    BOOST_TEST(error_of([&] { load_slice(v, o); }).find("k = 0..1") != std::string::npos);
    o.slice = SliceSpec{0, 1};
    o.levelset = label_options("1");
    BOOST_TEST(error_of([&] { load_slice(v, o); }).find("label mode needs integer values") != std::string::npos);
    o.levelset = ImageLevelSetOptions{};  // threshold: float values are fine
    BOOST_TEST(load_slice(v, o).f->tags_regions() == false);
    BOOST_TEST((parse_slice("j=12").axis == 1 && parse_slice("j=12").index == 12));
    const SliceRange r = parse_slice_range("k=0:113");
    BOOST_TEST((r.axis == 2 && r.first == 0 && r.end == 113));
    for (const char* bad : {"z=1", "k", "k=", "k=-1", "k=1x", "k=5:5", "k=7:3", "k=1:2:3"})
        BOOST_TEST(!error_of([&] { parse_slice_range(bad); }).empty(), bad);
    BOOST_TEST(slice_file_name("out_%03d.vtu", 7) == "out_007.vtu");
    BOOST_TEST(slice_file_name("a%%_%d.msh", 12) == "a%_12.msh");
    BOOST_TEST(slice_file_name("s%4d", 3) == "s   3");
    for (const char* bad : {"out.vtu", "out_%s.vtu", "%d_%d.vtu", "%", "%03x", "%.3d"})
        BOOST_TEST(error_of([&] { slice_file_name(bad, 1); }).find("bad output pattern") != std::string::npos, bad);
}

// --- the command line ----------------------------------------------------------------------

namespace {
struct Run {
    int code;
    std::string out, err;
};
Run run(const std::string& args, const fs::path& dir) {
    const std::string cmd = "cd '" + dir.string() + "' && '" WARPMESH_EXE "' " + args + " >'" + (dir / "stdout.txt").string() +
                            "' 2>'" + (dir / "stderr.txt").string() + "'";
    const int status = std::system(cmd.c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(dir / "stdout.txt"), slurp(dir / "stderr.txt")};
}
}  // namespace

// mesh_slices (slices.hpp): a slice that cannot be meshed for a reason of
// its own is skipped and listed, an error of another kind (here an
// OutputError thrown by the caller's writer) is not swallowed, and a range
// beyond the volume is refused before anything is meshed.
BOOST_AUTO_TEST_CASE(mesh_slices_skips_empty_slices_and_rethrows_other_errors) {
    Volume v;
    v.dims = {30, 20, 3};
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 20; ++j)
            for (int i = 0; i < 30; ++i) v.values.push_back(k != 1 && (i - 15) * (i - 15) + (j - 10) * (j - 10) < 40 ? 7 : 0);
    v.source = "mem", v.format = "NRRD";
    SliceOptions so;
    so.levelset.mode = ImageMode::label;
    so.levelset.labels = std::vector<int>{7};
    const auto mesh_one = [](const LoadedSlice& s) {
        MeshOptions m;
        return SliceMeshed{mesh(*s.f, m).report.quality, "slice " + std::to_string(s.slice.index)};
    };
    const SliceBatch b = mesh_slices(v, SliceRange{2, 0, 3}, so, mesh_one);
    BOOST_TEST_REQUIRE(b.slices.size() == 3u);
    BOOST_TEST(b.meshed() == 2);
    BOOST_TEST(!b.slices[1].report.has_value());
    BOOST_TEST(!b.slices[1].skipped.empty());
    BOOST_TEST(b.slices[2].outputs == "slice 2");
    BOOST_TEST(b.triangles() == b.slices[0].report->triangles + b.slices[2].report->triangles);
    BOOST_TEST(to_json(b).find("\"meshed\": 2, \"skipped\": 1") != std::string::npos, to_json(b));
    BOOST_TEST(to_text(b).find("2 of 3 slices meshed") != std::string::npos);

    BOOST_CHECK_THROW(mesh_slices(v, SliceRange{2, 0, 3}, so,
                                  [](const LoadedSlice&) -> SliceMeshed { throw OutputError("disk full"); }),
                      OutputError);
    BOOST_TEST(error_of([&] { mesh_slices(v, SliceRange{2, 1, 4}, so, mesh_one); }).find("reaches beyond") !=
               std::string::npos);
    BOOST_TEST(error_of([&] { mesh_slices(v, SliceRange{2, 1, 2}, so, mesh_one); }).find("no slice could be meshed") !=
               std::string::npos);
}

BOOST_AUTO_TEST_CASE(cli_slice_slices_units_and_points_3d) {
    Dir dir;
    // 3 slices of 30 x 20 voxels, 0.5 x 1.5 x 2 mm; slice 1 is empty.
    Nrrd n;
    n.type = T::i16, n.sizes = {30, 20, 3}, n.encoding = "gzip";
    n.extra = "space directions: (0.5,0,0) (0,1.5,0) (0,0,2)\nspace origin: (1,2,3)\n";
    for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 20; ++j)
            for (int i = 0; i < 30; ++i)
                n.values.push_back(k != 1 && (i - 15) * (i - 15) + (j - 10) * (j - 10) < 40 ? 7 : 0);
    dir.write("v.nrrd", nrrd(n));

    Run r = run("mesh v.nrrd --slice k=2 --label 7 -o one.vtu --points-3d one.csv --report one.json", dir.path);
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    const std::string report = slurp(dir.path / "one.json");
    BOOST_TEST(report.find("\"units\": \"mm\"") != std::string::npos, report);
    BOOST_TEST(report.find("\"axis\": \"k\", \"index\": 2") != std::string::npos);
    BOOST_TEST(report.find("\"origin\": [0, 0, 7]") != std::string::npos, report);  // 3 + 2 * 2 mm
    BOOST_TEST(report.find("\"spacing\": 0.5") != std::string::npos);  // default: the smaller pixel size
    const std::string csv = slurp(dir.path / "one.csv");
    BOOST_TEST(csv.rfind("x,y,z\n", 0) == 0);
    BOOST_TEST(csv.find(",7\n") != std::string::npos);  // every point at z = 7 mm

    r = run("mesh v.nrrd --slice k=0 --label 7 --units pixels -o px.vtu --report px.json --quiet", dir.path);
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    BOOST_TEST(slurp(dir.path / "px.json").find("\"units\": \"pixels\"") != std::string::npos);

    // --slices: one file per slice, the empty one skipped, one summary.
    r = run("mesh v.nrrd --slices k=0:3 --label 7 -o 'out_%03d.vtu' --also 'pic_%d.svg' --report sum.json", dir.path);
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    BOOST_TEST(fs::exists(dir.path / "out_000.vtu"));
    BOOST_TEST(!fs::exists(dir.path / "out_001.vtu"));
    BOOST_TEST(fs::exists(dir.path / "out_002.vtu"));
    BOOST_TEST(fs::exists(dir.path / "pic_2.svg"));
    const std::string sum = slurp(dir.path / "sum.json");
    BOOST_TEST(sum.find("\"meshed\": 2, \"skipped\": 1") != std::string::npos, sum);
    BOOST_TEST(sum.find("none of the labels {7} is present") != std::string::npos);
    BOOST_TEST(r.out.find("2 of 3 slices meshed") != std::string::npos, r.out);

    // Refusals: nothing written.
    const auto before = std::distance(fs::directory_iterator(dir.path), fs::directory_iterator());
    const struct {
        const char* args;
        int code;
        const char* message;
    } refusals[] = {
        {"v.nrrd --slices k=0:3 --label 7 -o bad.vtu", 2, "bad output pattern 'bad.vtu'"},
        {"v.nrrd --slices k=0:3 --label 7 -o 'x_%s.vtu'", 2, "bad output pattern"},
        {"v.nrrd --slices k=1:4 --label 7 -o 'o%d.vtu'", 1, "reaches beyond"},
        {"v.nrrd --slices k=1:2 --label 7 -o 'o%d.vtu'", 1, "no slice could be meshed"},
        {"v.nrrd --label 7 -o o.vtu", 1, "choose a slice with --slice"},
        {"v.nrrd --slice q=1 --label 7 -o o.vtu", 1, "AXIS i, j or k"},
        {"v.nrrd --slice k=1 --slices k=0:2 --label 7 -o o.vtu", 2, "exclude each other"},
        {"--shape circle:0,0,3 --slice k=1 -o o.vtu", 2, "not to --shape"},
    };
    for (const auto& t : refusals) {
        r = run(std::string("mesh ") + t.args, dir.path);
        BOOST_TEST(r.code == t.code, t.args);
        BOOST_TEST(r.err.find(t.message) != std::string::npos, t.args << ": " << r.err);
    }
    BOOST_TEST(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()) == before);
}

BOOST_AUTO_TEST_CASE(cli_pixel_size_puts_an_image_in_millimetres) {
    Dir dir;
    std::string pgm = "P2\n8 6\n255\n";
    for (int r = 0; r < 6; ++r)
        for (int c = 0; c < 8; ++c) pgm += (r >= 1 && r <= 4 && c >= 2 && c <= 5) ? "255 " : "0 ";
    dir.write("i.pgm", text(pgm));
    Run r = run("mesh i.pgm --iso 128 -o a.vtu --report a.json --quiet", dir.path);
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    r = run("mesh i.pgm --iso 128 --pixel-size 0.5,2 -o b.vtu --report b.json --quiet", dir.path);
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    auto area = [&](const char* f) {
        const std::string j = slurp(dir.path / f);
        const auto p = j.find("\"area\": ");
        return std::stod(j.substr(p + 8));
    };
    BOOST_TEST(std::abs(area("b.json") - area("a.json")) > 0);
    BOOST_TEST(slurp(dir.path / "a.json").find("\"units\"") == std::string::npos);  // plain images: report unchanged
    BOOST_TEST(slurp(dir.path / "b.json").find("\"units\": \"mm\"") != std::string::npos);
    // Threshold regions scale with the pixel area at the pixel-size spacing.
    r = run("mesh i.pgm --iso 128 --pixel-size 0.5,2 --spacing 0.5 -o c.vtu --report c.json --quiet", dir.path);
    BOOST_TEST_REQUIRE(r.code == 0, r.err);
    BOOST_TEST(area("c.json") > 0);
    r = run("mesh i.pgm --iso 128 --pixel-size 0,1 -o d.vtu", dir.path);
    BOOST_TEST(r.code == 1);
    BOOST_TEST(r.err.find("pixel-size") != std::string::npos, r.err);
}

// --- the fuzzers' seeds and regressions -------------------------------------------------------

BOOST_AUTO_TEST_CASE(fuzz_volume_seeds_and_regressions) {
    const fs::path root = fs::path(WARPMESH_SOURCE_DIR) / "tests" / "fuzz";
    const std::pair<const char*, void (*)(std::span<const std::uint8_t>)> targets[] = {
        {"nrrd_reader", fuzz::check_nrrd_reader}, {"nifti_reader", fuzz::check_nifti_reader}, {"tiff_reader", fuzz::check_tiff_reader}};
    for (const auto& [name, check] : targets) {
        int files = 0;
        for (const char* sub : {"corpus/", "regressions/"}) {
            const fs::path d = root / (std::string(sub) + name);
            if (!fs::is_directory(d)) continue;
            for (const auto& e : fs::directory_iterator(d)) {
                const std::string s = slurp(e.path());
                check(std::span<const std::uint8_t>(reinterpret_cast<const std::uint8_t*>(s.data()), s.size()));
                ++files;
            }
        }
        BOOST_TEST(files > 0, name);
    }
}

// Writes the seed corpus of the volume fuzzers (run by hand:
// WARPMESH_WRITE_SEEDS=tests/fuzz/corpus build/tests/test_volume_io -t write_seeds).
BOOST_AUTO_TEST_CASE(write_seeds) {
    const char* out = std::getenv("WARPMESH_WRITE_SEEDS");
    if (!out) return;
    auto save = [&](const std::string& sub, const std::string& name, const Bytes& b) {
        fs::create_directories(fs::path(out) / sub);
        std::ofstream f(fs::path(out) / sub / name, std::ios::binary);
        f.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    };
    for (T t : {T::u8, T::i16, T::f32}) {
        Nrrd n;
        n.type = t, n.sizes = {4, 3, 2}, n.values = values_for(t, 24);
        n.extra = "space directions: (0,1.5,0) (0,0,-2) (0.5,0,0)\nspace origin: (-10,20,30.5)\n";
        save("nrrd_reader", std::string("raw_") + nrrd_type(t), nrrd(n));
        n.encoding = "gzip", n.big = true;
        save("nrrd_reader", std::string("gzip_") + nrrd_type(t), nrrd(n));
        Nifti m;
        m.type = t, m.dim = {3, 4, 3, 2, 1, 1, 1, 1}, m.values = values_for(t, 24);
        m.sform_code = 1;
        m.srow = {{{-2, 0, 0, 90}, {0, 0, 3, -120}, {0, 2, 0, -70}}};
        m.slope = 2;
        save("nifti_reader", std::string("n1_") + std::to_string(nifti_code(t)), nifti(m));
        m.version = 2, m.big = true, m.sform_code = 0, m.qform_code = 1, m.quatern = {0, 0, 1};
        save("nifti_reader", std::string("n2_") + std::to_string(nifti_code(t)), nifti(m));
        save("nifti_reader", std::string("n2gz_") + std::to_string(nifti_code(t)), gzip(nifti(m)));
    }
    Dir dir;
    Tiff t;
    t.width = 5, t.height = 4, t.pages = {std::vector<double>(20, 3), std::vector<double>(20, 200)};
    save("tiff_reader", "two_pages_8bit", tiff_file(t, dir.path / "a.tif"));
    t.bits = 16, t.deflate = true, t.pages = {std::vector<double>(20, 3000)};
    save("tiff_reader", "deflate_16bit", tiff_file(t, dir.path / "b.tif"));
    t.tiled = true, t.width = 20, t.height = 18, t.pages = {std::vector<double>(360, 70)};
    save("tiff_reader", "tiled_16bit", tiff_file(t, dir.path / "c.tif"));
}
