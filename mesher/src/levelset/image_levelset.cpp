// image_levelset.cpp — threshold and label level sets on images.
//
// Both modes are a bilinear interpolant of one number per pixel centre (the
// `field`).  On the cell [c, c+1] x [y, y+1] between four pixel centres,
//
//     f(x, y) = (1-fy) ((1-fx) f00 + fx f10) + fy ((1-fx) f01 + fx f11),
//
// fx = x - c, fy = y - y0.  With y fixed, f is linear in x inside each cell,
// and continuous across cells: along a horizontal (or vertical) line f is
// piecewise linear with knots at the integers.  So the zero of f on a lattice
// edge is found exactly by evaluating f at the integer knots the edge spans
// and interpolating linearly inside the one sub-segment whose ends differ in
// sign.  On a lattice whose points are the pixel centres (x0 = 0, s = 1) an
// edge spans no knot and the cut point is u = fa / (fa - fb) — marching
// squares' linear interpolation, here exact rather than an approximation.
//
// With a PixelGeometry (pixel size sx, sy and origin x0, y0) all of this
// happens in pixel coordinates ((x - x0) / sx, (y - y0) / sy): the
// interpolant, the knots, the ranges and the region cells.  That map is
// monotone in each coordinate (so boxes map to boxes that contain every
// mapped point, rounding included), and for the default geometry it is the
// identity bit for bit ((x - 0) / 1 == x), so pixel-unit meshes are exactly
// what they were without it.
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

#include "warpmesh/core/errors.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "levelset/knot_walk.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh {
namespace {

// Position of coordinate t on the axis of n pixel centres 0..n-1: the cell
// index c (0 <= c <= n-2, or 0 when n == 1) and the fraction ft in [0, 1].
// Outside [0, n-1] the coordinate is clamped: f is extended as a constant.
inline void locate(double t, int n, int& c, double& ft) {
    t = std::clamp(t, 0.0, static_cast<double>(n - 1));
    c = std::min(static_cast<int>(t), std::max(n - 2, 0));
    ft = t - c;  // exact: c <= t < c + 2 and both are small integers or t
}

}  // namespace

// ---------------------------------------------------------------------------
// ImageField

ImageField::ImageField(int w, int h, std::vector<double> field_y_up, PixelGeometry geometry)
    : w_(w), h_(h), g_(geometry), field_(std::move(field_y_up)) {}

Box ImageField::bounds() const {
    return {g_.x0, g_.y0, g_.x0 + static_cast<double>(w_ - 1) * g_.sx, g_.y0 + static_cast<double>(h_ - 1) * g_.sy};
}

std::string ImageField::describe_geometry() const { return pixel_geometry_text(g_); }

std::string pixel_geometry_text(const PixelGeometry& g) {
    if (g.is_pixels()) return {};
    char buf[160];
    std::snprintf(buf, sizeof buf, ", pixel %.6g x %.6g, origin (%.6g, %.6g)", g.sx, g.sy, g.x0, g.y0);
    return buf;
}

namespace {
// Along one pixel row: the value at fraction fx of cell c.
inline double along_row(const double* row, int c, double fx) {
    return fx == 0 ? row[c] : (1 - fx) * row[c] + fx * row[c + 1];
}
// The interpolant at cell (c, y) with fractions (fx, fy).  At a pixel centre
// (fx = fy = 0) it is the stored value itself; (1-t) a + t b is exact at both
// t = 0 and t = 1, so the interpolant is continuous bit for bit across cells.
inline double interpolate(const double* F, int w, int c, double fx, int y, double fy) {
    const double* row0 = F + static_cast<std::size_t>(y) * static_cast<std::size_t>(w);
    const double v0 = along_row(row0, c, fx);  // p00 itself when fx = 0
    if (fy == 0) return v0;
    const double v1 = along_row(row0 + w, c, fx);
    return (1 - fy) * v0 + fy * v1;
}
}  // namespace

double ImageField::value(double x, double y) const {
    if (!std::isfinite(x) || !std::isfinite(y)) return std::numeric_limits<double>::quiet_NaN();
    return value_px(px(x), py(y));
}

double ImageField::value_px(double x, double y) const {
    int c = 0, r = 0;
    double fx = 0, fy = 0;
    locate(x, w_, c, fx);
    locate(y, h_, r, fy);
    return interpolate(field_.data(), w_, c, fx, r, fy);
}

