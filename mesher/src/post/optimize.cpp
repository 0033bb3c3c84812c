// optimize.cpp — the monotone quality pass (optimize.hpp: the rule, the
// vertex kinds, the report).
#include "warpmesh/post/optimize.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <iterator>
#include <unordered_set>

#include "warpmesh/certify/certified.hpp"
#include "warpmesh/post/mesh_checks.hpp"
#include "warpmesh/post/quality.hpp"
#include "curves.hpp"
#include "embedding.hpp"
#include "plane.hpp"
#include "refine.hpp"
#include "remove.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace warpmesh {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
// Angles whose quality lies within this many degrees of the star's worst
// steer the ascent direction together (an ε-subgradient).
constexpr double active_band_deg = 0.5;
constexpr int line_search_halvings = 8;
// A star whose quality is at least this is left alone, and a move must gain
// at least min_gain_deg.  (The lattice's right isosceles triangles score 45;
// polishing stars between 42 and 45 as well costs 2-3 times the moves for
// +0.5 deg of minimum angle.)
constexpr double good_star_deg = 42;
constexpr double min_gain_deg = 1e-3;
// Refinement (OptimizeOptions::refine_below_deg): rounds of refine-then-sweep.
constexpr int refine_rounds = 3;
// Materials: rounds of vertex removal (remove.hpp) then sweeps, for the
// triangles still below this many degrees after refinement.
constexpr int remove_rounds = 3;
// Materials: moves of stars of at least this quality do not spend area budget.
constexpr double reserve_deg = 35;
constexpr double remove_below_deg = 35;

using namespace plane;

// A triangle's smallest angle and quality, as reported (triangle_angles).
struct TriQ {
    double min_deg, max_deg, q;
};
TriQ tri_q(Vec2 a, Vec2 b, Vec2 c) {
    const TriangleAngles t = triangle_angles(a, b, c);
    return {t.min_deg, t.max_deg, std::min(t.min_deg, big_angle_pivot - t.max_deg)};
}

// The lattice's and the graded templates' triangles (45°, 45°, 90°), to a
// relative tolerance: the squared sides are l, l, 2l.
bool right_isosceles(Vec2 a, Vec2 b, Vec2 c) {
    double l[3] = {norm2(b - c), norm2(c - a), norm2(a - b)};
    std::sort(l, l + 3);
    const double tol = 1e-9 * l[2];
    return std::abs(l[0] - l[1]) <= tol && std::abs(l[2] - 2 * l[0]) <= tol && l[0] > 0;
}

// The minimum-norm point of the convex hull of a few 2D vectors (exact for
// the hull's vertices and edges; zero when the origin lies inside a triangle
// of them).
Vec2 min_norm_point(const std::vector<Vec2>& g) {
    Vec2 best = g[0];
    for (const Vec2& v : g)
        if (norm2(v) < norm2(best)) best = v;
    const std::size_t n = g.size();
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            const Vec2 e = g[j] - g[i];
            const double ee = norm2(e);
            if (!(ee > 0)) continue;
            const double t = std::clamp(-dot(g[i], e) / ee, 0.0, 1.0);
            const Vec2 p = g[i] + t * e;
            if (norm2(p) < norm2(best)) best = p;
            for (std::size_t k = j + 1; k < n; ++k) {
                const double c1 = cross(g[j] - g[i], Vec2{0, 0} - g[i]), c2 = cross(g[k] - g[j], Vec2{0, 0} - g[j]),
                             c3 = cross(g[i] - g[k], Vec2{0, 0} - g[k]);
                if ((c1 > 0 && c2 > 0 && c3 > 0) || (c1 < 0 && c2 < 0 && c3 < 0)) return {0, 0};
            }
        }
    return best;
}

// levelset: on a boundary curve (curves.hpp) with its two boundary edges;
// interface: on an interface curve with its two interface edges and a closed
// star (both sides are output triangles); junction (materials only): a vertex
// of several curves (three or more materials, or an interface meeting the
// dropped background, or an interface vertex off its curve) with a closed
// star or exactly two level-set boundary edges, which moves in the plane
// under the area budget with each of its curved edges within rule (4)'s
// distance of its curve.
enum class Kind : std::uint8_t { interior, levelset, interface, line_x, line_y, junction, fixed };

// The edges at one vertex, by kind (Optimizer::classify).
struct EdgeCount {
    int n1 = 0, n2 = 0, ni = 0, other = 0;
    bool horizontal = true, vertical = true, one_curve = true, uncurved = false;
    std::int32_t curve = SlideCurves::none;
    std::array<std::int32_t, 2> nb{-1, -1}, edges{-1, -1}, inb{-1, -1};
    // Level-set and interface edges: the other end and the edge's curve.
    std::vector<std::array<std::int32_t, 2>> curved;
    void on_curve(std::int32_t c, std::int32_t other_end) {
        if (n1 + ni == 0) curve = c;
        else one_curve = one_curve && curve == c;
        uncurved = uncurved || c == SlideCurves::none;
        curved.push_back({other_end, c});
    }
};

class Optimizer {
public:
    Optimizer(Mesh& mesh, const SlideCurves& curves, const OptimizeOptions& o)
        : m_(mesh), curves_(curves), o_(o), s_(o.spacing), areas_(mesh, curves) {
        for (auto& [name, data] : m_.cell_data)
            if (name == "certified_min_angle" && data.size() == m_.triangles.size()) cert_ = &data;
        if (std::isfinite(o.certified_max)) cap_ = o.certified_max;
    }

    OptimizeReport run();

private:
    std::int32_t local(std::int32_t v) const { return local1_[static_cast<std::size_t>(v)] - 1; }
    // A moved vertex's star and a flipped pair need their edges re-examined.
    void touch(std::size_t t) { tdirty_[t] = 1; }
    // The band (optimize.hpp) from the vertices of the triangles that are not
    // right isosceles, or of `seeds`; resets the per-vertex state.
    void find_band(const std::vector<std::size_t>* seeds);
    void classify();
    void classify_one(std::size_t l, const EdgeCount& k);
    int sweeps();  // Gauss-Seidel sweeps and flips until nothing changes; how many
    void refine(OptimizeReport& r);
    void remove_vertices(OptimizeReport& r);
    // The last sweeps, over the stars of the triangles still below
    // remove_below_deg, with spent_is_zero_ set (area_neutral).
    void retry_junctions(OptimizeReport& r);
    // Renumber the per-vertex and per-triangle state after a removal's compaction.
    void renumber(const RemoveResult& rr);
    bool try_move(std::int32_t lv);
    int flip_pass();
    bool try_flip(std::size_t t1, int k);
    double angle_models(std::int32_t lv, double& shortest);
    Vec2 ascent_direction(double q, Vec2 axis, bool one_dimensional);
    // Quality (fast atan2) and validity of v's star with v at p; the fast
    // smallest angle of each of its triangles goes to fast_min.
    struct StarQ {
        double q = inf, longest2 = 0;  // longest2: the longest edge, squared
        bool valid = true;
    };
    StarQ star_q(std::int32_t lv, Vec2 p, std::vector<double>& fast_min) const;
    // The smallest reported angle (triangle_min_angle) of v's star with v at
    // p, given the fast smallest angle of each of its triangles there.
    double exact_min(std::int32_t lv, Vec2 p, std::span<const double> fast_min) const;
    bool project_to_levelset(const LevelSet& f, Vec2 p, Vec2 normal, double reach, Vec2& out) const;
    // The curves of the boundary edges of `tris` (materials: by the region
    // on their left) into bcurve_.
    void assign_boundary_curves(std::span<const std::size_t> tris);
    // The largest distance of a boundary or interface edge to its curve
    // (only_moved: measure again only the edges with a moved end).
    double boundary_distance(bool only_moved);
    // The regions' area change if v moves to q (empty without reference areas).
    AreaChange area_change(std::int32_t lv, Vec2 q) const;
    void lower_certified(std::span<const std::size_t> tris, double floor_before);
    // Would moving boundary vertex lv to q keep the mesh an embedding
    // (embedding.hpp: its two boundary edges against the other boundary
    // edges and its link, no boundary vertex inside its new star)?
    bool embeds(std::int32_t lv, Vec2 q) const;
    // Would junction lv at q keep each of its level-set and interface edges
    // within rule (4)'s distance dmax_ of its curve (or of its distance now)?
    bool junction_close(std::int32_t lv, Vec2 q) const;
    // The junction's ascent direction d, made area-neutral for the one region
    // (if one) whose budget cannot take a step of `step` along it.
    // spent_is_zero: a room within rounding of zero (AreaBudget::spent)
    // counts as none.
    Vec2 area_neutral(std::int32_t lv, Vec2 d, double step, bool spent_is_zero) const;
    // Would a triangle of v's star with v at q have a largest angle > cap_?
    bool exceeds_cap(std::int32_t lv, Vec2 q) const;

