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
// distance transform (one pass of squared distances per index axis, weighted
// by the spacings) gives d_out at every voxel outside (the distance to the
// nearest centre inside) and d_in at every voxel inside; f = d_out − c
// outside and −(d_in − c) inside, c half the smallest spacing, so along the
// axis of the smallest spacing f is antisymmetric about the midpoint between
// a voxel and its neighbour of the other class and the trilinear
// interpolant's zero passes there.  Only the region's bounding box grown by
// `band` voxels is stored (as floats); f is clamped to ±band × the largest
// spacing, which farther voxels get without being stored.  The labels stay
// 16-bit integers (Volume::labels) up to the region's mask over that box (1
// byte a voxel); the transforms run on the mask plane by plane through a ring
// of planes of the band's reach (banded_distance), start from the voxels on
// the region's surface only (row_sources), drop distances beyond the band
// after each pass and skip what lies beyond it (Planes), so their work
// follows the surface and their memory is a ring's; the region's inscribed
// distance (feature_size) is then known only within the band.
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

// The transforms' sources: the voxels of each class (the region's, or the
// rest's) with a 6-neighbour of the other class in the box.  The nearest
// voxel of a class to a voxel p of the other class is one of them: a voxel
// q of the class without such a neighbour has a neighbour of its class one
// step nearer p along an axis where q − p is non-zero, and a transform's
// value (rounded sums of the squared offsets, axis by axis) never grows as
// one axis's offset shrinks.  So the fields are those of the transforms from
// every voxel of the class (to the last bit, unless two sources tie within
// rounding), at the cost of a surface's worth of sources.  On row (j, k) of
// the mask m (1 in the region, 0 elsewhere): e[i] = 1 where voxel i is a
// source (of its class); false if the row has none.
bool row_sources(const std::uint8_t* m, std::int64_t j, std::int64_t k, const std::array<std::int64_t, 3>& n, std::uint8_t* e) {
    const std::int64_t n0 = n[0], plane = n[0] * n[1];
    // A neighbour's row beyond the box: the row itself, which differs nowhere.
    const std::uint8_t *y0 = j > 0 ? m - n0 : m, *y1 = j + 1 < n[1] ? m + n0 : m;
    const std::uint8_t *z0 = k > 0 ? m - plane : m, *z1 = k + 1 < n[2] ? m + plane : m;
    for (std::int64_t i = 0; i < n0; ++i) e[i] = (m[i] ^ y0[i]) | (m[i] ^ y1[i]) | (m[i] ^ z0[i]) | (m[i] ^ z1[i]);
    for (std::int64_t i = 1; i < n0; ++i) e[i] |= m[i] ^ m[i - 1];
    for (std::int64_t i = 0; i + 1 < n0; ++i) e[i] |= m[i] ^ m[i + 1];
    return std::any_of(e, e + n0, [](std::uint8_t x) { return x != 0; });
}

// The passes.  Every squared distance the transforms keep is at most
// `limit`, so along an axis of spacing w a value reaches another only over
// offsets d with w² d² <= limit, and the pass g(i) → min_j g(j) + w² (i −
// j)² is the least of those few candidates: g(i + d) + b[|d|], b[d] = w² d²
// (in doubles from the float values, the sums Felzenszwalb and
// Huttenlocher's lower envelope of parabolas compares: its value, wherever no
// two candidates tie within rounding).  The first pass starts from 0 at the sources and +inf elsewhere:
// its value is the float of b[d] for the nearest source, d offsets away.
// The offsets' terms, b[0] = 0 first:
std::vector<double> offset_terms(double w, double limit) {
    std::vector<double> b;
    for (std::int64_t d = 0; w * w * static_cast<double>(d * d) <= limit; ++d) b.push_back(w * w * static_cast<double>(d * d));
    return b;
}

// Planes of n0 × n1 squared distances (x fastest), each row cut into chunks
// of `chunk` values (the last one padded with +inf) with a flag: set when the
// chunk may hold a finite value.  A chunk whose flag is clear is +inf
// throughout: its values are neither written nor read.  A row's last flag:
// whether any chunk's is set.  The passes along y and z keep x, so a chunk's
// candidates are the same chunk of other rows, and a chunk with no flagged
// candidate is skipped — the transforms' work follows the band around the
// surface.
struct Planes {
    static constexpr std::int64_t chunk = 16;
    std::int64_t n0, n1, chunks, planes;
    Buffer<float> g;  // a chunk's values written before its flag is set
    std::vector<std::uint8_t> live;
    Planes(std::int64_t x, std::int64_t y, std::int64_t p)
        : n0(x), n1(y), chunks((x + chunk - 1) / chunk), planes(p), g(static_cast<std::size_t>(y * p * chunks * chunk)),
          live(static_cast<std::size_t>(y * p * (chunks + 1)), 0) {}
    float* row(std::int64_t p, std::int64_t j) { return g.data() + (p * n1 + j) * chunks * chunk; }
    std::uint8_t* flags(std::int64_t p, std::int64_t j) { return live.data() + (p * n1 + j) * (chunks + 1); }
};
struct Row {
    const float* values = nullptr;  // nullptr: beyond the box
    const std::uint8_t* flags = nullptr;
};

