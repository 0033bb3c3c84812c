// bcc_explore — double-precision explorer of the BCC generic tetrahedron
// (generic_bcc.hpp): not on the proof path (it uses acos), it estimates what
// the prover should find.
//
//   bcc_explore keys                      key counts by class
//   bcc_explore search L S [N]            per key: N random points of the
//                                         parameter box plus a local search
//                                         for the smallest and largest
//                                         dihedral angle; worst keys printed
//   bcc_explore shapes L S [TRIALS]       random quadrics stuffed on a 6³
//                                         block (bcc_stuffing.hpp)
//   bcc_explore counterexample L S        the counter-example certificate
//                                         (proofs/bcc_half.cert at 0.5 0.5):
//                                         the most negative 6·volume of an
//                                         output tetrahedron over every key's
//                                         box points on the 1/16 grid
//   bcc_explore signs L- L+ S- S+ [N] [TRIALS]
//                                         rule experiment (proofs/README.md,
//                                         "Towards 12°"): thresholds per sign
//                                         of the violated vertex (− inside,
//                                         + outside); the space's extremes
//                                         (per key, every pre-warp sign of its
//                                         warped vertices) and random shapes
//   bcc_explore faces RULE L S [N]        rule experiment (proofs/README.md,
//                                         "Towards 12°"): as search, with the
//                                         quads on background faces split by
//                                         RULE instead of generic_bcc.hpp's
//                                         face rule: parity (generic_bcc.hpp's,
//                                         for comparison), shorter (the shorter
//                                         diagonal) or maxmin (the diagonal
//                                         whose two triangles have the larger
//                                         smallest angle) or delaunay (the
//                                         in-circle test as an exact degree-6
//                                         form, evaluated in double here);
//                                         ties go to generic_bcc.hpp's rule;
//                                         the prism's inside quad (in one
//                                         tetrahedron only) takes, with maxmin,
//                                         the diagonal with the larger smallest
//                                         dihedral angle, with delaunay the
//                                         shorter one.
//                                         Prints how many n- = 3 prisms came
//                                         out cyclic (no triangulation).
// L, S: α_long, α_short as decimals (e.g. 0.24999 0.41189).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>

#include "warpmesh/bcc_stuffing.hpp"
#include "warpmesh/prove_bcc.hpp"

using namespace warpmesh;

