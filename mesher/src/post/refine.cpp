// refine.cpp — local refinement of the worst triangles after the optimisation
// sweeps (refine.hpp: the candidates and the acceptance rule).
#include "refine.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <tuple>
#include <unordered_map>
#include <utility>

#include "plane.hpp"
#include "warpmesh/certify/certified.hpp"
#include "warpmesh/post/quality.hpp"

namespace warpmesh {

namespace {

using namespace plane;
using Tri = std::array<std::int32_t, 3>;

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double max_angle_target = 110;  // rule (3): a larger maximum only if the mesh or patch had one
constexpr std::size_t max_candidates = 8;
constexpr int max_insertions = 6;        // Steiner points per patch
constexpr int max_lawson_passes = 64;
constexpr double min_gain_deg = 1e-9;    // "strictly increases", above rounding
// Local smoothing of a trial: sweeps, step halvings, least gain per move.
constexpr int smooth_sweeps = 3;
constexpr int smooth_halvings = 3;
constexpr double smooth_min_gain_deg = 1e-3;

Vec2 circumcentre(Vec2 a, Vec2 b, Vec2 c) {
    const Vec2 u = b - a, v = c - a;
    const double d = 2 * cross(u, v);
    return a + (1 / d) * Vec2{v.y * norm2(u) - u.y * norm2(v), u.x * norm2(v) - v.x * norm2(u)};
}

// A boundary edge of a trial, oriented as in its triangle.
struct BEdge {
    std::int32_t a, b, tag;
};
// A split boundary edge: a-b became a-m, m-b.
struct Split {
    std::int32_t a, b, m;
};

// A patch being re-triangulated: its triangles and their regions, the mesh
// triangles it replaces (the patch, then the other sides of split
// interfaces), the positions of its new and moved vertices, its boundary
// edges, the boundary and interface splits made, and its extreme angles.
struct Trial {
    std::vector<Tri> tris;
    std::vector<std::int32_t> reg;
    std::vector<std::size_t> slots;
    std::vector<Split> isplits;
    std::vector<std::pair<std::int32_t, Vec2>> at;
    std::vector<BEdge> bedges;
    std::vector<Split> splits;
    std::int32_t next_vertex = 0;
    double min_deg = inf, max_deg = 0;
};

// A Steiner point: free (a < 0: inside a trial triangle) or on the edge a-b,
// a boundary edge when tag != 0, an interface when iface.
struct Candidate {
    Vec2 p;
    std::int32_t a = -1, b = -1;
    std::int32_t tag = 0;
    bool iface = false;
    std::int32_t curve = -1;  // an interface's curve (curves.hpp)
};

class Refiner {
public:
    Refiner(Mesh& mesh, const SlideCurves& curves, std::span<const std::size_t> eligible, const RefineParams& p)
        : m_(mesh), curves_(curves), p_(p), order_(eligible.begin(), eligible.end()) {}

    RefineResult run() {
        std::vector<std::pair<double, std::size_t>> bad;
        for (const std::size_t t : order_)
            if (const double mn = min_angle(m_.triangles[t]); mn < p_.below_deg) bad.emplace_back(mn, t);
        if (bad.empty()) return {};
        std::sort(bad.begin(), bad.end());
        for (const std::size_t t : order_) add_edges(t);
        for (std::size_t k = 0; k < m_.interfaces.size() && k < m_.interface_regions.size(); ++k)
            iface_at_[edge_key(m_.interfaces[k][0], m_.interfaces[k][1])] = k;
        bdeg_.assign(m_.vertices.size(), 0);
        for (std::size_t e = 0; e < m_.boundary.size(); ++e) {
            boundary_[edge_key(m_.boundary[e][0], m_.boundary[e][1])] = e;
            for (const std::int32_t v : m_.boundary[e]) ++bdeg_[static_cast<std::size_t>(v)];
        }
        for (const auto& [mn, t] : bad)
            if (min_angle(m_.triangles[t]) < p_.below_deg) refine(t);  // its slot may have been rewritten
        std::sort(r_.touched.begin(), r_.touched.end());
        r_.touched.erase(std::unique(r_.touched.begin(), r_.touched.end()), r_.touched.end());
        return std::move(r_);
    }

private:
    Vec2 P(std::int32_t v) const { return m_.vertices[static_cast<std::size_t>(v)]; }
    Vec2 pos(const Trial& t, std::int32_t v) const {
        for (const auto& [w, p] : t.at)
            if (w == v) return p;
        return P(v);
    }
    double min_angle(const Tri& t) const { return triangle_min_angle(P(t[0]), P(t[1]), P(t[2])); }
    bool interface(std::int32_t a, std::int32_t b) const { return p_.interfaces && p_.interfaces->count(edge_key(a, b)); }
    std::int32_t tag_of(std::size_t e) const { return e < m_.boundary_tag.size() ? m_.boundary_tag[e] : 0; }

