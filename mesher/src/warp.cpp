// warp.cpp — stage 4: move the closer endpoint of every cut edge onto it.
//
// For a cut edge with cut point at parameter u from p (towards q), p is at
// distance u and q at distance 1 - u (in units of s), so the closer endpoint is
// at distance min(u, 1 - u) <= 1/2.  Tie (u = 1/2 exactly): the endpoint with
// f < 0 moves — a rule that depends on the level set only, not on the
// orientation of the lattice.  A point that is the closer endpoint of several
// cut edges takes the nearest of their cut points (ties: +x, -x, +y, -y).
// Warped points carry the value 0 from here on: they lie on the level set.
#include <algorithm>
#include <array>
#include <tuple>

#include "warpmesh/lattice.hpp"

namespace warpmesh {

std::vector<WarpedPoint> warp_points(const Lattice& lattice, std::span<const CutEdge> cuts) {
    // The candidates fall into four lists by mover and axis: p along +x, p
    // along +y, q = p + x along -x, q = p + y along -y.  `cuts` is sorted by
    // (p, axis), and a point is the lower (upper) endpoint of at most one cut
    // edge per axis, so each list is sorted by point with no point twice.  A
    // four-way merge in the order (point, t, direction) — nearest first, then
    // the order of the Warp enumeration — replaces a sort.
    std::array<std::vector<WarpedPoint>, 4> list;
    for (auto& l : list) l.reserve(cuts.size() / 2 + 1);
    for (const CutEdge& e : cuts) {
        const std::int64_t q = e.p + (e.axis == 0 ? 1 : lattice.points_x());
        const bool p_moves = e.u < 0.5 || (e.u == 0.5 && e.sign < 0);
        if (p_moves)
            list[e.axis == 0 ? 0 : 1].push_back({e.p, e.axis == 0 ? Warp::px : Warp::py, e.u});
        else
            list[e.axis == 0 ? 2 : 3].push_back({q, e.axis == 0 ? Warp::mx : Warp::my, 1 - e.u});
    }
    auto before = [](const WarpedPoint& a, const WarpedPoint& b) { return std::tie(a.p, a.t, a.dir) < std::tie(b.p, b.t, b.dir); };
    std::vector<WarpedPoint> out;
    out.reserve(cuts.size());
    std::array<std::size_t, 4> at{};
    for (;;) {
        int best = -1;
        for (int k = 0; k < 4; ++k)
            if (at[static_cast<std::size_t>(k)] < list[static_cast<std::size_t>(k)].size() &&
                (best < 0 || before(list[static_cast<std::size_t>(k)][at[static_cast<std::size_t>(k)]],
                                    list[static_cast<std::size_t>(best)][at[static_cast<std::size_t>(best)]])))
                best = k;
        if (best < 0) break;
        const WarpedPoint& w = list[static_cast<std::size_t>(best)][at[static_cast<std::size_t>(best)]++];
        if (out.empty() || out.back().p != w.p) out.push_back(w);  // the first of a point's candidates wins
    }
    return out;
}

}  // namespace warpmesh
