// nifti.cpp — NIfTI-1 and NIfTI-2 single-file volumes (.nii, .nii.gz), either
// byte order (https://nifti.nimh.nih.gov/nifti-1, nifti2.h).
//
// Read: 2-D and 3-D data (dim[4..7] must be 1) of datatypes uint8, int8,
// int16, uint16, int32, uint32, float32, float64, from vox_offset on;
// scl_slope / scl_inter (value = slope * stored + inter when slope is
// non-zero and finite); the geometry from the sform when sform_code > 0, else
// the qform (quaternion, qfac = pixdim[0]) when qform_code > 0, else pixdim
// alone (origin 0, identity axes).  The affine's columns give each index
// axis's spacing and direction; directions must be axis-aligned (permuted or
// flipped is fine).  Refused with a message: oblique or sheared affines,
// NIfTI pairs (.hdr/.img, magic ni1/ni2), other datatypes (RGB, complex,
// 64-bit integers), more than 3 dimensions, data beyond the end of the file.
#include <cmath>
#include <cstring>

#include "volume_detail.hpp"

namespace warpmesh {
namespace {

using namespace volume_detail;

// Little or big-endian fields of a header in memory.
struct Fields {
    std::span<const std::uint8_t> h;
    bool swap;
    template <class T>
    T get(std::size_t off) const {
        std::uint8_t b[sizeof(T)];
        for (std::size_t q = 0; q < sizeof(T); ++q) b[q] = swap ? h[off + sizeof(T) - 1 - q] : h[off + q];
        T v;
        std::memcpy(&v, b, sizeof(T));
        return v;
    }
};

bool datatype(int code, Sample* s) {
    switch (code) {
        case 2: *s = Sample::u8; return true;
        case 4: *s = Sample::i16; return true;
        case 8: *s = Sample::i32; return true;
        case 16: *s = Sample::f32; return true;
        case 64: *s = Sample::f64; return true;
        case 256: *s = Sample::i8; return true;
        case 512: *s = Sample::u16; return true;
        case 768: *s = Sample::u32; return true;
        default: return false;
    }
}

std::string vec_text(const Vec3& v) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "(%.6g, %.6g, %.6g)", v[0], v[1], v[2]);
    return buf;
}

}  // namespace