    Mesh& m_;
    const SlideCurves& curves_;
    const OptimizeOptions& o_;
    double s_;
    AreaBudget areas_;
    std::vector<std::int32_t> curve_;   // per active vertex: its curve (levelset, interface), else none
    std::vector<std::int32_t> bcurve_;  // per boundary edge: its curve, none if not known (materials: outside the band)
    std::vector<double> edge_distance_, iface_distance_;  // per boundary / interface edge: distance to its curve, -1: not measured
    Buffer<double>* cert_ = nullptr;
    bool spent_is_zero_ = false;  // area_neutral's flag (retry_junctions)

    std::vector<std::size_t> band_;               // triangles with an active vertex, increasing
    std::vector<std::size_t> changed_;            // every triangle the pass may have changed, increasing
    std::vector<std::int32_t> act_;               // active vertices, increasing
    ZeroBuffer<std::int32_t> local1_;             // per mesh vertex: 1 + index in act_, or 0
    ZeroBuffer<std::uint8_t> tdirty_;             // per mesh triangle: edges to examine for flips
    ZeroBuffer<std::uint8_t> moved_;              // per mesh vertex: 1 once moved
    std::vector<Kind> kind_;                      // per active vertex
    std::vector<std::vector<std::size_t>> star_;  // per active vertex: its triangles
    std::vector<std::array<std::int32_t, 2>> bnb_;  // level-set vertices: the two boundary neighbours
    std::vector<std::array<std::int32_t, 2>> bedge_;  // boundary vertices that move: their two edges in Mesh::boundary
    std::vector<std::vector<std::array<std::int32_t, 2>>> jedges_;  // junctions: their curved edges' other ends and curves
    BoundaryIndex index_;                             // the boundary edges, for embeds()
    std::vector<char> dirty_;
    std::unordered_set<std::uint64_t> interfaces_;
    double dmax_ = 0;  // largest boundary distance before the pass
    double cap_ = std::numeric_limits<double>::infinity();  // rule (6): certified_max, or none
    std::vector<Vec2> active_, grads_;  // scratch of angle_models, ascent_direction, try_move
    std::vector<double> values_, slope_;
    std::vector<double> model_min_, trial_min_;  // per star triangle: fast smallest angle (angle_models; a trial position)
    std::int64_t moves_ = 0, flips_ = 0;
};

