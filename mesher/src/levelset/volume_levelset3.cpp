// volume_levelset3.cpp — the level set of a 3D volume (levelset3.hpp:
// make_volume_levelset3): a trilinear interpolant of per-voxel values, the
// grey values themselves (threshold mode) or a signed distance (label mode).
//
// Geometry (volume.hpp).  Voxel (i, j, k) sits at origin + i s0 a0 + j s1 a1
// + k s2 a2 with axis-aligned unit a_n (a signed permutation), so a point X
// has the index coordinate t_n = ((X − origin)·a_n) / s_n along index axis n.
// The region is cut off at the hull of the voxel centres, t_n in [0,
// dims_n − 1]: f = max(F, K b), F the interpolant at the point clamped to the
// hull, b = max_n (|t_n − m_n| − r_n) s_n the box distance to the hull (m, r its
// centre and half-width in index units, s_n the spacing; < 0 inside) and K
// the units of F per millimetre (1 in label mode).  So f is continuous, a
// region reaching the volume's edge is closed by the hull's face, and the cut
// points there are zeros of f like any other.
//
// Label mode.  With m = 1 on the region's voxels, the exact Euclidean
// distance transform (Felzenszwalb and Huttenlocher's lower envelope of
// parabolas, one pass per index axis, weighted by the spacings) gives d_out
// at every voxel outside (the distance to the nearest centre inside) and d_in
// at every voxel inside; f = d_out − c outside and −(d_in − c) inside, c half
// the smallest spacing, so along the axis of the smallest spacing f is
// antisymmetric about the midpoint between a voxel and its neighbour of the
// other class and the trilinear interpolant's zero passes there.  Only the
// region's bounding box grown by `band` voxels is stored (as floats); f is
// clamped to ±band × the largest spacing, which farther voxels get without
// being stored.  The labels stay 16-bit integers (Volume::labels) up to the
// region's mask over that box (1 byte a voxel); the transforms run on the
// mask in slabs with a halo of the band's reach (banded_distance), start
// from the voxels on the region's surface only (mark_sources) and drop
// distances beyond the band after each pass, so their work follows the
// surface and their memory is a slab's; the region's inscribed distance
// (feature_size) is then known only within the band.
#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <sstream>

#include "warpmesh/core/buffer.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/core/memory.hpp"
#include "warpmesh/levelset/levelset3.hpp"
#include "warpmesh/io/volume.hpp"
#include "core/root_finder.hpp"

