// volume_io.cpp — read_volume: recognise the format by its content and hand
// the bytes to its reader (nrrd.cpp, nifti.cpp, tiff.cpp; PGM and PNG through
// image_io.cpp as one slice); gzip inflation shared by the NRRD and NIfTI
// readers.
#include <zlib.h>

#include <array>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>

#include "volume_detail.hpp"
#include "warpmesh/io/image.hpp"

namespace warpmesh {
namespace {

bool starts_with(std::span<const std::uint8_t> b, std::string_view magic) {
    return b.size() >= magic.size() && std::memcmp(b.data(), magic.data(), magic.size()) == 0;
}

// The first four bytes as a 32-bit integer in either byte order.
bool first_int_is(std::span<const std::uint8_t> b, std::uint32_t v) {
    if (b.size() < 4) return false;
    const std::uint32_t le = b[0] | b[1] << 8 | b[2] << 16 | std::uint32_t{b[3]} << 24;
    const std::uint32_t be = b[3] | b[2] << 8 | b[1] << 16 | std::uint32_t{b[0]} << 24;
    return le == v || be == v;
}

// A PGM or PNG image as a one-slice volume: i = column, j = H - 1 - row.
Volume image_volume(const Image& img, const char* format) {
    Volume v;
    v.dims = {img.width, img.height, 1};
    v.values.resize(img.pixels.size());
    const std::size_t W = static_cast<std::size_t>(img.width);
    for (int r = 0; r < img.height; ++r)
        for (int c = 0; c < img.width; ++c)
            v.values[static_cast<std::size_t>(img.height - 1 - r) * W + static_cast<std::size_t>(c)] = img.at(c, r);
    v.format = format;
    v.source = img.source;
    v.maxval = img.maxval;
    return v;
}

}  // namespace

namespace volume_detail {

std::string memory_limit_text(std::uint64_t max_bytes) {
    return "the --max-memory limit of " + std::to_string(max_bytes >> 20) + " MB";
}

std::vector<std::uint8_t> read_regular_file(const std::string& prefix, const std::string& path,
                                            std::uint64_t max_bytes, const std::string& limit) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::file_status st = fs::status(path, ec);
    if (ec && st.type() != fs::file_type::not_found)
        throw InputError(prefix + ": cannot read: " + ec.message());
    if (st.type() == fs::file_type::directory) throw InputError(prefix + ": cannot read: is a directory");
    if (st.type() != fs::file_type::regular && st.type() != fs::file_type::not_found) {
        const char* kind = st.type() == fs::file_type::character || st.type() == fs::file_type::block ? "a device"
                           : st.type() == fs::file_type::fifo                                         ? "a FIFO (pipe)"
                           : st.type() == fs::file_type::socket                                       ? "a socket"
                                                                                                      : "not a regular file";
        throw InputError(prefix + ": cannot read: is " + kind + ", not a regular file (it may never end; copy the data "
                                  "into a file)");
    }
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(prefix + ": cannot open: " + std::strerror(errno));
    const std::uint64_t size = fs::file_size(path, ec);
    if (!ec && size > max_bytes)
        throw InputError(prefix + ": the file has " + std::to_string(size) + " bytes, more than " + limit);
    std::vector<std::uint8_t> bytes;
    bytes.reserve(static_cast<std::size_t>(ec ? 0 : size));
    std::array<char, 1 << 16> buf;
    while (in && bytes.size() <= max_bytes) {
        in.read(buf.data(), static_cast<std::streamsize>(std::min<std::uint64_t>(buf.size(), max_bytes + 1 - bytes.size())));
        bytes.insert(bytes.end(), buf.data(), buf.data() + in.gcount());
    }
    if (in.bad()) throw InputError(prefix + ": read error");
    if (bytes.size() > max_bytes)
        throw InputError(prefix + ": the file has more than " + std::to_string(max_bytes) + " bytes, more than " + limit);
    return bytes;
}

}  // namespace volume_detail

namespace {

// A gzip/zlib stream (several gzip members, one after the other, are one
// stream), inflated into the caller's buffers piece by piece.
class Inflater {
public:
    Inflater(std::span<const std::uint8_t> in, const std::string& name) : in_(in), name_(name) {
        if (inflateInit2(&zs_, 15 + 32) != Z_OK) throw InputError("'" + name + "': cannot initialise zlib");
    }
    ~Inflater() { inflateEnd(&zs_); }
    Inflater(const Inflater&) = delete;
    Inflater& operator=(const Inflater&) = delete;
    // Up to `want` bytes into out; fewer only where the stream ends.
    std::size_t read(std::uint8_t* out, std::size_t want) {
        std::size_t got = 0;
        while (got < want && !done_) {
            if (zs_.avail_in == 0) {
                if (pos_ >= in_.size()) break;  // input ends: the caller sees a short result
                const std::size_t chunk = std::min<std::size_t>(in_.size() - pos_, 1u << 30);
                zs_.next_in = const_cast<Bytef*>(in_.data() + pos_);
                zs_.avail_in = static_cast<uInt>(chunk);
                pos_ += chunk;
            }
            const std::size_t step = std::min<std::size_t>(want - got, 1u << 30);
            zs_.next_out = out + got;
            zs_.avail_out = static_cast<uInt>(step);
            const int rc = inflate(&zs_, Z_NO_FLUSH);
            got += step - zs_.avail_out;
            if (rc == Z_STREAM_END) {
                if ((zs_.avail_in == 0 && pos_ >= in_.size()) || inflateReset(&zs_) != Z_OK) done_ = true;
                continue;
            }
            if (rc == Z_BUF_ERROR && zs_.avail_in == 0 && pos_ >= in_.size()) break;
            if (rc != Z_OK && rc != Z_BUF_ERROR)
                throw InputError("'" + name_ + "': corrupt gzip data (" + (zs_.msg ? zs_.msg : "zlib error " + std::to_string(rc)) + ")");
        }
        return got;
    }

private:
    z_stream zs_{};
    std::span<const std::uint8_t> in_;
    std::size_t pos_ = 0;
    bool done_ = false;
    const std::string& name_;
};

}  // namespace