    void add_edges(std::size_t t) {
        const Tri& T = m_.triangles[t];
        for (int k = 0; k < 3; ++k) {
            auto& slot = edges_.try_emplace(edge_key(T[k], T[(k + 1) % 3]), std::array<std::int64_t, 2>{-1, -1}).first->second;
            (slot[0] < 0 ? slot[0] : slot[1]) = static_cast<std::int64_t>(t);
        }
    }
    void remove_edges(std::size_t t) {
        const Tri& T = m_.triangles[t];
        for (int k = 0; k < 3; ++k) {
            auto it = edges_.find(edge_key(T[k], T[(k + 1) % 3]));
            auto& slot = it->second;
            if (slot[0] == static_cast<std::int64_t>(t)) std::swap(slot[0], slot[1]);
            slot[1] = -1;
            if (slot[0] < 0) edges_.erase(it);
        }
    }
    // The eligible triangle across edge a-b from t, or -1.
    std::int64_t neighbour(std::size_t t, std::int32_t a, std::int32_t b) const {
        const auto it = edges_.find(edge_key(a, b));
        if (it == edges_.end()) return -1;
        return it->second[0] == static_cast<std::int64_t>(t) ? it->second[1] : it->second[0];
    }

    // t's patch (refine.hpp), increasing.
    std::vector<std::size_t> patch(std::size_t t) const {
        std::vector<std::size_t> out{t};
        std::size_t begin = 0;
        for (int ring = 0; ring < p_.patch_rings; ++ring) {
            const std::size_t end = out.size();
            for (std::size_t i = begin; i < end; ++i) {
                const Tri& T = m_.triangles[out[i]];
                for (int k = 0; k < 3; ++k) {
                    const std::int32_t a = T[k], b = T[(k + 1) % 3];
                    const std::int64_t n = neighbour(out[i], a, b);
                    if (n < 0 || interface(a, b) || m_.region[static_cast<std::size_t>(n)] != m_.region[t]) continue;
                    if (std::find(out.begin(), out.end(), static_cast<std::size_t>(n)) == out.end())
                        out.push_back(static_cast<std::size_t>(n));
                }
            }
            begin = end;
        }
        std::sort(out.begin(), out.end());
        return out;
    }

    // The trial's boundary edge {v, w}, if any.
    const BEdge* bedge(const Trial& t, std::int32_t v, std::int32_t w) const {
        for (const BEdge& e : t.bedges)
            if ((e.a == v && e.b == w) || (e.a == w && e.b == v)) return &e;
        return nullptr;
    }
    // v's neighbours across boundary edges of the trial.
    std::vector<std::int32_t> boundary_neighbours(const Trial& t, std::int32_t v) const {
        std::vector<std::int32_t> out;
        for (const BEdge& e : t.bedges)
            if (e.a == v || e.b == v) out.push_back(e.a == v ? e.b : e.a);
        return out;
    }

    // The split point of boundary edge e (the mesh to its left): on f = 0 for
    // a level-set edge, the midpoint for a border edge.
    std::optional<Vec2> boundary_point(const Trial& t, const BEdge& e) const {
        const Vec2 pa = pos(t, e.a), pb = pos(t, e.b), mid = 0.5 * (pa + pb);
        if (e.tag == boundary_domain) return mid;
        if (e.tag != boundary_level_set || !f_) return std::nullopt;
        if (f_->value(mid.x, mid.y) == 0) return mid;
        const Vec2 inward = perp(pb - pa);  // |inward| = |ab|: f < 0 on this side
        for (const double r : {0.05, 0.15, 0.5}) {
            const Vec2 in = mid + r * inward, out = mid - r * inward;
            const double fi = f_->value(in.x, in.y), fo = f_->value(out.x, out.y);
            if (!(fi < 0 && fo > 0)) continue;
            const Vec2 q = in + f_->cut_parameter(in, out, fi, fo) * (out - in);
            if (std::abs(f_->value(q.x, q.y)) <= 1e-10 * p_.spacing) return q;
            return std::nullopt;
        }
        return std::nullopt;
    }