namespace warpmesh {
namespace {

// Squared-distance transform of one line, in place: g[i] → min_j g[j] +
// (w (i − j))², +inf where that exceeds `limit`.  The lower envelope of the
// finite g's parabolas (v: their positions, vg: their values, z: where each
// starts), then its values only within r = ⌈√limit / w⌉ + 1 of the first and
// last parabola: beyond, every parabola is more than √limit + w away, above
// the limit, and g is +inf there already.  False: no finite value (g unchanged).
bool edt_line(float* g, std::int64_t n, std::int64_t stride, double w, double limit, std::vector<std::int64_t>& v,
              std::vector<double>& z, std::vector<double>& vg) {
    constexpr double inf = std::numeric_limits<double>::infinity();
    v.resize(static_cast<std::size_t>(n)), z.resize(static_cast<std::size_t>(n) + 1), vg.resize(static_cast<std::size_t>(n));
    std::int64_t k = -1;
    const double w2 = w * w;
    for (std::int64_t q = 0; q < n; ++q) {
        const double fq = g[q * stride];
        if (!(fq < inf)) continue;
        double s = -inf;
        while (k >= 0) {
            const std::int64_t p = v[static_cast<std::size_t>(k)];
            s = ((fq + w2 * static_cast<double>(q * q)) - (vg[static_cast<std::size_t>(k)] + w2 * static_cast<double>(p * p))) /
                (2 * w2 * static_cast<double>(q - p));
            if (s > z[static_cast<std::size_t>(k)]) break;
            --k;
        }
        ++k;
        v[static_cast<std::size_t>(k)] = q, vg[static_cast<std::size_t>(k)] = fq;
        z[static_cast<std::size_t>(k)] = k == 0 ? -inf : s;
        z[static_cast<std::size_t>(k) + 1] = inf;
    }
    if (k < 0) return false;
    const std::int64_t r = static_cast<std::int64_t>(std::ceil(std::sqrt(limit) / w)) + 1;
    const std::int64_t lo = std::max<std::int64_t>(0, v[0] - r), hi = std::min(n, v[static_cast<std::size_t>(k)] + r + 1);
    for (std::int64_t i = lo, j = 0; i < hi; ++i) {
        while (z[static_cast<std::size_t>(j) + 1] < static_cast<double>(i)) ++j;
        const std::int64_t p = v[static_cast<std::size_t>(j)];
        const double di = vg[static_cast<std::size_t>(j)] + w2 * static_cast<double>((i - p) * (i - p));
        g[i * stride] = di > limit ? std::numeric_limits<float>::infinity() : static_cast<float>(di);
    }
    return true;
}

// The mask of the box (label_levelset): bit 0 the region, bit 1 a source
// (mark_sources).
constexpr std::uint8_t in_region = 1, source = 2;

// The first pass on one line: the sources are the mask's voxels m with
// (m & (source | in_region)) == want; g[i] = w² (i − p)² for the nearest
// source p, +inf beyond `limit` or with no source — edt_line's value on the
// line of sources (0 at a source, +inf elsewhere) to the bit (its parabolas
// all have g = 0, so its envelope at an integer i is a nearest source's,
// 0 + w² (i − p)²), found by one sweep each way instead of the envelope's
// divisions.
void sources_line(const std::uint8_t* mask, std::uint8_t want, float* g, std::int64_t n, double w, double limit,
                  std::vector<std::int64_t>& left) {
    constexpr std::int64_t none = std::numeric_limits<std::int64_t>::min() / 4;
    const auto is_source = [&](std::int64_t i) { return (mask[i] & (source | in_region)) == want; };
    left.resize(static_cast<std::size_t>(n));
    for (std::int64_t i = 0, last = none; i < n; ++i) left[static_cast<std::size_t>(i)] = last = is_source(i) ? i : last;
    const double w2 = w * w;
    for (std::int64_t i = n - 1, next = -none; i >= 0; --i) {
        next = is_source(i) ? i : next;
        const std::int64_t d = std::min(i - left[static_cast<std::size_t>(i)], next - i);
        const double di = d > n ? limit + 1 : 0.0 + w2 * static_cast<double>(d * d);
        g[i] = di > limit ? std::numeric_limits<float>::infinity() : static_cast<float>(di);
    }
}

// The squared distances to the sources `want` of the mask (sources_line) on
// the box of n voxels, into g, +inf beyond `limit` after each pass (a later
// pass only adds to a value).  The x lines are contiguous (sources_line, from
// the mask); the y and z lines are taken in tiles of `tile` lines
// adjacent along x, copied into a small buffer (each voxel row read and
// written as whole cache lines) and transformed there in place, a line at a
// time with its stride.
void edt(const std::uint8_t* mask, std::uint8_t want, std::span<float> g, const std::array<std::int64_t, 3>& n, const std::array<double, 3>& w,
         double limit) {
    constexpr std::int64_t tile = 16;
#pragma omp parallel
    {
        std::vector<std::int64_t> v;
        std::vector<double> z, vg;
        std::vector<float> lines;
#pragma omp for schedule(static)
        for (std::int64_t line = 0; line < n[1] * n[2]; ++line)
            sources_line(mask + line * n[0], want, g.data() + line * n[0], n[0], w[0], limit, v);
        for (std::size_t a = 1; a < 3; ++a) {
            const std::size_t c = 3 - a;  // the axis other than x and a
            const std::int64_t stride_a = a == 1 ? n[0] : n[0] * n[1], stride_c = c == 1 ? n[0] : n[0] * n[1];
            const std::int64_t tiles = (n[0] + tile - 1) / tile, len = n[a];
            lines.resize(static_cast<std::size_t>(len * tile));
#pragma omp for schedule(static)
            for (std::int64_t job = 0; job < tiles * n[c]; ++job) {
                const std::int64_t x0 = job % tiles * tile, width = std::min(tile, n[0] - x0), base = x0 + job / tiles * stride_c;
                for (std::int64_t i = 0; i < len; ++i) std::copy_n(g.data() + base + i * stride_a, width, lines.data() + i * tile);
                bool any = false;
                for (std::int64_t x = 0; x < width; ++x) any = edt_line(lines.data() + x, len, tile, w[a], limit, v, z, vg) || any;
                if (any)
                    for (std::int64_t i = 0; i < len; ++i) std::copy_n(lines.data() + i * tile, width, g.data() + base + i * stride_a);
            }
        }
    }
}

// The transforms' sources: the voxels of each class (the region's, or the
// rest's) with a 6-neighbour of the other class in the box.  The nearest
// voxel of a class to a voxel p of the other class is one of them: a voxel
// q of the class without such a neighbour has a neighbour of its class one
// step nearer p along an axis where q − p is non-zero, and a transform's
// value (rounded sums of the squared offsets, axis by axis) never grows as
// one axis's offset shrinks.  So the fields are those of the transforms from
// every voxel of the class (to the last bit, unless two sources tie within
// rounding), at the cost of a surface's worth of sources.  mark_sources sets
// bit 1 of the mask (bit 0: the region) on them, once.
void mark_sources(std::span<std::uint8_t> mask, const std::array<std::int64_t, 3>& n) {
    const std::array<std::int64_t, 3> stride{1, n[0], n[0] * n[1]};
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < n[2]; ++k)
        for (std::int64_t j = 0; j < n[1]; ++j)
            for (std::int64_t i = 0; i < n[0]; ++i) {
                const std::int64_t at = i + stride[1] * j + stride[2] * k;
                const std::array<std::int64_t, 3> q{i, j, k};
                const std::uint8_t r = mask[static_cast<std::size_t>(at)] & in_region;
                bool edge = false;
                for (std::size_t a = 0; a < 3; ++a) {
                    edge = edge || (q[a] > 0 && (mask[static_cast<std::size_t>(at - stride[a])] & in_region) != r);
                    edge = edge || (q[a] + 1 < n[a] && (mask[static_cast<std::size_t>(at + stride[a])] & in_region) != r);
                }
                if (edge) mask[static_cast<std::size_t>(at)] |= source;
            }
}
// The label field (levelset3.hpp, label mode) on the box of n voxels whose
// mask (in_region, source: mark_sources) is `region`: f = d_out − c outside and −(d_in − c) inside,
// clamped to [−cap, cap].  Exact wherever |f| < cap: a value there is a
// distance below cap + c to a source, and the transforms keep every squared
// distance up to limit = (cap + 2c)², so a source within cap + 2c of a voxel
// is seen.  The box is transformed in slabs of planes along index axis 2,
// each with a halo of h = ⌈(cap + 2c)/w₂⌉ planes on either side: a source
// more than h planes away is more than cap + 2c away, so the slab's own
// planes get what the whole box's transforms give them (the x and y passes
// are the same lines; a z line loses only sources beyond the limit).  So the
// work and memory beyond the field are one slab's.  `feature`: the largest
// inscribed distance, +inf where it is beyond the band.
struct Slabs {
    std::int64_t slab, halo;  // planes a slab, planes of halo on either side
};
Slabs slabs_of(double reach, double w2) {
    const std::int64_t halo = static_cast<std::int64_t>(std::ceil(reach / w2));
    return {std::max<std::int64_t>(64, 4 * halo), halo};
}

Buffer<float> banded_distance(std::span<const std::uint8_t> region, const std::array<std::int64_t, 3>& n, const std::array<double, 3>& w,
                              double c, double cap, double& feature) {
    const double limit = (cap + 2 * c) * (cap + 2 * c);
    const auto [slab, halo] = slabs_of(cap + 2 * c, w[2]);
    const std::int64_t plane = n[0] * n[1];
    Buffer<float> field(static_cast<std::size_t>(plane * n[2]));  // every element written below
    Buffer<float> g(static_cast<std::size_t>(plane * std::min(n[2], slab + 2 * halo)));
    feature = 0;
    for (std::int64_t z0 = 0; z0 < n[2]; z0 += slab) {
        const std::int64_t z1 = std::min(n[2], z0 + slab), w0 = std::max<std::int64_t>(0, z0 - halo),
                           w1 = std::min(n[2], z1 + halo);
        const std::span<float> window(g.data(), static_cast<std::size_t>(plane * (w1 - w0)));
        for (const bool of_region : {true, false}) {  // d_out from the region's sources, then d_in
            edt(region.data() + w0 * plane, static_cast<std::uint8_t>(source | (of_region ? in_region : 0)), window, {n[0], n[1], w1 - w0}, w,
                limit);
            double deepest = 0;
#pragma omp parallel for schedule(static) reduction(max : deepest)
            for (std::int64_t at = z0 * plane; at < z1 * plane; ++at) {
                const bool r = (region[static_cast<std::size_t>(at)] & in_region) != 0;
                if (r == of_region) continue;  // the other transform's voxel
                const float d2 = window[static_cast<std::size_t>(at - w0 * plane)];
                if (!(d2 < std::numeric_limits<float>::infinity())) {  // beyond the band: ±cap (what the clamp gives)
                    if (r) deepest = std::numeric_limits<double>::infinity();
                    field[static_cast<std::size_t>(at)] = static_cast<float>(r ? -cap : cap);
                    continue;
                }
                const double d = std::sqrt(static_cast<double>(d2)) - c;
                if (r) deepest = std::max(deepest, d);
                field[static_cast<std::size_t>(at)] = static_cast<float>(std::clamp(r ? -d : d, -cap, cap));
            }
            feature = std::max(feature, deepest);
        }
    }
    return field;
}

class VolumeLevelSet3 final : public LevelSet3 {
public:
    // Values on the box [lo, lo + n) of voxel indices; `far` beyond it.
    // region_lo, region_hi: the voxels whose value is <= 0 lie in this index box.
    VolumeLevelSet3(const Volume& v, Buffer<float> values, std::array<std::int64_t, 3> lo, std::array<std::int64_t, 3> n,
                    std::array<std::int64_t, 3> region_lo, std::array<std::int64_t, 3> region_hi, float far, double feature,
                    double per_mm, std::string name)
        : values_(std::move(values)), lo_(lo), n_(n), dims_(v.dims), far_(far), feature_(feature), name_(std::move(name)) {
        resolution_ = std::min({v.spacing[0], v.spacing[1], v.spacing[2]});
        spacing_ = {v.spacing[0], v.spacing[1], v.spacing[2]};
        per_mm_ = per_mm;
        lowest_ = std::min(far_, values_.empty() ? far_ : *std::min_element(values_.begin(), values_.end()));
        for (std::size_t a = 0; a < 3; ++a) {
            const Vec3 ax = *axis_aligned(v.axes[a]);
            for (std::size_t p = 0; p < 3; ++p)
                if (ax[p] != 0) perm_[a] = static_cast<int>(p), scale_[a] = ax[p] / v.spacing[a];
            origin_[a] = v.origin[static_cast<std::size_t>(perm_[a])];
        }
        // f > 0 wherever the 8 voxels around a point are all outside, so the
        // region lies within one voxel of the box of its voxels.
        for (std::size_t a = 0; a < 3; ++a) {
            const std::size_t p = static_cast<std::size_t>(perm_[a]);
            const double e0 = origin_[a] + static_cast<double>(region_lo[a] - 1) / scale_[a];
            const double e1 = origin_[a] + static_cast<double>(region_hi[a] + 1) / scale_[a];
            lo_box_[p] = std::min(e0, e1), hi_box_[p] = std::max(e0, e1);
            const double h0 = origin_[a], h1 = origin_[a] + static_cast<double>(dims_[a] - 1) / scale_[a];
            hull_lo_[p] = std::min(h0, h1), hull_hi_[p] = std::max(h0, h1);
        }
    }
    double value(double x, double y, double z) const override {
        std::array<double, 3> t = index_coordinates({x, y, z});
        for (std::size_t a = 0; a < 3; ++a)
            if (!(t[a] == t[a])) return far_;  // a NaN coordinate
        const double box = hull_distance(t);
        std::array<std::int64_t, 3> i{};
        std::array<double, 3> u{};
        for (std::size_t a = 0; a < 3; ++a) {
            t[a] = std::clamp(t[a], 0.0, static_cast<double>(dims_[a] - 1));
            i[a] = std::min<std::int64_t>(static_cast<std::int64_t>(t[a]), dims_[a] - 2);
            u[a] = t[a] - static_cast<double>(i[a]);
        }
        return std::max(interpolate(corners(i), u), per_mm_ * box);
    }
    double cut_parameter(Point3 a, Point3 b, double fa, double fb) const override;
    Box3 bounds() const override {
        return {lo_box_[0], lo_box_[1], lo_box_[2], hi_box_[0], hi_box_[1], hi_box_[2]};
    }
    std::optional<Box3> domain() const override {
        return Box3{hull_lo_[0], hull_lo_[1], hull_lo_[2], hull_hi_[0], hull_hi_[1], hull_hi_[2]};
    }
    double feature_size() const override { return feature_; }
    double resolution() const override { return resolution_; }
    std::string describe() const override { return name_; }
    std::optional<double> reference_volume() const override { return reference_volume_; }
    void set_reference_volume(double v) { reference_volume_ = v; }

private:
    // Index coordinates t of a physical point X: t_n = ((X − origin)·a_n) / s_n.
    std::array<double, 3> index_coordinates(const std::array<double, 3>& X) const {
        std::array<double, 3> t{};
        for (std::size_t a = 0; a < 3; ++a) t[a] = (X[static_cast<std::size_t>(perm_[a])] - origin_[a]) * scale_[a];
        return t;
    }
    // b = max_n (|t_n − m_n| − r_n) s_n: the box distance to the voxel centres' hull, < 0 inside.
    double hull_distance(const std::array<double, 3>& t) const {
        double box = -std::numeric_limits<double>::infinity();
        for (std::size_t a = 0; a < 3; ++a) {
            const double half = 0.5 * static_cast<double>(dims_[a] - 1);
            box = std::max(box, (std::abs(t[a] - half) - half) * spacing_[a]);
        }
        return box;
    }
    // The 8 voxels i .. i + 1 (bit 0: +x, bit 1: +y, bit 2: +z): straight
    // from the stored box when they are all in it (the common case), else
    // voxel by voxel (far_ outside it).
    std::array<double, 8> corners(const std::array<std::int64_t, 3>& i) const {
        std::array<std::int64_t, 3> r{};
        bool stored = true;
        for (std::size_t a = 0; a < 3; ++a) {
            r[a] = i[a] - lo_[a];
            stored = stored && r[a] >= 0 && r[a] + 1 < n_[a];
        }
        std::array<double, 8> c{};
        if (stored) {
            const std::int64_t sy = n_[0], sz = n_[0] * n_[1];
            const float* p = values_.data() + r[0] + sy * r[1] + sz * r[2];
            c = {p[0], p[1], p[sy], p[sy + 1], p[sz], p[sz + 1], p[sz + sy], p[sz + sy + 1]};
        } else {
            for (int k = 0; k < 8; ++k) c[static_cast<std::size_t>(k)] = at({i[0] + (k & 1), i[1] + (k >> 1 & 1), i[2] + (k >> 2)});
        }
        return c;
    }
    // The trilinear interpolant of a cell's corners c at fractions u.
    static double interpolate(const std::array<double, 8>& c, const std::array<double, 3>& u) {
        const double x0 = c[0] + u[0] * (c[1] - c[0]), x1 = c[2] + u[0] * (c[3] - c[2]);
        const double x2 = c[4] + u[0] * (c[5] - c[4]), x3 = c[6] + u[0] * (c[7] - c[6]);
        const double y0 = x0 + u[1] * (x1 - x0), y1 = x2 + u[1] * (x3 - x2);
        return y0 + u[2] * (y1 - y0);
    }
    double at(const std::array<std::int64_t, 3>& j) const {
        std::int64_t k = 0;
        for (int a = 2; a >= 0; --a) {
            const std::int64_t r = j[static_cast<std::size_t>(a)] - lo_[static_cast<std::size_t>(a)];
            if (r < 0 || r >= n_[static_cast<std::size_t>(a)]) return far_;
            k = k * n_[static_cast<std::size_t>(a)] + r;
        }
        return values_[static_cast<std::size_t>(k)];
    }
    Buffer<float> values_;
    std::array<std::int64_t, 3> lo_, n_, dims_;
    float far_;
    double lowest_ = 0;  // no voxel value is below it: F >= lowest_ everywhere
    double feature_, resolution_ = 0, per_mm_ = 1;
    std::array<double, 3> spacing_{1, 1, 1};
    std::string name_;
    std::optional<double> reference_volume_;
    std::array<int, 3> perm_{0, 1, 2};
    std::array<double, 3> scale_{1, 1, 1}, origin_{0, 0, 0}, lo_box_{}, hi_box_{}, hull_lo_{}, hull_hi_{};
};

// A cubic c0 + c1 s + c2 s² + c3 s³.
struct Cubic {
    std::array<double, 4> c{};
    double operator()(double s) const { return ((c[3] * s + c[2]) * s + c[1]) * s + c[0]; }
};

// p + (x0 + s dx)(q − p): one lerp of the trilinear interpolant along a
// linear path, one degree up (p and q of degree <= 2).
Cubic lerp(const Cubic& p, const Cubic& q, double x0, double dx) {
    Cubic r;
    for (std::size_t k = 0; k < 3; ++k) {
        const double d = q.c[k] - p.c[k];
        r.c[k] += p.c[k] + x0 * d;
        r.c[k + 1] += dx * d;
    }
    return r;
}

// Cut points.  Where the hull term cannot win on the segment a b (K b <= the
// lowest voxel value at both ends, hence all along it: b is convex along a
// line), f is the interpolant F there, unclamped, and in each voxel cell the
// segment crosses F is the trilinear interpolant of a linear path: a cubic
// in the segment's parameter.  The segment is split at the cells' faces
// (piece [u, e], local parameter s in [0, 1]); in the first piece whose end
// has the sign opposite to f(a), the bracketed root finder runs on that
// piece's cubic (Horner: a few flops an evaluation instead of a lookup of
// eight voxels), to the same convergence as on f (root_finder.hpp).  F is
// continuous, so that piece brackets a zero of f: the one nearest a where f
// has several on the edge.  Elsewhere (the hull term, a NaN), or where
// rounding makes a piece's start disagree with the previous piece's end,
// the root finder on f itself.
double VolumeLevelSet3::cut_parameter(Point3 a, Point3 b, double fa, double fb) const {
    const std::array<double, 3> t0 = index_coordinates({a.x, a.y, a.z}), t1 = index_coordinates({b.x, b.y, b.z});
    bool plain = per_mm_ * hull_distance(t0) <= lowest_ && per_mm_ * hull_distance(t1) <= lowest_;
    for (std::size_t k = 0; k < 3; ++k) plain = plain && std::isfinite(t0[k]) && std::isfinite(t1[k]);
    if (!plain) return bracketed_root3(*this, a, b, fa, fb);
    std::array<double, 3> dt{}, next{};  // per axis: t's rate, the parameter of the next cell face
    std::array<std::int64_t, 3> face{}, step{};
    for (std::size_t k = 0; k < 3; ++k) {
        dt[k] = t1[k] - t0[k];
        step[k] = dt[k] > 0 ? 1 : -1;
        face[k] = dt[k] > 0 ? static_cast<std::int64_t>(std::floor(t0[k])) + 1 : static_cast<std::int64_t>(std::ceil(t0[k])) - 1;
        next[k] = dt[k] != 0 ? (static_cast<double>(face[k]) - t0[k]) / dt[k] : 2.0;
    }
    for (double u = 0; u < 1;) {
        const double e = std::min({1.0, next[0], next[1], next[2]}), len = e - u, mid = 0.5 * (u + e);
        std::array<std::int64_t, 3> i{};
        std::array<double, 3> x0{}, dx{};  // the cell's fractions along the piece: x0 + s dx
        for (std::size_t k = 0; k < 3; ++k) {
            i[k] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(t0[k] + mid * dt[k])), 0, dims_[k] - 2);
            x0[k] = t0[k] + u * dt[k] - static_cast<double>(i[k]);
            dx[k] = len * dt[k];
        }
        const std::array<double, 8> c = corners(i);
        std::array<Cubic, 4> xs{};
        for (std::size_t m = 0; m < 4; ++m) xs[m] = lerp({{c[2 * m], 0, 0, 0}}, {{c[2 * m + 1], 0, 0, 0}}, x0[0], dx[0]);
        const Cubic p = lerp(lerp(xs[0], xs[1], x0[1], dx[1]), lerp(xs[2], xs[3], x0[1], dx[1]), x0[2], dx[2]);
        const double p0 = p(0), p1 = p(1);
        if ((p1 < 0) != (fa < 0) || p1 == 0) {
            if (p1 == 0) return inside_unit_interval(e);
            if (p0 == 0) return inside_unit_interval(u);
            if ((p0 < 0) != (fa < 0)) break;
            return inside_unit_interval(u + len * bracketed_root_of(p, p0, p1));
        }
        for (std::size_t k = 0; k < 3; ++k)
            if (next[k] == e) face[k] += step[k], next[k] = (static_cast<double>(face[k]) - t0[k]) / dt[k];
        u = e;
    }
    return bracketed_root3(*this, a, b, fa, fb);
}

