// remove.cpp — removal of interior vertices whose star a re-triangulation of
// their link lifts (remove.hpp: which vertices, the rule, the bookkeeping).
#include "remove.hpp"

#include <algorithm>
#include <array>
#include <utility>

#include "plane.hpp"
#include "warpmesh/post/quality.hpp"

namespace warpmesh {

namespace {

using namespace plane;
using Tri = std::array<std::int32_t, 3>;

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double max_angle_target = 110;  // a larger maximum only if the star had one
constexpr double min_gain_deg = 1e-9;     // "strictly increases", above rounding
constexpr std::size_t max_link = 12;      // larger stars are not tried

// Do the closed segments p-q and r-s share a point?
bool segments_meet(Vec2 p, Vec2 q, Vec2 r, Vec2 s) {
    const double d1 = cross(q - p, r - p), d2 = cross(q - p, s - p), d3 = cross(s - r, p - r), d4 = cross(s - r, q - r);
    if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
    const auto on = [](Vec2 a, Vec2 b, Vec2 c) {  // c on the segment a-b, given collinear
        return std::min(a.x, b.x) <= c.x && c.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= c.y && c.y <= std::max(a.y, b.y);
    };
    return (d1 == 0 && on(p, q, r)) || (d2 == 0 && on(p, q, s)) || (d3 == 0 && on(r, s, p)) || (d4 == 0 && on(r, s, q));
}

class Remover {
public:
    Remover(Mesh& mesh, const RemoveParams& p) : m_(mesh), p_(p) {}

    RemoveResult run(std::span<const std::size_t> eligible) {
        std::vector<std::pair<double, std::size_t>> bad;
        for (const std::size_t t : eligible)
            if (const double mn = min_angle(m_.triangles[t]); mn < p_.below_deg) bad.emplace_back(mn, t);
        if (bad.empty()) return {};
        std::sort(bad.begin(), bad.end());
        index(bad);
        for (const auto& [mn, t] : bad)
            for (int k = 0; k < 3; ++k) {
                const Tri T = m_.triangles[t];  // rewritten or emptied by a removal: look again
                if (T[0] < 0 || min_angle(T) >= p_.below_deg) break;
                const std::int32_t v = T[static_cast<std::size_t>(k)];
                if (interior_[static_cast<std::size_t>(v)] && candidate_[static_cast<std::size_t>(v)]) try_remove(v);
            }
        if (r_.removed_vertices) compact();
        return std::move(r_);
    }

private:
    Vec2 P(std::int32_t v) const { return m_.vertices[static_cast<std::size_t>(v)]; }
    double min_angle(const Tri& t) const { return triangle_min_angle(P(t[0]), P(t[1]), P(t[2])); }
    // The star of an indexed vertex (slot_ >= 0).
    std::vector<std::size_t>& star(std::int32_t v) { return stars_[static_cast<std::size_t>(slot_[static_cast<std::size_t>(v)])]; }
    const std::vector<std::size_t>& star(std::int32_t v) const {
        return stars_[static_cast<std::size_t>(slot_[static_cast<std::size_t>(v)])];
    }

    // Which vertices may be removed (on no boundary or interface edge), and
    // the stars of the candidates (the vertices of the bad triangles) and of
    // their neighbours — every vertex a removal rewrites a triangle of, since
    // a removal only joins neighbours of the removed candidate — from two
    // scans of the triangles; memory in proportion to the bad triangles.
    void index(const std::vector<std::pair<double, std::size_t>>& bad) {
        interior_.assign(m_.vertices.size(), 1);
        for (const auto& e : m_.boundary) interior_[static_cast<std::size_t>(e[0])] = interior_[static_cast<std::size_t>(e[1])] = 0;
        for (const auto& e : m_.interfaces) interior_[static_cast<std::size_t>(e[0])] = interior_[static_cast<std::size_t>(e[1])] = 0;
        if (p_.interfaces)
            for (const std::uint64_t k : *p_.interfaces) {
                interior_[static_cast<std::size_t>(k >> 32)] = 0;
                interior_[static_cast<std::size_t>(k & 0xffffffffu)] = 0;
            }
        slot_.assign(m_.vertices.size(), -1);
        std::int32_t slots = 0;
        const auto give = [&](std::int32_t v) {
            if (slot_[static_cast<std::size_t>(v)] < 0) slot_[static_cast<std::size_t>(v)] = slots++;
        };
        for (const auto& [mn, t] : bad)
            for (const std::int32_t v : m_.triangles[t]) give(v);
        candidate_.assign(m_.vertices.size(), 0);
        for (std::size_t v = 0; v < slot_.size(); ++v) candidate_[v] = slot_[v] >= 0;
        for (const Tri& T : m_.triangles)
            if (candidate_[static_cast<std::size_t>(T[0])] || candidate_[static_cast<std::size_t>(T[1])] ||
                candidate_[static_cast<std::size_t>(T[2])])
                for (const std::int32_t v : T) give(v);
        stars_.assign(static_cast<std::size_t>(slots), {});
        for (std::size_t t = 0; t < m_.triangles.size(); ++t)
            for (const std::int32_t v : m_.triangles[t])
                if (slot_[static_cast<std::size_t>(v)] >= 0) star(v).push_back(t);
    }

