// bcc_stuffing.hpp — a small reference implementation of the 3D mesher's
// contract (generic_bcc.hpp, steps 1–6) on a block of n³ cubes, for the tests
// and the explorer (prover/tools/bcc_explore.cpp).  It is not the 3D mesher:
// it exists to check the definition (conformity, orientation) and to map each
// background tetrahedron to its configuration in the local frame (the
// prover's key and parameters).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <map>
#include <vector>

#include "warpmesh/generic_bcc.hpp"
#include "warpmesh/generic_bcc_keys.hpp"

namespace warpmesh::testing {

// One background tetrahedron that produced output: its configuration in the
// local frame, the parameters, and the global ids of its output tetrahedra.
struct StuffedTet {
    bcc::Config config;
    std::array<double, 4> t{};
    std::array<double, 6> u{};
    int first = 0, count = 0;  // output tetrahedra first .. first + count - 1
};

struct Stuffed {
    std::vector<std::array<double, 3>> points;
    std::vector<bool> on_surface;  // per point: a zero lattice point or a cut point
    std::vector<std::array<int, 4>> tets;
    std::vector<StuffedTet> background;
    int all_zero_left_out = 0;  // background tetrahedra with four zero vertices (never output)
};

// Meshes {f <= 0} on the block [0, n s]³ (lattice points of doubled
// coordinates 0..2n) with violation thresholds `al`.  Cut points by linear
// interpolation of f along the edge (a zero of f for affine f).
inline Stuffed stuff(const std::function<double(double, double, double)>& f, int n, double s, const bcc::Alphas& al) {
    const int m = 2 * n + 1;
    const auto idx = [m](const bcc::Ivec& q) { return (q[2] * m + q[1]) * m + q[0]; };
    const auto inside = [m](const bcc::Ivec& q) {
        for (int k = 0; k < 3; ++k)
            if (q[static_cast<std::size_t>(k)] < 0 || q[static_cast<std::size_t>(k)] >= m) return false;
        return (q[0] & 1) == (q[1] & 1) && (q[1] & 1) == (q[2] & 1);
    };
    const double al_long = static_cast<double>(al.long_num) / static_cast<double>(al.long_den);
    const double al_short = static_cast<double>(al.short_num) / static_cast<double>(al.short_den);
    std::vector<double> val(static_cast<std::size_t>(m * m * m), 0);
    std::vector<int> sign(val.size(), 0), warp(val.size(), bcc::stay), vid(val.size(), -1);
    std::vector<double> wfrac(val.size(), 0);
    Stuffed out;
    std::vector<bcc::Ivec> lattice;
    for (int z = 0; z < m; ++z)
        for (int y = 0; y < m; ++y)
            for (int x = 0; x < m; ++x) {
                const bcc::Ivec q{x, y, z};
                if (!inside(q)) continue;
                const auto i = static_cast<std::size_t>(idx(q));
                val[i] = f(x * s / 2, y * s / 2, z * s / 2);
                sign[i] = val[i] < 0 ? -1 : val[i] > 0 ? 1 : 0;
                lattice.push_back(q);
            }
    const auto frac = [&](const bcc::Ivec& p, const bcc::Ivec& q) {  // cut fraction from p
        const double a = val[static_cast<std::size_t>(idx(p))], b = val[static_cast<std::size_t>(idx(q))];
        return a / (a - b);
    };
    // Steps 3-4: violations, closest first.
    std::vector<bcc::Violation> viol;
    for (const bcc::Ivec& p : lattice)
        for (int d = 0; d < bcc::direction_count; ++d) {
            const bcc::Ivec q = bcc::add(p, bcc::neighbour_offsets[static_cast<std::size_t>(d)]);
            if (!inside(q) || sign[static_cast<std::size_t>(idx(p))] * sign[static_cast<std::size_t>(idx(q))] >= 0) continue;
            const double u = frac(p, q);
            if (u < (bcc::is_long_direction(d) ? al_long : al_short)) viol.push_back({u, p, d});
        }
    std::sort(viol.begin(), viol.end(), bcc::warp_before);
    std::vector<std::array<double, 3>> pos(val.size());
    for (const bcc::Ivec& p : lattice)
        pos[static_cast<std::size_t>(idx(p))] = {p[0] * s / 2, p[1] * s / 2, p[2] * s / 2};
    for (const bcc::Violation& v : viol) {
        const auto i = static_cast<std::size_t>(idx(v.vertex));
        const bcc::Ivec q = bcc::add(v.vertex, bcc::neighbour_offsets[static_cast<std::size_t>(v.direction)]);
        const auto j = static_cast<std::size_t>(idx(q));
        if (warp[i] != bcc::stay || warp[j] != bcc::stay || sign[i] == 0 || sign[j] == 0) continue;
        warp[i] = v.direction;
        wfrac[i] = v.frac;
        for (int k = 0; k < 3; ++k) pos[i][static_cast<std::size_t>(k)] += v.frac * (pos[j][static_cast<std::size_t>(k)] - pos[i][static_cast<std::size_t>(k)]);
        sign[i] = 0;
    }
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
                    const bcc::Stencil st = bcc::stencil(bt.config.sign, bt.config.parity);
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

}  // namespace warpmesh::testing
