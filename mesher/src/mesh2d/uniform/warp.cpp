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
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <tuple>

#include "warpmesh/mesh2d/lattice.hpp"

namespace warpmesh {

std::vector<WarpedPoint> warp_points(const Lattice& lattice, std::span<const CutEdge> cuts, std::span<const std::uint32_t> order) {
    // The candidates fall into four streams by mover and axis: p along +x, p
    // along +y, q = p + x along -x, q = p + y along -y.  The cut edges come in
    // (p, axis) order, and a point is the lower (upper) endpoint of at most
    // one cut edge per axis, so each stream — a subsequence of that order — is
    // sorted by point with no point twice.  A four-way merge in the order
    // (point, t, direction) — nearest first, then the order of the Warp
    // enumeration — replaces a sort.  The streams hold indices into `cuts` (4
    // bytes an edge, not a copy of it).
    const std::int64_t nxp = lattice.points_x();
    if (cuts.size() >= UINT32_MAX) throw std::length_error("too many cut edges");
    if (!order.empty() && order.size() != cuts.size()) throw std::invalid_argument("warp_points: order is not a permutation of the cut edges");
    auto p_moves = [](const CutEdge& e) { return e.u < 0.5 || (e.u == 0.5 && e.sign < 0); };
    std::array<std::vector<std::uint32_t>, 4> stream;  // k = axis + 2 (q moves)
    for (auto& l : stream) l.reserve(cuts.size() / 2 + 1);
    for (std::size_t k = 0; k < cuts.size(); ++k) {
        const std::uint32_t c = order.empty() ? static_cast<std::uint32_t>(k) : order[k];
        stream[static_cast<std::size_t>(cuts[c].axis + (p_moves(cuts[c]) ? 0 : 2))].push_back(c);
    }
    auto candidate = [&](int k, std::uint32_t c) -> WarpedPoint {
        const CutEdge& e = cuts[c];
        switch (k) {
            case 0: return {e.p, Warp::px, e.u};
            case 1: return {e.p, Warp::py, e.u};
            case 2: return {e.p + 1, Warp::mx, 1 - e.u};
            default: return {e.p + nxp, Warp::my, 1 - e.u};
        }
    };
    auto before = [](const WarpedPoint& a, const WarpedPoint& b) { return std::tie(a.p, a.t, a.dir) < std::tie(b.p, b.t, b.dir); };
    constexpr std::int64_t done = std::numeric_limits<std::int64_t>::max();
    std::array<std::size_t, 4> at{};
    std::array<WarpedPoint, 4> head{};
    std::array<std::int64_t, 4> key{};  // the head's point, or `done`
    auto load = [&](std::size_t k) {
        key[k] = done;
        if (at[k] < stream[k].size()) head[k] = candidate(static_cast<int>(k), stream[k][at[k]]), key[k] = head[k].p;
    };
    for (std::size_t k = 0; k < 4; ++k) load(k);
    std::vector<WarpedPoint> out;
    out.reserve(cuts.size());
    for (;;) {
        // The smallest point by selects (which stream holds it is data-
        // dependent); another head at the same point, rarely, by (t, direction).
        std::size_t b = 0;
        for (std::size_t k = 1; k < 4; ++k) b = key[k] < key[b] ? k : b;
        if (key[b] == done) break;
        for (std::size_t k = 0; k < 4; ++k)
            if (k != b && key[k] == key[b] && before(head[k], head[b])) b = k;
        if (out.empty() || out.back().p != head[b].p) out.push_back(head[b]);  // the first of a point's candidates wins
        ++at[b];
        load(b);
    }
    return out;
}

}  // namespace warpmesh
