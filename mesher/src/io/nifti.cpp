// nifti.cpp — NIfTI-1 and NIfTI-2 single-file volumes (.nii, .nii.gz), either
// byte order (https://nifti.nimh.nih.gov/nifti-1, nifti2.h).
//
// Read: 2-D and 3-D data (dim[4..7] must be 1) of datatypes uint8, int8,
// int16, uint16, int32, uint32, float32, float64, from vox_offset on;
// scl_slope / scl_inter (value = slope * stored + inter when slope is
// non-zero and finite; 0 means no scaling, and so does a NaN or infinite
// slope, as nibabel reads it, with a warning; a non-finite scl_inter beside a
// valid slope is refused); the geometry from the sform when sform_code > 0, else
// the qform (quaternion, qfac = pixdim[0]) when qform_code > 0, else pixdim
// alone (origin 0, identity axes).  The affine's columns give each index
// axis's spacing and direction; directions must be axis-aligned (permuted or
// flipped is fine).  Refused with a message: oblique or sheared affines,
// NIfTI pairs (.hdr/.img, magic ni1/ni2), other datatypes (RGB, complex,
// 64-bit integers), more than 3 dimensions, data beyond the end of the file,
// gzip data that inflates to more than the header implies.
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

// The fields of a NIfTI-1 or NIfTI-2 header (at their offsets, either byte
// order) that the reader uses.
struct Header {
    bool v2 = false, swap = false;
    std::size_t size = 348;  // sizeof_hdr
    std::int64_t dim[8]{};
    double pixdim[8]{};
    int datatype = 0;
    double vox_offset = 0, slope = 0, inter = 0;
    int qform_code = 0, sform_code = 0;
    double qb = 0, qc = 0, qd = 0;
    Vec3 qoffset{0, 0, 0};
    double srow[3][4]{};
};

// sizeof_hdr, magic and the fields from the first bytes of the file (for
// gzip: of its inflated start).
Header parse_header(std::span<const std::uint8_t> file, bool gz, const std::string& name) {
    auto bad = [&](const std::string& what) { fail("NIfTI", name, what); };
    if (file.size() < 4) bad("truncated header: " + std::to_string(file.size()) + " bytes");
    std::uint32_t size_le = 0;
    std::memcpy(&size_le, file.data(), 4);
    if (!host_is_little_endian()) size_le = __builtin_bswap32(size_le);
    const std::uint32_t size_be = __builtin_bswap32(size_le);
    Header H;
    H.v2 = size_le == 540 || size_be == 540;
    if (!H.v2 && size_le != 348 && size_be != 348)
        bad(gz ? "gzip data that is not NIfTI (sizeof_hdr is neither 348 nor 540)" : "sizeof_hdr is neither 348 nor 540");
    const bool little = (size_le == 348 || size_le == 540);
    H.swap = little != host_is_little_endian();
    const bool v2 = H.v2;
    const Fields f{file, H.swap};
    H.size = v2 ? 540 : 348;
    if (file.size() < H.size)
        bad("truncated header: " + std::to_string(file.size()) + " of " + std::to_string(H.size) + " bytes");
    const std::string magic(reinterpret_cast<const char*>(file.data() + (v2 ? 4 : 344)), 3);
    if (magic == "ni1" || magic == "ni2") bad("a NIfTI pair (.hdr + .img) is not read; convert it to a single .nii");
    if (magic != (v2 ? "n+2" : "n+1")) bad("bad magic '" + magic + "' (expected " + (v2 ? "n+2" : "n+1") + ")");
    for (int q = 0; q < 8; ++q) {
        H.dim[q] = v2 ? f.get<std::int64_t>(16 + 8 * q) : f.get<std::int16_t>(40 + 2 * q);
        H.pixdim[q] = v2 ? f.get<double>(104 + 8 * q) : f.get<float>(76 + 4 * q);
    }
    H.datatype = v2 ? f.get<std::int16_t>(12) : f.get<std::int16_t>(70);
    H.vox_offset = v2 ? static_cast<double>(f.get<std::int64_t>(168)) : f.get<float>(108);
    H.slope = v2 ? f.get<double>(176) : f.get<float>(112);
    H.inter = v2 ? f.get<double>(184) : f.get<float>(116);
    H.qform_code = v2 ? f.get<std::int32_t>(344) : f.get<std::int16_t>(252);
    H.sform_code = v2 ? f.get<std::int32_t>(348) : f.get<std::int16_t>(254);
    auto real = [&](std::size_t off1, std::size_t off2) { return v2 ? f.get<double>(off2) : double{f.get<float>(off1)}; };
    H.qb = real(256, 352), H.qc = real(260, 360), H.qd = real(264, 368);
    H.qoffset = {real(268, 376), real(272, 384), real(276, 392)};
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c) H.srow[r][c] = real(280 + 16 * r + 4 * c, 400 + 32 * r + 8 * c);
    return H;
}