    // v's link as a counter-clockwise cycle, or empty if its star is not a
    // closed disc of one region.
    std::vector<std::int32_t> link(std::int32_t v) const {
        const auto& star = this->star(v);
        if (star.size() < 3 || star.size() > max_link) return {};
        std::vector<std::pair<std::int32_t, std::int32_t>> next;  // (a, b): triangle v, a, b
        for (const std::size_t t : star) {
            if (m_.region[t] != m_.region[star[0]]) return {};
            const Tri& T = m_.triangles[t];
            int k = 0;
            while (T[static_cast<std::size_t>(k)] != v) ++k;
            next.emplace_back(T[static_cast<std::size_t>((k + 1) % 3)], T[static_cast<std::size_t>((k + 2) % 3)]);
        }
        std::vector<std::int32_t> cycle{next[0].first};
        while (cycle.size() <= star.size()) {
            const auto it = std::find_if(next.begin(), next.end(), [&](const auto& ab) { return ab.first == cycle.back(); });
            if (it == next.end()) return {};
            if (it->second == cycle.front()) return cycle.size() == star.size() ? cycle : std::vector<std::int32_t>{};
            cycle.push_back(it->second);
        }
        return {};
    }

    // Is the chord L[i]-L[j] of the simple counter-clockwise polygon L inside
    // it (a diagonal)?  Polygon edges are.
    static bool diagonal(const std::vector<Vec2>& L, std::size_t i, std::size_t j) {
        const std::size_t n = L.size();
        if ((i + 1) % n == j || (j + 1) % n == i) return true;
        for (std::size_t e = 0; e < n; ++e) {
            const std::size_t f = (e + 1) % n;
            if (e == i || e == j || f == i || f == j) continue;
            if (segments_meet(L[i], L[j], L[e], L[f])) return false;
        }
        // In the cone of L's interior angle at L[i] (between the directions to
        // its successor and its predecessor, counter-clockwise).
        const Vec2 a = L[(i + n - 1) % n], b = L[i], c = L[(i + 1) % n], d = L[j];
        if (cross(b - a, c - b) >= 0) return cross(c - b, d - b) > 0 && cross(d - b, a - b) > 0;  // convex corner
        return !(cross(d - b, c - b) >= 0 && cross(a - b, d - b) >= 0);                         // reflex corner
    }

    // The max-min triangulation of polygon L under the caps: the least of
    // its smallest angles (-inf if none) and its triangles (indices into L).
    double best_triangulation(const std::vector<Vec2>& L, double max_deg, std::vector<std::array<std::size_t, 3>>& out) const;
    void try_remove(std::int32_t v);
    void compact();

