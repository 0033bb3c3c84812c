// octree3.cpp — the graded mesher's balanced octree (octree3.hpp): the
// critical cubes, the coarsenable cells per level (with the
// grading buffer), the leaves, 2:1 balance across faces and edges, and the
// templates of a leaf (generic_octree.hpp's fans).
#include "mesh3d/graded/octree3.hpp"

#include <algorithm>
#include <stdexcept>

namespace warpmesh::graded3 {
namespace {

using uniform3d::Grid;
using uniform3d::Window;

// Cell classes: critical, or coarsenable of one class: one region's inside
// (−) or outside (+), or one material (its code).  A class fits 31 bits
// (a material code is 16), so critical is −1.
using Class = std::int32_t;
constexpr Class critical = -1, inside = 0, outside = 1;

// The class of window point p, or critical: one region, its post-warp sign
// (0: on the level set); several materials (`material` not empty), its
// material code (merge_outside: the outside is the background, code 0) if
// it is not warped (warp3 sets a warped point's sign to 0).
Class point_class(const Window& w, std::span<const std::uint16_t> material, bool merge_outside, std::int64_t p) {
    const int sign = w.sign[static_cast<std::size_t>(p)];
    if (sign == 0) return critical;
    if (material.empty()) return sign < 0 ? inside : outside;
    const std::uint16_t m = material[static_cast<std::size_t>(p)];
    return merge_outside && m == uniform3d::outside_code ? 0 : static_cast<Class>(m);
}

// Level 0: each cube's class from the classes of its 15 points (indices by
// offsets from the cube's lowest corner and its centre, as tets3.cpp's
// neighbourhood): coarsenable iff all 15 have one class that is not critical.
std::vector<Class> cube_classes(const Window& w, std::span<const std::uint16_t> material, bool merge_outside,
                                const std::array<std::int64_t, 3>& n) {
    const Grid& g = w.grid;
    const std::int64_t plane_pair = g.corner_w * g.corner_h + g.centre_w * g.centre_h;
    std::array<std::int64_t, 8> corner{};
    for (int b = 0; b < 8; ++b) corner[static_cast<std::size_t>(b)] = (b & 1) + ((b >> 1) & 1) * g.corner_w + (b >> 2) * plane_pair;
    const std::array<std::int64_t, 6> centre{-1, 1, -g.centre_w, g.centre_w, -plane_pair, plane_pair};
    std::vector<Class> cls(static_cast<std::size_t>(n[0] * n[1] * n[2]), critical);
#pragma omp parallel for schedule(dynamic, 1)
    for (std::int64_t z = 2; z < n[2] - 2; ++z)
        for (std::int64_t y = 2; y < n[1] - 2; ++y) {
            const bcc::Ivec m{4, static_cast<int>(2 * y), static_cast<int>(2 * z)};
            const std::int64_t k0 = g.index(m), c0 = g.index(bcc::add(m, {1, 1, 1}));
            for (std::int64_t x = 2; x < n[0] - 2; ++x) {
                const std::int64_t k = k0 + (x - 2), c = c0 + (x - 2);
                const Class first = point_class(w, material, merge_outside, c);
                bool ok = first != critical;
                for (std::size_t i = 0; i < 8 && ok; ++i) ok = point_class(w, material, merge_outside, k + corner[i]) == first;
                for (std::size_t i = 0; i < 6 && ok; ++i) ok = point_class(w, material, merge_outside, c + centre[i]) == first;
                if (ok) cls[static_cast<std::size_t>((z * n[1] + y) * n[0] + x)] = first;
            }
        }
    return cls;
}

// Level l + 1 from level l (dims n → n / 2): one class of 8 coarsenable children.
std::vector<Class> parent_classes(const std::vector<Class>& c, const std::array<std::int64_t, 3>& n,
                                         const std::array<std::int64_t, 3>& m) {
    std::vector<Class> out(static_cast<std::size_t>(m[0] * m[1] * m[2]), critical);
#pragma omp parallel for schedule(static)
    for (std::int64_t z = 0; z < m[2]; ++z)
        for (std::int64_t y = 0; y < m[1]; ++y)
            for (std::int64_t x = 0; x < m[0]; ++x) {
                const Class first = c[static_cast<std::size_t>((2 * z * n[1] + 2 * y) * n[0] + 2 * x)];
                bool same = first != critical;
                for (int b = 1; b < 8 && same; ++b)
                    same = c[static_cast<std::size_t>(((2 * z + (b >> 2)) * n[1] + 2 * y + ((b >> 1) & 1)) * n[0] + 2 * x + (b & 1))] == first;
                if (same) out[static_cast<std::size_t>((z * m[1] + y) * m[0] + x)] = first;
            }
    return out;
}

// The grading buffer: a cell stays coarsenable only if every cell within r
// (max norm) is coarsenable (cells beyond the grid count as critical); one
// pass per axis of a running count of critical cells.
void erode(std::vector<Class>& c, const std::array<std::int64_t, 3>& n, std::int64_t r) {
    std::vector<std::uint8_t> bad(c.size());
    for (std::size_t i = 0; i < c.size(); ++i) bad[i] = c[i] == critical;
    const std::array<std::int64_t, 3> stride{1, n[0], n[0] * n[1]};
    for (std::size_t a = 0; a < 3; ++a) {
        std::vector<std::uint8_t> next(bad.size());
        for (std::int64_t i = 0; i < static_cast<std::int64_t>(bad.size()); ++i) {
            const std::int64_t pos = (i / stride[a]) % n[a];
            bool any = pos - r < 0 || pos + r >= n[a];
            for (std::int64_t k = -r; k <= r && !any; ++k) any = bad[static_cast<std::size_t>(i + k * stride[a])];
            next[static_cast<std::size_t>(i)] = any;
        }
        bad.swap(next);
    }
    for (std::size_t i = 0; i < c.size(); ++i)
        if (bad[i]) c[i] = critical;
}

// Split the leaf containing cube q (level `from`) until the cell of level
// `to` containing q is a leaf.
void split_down(Octree3& t, const Cube& q, int from, int to) {
    for (int k = from; k > to; --k) {
        const std::int64_t side = std::int64_t{1} << k;
        Cube o{};
        for (std::size_t a = 0; a < 3; ++a) o[a] = q[a] & ~(side - 1);
        for (std::int64_t z = o[2]; z < o[2] + side; ++z)
            for (std::int64_t y = o[1]; y < o[1] + side; ++y)
                for (std::int64_t x = o[0]; x < o[0] + side; ++x) t.level[static_cast<std::size_t>(t.index({x, y, z}))] = static_cast<std::int8_t>(k - 1);
    }
}

// 2:1 balance across faces and edges, bottom up: every leaf of level l
// splits its neighbours (the 18 cells of its level sharing a face or an
// edge) of level l + 2 or more down to l + 1.  Splits only create leaves of
// levels above l, which later rounds treat; the result is the coarsest
// balanced refinement.
void balance(Octree3& t, int top) {
    std::vector<Cube> around;
    for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
                if (std::abs(dx) + std::abs(dy) + std::abs(dz) == 1 || std::abs(dx) + std::abs(dy) + std::abs(dz) == 2) around.push_back({dx, dy, dz});
    for (int l = 0; l + 2 <= top; ++l) {
        const std::int64_t side = std::int64_t{1} << l;
        for (std::int64_t z = 0; z + side <= t.cubes[2]; z += side)
            for (std::int64_t y = 0; y + side <= t.cubes[1]; y += side)
                for (std::int64_t x = 0; x + side <= t.cubes[0]; x += side) {
                    if (t.level_at({x, y, z}) != l) continue;
                    for (const Cube& d : around) {
                        const Cube q{x + d[0] * side, y + d[1] * side, z + d[2] * side};
                        if (!t.contains(q)) continue;
                        const int lq = t.level_at(q);
                        if (lq >= l + 2) split_down(t, q, lq, l + 1);
                    }
                }
    }
}

}  // namespace

Octree3 build_octree3(const Window& w, int max_level, int buffer, std::span<const std::uint16_t> material, bool merge_outside) {
    Octree3 t;
    t.cubes = w.grid.lattice.cubes;
    std::vector<std::vector<Class>> cls;
    std::vector<std::array<std::int64_t, 3>> dims;
    dims.push_back(t.cubes);
    cls.push_back(cube_classes(w, material, merge_outside, t.cubes));
    for (int l = 1; l <= max_level; ++l) {
        const std::array<std::int64_t, 3> n = dims.back(), m{n[0] / 2, n[1] / 2, n[2] / 2};
        if (m[0] == 0 || m[1] == 0 || m[2] == 0) break;
        cls.push_back(parent_classes(cls.back(), n, m));
        dims.push_back(m);
        if (buffer > 1) erode(cls.back(), m, buffer);
    }
    const int top = static_cast<int>(cls.size()) - 1;
    // The leaves: each cube at the level of its largest coarsenable cell
    // (a coarsenable cell's children are coarsenable): top down, a cell is
    // written once, when its parent is not coarsenable.
    t.level.assign(static_cast<std::size_t>(t.cubes[0] * t.cubes[1] * t.cubes[2]), 0);
    for (int l = top; l > 0; --l) {
        const auto& n = dims[static_cast<std::size_t>(l)];
        const std::int64_t side = std::int64_t{1} << l;
#pragma omp parallel for schedule(dynamic, 1)
        for (std::int64_t Z = 0; Z < n[2]; ++Z)
            for (std::int64_t Y = 0; Y < n[1]; ++Y)
                for (std::int64_t X = 0; X < n[0]; ++X) {
                    if (cls[static_cast<std::size_t>(l)][static_cast<std::size_t>((Z * n[1] + Y) * n[0] + X)] == critical) continue;
                    if (l < top) {
                        const auto& p = dims[static_cast<std::size_t>(l) + 1];
                        const std::int64_t PX = X >> 1, PY = Y >> 1, PZ = Z >> 1;
                        if (PX < p[0] && PY < p[1] && PZ < p[2] &&
                            cls[static_cast<std::size_t>(l) + 1][static_cast<std::size_t>((PZ * p[1] + PY) * p[0] + PX)] != critical)
                            continue;  // inside a coarser leaf, written at its level
                    }
                    for (std::int64_t z = Z * side; z < (Z + 1) * side; ++z)
                        for (std::int64_t y = Y * side; y < (Y + 1) * side; ++y)
                            std::fill_n(t.level.begin() + t.index({X * side, y, z}), side, static_cast<std::int8_t>(l));
                }
    }
    balance(t, top);
    t.leaves_per_level.assign(static_cast<std::size_t>(top) + 1, 0);
    for (const std::int8_t l : t.level) t.leaves_per_level[static_cast<std::size_t>(l)] += 1;
    for (int l = 0; l <= top; ++l) t.leaves_per_level[static_cast<std::size_t>(l)] >>= 3 * l;
    return t;
}

unsigned uniform_mask(const Octree3& t, const Cube& c) {
    unsigned mask = 0;
    for (std::size_t a = 0; a < 3; ++a) {
        Cube q = c;
        q[a] -= 1;
        if (!t.contains(q) || t.level_at(q) == 0) mask |= 0xFu << (4 * a);
    }
    return mask;
}

namespace {

// Whether the side of a level-l leaf's face with midpoint M (doubled
// coordinates, a corner) is split: a leaf of a lower level touches it, so
// one of the 8 cubes around M.
bool side_split(const Octree3& t, const bcc::Ivec& M, int l) {
    for (int b = 0; b < 8; ++b) {
        const Cube q{M[0] / 2 - 1 + (b & 1), M[1] / 2 - 1 + ((b >> 1) & 1), M[2] / 2 - 1 + (b >> 2)};
        if (t.contains(q) && t.level_at(q) < l) return true;
    }
    return false;
}

}  // namespace

int leaf_templates(const Octree3& t, const Cube& c, Templates& out) {
    const int l = t.level_at(c);
    const std::int64_t side = std::int64_t{1} << l;
    for (std::size_t a = 0; a < 3; ++a)
        if (c[a] & (side - 1)) return 0;  // not the leaf's origin
    const int n = static_cast<int>(side);
    const bcc::Ivec o{static_cast<int>(2 * c[0]), static_cast<int>(2 * c[1]), static_cast<int>(2 * c[2])};
    const bcc::Ivec cx = bcc::add(o, {n, n, n});
    int count = 0;
    for (int a = 0; a < 3; ++a)
        for (int s = -1; s <= 1; s += 2) {
            Cube q = c;
            q[static_cast<std::size_t>(a)] += s < 0 ? -1 : side;
            if (!t.contains(q)) continue;
            const int lq = t.level_at(q);
            if (!(lq > l || (lq == l && s < 0 && l > 0))) continue;  // the other leaf owns it, or the uniform stencils do
            const int ny = 1 << lq;
            bcc::Ivec cy{};
            for (std::size_t k = 0; k < 3; ++k) cy[k] = static_cast<int>(2 * (q[k] & ~static_cast<std::int64_t>(ny - 1))) + ny;
            bcc::Ivec f0 = o;
            if (s > 0) f0[static_cast<std::size_t>(a)] += 2 * n;
            unsigned split = 0;
            if (l > 0) {
                const bcc::FacePiece whole = bcc::face_piece(cx, cy, f0, a, 2 * n, 0);
                for (int k = 0; k < 4; ++k) {
                    const bcc::Ivec& P = whole.ring[static_cast<std::size_t>(k)];
                    const bcc::Ivec& Q = whole.ring[static_cast<std::size_t>((k + 1) % 4)];
                    if (side_split(t, {(P[0] + Q[0]) / 2, (P[1] + Q[1]) / 2, (P[2] + Q[2]) / 2}, l)) split |= 1u << k;
                }
            }
            std::array<bcc::LatticeTet, 8> fan;
            const int k = bcc::piece_tets(bcc::face_piece(cx, cy, f0, a, 2 * n, split), fan);
            for (int i = 0; i < k; ++i) out[static_cast<std::size_t>(count++)] = fan[static_cast<std::size_t>(i)];
        }
    return count;
}

}  // namespace warpmesh::graded3
