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

int run_shapes(const bcc::Alphas& al, int trials) {
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
        const testing::Stuffed m = testing::stuff(f, 6, 1.0, al);
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
    std::fprintf(stderr, "usage: bcc_explore keys | search L S [N] | shapes L S [TRIALS]\n");
    return 2;
}