    // The region on the other side of the trial's edge a -> b (a triangle of
    // the trial with b -> a, else the eligible mesh triangle), or -1.
    std::int32_t other_region(const Trial& t, std::int32_t a, std::int32_t b, std::int64_t* slot = nullptr) const {
        for (std::size_t i = 0; i < t.tris.size(); ++i)
            for (int k = 0; k < 3; ++k)
                if (t.tris[i][k] == b && t.tris[i][(k + 1) % 3] == a) return t.reg[i];
        const auto it = edges_.find(edge_key(a, b));
        if (it == edges_.end()) return -1;
        for (const std::int64_t u : it->second)
            if (u >= 0 && std::find(t.slots.begin(), t.slots.end(), static_cast<std::size_t>(u)) == t.slots.end()) {
                if (slot) *slot = u;
                return m_.region[static_cast<std::size_t>(u)];
            }
        return -1;
    }
    // Is a - b an edge between two trial triangles of different regions?
    bool split_interface(const Trial& t, std::int32_t a, std::int32_t b) const {
        const std::int32_t r = own_region(t, b, a);
        return r >= 0 && r != own_region(t, a, b);
    }
    // The region of the trial triangle with the edge a -> b, or -1.
    std::int32_t own_region(const Trial& t, std::int32_t a, std::int32_t b) const {
        for (std::size_t i = 0; i < t.tris.size(); ++i)
            for (int k = 0; k < 3; ++k)
                if (t.tris[i][k] == a && t.tris[i][(k + 1) % 3] == b) return t.reg[i];
        return -1;
    }
    // Adds the mesh triangle across the interface a -> b to the trial (if it
    // is not in it already); false if there is none.
    bool add_other_side(Trial& t, std::int32_t a, std::int32_t b) const {
        std::int64_t slot = -1;
        if (own_region(t, b, a) >= 0) return true;
        if (other_region(t, a, b, &slot) < 0 || slot < 0) return false;
        t.tris.push_back(m_.triangles[static_cast<std::size_t>(slot)]);
        t.reg.push_back(m_.region[static_cast<std::size_t>(slot)]);
        t.slots.push_back(static_cast<std::size_t>(slot));
        return true;
    }
    // A Steiner point on the interface a -> b of the trial (materials): on
    // the curve of its two regions, found by its cut_parameter on a segment
    // across the edge's midpoint.
    std::optional<Candidate> interface_point(const Trial& t, std::int32_t a, std::int32_t b) const {
        const std::int32_t left = own_region(t, a, b), right = other_region(t, a, b);
        if (left < 0 || right < 0 || left == right) return std::nullopt;
        const std::int32_t curve = curves_.interface_curve(left, right);
        if (curve == SlideCurves::none) return std::nullopt;
        const LevelSet& g = curves_.curve(curve);
        const Vec2 pa = pos(t, a), pb = pos(t, b), mid = 0.5 * (pa + pb), across = perp(pb - pa);
        Candidate c{mid, a, b, 0, true, curve};
        if (g.value(mid.x, mid.y) == 0) return c;
        for (const double r : {0.05, 0.15, 0.5}) {
            const Vec2 lo = mid + r * across, hi = mid - r * across;
            const double glo = g.value(lo.x, lo.y), ghi = g.value(hi.x, hi.y);
            if (!((glo < 0 && ghi > 0) || (glo > 0 && ghi < 0))) continue;
            c.p = zero_on_segment(g, lo, hi, glo, ghi);
            if (std::abs(g.value(c.p.x, c.p.y)) <= 1e-10 * p_.spacing) return c;
            return std::nullopt;
        }
        return std::nullopt;
    }

    // Lawson flips of the edges inside the trial (both triangles in it, not a
    // boundary or an interface edge) while a pair's minimum rises.
    void lawson(Trial& t) const {
        std::vector<Tri>& tris = t.tris;
        for (int pass = 0; pass < max_lawson_passes; ++pass) {
            bool flipped = false;
            for (std::size_t i = 0; i < tris.size(); ++i)
                for (int k = 0; k < 3; ++k) {
                    const std::int32_t a = tris[i][k], b = tris[i][(k + 1) % 3], c = tris[i][(k + 2) % 3];
                    if (bedge(t, a, b) || interface(a, b)) continue;
                    std::size_t j = tris.size();
                    int k2 = -1;
                    for (std::size_t u = 0; u < tris.size() && k2 < 0; ++u)
                        for (int q = 0; q < 3; ++q)
                            if (tris[u][q] == b && tris[u][(q + 1) % 3] == a) j = u, k2 = q;
                    if (k2 < 0 || t.reg[i] != t.reg[j]) continue;  // the patch border, a split interface
                    const std::int32_t d = tris[j][(k2 + 2) % 3];
                    const Vec2 A = pos(t, a), B = pos(t, b), C = pos(t, c), D = pos(t, d);
                    if (!(cross(A - C, D - C) > 0) || !(cross(B - D, C - D) > 0)) continue;  // not convex
                    if (p_.max_edge > 0 && norm2(D - C) > p_.max_edge * p_.max_edge) continue;
                    const double before = std::min(triangle_min_angle(A, B, C), triangle_min_angle(B, A, D));
                    const double after = std::min(triangle_min_angle(C, A, D), triangle_min_angle(D, B, C));
                    if (!(after > before + min_gain_deg)) continue;
                    tris[i] = {c, a, d};
                    tris[j] = {d, b, c};
                    flipped = true;
                }
            if (!flipped) return;
        }
    }