// Triangles (in increasing order) for which `pick` holds: a parallel scan in
// contiguous chunks, concatenated in chunk order.
template <class Pick>
std::vector<std::size_t> scan_triangles(const Mesh& m, Pick&& pick) {
    const std::int64_t nt = static_cast<std::int64_t>(m.triangles.size());
    int threads = 1;
#ifdef _OPENMP
    threads = omp_get_max_threads();
#endif
    std::vector<std::vector<std::size_t>> part(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
    {
        int me = 0;
#ifdef _OPENMP
        me = omp_get_thread_num();
        const int nth = omp_get_num_threads();
#else
        const int nth = 1;
#endif
        const std::int64_t lo = nt * me / nth, hi = nt * (me + 1) / nth;
        auto& out = part[static_cast<std::size_t>(me)];
        for (std::int64_t t = lo; t < hi; ++t)
            if (pick(m.triangles[static_cast<std::size_t>(t)], static_cast<std::size_t>(t))) out.push_back(static_cast<std::size_t>(t));
    }
    std::vector<std::size_t> all;
    for (const auto& p : part) all.insert(all.end(), p.begin(), p.end());
    return all;
}

void Optimizer::find_band(const std::vector<std::size_t>* seeds) {
    const auto& V = m_.vertices;
    // Seeds: the vertices of triangles that are not right isosceles.
    const auto odd = seeds ? std::vector<std::size_t>{} : scan_triangles(m_, [&](const std::array<std::int32_t, 3>& t, std::size_t) {
        return !right_isosceles(V[static_cast<std::size_t>(t[0])], V[static_cast<std::size_t>(t[1])],
                                V[static_cast<std::size_t>(t[2])]);
    });
    act_.clear();
    ZeroBuffer<std::uint8_t> mark(V.size());
    for (const std::size_t t : seeds ? *seeds : odd)
        for (const std::int32_t v : m_.triangles[t]) mark[static_cast<std::size_t>(v)] = 1;
    // Active: the seeds and their neighbours.
    const auto ring = scan_triangles(m_, [&](const std::array<std::int32_t, 3>& t, std::size_t) {
        return (mark[static_cast<std::size_t>(t[0])] | mark[static_cast<std::size_t>(t[1])] |
                mark[static_cast<std::size_t>(t[2])]) & 1;
    });
    for (const std::size_t t : ring)
        for (const std::int32_t v : m_.triangles[t]) {
            auto& mv = mark[static_cast<std::size_t>(v)];
            if (!(mv & 2)) act_.push_back(v);
            mv |= 2;
        }
    std::sort(act_.begin(), act_.end());
    local1_ = ZeroBuffer<std::int32_t>(V.size());
    for (std::size_t l = 0; l < act_.size(); ++l) local1_[static_cast<std::size_t>(act_[l])] = static_cast<std::int32_t>(l + 1);
    band_ = scan_triangles(m_, [&](const std::array<std::int32_t, 3>& t, std::size_t) {
        return (mark[static_cast<std::size_t>(t[0])] | mark[static_cast<std::size_t>(t[1])] |
                mark[static_cast<std::size_t>(t[2])]) & 2;
    });
    star_.assign(act_.size(), {});
    tdirty_ = ZeroBuffer<std::uint8_t>(m_.triangles.size());
    for (const std::size_t t : band_) touch(t);
    for (const std::size_t t : band_)
        for (const std::int32_t v : m_.triangles[t]) {
            const std::int32_t l = local(v);
            if (l >= 0) star_[static_cast<std::size_t>(l)].push_back(t);
        }
}

// Which vertices move and how (optimize.hpp): a vertex with exactly two
// boundary or interface edges on one curve (curves.hpp) and on it slides along
// it, one with two lattice-border edges on one line along that line; one with
// no such edge is interior; every other vertex (junctions of three or more
// materials, where two kinds of edge meet, pinches, interface ends of one
// region's tagged label mode) is fixed.
void Optimizer::classify() {
    std::vector<EdgeCount> c(act_.size());
    for (std::size_t e = 0; e < m_.boundary.size(); ++e) {
        const auto [a, b] = m_.boundary[e];
        const std::int32_t tag = e < m_.boundary_tag.size() ? m_.boundary_tag[e] : 0;
        const Vec2 pa = m_.vertices[static_cast<std::size_t>(a)], pb = m_.vertices[static_cast<std::size_t>(b)];
        for (int end = 0; end < 2; ++end) {
            const std::int32_t l = local(end ? b : a);
            if (l < 0) continue;
            EdgeCount& k = c[static_cast<std::size_t>(l)];
            k.edges[static_cast<std::size_t>(end)] = static_cast<std::int32_t>(e);
            if (tag == boundary_level_set) {
                k.on_curve(bcurve_[e], end ? a : b);
                k.nb[static_cast<std::size_t>(end)] = end ? a : b;  // end 0: a's successor b; end 1: b's predecessor a
                ++k.n1;
            } else if (tag == boundary_domain) {
                ++k.n2;
                k.horizontal = k.horizontal && pa.y == pb.y;
                k.vertical = k.vertical && pa.x == pb.x;
            } else {
                ++k.other;
            }
        }
    }
    for (std::size_t i = 0; i < m_.interfaces.size(); ++i) {
        const auto& e = m_.interfaces[i];
        interfaces_.insert(edge_key(e[0], e[1]));
        const std::int32_t curve = i < m_.interface_regions.size()
                                       ? curves_.interface_curve(m_.interface_regions[i][0], m_.interface_regions[i][1])
                                       : SlideCurves::none;
        for (int end = 0; end < 2; ++end)
            if (const std::int32_t l = local(e[static_cast<std::size_t>(end)]); l >= 0) {
                EdgeCount& k = c[static_cast<std::size_t>(l)];
                if (curve == SlideCurves::none) k.other = 1;  // one region's tagged label mode: fixed
                k.on_curve(curve, e[static_cast<std::size_t>(1 - end)]);
                if (k.ni < 2) k.inb[static_cast<std::size_t>(k.ni)] = e[static_cast<std::size_t>(1 - end)];
                ++k.ni;
            }
    }
    kind_.assign(act_.size(), Kind::interior);
    bnb_.assign(act_.size(), {-1, -1});
    bedge_.assign(act_.size(), {-1, -1});
    curve_.assign(act_.size(), SlideCurves::none);
    jedges_.assign(act_.size(), {});
    for (std::size_t l = 0; l < act_.size(); ++l) classify_one(l, c[l]);
}

void Optimizer::classify_one(std::size_t l, const EdgeCount& k) {
    Kind& kd = kind_[l];
    const Vec2 p = m_.vertices[static_cast<std::size_t>(act_[l])];
    const auto on = [&] { return k.curve != SlideCurves::none && std::abs(curves_.curve(k.curve).value(p.x, p.y)) <= 1e-9 * s_; };
    if (k.other || k.n1 + k.n2 > 2 || (k.n1 && k.n2) || (k.ni && k.n1 + k.n2) || k.ni > 2 || !k.one_curve) {
        kd = Kind::fixed;
    } else if (k.n1 == 2) {
        kd = on() ? Kind::levelset : Kind::fixed;
        bnb_[l] = k.nb;
    } else if (k.ni == 2) {
        kd = on() ? Kind::interface : Kind::fixed;
        bnb_[l] = k.inb;
    } else if (k.n2 == 2) {
        kd = k.horizontal ? Kind::line_x : k.vertical ? Kind::line_y : Kind::fixed;
    } else if (k.n1 + k.n2 + k.ni != 0) {
        kd = Kind::fixed;
    }
    // Materials: a fixed vertex of curves only (no lattice-border or other
    // edge, every edge's curve known) with a closed star or two level-set
    // boundary edges (one in, one out: the embedding test applies) moves
    // as a junction.
    if (kd == Kind::fixed && curves_.materials() && !k.other && !k.n2 && !k.uncurved && (k.n1 == 0 || k.n1 == 2) &&
        (k.edges[0] >= 0) == (k.n1 == 2) && (k.edges[1] >= 0) == (k.n1 == 2) && k.curved.size() >= 2) {
        kd = Kind::junction;
        jedges_[l] = k.curved;
    }
    if (kd == Kind::levelset || kd == Kind::interface) curve_[l] = k.curve;
    if (kd == Kind::levelset || kd == Kind::line_x || kd == Kind::line_y || (kd == Kind::junction && k.n1 == 2)) bedge_[l] = k.edges;
}

void Optimizer::assign_boundary_curves(std::span<const std::size_t> tris) {
    bcurve_.resize(m_.boundary.size(), SlideCurves::none);
    if (!curves_.materials()) {
        std::fill(bcurve_.begin(), bcurve_.end(), curves_.boundary_curve(0));
        return;
    }
    const auto directed = [](std::int32_t a, std::int32_t b) {
        return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
    };
    std::unordered_map<std::uint64_t, std::size_t> level;  // level-set edges without a curve yet
    for (std::size_t e = 0; e < m_.boundary.size(); ++e)
        if (e < m_.boundary_tag.size() && m_.boundary_tag[e] == boundary_level_set && bcurve_[e] == SlideCurves::none)
            level[directed(m_.boundary[e][0], m_.boundary[e][1])] = e;
    if (level.empty()) return;
    for (const std::size_t t : tris)
        for (int k = 0; k < 3; ++k) {
            const auto& T = m_.triangles[t];
            if (const auto it = level.find(directed(T[static_cast<std::size_t>(k)], T[static_cast<std::size_t>((k + 1) % 3)])); it != level.end())
                bcurve_[it->second] = curves_.boundary_curve(m_.region[t]);
        }
}

double Optimizer::boundary_distance(bool only_moved) {
    double worst = 0;
    const auto measure = [&](double& d, std::int32_t curve, std::int32_t a, std::int32_t b) {
        if (curve == SlideCurves::none) return;
        if (!only_moved || moved_[static_cast<std::size_t>(a)] || moved_[static_cast<std::size_t>(b)])
            d = edge_distance_to_levelset(curves_.curve(curve), m_.vertices[static_cast<std::size_t>(a)],
                                          m_.vertices[static_cast<std::size_t>(b)], s_);
        worst = std::max(worst, d);
    };
    edge_distance_.resize(m_.boundary.size(), -1);
    for (std::size_t e = 0; e < m_.boundary.size(); ++e)
        if (e < m_.boundary_tag.size() && m_.boundary_tag[e] == boundary_level_set)
            measure(edge_distance_[e], bcurve_[e], m_.boundary[e][0], m_.boundary[e][1]);
    if (!curves_.materials()) return worst;
    iface_distance_.resize(m_.interfaces.size(), -1);
    for (std::size_t i = 0; i < m_.interfaces.size() && i < m_.interface_regions.size(); ++i)
        measure(iface_distance_[i], curves_.interface_curve(m_.interface_regions[i][0], m_.interface_regions[i][1]),
                m_.interfaces[i][0], m_.interfaces[i][1]);
    return worst;
}

AreaChange Optimizer::area_change(std::int32_t lv, Vec2 q) const {
    AreaChange change;
    if (!areas_.active()) return change;
    const std::int32_t g = act_[static_cast<std::size_t>(lv)];
    for (const std::size_t t : star_[static_cast<std::size_t>(lv)]) {
        const auto& T = m_.triangles[t];
        Vec2 x[3], y[3];
        for (int k = 0; k < 3; ++k) {
            x[k] = m_.vertices[static_cast<std::size_t>(T[static_cast<std::size_t>(k)])];
            y[k] = T[static_cast<std::size_t>(k)] == g ? q : x[k];
        }
        add_area(change, m_.region[t], 0.5 * (cross(y[1] - y[0], y[2] - y[0]) - cross(x[1] - x[0], x[2] - x[0])));
    }
    return change;
}

Optimizer::StarQ Optimizer::star_q(std::int32_t lv, Vec2 p, std::vector<double>& fast_min) const {
    StarQ r;
    const std::int32_t g = act_[static_cast<std::size_t>(lv)];
    fast_min.clear();
    for (const std::size_t t : star_[static_cast<std::size_t>(lv)]) {
        Vec2 q[3];
        for (int k = 0; k < 3; ++k) {
            const std::int32_t v = m_.triangles[t][static_cast<std::size_t>(k)];
            q[k] = v == g ? p : m_.vertices[static_cast<std::size_t>(v)];
        }
        if (!(cross(q[1] - q[0], q[2] - q[0]) > 0)) {
            r.valid = false;
            return r;
        }
        const FastQ f = tri_fast(q[0], q[1], q[2]);
        r.q = std::min(r.q, f.q);
        fast_min.push_back(f.min_deg);
        r.longest2 = std::max({r.longest2, norm2(q[1] - q[0]), norm2(q[2] - q[1]), norm2(q[0] - q[2])});
    }
    return r;
}

// The reported smallest angle lies among the triangles whose fast one is
// within twice its error of the least fast one (each errs by at most
// 3·fast_atan2_error_deg); the others cannot hold it, and are not evaluated.
double Optimizer::exact_min(std::int32_t lv, Vec2 p, std::span<const double> fast_min) const {
    const std::int32_t g = act_[static_cast<std::size_t>(lv)];
    const auto& star = star_[static_cast<std::size_t>(lv)];
    const double bound = *std::min_element(fast_min.begin(), fast_min.end()) + 6 * fast_atan2_error_deg + 1e-9;
    double mn = inf;
    for (std::size_t i = 0; i < star.size(); ++i) {
        if (fast_min[i] > bound) continue;
        Vec2 q[3];
        for (int k = 0; k < 3; ++k) {
            const std::int32_t v = m_.triangles[star[i]][static_cast<std::size_t>(k)];
            q[k] = v == g ? p : m_.vertices[static_cast<std::size_t>(v)];
        }
        mn = std::min(mn, triangle_min_angle(q[0], q[1], q[2]));
    }
    return mn;
}

// The linear models of the qualities of the star's angles at the vertex's
// position: values_[i] = g(θi) and grads_[i] its gradient in the vertex
// (and model_min_: each triangle's fast smallest angle, for exact_min).
// Returns the star quality (the least value; NaN if a triangle is not
// counter-clockwise) and sets `shortest` to the star's shortest edge.
double Optimizer::angle_models(std::int32_t lv, double& shortest) {
    const std::int32_t g = act_[static_cast<std::size_t>(lv)];
    const Vec2 p = m_.vertices[static_cast<std::size_t>(g)];
    values_.clear();
    grads_.clear();
    model_min_.clear();
    double q = inf, shortest2 = inf;
    for (const std::size_t t : star_[static_cast<std::size_t>(lv)]) {
        const auto& tri = m_.triangles[t];
        int k = 0;
        while (tri[static_cast<std::size_t>(k)] != g) ++k;
        const Vec2 a = m_.vertices[static_cast<std::size_t>(tri[static_cast<std::size_t>((k + 1) % 3)])];
        const Vec2 b = m_.vertices[static_cast<std::size_t>(tri[static_cast<std::size_t>((k + 2) % 3)])];
        // Angles at a and b (ccw triangle p, a, b) and their gradients in p:
        // θa = arg(p − a) − arg(b − a), θb = arg(a − b) − arg(p − b), θp = π − θa − θb.
        const Vec2 pa = p - a, pb = p - b;
        const double area2 = cross(b - a, pa);
        if (!(area2 > 0)) return std::numeric_limits<double>::quiet_NaN();
        const double ta = fast_atan2_deg(area2, dot(b - a, pa));
        const double tb = fast_atan2_deg(area2, dot(a - b, pb));
        const double tp = 180 - ta - tb;
        model_min_.push_back(std::min({ta, tb, tp}));
        const Vec2 ga = (deg_per_rad / norm2(pa)) * perp(pa), gb = (-deg_per_rad / norm2(pb)) * perp(pb);
        const Vec2 gp = -1.0 * (ga + gb);
        for (const auto& [theta, grad] : {std::pair{ta, ga}, std::pair{tb, gb}, std::pair{tp, gp}}) {
            const bool rising = theta <= big_angle_pivot / 2;
            values_.push_back(rising ? theta : big_angle_pivot - theta);
            grads_.push_back(rising ? grad : -1.0 * grad);
            q = std::min(q, values_.back());
        }
        shortest2 = std::min({shortest2, norm2(pa), norm2(pb), norm2(b - a)});
    }
    shortest = std::sqrt(shortest2);
    return q;
}

// The ascent direction of the star quality q: the minimum-norm element of the
// convex hull of the gradients of the angles within active_band_deg of q,
// restricted to `axis` when one_dimensional.
Vec2 Optimizer::ascent_direction(double q, Vec2 axis, bool one_dimensional) {
    active_.clear();
    for (std::size_t i = 0; i < values_.size(); ++i)
        if (values_[i] <= q + active_band_deg) active_.push_back(one_dimensional ? dot(grads_[i], axis) * axis : grads_[i]);
    return active_.empty() ? Vec2{0, 0} : min_norm_point(active_);
}

bool Optimizer::project_to_levelset(const LevelSet& f, Vec2 p, Vec2 n, double reach, Vec2& out) const {
    const double f0 = f.value(p.x, p.y);
    if (f0 == 0) {
        out = p;
        return true;
    }
    const Vec2 a = p - reach * n, b = p + reach * n;
    const double fa = f.value(a.x, a.y), fb = f.value(b.x, b.y);
    if (!((fa < 0 && fb > 0) || (fa > 0 && fb < 0))) return false;
    out = zero_on_segment(f, a, b, fa, fb);
    return std::abs(f.value(out.x, out.y)) <= 1e-10 * s_;
}

void Optimizer::lower_certified(std::span<const std::size_t> tris, double floor_before) {
    if (!cert_) return;
    for (const std::size_t t : tris) {
        double& c = (*cert_)[t];
        if (c <= floor_before) continue;  // min(c, floor_before) = c: nothing to lower
        const auto& tri = m_.triangles[t];
        const double mn = triangle_min_angle(m_.vertices[static_cast<std::size_t>(tri[0])], m_.vertices[static_cast<std::size_t>(tri[1])],
                                             m_.vertices[static_cast<std::size_t>(tri[2])]);
        if (mn < c) c = floor_before;
    }
}

bool Optimizer::exceeds_cap(std::int32_t lv, Vec2 q) const {
    if (!std::isfinite(cap_)) return false;
    const std::int32_t g = act_[static_cast<std::size_t>(lv)];
    for (const std::size_t t : star_[static_cast<std::size_t>(lv)]) {
        Vec2 x[3];
        for (int k = 0; k < 3; ++k) {
            const std::int32_t v = m_.triangles[t][static_cast<std::size_t>(k)];
            x[k] = v == g ? q : m_.vertices[static_cast<std::size_t>(v)];
        }
        // The fast largest angle errs by at most 3·fast_atan2_error_deg.
        if (tri_fast(x[0], x[1], x[2]).max_deg < cap_ - 6 * fast_atan2_error_deg) continue;
        if (triangle_angles(x[0], x[1], x[2]).max_deg > cap_) return true;
    }
    return false;
}

bool Optimizer::embeds(std::int32_t lv, Vec2 q) const {
    const std::int32_t g = act_[static_cast<std::size_t>(lv)];
    // Not a structured binding: clang 14 cannot capture one in a lambda.
    const auto e0 = bedge_[static_cast<std::size_t>(lv)][0], e1 = bedge_[static_cast<std::size_t>(lv)][1];
    if (e0 < 0 || e1 < 0) return false;
    const EdgeIds changed[2] = {m_.boundary[static_cast<std::size_t>(e0)], m_.boundary[static_cast<std::size_t>(e1)]};
    std::vector<EdgeIds> link;
    std::vector<std::array<std::int32_t, 3>> tris;
    for (const std::size_t t : star_[static_cast<std::size_t>(lv)]) {
        const auto& T = m_.triangles[t];
        tris.push_back(T);
        for (int k = 0; k < 3; ++k)
            if (T[static_cast<std::size_t>(k)] == g) link.push_back({T[static_cast<std::size_t>((k + 1) % 3)], T[static_cast<std::size_t>((k + 2) % 3)]});
    }
    const auto pos = [&](std::int32_t v) { return v == g ? q : m_.vertices[static_cast<std::size_t>(v)]; };
    const auto replaced = [&](std::size_t e) { return e == static_cast<std::size_t>(e0) || e == static_cast<std::size_t>(e1); };
    return change_embeds(m_, index_, changed, link, tris, pos, replaced);
}

// A junction's star changes the areas of several regions, each linearly in
// its position (a triangle's area is affine in one vertex): region r's
// changes by g_r . (q - p) with g_r the sum over its triangles (v, b, c) of
// (b.y - c.y, c.x - b.x) / 2.  If one region lacks the room in its budget
// for a step of `step` along d, d is projected onto the direction along
// which that region's area does not change (a region of zero error keeps
// its area exactly, up to rounding); of several such regions, the one whose
// room allows the shortest step (the line search shortens the step for the
// others).  With spent_is_zero, a region whose room is zero up to rounding
// (the drift of earlier area-neutral moves: a label kept exactly may be left
// 1e-14 px² of "room") counts as having none, so d is projected for it even
// when a second region is short too (the last sweeps, retry_junctions).
Vec2 Optimizer::area_neutral(std::int32_t lv, Vec2 d, double step, bool spent_is_zero) const {
    if (!areas_.active()) return d;
    const std::int32_t g = act_[static_cast<std::size_t>(lv)];
    std::vector<std::pair<std::int32_t, Vec2>> grad;
    for (const std::size_t t : star_[static_cast<std::size_t>(lv)]) {
        const auto& T = m_.triangles[t];
        int k = 0;
        while (T[static_cast<std::size_t>(k)] != g) ++k;
        const Vec2 b = m_.vertices[static_cast<std::size_t>(T[static_cast<std::size_t>((k + 1) % 3)])];
        const Vec2 c = m_.vertices[static_cast<std::size_t>(T[static_cast<std::size_t>((k + 2) % 3)])];
        const Vec2 gt{0.5 * (b.y - c.y), 0.5 * (c.x - b.x)};
        auto it = std::find_if(grad.begin(), grad.end(), [&](const auto& e) { return e.first == m_.region[t]; });
        if (it == grad.end()) grad.emplace_back(m_.region[t], gt);
        else it->second = it->second + gt;
    }
    // The region whose room allows the shortest step along d.
    Vec2 tight{0, 0};
    double shortest = step;
    int n = 0;
    for (const auto& [r, gr] : grad) {
        const double rate = std::abs(dot(gr, d));
        const bool grow = dot(gr, d) > 0;
        const double room = spent_is_zero && areas_.spent(r, grow) ? 0.0 : std::max(0.0, areas_.room(r, grow));
        if (room < rate * step) ++n;
        if (room < rate * shortest) tight = gr, shortest = room / rate;
    }
    if (!(norm2(tight) > 0) || (n > 1 && shortest > 0)) return d;
    return d - (dot(d, tight) / norm2(tight)) * tight;
}

bool Optimizer::junction_close(std::int32_t lv, Vec2 q) const {
    const Vec2 p = m_.vertices[static_cast<std::size_t>(act_[static_cast<std::size_t>(lv)])];
    for (const auto& [w, curve] : jedges_[static_cast<std::size_t>(lv)]) {
        const LevelSet& f = curves_.curve(curve);
        const Vec2 pw = m_.vertices[static_cast<std::size_t>(w)];
        if (edge_distance_to_levelset(f, pw, q, s_) > std::max(dmax_, edge_distance_to_levelset(f, pw, p, s_))) return false;
    }
    return true;
}

bool Optimizer::try_move(std::int32_t lv) {
    const Kind kind = kind_[static_cast<std::size_t>(lv)];
    const std::int32_t g = act_[static_cast<std::size_t>(lv)];
    const Vec2 p = m_.vertices[static_cast<std::size_t>(g)];
    double shortest = 0;
    const double now_q = angle_models(lv, shortest);  // NaN: an inverted star, left alone
    if (!(now_q < good_star_deg)) return false;
    double now_min = inf;  // the star's smallest angle, computed once needed

    Vec2 axis{0, 0}, normal{0, 0};
    bool one_d = kind != Kind::interior && kind != Kind::junction;
    if (kind == Kind::line_x) axis = {1, 0};
    if (kind == Kind::line_y) axis = {0, 1};
    const bool on_curve = kind == Kind::levelset || kind == Kind::interface;
    const LevelSet* f = on_curve ? &curves_.curve(curve_[static_cast<std::size_t>(lv)]) : nullptr;
    if (on_curve) {
        const double h = 1e-6 * s_;
        const Vec2 grad{(f->value(p.x + h, p.y) - f->value(p.x - h, p.y)) / (2 * h),
                        (f->value(p.x, p.y + h) - f->value(p.x, p.y - h)) / (2 * h)};
        const double len = std::sqrt(norm2(grad));
        if (!(len > 0) || !std::isfinite(len)) return false;
        normal = (1 / len) * grad;
        axis = perp(normal);
    }
    const std::vector<double>& values = values_;
    const std::vector<Vec2>& grads = grads_;
    Vec2 d = ascent_direction(now_q, axis, one_d);
    if (kind == Kind::junction) d = area_neutral(lv, d, 0.5 * shortest, spent_is_zero_);
    const double dn = std::sqrt(norm2(d));
    // Stationary (degrees per star size: scale-free); no step can gain min_gain_deg.
    if (!(dn * shortest > 1e-9)) return false;
    const Vec2 dir = (1 / dn) * d;

    // Predicted best step: follow the lowest linear model min_i (c_i + α s_i)
    // from α = 0 until a line with slope <= 0 takes over.
    double alpha = 0.5 * shortest;
    {
        std::vector<double>& slope = slope_;
        slope.resize(values.size());
        for (std::size_t i = 0; i < values.size(); ++i) slope[i] = dot(grads[i], dir);
        std::size_t cur = 0;
        for (std::size_t i = 1; i < values.size(); ++i)
            if (values[i] < values[cur] || (values[i] == values[cur] && slope[i] < slope[cur])) cur = i;
        double at = 0;
        for (std::size_t guard = 0; guard < values.size() && slope[cur] > 0; ++guard) {
            double next = inf;
            std::size_t who = cur;
            for (std::size_t i = 0; i < values.size(); ++i) {
                if (!(slope[i] < slope[cur])) continue;
                const double x = (values[i] - values[cur]) / (slope[cur] - slope[i]);
                if (x > at && x < next) next = x, who = i;
            }
            if (who == cur) break;
            at = next, cur = who;
        }
        if (slope[cur] <= 0 && at > 0) alpha = std::min(alpha, at);
    }

    for (int halving = 0; halving <= line_search_halvings; ++halving, alpha *= 0.5) {
        Vec2 q = p + alpha * dir;
        if (kind == Kind::line_x) q.y = p.y;
        if (kind == Kind::line_y) q.x = p.x;
        if (on_curve && !project_to_levelset(*f, q, normal, alpha + 0.05 * s_, q)) continue;
        const StarQ next = star_q(lv, q, trial_min_);
        if (!next.valid || !(next.q > now_q + min_gain_deg)) continue;
        if (o_.max_edge > 0 && next.longest2 > o_.max_edge * o_.max_edge) continue;  // the size bound
        if (now_min == inf) now_min = exact_min(lv, p, model_min_);
        if (exact_min(lv, q, trial_min_) < now_min) continue;  // the monotone rule
        if (exceeds_cap(lv, q)) continue;                         // rule (6)
        if (on_curve) {
            const auto nb = bnb_[static_cast<std::size_t>(lv)];
            bool close = true;
            for (const std::int32_t w : nb)
                close = close && edge_distance_to_levelset(*f, m_.vertices[static_cast<std::size_t>(w)], q, s_) <= dmax_;
            if (!close) continue;
        }
        if (kind == Kind::junction && !junction_close(lv, q)) continue;  // rule (4) on each of its curves
        // A closed star (interior, interface and inner junction vertices) needs no embedding test.
        const bool closed = kind == Kind::interior || kind == Kind::interface ||
                            (kind == Kind::junction && bedge_[static_cast<std::size_t>(lv)][0] < 0);
        if (!closed && !embeds(lv, q)) continue;
        const AreaChange area = area_change(lv, q);  // the area budget (curves.hpp)
        // A star already of quality >= reserve_deg may not spend any label's
        // room (its error may only shrink): the room is kept for the worse stars.
        if (!areas_.allows(area, now_q >= reserve_deg)) continue;
        areas_.apply(area);
        // Accept: the least certified value of the star bounds every triangle
        // of it from now on (each was >= it before, so the star's old minimum
        // angle is >= it, and the new star's minimum is not smaller).
        double floor_before = inf;
        if (cert_)
            for (const std::size_t t : star_[static_cast<std::size_t>(lv)]) floor_before = std::min(floor_before, (*cert_)[t]);
        m_.vertices[static_cast<std::size_t>(g)] = q;
        moved_[static_cast<std::size_t>(g)] = 1;
        for (const std::int32_t e : bedge_[static_cast<std::size_t>(lv)])
            if (e >= 0) index_.add(m_, static_cast<std::size_t>(e));
        lower_certified(star_[static_cast<std::size_t>(lv)], floor_before);
        for (const std::size_t t : star_[static_cast<std::size_t>(lv)]) {
            touch(t);
            for (const std::int32_t v : m_.triangles[t])
                if (const std::int32_t l = local(v); l >= 0) dirty_[static_cast<std::size_t>(l)] = 1;
        }
        ++moves_;
        if (o_.observer) {
            OptimizeEvent ev;
            ev.vertex = g, ev.from = p, ev.to = q, ev.star = star_[static_cast<std::size_t>(lv)];
            o_.observer(m_, ev);
        }
        return true;
    }
    return false;
}

// Flip the edge k (tri[k] → tri[k+1]) of triangle t1 if the max-min rule
// gains and the edge is neither a boundary nor an interface edge.
bool Optimizer::try_flip(std::size_t t1, int k) {
    const auto T1 = m_.triangles[t1];
    const std::int32_t a = T1[static_cast<std::size_t>(k)], b = T1[static_cast<std::size_t>((k + 1) % 3)],
                       c = T1[static_cast<std::size_t>((k + 2) % 3)];
    const std::int32_t la = local(a), lb = local(b);
    if (la < 0 && lb < 0) return false;
    const auto& around = star_[static_cast<std::size_t>(la >= 0 ? la : lb)];
    std::size_t t2 = t1;
    int k2 = -1;
    for (const std::size_t t : around) {
        if (t == t1) continue;
        const auto& T = m_.triangles[t];
        for (int j = 0; j < 3; ++j)
            if (T[static_cast<std::size_t>(j)] == b && T[static_cast<std::size_t>((j + 1) % 3)] == a) t2 = t, k2 = j;
    }
    if (k2 < 0) return false;  // a boundary edge
    if (m_.region[t1] != m_.region[t2] || interfaces_.count(edge_key(a, b))) return false;
    const auto T2 = m_.triangles[t2];
    const std::int32_t d = T2[static_cast<std::size_t>((k2 + 2) % 3)];
    const auto P = [&](std::int32_t v) { return m_.vertices[static_cast<std::size_t>(v)]; };
    // New pair (c, a, d), (d, b, c): both counter-clockwise iff a-d-b-c is convex.
    if (!(cross(P(a) - P(c), P(d) - P(c)) > 0) || !(cross(P(b) - P(d), P(c) - P(d)) > 0)) return false;
    if (o_.max_edge > 0 && norm2(P(d) - P(c)) > o_.max_edge * o_.max_edge) return false;  // the size bound
    // Of the two triangulations of a convex quadrilateral the Delaunay one has
    // the larger smallest angle (Lawson), equal when the four points are
    // cocircular: the smallest angle can rise only if d lies strictly inside
    // the circumcircle of a, b, c.  (Rounding decides only near-cocircular
    // quadrilaterals, whose gain is far below the rule's 1e-9 degrees.)
    if (!(incircle(P(a), P(b), P(c), P(d)) > 0)) return false;
    // The fast quality first (most candidate flips gain nothing), then the rule
    // on the reported angles.
    if (std::min(tri_q_fast(P(c), P(a), P(d)), tri_q_fast(P(d), P(b), P(c))) <
        std::min(tri_q_fast(P(a), P(b), P(c)), tri_q_fast(P(b), P(a), P(d))))
        return false;
    const TriQ o1 = tri_q(P(a), P(b), P(c)), o2 = tri_q(P(b), P(a), P(d));
    const TriQ n1 = tri_q(P(c), P(a), P(d)), n2 = tri_q(P(d), P(b), P(c));
    const double old_min = std::min(o1.min_deg, o2.min_deg), new_min = std::min(n1.min_deg, n2.min_deg);
    if (!(new_min > old_min + 1e-9) || std::min(n1.q, n2.q) < std::min(o1.q, o2.q)) return false;
    if (std::max(n1.max_deg, n2.max_deg) > cap_) return false;  // rule (6)

    const std::array<std::array<std::int32_t, 3>, 2> before{T1, T2};
    m_.triangles[t1] = {c, a, d};
    m_.triangles[t2] = {d, b, c};
    for (auto& [name, data] : m_.cell_data)
        if (data.size() == m_.triangles.size()) data[t1] = data[t2] = std::min(data[t1], data[t2]);
    auto drop = [&](std::int32_t v, std::size_t t) {
        if (const std::int32_t l = local(v); l >= 0) {
            auto& s = star_[static_cast<std::size_t>(l)];
            s.erase(std::find(s.begin(), s.end(), t));
        }
    };
    auto add = [&](std::int32_t v, std::size_t t) {
        if (const std::int32_t l = local(v); l >= 0) star_[static_cast<std::size_t>(l)].push_back(t);
    };
    drop(a, t2), drop(b, t1), add(c, t2), add(d, t1);
    for (const std::int32_t v : {a, b, c, d})
        if (const std::int32_t l = local(v); l >= 0) dirty_[static_cast<std::size_t>(l)] = 1;
    touch(t1), touch(t2);
    ++flips_;
    if (o_.observer) {
        OptimizeEvent ev;
        ev.flip = true;
        ev.before = before;
        ev.after = {m_.triangles[t1], m_.triangles[t2]};
        o_.observer(m_, ev);
    }
    return true;
}

int Optimizer::flip_pass() {
    int n = 0;
    for (const std::size_t t : band_) {
        if (!tdirty_[t]) continue;
        tdirty_[t] = 0;
        for (int k = 0; k < 3; ++k) n += try_flip(t, k);
    }
    return n;
}

int Optimizer::sweeps() {
    dirty_.assign(act_.size(), 1);
    int sweep = 0;
    while (sweep < o_.max_sweeps) {
        bool changed = false;
        for (std::size_t l = 0; l < act_.size(); ++l) {
            if (!dirty_[l] || kind_[l] == Kind::fixed) continue;
            dirty_[l] = 0;
            changed = try_move(static_cast<std::int32_t>(l)) || changed;
        }
        if (o_.flips) changed = flip_pass() > 0 || changed;
        ++sweep;
        if (!changed) break;
    }
    return sweep;
}

std::vector<std::size_t> merged(const std::vector<std::size_t>& a, const std::vector<std::size_t>& b) {
    std::vector<std::size_t> out;
    std::set_union(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(out));
    return out;
}

// Rounds of local refinement (refine.hpp), each followed by sweeps over the
// band of the rewritten triangles.
// A later round looks only at the band the previous round's sweeps went over:
// elsewhere nothing changed, and a patch that could not be improved then
// cannot be now.
void Optimizer::refine(OptimizeReport& r) {
    std::vector<std::size_t> scope = changed_;
    for (int round = 0; round < refine_rounds; ++round) {
        RefineParams rp;
        rp.max_angle = 90;
        rp.below_deg = o_.refine_below_deg, rp.spacing = s_, rp.max_edge = o_.max_edge;
        rp.boundary_distance = dmax_, rp.interfaces = &interfaces_, rp.index = &index_;
        rp.max_angle_cap = cap_;
        rp.areas = areas_.active() ? &areas_ : nullptr;
        // The mesh's largest angle as reported, from 90° (the right isosceles
        // triangles outside changed_; the rule's cap is >= 110° anyway); a
        // triangle whose fast largest angle is below the running maximum by
        // more than twice its error cannot raise it and is not evaluated.
        for (const std::size_t t : changed_) {
            const auto& tri = m_.triangles[t];
            const Vec2 a = m_.vertices[static_cast<std::size_t>(tri[0])], b = m_.vertices[static_cast<std::size_t>(tri[1])],
                       c = m_.vertices[static_cast<std::size_t>(tri[2])];
            if (tri_fast(a, b, c).max_deg < rp.max_angle - 6 * fast_atan2_error_deg) continue;
            rp.max_angle = std::max(rp.max_angle, triangle_angles(a, b, c).max_deg);
        }
        const RefineResult rr = refine_bad_triangles(m_, curves_, scope, rp);
        if (rr.touched.empty()) return;
        r.refined_triangles += rr.refined_triangles, r.inserted_vertices += rr.inserted_vertices;
        r.boundary_splits += rr.boundary_splits, r.interface_splits += rr.interface_splits;
        // The rewritten triangles' vertices (new or moved) count as moved:
        // their boundary edges are measured again.
        moved_.resize(m_.vertices.size());
        for (const std::size_t t : rr.touched)
            for (const std::int32_t v : m_.triangles[t]) moved_[static_cast<std::size_t>(v)] = 1;
        find_band(&rr.touched);
        assign_boundary_curves(band_);
        classify();
        changed_ = merged(merged(changed_, rr.touched), band_);
        r.sweeps += sweeps();
        scope = merged(rr.touched, band_);
    }
}

// A junction next to a label whose area was exact before the pass (budget
// 0: its room is zero up to the rounding drift of earlier area-neutral
// moves, AreaBudget::spent) and a second label short of room: area_neutral
// counts two short regions with a positive least room and leaves d to the
// line search, which the exact label refuses at every step.  These last
// sweeps, over the stars of the triangles still below remove_below_deg (the
// 2 px target), project d for the exact label (pinned by
// test_optimize_materials' issue28_sagittal_2px_budget).  They come last so
// that everything the pass did before is unchanged: the same moves made
// earlier spend the area budget differently and may leave a worse minimum
// elsewhere (docs/optimisation.md has the measurements).
void Optimizer::retry_junctions(OptimizeReport& r) {
    if (!areas_.active()) return;
    std::vector<std::size_t> seeds;
    for (const std::size_t t : changed_) {
        const auto& tri = m_.triangles[t];
        if (triangle_angles(m_.vertices[static_cast<std::size_t>(tri[0])], m_.vertices[static_cast<std::size_t>(tri[1])],
                            m_.vertices[static_cast<std::size_t>(tri[2])])
                .min_deg < remove_below_deg)
            seeds.push_back(t);
    }
    if (seeds.empty()) return;
    find_band(&seeds);
    assign_boundary_curves(band_);
    classify();
    changed_ = merged(changed_, band_);
    spent_is_zero_ = true;
    r.sweeps += sweeps();
    spent_is_zero_ = false;
}

void Optimizer::renumber(const RemoveResult& rr) {
    std::vector<std::size_t> changed;
    for (const std::size_t t : changed_)
        if (const std::int64_t n = rr.triangle_map[t]; n >= 0) changed.push_back(static_cast<std::size_t>(n));
    changed_ = std::move(changed);  // the compaction keeps the order
    ZeroBuffer<std::uint8_t> moved(m_.vertices.size());
    for (std::size_t v = 0; v < rr.vertex_map.size() && v < moved_.size(); ++v)
        if (const std::int32_t n = rr.vertex_map[v]; n >= 0) moved[static_cast<std::size_t>(n)] = moved_[v];
    moved_ = std::move(moved);
    interfaces_.clear();  // classify() fills it again
}

// Rounds of removal of interior vertices (remove.hpp) among the triangles
// the pass changed, each followed by sweeps over the band of the rewritten
// triangles.
void Optimizer::remove_vertices(OptimizeReport& r) {
    for (int round = 0; round < remove_rounds; ++round) {
        RemoveParams rp;
        rp.below_deg = remove_below_deg, rp.max_edge = o_.max_edge, rp.max_angle_cap = cap_;
        rp.interfaces = &interfaces_;
        const RemoveResult rr = remove_interior_vertices(m_, changed_, rp);
        if (!rr.removed_vertices) return;
        r.removed_vertices += rr.removed_vertices;
        renumber(rr);
        if (o_.observer) {
            OptimizeEvent ev;
            ev.renumbered = rr.vertex_map;
            o_.observer(m_, ev);
        }
        find_band(&rr.touched);
        assign_boundary_curves(band_);
        classify();
        changed_ = merged(changed_, band_);
        r.sweeps += sweeps();
    }
}

OptimizeReport Optimizer::run() {
    const auto start = std::chrono::steady_clock::now();
    OptimizeReport r;
    find_band(nullptr);
    assign_boundary_curves(band_);
    classify();
    index_ = BoundaryIndex(m_, s_);
    r.band_triangles = static_cast<std::int64_t>(band_.size());
    for (const Kind k : kind_) r.active_vertices += k != Kind::fixed;
    changed_ = band_;

    // Statistics: the triangles outside changed_ are right isosceles.
    // (after the pass, check_certified: no triangle below its certified value)
    constexpr double slack = 1e-7;
    auto stats = [&](double& mn, double& mx, double& mean, bool check_certified) {
        const std::size_t outside = m_.triangles.size() - changed_.size();
        mn = outside ? 45 : inf, mx = outside ? 90 : -inf;
        double sum = 45.0 * static_cast<double>(outside);
        for (const std::size_t t : changed_) {
            const auto& tri = m_.triangles[t];
            const TriangleAngles a = triangle_angles(m_.vertices[static_cast<std::size_t>(tri[0])],
                                                     m_.vertices[static_cast<std::size_t>(tri[1])],
                                                     m_.vertices[static_cast<std::size_t>(tri[2])]);
            mn = std::min(mn, a.min_deg), mx = std::max(mx, a.max_deg), sum += a.min_deg;
            if (check_certified && cert_ && a.min_deg < (*cert_)[t] - slack)
                throw std::logic_error("optimize: triangle " + std::to_string(t) + " has minimum angle " +
                                       std::to_string(a.min_deg) + " below its certified value " + std::to_string((*cert_)[t]));
        }
        mean = m_.triangles.empty() ? std::numeric_limits<double>::quiet_NaN() : sum / static_cast<double>(m_.triangles.size());
    };
    stats(r.min_angle_before, r.max_angle_before, r.mean_min_angle_before, false);
    r.certified_floor = cert_ ? *std::min_element(cert_->begin(), cert_->end()) : o_.certified_floor;
    moved_.resize(m_.vertices.size());
    dmax_ = r.boundary_distance_before = boundary_distance(false);

    r.sweeps = sweeps();
    if (o_.refine_below_deg > 0) refine(r);
    if (o_.refine_below_deg > 0 && curves_.materials()) {
        remove_vertices(r);
        // Once more over everything the pass changed: a refinement patch
        // works on its worst triangle, and the moves after it may have
        // lifted that one and left another of the patch below the threshold.
        refine(r);
        retry_junctions(r);
    }

    // The rule's consequences, checked: no triangle below its (transferred)
    // certified value (in stats), none below the floor, the minimum not lower.
    r.triangles = static_cast<std::int64_t>(m_.triangles.size());
    stats(r.min_angle_after, r.max_angle_after, r.mean_min_angle_after, true);
    r.boundary_distance_after = boundary_distance(true);
    r.moves = moves_, r.flips = flips_;
    if (r.min_angle_after < r.min_angle_before || r.min_angle_after < r.certified_floor - slack)
        throw std::logic_error("optimize: the minimum angle decreased from " + std::to_string(r.min_angle_before) + " to " +
                               std::to_string(r.min_angle_after));
    if (r.max_angle_after > std::max(cap_, r.max_angle_before))  // rule (6)
        throw std::logic_error("optimize: the maximum angle rose to " + std::to_string(r.max_angle_after) +
                               ", above the certified maximum " + std::to_string(cap_));
    // The post-condition, always: the whole mesh is still a valid embedding
    // (mesh_checks.hpp: orientation, manifold edges, closed and simple
    // boundary loops, no folds).  A failure is a bug of this pass.
    if (const std::string worse = areas_.worse(AreaBudget(m_, curves_)); !worse.empty())
        throw std::logic_error("optimize: " + worse);
    if (const MeshCheck c = check_mesh(m_); !c.ok()) {
        std::string msg = "optimize: the optimised mesh is not valid";
        for (const std::string& m : c.messages) msg += "; " + m;
        throw std::logic_error(msg + " (a bug of the pass: nothing written; please report the input)");
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return r;
}

OptimizeReport optimize(Mesh& mesh, const SlideCurves& curves, const OptimizeOptions& options) {
    if (!(options.spacing > 0) || !std::isfinite(options.spacing))
        throw std::invalid_argument("optimize_mesh: the spacing must be positive and finite");
    if (options.max_sweeps < 0) throw std::invalid_argument("optimize_mesh: max_sweeps must be >= 0");
    if (mesh.triangles.empty()) return {};
    return Optimizer(mesh, curves, options).run();
}

}  // namespace

OptimizeReport optimize_mesh(Mesh& mesh, const LevelSet& f, const OptimizeOptions& options) {
    return optimize(mesh, SlideCurves(f), options);
}

OptimizeReport optimize_mesh(Mesh& mesh, const MaterialField& field, const OptimizeOptions& options) {
    return optimize(mesh, SlideCurves(field), options);
}

}  // namespace warpmesh
