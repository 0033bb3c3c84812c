// embedding.hpp (internal) — what keeps a mesh a valid embedding while the
// optimisation pass and its refinement move boundary vertices, and what the
// mesh checks use to find overlaps.
//
// Why boundary edges suffice.  Let a valid mesh M change only on a set R of
// triangles (a moved vertex's star, a refined patch) into R', every triangle
// of R' counter-clockwise, and the closed curve ∂R' the same as ∂R except for
// the changed boundary edges (those at a moved or new vertex).  The number of
// triangles of R' covering a point is the winding number of ∂R' around it
// (each triangle counts +1), so R' covers its region once iff ∂R' is simple.
// R' overlaps the rest of the mesh, M \ R, only if ∂R' crosses ∂(M \ R) =
// the mesh's other boundary edges plus the border of R (shared, on the other
// side), or if a whole piece of M \ R lies inside R' (then one of its
// boundary vertices does).  Hence a change is a valid embedding iff
//   (a) no changed boundary edge meets another boundary edge of the mesh or
//       of R', or an edge of R's border, except at a shared endpoint (and
//       two edges with a shared endpoint do not overlap along a line), and
//   (b) no boundary vertex of the mesh that is not a vertex of R' lies in a
//       triangle of R' (closed).
// Moves of interior vertices (their star is a closed fan around a simple
// polygon) and flips of convex quadrilaterals never need the test.
//
// BoundaryIndex finds the boundary edges near a box: a hash grid of cells of
// side `cell`, each listing the edges whose box met it when added.  An edge
// is re-added after its ends move; stale entries stay and only cost time (the
// callers test the current positions).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <unordered_map>
#include <vector>

#include "plane.hpp"
#include "warpmesh/core/mesh.hpp"

namespace warpmesh {

// Orientation of c with respect to the line a → b: twice the signed area.
inline double orient(Vec2 a, Vec2 b, Vec2 c) { return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x); }

// Do the closed segments a-b and c-d (no shared endpoint) meet?
inline bool segments_meet(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
    const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
    if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
    const auto on = [](Vec2 p, Vec2 q, Vec2 x) {  // x on segment p-q, given collinear
        return std::min(p.x, q.x) <= x.x && x.x <= std::max(p.x, q.x) && std::min(p.y, q.y) <= x.y && x.y <= std::max(p.y, q.y);
    };
    return (o1 == 0 && on(a, b, c)) || (o2 == 0 && on(a, b, d)) || (o3 == 0 && on(c, d, a)) || (o4 == 0 && on(c, d, b));
}

// Two segments p-q1 and p-q2 with the shared endpoint p: do they overlap
// along a line (q2 on the ray p → q1, or q1 on p → q2)?
inline bool segments_fold(Vec2 p, Vec2 q1, Vec2 q2) {
    return orient(p, q1, q2) == 0 && (q1.x - p.x) * (q2.x - p.x) + (q1.y - p.y) * (q2.y - p.y) > 0;
}

// Is x in the closed counter-clockwise triangle a, b, c?
inline bool in_triangle(Vec2 a, Vec2 b, Vec2 c, Vec2 x) {
    return orient(a, b, x) >= 0 && orient(b, c, x) >= 0 && orient(c, a, x) >= 0;
}

// Do two segments given by vertex indices meet where they should not: a
// shared endpoint allows touching there only (no fold along a line); no
// shared endpoint allows nothing.  Positions are passed (a trial may move
// vertices).
inline bool edges_conflict(std::int32_t a, std::int32_t b, Vec2 pa, Vec2 pb, std::int32_t c, std::int32_t d, Vec2 pc,
                           Vec2 pd) {
    if ((a == c && b == d) || (a == d && b == c)) return false;  // the same edge
    if (a == c) return segments_fold(pa, pb, pd);
    if (a == d) return segments_fold(pa, pb, pc);
    if (b == c) return segments_fold(pb, pa, pd);
    if (b == d) return segments_fold(pb, pa, pc);
    return segments_meet(pa, pb, pc, pd);
}

