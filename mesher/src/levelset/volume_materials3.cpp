// volume_materials3.cpp — the materials of a label volume (materials3.hpp:
// make_volume_materials3): a material index per voxel, phi_m from each
// voxel's 3 x 3 x 3 neighbourhood, the winner among a voxel cell's corner
// labels, and cut points as zeros of phi_a − phi_b.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <span>
#include <vector>

#include "../core/root_finder.hpp"
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
    std::optional<Box3> domain() const override { return bounds_; }  // the hull of the voxel centres
    std::string describe() const override { return "materials " + spec_ + " of '" + source_ + "'"; }
    double resolution() const override { return resolution_; }
    std::optional<double> reference_volume(int m) const override {
        return static_cast<double>(voxels_[static_cast<std::size_t>(m)]) * voxel_volume_;
    }
    int material_at(Point3 p) const override;
    double cut_parameter(Point3 a, Point3 b, int ma, int mb) const override;

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
    std::int64_t at(std::int64_t i, std::int64_t j, std::int64_t k) const { return i + n_[0] * (j + n_[1] * k); }
    // D_m (materials3.hpp) at the 8 corners of cell c (corner q = (i + (q & 1),
    // j + (q >> 1 & 1), k + (q >> 2))) for each material ms[m] (at most 8), in out[m].
    void corner_phis(const std::array<std::int64_t, 3>& c, std::span<const int> ms, std::span<std::array<double, 8>> out) const;
    static double trilinear(const std::array<double, 8>& d, const Index3& f);
    // The cell of x (its lowest corner, clamped so that the cell exists) and x's offset in it.
    void cell_of(const Index3& x, std::array<std::int64_t, 3>& c, Index3& f) const {
        for (std::size_t a = 0; a < 3; ++a) {
            c[a] = std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(x[a])), 0, n_[a] - 2);
            f[a] = x[a] - static_cast<double>(c[a]);
        }
    }

    std::array<std::int64_t, 3> n_{};
    std::array<std::size_t, 3> axis_{};  // the physical axis of index axis a
    std::array<double, 3> sign_{}, spacing_{}, origin_{};
    std::vector<std::uint16_t> mat_;          // per voxel
    std::vector<std::int32_t> tags_;          // per material
    std::vector<std::int64_t> voxels_;        // per material
    double voxel_volume_ = 1, resolution_ = 1;
    Box3 bounds_{};
    std::string source_, spec_;
};

