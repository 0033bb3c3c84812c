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
#include <atomic>
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
// (mark_sources), bit 2 a voxel whose depth banded_distance's `feature`
// leaves out (a part's voxels that are not its own: label_part_facts).
constexpr std::uint8_t in_region = 1, source = 2, uncounted = 4;

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
                const bool counted = r && !(region[static_cast<std::size_t>(at)] & uncounted);
                const float d2 = window[static_cast<std::size_t>(at - w0 * plane)];
                if (!(d2 < std::numeric_limits<float>::infinity())) {  // beyond the band: ±cap (what the clamp gives)
                    if (counted) deepest = std::numeric_limits<double>::infinity();
                    field[static_cast<std::size_t>(at)] = static_cast<float>(r ? -cap : cap);
                    continue;
                }
                const double d = std::sqrt(static_cast<double>(d2)) - c;
                if (counted) deepest = std::max(deepest, d);
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
        : values_(std::move(values)), lo_(lo), n_(n), dims_(v.is_part() ? v.whole_dims : v.dims), far_(far), feature_(feature),
          name_(std::move(name)) {
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
    // A part's (label_part_levelset): the whole field's minimum, and the
    // whole's stored box [lo, hi], whose voxels beyond the stored ones are
    // read outside the part.
    void set_part(double lowest, const std::array<std::int64_t, 3>& lo, const std::array<std::int64_t, 3>& hi) {
        lowest_ = lowest, part_ = true, whole_lo_ = lo, whole_hi_ = hi;
    }
    bool read_outside_part() const override { return outside_.load(); }

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
            if (r < 0 || r >= n_[static_cast<std::size_t>(a)]) return outside(j);
            k = k * n_[static_cast<std::size_t>(a)] + r;
        }
        return values_[static_cast<std::size_t>(k)];
    }
    // far_ for a voxel beyond the stored box; of a part, flagged where the whole stores it.
    float outside(const std::array<std::int64_t, 3>& j) const {
        bool stored = part_;
        for (std::size_t a = 0; a < 3; ++a) stored = stored && j[a] >= whole_lo_[a] && j[a] <= whole_hi_[a];
        if (stored) outside_.store(true, std::memory_order_relaxed);
        return far_;
    }
    Buffer<float> values_;
    std::array<std::int64_t, 3> lo_, n_, dims_;
    bool part_ = false;
    std::array<std::int64_t, 3> whole_lo_{}, whole_hi_{};
    mutable std::atomic<bool> outside_{false};
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
// and which listed labels occur (refusing non-integer values; check_region
// refuses an empty region and absent labels).  A row of voxels (x fastest)
// at a time, the 16-bit labels straight (Volume::labels), doubles checked to
// be labels.
struct RegionScan {
    std::array<std::int64_t, 3> lo{}, hi{};
    std::int64_t voxels = 0;
    std::vector<std::uint8_t> seen;  // per listed label
};
RegionScan scan_region(const Volume& v, const ImageLevelSetOptions& m, const std::vector<std::uint16_t>& slot) {
    RegionScan out{v.dims, {-1, -1, -1}, 0, std::vector<std::uint8_t>(std::max<std::size_t>(1, m.labels.size()), 0)};
    std::vector<std::uint8_t>& seen = out.seen;
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
    return out;
}
void check_region(const RegionScan& scan, const ImageLevelSetOptions& m, const std::vector<std::uint16_t>& slot,
                  const std::string& source) {
    if (scan.hi[0] < 0) throw InputError(source + ": the region is empty: no voxel has the label(s) " + labels_text(m));
    std::string absent;
    for (std::size_t i = 0; i < m.labels.size() && !m.label_nonzero; ++i) {
        const bool valid = m.labels[i] >= 0 && m.labels[i] <= 65535;
        if (valid && (scan.seen[i] || slot[static_cast<std::size_t>(m.labels[i])] != i + 1)) continue;
        if (!absent.empty()) absent += ',';
        absent += std::to_string(m.labels[i]);
    }
    if (!absent.empty())
        throw InputError(source + ": no voxel has the label(s) " + absent + " (of " + labels_text(m) + "): a typo, or the wrong volume?");
}