std::string labels_text(const ImageLevelSetOptions& m) {
    if (m.label_nonzero) return "nonzero";
    std::ostringstream s;
    for (std::size_t i = 0; i < m.labels.size(); ++i) s << (i ? "," : "") << m.labels[i];
    return s.str();
}

// The region's labels: slot[x] = k + 1 for the k-th listed label x (1 for
// every non-zero x with label_nonzero), 0 for a label outside the region.
std::vector<std::uint16_t> region_slots(const ImageLevelSetOptions& m) {
    std::vector<std::uint16_t> slot(65536, 0);
    if (m.label_nonzero) std::fill(slot.begin() + 1, slot.end(), std::uint16_t{1});
    for (std::size_t i = m.label_nonzero ? m.labels.size() : 0; i < m.labels.size(); ++i)
        if (m.labels[i] >= 0 && m.labels[i] <= 65535 && slot[static_cast<std::size_t>(m.labels[i])] == 0)
            slot[static_cast<std::size_t>(m.labels[i])] = static_cast<std::uint16_t>(i + 1);
    return slot;
}

// The region's voxels in a volume: their bounding box [lo, hi] and count,
// and which listed labels occur (refusing non-integer values, an empty
// region and absent labels).  A row of voxels (x fastest) at a time, the
// 16-bit labels straight (Volume::labels), doubles checked to be labels.
struct RegionScan {
    std::array<std::int64_t, 3> lo{}, hi{};
    std::int64_t voxels = 0;
};
RegionScan scan_region(const Volume& v, const ImageLevelSetOptions& m, const std::vector<std::uint16_t>& slot) {
    RegionScan out{v.dims, {-1, -1, -1}, 0};
    std::vector<char> seen(std::max<std::size_t>(1, m.labels.size()), 0);
    for (std::int64_t k = 0; k < v.dims[2]; ++k)
        for (std::int64_t j = 0; j < v.dims[1]; ++j) {
            const std::size_t row = static_cast<std::size_t>(v.dims[0] * (j + v.dims[1] * k));
            std::int64_t first = -1, last = -1;
            for (std::int64_t i = 0; i < v.dims[0]; ++i) {
                std::size_t x = 0;
                if (!v.labels.empty()) {
                    x = v.labels[row + static_cast<std::size_t>(i)];
                } else {
                    const double d = v.values[row + static_cast<std::size_t>(i)];
                    // In 0..65535, then an integer (the cast is exact there).
                    if (!(d >= 0 && d <= 65535) || static_cast<double>(static_cast<std::int32_t>(d)) != d)
                        throw InputError(v.source + ": label mode needs integer voxel values in 0..65535 (found " + std::to_string(d) + ")");
                    x = static_cast<std::size_t>(d);
                }
                if (slot[x] == 0) continue;
                seen[slot[x] - 1u] = 1;
                if (first < 0) first = i;
                last = i;
                ++out.voxels;
            }
            if (first < 0) continue;
            out.lo = {std::min(out.lo[0], first), std::min(out.lo[1], j), std::min(out.lo[2], k)};
            out.hi = {std::max(out.hi[0], last), std::max(out.hi[1], j), std::max(out.hi[2], k)};
        }
    if (out.hi[0] < 0) throw InputError(v.source + ": the region is empty: no voxel has the label(s) " + labels_text(m));
    std::string absent;
    for (std::size_t i = 0; i < m.labels.size() && !m.label_nonzero; ++i) {
        const bool valid = m.labels[i] >= 0 && m.labels[i] <= 65535;
        if (valid && (seen[i] || slot[static_cast<std::size_t>(m.labels[i])] != i + 1)) continue;
        if (!absent.empty()) absent += ',';
        absent += std::to_string(m.labels[i]);
    }
    if (!absent.empty())
        throw InputError(v.source + ": no voxel has the label(s) " + absent + " (of " + labels_text(m) + "): a typo, or the wrong volume?");
    return out;
}