// One row of a pass along y or z, chunk by chunk: acc[x] = min_d in(d)[x] +
// b[|d|] over |d| < b.size(), in(d) the row at offset d, for the chunks c
// with need[c]; any[c] is set where some row's chunk is flagged (elsewhere
// every candidate is +inf and acc is not written).
template <class In>
void least_candidates(const In& in, const std::vector<double>& b, const std::uint8_t* need, std::int64_t chunks, double* acc,
                      std::uint8_t* any) {
    constexpr std::int64_t w = Planes::chunk;
    std::fill_n(any, chunks, 0);
    const std::int64_t r = static_cast<std::int64_t>(b.size()) - 1;
    for (std::int64_t d = -r; d <= r; ++d) {
        const Row from = in(d);
        if (!from.values || !from.flags[chunks]) continue;
        const double bd = b[static_cast<std::size_t>(std::abs(d))];
        for (std::int64_t c = 0; c < chunks; ++c) {
            if (!from.flags[c] || !need[c]) continue;
            double* a = acc + c * w;
            const float* f = from.values + c * w;
            if (any[c]) {
#pragma omp simd
                for (std::int64_t x = 0; x < w; ++x) {
                    const double v = static_cast<double>(f[x]) + bd, old = a[x];
                    a[x] = v < old ? v : old;
                }
            } else {
#pragma omp simd
                for (std::int64_t x = 0; x < w; ++x) a[x] = static_cast<double>(f[x]) + bd;
            }
            any[c] = 1;
        }
    }
}

// Per thread: the row's sources (e), a row of candidates for each transform,
// the chunks computed (every: all of them; need) and those with a candidate (any).
struct Scratch {
    std::vector<std::uint8_t> e, every, need[2], any[2];
    std::vector<double> acc[2];
    explicit Scratch(const Planes& p) : e(static_cast<std::size_t>(p.n0)), every(static_cast<std::size_t>(p.chunks), 1) {
        for (std::size_t t = 0; t < 2; ++t) {
            need[t].resize(static_cast<std::size_t>(p.chunks)), any[t].resize(static_cast<std::size_t>(p.chunks));
            acc[t].resize(static_cast<std::size_t>(p.chunks * Planes::chunk));
        }
    }
};

// The two transforms (t = 0: from the region's sources, read outside; t = 1:
// from the other class's, read inside) on plane k, in place of the whole
// box's first two passes: the x pass into xs's plane t (each source's offsets
// b0, as floats), then the y pass from it into ys[t]'s plane `slot`.  Values
// above `limit` become +inf after each pass (a later pass only adds to a
// value).  Called by every thread of a parallel region, each taking rows.
void xy_passes(std::span<const std::uint8_t> mask, std::int64_t k, const std::array<std::int64_t, 3>& n, const std::vector<float>& b0,
               const std::vector<double>& b1, double limit, Planes& xs, std::array<Planes, 2>& ys, std::int64_t slot, Scratch& s) {
    constexpr std::int64_t w = Planes::chunk;
    constexpr float inf = std::numeric_limits<float>::infinity();
    const std::int64_t n0 = n[0], n1 = n[1], chunks = xs.chunks, r0 = static_cast<std::int64_t>(b0.size()) - 1;
#pragma omp for schedule(static)
    for (std::int64_t j = 0; j < n1; ++j) {
        const std::uint8_t* m = mask.data() + (k * n1 + j) * n0;
        const bool any = row_sources(m, j, k, n, s.e.data());
        for (std::int64_t t = 0; t < 2; ++t) {
            std::fill_n(xs.flags(t, j), chunks + 1, 0);
            if (any) std::fill_n(xs.row(t, j), chunks * w, inf);
        }
        for (std::int64_t i = 0; any && i < n0; ++i) {
            if (!s.e[static_cast<std::size_t>(i)]) continue;
            const std::int64_t t = 1 - m[i], lo = std::max<std::int64_t>(0, i - r0), hi = std::min(n0 - 1, i + r0);
            float* g = xs.row(t, j);
            for (std::int64_t x = lo; x <= hi; ++x) g[x] = std::min(g[x], b0[static_cast<std::size_t>(std::abs(x - i))]);
            std::fill(xs.flags(t, j) + lo / w, xs.flags(t, j) + hi / w + 1, std::uint8_t{1});
            xs.flags(t, j)[chunks] = 1;
        }
    }
#pragma omp for schedule(static)
    for (std::int64_t j = 0; j < n1; ++j)
        for (std::size_t t = 0; t < 2; ++t) {
            const auto in = [&](std::int64_t d) {
                const std::int64_t y = j + d, plane = static_cast<std::int64_t>(t);
                return y < 0 || y >= n1 ? Row{} : Row{xs.row(plane, y), xs.flags(plane, y)};
            };
            least_candidates(in, b1, s.every.data(), chunks, s.acc[t].data(), s.any[t].data());
            float* out = ys[t].row(slot, j);
            std::uint8_t* flags = ys[t].flags(slot, j);
            flags[chunks] = 0;
            for (std::int64_t c = 0; c < chunks; ++c) {
                bool finite = false;
                if (s.any[t][static_cast<std::size_t>(c)])
                    for (std::int64_t x = c * w; x < (c + 1) * w; ++x) {
                        const double a = s.acc[t][static_cast<std::size_t>(x)];
                        out[x] = a > limit ? inf : static_cast<float>(a);
                        finite |= a <= limit;
                    }
                flags[c] = finite;
                flags[chunks] |= finite;
            }
        }
}