// The label field (levelset3.hpp, label mode) on the box [lo, lo + n) of
// v's voxels (its own indices): the region's mask over the box, its sources,
// the banded distances.  `feature` (banded_distance's): of the voxels in
// the box `counted` [lo, hi) (own indices; none: all).  `release`: v's
// samples are released once the mask is read from them.
using Index3 = std::array<std::int64_t, 3>;
double label_cap(const Volume& v, int band) { return band * std::max({v.spacing[0], v.spacing[1], v.spacing[2]}); }
Buffer<float> label_field(const Volume& v, int band, std::uint64_t max_memory, const std::vector<std::uint16_t>& slot, const Index3& lo,
                          const Index3& n, double& feature, Volume* release, const std::array<Index3, 2>* counted = nullptr) {
    const std::uint64_t count = static_cast<std::uint64_t>(n[0]) * static_cast<std::uint64_t>(n[1]) * static_cast<std::uint64_t>(n[2]);
    const std::array<double, 3> w{v.spacing[0], v.spacing[1], v.spacing[2]};
    const double c = 0.5 * std::min({w[0], w[1], w[2]}), cap = label_cap(v, band);
    const Slabs sl = slabs_of(cap + 2 * c, w[2]);
    // The mask and the field (1 + 4 bytes a voxel of the box), and a slab of the transforms'.
    const std::uint64_t window = static_cast<std::uint64_t>(std::min(n[2], sl.slab + 2 * sl.halo));
    check_memory(count * 5 + count / static_cast<std::uint64_t>(n[2]) * window * 4, max_memory,
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
    for (std::int64_t q = 0; counted && q < static_cast<std::int64_t>(count); ++q) {
        const Index3 at{lo[0] + q % n[0], lo[1] + q / n[0] % n[1], lo[2] + q / (n[0] * n[1])};
        bool in = true;
        for (std::size_t a = 0; a < 3; ++a) in = in && at[a] >= (*counted)[0][a] && at[a] < (*counted)[1][a];
        if (!in) region[static_cast<std::size_t>(q)] |= uncounted;
    }
    if (release) Buffer<std::uint16_t>().swap(release->labels), std::vector<double>().swap(release->values);
    mark_sources(region, n);
    return banded_distance(region, n, w, c, cap, feature);
}

std::string label_name(const Volume& v, const ImageLevelSetOptions& m) { return v.source + " (label " + labels_text(m) + ")"; }

// Label mode (levelset3.hpp).  The volume's samples are read twice — the
// scan, then the region's mask over its box — and may be released after
// that (`release`: the caller's volume, whose samples nothing needs later);
// the field is built from the mask alone (banded_distance).  A part's:
// label_part_levelset.
std::unique_ptr<LevelSet3> label_part_levelset(const Volume& v, const VolumeLevelSet3Options& o);
std::unique_ptr<LevelSet3> label_levelset(const Volume& v, const VolumeLevelSet3Options& o, Volume* release) {
    const auto& m = o.mode;
    if (!m.label_nonzero && m.labels.empty()) throw InputError("label mode needs labels: a label list (e.g. 3 or 51,52) or nonzero");
    if (v.is_part() || o.whole) return label_part_levelset(v, o);
    const std::vector<std::uint16_t> slot = region_slots(m);
    const RegionScan scan = scan_region(v, m, slot);
    check_region(scan, m, slot, v.source);
    Index3 lo{}, n{};
    for (std::size_t a = 0; a < 3; ++a) {
        lo[a] = std::max<std::int64_t>(0, scan.lo[a] - o.band);
        n[a] = std::min<std::int64_t>(v.dims[a] - 1, scan.hi[a] + o.band) - lo[a] + 1;
    }
    double feature = 0;
    Buffer<float> field = label_field(v, o.band, o.max_memory, slot, lo, n, feature, release);
    if (!std::isfinite(feature)) feature = 0;  // unknown: deeper than the band somewhere
    auto f = std::make_unique<VolumeLevelSet3>(v, std::move(field), lo, n, scan.lo, scan.hi, static_cast<float>(label_cap(v, o.band)),
                                               feature, 1.0, label_name(v, m));
    f->set_reference_volume(static_cast<double>(scan.voxels) * v.spacing[0] * v.spacing[1] * v.spacing[2]);
    return f;
}

// A part's place in the whole volume (Volume::is_part; a whole volume:
// itself): its offset and the whole's voxels; InputError unless it lies in it.
struct PartPlace {
    Index3 off, whole;
};
PartPlace place_of(const Volume& v) {
    const PartPlace p{v.is_part() ? v.part_offset : Index3{0, 0, 0}, v.is_part() ? v.whole_dims : v.dims};
    for (std::size_t a = 0; a < 3; ++a)
        if (!(p.off[a] >= 0 && v.dims[a] >= 1 && p.off[a] + v.dims[a] <= p.whole[a]))
            throw InputError(v.source + ": the part does not lie in the whole volume");
    return p;
}

// The part's voxels [lo, hi] (whole indices) whose label values are the
// whole volume's: label_reach from its faces that cut the volume.
std::array<Index3, 2> exact_zone(const Volume& v, const PartPlace& p, int band) {
    const Index3 k = label_reach(v.spacing, band);
    std::array<Index3, 2> z{};
    for (std::size_t a = 0; a < 3; ++a) {
        z[0][a] = p.off[a] + (p.off[a] > 0 ? k[a] : 0);
        z[1][a] = p.off[a] + v.dims[a] - 1 - (p.off[a] + v.dims[a] < p.whole[a] ? k[a] : 0);
    }
    return z;
}

std::string index_text(const Index3& x) {
    return "(" + std::to_string(x[0]) + ", " + std::to_string(x[1]) + ", " + std::to_string(x[2]) + ")";
}

// LabelRegionFacts::of: the band and the voxel size.
std::string facts_of(const Volume& v, int band) {
    std::ostringstream s;
    s << "band " << band << ", voxel " << v.spacing[0] << " x " << v.spacing[1] << " x " << v.spacing[2];
    return s.str();
}

// The whole region's facts given to a part: of its labels, band, voxel
// size and volume, and merged (of the whole volume).
void check_whole_facts(const LabelRegionFacts& w, const Volume& v, const VolumeLevelSet3Options& o, const PartPlace& place) {
    const std::string mine = "labels " + labels_text(o.mode) + ", " + facts_of(v, o.band) + ", volume " + index_text(place.whole);
    const std::string theirs = "labels " + w.labels + ", " + w.of + ", volume " + index_text(w.whole);
    if (mine != theirs) throw InputError(v.source + ": the region's facts are of " + theirs + ", not of this part's " + mine);
    if (w.owned_lo != Index3{0, 0, 0} || w.owned_hi != w.whole)
        throw InputError(v.source + ": the region's facts are of the voxels [" + index_text(w.owned_lo) + ", " + index_text(w.owned_hi) +
                         ") (i, j, k) only, not of the whole volume: merge the parts' facts first (merge_region_facts)");
    for (std::size_t a = 0; a < 3; ++a)
        if (!(w.lo[a] >= 0 && w.lo[a] <= w.hi[a] && w.hi[a] < w.whole[a] && w.voxels > 0))
            throw InputError(v.source + ": the region's facts give no region (an empty region, or facts not made by merge_region_facts)");
}

// A part's label level set (levelset3.hpp, "One region of a label volume in
// parts"): the field on the whole's stored box (the whole region's box grown
// by the band) within the part, kept on its exact zone; bounds, minimum,
// feature size and reference volume from the whole region's facts.
std::unique_ptr<LevelSet3> label_part_levelset(const Volume& v, const VolumeLevelSet3Options& o) {
    if (!v.is_part()) throw InputError(v.source + ": the whole region's facts apply to a part of a volume, and this volume is whole");
    if (!o.whole)
        throw InputError(v.source + ": a part of a volume in label mode needs the whole region's facts (its box, voxels, field minimum "
                                    "and depth: the reduction over the volume's parts, merge_region_facts)");
    const LabelRegionFacts& w = *o.whole;
    const PartPlace place = place_of(v);
    check_whole_facts(w, v, o, place);
    const std::vector<std::uint16_t> slot = region_slots(o.mode);
    scan_region(v, o.mode, slot);  // refuses values that are no labels (the mask looks them up)
    const std::array<Index3, 2> zone = exact_zone(v, place, o.band);
    Index3 blo{}, bhi{}, qlo{}, qn{}, slo{}, sn{};
    bool kept = true;
    for (std::size_t a = 0; a < 3; ++a) {
        blo[a] = std::max<std::int64_t>(0, w.lo[a] - o.band), bhi[a] = std::min<std::int64_t>(place.whole[a] - 1, w.hi[a] + o.band);
        qlo[a] = std::max(blo[a], place.off[a]);
        qn[a] = std::min(bhi[a], place.off[a] + v.dims[a] - 1) - qlo[a] + 1;
        slo[a] = std::max(blo[a], zone[0][a]);
        sn[a] = std::min(bhi[a], zone[1][a]) - slo[a] + 1;
        kept = kept && sn[a] > 0;
    }
    Buffer<float> values;
    if (kept) {
        double feature = 0;
        const Index3 local{qlo[0] - place.off[0], qlo[1] - place.off[1], qlo[2] - place.off[2]};
        const Buffer<float> field = label_field(v, o.band, o.max_memory, slot, local, qn, feature, nullptr);
        values.resize(static_cast<std::size_t>(sn[0] * sn[1] * sn[2]));
        for (std::int64_t k = 0; k < sn[2]; ++k)
            for (std::int64_t j = 0; j < sn[1]; ++j)
                std::copy_n(field.data() + (slo[0] - qlo[0]) + qn[0] * (slo[1] - qlo[1] + j + qn[1] * (slo[2] - qlo[2] + k)), sn[0],
                            values.data() + sn[0] * (j + sn[1] * k));
    } else {
        sn = {0, 0, 0};
    }
    auto f = std::make_unique<VolumeLevelSet3>(v, std::move(values), slo, sn, w.lo, w.hi, static_cast<float>(label_cap(v, o.band)),
                                               std::isfinite(w.deepest) ? w.deepest : 0.0, 1.0, label_name(v, o.mode));
    f->set_reference_volume(static_cast<double>(w.voxels) * v.spacing[0] * v.spacing[1] * v.spacing[2]);
    f->set_part(w.lowest, blo, bhi);
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
    const Index3 dims = volume.is_part() ? volume.whole_dims : volume.dims;
    for (std::size_t a = 0; a < 3; ++a) {
        if (dims[a] < 2)
            throw InputError(volume.source + ": a 3D mesh needs at least 2 voxels along every axis (" + std::to_string(dims[0]) +
                             " x " + std::to_string(dims[1]) + " x " + std::to_string(dims[2]) + ")");
        if (!axis_aligned(volume.axes[a])) throw InputError(volume.source + ": oblique orientations are not supported");
    }
    if (options.band < 2) throw InputError("the distance band must be at least 2 voxels");
    if (options.mode.mode == ImageMode::label) return label_levelset(volume, options, release);
    if (volume.is_part() || options.whole)
        throw InputError(volume.source + ": a part of a volume is meshed in label mode only (threshold mode's iso and bounds are "
                                         "the whole volume's)");
    return threshold_levelset(volume, options);
}

}  // namespace

