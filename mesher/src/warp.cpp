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
    // The candidates fall into four streams by mover and axis: p along +x, p
    // along +y, q = p + x along -x, q = p + y along -y.  `cuts` is sorted by
    // (p, axis), and a point is the lower (upper) endpoint of at most one cut
    // edge per axis, so each stream — a subsequence of `cuts` — is sorted by
    // point with no point twice.  A four-way merge in the order (point, t,
    // direction) — nearest first, then the order of the Warp enumeration —
    // replaces a sort; each stream is read in place by its own cursor (no copy).
    const std::int64_t nxp = lattice.points_x();
    const std::size_t n = cuts.size();
    auto p_moves = [](const CutEdge& e) { return e.u < 0.5 || (e.u == 0.5 && e.sign < 0); };
    // Stream k: axis k & 1; the mover is p for k < 2, q for k >= 2.
    auto in_stream = [&](const CutEdge& e, int k) { return e.axis == (k & 1) && p_moves(e) == (k < 2); };
    auto candidate = [&](const CutEdge& e) -> WarpedPoint {
        if (p_moves(e)) return {e.p, e.axis == 0 ? Warp::px : Warp::py, e.u};
        return {e.p + (e.axis == 0 ? 1 : nxp), e.axis == 0 ? Warp::mx : Warp::my, 1 - e.u};
    };
    std::array<std::size_t, 4> at{};
    std::array<WarpedPoint, 4> head{};
    auto advance = [&](int k) {  // to stream k's next edge at or after at[k]; its candidate
        std::size_t& a = at[static_cast<std::size_t>(k)];
        while (a < n && !in_stream(cuts[a], k)) ++a;
        if (a < n) head[static_cast<std::size_t>(k)] = candidate(cuts[a]);
    };
    for (int k = 0; k < 4; ++k) advance(k);
    auto before = [](const WarpedPoint& a, const WarpedPoint& b) { return std::tie(a.p, a.t, a.dir) < std::tie(b.p, b.t, b.dir); };
    std::vector<WarpedPoint> out;
    out.reserve(n);
    for (;;) {
        int best = -1;
        for (int k = 0; k < 4; ++k)
            if (at[static_cast<std::size_t>(k)] < n &&
                (best < 0 || before(head[static_cast<std::size_t>(k)], head[static_cast<std::size_t>(best)])))
                best = k;
        if (best < 0) break;
        const WarpedPoint w = head[static_cast<std::size_t>(best)];
        if (out.empty() || out.back().p != w.p) out.push_back(w);  // the first of a point's candidates wins
        ++at[static_cast<std::size_t>(best)];
        advance(best);
    }
    return out;
}

}  // namespace warpmesh