    // Local smoothing of the trial (refine.hpp): each vertex whose every
    // triangle is in the trial moves to raise the least quality of its star —
    // interior vertices in eight directions, level-set vertices with two
    // boundary edges along f = 0 (a tangent step, then back onto f = 0 by
    // cut_parameter along the normal), border vertices along their line —
    // with step halving; a few Gauss-Seidel sweeps in increasing vertex order.
    // (interior_only: only vertices on no boundary edge move: the areas of
    // the trial's regions do not change.)
    void smooth(Trial& t, bool interior_only = false) const {
        // Edges of one trial triangle that are not boundary edges: the patch border.
        std::vector<std::uint64_t> all, border;
        for (const Tri& T : t.tris)
            for (int k = 0; k < 3; ++k) all.push_back(edge_key(T[k], T[(k + 1) % 3]));
        std::sort(all.begin(), all.end());
        for (std::size_t i = 0; i < all.size(); ++i)
            if ((i == 0 || all[i] != all[i - 1]) && (i + 1 == all.size() || all[i] != all[i + 1]))
                border.push_back(all[i]);
        std::vector<std::int32_t> verts;
        for (const Tri& T : t.tris) verts.insert(verts.end(), T.begin(), T.end());
        std::sort(verts.begin(), verts.end());
        verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
        // Vertices on an edge between two regions of the trial (a split
        // interface) stay put.
        std::vector<std::int32_t> pinned;
        for (std::size_t i = 0; i < t.tris.size(); ++i)
            for (std::size_t j = i + 1; j < t.tris.size(); ++j)
                if (t.reg[i] != t.reg[j])
                    for (int k = 0; k < 3; ++k)
                        for (int q = 0; q < 3; ++q)
                            if (t.tris[i][k] == t.tris[j][(q + 1) % 3] && t.tris[i][(k + 1) % 3] == t.tris[j][q])
                                pinned.push_back(t.tris[i][k]), pinned.push_back(t.tris[j][q]);
        enum class Move { free, levelset, along_x, along_y };
        std::vector<std::pair<std::int32_t, Move>> movers;
        for (const std::int32_t v : verts) {
            bool fixed = false;
            for (const std::uint64_t e : border) {
                const auto a = static_cast<std::int32_t>(e >> 32), b = static_cast<std::int32_t>(e & 0xffffffffu);
                fixed = fixed || ((a == v || b == v) && !bedge(t, a, b));
            }
            if (fixed || std::find(pinned.begin(), pinned.end(), v) != pinned.end()) continue;
            const std::vector<std::int32_t> nb = boundary_neighbours(t, v);
            // An old vertex's boundary edges in the whole mesh; a new one has only the trial's.
            const std::size_t deg = static_cast<std::size_t>(v) < bdeg_.size() ? static_cast<std::size_t>(bdeg_[static_cast<std::size_t>(v)]) : nb.size();
            if (nb.empty() && deg == 0) {
                movers.emplace_back(v, Move::free);
                continue;
            }
            if (nb.size() != 2 || deg != 2 || interior_only) continue;  // corners, pinches
            const std::int32_t tg0 = bedge(t, v, nb[0])->tag, tg1 = bedge(t, v, nb[1])->tag;
            const Vec2 p = pos(t, v), q0 = pos(t, nb[0]), q1 = pos(t, nb[1]);
            if (tg0 == boundary_level_set && tg1 == boundary_level_set && f_ && std::abs(f_->value(p.x, p.y)) <= 1e-9 * p_.spacing)
                movers.emplace_back(v, Move::levelset);
            else if (tg0 == boundary_domain && tg1 == boundary_domain && p.y == q0.y && p.y == q1.y)
                movers.emplace_back(v, Move::along_x);
            else if (tg0 == boundary_domain && tg1 == boundary_domain && p.x == q0.x && p.x == q1.x)
                movers.emplace_back(v, Move::along_y);
        }
        for (int sweep = 0; sweep < smooth_sweeps; ++sweep) {
            bool any = false;
            for (const auto& mover : movers) {
                const auto v = mover.first;  // captured by star_quality: not a structured binding (clang 14)
                const auto how = mover.second;
                std::vector<std::size_t> star;
                double shortest2 = inf;
                for (std::size_t i = 0; i < t.tris.size(); ++i)
                    for (int k = 0; k < 3; ++k)
                        if (t.tris[i][k] == v) {
                            star.push_back(i);
                            shortest2 = std::min({shortest2, norm2(pos(t, t.tris[i][(k + 1) % 3]) - pos(t, v)),
                                                  norm2(pos(t, t.tris[i][(k + 2) % 3]) - pos(t, v))});
                        }
                const Vec2 p = pos(t, v);
                const auto star_quality = [&](Vec2 q) {
                    double worst = inf;
                    for (const std::size_t i : star) {
                        Vec2 x[3];
                        for (int k = 0; k < 3; ++k) x[k] = t.tris[i][k] == v ? q : pos(t, t.tris[i][k]);
                        if (!(cross(x[1] - x[0], x[2] - x[0]) > 0)) return -inf;
                        worst = std::min(worst, tri_q_fast(x[0], x[1], x[2]));
                    }
                    return worst;
                };
                std::vector<Vec2> dirs;
                Vec2 normal{0, 0};
                if (how == Move::free) {
                    for (int d = 0; d < 8; ++d) dirs.push_back({std::cos(d * std::numbers::pi / 4), std::sin(d * std::numbers::pi / 4)});
                } else if (how == Move::along_x) {
                    dirs = {{1, 0}, {-1, 0}};
                } else if (how == Move::along_y) {
                    dirs = {{0, 1}, {0, -1}};
                } else {
                    const double h = 1e-6 * p_.spacing;
                    const Vec2 g{(f_->value(p.x + h, p.y) - f_->value(p.x - h, p.y)) / (2 * h),
                                 (f_->value(p.x, p.y + h) - f_->value(p.x, p.y - h)) / (2 * h)};
                    const double len = std::sqrt(norm2(g));
                    if (!(len > 0) || !std::isfinite(len)) continue;
                    normal = (1 / len) * g;
                    dirs = {perp(normal), -1.0 * perp(normal)};
                }
                const double now = star_quality(p);
                double step = 0.25 * std::sqrt(shortest2);
                for (int halving = 0; halving < smooth_halvings; ++halving, step *= 0.5) {
                    double best = now + smooth_min_gain_deg;
                    std::optional<Vec2> to;
                    for (const Vec2 d : dirs) {
                        Vec2 q = p + step * d;
                        if (how == Move::levelset) {
                            const double reach = step + 0.05 * p_.spacing;
                            const Vec2 a = q - reach * normal, b = q + reach * normal;
                            const double fa = f_->value(a.x, a.y), fb = f_->value(b.x, b.y);
                            if (!(fa < 0 && fb > 0)) continue;
                            q = a + f_->cut_parameter(a, b, fa, fb) * (b - a);
                            if (!(std::abs(f_->value(q.x, q.y)) <= 1e-10 * p_.spacing)) continue;
                        }
                        if (const double sq = star_quality(q); sq > best) best = sq, to = q;
                    }
                    if (!to) continue;
                    set_pos(t, v, *to);
                    any = true;
                    break;
                }
            }
            if (!any) break;
        }
    }

