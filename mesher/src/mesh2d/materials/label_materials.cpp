// label_materials.cpp — the materials of a label image (materials.hpp).
//
// Coordinates as in image_levelset.hpp: pixel (column c, row r) is centred at
// (x0 + c sx, y0 + (H - 1 - r) sy), by default (c, H - 1 - r); the lattice
// covers the pixel-centre box.  Everything below happens in pixel coordinates
// ((x - x0) / sx, (y - y0) / sy: monotone in each coordinate, affine along a
// lattice edge so that an edge's parameter u is the same in both, and the
// identity bit for bit in pixel units).  Per pixel centre
// and material m, phi_m is label mode's field for the region "label m",
// -(d_out - 1/2) on m's pixels and d_in - 1/2 elsewhere, the distances between
// pixel centres capped at `cap` pixels; between centres it is bilinear.
//
// Which values are ever needed: at a point of pixel cell Q (four corner
// pixels), a material that no corner carries has phi >= 1/2 at all four, so
// its interpolant is >= 1/2; the label of the corner with the largest weight
// has phi <= -1/2 there and phi <= d - 1/2 <= sqrt 2 - 1/2 at the others
// (d the distance between the corners), so its interpolant is at most
// -1/2 + (fx (1-fy) + (1-fx) fy + sqrt 2 fx fy) <= 0.36 < 1/2 (fx, fy <= 1/2
// in the nearest corner's frame).  So the winner is a corner label, and in a
// cell whose corners differ each corner label's distances at the corners are
// at most sqrt 2: exact below the cap.  Cells whose corners agree are that
// label everywhere.  Hence per cell: one label, or (mixed cells) the up to
// four corner labels with their phi at the four corners, computed from each
// corner's (2 cap + 1)^2 window.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#ifdef _OPENMP
#include <omp.h>
#endif

#include "levelset/knot_walk.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/levelset/image_levelset.hpp"
#include "warpmesh/mesh2d/materials.hpp"
#include "warpmesh/core/memory.hpp"