std::unique_ptr<LevelSet3> make_volume_levelset3(const Volume& volume, const VolumeLevelSet3Options& options) {
    return volume_levelset3(volume, options, nullptr);
}

std::unique_ptr<LevelSet3> make_volume_levelset3(Volume&& volume, const VolumeLevelSet3Options& options) {
    return volume_levelset3(volume, options, &volume);
}

std::array<std::int64_t, 3> label_reach(const std::array<double, 3>& spacing, int band) {
    const double c = 0.5 * std::min({spacing[0], spacing[1], spacing[2]}), cap = band * std::max({spacing[0], spacing[1], spacing[2]});
    std::array<std::int64_t, 3> k{};
    for (std::size_t a = 0; a < 3; ++a) k[a] = static_cast<std::int64_t>(std::ceil((cap + 2 * c) / spacing[a])) + 1;
    return k;
}

LabelRegionFacts label_part_facts(const Volume& v, const VolumeLevelSet3Options& o, const std::array<std::int64_t, 3>& owned_lo,
                                  const std::array<std::int64_t, 3>& owned_hi) {
    const ImageLevelSetOptions& m = o.mode;
    if (m.mode != ImageMode::label) throw InputError("the region's facts are of label mode (labels), not of threshold mode");
    if (!m.label_nonzero && m.labels.empty()) throw InputError("label mode needs labels: a label list (e.g. 3 or 51,52) or nonzero");
    if (o.band < 2) throw InputError("the distance band must be at least 2 voxels");
    const PartPlace place = place_of(v);
    const std::string own = "[" + index_text(owned_lo) + ", " + index_text(owned_hi) + ")";
    for (std::size_t a = 0; a < 3; ++a)
        if (!(owned_lo[a] >= 0 && owned_lo[a] < owned_hi[a] && owned_hi[a] <= place.whole[a]))
            throw InputError(v.source + ": the part's own voxels " + own + " (i, j, k) are not a box of the volume's " +
                             index_text(place.whole));
    const std::array<Index3, 2> zone = exact_zone(v, place, o.band);
    for (std::size_t a = 0; a < 3; ++a)
        if (owned_lo[a] < zone[0][a] || owned_hi[a] - 1 > zone[1][a])
            throw InputError(v.source + ": the part [" + index_text(place.off) + ", " +
                             index_text({place.off[0] + v.dims[0], place.off[1] + v.dims[1], place.off[2] + v.dims[2]}) +
                             ") (i, j, k) does not hold the voxels within " + index_text(label_reach(v.spacing, o.band)) + " of its own " +
                             own + ", on which their values depend: read the part region_part_voxels names");
    LabelRegionFacts f;
    f.labels = labels_text(m), f.of = facts_of(v, o.band), f.whole = place.whole, f.owned_lo = owned_lo, f.owned_hi = owned_hi;
    const std::vector<std::uint16_t> slot = region_slots(m);
    const RegionScan scan = scan_region(v, m, slot);
    f.seen = scan.seen;
    if (scan.voxels == 0) return f;
    Index3 lo{}, n{};
    std::array<Index3, 2> counted{};
    for (std::size_t a = 0; a < 3; ++a) {
        lo[a] = std::max<std::int64_t>(0, scan.lo[a] - o.band);
        n[a] = std::min<std::int64_t>(v.dims[a] - 1, scan.hi[a] + o.band) - lo[a] + 1;
        counted[0][a] = owned_lo[a] - place.off[a], counted[1][a] = owned_hi[a] - place.off[a];
    }
    double deepest = 0, lowest = std::numeric_limits<double>::infinity();
    const Buffer<float> field = label_field(v, o.band, o.max_memory, slot, lo, n, deepest, nullptr, &counted);
    // The region's own voxels: those of negative value (levelset3.hpp: the sign is the class).
    for (std::int64_t k = std::max(lo[2], counted[0][2]); k < std::min(lo[2] + n[2], counted[1][2]); ++k)
        for (std::int64_t j = std::max(lo[1], counted[0][1]); j < std::min(lo[1] + n[1], counted[1][1]); ++j)
            for (std::int64_t i = std::max(lo[0], counted[0][0]); i < std::min(lo[0] + n[0], counted[1][0]); ++i) {
                const float x = field[static_cast<std::size_t>(i - lo[0] + n[0] * (j - lo[1] + n[1] * (k - lo[2])))];
                if (!(x < 0)) continue;
                const Index3 q{i + place.off[0], j + place.off[1], k + place.off[2]};
                for (std::size_t a = 0; a < 3; ++a) f.lo[a] = f.voxels ? std::min(f.lo[a], q[a]) : q[a], f.hi[a] = std::max(f.hi[a], q[a]);
                ++f.voxels;
                lowest = std::min(lowest, static_cast<double>(x));
            }
    if (f.voxels > 0) f.lowest = lowest, f.deepest = deepest;
    return f;
}