    static void set_pos(Trial& t, std::int32_t v, Vec2 p) {
        for (auto& [w, q] : t.at)
            if (w == v) {
                q = p;
                return;
            }
        t.at.emplace_back(v, p);
    }

    // The trial with candidate c inserted, flipped and smoothed, if it is
    // valid (rule (1)) and keeps rules (4) and (5) (refine.hpp).
    // Smoothing: 2 as above; (materials, when the smoothed trial breaks the
    // area budget) 1 moves only interior vertices, 0 none.
    std::optional<Trial> insert(const Trial& base, const Candidate& c, std::span<const std::uint64_t> old_edges,
                                int smoothing = 2) const {
        Trial t = base;
        const std::int32_t nv = t.next_vertex++;
        t.at.emplace_back(nv, c.p);
        if (c.a < 0) {
            std::size_t hit = t.tris.size();
            for (std::size_t i = 0; i < t.tris.size() && hit == t.tris.size(); ++i) {
                const Vec2 a = pos(t, t.tris[i][0]), b = pos(t, t.tris[i][1]), d = pos(t, t.tris[i][2]);
                const double eps = 1e-9 * cross(b - a, d - a);
                if (cross(b - a, c.p - a) > eps && cross(d - b, c.p - b) > eps && cross(a - d, c.p - d) > eps) hit = i;
            }
            if (hit == t.tris.size()) return std::nullopt;  // outside the trial, or on an edge
            const Tri T = t.tris[hit];
            t.tris[hit] = {T[0], T[1], nv};
            t.tris.push_back({T[1], T[2], nv});
            t.tris.push_back({T[2], T[0], nv});
            t.reg.push_back(t.reg[hit]), t.reg.push_back(t.reg[hit]);
        } else {
            if (c.iface && !add_other_side(t, c.a, c.b)) return std::nullopt;
            int found = 0;
            const std::size_t n = t.tris.size();
            for (std::size_t i = 0; i < n; ++i)
                for (int k = 0; k < 3; ++k) {
                    const std::int32_t u = t.tris[i][k], v = t.tris[i][(k + 1) % 3], w = t.tris[i][(k + 2) % 3];
                    if (!((u == c.a && v == c.b) || (u == c.b && v == c.a))) continue;
                    t.tris[i] = {u, nv, w};
                    t.tris.push_back({nv, v, w});
                    t.reg.push_back(t.reg[i]);
                    ++found;
                    break;
                }
            if (found != (c.tag ? 1 : 2)) return std::nullopt;  // an interior edge on the patch border
            if (c.tag) {
                const auto e = std::find_if(t.bedges.begin(), t.bedges.end(), [&](const BEdge& x) { return x.a == c.a && x.b == c.b; });
                if (e == t.bedges.end()) return std::nullopt;
                const BEdge old = *e;
                *e = {old.a, nv, old.tag};
                t.bedges.push_back({nv, old.b, old.tag});
                t.splits.push_back({old.a, old.b, nv});
            }
            if (c.iface) {  // rule (4) for the two halves, on the interface's curve
                const LevelSet& g = curves_.curve(c.curve);
                for (const std::int32_t end : {c.a, c.b})
                    if (!(edge_distance_to_levelset(g, pos(t, end), c.p, p_.spacing) <= p_.boundary_distance)) return std::nullopt;
                t.isplits.push_back({c.a, c.b, nv});
            }
        }
        lawson(t);
        if (smoothing) smooth(t, smoothing == 1), lawson(t);
        t.min_deg = inf, t.max_deg = 0;
        for (const Tri& T : t.tris) {
            const Vec2 a = pos(t, T[0]), b = pos(t, T[1]), d = pos(t, T[2]);
            if (!(cross(b - a, d - a) > 0)) return std::nullopt;  // (1)
            const TriangleAngles ang = triangle_angles(a, b, d);
            t.min_deg = std::min(t.min_deg, ang.min_deg), t.max_deg = std::max(t.max_deg, ang.max_deg);
            if (p_.max_edge > 0)  // (5), on the new edges and those at new or moved vertices
                for (int k = 0; k < 3; ++k) {
                    const std::int32_t u = T[k], v = T[(k + 1) % 3];
                    const bool changed = !std::binary_search(old_edges.begin(), old_edges.end(), edge_key(u, v)) ||
                                         std::any_of(t.at.begin(), t.at.end(), [&](const auto& w) { return w.first == u || w.first == v; });
                    if (changed && norm2(pos(t, v) - pos(t, u)) > p_.max_edge * p_.max_edge) return std::nullopt;
                }
        }
        for (const auto& [v, q] : t.at)  // (4), the level-set edges at every new or moved vertex
            for (const BEdge& e : t.bedges)
                if ((e.a == v || e.b == v) && e.tag == boundary_level_set &&
                    !(f_ && edge_distance_to_levelset(*f_, pos(t, e.a), pos(t, e.b), p_.spacing) <= p_.boundary_distance))
                    return std::nullopt;
        return t;
    }