// The field's values on plane z: the z pass of both transforms over ys's
// planes z − r .. z + r (plane p in slot p mod the ring's planes), then at
// each voxel, from the transform of the other class's sources, f = ±(√d² −
// c) clamped to [−cap, cap] (− inside), ±cap where d² is +inf (beyond the
// band).  `deepest`: the largest d − c inside the region at the voxels of
// the box `counted` [lo, hi), +inf if such a voxel is beyond the band.
void field_plane(std::span<const std::uint8_t> mask, std::int64_t z, std::int64_t n2, const std::vector<double>& b2, double limit, double c,
                 double cap, std::array<Planes, 2>& ys, std::span<float> field, const std::array<std::array<std::int64_t, 3>, 2>& counted,
                 double& deepest, Scratch& s) {
    constexpr std::int64_t w = Planes::chunk;
    constexpr double inf = std::numeric_limits<double>::infinity();
    const std::int64_t n0 = ys[0].n0, n1 = ys[0].n1, chunks = ys[0].chunks, ring = ys[0].planes;
    const bool plane_counted = z >= counted[0][2] && z < counted[1][2];
#pragma omp for schedule(static)
    for (std::int64_t j = 0; j < n1; ++j) {
        const std::uint8_t* m = mask.data() + (z * n1 + j) * n0;
        float* f = field.data() + (z * n1 + j) * n0;
        const bool row_counted = plane_counted && j >= counted[0][1] && j < counted[1][1];
        const auto deep = [&](std::int64_t x) { return row_counted && x >= counted[0][0] && x < counted[1][0]; };
        for (std::size_t ch = 0; ch < static_cast<std::size_t>(chunks); ++ch) {  // whether a voxel of the chunk reads transform t
            std::uint8_t some = 0, all = 1;
            for (std::int64_t x = static_cast<std::int64_t>(ch) * w; x < std::min(n0, static_cast<std::int64_t>(ch + 1) * w); ++x)
                some |= m[x], all &= m[x];
            s.need[0][ch] = !all, s.need[1][ch] = some;
        }
        for (std::size_t t = 0; t < 2; ++t) {
            const auto in = [&](std::int64_t d) {
                const std::int64_t p = z + d;
                return p < 0 || p >= n2 ? Row{} : Row{ys[t].row(p % ring, j), ys[t].flags(p % ring, j)};
            };
            least_candidates(in, b2, s.need[t].data(), chunks, s.acc[t].data(), s.any[t].data());
        }
        for (std::size_t ch = 0; ch < static_cast<std::size_t>(chunks); ++ch) {
            const std::int64_t x0 = static_cast<std::int64_t>(ch) * w, x1 = std::min(n0, x0 + w);
            if (!s.any[0][ch] && !s.any[1][ch]) {  // every voxel beyond the band: ±cap (what the clamp gives)
                for (std::int64_t x = x0; x < x1; ++x) {
                    f[x] = static_cast<float>(m[x] ? -cap : cap);
                    if (m[x] && deep(x)) deepest = inf;
                }
                continue;
            }
            for (std::int64_t x = x0; x < x1; ++x) {
                const std::uint8_t inside = m[x];
                const double di = s.any[inside][ch] ? s.acc[inside][static_cast<std::size_t>(x)] : inf;
                const float d2 = di > limit ? std::numeric_limits<float>::infinity() : static_cast<float>(di);
                if (!(d2 < std::numeric_limits<float>::infinity())) {  // beyond the band
                    if (inside && deep(x)) deepest = inf;
                    f[x] = static_cast<float>(inside ? -cap : cap);
                    continue;
                }
                const double d = std::sqrt(static_cast<double>(d2)) - c;
                if (inside && deep(x)) deepest = std::max(deepest, d);
                f[x] = static_cast<float>(std::clamp(inside ? -d : d, -cap, cap));
            }
        }
    }
}

