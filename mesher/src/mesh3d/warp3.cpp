// warp3.cpp — stage 4: closest-first warping (steps 3–5 of generic_bcc.hpp's
// contract).  A cut point at fraction u < α_e of its edge from an endpoint v
// is a violation of v; violations are applied in warp_before order (smaller
// fraction first, ties by v's coordinates, then the direction), each iff v
// and the edge's other endpoint are both still unwarped.  v then moves to the
// cut point and its sign becomes 0.  The list of violations is surface-sized;
// sorting it makes the result independent of the threads.
//
// Blocks.  A window that is not the whole lattice does not see the
// violations of its points towards points outside it.  Those points (the
// window's rim, where the lattice continues) are *tainted* from the start:
// their state may differ from the whole lattice's at any time.  A violation
// (v, w) whose v or w is tainted when it is reached may be decided
// differently in the whole, so v becomes tainted.  An untainted point's
// whole history was decided by untainted states only, hence exactly as in
// the whole lattice.  mesh3d_block grows the window until no point its
// tetrahedra use is tainted.
#include <algorithm>
#include <cassert>
#include <tuple>

#include "uniform3d.hpp"

namespace warpmesh::uniform3d {
namespace {

struct Candidate {
    bcc::Violation v;
    std::int64_t vi, wi;   // window indices of v and of the edge's other endpoint
    std::int64_t lower;    // the edge's lower endpoint (window index) and slot
    int slot;
    double u;              // from the lower endpoint
};

constexpr int opposite(int d) {
    const bcc::Ivec& o = bcc::neighbour_offsets[static_cast<std::size_t>(d)];
    return bcc::direction_of({-o[0], -o[1], -o[2]});
}

// The order of the candidates by bcc::warp_before (fraction, then the
// violated vertex's coordinates lexicographically, then the direction):
// 32-byte keys, sorted, each with its candidate's index (`at`).  The
// coordinates are lattice coordinates, >= 0 and below 2^32, so (x, y) and
// (z, direction) packed into two 64-bit words compare as the tuple does
// (checked against warp_before, the definition, in debug builds).  The
// candidates themselves are not moved: they are read through the keys.
struct WarpKey {
    double frac;
    std::uint64_t xy, zd;
    std::size_t at;
    bool operator<(const WarpKey& o) const { return std::tie(frac, xy, zd) < std::tie(o.frac, o.xy, o.zd); }
};
Buffer<WarpKey> in_warp_order(std::span<const Candidate> all) {
    Buffer<WarpKey> keys(all.size());
    for (std::size_t i = 0; i < all.size(); ++i) {
        const bcc::Violation& v = all[i].v;
        const auto bits = [](int x) { return static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)); };
        keys[i] = {v.frac, bits(v.vertex[0]) << 32 | bits(v.vertex[1]), bits(v.vertex[2]) << 32 | bits(v.direction), i};
    }
    std::sort(keys.begin(), keys.end());
    assert(std::is_sorted(keys.begin(), keys.end(), [&](const WarpKey& a, const WarpKey& b) { return bcc::warp_before(all[a.at].v, all[b.at].v); }));
    return keys;
}

// The violations of the cut edges of plane z's points, in point and slot
// order: body(candidate) for each.
template <class Body>
void plane_violations(const Window& w, int z, double a_long, double a_short, Body&& body) {
    const Grid& g = w.grid;
    for (std::int64_t p = g.plane_start[static_cast<std::size_t>(z)]; p < g.plane_start[static_cast<std::size_t>(z) + 1]; ++p) {
        const unsigned mask = w.cut_mask[static_cast<std::size_t>(p)];
        if (!mask) continue;
        const bcc::Ivec pq = g.point_in_plane(z, p);
        for (int s = 0; s < 7; ++s) {
            if (!(mask >> s & 1u)) continue;
            const int d = forward_direction[static_cast<std::size_t>(s)];
            const bcc::Ivec q = bcc::add(pq, bcc::neighbour_offsets[static_cast<std::size_t>(d)]);
            const std::int64_t qi = g.index(q);
            const double u = w.u(p, s), alpha = slot_is_long(s) ? a_long : a_short;
            if (u < alpha) body(Candidate{{u, pq, d}, p, qi, p, s, u});
            if (1 - u < alpha) body(Candidate{{1 - u, q, opposite(d)}, qi, p, p, s, u});
        }
    }
}

}  // namespace

Point3 Window::point_position(std::int64_t p) const {
    if (warp[static_cast<std::size_t>(p)] != bcc::stay) {
        const auto it = std::lower_bound(warped.begin(), warped.end(), p,
                                         [](const std::pair<std::int64_t, Point3>& a, std::int64_t b) { return a.first < b; });
        return it->second;
    }
    return lattice_position(grid.point(p));
}

void warp_points(const bcc::Alphas& alphas, Window& w, bool blocked) {
    const Grid& g = w.grid;
    const std::size_t n = static_cast<std::size_t>(g.count());
    const int planes = g.hi[2] - g.lo[2] + 1;
    const double a_long = bcc::alpha<double>(alphas, true), a_short = bcc::alpha<double>(alphas, false);
    w.warp.resize(n);
    // The candidates of every plane, counted, then written in place in plane order.
    std::vector<std::int64_t> start(static_cast<std::size_t>(planes) + 1, 0);
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z) {
        std::fill(w.warp.begin() + g.plane_start[static_cast<std::size_t>(z)], w.warp.begin() + g.plane_start[static_cast<std::size_t>(z) + 1], bcc::stay);
        std::int64_t count = 0;
        plane_violations(w, z, a_long, a_short, [&](const Candidate&) { ++count; });
        start[static_cast<std::size_t>(z) + 1] = count;
    }
    for (int z = 0; z < planes; ++z) start[static_cast<std::size_t>(z) + 1] += start[static_cast<std::size_t>(z)];
    Buffer<Candidate> all(static_cast<std::size_t>(start.back()));  // every element written below
#pragma omp parallel for schedule(dynamic, 1)
    for (int z = 0; z < planes; ++z) {
        Candidate* out = all.data() + start[static_cast<std::size_t>(z)];
        plane_violations(w, z, a_long, a_short, [&](const Candidate& c) { *out++ = c; });
    }
    const Buffer<WarpKey> order = in_warp_order(all);

    if (blocked) {  // the rim: points with a lattice neighbour outside the window
        w.taint.assign(n, 0);
        for (std::size_t p = 0; p < n; ++p) {
            const bcc::Ivec q = g.point(static_cast<std::int64_t>(p));
            for (const bcc::Ivec& d : bcc::neighbour_offsets) {
                const bcc::Ivec r = bcc::add(q, d);
                if (!g.contains(r) && in_lattice(g.lattice, r)) w.taint[p] = 1;
            }
        }
    }
    w.warped.clear();
    w.warped.reserve(all.size());  // at most one a candidate (address space: only what is written is touched)
    for (const WarpKey& k : order) {
        const Candidate& c = all[k.at];
        const std::size_t v = static_cast<std::size_t>(c.vi), o = static_cast<std::size_t>(c.wi);
        if (blocked && (w.taint[v] || w.taint[o])) w.taint[v] = 1;
        if (w.warp[v] != bcc::stay || w.warp[o] != bcc::stay) continue;
        w.warp[v] = static_cast<std::uint8_t>(c.v.direction);
        w.sign[v] = 0;
        w.warped.emplace_back(c.vi, w.cut_position(g.point(c.lower), c.slot, c.u));
    }
    std::sort(w.warped.begin(), w.warped.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    w.warp_count = static_cast<std::int64_t>(w.warped.size());
}

}  // namespace warpmesh::uniform3d