// The same arithmetic as value() — coordinates from Lattice::position, the
// same locate/interpolate — so that sample_block() and value() agree bit for
// bit; the cell lookup along x is done once per column instead of once per
// point.  And the lattice rows of one pixel row r (several, when the spacing
// is below a pixel) share their horizontal interpolations: interpolate()
// first computes v0 on pixel row r and v1 on row r + 1, each depending only
// on the column, then (1 - fy) v0 + fy v1.  So v0 and v1 are computed once per
// pixel row and column (h0, h1) by the very same expressions, and each point
// costs the last step only.
void ImageField::sample_block(const Lattice& lattice, const PointBlock& b, std::span<double> out) const {
    const std::size_t ni = static_cast<std::size_t>(b.ni);
    // Scratch on the stack for narrow blocks (a graded tile is 17 points
    // wide, and thousands are sampled: heap scratch cost as much as the
    // sampling), else on the heap.
    constexpr std::size_t narrow = 64;
    std::array<int, narrow> col_small;
    std::array<double, narrow> colf_small;
    std::vector<int> col_heap(ni > narrow ? ni : 0);
    std::vector<double> colf_heap(ni > narrow ? ni : 0);
    int* const col = ni > narrow ? col_heap.data() : col_small.data();
    double* const colf = ni > narrow ? colf_heap.data() : colf_small.data();
    bool finite = true;
    for (std::size_t i = 0; i < ni; ++i) {
        const double x = lattice.position(b.i0 + static_cast<std::int64_t>(i), 0).x;
        finite = finite && std::isfinite(x);
        locate(px(x), w_, col[i], colf[i]);
    }
    if (!finite) return LevelSet::sample_block(lattice, b, out);  // value() reports NaN where it belongs
    // v0 or v1 of interpolate() on pixel row `row`, for every column.
    auto horizontal = [&](const double* row, double* h) {
        for (std::size_t i = 0; i < ni; ++i) h[i] = along_row(row, col[i], colf[i]);
    };
    // Rows [j0, j1), with h0 / h1 for the pixel rows last used (r0, r1).
    auto rows = [&](std::int64_t j0, std::int64_t j1) {
        std::array<double, 2 * narrow> h_small;
        std::vector<double> h_heap(ni > narrow ? 2 * ni : 0);
        double *h0 = ni > narrow ? h_heap.data() : h_small.data(), *h1 = h0 + ni;
        int r0 = -1, r1 = -1;
        for (std::int64_t j = j0; j < j1; ++j) {
            const double y = lattice.position(0, b.j0 + j).y;
            double* o = out.data() + j * b.ni;
            if (!std::isfinite(y)) {
                std::fill(o, o + b.ni, std::numeric_limits<double>::quiet_NaN());
                continue;
            }
            int r = 0;
            double fy = 0;
            locate(py(y), h_, r, fy);
            const double* row0 = field_.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(w_);
            if (r != r0) horizontal(row0, h0), r0 = r;
            if (fy == 0) {  // interpolate() returns v0 (p00 itself when fx = 0 too)
                std::copy(h0, h0 + ni, o);
                continue;
            }
            if (r != r1) horizontal(row0 + w_, h1), r1 = r;
            for (std::size_t i = 0; i < ni; ++i) o[i] = (1 - fy) * h0[i] + fy * h1[i];
        }
    };
    // A small block (a tile of the graded front end) runs here: even a
    // parallel region with a false `if` costs microseconds, as much as
    // sampling the block.
    if (b.ni * b.nj < 4096) return rows(0, b.nj);
#pragma omp parallel
    {
        std::int64_t j0 = 0, j1 = b.nj;
#ifdef _OPENMP
        const std::int64_t nt = omp_get_num_threads(), t = omp_get_thread_num();
        j0 = b.nj * t / nt, j1 = b.nj * (t + 1) / nt;
#endif
        rows(j0, j1);
    }
}

// Level k of the pyramid (k >= 1) has blocks of 2^(k+2) pixels a side; level 1
// is made from field_ directly, each further level from the one below.  About
// 1/3 B per pixel.
void ImageField::build_range_pyramid() {
    pyramid_.clear();
    auto blocks = [](int n, int k) { return (n + (1 << (k + 2)) - 1) >> (k + 2); };
    for (int k = 1; (1 << (k + 1)) < std::max(w_, h_); ++k) {
        const int bw = blocks(w_, k), bh = blocks(h_, k);
        std::vector<std::array<double, 2>> lv(static_cast<std::size_t>(bw) * static_cast<std::size_t>(bh),
                                              {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()});
        auto merge = [](std::array<double, 2>& a, double lo, double hi) { a[0] = std::min(a[0], lo), a[1] = std::max(a[1], hi); };
        if (k == 1) {
            for (int y = 0; y < h_; ++y)
                for (int c = 0; c < w_; ++c) {
                    const double v = field_[index(c, y)];
                    merge(lv[static_cast<std::size_t>((y >> 3) * bw + (c >> 3))], v, v);
                }
        } else {
            const auto& below = pyramid_.back();
            const int cw = blocks(w_, k - 1), ch = blocks(h_, k - 1);
            for (int y = 0; y < ch; ++y)
                for (int c = 0; c < cw; ++c) {
                    const auto& v = below[static_cast<std::size_t>(y * cw + c)];
                    merge(lv[static_cast<std::size_t>((y >> 1) * bw + (c >> 1))], v[0], v[1]);
                }
        }
        pyramid_.push_back(std::move(lv));
    }
}