// What the data is: sizes, sample type, voxel count (within the limits) and
// where the voxels start.
struct Layout {
    std::vector<std::uint64_t> sizes;
    Sample type{};
    std::uint64_t n = 0, offset = 0;
    std::uint64_t end() const { return offset + n * sample_bytes(type); }
};

Layout check_layout(const Header& H, const std::string& name, const VolumeLimits& limits, std::uint64_t held) {
    auto bad = [&](const std::string& what) { fail("NIfTI", name, what); };
    const auto& dim = H.dim;
    if (dim[0] < 1 || dim[0] > 7) bad("malformed header: dim[0] = " + std::to_string(dim[0]) + " is not in 1..7");
    for (int q = 4; q <= dim[0]; ++q)
        if (dim[q] != 1)
            bad("dim[" + std::to_string(q) + "] = " + std::to_string(dim[q]) +
                ": only 2-D and 3-D scalar volumes are read (not time series or vector data)");
    Layout L;
    for (int q = 1; q <= 3; ++q) {
        const std::int64_t d = q <= dim[0] ? dim[q] : 1;
        if (d < 1) bad("malformed header: dim[" + std::to_string(q) + "] = " + std::to_string(d));
        L.sizes.push_back(static_cast<std::uint64_t>(d));
    }
    if (!datatype(H.datatype, &L.type))
        bad("unsupported datatype " + std::to_string(H.datatype) +
            " (read: uint8, int8, int16, uint16, int32, uint32, float32, float64)");
    L.n = checked_voxels("NIfTI", name, L.sizes, sample_bytes(L.type), limits, held);
    if (!(H.vox_offset >= static_cast<double>(H.size)) || H.vox_offset > 1e15)
        bad("malformed header: vox_offset " + std::to_string(H.vox_offset) + " is before the end of the header");
    L.offset = static_cast<std::uint64_t>(H.vox_offset);
    if (L.offset > limits.max_bytes)
        bad("vox_offset " + std::to_string(L.offset) + " is beyond " + memory_limit_text(limits.max_bytes));
    return L;
}

// value = slope * stored + inter (see the file's comment for the special
// values); warnings into v.warnings.
void apply_scaling(const Header& H, const std::string& name, Volume& v) {
    auto bad = [&](const std::string& what) { fail("NIfTI", name, what); };
    const double slope = H.slope, inter = H.inter;
    if (slope == 0) return;
    if (!std::isfinite(slope)) {
        v.warnings.push_back("NIfTI '" + name + "': scl_slope is " + (std::isnan(slope) ? "NaN" : "infinite") +
                             ": read as no scaling (the stored values, as nibabel reads them)");
        return;
    }
    if (!std::isfinite(inter))
        bad("scl_slope is " + std::to_string(slope) + " but scl_inter is " + (std::isnan(inter) ? "NaN" : "infinite") +
            ": the scaling is undefined; fix scl_inter (0: no offset)");
    if (slope == 1 && inter == 0) return;
    samples_to_values(v);
    bool integer = true;
    for (double& x : v.values) {
        x = slope * x + inter;
        if (!std::isfinite(x))
            bad("scl_slope " + std::to_string(slope) + " and scl_inter " + std::to_string(inter) +
                " scale a voxel beyond the range of numbers");
        integer = integer && x == std::floor(x);
    }
    v.integer_valued = integer;
}