LabelRegionFacts merge_label_facts(std::span<const LabelRegionFacts> parts, const std::string& source) {
    if (parts.empty()) throw InputError("the region's facts do not merge: no parts");
    const LabelRegionFacts& a = parts.front();
    const auto what = [](const LabelRegionFacts& x) { return "labels " + x.labels + ", " + x.of + ", volume " + index_text(x.whole); };
    LabelRegionFacts w;
    w.labels = a.labels, w.of = a.of, w.whole = a.whole, w.owned_hi = a.whole, w.seen.assign(a.seen.size(), 0);
    w.lowest = std::numeric_limits<double>::infinity();
    const auto box = [](const LabelRegionFacts& x) { return "[" + index_text(x.owned_lo) + ", " + index_text(x.owned_hi) + ")"; };
    std::int64_t held = 0;
    for (std::size_t i = 0; i < parts.size(); ++i) {
        const LabelRegionFacts& p = parts[i];
        const std::string which = "part " + std::to_string(i);
        if (what(p) != what(a) || p.seen.size() != a.seen.size())
            throw InputError("the region's facts do not merge: " + which + "'s are of " + what(p) + ", part 0's of " + what(a));
        bool overlap = true;
        for (std::size_t k = 0; k < 3; ++k)
            if (!(p.owned_lo[k] >= 0 && p.owned_lo[k] < p.owned_hi[k] && p.owned_hi[k] <= a.whole[k]))
                throw InputError("the region's facts do not merge: " + which + "'s voxels " + box(p) + " are not a box of the volume");
        held += (p.owned_hi[0] - p.owned_lo[0]) * (p.owned_hi[1] - p.owned_lo[1]) * (p.owned_hi[2] - p.owned_lo[2]);
        for (std::size_t j = 0; j < i; ++j, overlap = true) {
            for (std::size_t k = 0; k < 3; ++k)
                overlap = overlap && p.owned_lo[k] < parts[j].owned_hi[k] && parts[j].owned_lo[k] < p.owned_hi[k];
            if (overlap)
                throw InputError("the region's facts do not merge: parts " + std::to_string(j) + " and " + std::to_string(i) +
                                 " overlap (" + box(parts[j]) + " and " + box(p) + "), or a part is given twice");
        }
        for (std::size_t k = 0; k < w.seen.size(); ++k) w.seen[k] |= p.seen[k];
        if (p.voxels == 0) continue;
        for (std::size_t k = 0; k < 3; ++k)
            w.lo[k] = w.voxels ? std::min(w.lo[k], p.lo[k]) : p.lo[k], w.hi[k] = std::max(w.hi[k], p.hi[k]);
        w.voxels += p.voxels, w.lowest = std::min(w.lowest, p.lowest), w.deepest = std::max(w.deepest, p.deepest);
    }
    if (held != a.whole[0] * a.whole[1] * a.whole[2])
        throw InputError("the region's facts do not merge: the parts hold " + std::to_string(held) + " of the volume's " +
                         std::to_string(a.whole[0] * a.whole[1] * a.whole[2]) + " voxels: a part is missing");
    if (w.voxels == 0) w.lowest = 0;
    // Refused as make_volume_levelset3 refuses the whole volume.
    const ImageLevelSetOptions m = label_options(a.labels);
    check_region(RegionScan{w.lo, w.voxels ? w.hi : Index3{-1, -1, -1}, w.voxels, w.seen}, m, region_slots(m), source);
    return w;
}

}  // namespace warpmesh