Range ImageField::range(const Box& box) const {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (!(std::isfinite(box.xmin) && std::isfinite(box.xmax) && std::isfinite(box.ymin) && std::isfinite(box.ymax)))
        return {-inf, inf};
    // f on the box is f on the box clamped to the pixel-centre rectangle (f
    // is extended as a constant beyond it), in pixel coordinates.
    const double x0 = std::clamp(px(box.xmin), 0.0, static_cast<double>(w_ - 1)),
                 x1 = std::clamp(px(box.xmax), 0.0, static_cast<double>(w_ - 1)),
                 y0 = std::clamp(py(box.ymin), 0.0, static_cast<double>(h_ - 1)),
                 y1 = std::clamp(py(box.ymax), 0.0, static_cast<double>(h_ - 1));
    const int c0 = static_cast<int>(std::floor(x0)), c1 = static_cast<int>(std::ceil(x1)),
              r0 = static_cast<int>(std::floor(y0)), r1 = static_cast<int>(std::ceil(y1));
    double lo = inf, hi = -inf;
    if (c1 - c0 <= 8 && r1 - r0 <= 8) {
        // Exact for a small box: on each pixel cell f is bilinear, linear in x
        // for fixed y and in y for fixed x, so its extremes on a rectangle are
        // at the rectangle's corners.  The box's pieces in the cells have
        // their corners on the grid {x0, the integers between, x1} x {y0, …}.
        auto knots = [](double a, double b, int ka, int kb, std::array<double, 10>& out) {
            int n = 0;
            out[static_cast<std::size_t>(n++)] = a;
            for (int k = ka + 1; k < kb; ++k) out[static_cast<std::size_t>(n++)] = k;
            if (b > a) out[static_cast<std::size_t>(n++)] = b;
            return n;
        };
        std::array<double, 10> xs{}, ys{};
        const int nxk = knots(x0, x1, c0, c1, xs), nyk = knots(y0, y1, r0, r1, ys);
        // value() at the knots (finite): each coordinate located once.
        std::array<int, 10> kc{}, kr{};
        std::array<double, 10> kfx{}, kfy{};
        for (std::size_t a = 0; a < static_cast<std::size_t>(nxk); ++a) locate(xs[a], w_, kc[a], kfx[a]);
        for (std::size_t b = 0; b < static_cast<std::size_t>(nyk); ++b) locate(ys[b], h_, kr[b], kfy[b]);
        for (std::size_t b = 0; b < static_cast<std::size_t>(nyk); ++b)
            for (std::size_t a = 0; a < static_cast<std::size_t>(nxk); ++a) {
                const double v = interpolate(field_.data(), w_, kc[a], kfx[a], kr[b], kfy[b]);
                lo = std::min(lo, v), hi = std::max(hi, v);
            }
    } else if (pyramid_.empty()) {
        for (int y = r0; y <= r1; ++y)
            for (int c = c0; c <= c1; ++c) {
                const double v = field_[index(c, y)];
                lo = std::min(lo, v), hi = std::max(hi, v);
            }
    } else {
        // The interpolant is a convex combination of the pixel values around
        // the box, [c0, c1] x [r0, r1]: their extremes bound it.  The pyramid
        // level whose blocks are at least as wide as that range has at most
        // 2 x 2 blocks meeting it.
        const int extent = std::max(c1 - c0, r1 - r0) + 1;
        int k = 1;
        while ((1 << (k + 2)) < extent && static_cast<std::size_t>(k) < pyramid_.size()) ++k;
        const auto& lv = pyramid_[static_cast<std::size_t>(k) - 1];
        const int bw = (w_ + (1 << (k + 2)) - 1) >> (k + 2);
        for (int by = r0 >> (k + 2); by <= r1 >> (k + 2); ++by)
            for (int bx = c0 >> (k + 2); bx <= c1 >> (k + 2); ++bx) {
                const auto& v = lv[static_cast<std::size_t>(by * bw + bx)];
                lo = std::min(lo, v[0]), hi = std::max(hi, v[1]);
            }
    }
    // value() rounds: a bilinear combination computed in floating point stays
    // within its exact range up to a few units in the last place of the
    // data's magnitude; widen by far more than that.
    const double slack = 1e-12 * std::max(std::abs(lo), std::abs(hi)) + std::numeric_limits<double>::min();
    return {lo - slack, hi + slack};
}