// Label mode (levelset3.hpp).  The volume's samples are read twice — the
// scan, then the region's mask over its box — and may be released after
// that (`release`: the caller's volume, whose samples nothing needs later);
// the field is built from the mask alone (banded_distance).
std::unique_ptr<LevelSet3> label_levelset(const Volume& v, const VolumeLevelSet3Options& o, Volume* release) {
    const auto& m = o.mode;
    if (!m.label_nonzero && m.labels.empty()) throw InputError("label mode needs labels: a label list (e.g. 3 or 51,52) or nonzero");
    const std::vector<std::uint16_t> slot = region_slots(m);
    const RegionScan scan = scan_region(v, m, slot);
    std::array<std::int64_t, 3> lo{}, hi{}, n{};
    std::uint64_t count = 1;
    for (std::size_t a = 0; a < 3; ++a) {
        lo[a] = std::max<std::int64_t>(0, scan.lo[a] - o.band), hi[a] = std::min<std::int64_t>(v.dims[a] - 1, scan.hi[a] + o.band);
        n[a] = hi[a] - lo[a] + 1;
        count *= static_cast<std::uint64_t>(n[a]);
    }
    const std::array<double, 3> w{v.spacing[0], v.spacing[1], v.spacing[2]};
    const double c = 0.5 * std::min({w[0], w[1], w[2]}), cap = o.band * std::max({w[0], w[1], w[2]});
    const Slabs sl = slabs_of(cap + 2 * c, w[2]);
    // The mask and the field (1 + 4 bytes a voxel of the box), and a slab of the transforms'.
    const std::uint64_t window = static_cast<std::uint64_t>(std::min(n[2], sl.slab + 2 * sl.halo));
    check_memory(count * 5 + count / static_cast<std::uint64_t>(n[2]) * window * 4, o.max_memory,
                 "the label volume's distance field (" + std::to_string(count) + " voxels)", "5 bytes a voxel of the region's bounding box",
                 "crop the volume to the region");
    Buffer<std::uint8_t> region(count);  // every element written below
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < n[2]; ++k)
        for (std::int64_t j = 0; j < n[1]; ++j) {
            const std::size_t from = static_cast<std::size_t>(lo[0] + v.dims[0] * (lo[1] + j + v.dims[1] * (lo[2] + k)));
            std::uint8_t* to = region.data() + n[0] * (j + n[1] * k);
            for (std::int64_t i = 0; i < n[0]; ++i)
                to[i] = slot[v.labels.empty() ? static_cast<std::size_t>(v.values[from + static_cast<std::size_t>(i)])
                                              : v.labels[from + static_cast<std::size_t>(i)]] != 0;
        }
    if (release) Buffer<std::uint16_t>().swap(release->labels), std::vector<double>().swap(release->values);
    double feature = 0;
    mark_sources(region, n);
    Buffer<float> field = banded_distance(region, n, w, c, cap, feature);
    if (!std::isfinite(feature)) feature = 0;  // unknown: deeper than the band somewhere
    Buffer<std::uint8_t>().swap(region);
    auto f = std::make_unique<VolumeLevelSet3>(v, std::move(field), lo, n, scan.lo, scan.hi, static_cast<float>(cap), feature, 1.0,
                                               v.source + " (label " + labels_text(m) + ")");
    f->set_reference_volume(static_cast<double>(scan.voxels) * v.spacing[0] * v.spacing[1] * v.spacing[2]);
    return f;
}

