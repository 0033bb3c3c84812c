// bcc_ceiling — writes the ceiling certificate proofs/bcc_ceiling.cert
// (proofs/README.md, "A ceiling: no thresholds reach 12°"), which
// warpmesh-check-bcc checks exactly.
//
//   bcc_ceiling [DEGREES]      the certificate on stdout (DEGREES: 12)
//
// THE STATEMENT.  For every pair (α_long, α_short) in [0, 1/2]² the BCC
// space (proofs/README.md, "The BCC space") contains, in one of four keys
// whose stencil is a single tetrahedron (so no face rule enters), a
// positively oriented output tetrahedron with a dihedral angle below
// DEGREES.  So no choice of thresholds, with any face rule, certifies
// θmin >= DEGREES over this space.  The four keys are the configurations
// that bind at the best pairs (a − vertex with its cut point at α from it,
// or a whole tetrahedron of warps; each warp a single violation leaving
// the tetrahedron or reaching an unwarped vertex):
//   -,+,0i,0m/0   cut point on the long edge k0k1 at α_long from k0, both
//                 centres warped towards k1 (wants α_long large, α_short small)
//   -,0c,0m,+/0   cut point on the short edge k0c1 at α_short from k0, k1 and
//                 c0 warped out of the tetrahedron (wants α_short large)
//   -,0c,0m,0i/0  three warps out of the tetrahedron (wants α small)
//   -,0c,0d,0d/0  three warps out of the tetrahedron, two of them long
//
// THE CERTIFICATE.  A quadtree over the square [0, 1/2]² of (α_long,
// α_short), depth first: a line `split` stands for the current box's four
// quadrants, which follow in the order (low, low), (high, low), (low, high),
// (high, high) of (α_long, α_short); a line `witness CODE x_0 .. x_{m-1}`
// settles the current box [L0, L1] × [S0, S1] with one exact point of the
// key's space at every pair of the box: a warp fraction t ∈ [0, α] for every
// α >= L0 (long) or S0 (short), so t = L0 or S0; a cut fraction u ∈ [α, 1 − α]
// for every α <= L1 or S1, so u = L1 or S1 (both <= 1/2).  Box ends are
// dyadic, so every x is.  A box is split until one key's point has a
// dihedral angle below DEGREES − 10^-6 in double (the checker decides
// exactly; the margin keeps double's rounding out of the choice).  Among the
// keys that settle a box, the one with the smallest angle; so the output is
// deterministic and CI can rewrite it and compare.
#include <cmath>
#include <numeric>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "warpmesh/bcc_stuffing.hpp"
#include "warpmesh/prove_bcc.hpp"

using namespace warpmesh;