double ImageField::cut_parameter(Vec2 a, Vec2 b, double fa, double fb) const {
    // Which axis the edge runs along; anything else gets the generic root finder.
    int axis = -1;
    if (a.y == b.y && a.x != b.x) axis = 0;
    if (a.x == b.x && a.y != b.y) axis = 1;
    if (axis < 0 || !std::isfinite(a.x) || !std::isfinite(a.y) || !std::isfinite(b.x) || !std::isfinite(b.y))
        return bracketed_root(*this, a, b, fa, fb);

    // In pixel coordinates, where the knots are the integers.
    const Vec2 pa{px(a.x), py(a.y)}, pb{px(b.x), py(b.y)};
    return knots::zero_on_edge(pa, pb, axis, axis == 0 ? w_ : h_, fa, fb,
                               [this](double x, double y) { return value_px(x, y); });
}

// ---------------------------------------------------------------------------
// Threshold mode.  f = V - I is the bilinear interpolant of V - p (bilinear
// interpolation is linear in the data), so the field stores V - p or p - V.

namespace {
std::vector<double> threshold_field(const Image& img, double iso, bool above) {
    std::vector<double> f(img.pixels.size());
    for (int r = 0; r < img.height; ++r) {
        const int y = img.height - 1 - r;
        for (int c = 0; c < img.width; ++c) {
            const double p = img.at(c, r);
            f[static_cast<std::size_t>(y) * static_cast<std::size_t>(img.width) + static_cast<std::size_t>(c)] =
                above ? iso - p : p - iso;
        }
    }
    return f;
}

std::string format_number(double v) {
    std::ostringstream os;
    os.precision(17);
    os << v;
    return os.str();
}

}  // namespace

// Pixel sizes positive and finite, and the origin within 2^24 pixels (see
// region_in: the coordinates' rounding must stay far below a pixel).
void check_pixel_geometry(const PixelGeometry& g, int w, int h) {
    if (g.is_pixels()) return;
    if (!(g.sx > 0 && g.sy > 0 && std::isfinite(g.sx) && std::isfinite(g.sy) && g.sx < 1e100 && g.sy < 1e100 &&
          g.sx > 1e-100 && g.sy > 1e-100))
        throw InputError("pixel size " + format_number(g.sx) + " x " + format_number(g.sy) +
                         " is not positive and finite");
    const double far = 0x1p24;
    if (!(std::abs(g.x0 / g.sx) <= far && std::abs(g.y0 / g.sy) <= far && w < far && h < far))
        throw InputError("origin (" + format_number(g.x0) + ", " + format_number(g.y0) + ") lies more than 2^24 pixels " +
                         "from the image; coordinates would lose precision");
}

std::string label_value_problem(double v) {
    if (v != std::floor(v) || !std::isfinite(v)) return "value " + format_number(v) + ", not an integer (labels are integers 0..65535)";
    if (v > 65535) return "label " + format_number(v) + ", out of range: labels are 0..65535 (16-bit); relabel the image";
    return "label " + format_number(v) + ", out of range: labels are 0..65535 (no negative labels); relabel the image";
}

ThresholdLevelSet::ThresholdLevelSet(const Image& image, double iso, bool inside_above, PixelGeometry geometry)
    : ImageField(image.width, image.height, threshold_field(image, iso, inside_above), geometry),
      iso_(iso),
      above_(inside_above),
      maxval_(image.maxval),
      source_(image.source) {
    build_range_pyramid();
}

ThresholdLevelSet::ThresholdLevelSet(int w, int h, const std::vector<double>& values_y_up, double iso,
                                     bool inside_above, std::string source, PixelGeometry geometry, int maxval)
    : ImageField(w, h, {}, geometry), iso_(iso), above_(inside_above), maxval_(maxval), source_(std::move(source)) {
    field_.resize(values_y_up.size());
    for (std::size_t k = 0; k < values_y_up.size(); ++k)
        field_[k] = inside_above ? iso - values_y_up[k] : values_y_up[k] - iso;
    build_range_pyramid();
}

std::string ThresholdLevelSet::describe() const {
    return "image '" + source_ + "' (" + std::to_string(w_) + " x " + std::to_string(h_) +
           (maxval_ >= 0 ? ", maxval " + std::to_string(maxval_) : std::string()) + describe_geometry() +
           "), inside where the bilinear intensity is " + (above_ ? "above " : "below ") + format_number(iso_);
}