namespace warpmesh {
namespace {

constexpr int cap = 3;  // pixels: the distance cap (window radius)
constexpr std::uint32_t mixed_bit = 0x80000000u;

// Cell index c (0 <= c <= n-2) and fraction ft in [0, 1] of coordinate t on an
// axis of n >= 2 pixel centres; clamped outside [0, n-1].
inline void locate_cell(double t, int n, int& c, double& ft) {
    t = std::clamp(t, 0.0, static_cast<double>(n - 1));
    c = std::min(static_cast<int>(t), n - 2);
    ft = t - c;
}

// Bilinear interpolation of corner values v = {v00, v10, v01, v11}, written as
// ImageField's interpolate (exact at fx, fy in {0, 1}: continuous bit for bit
// across cells).
inline double bilinear(const std::array<double, 4>& v, double fx, double fy) {
    const double v0 = fx == 0 ? v[0] : (1 - fx) * v[0] + fx * v[1];
    if (fy == 0) return v0;
    const double v1 = fx == 0 ? v[2] : (1 - fx) * v[2] + fx * v[3];
    return (1 - fy) * v0 + fy * v1;
}

struct Mixed {
    int n = 0;                                  // 2..4 labels, ascending material numbers
    std::array<std::uint16_t, 4> m{};
    std::array<std::uint16_t, 4> corner{};      // the corners' materials: 00, 10, 01, 11
    std::array<std::array<double, 4>, 4> v{};   // v[k][corner]: phi of m[k] at corners 00, 10, 01, 11
};

class LabelMaterials final : public MaterialField {
public:
    LabelMaterials(const Image& image, const std::string& spec, const PixelGeometry& geometry);
    int count() const override { return static_cast<int>(tags_.size()); }
    std::int32_t tag(int m) const override { return tags_[static_cast<std::size_t>(m)]; }
    std::string name(int m) const override { return m == 0 ? "background" : "label_" + std::to_string(tag(m)); }
    Box bounds() const override {
        return {g_.x0, g_.y0, g_.x0 + static_cast<double>(w_ - 1) * g_.sx, g_.y0 + static_cast<double>(h_ - 1) * g_.sy};
    }
    bool bounds_are_domain() const override { return true; }
    std::string describe() const override;
    double phi(int m, double x, double y) const override;
    int material_at(double x, double y) const override;
    void sample_block(const Lattice& lattice, const PointBlock& block, std::span<std::uint16_t> out) const override;
    double cut_parameter(Vec2 a, Vec2 b, int ma, int mb) const override;
    std::optional<double> reference_area(int m) const override {
        return static_cast<double>(pixels_[static_cast<std::size_t>(m)]) * g_.sx * g_.sy;
    }

private:
    std::size_t index(int c, int y) const { return static_cast<std::size_t>(y) * static_cast<std::size_t>(w_) + static_cast<std::size_t>(c); }
    std::uint16_t mat(int c, int y) const { return mat_[index(c, y)]; }
    double pixel_phi(int m, int c, int y) const;
    double phi_px(int m, double x, double y) const;  // phi at pixel coordinates
    double px(double x) const { return (x - g_.x0) / g_.sx; }
    double py(double y) const { return (y - g_.y0) / g_.sy; }
    // The material at (fx, fy) of a cell: argmin phi; an exact tie goes to
    // the tied material of the nearest corner (largest bilinear weight),
    // equally near corners in the order 11, 01, 10, 00 (the upper, then the
    // right pixel) — a rule of the geometry, not of the label numbers.
    int in_cell(std::uint32_t cell, double fx, double fy) const {
        if (!(cell & mixed_bit)) return static_cast<int>(cell);
        const Mixed& e = mixed_[cell & ~mixed_bit];
        std::array<double, 4> v{};
        double best = std::numeric_limits<double>::infinity();
        int pick = 0, tied = 0;
        for (int k = 0; k < e.n; ++k) {
            v[static_cast<std::size_t>(k)] = bilinear(e.v[static_cast<std::size_t>(k)], fx, fy);
            if (v[static_cast<std::size_t>(k)] < best) best = v[static_cast<std::size_t>(k)], pick = k, tied = 1;
            else if (v[static_cast<std::size_t>(k)] == best) ++tied;
        }
        if (tied == 1) return e.m[static_cast<std::size_t>(pick)];
        const std::array<double, 4> w{(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy};
        int winner = -1;
        double wbest = -1;
        for (const int q : {3, 2, 1, 0}) {
            const std::uint16_t m = e.corner[static_cast<std::size_t>(q)];
            const int k = static_cast<int>(std::find(e.m.begin(), e.m.begin() + e.n, m) - e.m.begin());
            if (v[static_cast<std::size_t>(k)] == best && w[static_cast<std::size_t>(q)] > wbest) wbest = w[static_cast<std::size_t>(q)], winner = m;
        }
        return winner;
    }

    int w_, h_;
    PixelGeometry g_;
    std::string source_, spec_;
    std::vector<std::int32_t> tags_;
    std::vector<std::int64_t> pixels_;
    std::vector<std::uint16_t> mat_;      // per pixel (y-up): its material
    std::vector<std::uint32_t> cells_;    // per cell (c, y), c < w-1, y < h-1: material, or mixed_bit | index
    std::vector<Mixed> mixed_;
};


LabelMaterials::LabelMaterials(const Image& image, const std::string& spec, const PixelGeometry& geometry)
    : w_(image.width), h_(image.height), g_(geometry), source_(image.source), spec_(spec) {
    if (w_ < 2 || h_ < 2 || image.pixels.size() != static_cast<std::size_t>(w_) * static_cast<std::size_t>(h_))
        throw InputError("image '" + source_ + "': multi-material meshing needs at least 2 x 2 pixels");
    check_pixel_geometry(g_, w_, h_);
    std::vector<std::int64_t> hist(65536, 0);
    for (const std::uint16_t v : image.pixels) ++hist[v];
    const std::vector<int> labels = select_material_labels(hist, spec, {"image '" + source_ + "'", "--materials", "pixel", "image"});
    if (labels.size() > 65535)
        throw InputError("image '" + source_ + "': " + std::to_string(labels.size()) + " labels, more than 65535 materials");
    std::vector<std::uint16_t> material_of(65536, 0);
    tags_.push_back(0);
    for (std::size_t k = 0; k < labels.size(); ++k) {
        material_of[static_cast<std::size_t>(labels[k])] = static_cast<std::uint16_t>(k + 1);
        tags_.push_back(labels[k]);
    }
    pixels_.assign(tags_.size(), 0);
    mat_.resize(image.pixels.size());
    for (int r = 0; r < h_; ++r)
        for (int c = 0; c < w_; ++c) {
            const std::uint16_t m = material_of[image.at(c, r)];
            mat_[index(c, h_ - 1 - r)] = m;
            ++pixels_[m];
        }
    // Cells: one material, or the mixed record.
    cells_.resize(static_cast<std::size_t>(w_ - 1) * static_cast<std::size_t>(h_ - 1));
    for (int y = 0; y + 1 < h_; ++y)
        for (int c = 0; c + 1 < w_; ++c) {
            const std::array<std::uint16_t, 4> corner{mat(c, y), mat(c + 1, y), mat(c, y + 1), mat(c + 1, y + 1)};
            std::uint32_t& cell = cells_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w_ - 1) + static_cast<std::size_t>(c)];
            if (corner[0] == corner[1] && corner[0] == corner[2] && corner[0] == corner[3]) {
                cell = corner[0];
                continue;
            }
            Mixed e;
            e.corner = corner;
            std::array<std::uint16_t, 4> sorted = corner;
            std::sort(sorted.begin(), sorted.end());
            for (int k = 0; k < 4; ++k)
                if (k == 0 || sorted[static_cast<std::size_t>(k)] != sorted[static_cast<std::size_t>(k - 1)])
                    e.m[static_cast<std::size_t>(e.n++)] = sorted[static_cast<std::size_t>(k)];
            for (int k = 0; k < e.n; ++k)
                for (int q = 0; q < 4; ++q)
                    e.v[static_cast<std::size_t>(k)][static_cast<std::size_t>(q)] = pixel_phi(e.m[static_cast<std::size_t>(k)], c + (q & 1), y + (q >> 1));
            cell = mixed_bit | static_cast<std::uint32_t>(mixed_.size());
            mixed_.push_back(e);
        }
}

// phi_m at pixel centre (c, y): the nearest centre of the other phase within
// the window, the distance capped at `cap`.
double LabelMaterials::pixel_phi(int m, int c, int y) const {
    const bool in = mat(c, y) == m;
    int best = cap * cap + 1;
    for (int dy = -cap; dy <= cap; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= h_) continue;
        for (int dx = -cap; dx <= cap; ++dx) {
            const int cc = c + dx;
            if (cc < 0 || cc >= w_ || (mat(cc, yy) == m) == in) continue;
            best = std::min(best, dx * dx + dy * dy);
        }
    }
    const double d = best > cap * cap ? static_cast<double>(cap) : std::sqrt(static_cast<double>(best));
    return in ? -(d - 0.5) : d - 0.5;
}

