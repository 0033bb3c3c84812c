// volume_materials3.cpp — the materials of a label volume (materials3.hpp:
// make_volume_materials3): a material index per voxel, phi_m from each
// voxel's 3 x 3 x 3 neighbourhood, the winner among a voxel cell's corner
// labels, and cut points as zeros of phi_a − phi_b.
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "../core/root_finder.hpp"
#include "warpmesh/core/buffer.hpp"
#include "warpmesh/core/errors.hpp"
#include "warpmesh/io/volume.hpp"
#include "warpmesh/levelset/image_levelset.hpp"  // parse_label_list
#include "warpmesh/levelset/materials3.hpp"

namespace warpmesh {
namespace {


class VolumeMaterials3 final : public MaterialField3 {
public:
    VolumeMaterials3(const Volume& v, const std::string& spec, std::uint64_t max_memory);

    int count() const override { return static_cast<int>(tags_.size()); }
    std::int32_t tag(int m) const override { return tags_[static_cast<std::size_t>(m)]; }
    std::string name(int m) const override { return m == 0 ? "background" : "label_" + std::to_string(tag(m)); }
    Box3 bounds() const override { return bounds_; }
    std::optional<Box3> domain() const override { return bounds_; }  // the hull of the voxel centres (the whole volume's, for a part)
    std::string describe() const override { return "materials " + spec_ + " of '" + source_ + "'"; }
    double resolution() const override { return resolution_; }
    std::optional<double> reference_volume(int m) const override {
        return static_cast<double>(voxels_[static_cast<std::size_t>(m)]) * voxel_volume_;
    }
    int material_at(Point3 p) const override;
    double cut_parameter(Point3 a, Point3 b, int ma, int mb) const override;
    bool read_outside_part() const override { return outside_.load(); }

private:
    using Index3 = std::array<double, 3>;
    Index3 to_index(Point3 p) const {
        const double q[3] = {p.x, p.y, p.z};
        Index3 x{};
        for (std::size_t a = 0; a < 3; ++a) x[a] = sign_[a] * (q[axis_[a]] - origin_[axis_[a]]) / spacing_[a];
        return x;
    }
    bool in_hull(const Index3& x) const {
        for (std::size_t a = 0; a < 3; ++a)
            if (!(x[a] >= 0 && x[a] <= static_cast<double>(n_[a] - 1))) return false;
        return true;
    }
    // Whole-volume voxel (i, j, k)'s place in mat_ (it must lie in the part,
    // if this is one), which is stored in the physical axes' order (x
    // fastest, then y, then z): the lattice is traversed in that order, and a
    // volume whose index axes are permuted (an NRRD's space directions) would
    // otherwise be read a slice apart at every step.
    std::int64_t at(std::int64_t i, std::int64_t j, std::int64_t k) const {
        return (i - off_[0]) * stride_[0] + (j - off_[1]) * stride_[1] + (k - off_[2]) * stride_[2];
    }
    bool in_part(std::int64_t i, std::int64_t j, std::int64_t k) const {
        i -= off_[0], j -= off_[1], k -= off_[2];
        return i >= 0 && j >= 0 && k >= 0 && i < pn_[0] && j < pn_[1] && k < pn_[2];
    }
    // The material index of whole-volume voxel (i, j, k): of a part, the
    // background (flagged) outside it.
    std::uint16_t mat(std::int64_t i, std::int64_t j, std::int64_t k) const {
        if (part_ && !in_part(i, j, k)) {
            outside_.store(true, std::memory_order_relaxed);
            return 0;
        }
        return mat_[static_cast<std::size_t>(at(i, j, k))];
    }
    // D_m (materials3.hpp) at the 8 corners of cell c (corner q = (i + (q & 1),
    // j + (q >> 1 & 1), k + (q >> 2))) for each material ms[m] (at most 8), in out[m].
    void corner_phis(const std::array<std::int64_t, 3>& c, std::span<const int> ms, std::span<std::array<double, 8>> out) const;
    // The interpolant of corner values d at offset f in a cell: the sum of
    // weights[q] d[q], the weights (trilinear_weights) shared by every
    // material's values at one point.
    static std::array<double, 8> trilinear_weights(const Index3& f);
    static double trilinear(const std::array<double, 8>& d, const std::array<double, 8>& weights);
    // The cell of x (its lowest corner, clamped so that the cell exists) and x's offset in it.
    void cell_of(const Index3& x, std::array<std::int64_t, 3>& c, Index3& f) const {
        for (std::size_t a = 0; a < 3; ++a) {
            c[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(x[a])), 0, n_[a] - 2);
            f[a] = x[a] - static_cast<double>(c[a]);
        }
    }