std::vector<std::uint8_t> gunzip(std::span<const std::uint8_t> in, std::size_t max_out, const std::string& name) {
    std::vector<std::uint8_t> out;
    Inflater z(in, name);
    // Grow the output as data arrives (never beyond max_out): a small corrupt
    // stream cannot make us allocate what its header merely claims.
    while (out.size() < max_out) {
        const std::size_t have = out.size();
        const std::size_t want = std::min<std::size_t>({max_out - have, std::max<std::size_t>(have, 1u << 16), 1u << 30});
        out.resize(have + want);
        const std::size_t got = z.read(out.data() + have, want);
        out.resize(have + got);
        if (got < want) break;
    }
    return out;
}

std::vector<std::uint8_t> gunzip_exact(std::span<const std::uint8_t> in, std::size_t expected, const std::string& name) {
    std::vector<std::uint8_t> out = gunzip(in, expected + 1, name);  // one byte more tells a longer stream
    if (out.size() > expected)
        throw InputError("'" + name + "': the gzip data inflates to more than the " + std::to_string(expected) +
                         " bytes the header implies");
    return out;
}

std::size_t gunzip_exact_into(std::span<const std::uint8_t> in, std::span<std::uint8_t> out, const std::string& name) {
    Inflater z(in, name);
    const std::size_t got = z.read(out.data(), out.size());
    std::uint8_t more = 0;
    if (got == out.size() && z.read(&more, 1) > 0)
        throw InputError("'" + name + "': the gzip data inflates to more than the " + std::to_string(out.size()) +
                         " bytes the header implies");
    return got;
}

void samples_to_values(Volume& v) {
    if (v.labels.empty()) return;
    v.values.assign(v.labels.begin(), v.labels.end());
    Buffer<std::uint16_t>().swap(v.labels);
}

std::optional<Vec3> axis_aligned(const Vec3& d) {
    const double n = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(n > 0) || !std::isfinite(n)) return std::nullopt;
    int p = 0;
    for (int q = 1; q < 3; ++q)
        if (std::abs(d[q]) > std::abs(d[p])) p = q;
    Vec3 e{0, 0, 0};
    for (int q = 0; q < 3; ++q)
        if (q != p && std::abs(d[q]) > 1e-6 * n) return std::nullopt;
    e[p] = d[p] > 0 ? 1 : -1;
    return e;
}

Volume decode_volume(std::span<const std::uint8_t> bytes, const std::string& name, const VolumeLimits& limits,
                     const std::string& dir) {
    if (starts_with(bytes, "NRRD000")) return decode_nrrd(bytes, name, limits, dir);
    if (first_int_is(bytes, 348) || first_int_is(bytes, 540) || starts_with(bytes, "\x1f\x8b"))
        return decode_nifti(bytes, name, limits);
    if (starts_with(bytes, "II*") || starts_with(bytes, std::string_view("MM\0*", 4)) ||
        starts_with(bytes, std::string_view("II+\0", 4)) || starts_with(bytes, std::string_view("MM\0+", 4)))
        return decode_tiff(bytes, name, limits);
    // Everything else is an image (or refused by the image reader, whose
    // messages name what the bytes look like).
    try {
        const Image img = decode_image(bytes, name, limits.max_voxels, limits.max_bytes);  // not empty once decoded
        const std::uint64_t dims[2] = {static_cast<std::uint64_t>(img.width), static_cast<std::uint64_t>(img.height)};
        volume_detail::checked_voxels(bytes[0] == 'P' ? "PGM" : "PNG", name, dims, sizeof(std::uint16_t), limits,
                                      bytes.size());  // the image's samples beside their doubles
        return image_volume(img, bytes[0] == 'P' ? "PGM" : "PNG");
    } catch (const InputError& e) {
        const std::string m = e.what();
        if (m.find("unsupported format") == std::string::npos) throw;
        throw InputError(m + ", or a volume: NRRD (.nrrd, .nhdr), NIfTI (.nii, .nii.gz) or TIFF");
    }
}

Volume read_volume(const std::string& path, const VolumeLimits& limits) {
    const std::vector<std::uint8_t> bytes =
        volume_detail::read_regular_file("'" + path + "'", path, limits.max_bytes, volume_detail::memory_limit_text(limits.max_bytes));
    const std::string dir = std::filesystem::path(path).parent_path().string();
    return decode_volume(bytes, path, limits, dir.empty() ? "." : dir);
}

}  // namespace warpmesh