// ---------------------------------------------------------------------------
// Label mode.
//
// Why the signed distance, offset by 1/2, interpolated bilinearly:
//  * A 4-adjacent inside/outside pair of pixels gets f = -1/2 and +1/2, so the
//    boundary crosses the segment between their centres exactly midway — the
//    pixel edge, as marching squares on the 0/1 indicator would put it.  With
//    the pixel-centre lattice the mesh boundary therefore follows the pixel
//    outlines, cutting corners at 45 degrees.
//  * Further from the boundary f keeps growing with the distance (|f| is the
//    Euclidean distance to the other phase, minus 1/2), so on coarser lattices
//    the zero set interpolated between distant points is a smooth curve
//    through the staircase rather than a replica of it: diagonal staircases
//    become straight lines.
//  * A one-pixel-wide line has f = -1/2 on its pixels and positive values
//    beside it, so it survives at the pixel-centre spacing (it would vanish
//    from a sampled indicator function only at coarser spacings, as it must).
//  * f is never 0 at a pixel centre (|f| >= 1/2 there), so a pixel-centre
//    lattice has no zero-valued points.
// The distances are exact (Felzenszwalb & Huttenlocher, "Distance transforms
// of sampled functions", 2012): a 1-D pass per column, then the lower envelope
// of parabolas per row, O(W H) in total.

namespace {

constexpr std::int64_t no_feature = std::numeric_limits<std::int64_t>::max();

struct Edt {
    std::vector<std::int64_t> d2;         // squared distance to the nearest feature pixel centre
    std::vector<std::uint32_t> nearest;   // that pixel's index (y-up)
};

// Exact squared Euclidean distance transform of the feature pixels (y-up
// indexing).  Pixels get d2 = no_feature if there is no feature at all.
Edt distance_transform(const std::vector<std::uint8_t>& feature, int w, int h) {
    const std::size_t W = static_cast<std::size_t>(w), N = W * static_cast<std::size_t>(h);
    // Pass 1, per column: distance (in rows) to the nearest feature in the
    // same column, and that feature's row.
    std::vector<std::int64_t> g(N);
    std::vector<std::int32_t> grow(N);
#pragma omp parallel for schedule(static)
    for (int c = 0; c < w; ++c) {
        std::int64_t last = -1;
        for (int y = 0; y < h; ++y) {
            const std::size_t k = static_cast<std::size_t>(y) * W + static_cast<std::size_t>(c);
            if (feature[k]) last = y;
            g[k] = last >= 0 ? y - last : no_feature;
            grow[k] = static_cast<std::int32_t>(last);
        }
        std::int64_t next = -1;
        for (int y = h - 1; y >= 0; --y) {
            const std::size_t k = static_cast<std::size_t>(y) * W + static_cast<std::size_t>(c);
            if (feature[k]) next = y;
            if (next >= 0 && next - y < g[k]) g[k] = next - y, grow[k] = static_cast<std::int32_t>(next);
        }
        for (int y = 0; y < h; ++y) {
            const std::size_t k = static_cast<std::size_t>(y) * W + static_cast<std::size_t>(c);
            if (g[k] != no_feature) g[k] *= g[k];
        }
    }
    // Pass 2, per row: d2(q) = min_p (q - p)^2 + g(p), the lower envelope of
    // the parabolas rooted at the columns p with a finite g(p).
    Edt out{std::vector<std::int64_t>(N), std::vector<std::uint32_t>(N)};
#pragma omp parallel
    {
        std::vector<int> v(W);          // columns of the envelope's parabolas
        std::vector<double> z(W + 1);   // boundaries between them
#pragma omp for schedule(static)
        for (int y = 0; y < h; ++y) {
            const std::int64_t* gr = g.data() + static_cast<std::size_t>(y) * W;
            auto key = [&](int p) { return gr[p] + std::int64_t{p} * p; };
            int k = -1;
            for (int q = 0; q < w; ++q) {
                if (gr[q] == no_feature) continue;
                double s = -std::numeric_limits<double>::infinity();
                while (k >= 0) {
                    // Abscissa where parabola q starts to beat parabola v[k].
                    s = static_cast<double>(key(q) - key(v[k])) / (2.0 * (q - v[k]));
                    if (s > z[k]) break;
                    --k;
                }
                if (k < 0) s = -std::numeric_limits<double>::infinity();
                ++k;
                v[k] = q, z[k] = s, z[k + 1] = std::numeric_limits<double>::infinity();
            }
            const std::size_t base = static_cast<std::size_t>(y) * W;
            if (k < 0) {  // no feature in any column
                std::fill(out.d2.begin() + base, out.d2.begin() + base + W, no_feature);
                std::fill(out.nearest.begin() + base, out.nearest.begin() + base + W, 0u);
                continue;
            }
            int j = 0;
            for (int q = 0; q < w; ++q) {
                while (z[j + 1] < q) ++j;
                const std::int64_t p = v[j];
                out.d2[base + q] = (q - p) * (q - p) + gr[p];
                out.nearest[base + q] = static_cast<std::uint32_t>(
                    static_cast<std::size_t>(grow[base + static_cast<std::size_t>(p)]) * W + static_cast<std::size_t>(p));
            }
        }
    }
    return out;
}

std::string list_labels(const std::vector<int>& labels, std::size_t limit = 12) {
    std::string s;
    for (std::size_t i = 0; i < labels.size() && i < limit; ++i) s += (i ? ", " : "") + std::to_string(labels[i]);
    if (labels.size() > limit) s += ", ... (" + std::to_string(labels.size()) + " in all)";
    return s;
}

}  // namespace