Volume decode_nifti(std::span<const std::uint8_t> bytes, const std::string& name, const VolumeLimits& limits) {
    auto bad = [&](const std::string& what) { fail("NIfTI", name, what); };
    const bool gz = bytes.size() >= 2 && bytes[0] == 0x1f && bytes[1] == 0x8b;
    std::vector<std::uint8_t> inflated;
    std::span<const std::uint8_t> file = bytes;
    if (gz) {  // the header first, to learn how much to inflate
        inflated = gunzip(bytes, 544, name);
        file = inflated;
    }
    if (file.size() < 4) bad("truncated header: " + std::to_string(file.size()) + " bytes");
    std::uint32_t size_le = 0;
    std::memcpy(&size_le, file.data(), 4);
    if (!host_is_little_endian()) size_le = __builtin_bswap32(size_le);
    const std::uint32_t size_be = __builtin_bswap32(size_le);
    const bool v2 = size_le == 540 || size_be == 540;
    if (!v2 && size_le != 348 && size_be != 348)
        bad(gz ? "gzip data that is not NIfTI (sizeof_hdr is neither 348 nor 540)" : "sizeof_hdr is neither 348 nor 540");
    const bool little = (size_le == 348 || size_le == 540);
    const Fields f{file, little != host_is_little_endian()};
    const std::size_t hdr = v2 ? 540 : 348;
    if (file.size() < hdr) bad("truncated header: " + std::to_string(file.size()) + " of " + std::to_string(hdr) + " bytes");
    const std::string magic(reinterpret_cast<const char*>(file.data() + (v2 ? 4 : 344)), 3);
    if (magic == "ni1" || magic == "ni2") bad("a NIfTI pair (.hdr + .img) is not read; convert it to a single .nii");
    if (magic != (v2 ? "n+2" : "n+1")) bad("bad magic '" + magic + "' (expected " + (v2 ? "n+2" : "n+1") + ")");

    // --- the fields, at their NIfTI-1 / NIfTI-2 offsets
    std::int64_t dim[8];
    double pixdim[8];
    for (int q = 0; q < 8; ++q) {
        dim[q] = v2 ? f.get<std::int64_t>(16 + 8 * q) : f.get<std::int16_t>(40 + 2 * q);
        pixdim[q] = v2 ? f.get<double>(104 + 8 * q) : f.get<float>(76 + 4 * q);
    }
    const int code = v2 ? f.get<std::int16_t>(12) : f.get<std::int16_t>(70);
    const double vox_offset = v2 ? static_cast<double>(f.get<std::int64_t>(168)) : f.get<float>(108);
    const double slope = v2 ? f.get<double>(176) : f.get<float>(112);
    const double inter = v2 ? f.get<double>(184) : f.get<float>(116);
    const int qform_code = v2 ? f.get<std::int32_t>(344) : f.get<std::int16_t>(252);
    const int sform_code = v2 ? f.get<std::int32_t>(348) : f.get<std::int16_t>(254);
    auto real = [&](std::size_t off1, std::size_t off2) { return v2 ? f.get<double>(off2) : double{f.get<float>(off1)}; };
    const double qb = real(256, 352), qc = real(260, 360), qd = real(264, 368);
    const Vec3 qoffset{real(268, 376), real(272, 384), real(276, 392)};
    double srow[3][4];
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) srow[r][c] = real(280 + 16 * r + 4 * c, 400 + 32 * r + 8 * c);

    if (dim[0] < 1 || dim[0] > 7) bad("malformed header: dim[0] = " + std::to_string(dim[0]) + " is not in 1..7");
    for (int q = 4; q <= dim[0]; ++q)
        if (dim[q] != 1)
            bad("dim[" + std::to_string(q) + "] = " + std::to_string(dim[q]) +
                ": only 2-D and 3-D scalar volumes are read (not time series or vector data)");
    std::vector<std::uint64_t> sizes;
    for (int q = 1; q <= 3; ++q) {
        const std::int64_t d = q <= dim[0] ? dim[q] : 1;
        if (d < 1) bad("malformed header: dim[" + std::to_string(q) + "] = " + std::to_string(d));
        sizes.push_back(static_cast<std::uint64_t>(d));
    }
    Sample type{};
    if (!datatype(code, &type))
        bad("unsupported datatype " + std::to_string(code) +
            " (read: uint8, int8, int16, uint16, int32, uint32, float32, float64)");
    const std::size_t b = sample_bytes(type);
    const std::uint64_t n = checked_voxels("NIfTI", name, sizes, b, limits);
    if (!(vox_offset >= static_cast<double>(hdr)) || vox_offset > 1e15)
        bad("malformed header: vox_offset " + std::to_string(vox_offset) + " is before the end of the header");
    const std::uint64_t off = static_cast<std::uint64_t>(vox_offset);
    const std::uint64_t need = off + n * b;
    if (gz) {
        if (static_cast<double>(bytes.size()) * 1032.0 + 4096 < static_cast<double>(need))
            bad("truncated data: " + std::to_string(bytes.size()) + " gzip bytes cannot hold " + std::to_string(need) +
                " bytes");
        inflated = gunzip(bytes, static_cast<std::size_t>(need), name);
        file = inflated;
    }
    if (file.size() < need)
        bad("truncated data: expected " + std::to_string(need) + " bytes (header, extensions and voxels), found " +
            std::to_string(file.size()));

    Volume v;
    v.format = v2 ? "NIfTI-2" : "NIfTI-1";
    v.source = name;
    v.physical = true;
    for (int a = 0; a < 3; ++a) v.dims[a] = static_cast<std::int64_t>(sizes[static_cast<std::size_t>(a)]);
    v.values = decode_samples("NIfTI", name, file.subspan(static_cast<std::size_t>(off)), type, f.swap,
                              static_cast<std::size_t>(n), &v.integer_valued);
    if (slope != 0 && std::isfinite(slope) && std::isfinite(inter) && !(slope == 1 && inter == 0)) {
        bool integer = true;
        for (double& x : v.values) {
            x = slope * x + inter;
            if (!std::isfinite(x)) bad("scl_slope " + std::to_string(slope) + " and scl_inter " + std::to_string(inter) +
                                       " scale a voxel beyond the range of numbers");
            integer = integer && x == std::floor(x);
        }
        v.integer_valued = integer;
    }

    // --- geometry: the columns of the 3x3 part of the affine
    double m[3][3];
    Vec3 origin{0, 0, 0};
    if (sform_code > 0) {
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) m[r][c] = srow[r][c];
            origin[r] = srow[r][3];
        }
        v.space = "sform_code " + std::to_string(sform_code);
    } else if (qform_code > 0) {
        // R from the quaternion (b, c, d), a = sqrt(1 - b^2 - c^2 - d^2).
        double a2 = 1 - (qb * qb + qc * qc + qd * qd);
        double a = 0, b_ = qb, c_ = qc, d_ = qd;
        if (a2 < 1e-7) {  // 180-degree rotation: normalise (b, c, d)
            const double s = std::sqrt(qb * qb + qc * qc + qd * qd);
            if (!(s > 0)) bad("malformed header: degenerate qform quaternion");
            b_ /= s, c_ /= s, d_ /= s;
        } else {
            a = std::sqrt(a2);
        }
        const double R[3][3] = {{a * a + b_ * b_ - c_ * c_ - d_ * d_, 2 * (b_ * c_ - a * d_), 2 * (b_ * d_ + a * c_)},
                                {2 * (b_ * c_ + a * d_), a * a + c_ * c_ - b_ * b_ - d_ * d_, 2 * (c_ * d_ - a * b_)},
                                {2 * (b_ * d_ - a * c_), 2 * (c_ * d_ + a * b_), a * a + d_ * d_ - c_ * c_ - b_ * b_}};
        const double qfac = pixdim[0] < 0 ? -1 : 1;
        const double s[3] = {pixdim[1], pixdim[2], qfac * pixdim[3]};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] = R[r][c] * s[c];
        origin = qoffset;
        v.space = "qform_code " + std::to_string(qform_code);
    } else {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] = r == c ? pixdim[r + 1] : 0;
        v.space = "no qform or sform (pixdim only)";
    }
    for (int c = 0; c < 3; ++c) {
        Vec3 col{m[0][c], m[1][c], m[2][c]};
        if (c >= dim[0] && col == Vec3{0, 0, 0}) col[static_cast<std::size_t>(c)] = 1;  // unused axis of a 2-D file
        const double len = std::sqrt(col[0] * col[0] + col[1] * col[1] + col[2] * col[2]);
        const auto e = axis_aligned(col);
        if (!e || !std::isfinite(len) || !(len > 1e-12 && len < 1e12))
            bad(std::string("oblique or degenerate orientation: ") + (sform_code > 0 ? "sform" : "qform") +
                " column " + std::to_string(c) + " (index axis " + "ijk"[c] + ") is " + vec_text(col) +
                "; only axis-aligned (possibly permuted or flipped) orientations are read — resample the volume");
        v.axes[static_cast<std::size_t>(c)] = *e;
        v.spacing[static_cast<std::size_t>(c)] = len;
    }
    for (int a = 0; a < 3; ++a)
        for (int c = a + 1; c < 3; ++c) {
            const Vec3 &x = v.axes[a], &y = v.axes[c];
            if (x[0] * y[0] + x[1] * y[1] + x[2] * y[2] != 0)
                bad("degenerate orientation: index axes " + std::string(1, "ijk"[a]) + " and " + "ijk"[c] +
                    " point along the same direction");
        }
    for (int r = 0; r < 3; ++r)
        if (!std::isfinite(origin[r])) bad("the origin is not finite");
    v.origin = origin;
    return v;
}

}  // namespace warpmesh