namespace {

bcc::Alphas alphas_of(const char* l, const char* s) {
    const auto q = [](const char* x) { return static_cast<std::int64_t>(std::llround(std::atof(x) * 100000)); };
    return {q(l), 100000, q(s), 100000};
}

struct Extremes {
    double min = 180, max = 0;
    bool inverted = false;
    bool cyclic = false;  // faces mode: an n- = 3 prism whose three face diagonals turn the same way
};

// ---- geometric face rules (the faces mode; not the mesher's rule) ------------
enum class ExploreRule { parity, shorter, maxmin, delaunay };
using Points = std::array<bcc::Vec<double>, 10>;

double min_angle_deg(const bcc::Vec<double>& p, const bcc::Vec<double>& q, const bcc::Vec<double>& r) {
    const auto at = [](const bcc::Vec<double>& o, const bcc::Vec<double>& u, const bcc::Vec<double>& v) {
        double d = 0, nu = 0, nv = 0;
        for (int i = 0; i < 3; ++i) {
            const double a = u[static_cast<std::size_t>(i)] - o[static_cast<std::size_t>(i)];
            const double b = v[static_cast<std::size_t>(i)] - o[static_cast<std::size_t>(i)];
            d += a * b, nu += a * a, nv += b * b;
        }
        return std::acos(std::clamp(d / std::sqrt(nu * nv), -1.0, 1.0)) * 180 / M_PI;
    };
    return std::min({at(p, q, r), at(q, r, p), at(r, p, q)});
}

// On the face (a, b, r) (a, b the - vertices), true iff its quad
// (a, b, cut(b, r), cut(a, r)) is split by a–cut(b, r).  The quad is planar
// (on the warped face), and both tetrahedra sharing the face see the same
// four points, so any rule of these points is conforming.
bool face_takes_a(ExploreRule rule, const Points& P, int a, int b, int r, int parity) {
    const int ca = bcc::cut_point(a, r), cb = bcc::cut_point(b, r);
    const auto d2 = [&](int i, int j) {
        double t = 0;
        for (std::size_t c = 0; c < 3; ++c)
            t += (P[static_cast<std::size_t>(i)][c] - P[static_cast<std::size_t>(j)][c]) * (P[static_cast<std::size_t>(i)][c] - P[static_cast<std::size_t>(j)][c]);
        return t;
    };
    const auto p = [&](int i) { return P[static_cast<std::size_t>(i)]; };
    double x = 0, y = 0;  // x: a–cb's merit, y: b–ca's (larger wins)
    if (rule == ExploreRule::shorter) x = -d2(a, cb), y = -d2(b, ca);
    if (rule == ExploreRule::delaunay) {
        // The quad is convex, so a–cb is Delaunay iff the angles opposite it,
        // at b in (a, b, cb) and at ca in (a, cb, ca), sum to at most π:
        // cot + cot >= 0, i.e. (u·v)(u'×v')·N + (u'·v')(u×v)·N >= 0 with N
        // the face's normal (both cross products point along N).  A degree-6
        // polynomial: the exact form a prover and checker would evaluate.
        using V = bcc::Vec<double>;
        const auto sub3 = [](const V& x, const V& y) { return V{x[0] - y[0], x[1] - y[1], x[2] - y[2]}; };
        const auto dot = [](const V& x, const V& y) { return x[0] * y[0] + x[1] * y[1] + x[2] * y[2]; };
        const auto cross = [](const V& x, const V& y) {
            return V{x[1] * y[2] - x[2] * y[1], x[2] * y[0] - x[0] * y[2], x[0] * y[1] - x[1] * y[0]};
        };
        const V n = cross(sub3(p(b), p(a)), sub3(p(r), p(a)));
        const V u = sub3(p(a), p(b)), v = sub3(p(cb), p(b)), u2 = sub3(p(cb), p(ca)), v2 = sub3(p(a), p(ca));
        const double g = dot(u, v) * std::abs(dot(cross(u2, v2), n)) + dot(u2, v2) * std::abs(dot(cross(u, v), n));
        x = g, y = -g;
    }
    if (rule == ExploreRule::maxmin)
        x = std::min(min_angle_deg(p(a), p(b), p(cb)), min_angle_deg(p(a), p(cb), p(ca))),
        y = std::min(min_angle_deg(p(a), p(b), p(ca)), min_angle_deg(p(b), p(cb), p(ca)));
    return x != y ? x > y : bcc::face_takes_a(a, b, r, parity);
}

double min_dihedral_deg(const bcc::Stencil& st, const Points& P) {
    double m = 180;
    for (int j = 0; j < st.count; ++j) {
        std::array<bcc::Vec<double>, 4> p{};
        for (std::size_t v = 0; v < 4; ++v) p[v] = P[st.tet[static_cast<std::size_t>(j)][v]];
        for (double x : bcc_stuffing::dihedral_degrees(p)) m = std::min(m, x);
    }
    return m;
}

// generic_bcc.hpp's stencil() with the face quads split by `rule` (the
// prism's inside quad, as there, turns against quad 0, but for maxmin and
// delaunay: see below).  count = -1: cyclic.
bcc::Stencil rule_stencil(ExploreRule rule, const std::array<int, 4>& sign, int parity, const Points& P) {
    std::array<int, 4> neg{}, pos{};
    int nn = 0, np = 0;
    for (int i = 0; i < 4; ++i) {
        if (sign[static_cast<std::size_t>(i)] < 0) neg[static_cast<std::size_t>(nn++)] = i;
        if (sign[static_cast<std::size_t>(i)] > 0) pos[static_cast<std::size_t>(np++)] = i;
    }
    bcc::Stencil s;
    if (nn == 2 && np == 1) {
        const int a = neg[0], b = neg[1], r = pos[0], z = 6 - a - b - r;
        const int ca = bcc::cut_point(a, r), cb = bcc::cut_point(b, r);
        if (face_takes_a(rule, P, a, b, r, parity)) bcc::push_oriented(s, z, a, b, cb), bcc::push_oriented(s, z, a, cb, ca);
        else bcc::push_oriented(s, z, a, b, ca), bcc::push_oriented(s, z, b, cb, ca);
        return s;
    }
    if (nn == 2 && np == 2) {
        const int a = neg[0], b = neg[1], r0 = pos[0], r1 = pos[1];
        const std::array<int, 3> bot{a, bcc::cut_point(a, r0), bcc::cut_point(a, r1)}, top{b, bcc::cut_point(b, r0), bcc::cut_point(b, r1)};
        const bool f0 = face_takes_a(rule, P, a, b, r0, parity), f2 = !face_takes_a(rule, P, a, b, r1, parity);
        bcc::prism_tets(s, bot, top, {f0, !f0, f2});
        if (rule < ExploreRule::maxmin || f0 == f2) return s;  // f0 == f2: the inside diagonal is forced
        // The inside quad (on the surface, in this tetrahedron only: any
        // choice is conforming) takes, for maxmin, the diagonal whose three
        // tetrahedra have the larger smallest dihedral angle; for delaunay the
        // shorter one, bot[1]–top[2] or bot[2]–top[1] (ties: as parity).
        bcc::Stencil t;
        bcc::prism_tets(t, bot, top, {f0, f0, f2});
        if (rule == ExploreRule::maxmin) return min_dihedral_deg(t, P) > min_dihedral_deg(s, P) ? t : s;
        const auto d2 = [&](int i, int j) {
            double q = 0;
            for (std::size_t c = 0; c < 3; ++c) {
                const double d = P[static_cast<std::size_t>(i)][c] - P[static_cast<std::size_t>(j)][c];
                q += d * d;
            }
            return q;
        };
        const double fwd = d2(bot[1], top[2]), back = d2(bot[2], top[1]);
        if (fwd == back) return s;
        return (fwd < back) == f0 ? t : s;  // t's inside diagonal is bot[1]–top[2] iff f0
    }
    if (nn == 3 && np == 1) {
        const int r = pos[0];
        const std::array<int, 3> bot{neg[0], neg[1], neg[2]};
        std::array<bool, 3> fwd{};
        for (std::size_t i = 0; i < 3; ++i) fwd[i] = face_takes_a(rule, P, bot[i], bot[(i + 1) % 3], r, parity);
        if (fwd[0] == fwd[1] && fwd[1] == fwd[2]) {
            s.count = -1;
            return s;
        }
        bcc::prism_tets(s, bot, {bcc::cut_point(bot[0], r), bcc::cut_point(bot[1], r), bcc::cut_point(bot[2], r)}, fwd);
        return s;
    }
    return bcc::stencil(sign, parity);
}

// Smallest and largest dihedral angle over the key's output tetrahedra at x
// (the face quads split by `rule`; parity: generic_bcc.hpp's stencil).
Extremes evaluate(const bcc_prover::Key& k, const std::vector<bcc_prover::Param>& ps, const std::vector<double>& x,
                  ExploreRule rule = ExploreRule::parity) {
    const auto pts = bcc_prover::key_points(k, ps, x.data());
    const bcc::Stencil st = rule == ExploreRule::parity ? bcc::stencil(k.sign, k.parity) : rule_stencil(rule, k.sign, k.parity, pts);
    Extremes e;
    if (st.count < 0) {
        e.cyclic = true;
        return e;
    }
    for (int j = 0; j < st.count; ++j) {
        std::array<bcc::Vec<double>, 4> p{};
        for (int v = 0; v < 4; ++v) p[static_cast<std::size_t>(v)] = pts[st.tet[static_cast<std::size_t>(j)][static_cast<std::size_t>(v)]];
        if (bcc::dihedral_forms(p).volume6 <= 0) e.inverted = true;
        for (double a : bcc_stuffing::dihedral_degrees(p)) e.min = std::min(e.min, a), e.max = std::max(e.max, a);
    }
    return e;
}

// Random restarts and a shrinking-step pattern search for the objective
// (sign = +1: minimise the smallest angle; -1: maximise the largest).
std::pair<double, std::vector<double>> search(const bcc_prover::Key& k, const std::vector<bcc_prover::Param>& ps, int n,
                                              int sign, std::mt19937& rng, bool& inverted, ExploreRule rule = ExploreRule::parity,
                                              long* cyclic = nullptr) {
    const auto obj = [&](const std::vector<double>& x) {
        const Extremes e = evaluate(k, ps, x, rule);
        inverted = inverted || e.inverted;
        if (e.cyclic && cyclic) ++*cyclic;
        if (e.cyclic) return sign > 0 ? 180.0 : 0.0;  // counted, not an angle
        return sign > 0 ? e.min : -e.max;
    };
    std::vector<double> best(ps.size());
    double fb = 1e9;
    for (int s = 0; s < n; ++s) {
        std::vector<double> x(ps.size());
        for (std::size_t i = 0; i < ps.size(); ++i) {
            const int corner = std::uniform_int_distribution<int>(0, 3)(rng);  // favour the box's faces
            const double r = corner == 0 ? 0 : corner == 1 ? 1 : std::uniform_real_distribution<double>(0, 1)(rng);
            x[i] = ps[i].lo + r * (ps[i].hi - ps[i].lo);
        }
        const double f = obj(x);
        if (f < fb) fb = f, best = x;
    }
    for (double step = 0.25; step > 1e-7; step *= 0.5)
        for (bool improved = true; improved;) {
            improved = false;
            for (std::size_t i = 0; i < ps.size(); ++i)
                for (double d : {-1.0, 1.0}) {
                    std::vector<double> x = best;
                    x[i] = std::clamp(x[i] + d * step * (ps[i].hi - ps[i].lo), ps[i].lo, ps[i].hi);
                    const double f = obj(x);
                    if (f < fb - 1e-12) fb = f, best = x, improved = true;
                }
        }
    return {sign > 0 ? fb : -fb, best};
}

int run_search(const bcc::Alphas& al, int n, ExploreRule rule = ExploreRule::parity) {
    const auto keys = bcc_prover::enumerate_keys();
    std::mt19937 rng(29);
    struct Row {
        double v;
        std::string code;
        std::vector<double> x;
    };
    std::vector<Row> mins, maxs;
    int inverted = 0;
    long cyclic = 0;
    for (const auto& k : keys) {
        const auto ps = bcc_prover::key_params(k, al);
        bool inv = false;
        auto lo = search(k, ps, n, 1, rng, inv, rule, &cyclic);
        auto hi = search(k, ps, n, -1, rng, inv, rule, &cyclic);
        inverted += inv;
        mins.push_back({lo.first, bcc_prover::code_of(k), lo.second});
        maxs.push_back({hi.first, bcc_prover::code_of(k), hi.second});
    }
    std::sort(mins.begin(), mins.end(), [](const Row& a, const Row& b) { return a.v < b.v; });
    std::sort(maxs.begin(), maxs.end(), [](const Row& a, const Row& b) { return a.v > b.v; });
    std::printf("keys %zu, keys with an inverted sample %d", keys.size(), inverted);
    if (rule != ExploreRule::parity) std::printf(", cyclic prism samples %ld", cyclic);
    std::printf("\n");
    for (int i = 0; i < 8 && i < static_cast<int>(mins.size()); ++i) {
        std::printf("min %.4f  %s  at", mins[static_cast<std::size_t>(i)].v, mins[static_cast<std::size_t>(i)].code.c_str());
        for (double x : mins[static_cast<std::size_t>(i)].x) std::printf(" %.6f", x);
        std::printf("\n");
    }
    for (int i = 0; i < 8 && i < static_cast<int>(maxs.size()); ++i) {
        std::printf("max %.4f  %s  at", maxs[static_cast<std::size_t>(i)].v, maxs[static_cast<std::size_t>(i)].code.c_str());
        for (double x : maxs[static_cast<std::size_t>(i)].x) std::printf(" %.6f", x);
        std::printf("\n");
    }
    return 0;
}

// The key's parameter box when the thresholds depend on the pre-warp sign
// `orig` of the violated vertex (a[0] α_long of −, a[1] of +, a[2] α_short of
// −, a[3] of +): a warp t <= α(type, orig); a cut (−, +) edge keeps its point
// at least α(type, −) from its − end and α(type, +) from its + end.  Empty if
// orig contradicts a warp inside the tetrahedron (its target had the
// opposite pre-warp sign).
std::vector<bcc_prover::Param> signed_params(const bcc_prover::Key& k, const std::array<int, 4>& orig, const std::array<double, 4>& a) {
    std::vector<bcc_prover::Param> out;
    const auto al = [&](bool lng, int sg) { return a[(lng ? 0U : 2U) + (sg > 0 ? 1U : 0U)]; };
    for (int i = 0; i < 4; ++i) {
        const int w = k.warp[static_cast<std::size_t>(i)];
        if (k.sign[static_cast<std::size_t>(i)] != 0 || w == bcc::stay) continue;
        const int j = bcc_prover::warp_target(i, w);
        if (j >= 0 && orig[static_cast<std::size_t>(j)] != -orig[static_cast<std::size_t>(i)]) return {};
        const double t = al(bcc::is_long_direction(w), orig[static_cast<std::size_t>(i)]);
        out.push_back({i, 0.0, t, 0.0, t});
    }
    for (int e = 0; e < 6; ++e) {
        const auto& ed = bcc::tet_edges[static_cast<std::size_t>(e)];
        const int s0 = k.sign[static_cast<std::size_t>(ed[0])];
        if (s0 * k.sign[static_cast<std::size_t>(ed[1])] >= 0) continue;
        const bool lng = bcc::edge_is_long(e);
        const double lo = al(lng, s0), hi = 1 - al(lng, -s0);
        out.push_back({4 + e, lo, hi, lo, hi});
    }
    return out;
}

int run_signs(const std::array<double, 4>& a, int n) {
    std::mt19937 rng(29);
    double mn = 180, mx = 0;
    std::string kmin, kmax;
    for (const auto& k : bcc_prover::enumerate_keys()) {
        std::vector<int> warped;
        for (int i = 0; i < 4; ++i)
            if (k.sign[static_cast<std::size_t>(i)] == 0 && k.warp[static_cast<std::size_t>(i)] != bcc::stay) warped.push_back(i);
        for (unsigned mask = 0; mask < (1U << warped.size()); ++mask) {
            std::array<int, 4> orig = k.sign;
            for (std::size_t b = 0; b < warped.size(); ++b) orig[static_cast<std::size_t>(warped[b])] = (mask >> b & 1U) ? 1 : -1;
            const auto ps = signed_params(k, orig, a);
            if (ps.empty() && !warped.empty()) continue;
            bool inv = false;
            const double lo = search(k, ps, n, 1, rng, inv).first, hi = search(k, ps, n, -1, rng, inv).first;
            std::string code = bcc_prover::code_of(k) + " pre-warp";
            for (int i : warped) code += orig[static_cast<std::size_t>(i)] > 0 ? " +" : " -";
            if (inv || lo < mn) mn = inv ? 0 : lo, kmin = code + (inv ? " (inverted)" : "");
            if (inv || hi > mx) mx = inv ? 180 : hi, kmax = code + (inv ? " (inverted)" : "");
        }
    }
    std::printf("space: min %.4f (%s), max %.4f (%s)\n", mn, kmin.c_str(), mx, kmax.c_str());
    return 0;
}

int run_shapes(const bcc::Alphas& al, int trials, const std::array<double, 4>* by_sign = nullptr) {
    std::mt19937 rng(30);
    std::uniform_real_distribution<double> u(-1, 1);
    Extremes all;
    long tets = 0, all_zero = 0;  // all_zero: background tetrahedra with four zero vertices, never output
    for (int tr = 0; tr < trials; ++tr) {
        const double cx = 3 + u(rng), cy = 3 + u(rng), cz = 3 + u(rng), a = 1 + 0.5 * u(rng), b = 1 + 0.5 * u(rng),
                     c = 1 + 0.5 * u(rng), r = 2 * (1 + 0.2 * u(rng)), xy = 0.3 * u(rng);
        const auto f = [&](double x, double y, double z) {
            return a * (x - cx) * (x - cx) + b * (y - cy) * (y - cy) + c * (z - cz) * (z - cz) + xy * (x - cx) * (y - cy) - r * r;
        };
        const bcc_stuffing::Stuffed m = bcc_stuffing::stuff(f, 6, 1.0, al, by_sign);
        all_zero += m.all_zero_left_out;
        for (const auto& bt : m.background) {
            for (int k = bt.first; k < bt.first + bt.count; ++k) {
                const auto& t = m.tets[static_cast<std::size_t>(k)];
                std::array<bcc::Vec<double>, 4> p{};
                for (int v = 0; v < 4; ++v) p[static_cast<std::size_t>(v)] = m.points[static_cast<std::size_t>(t[static_cast<std::size_t>(v)])];
                if (bcc::dihedral_forms(p).volume6 <= 0) all.inverted = true;
                for (double x : bcc_stuffing::dihedral_degrees(p)) all.min = std::min(all.min, x), all.max = std::max(all.max, x);
                ++tets;
            }
        }
    }
    std::printf("%d shapes, %ld tetrahedra: dihedral %.4f .. %.4f%s; all-zero background tetrahedra left out: %ld\n", trials, tets,
                all.min, all.max, all.inverted ? " (inverted tetrahedra)" : "", all_zero);
    return 0;
}

// ---- the counter-example certificate (warpmesh-check-bcc checks it) -----------
// Per key, every point of its box on the grid of multiples of 1/16 (the box
// ends at α = 1/2 are on it); the output tetrahedron with the most negative
// 6·volume (doubled lattice coordinates).  On that grid every coordinate is
// a multiple of 1/16 below 4 in magnitude, so double evaluates 6·volume
// exactly (products of three such numbers need 3·6 + a few bits): the sign is
// the exact one, which the checker re-derives in exact arithmetic anyway.
// Ties: the first key in canonical order, the first grid point, the first
// tetrahedron — deterministic, so CI can rewrite the file and compare.
struct Inverted {
    double volume6 = 0;
    std::string code;
    std::vector<double> x;
    std::array<int, 4> tet{};
};

// The grid values j/16 inside [lo, hi] (lo, hi the exact box ends as doubles).
std::vector<double> grid_values(const bcc_prover::Param& p) {
    std::vector<double> v;
    for (int j = 0; j <= 16; ++j)
        if (j / 16.0 >= p.lo && j / 16.0 <= p.hi) v.push_back(j / 16.0);
    return v;
}

// The most negative 6·volume of one key on its grid, folded into `best`.
void most_inverted(const bcc_prover::Key& k, const bcc::Alphas& al, Inverted& best) {
    const auto ps = bcc_prover::key_params(k, al);
    std::vector<std::vector<double>> axes;
    for (const auto& p : ps) axes.push_back(grid_values(p));
    for (const auto& a : axes)
        if (a.empty()) return;
    const bcc::Stencil st = bcc::stencil(k.sign, k.parity);
    std::vector<std::size_t> at(ps.size(), 0);
    for (bool more = true; more;) {
        std::vector<double> x(ps.size());
        for (std::size_t i = 0; i < ps.size(); ++i) x[i] = axes[i][at[i]];
        const auto pts = bcc_prover::key_points(k, ps, x.data());
        for (int j = 0; j < st.count; ++j) {
            std::array<bcc::Vec<double>, 4> p{};
            for (int v = 0; v < 4; ++v) p[static_cast<std::size_t>(v)] = pts[st.tet[static_cast<std::size_t>(j)][static_cast<std::size_t>(v)]];
            const double v6 = bcc::dihedral_forms(p).volume6;
            if (v6 < best.volume6) {
                best = {v6, bcc_prover::code_of(k), x, {}};
                for (int v = 0; v < 4; ++v) best.tet[static_cast<std::size_t>(v)] = st.tet[static_cast<std::size_t>(j)][static_cast<std::size_t>(v)];
            }
        }
        more = false;  // next grid point (odometer, last parameter fastest)
        for (std::size_t i = ps.size(); i-- > 0;) {
            if (++at[i] < axes[i].size()) {
                more = true;
                break;
            }
            at[i] = 0;
        }
    }
}

// j/16 as a reduced dyadic "p/q" (or "p").
std::string dyadic_text(double x) {
    long p = std::lround(x * 16), q = 16;
    while (q > 1 && p % 2 == 0) p /= 2, q /= 2;
    return q == 1 ? std::to_string(p) : std::to_string(p) + "/" + std::to_string(q);
}

int run_counterexample(const bcc::Alphas& al) {
    Inverted best;
    for (const auto& k : bcc_prover::enumerate_keys()) most_inverted(k, al, best);
    if (best.code.empty()) {
        std::fprintf(stderr, "bcc_explore: no output tetrahedron with 6*volume < 0 on the 1/16 grid\n");
        return 1;
    }
    std::printf("warpmesh-bcc-counterexample 1\n");
    std::printf("# written by bcc_explore counterexample; checked by warpmesh-check-bcc (proofs/README.md)\n");
    std::printf("# 6*volume at the point: %.6f (doubled lattice coordinates)\n", best.volume6);
    std::printf("alphas %lld/%lld %lld/%lld\n", static_cast<long long>(al.long_num), static_cast<long long>(al.long_den),
                static_cast<long long>(al.short_num), static_cast<long long>(al.short_den));
    std::printf("key %s\npoint", best.code.c_str());
    for (double x : best.x) std::printf(" %s", dyadic_text(x).c_str());
    std::printf("\ninverted %d %d %d %d\n", best.tet[0], best.tet[1], best.tet[2], best.tet[3]);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    const std::string mode = argc > 1 ? argv[1] : "";
    if (mode == "keys") {
        const auto keys = bcc_prover::enumerate_keys();
        std::map<int, int> by_count;
        int params = 0;
        for (const auto& k : keys) {
            ++by_count[bcc::stencil(k.sign, k.parity).count];
            params = std::max(params, static_cast<int>(bcc_prover::key_params(k, bcc::labelle_shewchuk_alphas).size()));
        }
        std::printf("keys %zu (all-zero keys %zu); max parameters %d\n", keys.size(), bcc_prover::enumerate_keys(true).size(), params);
        for (const auto& [c, n] : by_count) std::printf("  %d output tetrahedra: %d keys\n", c, n);
        return 0;
    }
    if ((mode == "search" || mode == "shapes") && argc >= 4) {
        const bcc::Alphas al = alphas_of(argv[2], argv[3]);
        const int n = argc > 4 ? std::atoi(argv[4]) : (mode == "search" ? 64 : 50);
        return mode == "search" ? run_search(al, n) : run_shapes(al, n);
    }
    if (mode == "faces" && argc >= 5) {
        const std::string r = argv[2];
        if (r != "parity" && r != "shorter" && r != "maxmin" && r != "delaunay") {
            std::fprintf(stderr, "bcc_explore: face rule %s is not parity, shorter, maxmin or delaunay\n", r.c_str());
            return 2;
        }
        const ExploreRule rule = r == "parity"    ? ExploreRule::parity
                              : r == "shorter" ? ExploreRule::shorter
                              : r == "maxmin"  ? ExploreRule::maxmin
                                               : ExploreRule::delaunay;
        return run_search(alphas_of(argv[3], argv[4]), argc > 5 ? std::atoi(argv[5]) : 64, rule);
    }
    if (mode == "counterexample" && argc == 4) return run_counterexample(alphas_of(argv[2], argv[3]));
    if (mode == "signs" && argc >= 6) {
        const std::array<double, 4> a{std::atof(argv[2]), std::atof(argv[3]), std::atof(argv[4]), std::atof(argv[5])};
        for (double x : a)
            if (!(x > 0 && x < 0.5)) {
                std::fprintf(stderr, "bcc_explore: thresholds must lie in (0, 0.5)\n");
                return 2;
            }
        const int r = run_signs(a, argc > 6 ? std::atoi(argv[6]) : 24);
        return r ? r : run_shapes(bcc::labelle_shewchuk_alphas, argc > 7 ? std::atoi(argv[7]) : 50, &a);
    }
    std::fprintf(stderr, "usage: bcc_explore keys | search L S [N] | shapes L S [TRIALS] | counterexample L S | faces parity|shorter|maxmin|delaunay L S [N] | signs L- L+ S- S+ [N] [TRIALS]\n");
    return 2;
}