    // Candidates for the trial's worst triangle (refine.hpp).
    std::vector<Candidate> candidates(const Trial& t) const {
        std::size_t w = 0;
        double worst = inf;
        for (std::size_t i = 0; i < t.tris.size(); ++i) {
            const Tri& T = t.tris[i];
            if (const double mn = triangle_min_angle(pos(t, T[0]), pos(t, T[1]), pos(t, T[2])); mn < worst) worst = mn, w = i;
        }
        const Tri T = t.tris[w];
        std::vector<Candidate> out;
        const auto add = [&](const Candidate& c) {
            for (const Candidate& o : out)
                if (c.a >= 0 ? o.a >= 0 && edge_key(o.a, o.b) == edge_key(c.a, c.b) : o.a < 0 && o.p.x == c.p.x && o.p.y == c.p.y) return;
            if (out.size() < max_candidates) out.push_back(c);
        };
        const auto split_boundary = [&](const BEdge& e) {
            if (const auto q = boundary_point(t, e)) add({*q, e.a, e.b, e.tag});
        };
        // The circumcentre, or the boundary edges it encroaches on.
        const Vec2 cc = circumcentre(pos(t, T[0]), pos(t, T[1]), pos(t, T[2]));
        bool encroaches = false;
        for (const BEdge& e : t.bedges) {
            const Vec2 a = pos(t, e.a), b = pos(t, e.b);
            if (norm2(cc - 0.5 * (a + b)) < 0.25 * norm2(b - a)) encroaches = true, split_boundary(e);
        }
        if (!encroaches && std::isfinite(cc.x) && std::isfinite(cc.y)) add({cc});
        const auto at_T = [&](std::int32_t v) { return std::find(T.begin(), T.end(), v) != T.end(); };
        for (const BEdge& e : t.bedges)
            if (at_T(e.a) && at_T(e.b)) split_boundary(e);
        for (const BEdge& e : t.bedges)
            if (at_T(e.a) || at_T(e.b)) split_boundary(e);
        if (curves_.materials())  // W's interfaces (materials): a point on their curve
            for (int k = 0; k < 3; ++k)
                if (const auto q = interface_point(t, T[k], T[(k + 1) % 3]); q && out.size() + 2 < max_candidates) add(*q);
        // W's interior edges' midpoints, longest first (ties: edge order).
        std::array<int, 3> by_length{0, 1, 2};
        const auto length2 = [&](int k) { return norm2(pos(t, T[(k + 1) % 3]) - pos(t, T[k])); };
        std::stable_sort(by_length.begin(), by_length.end(), [&](int i, int j) { return length2(i) > length2(j); });
        const Candidate centroid{(1.0 / 3) * (pos(t, T[0]) + pos(t, T[1]) + pos(t, T[2]))};
        for (const int k : by_length)
            if (const std::int32_t a = T[k], b = T[(k + 1) % 3]; !bedge(t, a, b) && !interface(a, b) && !split_interface(t, a, b)) {
                if (out.size() + 1 == max_candidates) break;  // room for the centroid
                add({0.5 * (pos(t, a) + pos(t, b)), a, b, 0});
            }
        add(centroid);
        return out;
    }

    void refine(std::size_t t) {
        // A kept background has no level-set edges (its edges to the materials
        // are interfaces): no curve.
        const std::int32_t curve = curves_.boundary_curve(m_.region[t]);
        f_ = curve == SlideCurves::none ? nullptr : &curves_.curve(curve);
        const std::vector<std::size_t> pt = patch(t);
        Trial base;
        base.next_vertex = static_cast<std::int32_t>(m_.vertices.size());
        double old_min = inf, old_max = 0;
        std::vector<std::uint64_t> old_edges;
        base.slots = pt;
        for (const std::size_t i : pt) {
            const Tri& U = m_.triangles[i];
            base.tris.push_back(U);
            base.reg.push_back(m_.region[i]);
            const TriangleAngles a = triangle_angles(P(U[0]), P(U[1]), P(U[2]));
            old_min = std::min(old_min, a.min_deg), old_max = std::max(old_max, a.max_deg);
            for (int k = 0; k < 3; ++k) {
                old_edges.push_back(edge_key(U[k], U[(k + 1) % 3]));
                if (const auto e = boundary_.find(old_edges.back()); e != boundary_.end()) {
                    const auto [a, b] = m_.boundary[e->second];
                    base.bedges.push_back({a, b, tag_of(e->second)});
                }
            }
        }
        std::sort(old_edges.begin(), old_edges.end());
        const double max_allowed = std::min(std::max({old_max, p_.max_angle, max_angle_target}), p_.max_angle_cap);
        // Greedy: insert the best candidate (within the angle cap first, then
        // the largest minimum) until the patch's minimum has risen.  With
        // materials, a trial the acceptance rule takes whole (embedding and
        // area budget included) ranks above every other: a candidate refused
        // only by rule (6) or (7) does not hide one that passes.
        const bool whole = curves_.materials();
        for (int step = 0; step < max_insertions; ++step) {
            std::optional<Trial> best;
            bool best_ok = false;
            for (const Candidate& c : candidates(base)) {
                std::optional<Trial> trial = insert(base, c, old_edges);
                for (int level = 1; level >= 0 && trial && whole && !budget_allows(*trial); --level)  // the smoothing moved area
                    if (std::optional<Trial> less = insert(base, c, old_edges, level)) trial = std::move(less);
                if (!trial) continue;
                const bool ok = whole && acceptable(*trial, old_min, old_max, pt.size());
                const auto key = [&](const Trial& x, bool x_ok) { return std::tuple{x_ok, x.max_deg <= max_allowed, x.min_deg}; };
                if (!best || key(*trial, ok) > key(*best, best_ok)) best = std::move(trial), best_ok = ok;
                if (best->min_deg >= p_.below_deg && best->max_deg <= max_allowed && (!whole || best_ok)) break;  // good enough: stop looking
            }
            if (!best) return;
            if (whole ? best_ok : acceptable_angles(*best, old_min, old_max, pt.size())) {  // (2), (3)
                if (whole || (embeds(*best) && budget_allows(*best))) apply_budget(*best), apply(*best);  // (6), (7)
                return;
            }
            base = std::move(*best);
        }
    }