double LabelMaterials::phi(int m, double x, double y) const { return phi_px(m, px(x), py(y)); }

double LabelMaterials::phi_px(int m, double x, double y) const {
    int c = 0, r = 0;
    double fx = 0, fy = 0;
    locate_cell(x, w_, c, fx);
    locate_cell(y, h_, r, fy);
    const std::uint32_t cell = cells_[static_cast<std::size_t>(r) * static_cast<std::size_t>(w_ - 1) + static_cast<std::size_t>(c)];
    if (cell & mixed_bit) {
        const Mixed& e = mixed_[cell & ~mixed_bit];
        for (int k = 0; k < e.n; ++k)
            if (e.m[static_cast<std::size_t>(k)] == m) return bilinear(e.v[static_cast<std::size_t>(k)], fx, fy);
    }
    return bilinear({pixel_phi(m, c, r), pixel_phi(m, c + 1, r), pixel_phi(m, c, r + 1), pixel_phi(m, c + 1, r + 1)}, fx, fy);
}

int LabelMaterials::material_at(double x, double y) const {
    if (!std::isfinite(x) || !std::isfinite(y)) return 0;
    int c = 0, r = 0;
    double fx = 0, fy = 0;
    locate_cell(px(x), w_, c, fx);
    locate_cell(py(y), h_, r, fy);
    return in_cell(cells_[static_cast<std::size_t>(r) * static_cast<std::size_t>(w_ - 1) + static_cast<std::size_t>(c)], fx, fy);
}

