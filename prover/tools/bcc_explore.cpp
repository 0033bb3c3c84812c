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
//                                         block (tests/bcc_stuffing.hpp)
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
// L, S: α_long, α_short as decimals (e.g. 0.24999 0.41189).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <random>
#include <string>

#include "../../tests/bcc_stuffing.hpp"
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
};

// Smallest and largest dihedral angle over the key's output tetrahedra at x.
Extremes evaluate(const bcc_prover::Key& k, const std::vector<bcc_prover::Param>& ps, const std::vector<double>& x) {
    const auto pts = bcc_prover::key_points(k, ps, x.data());
    const bcc::Stencil st = bcc::stencil(k.sign, k.parity);
    Extremes e;
    for (int j = 0; j < st.count; ++j) {
        std::array<bcc::Vec<double>, 4> p{};
        for (int v = 0; v < 4; ++v) p[static_cast<std::size_t>(v)] = pts[st.tet[static_cast<std::size_t>(j)][static_cast<std::size_t>(v)]];
        if (bcc::dihedral_forms(p).volume6 <= 0) e.inverted = true;
        for (double a : testing::dihedral_degrees(p)) e.min = std::min(e.min, a), e.max = std::max(e.max, a);
    }
    return e;
}

// Random restarts and a shrinking-step pattern search for the objective
// (sign = +1: minimise the smallest angle; -1: maximise the largest).
std::pair<double, std::vector<double>> search(const bcc_prover::Key& k, const std::vector<bcc_prover::Param>& ps, int n,
                                              int sign, std::mt19937& rng, bool& inverted) {
    const auto obj = [&](const std::vector<double>& x) {
        const Extremes e = evaluate(k, ps, x);
        inverted = inverted || e.inverted;
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

int run_search(const bcc::Alphas& al, int n) {
    const auto keys = bcc_prover::enumerate_keys();
    std::mt19937 rng(29);
    struct Row {
        double v;
        std::string code;
        std::vector<double> x;
    };
    std::vector<Row> mins, maxs;
    int inverted = 0;
    for (const auto& k : keys) {
        const auto ps = bcc_prover::key_params(k, al);
        bool inv = false;
        auto lo = search(k, ps, n, 1, rng, inv);
        auto hi = search(k, ps, n, -1, rng, inv);
        inverted += inv;
        mins.push_back({lo.first, bcc_prover::code_of(k), lo.second});
        maxs.push_back({hi.first, bcc_prover::code_of(k), hi.second});
    }
    std::sort(mins.begin(), mins.end(), [](const Row& a, const Row& b) { return a.v < b.v; });
    std::sort(maxs.begin(), maxs.end(), [](const Row& a, const Row& b) { return a.v > b.v; });
    std::printf("keys %zu, keys with an inverted sample %d\n", keys.size(), inverted);
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
        const testing::Stuffed m = testing::stuff(f, 6, 1.0, al, by_sign);
        all_zero += m.all_zero_left_out;
        for (const auto& bt : m.background) {
            for (int k = bt.first; k < bt.first + bt.count; ++k) {
                const auto& t = m.tets[static_cast<std::size_t>(k)];
                std::array<bcc::Vec<double>, 4> p{};
                for (int v = 0; v < 4; ++v) p[static_cast<std::size_t>(v)] = m.points[static_cast<std::size_t>(t[static_cast<std::size_t>(v)])];
                if (bcc::dihedral_forms(p).volume6 <= 0) all.inverted = true;
                for (double x : testing::dihedral_degrees(p)) all.min = std::min(all.min, x), all.max = std::max(all.max, x);
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
    std::fprintf(stderr, "usage: bcc_explore keys | search L S [N] | shapes L S [TRIALS] | counterexample L S | signs L- L+ S- S+ [N] [TRIALS]\n");
    return 2;
}