    // Rules (2) and (3) for a trial replacing the patch (old_min, old_max:
    // its extreme angles; the other sides of split interfaces, the slots
    // after the patch's `patch_size`, count in the old patch too).
    bool acceptable_angles(const Trial& trial, double old_min, double old_max, std::size_t patch_size) const {
        double omin = old_min, omax = old_max;
        for (std::size_t k = patch_size; k < trial.slots.size(); ++k) {
            const Tri& U = m_.triangles[trial.slots[k]];
            const TriangleAngles a = triangle_angles(P(U[0]), P(U[1]), P(U[2]));
            omin = std::min(omin, a.min_deg), omax = std::max(omax, a.max_deg);
        }
        const double allowed = std::min(std::max({omax, p_.max_angle, max_angle_target}), p_.max_angle_cap);
        return trial.min_deg > omin + min_gain_deg && trial.max_deg <= allowed;
    }

    // Rules (2), (3), (6) and (7).
    bool acceptable(const Trial& trial, double old_min, double old_max, std::size_t patch_size) const {
        return acceptable_angles(trial, old_min, old_max, patch_size) && budget_allows(trial) && embeds(trial);
    }

    // Rule (7): the regions' area change of a trial (curves.hpp).
    AreaChange budget_change(const Trial& trial) const {
        AreaChange c;
        for (std::size_t k = 0; k < trial.tris.size(); ++k) {
            const Tri& T = trial.tris[k];
            add_area(c, trial.reg[k], 0.5 * cross(pos(trial, T[1]) - pos(trial, T[0]), pos(trial, T[2]) - pos(trial, T[0])));
        }
        for (const std::size_t i : trial.slots)
            add_area(c, m_.region[i], -0.5 * cross(P(m_.triangles[i][1]) - P(m_.triangles[i][0]), P(m_.triangles[i][2]) - P(m_.triangles[i][0])));
        return c;
    }
    bool budget_allows(const Trial& trial) const { return !p_.areas || p_.areas->allows(budget_change(trial)); }
    void apply_budget(const Trial& trial) const {
        if (p_.areas) p_.areas->apply(budget_change(trial));
    }

    // Rule (6) for the trial replacing its slots (embedding.hpp).
    bool embeds(const Trial& trial) const {
        const std::vector<std::size_t>& pt = trial.slots;
        if (!p_.index) return true;
        std::vector<std::uint64_t> replaced;  // the patch's boundary edges in the mesh
        for (const std::size_t i : pt)
            for (int k = 0; k < 3; ++k)
                if (const std::uint64_t key = edge_key(m_.triangles[i][k], m_.triangles[i][(k + 1) % 3]); boundary_.count(key))
                    replaced.push_back(key);
        std::sort(replaced.begin(), replaced.end());
        const auto moved = [&](std::int32_t v) {
            return std::any_of(trial.at.begin(), trial.at.end(), [&](const auto& w) { return w.first == v; });
        };
        std::vector<EdgeIds> changed, local;
        for (const BEdge& e : trial.bedges) (moved(e.a) || moved(e.b) ? changed : local).push_back({e.a, e.b});
        std::vector<std::uint64_t> all;  // the trial's border: edges of one trial triangle, not boundary edges
        for (const Tri& T : trial.tris)
            for (int k = 0; k < 3; ++k) all.push_back(edge_key(T[k], T[(k + 1) % 3]));
        std::sort(all.begin(), all.end());
        for (std::size_t i = 0; i < all.size(); ++i)
            if ((i == 0 || all[i] != all[i - 1]) && (i + 1 == all.size() || all[i] != all[i + 1])) {
                const auto a = static_cast<std::int32_t>(all[i] >> 32), b = static_cast<std::int32_t>(all[i] & 0xffffffffu);
                if (!bedge(trial, a, b)) local.push_back({a, b});
            }
        const auto pos_of = [&](std::int32_t v) { return pos(trial, v); };
        const auto is_replaced = [&](std::size_t e) {
            return std::binary_search(replaced.begin(), replaced.end(), edge_key(m_.boundary[e][0], m_.boundary[e][1]));
        };
        return change_embeds(m_, *p_.index, changed, local, trial.tris, pos_of, is_replaced);
    }

