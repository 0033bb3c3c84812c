// bcc_stuffing.hpp — a small reference implementation of the 3D mesher's
// contract (generic_bcc.hpp, steps 1–6) on a block of n³ cubes, for the
// prover's tools (bcc_explore, bcc_ceiling) and the tests; in double, with
// acos in dihedral_degrees: never on the proof path.  It is not the 3D mesher:
// it exists to check the definition (conformity, orientation) and to map each
// background tetrahedron to its configuration in the local frame (the
// prover's key and parameters).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <vector>

#include "warpmesh/mesh3d/generic_bcc.hpp"
#include "warpmesh/mesh3d/generic_bcc_keys.hpp"

namespace warpmesh::bcc_stuffing {

// One background tetrahedron that produced output: its configuration in the
// local frame, the parameters, and the global ids of its output tetrahedra.
struct StuffedTet {
    bcc::Config config;
    std::array<double, 4> t{};
    std::array<double, 6> u{};
    bcc::Diagonals diagonals{};  // the quads' diagonals, as the face rule chose them
    int first = 0, count = 0;  // output tetrahedra first .. first + count - 1
};

struct Stuffed {
    std::vector<std::array<double, 3>> points;
    std::vector<bool> on_surface;  // per point: a zero lattice point or a cut point
    std::vector<std::array<int, 4>> tets;
    std::vector<StuffedTet> background;
    int all_zero_left_out = 0;  // background tetrahedra with four zero vertices (never output)
};

// The lattice of the block [0, n s]³ (doubled coordinates 0..2n, m = 2n + 1
// per axis) after steps 1–4: f's values and signs at the lattice points,
// each point's warp direction and fraction, and its position.
struct StuffGrid {
    int m = 0;
    double s = 0;
    std::vector<double> val, wfrac;
    std::vector<int> sign, warp;
    std::vector<std::array<double, 3>> pos;
    std::vector<bcc::Ivec> lattice;
    std::size_t idx(const bcc::Ivec& q) const { return static_cast<std::size_t>((q[2] * m + q[1]) * m + q[0]); }
    bool inside(const bcc::Ivec& q) const {
        for (int k = 0; k < 3; ++k)
            if (q[static_cast<std::size_t>(k)] < 0 || q[static_cast<std::size_t>(k)] >= m) return false;
        return (q[0] & 1) == (q[1] & 1) && (q[1] & 1) == (q[2] & 1);
    }
    double frac(const bcc::Ivec& p, const bcc::Ivec& q) const {  // cut fraction from p
        const double a = val[idx(p)], b = val[idx(q)];
        return a / (a - b);
    }
};

// Steps 1–4 with violation thresholds `al`: signs, and the violations applied
// closest first.  Cut points by linear interpolation of f along the edge (a
// zero of f for affine f).  `by_sign` (the explorer's rule experiments only,
// not the mesher's rule): thresholds per sign of the violated vertex,
// {α_long of a − vertex, α_long of a + vertex, α_short of −, α_short of +},
// replacing `al`'s.
inline StuffGrid stuff_grid(const std::function<double(double, double, double)>& f, int n, double s, const bcc::Alphas& al,
                            const std::array<double, 4>* by_sign) {
    StuffGrid g;
    g.m = 2 * n + 1, g.s = s;
    const int m = g.m;
    const double al_long = static_cast<double>(al.long_num) / static_cast<double>(al.long_den);
    const double al_short = static_cast<double>(al.short_num) / static_cast<double>(al.short_den);
    g.val.assign(static_cast<std::size_t>(m * m * m), 0);
    g.sign.assign(g.val.size(), 0), g.warp.assign(g.val.size(), bcc::stay), g.wfrac.assign(g.val.size(), 0);
    g.pos.resize(g.val.size());
    for (int z = 0; z < m; ++z)
        for (int y = 0; y < m; ++y)
            for (int x = 0; x < m; ++x) {
                const bcc::Ivec q{x, y, z};
                if (!g.inside(q)) continue;
                const auto i = g.idx(q);
                g.val[i] = f(x * s / 2, y * s / 2, z * s / 2);
                g.sign[i] = g.val[i] < 0 ? -1 : g.val[i] > 0 ? 1 : 0;
                g.pos[i] = {x * s / 2, y * s / 2, z * s / 2};
                g.lattice.push_back(q);
            }
    std::vector<bcc::Violation> viol;
    for (const bcc::Ivec& p : g.lattice)
        for (int d = 0; d < bcc::direction_count; ++d) {
            const bcc::Ivec q = bcc::add(p, bcc::neighbour_offsets[static_cast<std::size_t>(d)]);
            if (!g.inside(q) || g.sign[g.idx(p)] * g.sign[g.idx(q)] >= 0) continue;
            const double u = g.frac(p, q);
            const bool lng = bcc::is_long_direction(d);
            const double a = by_sign ? (*by_sign)[(lng ? 0U : 2U) + (g.sign[g.idx(p)] > 0 ? 1U : 0U)] : (lng ? al_long : al_short);
            if (u < a) viol.push_back({u, p, d});
        }
    std::sort(viol.begin(), viol.end(), bcc::warp_before);
    for (const bcc::Violation& v : viol) {
        const auto i = g.idx(v.vertex);
        const auto j = g.idx(bcc::add(v.vertex, bcc::neighbour_offsets[static_cast<std::size_t>(v.direction)]));
        if (g.warp[i] != bcc::stay || g.warp[j] != bcc::stay || g.sign[i] == 0 || g.sign[j] == 0) continue;
        g.warp[i] = v.direction;
        g.wfrac[i] = v.frac;
        for (std::size_t k = 0; k < 3; ++k) g.pos[i][k] += v.frac * (g.pos[j][k] - g.pos[i][k]);
        g.sign[i] = 0;
    }
    return g;
}

// Meshes {f <= 0} on the block [0, n s]³ (lattice points of doubled
// coordinates 0..2n) with violation thresholds `al` (and `by_sign`, as
// stuff_grid): steps 1–4 by stuff_grid, step 6 here.
// `delaunay`: quads split by generic_bcc.hpp's Delaunay face rule (at the
// double cut fractions) instead of the parity rule.
inline Stuffed stuff(const std::function<double(double, double, double)>& f, int n, double s, const bcc::Alphas& al,
                     const std::array<double, 4>* by_sign = nullptr, bool delaunay = false) {
    const StuffGrid g = stuff_grid(f, n, s, al, by_sign);
    const auto idx = [&g](const bcc::Ivec& q) { return static_cast<int>(g.idx(q)); };
    const auto inside = [&g](const bcc::Ivec& q) { return g.inside(q); };
    const auto frac = [&g](const bcc::Ivec& p, const bcc::Ivec& q) { return g.frac(p, q); };
    const std::vector<int>& sign = g.sign;
    const std::vector<int>& warp = g.warp;
    const std::vector<double>& wfrac = g.wfrac;
    const std::vector<std::array<double, 3>>& pos = g.pos;
    std::vector<int> vid(g.val.size(), -1);
    Stuffed out;
    // Step 6: stencils per background tetrahedron.
    std::map<std::pair<int, int>, int> cut_id;
    const auto vertex_id = [&](const bcc::Ivec& q) {
        int& v = vid[static_cast<std::size_t>(idx(q))];
        if (v < 0) {
            v = static_cast<int>(out.points.size());
            out.points.push_back(pos[static_cast<std::size_t>(idx(q))]);
            out.on_surface.push_back(sign[static_cast<std::size_t>(idx(q))] == 0);
        }
        return v;
    };
    const auto cut_vertex = [&](const bcc::Ivec& p, const bcc::Ivec& q) {
        const int a = idx(p), b = idx(q);
        auto it = cut_id.find({std::min(a, b), std::max(a, b)});
        if (it != cut_id.end()) return it->second;
        const double u = frac(p, q);
        std::array<double, 3> x{};
        for (int k = 0; k < 3; ++k) x[static_cast<std::size_t>(k)] = (p[static_cast<std::size_t>(k)] + u * (q[static_cast<std::size_t>(k)] - p[static_cast<std::size_t>(k)])) * s / 2;
        const int id = static_cast<int>(out.points.size());
        out.points.push_back(x);
        out.on_surface.push_back(true);
        cut_id[{std::min(a, b), std::max(a, b)}] = id;
        return id;
    };
    for (int cz = 0; cz < n; ++cz)
        for (int cy = 0; cy < n; ++cy)
            for (int cx = 0; cx < n; ++cx)
                for (int ti = 0; ti < 12; ++ti) {
                    const auto p = bcc::background_tet({2 * cx, 2 * cy, 2 * cz}, ti);
                    bool ok = true;
                    for (const auto& q : p) ok = ok && inside(q);
                    if (!ok) continue;  // the low faces' far centres lie outside the block
                    StuffedTet bt;
                    std::array<int, 4> vsign{}, vwarp{};
                    for (int i = 0; i < 4; ++i) {
                        const auto g = static_cast<std::size_t>(idx(p[static_cast<std::size_t>(i)]));
                        vsign[static_cast<std::size_t>(i)] = sign[g];
                        vwarp[static_cast<std::size_t>(i)] = warp[g];
                        if (warp[g] != bcc::stay) bt.t[static_cast<std::size_t>(i)] = wfrac[g];
                    }
                    bt.config = bcc::local_config(p, vsign, vwarp);
                    for (int e = 0; e < 6; ++e) {
                        const auto& ed = bcc::tet_edges[static_cast<std::size_t>(e)];
                        const auto& a = p[static_cast<std::size_t>(ed[0])];
                        const auto& b = p[static_cast<std::size_t>(ed[1])];
                        if (sign[static_cast<std::size_t>(idx(a))] * sign[static_cast<std::size_t>(idx(b))] < 0) bt.u[static_cast<std::size_t>(e)] = frac(a, b);
                    }
                    out.all_zero_left_out += vsign == std::array<int, 4>{0, 0, 0, 0};
                    bt.diagonals = delaunay ? bcc::delaunay_diagonals(bt.config.sign, bt.config.parity, bt.u)
                                            : bcc::parity_diagonals(bt.config.sign, bt.config.parity);
                    const bcc::Stencil st = bcc::stencil_with(bt.config.sign, bt.diagonals);
                    if (st.count == 0) continue;
                    bt.first = static_cast<int>(out.tets.size());
                    bt.count = st.count;
                    for (int k = 0; k < st.count; ++k) {
                        std::array<int, 4> g{};
                        for (int v = 0; v < 4; ++v) {
                            const int q = st.tet[static_cast<std::size_t>(k)][static_cast<std::size_t>(v)];
                            if (q < 4) g[static_cast<std::size_t>(v)] = vertex_id(p[static_cast<std::size_t>(q)]);
                            else {
                                const auto& ed = bcc::tet_edges[static_cast<std::size_t>(q - 4)];
                                g[static_cast<std::size_t>(v)] = cut_vertex(p[static_cast<std::size_t>(ed[0])], p[static_cast<std::size_t>(ed[1])]);
                            }
                        }
                        out.tets.push_back(g);
                    }
                    out.background.push_back(bt);
                }
    return out;
}

// A quadric level set (tests of the 3D definition).
struct Quadric {
    std::array<double, 10> c;
    double operator()(double x, double y, double z) const {
        return c[0] + c[1] * x + c[2] * y + c[3] * z + c[4] * x * x + c[5] * y * y + c[6] * z * z + c[7] * x * y +
               c[8] * y * z + c[9] * x * z;
    }
};

// A random ellipsoid-like level set centred in the block [0, n]^3.
inline Quadric random_shape(std::mt19937& rng, int n) {
    std::uniform_real_distribution<double> u(-1, 1);
    const double cx = n / 2.0 + u(rng), cy = n / 2.0 + u(rng), cz = n / 2.0 + u(rng);
    const double a = 1 + 0.5 * u(rng), b = 1 + 0.5 * u(rng), c = 1 + 0.5 * u(rng), r = n / 3.0 * (1 + 0.2 * u(rng));
    const double xy = 0.3 * u(rng), yz = 0.3 * u(rng), xz = 0.3 * u(rng);
    Quadric q{};
    q.c = {a * cx * cx + b * cy * cy + c * cz * cz + xy * cx * cy + yz * cy * cz + xz * cx * cz - r * r,
           -2 * a * cx - xy * cy - xz * cz, -2 * b * cy - xy * cx - yz * cz, -2 * c * cz - yz * cy - xz * cx,
           a, b, c, xy, yz, xz};
    return q;
}

// Conformity of a stuffed block: every tetrahedron positive, every face in
// at most two tetrahedra and then with opposite orientations, and a face of
// one tetrahedron only on the surface (all its vertices zero or cut points)
// or near the block's sides (the stuffed block is ragged).
struct Conformity {
    int non_positive = 0, over_shared = 0, same_orientation = 0, stray_boundary = 0, interior = 0;
    double volume = 0;
    bool ok() const { return non_positive == 0 && over_shared == 0 && same_orientation == 0 && stray_boundary == 0; }
};
inline Conformity conformity(const Stuffed& m, int n) {
    Conformity c;
    std::map<std::array<int, 3>, std::vector<int>> faces;  // sorted face -> +-1 by orientation parity
    for (const auto& t : m.tets) {
        std::array<bcc::Vec<double>, 4> p{};
        for (std::size_t v = 0; v < 4; ++v) p[v] = m.points[static_cast<std::size_t>(t[v])];
        const double vol = bcc::dihedral_forms(p).volume6;
        c.non_positive += vol > 0 ? 0 : 1;
        c.volume += vol / 6;
        static constexpr int opp[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};  // outward faces
        for (const auto& o : opp) {
            std::array<int, 3> f3{t[static_cast<std::size_t>(o[0])], t[static_cast<std::size_t>(o[1])], t[static_cast<std::size_t>(o[2])]};
            // rotate the smallest index first; the cyclic order then carries the orientation
            while (f3[0] != std::min({f3[0], f3[1], f3[2]})) std::rotate(f3.begin(), f3.begin() + 1, f3.end());
            const bool odd = f3[1] > f3[2];
            if (odd) std::swap(f3[1], f3[2]);
            faces[f3].push_back(odd ? -1 : 1);
        }
    }
    for (const auto& [f3, uses] : faces) {
        if (uses.size() > 2) ++c.over_shared;
        if (uses.size() == 2) {
            c.same_orientation += uses[0] == -uses[1] ? 0 : 1;
            ++c.interior;
            continue;
        }
        bool surface = true, near_side = false;
        for (int v : f3) {
            surface = surface && m.on_surface[static_cast<std::size_t>(v)];
            for (double x : m.points[static_cast<std::size_t>(v)]) near_side = near_side || x < 1 || x > n - 1;
        }
        c.stray_boundary += surface || near_side ? 0 : 1;
    }
    return c;
}

// The six dihedral angles of a tetrahedron, in degrees (tests and tools only:
// never on the proof path).
inline std::array<double, 6> dihedral_degrees(const std::array<bcc::Vec<double>, 4>& p) {
    const bcc::DihedralForms<double> f = bcc::dihedral_forms(p);
    std::array<double, 6> a{};
    for (int k = 0; k < 6; ++k)
        a[static_cast<std::size_t>(k)] =
            std::acos(std::clamp(f.dot[static_cast<std::size_t>(k)] / std::sqrt(f.nn[static_cast<std::size_t>(k)]), -1.0, 1.0)) * 180 / M_PI;
    return a;
}

}  // namespace warpmesh::bcc_stuffing