class BoundaryIndex {
public:
    BoundaryIndex() = default;
    // Every edge of mesh.boundary, cells of side `cell` (> 0).
    BoundaryIndex(const Mesh& mesh, double cell) : cell_(cell) {
        for (std::size_t e = 0; e < mesh.boundary.size(); ++e) add(mesh, e);
    }
    // (Re-)add boundary edge e at its current position.
    void add(const Mesh& mesh, std::size_t e) {
        const Vec2 a = mesh.vertices[static_cast<std::size_t>(mesh.boundary[e][0])];
        const Vec2 b = mesh.vertices[static_cast<std::size_t>(mesh.boundary[e][1])];
        const auto [i0, j0, i1, j1] = range(std::min(a.x, b.x), std::min(a.y, b.y), std::max(a.x, b.x), std::max(a.y, b.y));
        for (std::int64_t i = i0; i <= i1; ++i)
            for (std::int64_t j = j0; j <= j1; ++j) cells_[key(i, j)].push_back(static_cast<std::uint32_t>(e));
    }
    // fn(e) for the edges listed in the cells that meet the box (an edge may
    // come more than once).
    template <class Fn>
    void near(Vec2 lo, Vec2 hi, Fn&& fn) const {
        const auto [i0, j0, i1, j1] = range(lo.x, lo.y, hi.x, hi.y);
        for (std::int64_t i = i0; i <= i1; ++i)
            for (std::int64_t j = j0; j <= j1; ++j)
                if (const auto it = cells_.find(key(i, j)); it != cells_.end())
                    for (const std::uint32_t e : it->second) fn(static_cast<std::size_t>(e));
    }

private:
    std::array<std::int64_t, 4> range(double x0, double y0, double x1, double y1) const {
        const auto c = [&](double v) { return static_cast<std::int64_t>(std::floor(v / cell_)); };
        return {c(x0), c(y0), c(x1), c(y1)};
    }
    static std::uint64_t key(std::int64_t i, std::int64_t j) {
        return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(i)) << 32) | static_cast<std::uint32_t>(j);
    }
    double cell_ = 1;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells_;
};

using EdgeIds = std::array<std::int32_t, 2>;

// Tests (a) and (b) above for a change R -> R'.  `changed`: the changed
// boundary edges of R'; `local`: the other boundary edges of R' and the edges
// of R's border; `tris`: R' (counter-clockwise); pos(v): a vertex's position
// after the change; replaced(e): true for the mesh boundary edges that R'
// replaces (those of R), which are skipped.  Also no vertex of R' lies in a
// triangle of R' that does not have it.  True: the change is an embedding.
template <class Pos, class Replaced>
bool change_embeds(const Mesh& mesh, const BoundaryIndex& index, std::span<const EdgeIds> changed,
                   std::span<const EdgeIds> local, std::span<const std::array<std::int32_t, 3>> tris, Pos&& pos,
                   Replaced&& replaced) {
    const auto box = [&](std::span<const std::int32_t> vs, Vec2& lo, Vec2& hi) {
        lo = hi = pos(vs[0]);
        for (const std::int32_t v : vs) {
            const Vec2 p = pos(v);
            lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)}, hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
        }
    };
    for (const EdgeIds& c : changed) {
        const Vec2 pa = pos(c[0]), pb = pos(c[1]);
        for (const EdgeIds& l : local)
            if (edges_conflict(c[0], c[1], pa, pb, l[0], l[1], pos(l[0]), pos(l[1]))) return false;
        bool ok = true;
        Vec2 lo, hi;
        box(c, lo, hi);
        index.near(lo, hi, [&](std::size_t e) {
            const auto [x, y] = mesh.boundary[e];
            if (ok && !replaced(e)) ok = !edges_conflict(c[0], c[1], pa, pb, x, y, pos(x), pos(y));
        });
        if (!ok) return false;
    }
    std::vector<std::int32_t> own;  // the vertices of R'
    for (const auto& t : tris) own.insert(own.end(), t.begin(), t.end());
    std::sort(own.begin(), own.end());
    own.erase(std::unique(own.begin(), own.end()), own.end());
    for (const auto& t : tris) {
        const Vec2 a = pos(t[0]), b = pos(t[1]), c = pos(t[2]);
        const auto inside = [&](std::int32_t v) { return v != t[0] && v != t[1] && v != t[2] && in_triangle(a, b, c, pos(v)); };
        for (const std::int32_t v : own)
            if (inside(v)) return false;
        bool ok = true;
        Vec2 lo, hi;
        box(t, lo, hi);
        index.near(lo, hi, [&](std::size_t e) {
            if (!ok || replaced(e)) return;
            for (const std::int32_t v : mesh.boundary[e])
                if (!std::binary_search(own.begin(), own.end(), v) && inside(v)) ok = false;
        });
        if (!ok) return false;
    }
    return true;
}

}  // namespace warpmesh