// The label field (levelset3.hpp, label mode) on the box of n voxels whose
// mask is `region` (1 in the region, 0 elsewhere): f = d_out − c outside
// and −(d_in − c) inside, clamped to [−cap, cap].  Exact wherever |f| < cap:
// a value there is a distance below cap + c to a source, and the transforms
// keep every squared distance up to limit = (cap + 2c)², so a source within
// cap + 2c of a voxel is seen.  Both transforms run plane by plane along
// index axis 2: the x and y passes of plane k into a ring of 2r + 1 planes (r
// the z pass's largest offset), then the z pass of plane k − r, whose
// candidates are the ring's planes.  So the work and memory beyond the field
// are a ring's.  `feature`: the largest inscribed distance at the voxels of
// the box `counted` [lo, hi) (a part's own voxels; the whole box: [0, n)),
// +inf where it is beyond the band.
Buffer<float> banded_distance(std::span<const std::uint8_t> region, const std::array<std::int64_t, 3>& n, const std::array<double, 3>& w,
                              double c, double cap, const std::array<std::array<std::int64_t, 3>, 2>& counted, double& feature) {
    const double limit = (cap + 2 * c) * (cap + 2 * c);
    const std::vector<double> b1 = offset_terms(w[1], limit), b2 = offset_terms(w[2], limit);
    std::vector<float> b0;
    for (const double b : offset_terms(w[0], limit)) b0.push_back(static_cast<float>(b));
    const std::int64_t r = static_cast<std::int64_t>(b2.size()) - 1;
    Buffer<float> field(static_cast<std::size_t>(n[0] * n[1] * n[2]));  // every element written below (field_plane)
    Planes xs(n[0], n[1], 2);
    std::array<Planes, 2> ys{Planes(n[0], n[1], 2 * r + 1), Planes(n[0], n[1], 2 * r + 1)};
    double deepest = 0;
#pragma omp parallel reduction(max : deepest)
    {
        Scratch s(xs);
        for (std::int64_t k = 0; k < n[2] + r; ++k) {
            if (k < n[2]) xy_passes(region, k, n, b0, b1, limit, xs, ys, k % (2 * r + 1), s);
            if (k >= r) field_plane(region, k - r, n[2], b2, limit, c, cap, ys, field, counted, deepest, s);
        }
    }
    feature = deepest;
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
    const auto scan = [&](const auto& label) {  // label(q): voxel q's label
        for (std::int64_t k = 0; k < v.dims[2]; ++k)
            for (std::int64_t j = 0; j < v.dims[1]; ++j) {
                const std::size_t row = static_cast<std::size_t>(v.dims[0] * (j + v.dims[1] * k));
                std::int64_t first = -1, last = -1;
                for (std::int64_t i = 0; i < v.dims[0]; ++i) {
                    const std::size_t x = label(row + static_cast<std::size_t>(i));
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
    };
    if (!v.labels.empty()) {
        scan([&](std::size_t q) -> std::size_t { return v.labels[q]; });
    } else {
        scan([&](std::size_t q) -> std::size_t {
            const double d = v.values[q];
            // In 0..65535, then an integer (the cast is exact there).
            if (!(d >= 0 && d <= 65535) || static_cast<double>(static_cast<std::int32_t>(d)) != d)
                throw InputError(v.source + ": label mode needs integer voxel values in 0..65535 (found " + std::to_string(d) + ")");
            return static_cast<std::size_t>(d);
        });
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
    // The mask and the field (1 + 4 bytes a voxel of the box), and the transforms' planes (banded_distance: 2 (2r + 2)).
    const std::uint64_t planes = 4 * offset_terms(w[2], (cap + 2 * c) * (cap + 2 * c)).size();
    check_memory(count * 5 + count / static_cast<std::uint64_t>(n[2]) * planes * 4, max_memory,
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
    std::array<Index3, 2> mine{Index3{}, n};  // `counted` in the box's indices
    for (std::size_t a = 0; counted && a < 3; ++a)
        mine[0][a] = std::clamp((*counted)[0][a] - lo[a], std::int64_t{0}, n[a]), mine[1][a] = std::clamp((*counted)[1][a] - lo[a], mine[0][a], n[a]);
    return banded_distance(region, n, w, c, cap, mine, feature);
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