// The 3x3 part of the affine (sform, else qform, else pixdim) and the origin.
void affine(const Header& H, const std::string& name, double m[3][3], Vec3& origin, std::string& space) {
    origin = {0, 0, 0};
    if (H.sform_code > 0) {
        for (int r = 0; r < 3; ++r) {
            for (int c = 0; c < 3; ++c) m[r][c] = H.srow[r][c];
            origin[r] = H.srow[r][3];
        }
        space = "sform_code " + std::to_string(H.sform_code);
    } else if (H.qform_code > 0) {
        // R from the quaternion (b, c, d), a = sqrt(1 - b^2 - c^2 - d^2).
        const double a2 = 1 - (H.qb * H.qb + H.qc * H.qc + H.qd * H.qd);
        double a = 0, b_ = H.qb, c_ = H.qc, d_ = H.qd;
        if (a2 < 1e-7) {  // 180-degree rotation: normalise (b, c, d)
            const double s = std::sqrt(H.qb * H.qb + H.qc * H.qc + H.qd * H.qd);
            if (!(s > 0)) fail("NIfTI", name, "malformed header: degenerate qform quaternion");
            b_ /= s, c_ /= s, d_ /= s;
        } else {
            a = std::sqrt(a2);
        }
        const double R[3][3] = {{a * a + b_ * b_ - c_ * c_ - d_ * d_, 2 * (b_ * c_ - a * d_), 2 * (b_ * d_ + a * c_)},
                                {2 * (b_ * c_ + a * d_), a * a + c_ * c_ - b_ * b_ - d_ * d_, 2 * (c_ * d_ - a * b_)},
                                {2 * (b_ * d_ - a * c_), 2 * (c_ * d_ + a * b_), a * a + d_ * d_ - c_ * c_ - b_ * b_}};
        const double qfac = H.pixdim[0] < 0 ? -1 : 1;
        const double s[3] = {H.pixdim[1], H.pixdim[2], qfac * H.pixdim[3]};
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] = R[r][c] * s[c];
        origin = H.qoffset;
        space = "qform_code " + std::to_string(H.qform_code);
    } else {
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) m[r][c] = r == c ? H.pixdim[r + 1] : 0;
        space = "no qform or sform (pixdim only)";
    }
}

// The geometry: the columns of the affine's 3x3 part give each index axis's
// spacing and (axis-aligned) direction.
void read_geometry(const Header& H, const std::string& name, Volume& v) {
    auto bad = [&](const std::string& what) { fail("NIfTI", name, what); };
    double m[3][3];
    Vec3 origin;
    affine(H, name, m, origin, v.space);
    for (int c = 0; c < 3; ++c) {
        Vec3 col{m[0][c], m[1][c], m[2][c]};
        if (c >= H.dim[0] && col == Vec3{0, 0, 0}) col[static_cast<std::size_t>(c)] = 1;  // unused axis of a 2-D file
        const double len = std::sqrt(col[0] * col[0] + col[1] * col[1] + col[2] * col[2]);
        const auto e = axis_aligned(col);
        if (!e || !std::isfinite(len) || !(len > 1e-12 && len < 1e12))
            bad(std::string("oblique or degenerate orientation: ") + (H.sform_code > 0 ? "sform" : "qform") +
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
}

}  // namespace

Volume decode_nifti(std::span<const std::uint8_t> bytes, const std::string& name, const VolumeLimits& limits) {
    const bool gz = bytes.size() >= 2 && bytes[0] == 0x1f && bytes[1] == 0x8b;
    std::vector<std::uint8_t> inflated;
    std::span<const std::uint8_t> file = bytes;
    if (gz) {  // the header first, to learn how much to inflate
        inflated = gunzip(bytes, 544, name);
        file = inflated;
    }
    const Header H = parse_header(file, gz, name);
    // gzip: the file and its inflated data (header, extensions, voxels) are held.
    const Layout L = check_layout(H, name, limits, bytes.size());
    const std::uint64_t need = L.end();
    if (gz) {
        if (static_cast<double>(bytes.size()) * 1032.0 + 4096 < static_cast<double>(need))
            fail("NIfTI", name, "truncated data: " + std::to_string(bytes.size()) + " gzip bytes cannot hold " +
                                    std::to_string(need) + " bytes");
        inflated = gunzip_exact(bytes, static_cast<std::size_t>(need), name);
        file = inflated;
    }
    if (file.size() < need)
        fail("NIfTI", name, "truncated data: expected " + std::to_string(need) +
                                " bytes (header, extensions and voxels), found " + std::to_string(file.size()));
    // More bytes than the header implies: the dims or the datatype do not
    // describe the data (a wrong header), so the voxels would be misread.
    if (file.size() > need)
        fail("NIfTI", name, "the file has " + std::to_string(file.size()) + " bytes, more than the " + std::to_string(need) +
                                " the header implies (vox_offset, dims and datatype): a wrong header?");
    Volume v;
    v.format = H.v2 ? "NIfTI-2" : "NIfTI-1";
    v.source = name;
    v.physical = true;
    for (int a = 0; a < 3; ++a) v.dims[a] = static_cast<std::int64_t>(L.sizes[static_cast<std::size_t>(a)]);
    decode_samples("NIfTI", name, file.subspan(static_cast<std::size_t>(L.offset)), L.type, H.swap, static_cast<std::size_t>(L.n), v);
    apply_scaling(H, name, v);
    read_geometry(H, name, v);
    return v;
}

}  // namespace warpmesh