LabelLevelSet::LabelLevelSet(const Image& image, std::vector<int> labels, bool nonzero, PixelGeometry geometry)
    : ImageField(image.width, image.height, {}, geometry), labels_(std::move(labels)), nonzero_(nonzero), source_(image.source) {
    std::vector<std::uint8_t> selected(65536, 0);
    if (nonzero_)
        std::fill(selected.begin() + 1, selected.end(), 1);
    else
        for (int l : labels_) {
            if (l < 0 || l > 65535) throw InputError("label " + std::to_string(l) + " is not in 0..65535");
            selected[static_cast<std::size_t>(l)] = 1;
        }

    const std::size_t W = static_cast<std::size_t>(w_), N = image.pixels.size();
    label_.resize(N);
    inside_.resize(N);
    std::vector<std::uint8_t> present(65536, 0), outside(N);
    std::size_t count_in = 0;
    for (int r = 0; r < h_; ++r)
        for (int c = 0; c < w_; ++c) {
            const std::uint16_t v = image.at(c, r);
            const std::size_t k = static_cast<std::size_t>(h_ - 1 - r) * W + static_cast<std::size_t>(c);
            label_[k] = v;
            inside_[k] = selected[v];
            outside[k] = !selected[v];
            present[v] = 1;
            count_in += selected[v];
        }
    if (count_in == 0) {
        std::vector<int> have;
        for (int v = 0; v < 65536; ++v)
            if (present[static_cast<std::size_t>(v)]) have.push_back(v);
        throw InputError("image '" + source_ + "': " +
                         (nonzero_ ? std::string("no nonzero pixels") : "none of the labels {" + list_labels(labels_) + "} is present") +
                         " (labels present: " + list_labels(have) + ")");
    }

    // A cell's label: the one label of its corner pixels that are in the
    // region, if there is at least one and they agree — then the nearest
    // region pixel among the corners has it, wherever the point is.
    cell_label_.assign(N, -1);
    for (int y = 0; y + 1 < h_; ++y)
        for (int c = 0; c + 1 < w_; ++c) {
            std::int32_t l = -1;
            bool one = true;
            for (const std::size_t k : {index(c, y), index(c + 1, y), index(c, y + 1), index(c + 1, y + 1)}) {
                if (!inside_[k]) continue;
                if (l >= 0 && label_[k] != l) one = false;
                l = label_[k];
            }
            if (one) cell_label_[index(c, y)] = l;
        }

    const Edt to_outside = distance_transform(outside, w_, h_);
    Edt to_inside = distance_transform(inside_, w_, h_);
    nearest_in_ = std::move(to_inside.nearest);
    // Without any outside pixel the whole image is inside: any negative value
    // larger in magnitude than every in-image distance will do.
    const double all_inside = -static_cast<double>(w_) - static_cast<double>(h_);
    field_.resize(N);
#pragma omp parallel for schedule(static)
    for (std::int64_t k = 0; k < static_cast<std::int64_t>(N); ++k) {
        const std::size_t i = static_cast<std::size_t>(k);
        if (inside_[i])
            field_[i] = to_outside.d2[i] == no_feature ? all_inside
                                                       : -(std::sqrt(static_cast<double>(to_outside.d2[i])) - 0.5);
        else
            field_[i] = std::sqrt(static_cast<double>(to_inside.d2[i])) - 0.5;
    }
    build_range_pyramid();
}

