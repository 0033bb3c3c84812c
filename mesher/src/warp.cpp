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
#include <tuple>

#include "warpmesh/lattice.hpp"

namespace warpmesh {

std::vector<WarpedPoint> warp_points(const Lattice& lattice, std::span<const CutEdge> cuts) {
    std::vector<WarpedPoint> cand;
    cand.reserve(cuts.size());
    for (const CutEdge& e : cuts) {
        const std::int64_t q = e.p + (e.axis == 0 ? 1 : lattice.points_x());
        const bool p_moves = e.u < 0.5 || (e.u == 0.5 && e.sign < 0);
        if (p_moves)
            cand.push_back({e.p, e.axis == 0 ? Warp::px : Warp::py, e.u});
        else
            cand.push_back({q, e.axis == 0 ? Warp::mx : Warp::my, 1 - e.u});
    }
    // Nearest first, then the direction order of the Warp enumeration.
    std::sort(cand.begin(), cand.end(), [](const WarpedPoint& a, const WarpedPoint& b) {
        return std::tie(a.p, a.t, a.dir) < std::tie(b.p, b.t, b.dir);
    });
    cand.erase(std::unique(cand.begin(), cand.end(),
                           [](const WarpedPoint& a, const WarpedPoint& b) { return a.p == b.p; }),
               cand.end());
    return cand;
}

}  // namespace warpmesh