namespace {

constexpr int max_depth = 39;  // the checker's limit too: box ends k / 2^40

// m / 2^e as a reduced "p/q" (or "p").
std::string dyadic(long long m, int e) {
    while (e > 0 && m % 2 == 0) m /= 2, --e;
    return e == 0 ? std::to_string(m) : std::to_string(m) + "/" + std::to_string(1LL << e);
}

struct Witness {
    double deg = 180;
    std::string line;
};

// The key's point for the box [l0, l1] × [s0, s1] (ends m / 2^e), and the
// smallest dihedral angle of its single output tetrahedron there.
Witness witness(const bcc_prover::Key& k, const std::array<long long, 4>& ends, int e) {
    const auto ps = bcc_prover::key_params(k, bcc::labelle_shewchuk_alphas);  // the parameter order only
    std::vector<double> x;
    std::string line = "witness ";
    line += bcc_prover::code_of(k);
    for (const auto& p : ps) {
        const bool lng = p.index < 4 ? bcc::is_long_direction(k.warp[static_cast<std::size_t>(p.index)])
                                     : bcc::edge_is_long(p.index - 4);
        const long long m = p.index < 4 ? ends[lng ? 0 : 2] : ends[lng ? 1 : 3];  // t = α_lo, u = α_hi
        x.push_back(std::ldexp(static_cast<double>(m), -e));
        line += ' ';
        line += dyadic(m, e);
    }
    const auto pts = bcc_prover::key_points(k, ps, x.data());
    const bcc::Stencil st = bcc::stencil(k.sign, k.parity);
    std::array<bcc::Vec<double>, 4> p{};
    for (int v = 0; v < 4; ++v) p[static_cast<std::size_t>(v)] = pts[st.tet[0][static_cast<std::size_t>(v)]];
    Witness w;
    if (bcc::dihedral_forms(p).volume6 <= 0) return w;  // the statement wants a positive tetrahedron
    for (double a : bcc_stuffing::dihedral_degrees(p)) w.deg = std::min(w.deg, a);
    w.line = line;
    return w;
}

// Writes the subtree of box (i, j) at depth d: [i, i + 1] × [j, j + 1] / 2^(d+1).
bool write_box(const std::vector<bcc_prover::Key>& keys, double below, long long i, long long j, int d, std::string& out,
               long& boxes) {
    const int e = d + 1;
    const std::array<long long, 4> ends{i, i + 1, j, j + 1};
    Witness best;
    for (const auto& k : keys) {
        const Witness w = witness(k, ends, e);
        if (w.deg < best.deg) best = w;
    }
    if (best.deg < below - 1e-6) {
        out += best.line + "\n";
        ++boxes;
        return true;
    }
    if (d == max_depth) return false;
    out += "split\n";
    for (const auto& [di, dj] : {std::pair{0, 0}, {1, 0}, {0, 1}, {1, 1}})
        if (!write_box(keys, below, 2 * i + di, 2 * j + dj, d + 1, out, boxes)) return false;
    return true;
}

// c with c / 2^40 >= cos²(θ) for θ = deg degrees, 0 < deg <= 60: the checker
// verifies c against a rational upper bound of cos²θ; this one is that bound
// rounded up, so it passes: cos x <= 1 − x²/2 + x⁴/24 for |x| < π/2, and the
// polynomial decreases on (0, √6), so x_lo = 3.14159 · deg / 180 < x gives an
// upper bound.
long long cos2_threshold(long double deg) {
    const long double x = 3.14159L * deg / 180, p = 1 - x * x / 2 + x * x * x * x / 24;
    return static_cast<long long>(std::ceil(std::ldexp(p * p, 40))) + 1;
}

}  // namespace

int main(int argc, char** argv) {
    // DEGREES = p / 100 (at most two decimals), in (0, 60].
    const std::string text = argc > 1 ? argv[1] : "12";
    char* end = nullptr;
    const double given = std::strtod(text.c_str(), &end);
    const long long p = std::llround(given * 100);
    if (argc > 2 || *end != '\0' || !(given > 0 && given <= 60) || std::abs(given * 100 - static_cast<double>(p)) > 1e-6) {
        std::fprintf(stderr, "bcc_ceiling: DEGREES must be a number in (0, 60] with at most two decimals\n"
                             "usage: bcc_ceiling [DEGREES]   (default 12)\n");
        return 2;
    }
    const long long g = std::gcd(p, 100LL), num = p / g, q = 100 / g;
    const std::string deg = q == 1 ? std::to_string(num) : std::to_string(num) + "/" + std::to_string(q);
    const double below = static_cast<double>(p) / 100;
    std::vector<bcc_prover::Key> keys;
    for (const char* code : {"-,+,0i,0m/0", "-,0c,0m,+/0", "-,0c,0m,0i/0", "-,0c,0d,0d/0"}) {
        const auto k = bcc_prover::key_with_code(code);
        if (!k) {
            std::fprintf(stderr, "bcc_ceiling: %s is not a canonical key\n", code);
            return 1;
        }
        keys.push_back(*k);
    }
    std::string out;  // written whole, only when every box is settled
    long boxes = 0;
    if (!write_box(keys, below, 0, 0, 0, out, boxes)) {
        std::fprintf(stderr, "bcc_ceiling: a box of depth %d has no witness below %s degrees\n", max_depth, text.c_str());
        return 1;
    }
    std::printf("warpmesh-bcc-ceiling 1\n");
    std::printf("# written by bcc_ceiling %s; checked by warpmesh-check-bcc (proofs/README.md, \"A ceiling\")\n", text.c_str());
    std::printf("# %ld boxes\n", boxes);
    std::printf("below %s %lld\n%s", deg.c_str(), cos2_threshold(static_cast<long double>(p) / 100), out.c_str());
    return 0;
}