// Pixel cells [c, c + 1] x [r, r + 1] whose region centres share one label
// (cell_label_): every point (x, y) with c <= x < c + 1, r <= y < r + 1 is
// left alone by region_at's clamp (c + 1 <= w - 1, r + 1 <= h - 1) and
// truncates to the cell, so region_at's fast path answers that label.  The
// box may span up to 3 x 3 cells, all of one label.  `within` is those cells'
// union shrunk by a margin, 2^-30 of the image's size: far above the rounding
// of a centroid of three vertices in it (a few ulps of the coordinates), so
// such a centroid stays in the cells, and far below a pixel.
//
// With a pixel geometry the cells are found in pixel coordinates and
// `within` mapped back (x0 + v sx: exact in pixel units).  The margin grows
// with the origin's distance in pixels, which the coordinates' rounding is
// relative to; make_image_levelset bounds that distance by 2^24 pixels.
std::optional<RegionCell> LabelLevelSet::region_in(const Box& physical_box) const {
    const double m = 0x1p-30 * (1 + std::max(w_, h_) + std::max(std::abs(g_.x0 / g_.sx), std::abs(g_.y0 / g_.sy)));
    const Box box{px(physical_box.xmin), py(physical_box.ymin), px(physical_box.xmax), py(physical_box.ymax)};
    if (!(box.xmin >= m && box.ymin >= m && box.xmax < w_ && box.ymax < h_)) return std::nullopt;
    const int c0 = static_cast<int>(box.xmin), r0 = static_cast<int>(box.ymin);
    const int c1 = static_cast<int>(box.xmax), r1 = static_cast<int>(box.ymax);
    if (c1 + 1 >= w_ || r1 + 1 >= h_ || c1 - c0 > 2 || r1 - r0 > 2) return std::nullopt;
    const std::int32_t l = cell_label_[index(c0, r0)];
    if (l < 0) return std::nullopt;
    for (int r = r0; r <= r1; ++r)
        for (int c = c0; c <= c1; ++c)
            if (cell_label_[index(c, r)] != l) return std::nullopt;
    const RegionCell cell{l,
                          {g_.x0 + (c0 + m) * g_.sx, g_.y0 + (r0 + m) * g_.sy, g_.x0 + (c1 + 1 - m) * g_.sx,
                           g_.y0 + (r1 + 1 - m) * g_.sy}};
    if (!cell.holds(physical_box)) return std::nullopt;
    return cell;
}

std::int32_t LabelLevelSet::region_at(double x, double y) const {
    if (!std::isfinite(x) || !std::isfinite(y)) return label_[nearest_in_[0]];
    x = px(x), y = py(y);
    x = std::clamp(x, 0.0, static_cast<double>(w_ - 1));
    y = std::clamp(y, 0.0, static_cast<double>(h_ - 1));
    // The nearest region pixel among the (up to) four centres around (x, y);
    // if none of them is in the region, the region pixel nearest to the
    // nearest centre.
    const int c0 = static_cast<int>(x), y0 = static_cast<int>(y);
    // Fast path (almost every triangle): the centres around (x, y) that are in
    // the region all have one label — then it is the nearest one's label,
    // whichever that is.
    if (c0 + 1 < w_ && y0 + 1 < h_)
        if (const std::int32_t l = cell_label_[index(c0, y0)]; l >= 0) return l;
    double best = std::numeric_limits<double>::infinity();
    std::size_t pick = 0;
    for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx) {
            const int c = std::min(c0 + dx, w_ - 1), yy = std::min(y0 + dy, h_ - 1);
            const std::size_t k = index(c, yy);
            // Selects, not branches: which centre wins is data-dependent.
            const double d = inside_[k] ? (x - c) * (x - c) + (y - yy) * (y - yy) : std::numeric_limits<double>::infinity();
            const bool nearer = d < best;
            best = nearer ? d : best;
            pick = nearer ? k : pick;
        }
    if (best == std::numeric_limits<double>::infinity())
        pick = nearest_in_[index(static_cast<int>(std::lround(x)), static_cast<int>(std::lround(y)))];
    return label_[pick];
}

std::string LabelLevelSet::describe() const {
    return "image '" + source_ + "' (" + std::to_string(w_) + " x " + std::to_string(h_) + describe_geometry() +
           "), region = " + (nonzero_ ? std::string("nonzero pixels") : "labels {" + list_labels(labels_, 20) + "}") +
           ", f = bilinear signed distance to the pixel centres of the other phase, minus 1/2";
}

// ---------------------------------------------------------------------------
// Factory and option parsing.

std::unique_ptr<LevelSet> make_image_levelset(const Image& image, const ImageLevelSetOptions& options) {
    if (image.width <= 0 || image.height <= 0 ||
        image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
        throw InputError("image '" + image.source + "': empty or inconsistent image");
    check_pixel_geometry(options.geometry, image.width, image.height);
    if (options.mode == ImageMode::threshold) {
        const double iso = options.iso.value_or(image.maxval / 2.0);
        if (!std::isfinite(iso)) throw InputError("iso value must be a finite number");
        return std::make_unique<ThresholdLevelSet>(image, iso, options.inside_above, options.geometry);
    }
    if (!options.label_nonzero && options.labels.empty()) throw InputError("label mode needs at least one label");
    return std::make_unique<LabelLevelSet>(image, options.labels, options.label_nonzero, options.geometry);
}

std::unique_ptr<LevelSet> make_raster_levelset(int w, int h, const std::vector<double>& values,
                                               const std::string& source, const ImageLevelSetOptions& options,
                                               int maxval) {
    if (w <= 0 || h <= 0 || values.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h))
        throw InputError("'" + source + "': empty or inconsistent slice");
    if (options.mode == ImageMode::threshold) {
        check_pixel_geometry(options.geometry, w, h);
        const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
        const double iso = options.iso.value_or(maxval >= 0 ? maxval / 2.0 : *lo / 2 + *hi / 2);
        if (!std::isfinite(iso)) throw InputError("iso value must be a finite number");
        return std::make_unique<ThresholdLevelSet>(w, h, values, iso, options.inside_above, source, options.geometry,
                                                   maxval);
    }
    return make_image_levelset(label_image(w, h, values, source, "label mode"), options);
}