// As material_at at every point, with each column's cell located once.
void LabelMaterials::sample_block(const Lattice& lattice, const PointBlock& b, std::span<std::uint16_t> out) const {
    const std::size_t ni = static_cast<std::size_t>(b.ni);
    std::vector<int> col(ni);
    std::vector<double> colf(ni);
    for (std::size_t i = 0; i < ni; ++i) {
        const double x = lattice.position(b.i0 + static_cast<std::int64_t>(i), 0).x;
        if (!std::isfinite(x)) return MaterialField::sample_block(lattice, b, out);
        locate_cell(px(x), w_, col[i], colf[i]);
    }
#pragma omp parallel for schedule(static) if (b.ni * b.nj >= 4096)
    for (std::int64_t j = 0; j < b.nj; ++j) {
        int r = 0;
        double fy = 0;
        locate_cell(py(lattice.position(0, b.j0 + j).y), h_, r, fy);
        const std::uint32_t* cells = cells_.data() + static_cast<std::size_t>(r) * static_cast<std::size_t>(w_ - 1);
        std::uint16_t* o = out.data() + j * b.ni;
        for (std::size_t i = 0; i < ni; ++i) {
            const std::uint32_t cell = cells[col[i]];
            o[i] = static_cast<std::uint16_t>((cell & mixed_bit) ? in_cell(cell, colf[i], fy) : static_cast<int>(cell));
        }
    }
}

// g = phi_ma - phi_mb is piecewise linear along an axis-aligned edge, with
// knots at the integers of pixel coordinates: its exact zero (knot_walk.hpp),
// found in pixel coordinates (the parameter u is the same).  g(a) <= 0 <=
// g(b) since ma wins at a and mb at b; an exact 0 at an end (a tie) puts the
// cut point at that end (clamped into the open interval).
double LabelMaterials::cut_parameter(Vec2 a, Vec2 b, int ma, int mb) const {
    int axis = -1;
    if (a.y == b.y && a.x != b.x) axis = 0;
    if (a.x == b.x && a.y != b.y) axis = 1;
    const Vec2 pa{px(a.x), py(a.y)}, pb{px(b.x), py(b.y)};
    const auto g = [&](double x, double y) { return phi_px(ma, x, y) - phi_px(mb, x, y); };
    const double ga = g(pa.x, pa.y), gb = g(pb.x, pb.y);
    if (!(ga < 0)) return knots::open_unit(0);
    if (!(gb > 0)) return knots::open_unit(1);
    if (axis < 0) return MaterialField::cut_parameter(a, b, ma, mb);
    return knots::zero_on_edge(pa, pb, axis, axis == 0 ? w_ : h_, ga, gb, g);
}

std::string LabelMaterials::describe() const {
    return "image '" + source_ + "' (" + std::to_string(w_) + " x " + std::to_string(h_) + pixel_geometry_text(g_) + "), materials " + spec_ + ": " +
           std::to_string(count() - 1) + " label(s) and the background; phi = bilinear signed distance between pixel "
           "centres (capped at " + std::to_string(cap) + "), minus 1/2";
}

}  // namespace

std::unique_ptr<MaterialField> make_label_materials(const Image& image, const std::string& spec,
                                                    const PixelGeometry& geometry, std::uint64_t max_memory) {
    const std::uint64_t per = field_bytes_per_pixel(FieldKind::materials);
    check_memory(image.pixels.size() * per, max_memory, "the material field of '" + image.source + "'",
                 std::to_string(image.width) + " x " + std::to_string(image.height) + " pixels at " +
                     std::to_string(per) + " bytes each",
                 "crop or downsample the image");
    return std::make_unique<LabelMaterials>(image, spec, geometry);
}

}  // namespace warpmesh