std::unique_ptr<LevelSet3> threshold_levelset(const Volume& v, const VolumeLevelSet3Options& o) {
    double mn = std::numeric_limits<double>::infinity(), mx = -mn;
    for (std::size_t q = 0; q < static_cast<std::size_t>(v.voxel_count()); ++q) mn = std::min(mn, v.value(q)), mx = std::max(mx, v.value(q));
    const double iso = o.mode.iso ? *o.mode.iso : v.maxval > 0 ? 0.5 * v.maxval : 0.5 * (mn + mx);
    if (!std::isfinite(iso)) throw InputError("the iso value must be a finite number");
    const std::uint64_t count = static_cast<std::uint64_t>(v.voxel_count());
    check_memory(count * 4, o.max_memory, "the volume's grey values (" + std::to_string(count) + " voxels)", "4 bytes a voxel",
                 "crop or downsample the volume");
    Buffer<float> f(count);  // every element written below
    const double sign = o.mode.inside_above ? -1 : 1;
    std::array<std::int64_t, 3> lo{v.dims}, hi{-1, -1, -1};
    for (std::int64_t k = 0, i = 0; k < v.dims[2]; ++k)
        for (std::int64_t j = 0; j < v.dims[1]; ++j)
            for (std::int64_t x = 0; x < v.dims[0]; ++x, ++i) {
                f[static_cast<std::size_t>(i)] = static_cast<float>(sign * (v.value(static_cast<std::size_t>(i)) - iso));
                if (f[static_cast<std::size_t>(i)] > 0) continue;
                const std::array<std::int64_t, 3> q{x, j, k};
                for (std::size_t a = 0; a < 3; ++a) lo[a] = std::min(lo[a], q[a]), hi[a] = std::max(hi[a], q[a]);
            }
    if (hi[0] < 0) throw InputError(v.source + ": the region is empty: no voxel is " + (o.mode.inside_above ? "above" : "below") + " the iso value");
    std::ostringstream name;
    name << v.source << " (iso " << iso << (o.mode.inside_above ? ", inside above)" : ", inside below)");
    const float far = static_cast<float>(std::max(1.0, std::abs(mx - mn)));
    return std::make_unique<VolumeLevelSet3>(v, std::move(f), std::array<std::int64_t, 3>{0, 0, 0}, v.dims, lo, hi, far, 0.0, far / std::min({v.spacing[0], v.spacing[1], v.spacing[2]}), name.str());
}

std::unique_ptr<LevelSet3> volume_levelset3(const Volume& volume, const VolumeLevelSet3Options& options, Volume* release) {
    for (std::size_t a = 0; a < 3; ++a) {
        if (volume.dims[a] < 2)
            throw InputError(volume.source + ": a 3D mesh needs at least 2 voxels along every axis (" + std::to_string(volume.dims[0]) +
                             " x " + std::to_string(volume.dims[1]) + " x " + std::to_string(volume.dims[2]) + ")");
        if (!axis_aligned(volume.axes[a])) throw InputError(volume.source + ": oblique orientations are not supported");
    }
    if (options.band < 2) throw InputError("the distance band must be at least 2 voxels");
    if (options.mode.mode == ImageMode::label) return label_levelset(volume, options, release);
    return threshold_levelset(volume, options);
}

}  // namespace

std::unique_ptr<LevelSet3> make_volume_levelset3(const Volume& volume, const VolumeLevelSet3Options& options) {
    return volume_levelset3(volume, options, nullptr);
}

std::unique_ptr<LevelSet3> make_volume_levelset3(Volume&& volume, const VolumeLevelSet3Options& options) {
    return volume_levelset3(volume, options, &volume);
}

}  // namespace warpmesh