Image label_image(int w, int h, const std::vector<double>& values, const std::string& source, const std::string& what) {
    if (w <= 0 || h <= 0 || values.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h))
        throw InputError("'" + source + "': empty or inconsistent slice");
    Image img;
    img.width = w, img.height = h, img.source = source, img.maxval = 1;
    img.pixels.resize(values.size());
    for (int y = 0; y < h; ++y)
        for (int c = 0; c < w; ++c) {
            const double v = values[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(c)];
            if (!(v >= 0 && v <= 65535 && v == std::floor(v)))
                throw InputError("'" + source + "': " + what + " needs integer values in 0..65535, but pixel (" +
                                 std::to_string(c) + ", " + std::to_string(y) + ") has " + label_value_problem(v) +
                                 (what == "label mode" ? " (use --iso for a threshold instead)" : ""));
            const auto u = static_cast<std::uint16_t>(v);
            img.pixels[static_cast<std::size_t>(h - 1 - y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(c)] = u;
            img.maxval = std::max<int>(img.maxval, u);
        }
    return img;
}

std::vector<int> parse_label_list(const std::string& list) {
    auto bad = [&](const std::string& why) -> InputError {
        return InputError("bad label list '" + list + "': " + why +
                          " (expected e.g. 3, 51,52, 1000-1035 or nonzero; labels are 0..65535)");
    };
    auto number = [&](std::string_view t) {
        while (!t.empty() && t.front() == ' ') t.remove_prefix(1);
        while (!t.empty() && t.back() == ' ') t.remove_suffix(1);
        int v = 0;
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (t.empty() || ec != std::errc{} || end != t.data() + t.size())
            throw bad("'" + std::string(t) + "' is not a label");
        if (v < 0 || v > 65535) throw bad(std::to_string(v) + " is out of range");
        return v;
    };
    std::vector<int> out;
    std::string_view rest = list;
    if (rest.find_first_not_of(' ') == std::string_view::npos) throw bad("empty");
    while (true) {
        const std::size_t comma = rest.find(',');
        const std::string_view item = rest.substr(0, comma);
        const std::size_t dash = item.find('-', item.find_first_not_of(' ') + 1);  // not a leading sign
        if (dash == std::string_view::npos) {
            out.push_back(number(item));
        } else {
            const int from = number(item.substr(0, dash)), to = number(item.substr(dash + 1));
            if (from > to) throw bad("range " + std::to_string(from) + "-" + std::to_string(to) + " is empty");
            for (int v = from; v <= to; ++v) out.push_back(v);
        }
        if (comma == std::string_view::npos) break;
        rest.remove_prefix(comma + 1);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

ImageLevelSetOptions label_options(const std::string& spec) {
    ImageLevelSetOptions o;
    o.mode = ImageMode::label;
    if (spec == "nonzero")
        o.label_nonzero = true;
    else
        o.labels = parse_label_list(spec);
    return o;
}

namespace {

// "3, 41, 42" (the first `limit` of a list, and how many in all).
std::string list_some(const std::vector<int>& v, std::size_t limit = 12) {
    std::string s;
    for (std::size_t i = 0; i < v.size() && i < limit; ++i) s += (i ? ", " : "") + std::to_string(v[i]);
    if (v.size() > limit) s += ", ... (" + std::to_string(v.size()) + " in all)";
    return s;
}

}  // namespace

std::vector<int> select_material_labels(std::span<const std::int64_t> count, const std::string& spec, const LabelSource& where) {
    std::vector<int> present, labels;
    for (std::size_t l = 0; l < count.size(); ++l)
        if (count[l]) present.push_back(static_cast<int>(l));
    if (spec == "all") {
        for (int l : present)
            if (l != 0) labels.push_back(l);
        if (labels.empty())
            throw InputError(where.source + ": " + where.option + " all: no label other than 0 (the background) is present");
        return labels;
    }
    labels = parse_label_list(spec);
    if (std::binary_search(labels.begin(), labels.end(), 0))
        throw InputError(where.option + ": label 0 is the background (every " + where.element + " not listed); list only other labels");
    std::vector<int> absent;
    for (int l : labels)
        if (static_cast<std::size_t>(l) >= count.size() || !count[static_cast<std::size_t>(l)]) absent.push_back(l);
    if (!absent.empty())
        throw InputError(where.source + ": " + where.option + " names label(s) not present in the " + where.container + ": " +
                         list_some(absent) + " (labels present: " + list_some(present) + ")");
    return labels;
}

}  // namespace warpmesh