VolumeMaterials3::VolumeMaterials3(const Volume& v, const std::string& spec, std::uint64_t max_memory)
    : n_(v.dims), source_(v.source), spec_(spec) {
    for (std::size_t a = 0; a < 3; ++a)
        if (n_[a] < 2)
            throw InputError("volume '" + source_ + "': multi-material meshing needs at least 2 voxels along every axis (got " +
                             std::to_string(n_[0]) + " x " + std::to_string(n_[1]) + " x " + std::to_string(n_[2]) + ")");
    check_memory(static_cast<std::uint64_t>(v.voxel_count()) * 2, max_memory, "the material field of '" + source_ + "'",
                 "2 bytes a voxel", "");
    std::vector<std::int64_t> hist(65536, 0);
    for (std::size_t q = 0; q < v.values.size(); ++q) {
        const double x = v.values[q];
        if (!(x >= 0 && x <= 65535 && x == std::floor(x))) {
            const std::int64_t i = static_cast<std::int64_t>(q) % n_[0], j = static_cast<std::int64_t>(q) / n_[0] % n_[1],
                               k = static_cast<std::int64_t>(q) / (n_[0] * n_[1]);
            throw InputError("volume '" + source_ + "': materials need integer labels in 0..65535, but voxel (" + std::to_string(i) +
                             ", " + std::to_string(j) + ", " + std::to_string(k) + ") is " + std::to_string(x));
        }
        ++hist[static_cast<std::size_t>(x)];
    }
    const std::vector<int> labels = select_material_labels(hist, spec, {"volume '" + source_ + "'", "materials", "voxel", "volume"});
    std::vector<std::uint16_t> material_of(65536, 0);
    tags_.push_back(0);
    for (std::size_t k = 0; k < labels.size(); ++k) {
        material_of[static_cast<std::size_t>(labels[k])] = static_cast<std::uint16_t>(k + 1);
        tags_.push_back(labels[k]);
    }
    voxels_.assign(tags_.size(), 0);
    mat_.resize(v.values.size());
    for (std::size_t q = 0; q < v.values.size(); ++q) {
        mat_[q] = material_of[static_cast<std::size_t>(v.values[q])];
        ++voxels_[mat_[q]];
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
        const std::size_t c = axis_[a];
        const double e0 = origin_[c], e1 = origin_[c] + sign_[a] * spacing_[a] * static_cast<double>(n_[a] - 1);
        lo[c] = std::min(e0, e1), hi[c] = std::max(e0, e1);
    }
    bounds_ = {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
    voxel_volume_ = spacing_[0] * spacing_[1] * spacing_[2];
    resolution_ = std::min({spacing_[0], spacing_[1], spacing_[2]});
}

void VolumeMaterials3::corner_phis(const std::array<std::int64_t, 3>& c, std::span<const int> ms, std::span<std::array<double, 8>> out) const {
    static constexpr std::array<double, 5> root{0, 1, 1.4142135623730951, 1.7320508075688772, 2};
    // The labels of the 4 x 4 x 4 voxels around the cell (-1 beyond the
    // volume), block[(z + 1) 16 + (y + 1) 4 + (x + 1)] for x, y, z in -1..2.
    std::array<int, 64> block;  // every entry written below
    for (int z = -1; z <= 2; ++z)
        for (int y = -1; y <= 2; ++y)
            for (int x = -1; x <= 2; ++x) {
                const std::int64_t i = c[0] + x, j = c[1] + y, k = c[2] + z;
                const bool in = i >= 0 && j >= 0 && k >= 0 && i < n_[0] && j < n_[1] && k < n_[2];
                block[static_cast<std::size_t>((z + 1) * 16 + (y + 1) * 4 + (x + 1))] = in ? mat_[static_cast<std::size_t>(at(i, j, k))] : -1;
            }
    // The 26 neighbours' offsets in the block and their squared distances.
    static constexpr auto neighbours = [] {
        std::array<std::pair<int, int>, 26> n{};
        int m = 0;
        for (int z = -1; z <= 1; ++z)
            for (int y = -1; y <= 1; ++y)
                for (int x = -1; x <= 1; ++x)
                    if (x || y || z) n[static_cast<std::size_t>(m++)] = {z * 16 + y * 4 + x, x * x + y * y + z * z};
        return n;
    }();
    for (int q = 0; q < 8; ++q) {
        const int centre = ((q >> 2) + 1) * 16 + ((q >> 1 & 1) + 1) * 4 + (q & 1) + 1;
        const int own = block[static_cast<std::size_t>(centre)];
        // The nearest voxel not of `own` (own's d) and the nearest of each
        // other material asked for.
        std::array<int, 8> best{4, 4, 4, 4, 4, 4, 4, 4};
        int best_other = 4;
        for (const auto& [offset, d2] : neighbours) {
            const int label = block[static_cast<std::size_t>(centre + offset)];
            if (label == own || label < 0) continue;
            best_other = std::min(best_other, d2);
            for (std::size_t m = 0; m < ms.size(); ++m)
                if (ms[m] == label) best[m] = std::min(best[m], d2);
        }
        for (std::size_t m = 0; m < ms.size(); ++m)
            out[m][static_cast<std::size_t>(q)] = ms[m] == own ? 0.5 - root[static_cast<std::size_t>(best_other)]
                                                              : root[static_cast<std::size_t>(best[m])] - 0.5;
    }
}

double VolumeMaterials3::trilinear(const std::array<double, 8>& d, const Index3& f) {
    double s = 0;
    for (int q = 0; q < 8; ++q)
        s += (q & 1 ? f[0] : 1 - f[0]) * (q >> 1 & 1 ? f[1] : 1 - f[1]) * (q >> 2 ? f[2] : 1 - f[2]) * d[static_cast<std::size_t>(q)];
    return s;
}

int VolumeMaterials3::material_at(Point3 p) const {
    const Index3 x = to_index(p);
    if (!in_hull(x)) return outside_material;
    std::array<std::int64_t, 3> c{};
    Index3 f{};
    cell_of(x, c, f);
    std::array<int, 8> corner{};
    for (int q = 0; q < 8; ++q) corner[static_cast<std::size_t>(q)] = mat_[static_cast<std::size_t>(at(c[0] + (q & 1), c[1] + (q >> 1 & 1), c[2] + (q >> 2)))];
    if (std::all_of(corner.begin(), corner.end(), [&](int m) { return m == corner[0]; })) return corner[0];
    // The candidates: the corners' materials; the smallest phi wins.
    std::array<int, 8> cand{};
    int n = 0;
    for (const int m : corner)
        if (std::find(cand.begin(), cand.begin() + n, m) == cand.begin() + n) cand[static_cast<std::size_t>(n++)] = m;
    std::array<std::array<double, 8>, 8> d;  // the first n written by corner_phis
    corner_phis(c, std::span<const int>(cand.data(), static_cast<std::size_t>(n)), std::span<std::array<double, 8>>(d.data(), static_cast<std::size_t>(n)));
    std::array<double, 8> value{};
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < static_cast<std::size_t>(n); ++k) best = std::min(best, value[k] = trilinear(d[k], f));
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
        const auto g = [&](double u) {
            const Index3 x = x_at(u);
            for (std::size_t a = 0; a < 3; ++a) f[a] = x[a] - static_cast<double>(cell[a]);
            return trilinear(d[0], f) - trilinear(d[1], f);
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