    Mesh& m_;
    const RemoveParams& p_;
    std::vector<std::int32_t> slot_;                // per vertex: its index in stars_, or -1
    std::vector<std::vector<std::size_t>> stars_;  // the indexed vertices' triangles
    std::vector<char> interior_, candidate_;
    std::vector<char> dead_tri_, removed_;  // emptied triangle slots, removed vertices
    RemoveResult r_;
};

double Remover::best_triangulation(const std::vector<Vec2>& L, double max_deg, std::vector<std::array<std::size_t, 3>>& out) const {
    const std::size_t n = L.size();
    std::vector<char> ok(n * n, 0);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            const bool inside = diagonal(L, i, j);
            const bool short_enough = !(p_.max_edge > 0) || norm2(L[j] - L[i]) <= p_.max_edge * p_.max_edge;
            ok[i * n + j] = inside && short_enough;
        }
    // best[i][j]: the max-min triangulation of the sub-polygon L[i..j]
    // (closed by the chord i-j), split[i][j] its apex.
    std::vector<double> best(n * n, -inf);
    std::vector<std::size_t> split(n * n, 0);
    for (std::size_t i = 0; i + 1 < n; ++i) best[i * n + i + 1] = inf;
    for (std::size_t len = 2; len < n; ++len)
        for (std::size_t i = 0; i + len < n; ++i) {
            const std::size_t j = i + len;
            if (!ok[i * n + j]) continue;
            for (std::size_t k = i + 1; k < j; ++k) {
                const double sub = std::min(best[i * n + k], best[k * n + j]);
                if (!(sub > best[i * n + j]) || !(cross(L[k] - L[i], L[j] - L[i]) > 0)) continue;
                const TriangleAngles a = triangle_angles(L[i], L[k], L[j]);
                if (a.max_deg > max_deg) continue;
                if (const double q = std::min(sub, a.min_deg); q > best[i * n + j]) best[i * n + j] = q, split[i * n + j] = k;
            }
        }
    const double result = best[n - 1];
    if (!(result > -inf)) return result;
    std::vector<std::pair<std::size_t, std::size_t>> todo{{0, n - 1}};
    while (!todo.empty()) {
        const auto [i, j] = todo.back();
        todo.pop_back();
        if (j - i < 2) continue;
        const std::size_t k = split[i * n + j];
        out.push_back({i, k, j});
        todo.emplace_back(i, k), todo.emplace_back(k, j);
    }
    return result;
}

void Remover::try_remove(std::int32_t v) {
    const std::vector<std::int32_t> cycle = link(v);
    if (cycle.empty()) return;
    auto star = this->star(v);
    std::sort(star.begin(), star.end());
    double old_min = inf, old_max = 0;
    for (const std::size_t t : star) {
        const Tri& T = m_.triangles[t];
        const TriangleAngles a = triangle_angles(P(T[0]), P(T[1]), P(T[2]));
        old_min = std::min(old_min, a.min_deg), old_max = std::max(old_max, a.max_deg);
    }
    std::vector<Vec2> L;
    for (const std::int32_t w : cycle) L.push_back(P(w));
    std::vector<std::array<std::size_t, 3>> tris;
    const double max_deg = std::min(p_.max_angle_cap, std::max(old_max, max_angle_target));
    const double new_min = best_triangulation(L, max_deg, tris);
    if (!(new_min > old_min + min_gain_deg) || tris.size() + 2 != star.size()) return;

    // Accept: the new triangles take the first k - 2 slots of the star, the
    // last two are emptied; every cell data array gets the star's least value.
    for (const std::size_t t : star)
        for (const std::int32_t w : m_.triangles[t]) {  // all indexed: v and its neighbours
            auto& s = this->star(w);
            s.erase(std::remove(s.begin(), s.end(), t), s.end());
        }
    for (auto& [name, data] : m_.cell_data) {
        if (data.size() != m_.triangles.size()) continue;
        double least = inf;
        for (const std::size_t t : star) least = std::min(least, data[t]);
        for (const std::size_t t : star) data[t] = least;
    }
    dead_tri_.resize(m_.triangles.size(), 0);
    for (std::size_t i = 0; i < star.size(); ++i) {
        const std::size_t t = star[i];
        if (i >= tris.size()) {
            m_.triangles[t] = {-1, -1, -1};
            dead_tri_[t] = 1;
            continue;
        }
        m_.triangles[t] = {cycle[tris[i][0]], cycle[tris[i][1]], cycle[tris[i][2]]};
        for (const std::int32_t w : m_.triangles[t]) this->star(w).push_back(t);
        r_.touched.push_back(t);
    }
    interior_[static_cast<std::size_t>(v)] = 0;
    removed_.resize(m_.vertices.size(), 0);
    removed_[static_cast<std::size_t>(v)] = 1;
    ++r_.removed_vertices;
}

// Drop the removed vertices and the emptied triangle slots, keeping order.
void Remover::compact() {
    const std::size_t nv = m_.vertices.size(), nt = m_.triangles.size();
    r_.vertex_map.assign(nv, -1);
    std::size_t w = 0;
    for (std::size_t v = 0; v < nv; ++v)
        if (!removed_[v]) m_.vertices[w] = m_.vertices[v], r_.vertex_map[v] = static_cast<std::int32_t>(w++);
    m_.vertices.resize(w);
    const auto map = [&](std::int32_t v) { return r_.vertex_map[static_cast<std::size_t>(v)]; };
    r_.triangle_map.assign(nt, -1);
    w = 0;
    for (std::size_t t = 0; t < nt; ++t) {
        if (dead_tri_[t]) continue;
        const Tri& T = m_.triangles[t];
        m_.triangles[w] = {map(T[0]), map(T[1]), map(T[2])};
        m_.region[w] = m_.region[t];
        for (auto& [name, data] : m_.cell_data)
            if (data.size() == nt) data[w] = data[t];
        r_.triangle_map[t] = static_cast<std::int64_t>(w++);
    }
    m_.triangles.resize(w), m_.region.resize(w);
    for (auto& [name, data] : m_.cell_data)
        if (data.size() == nt) data.resize(w);
    for (auto& e : m_.boundary) e = {map(e[0]), map(e[1])};
    for (auto& e : m_.interfaces) e = {map(e[0]), map(e[1])};
    std::erase_if(r_.touched, [&](std::size_t t) { return dead_tri_[t] != 0; });
    for (std::size_t& t : r_.touched) t = static_cast<std::size_t>(r_.triangle_map[t]);
    std::sort(r_.touched.begin(), r_.touched.end());
    r_.touched.erase(std::unique(r_.touched.begin(), r_.touched.end()), r_.touched.end());
}

}  // namespace

RemoveResult remove_interior_vertices(Mesh& mesh, std::span<const std::size_t> eligible, const RemoveParams& params) {
    if (!(params.below_deg > 0)) return {};
    return Remover(mesh, params).run(eligible);
}

}  // namespace warpmesh