    std::array<std::int64_t, 3> n_{}, stride_{};  // the (whole) volume's voxels; mat_'s strides
    // A part (Volume::is_part): its voxels and offset in the whole.
    bool part_ = false;
    std::array<std::int64_t, 3> pn_{}, off_{0, 0, 0};
    mutable std::atomic<bool> outside_{false};
    std::array<std::size_t, 3> axis_{};  // the physical axis of index axis a
    std::array<double, 3> sign_{}, spacing_{}, origin_{};
    Buffer<std::uint16_t> mat_;               // per voxel (every one written by the constructor)
    std::vector<std::int32_t> tags_;          // per material
    std::vector<std::int64_t> voxels_;        // per material
    double voxel_volume_ = 1, resolution_ = 1;
    Box3 bounds_{};
    std::string source_, spec_;
};

VolumeMaterials3::VolumeMaterials3(const Volume& v, const std::string& spec, std::uint64_t max_memory)
    : n_(v.is_part() ? v.whole_dims : v.dims), part_(v.is_part()), pn_(v.dims), off_(v.part_offset), source_(v.source), spec_(spec) {
    if (part_ && spec == "all")
        throw InputError("volume '" + source_ + "': a part of a volume needs its materials listed (materials all depends on the "
                         "whole volume's labels)");
    for (std::size_t a = 0; a < 3; ++a)
        if (part_ && !(off_[a] >= 0 && v.dims[a] >= 1 && off_[a] + v.dims[a] <= n_[a]))
            throw InputError("volume '" + source_ + "': the part does not lie in the whole volume");
    for (std::size_t a = 0; a < 3; ++a)
        if (n_[a] < 2)
            throw InputError("volume '" + source_ + "': multi-material meshing needs at least 2 voxels along every axis (got " +
                             std::to_string(n_[0]) + " x " + std::to_string(n_[1]) + " x " + std::to_string(n_[2]) + ")");
    check_memory(static_cast<std::uint64_t>(v.voxel_count()) * 2, max_memory, "the material field of '" + source_ + "'",
                 "2 bytes a voxel", "");
    std::vector<std::int64_t> hist(65536, 0);
    for (std::size_t q = 0; q < static_cast<std::size_t>(v.voxel_count()); ++q) {
        const double x = v.value(q);
        if (!(x >= 0 && x <= 65535 && x == std::floor(x))) {
            const std::int64_t i = off_[0] + static_cast<std::int64_t>(q) % pn_[0], j = off_[1] + static_cast<std::int64_t>(q) / pn_[0] % pn_[1],
                               k = off_[2] + static_cast<std::int64_t>(q) / (pn_[0] * pn_[1]);
            throw InputError("volume '" + source_ + "': materials need integer labels in 0..65535, but voxel (" + std::to_string(i) +
                             ", " + std::to_string(j) + ", " + std::to_string(k) + ") is " + std::to_string(x));
        }
        ++hist[static_cast<std::size_t>(x)];
    }
    // A part need not hold every listed label: the whole has them.
    if (part_)
        for (const int l : parse_label_list(spec))
            if (l > 0 && l < 65536) ++hist[static_cast<std::size_t>(l)];
    const std::vector<int> labels = select_material_labels(hist, spec, {"volume '" + source_ + "'", "materials", "voxel", "volume"});
    std::vector<std::uint16_t> material_of(65536, 0);
    tags_.push_back(0);
    for (std::size_t k = 0; k < labels.size(); ++k) {
        material_of[static_cast<std::size_t>(labels[k])] = static_cast<std::uint16_t>(k + 1);
        tags_.push_back(labels[k]);
    }
    // Geometry (volume.hpp: axis-aligned, each axes[a] a signed unit vector).
    double lo[3], hi[3];
    for (std::size_t a = 0; a < 3; ++a) {
        for (std::size_t c = 0; c < 3; ++c)
            if (v.axes[a][c] != 0) axis_[a] = c, sign_[a] = v.axes[a][c] > 0 ? 1 : -1;
        spacing_[a] = v.spacing[a];
        origin_[a] = v.origin[a];
    }
    for (std::size_t a = 0; a < 3; ++a) {
        stride_[a] = 1;
        for (std::size_t b = 0; b < 3; ++b)
            if (axis_[b] < axis_[a]) stride_[a] *= pn_[b];
    }
    voxels_.assign(tags_.size(), 0);
    mat_.resize(static_cast<std::size_t>(v.voxel_count()));
    for (std::int64_t k = off_[2], q = 0; k < off_[2] + pn_[2]; ++k)
        for (std::int64_t j = off_[1]; j < off_[1] + pn_[1]; ++j)
            for (std::int64_t i = off_[0]; i < off_[0] + pn_[0]; ++i, ++q) {
                const std::uint16_t m = material_of[static_cast<std::size_t>(v.value(static_cast<std::size_t>(q)))];
                mat_[static_cast<std::size_t>(at(i, j, k))] = m;
                ++voxels_[m];
            }
    for (std::size_t a = 0; a < 3; ++a) {
        const std::size_t c = axis_[a];
        const double e0 = origin_[c], e1 = origin_[c] + sign_[a] * spacing_[a] * static_cast<double>(n_[a] - 1);
        lo[c] = std::min(e0, e1), hi[c] = std::max(e0, e1);
    }
    bounds_ = {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
    voxel_volume_ = spacing_[0] * spacing_[1] * spacing_[2];
    resolution_ = std::min({spacing_[0], spacing_[1], spacing_[2]});
}

// The 4 x 4 x 4 voxels around a cell as bits of a 64-bit word: voxel (x, y,
// z), each in -1..2 relative to the cell's lowest corner, is bit
// (z + 1) 16 + (y + 1) 4 + (x + 1).  near[d2 - 1][q]: the voxels at squared
// distance d2 (1, 2 or 3: the 26-neighbourhood) from the cell's corner q.
namespace {
constexpr int block_bit(int x, int y, int z) { return (z + 1) * 16 + (y + 1) * 4 + (x + 1); }
constexpr auto near = [] {
    std::array<std::array<std::uint64_t, 8>, 3> n{};
    for (int q = 0; q < 8; ++q)
        for (int z = -1; z <= 1; ++z)
            for (int y = -1; y <= 1; ++y)
                for (int x = -1; x <= 1; ++x)
                    if (const int d2 = x * x + y * y + z * z; d2 > 0)
                        n[static_cast<std::size_t>(d2 - 1)][static_cast<std::size_t>(q)] |=
                            std::uint64_t{1} << block_bit((q & 1) + x, (q >> 1 & 1) + y, (q >> 2) + z);
    return n;
}();
// The squared distance (1, 2, 3) from corner q to the nearest voxel of `voxels`
// in its 26-neighbourhood, 4 if none.
int nearest_d2(std::uint64_t voxels, int q) {
    for (std::size_t d = 0; d < 3; ++d)
        if (voxels & near[d][static_cast<std::size_t>(q)]) return static_cast<int>(d) + 1;
    return 4;
}
}  // namespace

void VolumeMaterials3::corner_phis(const std::array<std::int64_t, 3>& c, std::span<const int> ms, std::span<std::array<double, 8>> out) const {
    static constexpr std::array<double, 5> root{0, 1, 1.4142135623730951, 1.7320508075688772, 2};
    // The voxels of the block in the volume, and those of each material
    // asked for, row by row.
    std::uint64_t inside = 0;
    std::array<std::uint64_t, 8> of{};
    for (int z = -1; z <= 2; ++z)
        for (int y = -1; y <= 2; ++y) {
            const std::int64_t j = c[1] + y, k = c[2] + z, row = at(0, j, k);
            if (!(j >= 0 && k >= 0 && j < n_[1] && k < n_[2])) continue;
            for (int x = -1; x <= 2; ++x) {
                const std::int64_t i = c[0] + x;
                if (!(i >= 0 && i < n_[0])) continue;
                const int label = part_ ? mat(i, j, k) : mat_[static_cast<std::size_t>(row + i * stride_[0])];
                const std::uint64_t bit = std::uint64_t{1} << block_bit(x, y, z);
                inside |= bit;
                for (std::size_t m = 0; m < ms.size(); ++m) of[m] |= label == ms[m] ? bit : 0;
            }
        }
    std::array<int, 8> corner{};  // the corners' materials
    for (int q = 0; q < 8; ++q) corner[static_cast<std::size_t>(q)] = mat(c[0] + (q & 1), c[1] + (q >> 1 & 1), c[2] + (q >> 2));
    // At corner q of material `own`: D_own from the nearest voxel not of
    // `own`, D_m (m != own) from the nearest voxel of m.
    for (int q = 0; q < 8; ++q)
        for (std::size_t m = 0; m < ms.size(); ++m)
            out[m][static_cast<std::size_t>(q)] = ms[m] == corner[static_cast<std::size_t>(q)]
                                                       ? 0.5 - root[static_cast<std::size_t>(nearest_d2(inside & ~of[m], q))]
                                                       : root[static_cast<std::size_t>(nearest_d2(of[m], q))] - 0.5;
}

std::array<double, 8> VolumeMaterials3::trilinear_weights(const Index3& f) {
    std::array<double, 8> w{};
    for (int q = 0; q < 8; ++q)
        w[static_cast<std::size_t>(q)] = (q & 1 ? f[0] : 1 - f[0]) * (q >> 1 & 1 ? f[1] : 1 - f[1]) * (q >> 2 ? f[2] : 1 - f[2]);
    return w;
}

double VolumeMaterials3::trilinear(const std::array<double, 8>& d, const std::array<double, 8>& w) {
    double s = 0;
    for (std::size_t q = 0; q < 8; ++q) s += w[q] * d[q];
    return s;
}

int VolumeMaterials3::material_at(Point3 p) const {
    const Index3 x = to_index(p);
    if (!in_hull(x)) return outside_material;
    std::array<std::int64_t, 3> c{};
    Index3 f{};
    cell_of(x, c, f);
    std::array<int, 8> corner{};
    for (int q = 0; q < 8; ++q) corner[static_cast<std::size_t>(q)] = mat(c[0] + (q & 1), c[1] + (q >> 1 & 1), c[2] + (q >> 2));
    if (std::all_of(corner.begin(), corner.end(), [&](int m) { return m == corner[0]; })) return corner[0];
    // At a voxel centre (a corner of its cell) the voxel's material wins:
    // its D is below −1/2 there, every other material's above 1/2.
    if ((f[0] == 0 || f[0] == 1) && (f[1] == 0 || f[1] == 1) && (f[2] == 0 || f[2] == 1))
        return corner[static_cast<std::size_t>((f[0] == 1) + 2 * (f[1] == 1) + 4 * (f[2] == 1))];
    // The candidates: the corners' materials; the smallest phi wins.
    std::array<int, 8> cand{};
    int n = 0;
    for (const int m : corner)
        if (std::find(cand.begin(), cand.begin() + n, m) == cand.begin() + n) cand[static_cast<std::size_t>(n++)] = m;
    std::array<std::array<double, 8>, 8> d;  // the first n written by corner_phis
    corner_phis(c, std::span<const int>(cand.data(), static_cast<std::size_t>(n)), std::span<std::array<double, 8>>(d.data(), static_cast<std::size_t>(n)));
    std::array<double, 8> value{};
    double best = std::numeric_limits<double>::infinity();
    const std::array<double, 8> weights = trilinear_weights(f);
    for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) best = std::min(best, value[k] = trilinear(d[k], weights));
    // A tie: the tied material of the nearest corner; equally near ones, the
    // last in (z, y, x) order.
    int winner = -1;
    double nearest = std::numeric_limits<double>::infinity();
    for (int q = 0; q < 8; ++q) {
        const int m = corner[static_cast<std::size_t>(q)];
        const std::size_t k = static_cast<std::size_t>(std::find(cand.begin(), cand.begin() + n, m) - cand.begin());
        if (value[k] != best) continue;
        double d2 = 0;
        for (std::size_t a = 0; a < 3; ++a) {
            const double d = (q >> a & 1) ? 1 - f[a] : f[a];
            d2 += d * d;
        }
        if (d2 <= nearest) nearest = d2, winner = m;
    }
    return winner;
}

double VolumeMaterials3::cut_parameter(Point3 a, Point3 b, int ma, int mb) const {
    const Index3 xa = to_index(a), xb = to_index(b);
    const auto x_at = [&](double u) {
        return Index3{xa[0] + u * (xb[0] - xa[0]), xa[1] + u * (xb[1] - xa[1]), xa[2] + u * (xb[2] - xa[2])};
    };
    if (ma == outside_material || mb == outside_material) {
        // Where the segment crosses the hull: the inside end's last point in it.
        const bool a_in = ma != outside_material;
        const Index3 &in = a_in ? xa : xb, &out = a_in ? xb : xa;
        double t = 1;  // along in -> out
        for (std::size_t k = 0; k < 3; ++k) {
            const double limit = out[k] < 0 ? 0 : out[k] > static_cast<double>(n_[k] - 1) ? static_cast<double>(n_[k] - 1) : out[k];
            if (limit != out[k]) t = std::min(t, (limit - in[k]) / (out[k] - in[k]));
        }
        return inside_unit_interval(a_in ? t : 1 - t);
    }
    // g = phi_ma − phi_mb along the segment, cell by cell: the segment's
    // pieces between the voxel-cell faces it crosses; on each, g is the
    // (cubic) restriction of one cell's trilinear interpolants, and it is
    // continuous across the faces (the weights of the corners off a face are
    // 0 there).  The cut is g's first zero from a: found in the first piece
    // where g turns positive.
    std::array<double, 64> small;  // the breaks, on the stack unless the segment crosses many cells
    std::vector<double> large;
    std::size_t count = 0;
    std::span<double> breaks(small);
    const auto add = [&](double t) {
        if (count == breaks.size()) {
            large.assign(breaks.begin(), breaks.end());
            large.resize(2 * large.size());
            breaks = large;
        }
        breaks[count++] = t;
    };
    add(0), add(1);
    for (std::size_t k = 0; k < 3; ++k) {
        const double lo = std::min(xa[k], xb[k]), hi = std::max(xa[k], xb[k]);
        for (double z = std::floor(lo) + 1; z < hi; ++z) add((z - xa[k]) / (xb[k] - xa[k]));
    }
    breaks = breaks.first(count);
    std::sort(breaks.begin(), breaks.end());
    const std::array<int, 2> ms{ma, mb};
    std::array<std::array<double, 8>, 2> d;  // written by corner_phis before use
    double g_start = 0;
    for (std::size_t i = 0; i + 1 < breaks.size(); ++i) {
        const double t0 = breaks[i], t1 = breaks[i + 1];
        if (!(t1 > t0)) continue;
        std::array<std::int64_t, 3> cell{};
        Index3 f{};
        cell_of(x_at(0.5 * (t0 + t1)), cell, f);
        corner_phis(cell, ms, d);
        const Index3 corner{static_cast<double>(cell[0]), static_cast<double>(cell[1]), static_cast<double>(cell[2])};
        const auto g = [&](double u) {
            const Index3 x = x_at(u);
            for (std::size_t a = 0; a < 3; ++a) f[a] = x[a] - corner[a];
            const std::array<double, 8> weights = trilinear_weights(f);
            return trilinear(d[0], weights) - trilinear(d[1], weights);
        };
        if (i == 0) {
            g_start = g(0);
            if (!(g_start < 0)) return inside_unit_interval(0);  // a tie at a: the cut is at a
        }
        const double g_end = g(t1);
        if (g_end == 0) return inside_unit_interval(t1);
        if (g_end > 0) {
            const double v = bracketed_root_of([&](double w) { return g(t0 + w * (t1 - t0)); }, g_start, g_end);
            return inside_unit_interval(t0 + v * (t1 - t0));
        }
        g_start = g_end;
    }
    return inside_unit_interval(1);  // never positive before b: the cut is at b
}

}  // namespace

std::unique_ptr<MaterialField3> make_volume_materials3(const Volume& volume, const std::string& spec, std::uint64_t max_memory) {
    return std::make_unique<VolumeMaterials3>(volume, spec, max_memory);
}

}  // namespace warpmesh