    // A split interface a-b (its entry a'-b' in Mesh::interfaces, either
    // way round) becomes a'-m in place plus m-b' appended, same regions.
    void split_interface_entry(const Split& s) {
        const auto it = iface_at_.find(edge_key(s.a, s.b));
        if (it == iface_at_.end()) return;
        const std::size_t k = it->second;
        const auto [x, y] = m_.interfaces[k];
        iface_at_.erase(it);
        m_.interfaces[k] = {x, s.m};
        m_.interfaces.push_back({s.m, y});
        m_.interface_regions.push_back(m_.interface_regions[k]);
        iface_at_[edge_key(x, s.m)] = k;
        iface_at_[edge_key(s.m, y)] = m_.interfaces.size() - 1;
        if (p_.interfaces) {
            p_.interfaces->erase(edge_key(s.a, s.b));
            p_.interfaces->insert(edge_key(x, s.m)), p_.interfaces->insert(edge_key(s.m, y));
        }
    }

    void apply(const Trial& trial) {
        const std::vector<std::size_t>& pt = trial.slots;
        const std::size_t nv0 = m_.vertices.size();
        m_.vertices.resize(static_cast<std::size_t>(trial.next_vertex));
        for (const auto& [v, q] : trial.at) m_.vertices[static_cast<std::size_t>(v)] = q;
        bdeg_.resize(m_.vertices.size(), 0);
        const bool tagged = m_.boundary_tag.size() == m_.boundary.size();
        for (const Split& s : trial.splits) {  // a-b becomes a-m in place, m-b is appended
            const std::size_t e = boundary_.at(edge_key(s.a, s.b));
            const std::int32_t tag = tag_of(e);
            boundary_.erase(edge_key(s.a, s.b));
            m_.boundary[e] = {s.a, s.m};
            m_.boundary.push_back({s.m, s.b});
            if (tagged) m_.boundary_tag.push_back(tag);
            boundary_[edge_key(s.a, s.m)] = e;
            boundary_[edge_key(s.m, s.b)] = m_.boundary.size() - 1;
            bdeg_[static_cast<std::size_t>(s.m)] = 2;
        }
        const std::size_t nt = m_.triangles.size();
        std::vector<double> low;  // per cell data array: the least value over the old patch
        for (const auto& [name, data] : m_.cell_data) {
            double v = inf;
            if (data.size() == nt)
                for (const std::size_t i : pt) v = std::min(v, data[i]);
            low.push_back(v);
        }
        for (const std::size_t i : pt) remove_edges(i);
        for (std::size_t k = 0; k < trial.tris.size(); ++k) {
            std::size_t slot = 0;
            if (k < pt.size()) {
                slot = pt[k];
                m_.triangles[slot] = trial.tris[k];
                m_.region[slot] = trial.reg[k];
            } else {
                slot = m_.triangles.size();
                m_.triangles.push_back(trial.tris[k]);
                m_.region.push_back(trial.reg[k]);
            }
            r_.touched.push_back(slot);
            add_edges(slot);
        }
        for (std::size_t d = 0; d < m_.cell_data.size(); ++d) {
            auto& data = m_.cell_data[d].second;
            if (data.size() != nt) continue;
            for (const std::size_t i : pt) data[i] = low[d];
            data.resize(m_.triangles.size(), low[d]);
        }
        if (p_.index)
            for (const BEdge& e : trial.bedges) p_.index->add(m_, boundary_.at(edge_key(e.a, e.b)));
        for (const Split& s : trial.isplits) split_interface_entry(s);
        ++r_.refined_triangles;
        r_.inserted_vertices += static_cast<std::int64_t>(m_.vertices.size() - nv0);
        r_.boundary_splits += static_cast<std::int64_t>(trial.splits.size());
        r_.interface_splits += static_cast<std::int64_t>(trial.isplits.size());
    }

    Mesh& m_;
    const SlideCurves& curves_;
    const LevelSet* f_ = nullptr;  // the current patch's boundary curve
    const RefineParams& p_;
    std::vector<std::size_t> order_;                                       // the eligible triangles, increasing
    std::unordered_map<std::uint64_t, std::array<std::int64_t, 2>> edges_;  // eligible triangles by edge
    std::unordered_map<std::uint64_t, std::size_t> boundary_;              // boundary edge -> index in Mesh::boundary
    std::vector<std::int32_t> bdeg_;                                       // per vertex: its number of boundary edges
    std::unordered_map<std::uint64_t, std::size_t> iface_at_;              // interface edge -> index in Mesh::interfaces
    RefineResult r_;
};

}  // namespace

RefineResult refine_bad_triangles(Mesh& mesh, const SlideCurves& curves, std::span<const std::size_t> eligible,
                                  const RefineParams& params) {
    if (!(params.below_deg > 0) || mesh.triangles.empty()) return {};
    return Refiner(mesh, curves, eligible, params).run();
}

}  // namespace warpmesh
