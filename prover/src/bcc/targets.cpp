// targets.cpp — per-key targets of the 3D prover: a double-precision search of
// each key's box for its smallest and largest dihedral angle, turned into
// exact witnesses (points of the 2^-24 grid inside the exact box) and claims
// (the witness's cos² plus a margin, rounded up to 2^-40).  Not on the proof
// path: the search only chooses what to prove; the branch and bound
// (bound.cpp) proves it and the checker re-evaluates every witness exactly.
// Only + − × / and sqrt (correctly rounded) are used, and the pseudo-random
// starts are seeded by the key's code, so the targets of a key are the same
// on every IEEE machine and in every thread: a key's certificate line is
// reproducible alone.
#include <algorithm>
#include <cmath>
#include <random>

#include "warpmesh/prove_bcc.hpp"

namespace warpmesh::bcc_prover {
namespace {

// cos of the extreme angle over the key's output tetrahedra at x: the
// largest cos of a dihedral angle (smallest angle, sign = +1) or the
// smallest (largest angle, sign = −1), as +cos resp. −cos so that larger is
// more extreme; sign = 2: the largest cos of a face angle.
double extreme_cos(const Key& k, const std::vector<Param>& ps, const std::array<double, 4>& x, int sign, FaceRule rule) {
    const auto pts = key_points(k, ps, x.data());
    const bcc::Stencil st = stencil_at(k, ps, x.data(), rule);
    double best = -2;
    for (int j = 0; j < st.count; ++j) {
        std::array<bcc::Vec<double>, 4> p{};
        for (int v = 0; v < 4; ++v) p[static_cast<std::size_t>(v)] = pts[st.tet[static_cast<std::size_t>(j)][static_cast<std::size_t>(v)]];
        if (sign == 2) {
            const auto fa = bcc::face_angle_forms(p);
            for (std::size_t q = 0; q < 12; ++q)
                best = std::max(best, fa.nn[q] > 0 ? fa.dot[q] / std::sqrt(fa.nn[q]) : 1.0);
            continue;
        }
        const auto f = bcc::dihedral_forms(p);
        for (int e = 0; e < 6; ++e) {
            const double nn = f.nn[static_cast<std::size_t>(e)];
            const double c = nn > 0 ? f.dot[static_cast<std::size_t>(e)] / std::sqrt(nn) : 1.0;  // degenerate: extreme
            best = std::max(best, sign * c);
        }
    }
    return best;
}

// The grid point (multiple of 2^-24) nearest x inside the exact box [lo, hi]
// of parameter p (its ends exact rationals num/den).
double snap(double x, const Param& p) {
    const double g = 16777216.0;
    double s = std::nearbyint(x * g) / g;
    const double lo = std::ceil(p.lo * g - 1e-6) / g, hi = std::floor(p.hi * g + 1e-6) / g;  // see exact_inside
    return std::clamp(s, lo, hi);
}

// The warp fractions t and cut fractions u at the parameter values x.
void split_params(const std::vector<Param>& ps, const double* x, std::array<double, 4>& t, std::array<double, 6>& u) {
    for (std::size_t i = 0; i < ps.size(); ++i) {
        if (ps[i].index < 4) t[static_cast<std::size_t>(ps[i].index)] = x[i];
        else u[static_cast<std::size_t>(ps[i].index - 4)] = x[i];
    }
}

}  // namespace

std::array<bcc::Vec<double>, 10> key_points(const Key& k, const std::vector<Param>& ps, const double* x) {
    std::array<double, 4> t{};
    std::array<double, 6> u{};
    split_params(ps, x, t, u);
    return bcc::generic_points(k, t, u);
}

// On the 2^-24 grid the forms are exact in double: face_form's terms are
// small integers times 1 − u; inside_form's coordinate differences lie in
// [−3, 3] on the grid, their squares and sums below 2^5 on the 2^-48 grid.
bcc::Stencil stencil_at(const Key& k, const std::vector<Param>& ps, const double* x, FaceRule rule) {
    if (rule == FaceRule::parity) return bcc::stencil(k.sign, k.parity);
    std::array<double, 4> t{};
    std::array<double, 6> u{};
    split_params(ps, x, t, u);
    return bcc::stencil_with(k.sign, bcc::delaunay_diagonals(k.sign, k.parity, u));
}

double witness_cos(const Key& k, const std::vector<Param>& ps, const std::array<double, 4>& x, int sign, FaceRule rule) {
    return (sign == -1 ? -1 : 1) * extreme_cos(k, ps, x, sign, rule);
}

// Random starts (corners and faces favoured) and a shrinking-step pattern
// search on the 2^-24 grid, from `start` if given.
Witness search_witness(const Key& k, const std::vector<Param>& ps, int sign, const std::array<double, 4>* start, FaceRule rule) {
    std::mt19937 rng(static_cast<unsigned>(std::hash<std::string>{}(code_of(k)) & 0xffffffffu) + static_cast<unsigned>(sign + 1));
    const auto obj = [&](const std::array<double, 4>& x) { return extreme_cos(k, ps, x, sign, rule); };
    Witness w;
    double fb = -3;
    const int n = start ? 0 : 48;
    if (start) w.x = *start, fb = obj(w.x);
    for (int s = 0; s < n; ++s) {
        std::array<double, 4> x{};
        for (std::size_t i = 0; i < ps.size(); ++i) {
            const int corner = std::uniform_int_distribution<int>(0, 3)(rng);
            const double r = corner == 0 ? 0 : corner == 1 ? 1 : std::uniform_real_distribution<double>(0, 1)(rng);
            x[i] = snap(ps[i].lo + r * (ps[i].hi - ps[i].lo), ps[i]);
        }
        const double f = obj(x);
        if (f > fb) fb = f, w.x = x;
    }
    for (double step = 0.25; step > 0x1p-24; step *= 0.5)
        for (bool improved = true; improved;) {
            improved = false;
            for (std::size_t i = 0; i < ps.size(); ++i)
                for (double d : {-1.0, 1.0}) {
                    std::array<double, 4> x = w.x;
                    x[i] = snap(x[i] + d * step * (ps[i].hi - ps[i].lo), ps[i]);
                    const double f = obj(x);
                    if (f > fb + 1e-15) fb = f, w.x = x, improved = true;
                }
        }
    w.cos = (sign == -1 ? -1 : 1) * fb;
    return w;
}

// The claim cos² c + 2 sqrt(c (1 − c)) δ + δ² (δ the margin in radians:
// dc/dθ = −sin 2θ; the δ² keeps a claim at 90 deg provable, where an edge's
// d may vanish identically), rounded up to 2^-40.
double claim_cos2(double cos, double margin_deg) {
    const double c = cos * cos;
    const double d = margin_deg * (3.14159265358979323846 / 180);
    return std::ceil(std::ldexp(c + 2 * std::sqrt(c * (1 - c)) * d + d * d, 40)) / 1099511627776.0;
}

}  // namespace warpmesh::bcc_prover

namespace warpmesh::bcc_prover {

// cos² of each angle (degrees), rounded to a multiple of 2^-40 (the claim is
// stated by these numbers; the degrees are only their names).
Claim cap_claim(double min_deg, double max_deg) {
    const auto c2 = [](double deg) {
        const double c = std::cos(deg * M_PI / 180);
        return std::round(std::ldexp(c * c, 40)) / 1099511627776.0;
    };
    return {c2(min_deg), c2(max_deg), 1};
}

namespace {

// A key's claim (cos²) for a witness with this cos and margin: the witness's
// angle moved outward by the margin, or the cap when that is as loose or the
// cap lies within `tight_deg` of the witness (the keys at the theorem's
// extremes then claim the theorem's round values, and stay tight).
double key_claim(double cos, double margin_deg, double cap, double tight_deg) {
    return cap <= claim_cos2(cos, std::max(margin_deg, tight_deg)) ? cap : claim_cos2(cos, margin_deg);
}

// Where a failure points the witness: the failed box's centre (on the grid).
// Delaunay: the failed box may straddle a tie, where the rule's stencil
// changes and the extreme lies on the tie (a face quad's or the inside
// quad's forms vanish there), which a coordinate-wise pattern search does not
// follow; the box's corners (on the grid) are probed too, and the most
// extreme of these points is taken (a corner on the side where the stencil
// that failed is chosen).
std::array<double, 4> fail_probe(const Key& k, const std::vector<Param>& ps, const KeyProof& p, int sign, FaceRule rule) {
    std::array<double, 4> x{};
    for (std::size_t i = 0; i < ps.size(); ++i) x[i] = snap(p.fail_point[i], ps[i]);
    if (rule == FaceRule::parity) return x;
    double best = extreme_cos(k, ps, x, sign, rule);
    for (unsigned c = 0; c < 1u << ps.size(); ++c) {
        std::array<double, 4> y{};
        for (std::size_t i = 0; i < ps.size(); ++i) y[i] = snap((c >> i & 1u) ? p.fail_box.hi[i] : p.fail_box.lo[i], ps[i]);
        const double f = extreme_cos(k, ps, y, sign, rule);
        if (f > best) best = f, x = y;
    }
    return x;
}

}  // namespace

KeyProof prove_key_tight(const Key& k, const bcc::Alphas& al, Margins mg, int max_depth, FaceRule rule) {
    const std::vector<Param> ps = key_params(k, al);
    // Per kind j: 0 the smallest dihedral angle, 1 the largest, 2 the
    // smallest face angle; `sign` as in extreme_cos, `dir` +1 where a larger
    // cos is more extreme.
    const int sign[3] = {1, -1, 2}, dir[3] = {1, -1, 1};
    Witness w[3] = {search_witness(k, ps, 1, nullptr, rule), search_witness(k, ps, -1, nullptr, rule),
                    search_witness(k, ps, 2, nullptr, rule)};
    const double start[3] = {mg.min_deg, mg.max_deg, mg.face_deg};
    double margin[3] = {mg.min_deg, mg.max_deg, mg.face_deg};
    long budget = mg.budget;
    const auto widen = [&](int j) { margin[j] = std::min(2 * margin[j], 64 * start[j]); };
    KeyProof p;
    for (int attempt = 0; attempt < 32; ++attempt) {
        // A largest angle below 90 deg (cos > 0) is claimed as 90 deg + the
        // margin; no claim is looser than the caps.
        const Claim c{key_claim(w[0].cos, margin[0], mg.cap.cmin, mg.tight_min_deg),
                      key_claim(std::min(w[1].cos, 0.0), margin[1], mg.cap.cmax, mg.tight_max_deg),
                      key_claim(w[2].cos, margin[2], mg.cap.cface, mg.tight_min_deg)};
        // No budget once a margin reached 64 times its start: prove or fail.
        bool last = false;
        for (int j = 0; j < 3; ++j) last = last || margin[j] >= 64 * start[j];
        p = prove_key(k, al, c, max_depth, last ? 1L << 40 : budget, rule);
        p.claim = c, p.wmin = w[0], p.wmax = w[1], p.wface = w[2];
        if (p.ok || p.fail_kind == 0) return p;
        if (p.fail_kind == 3) {
            // Over budget: first every margin to twice its start (still
            // within tight), then the budget doubles up to max_budget, then
            // the margin that caused most splits doubles (and any other that
            // caused at least a quarter as many).
            const long f[3] = {p.split_fails[1], p.split_fails[2], p.split_fails[4]};
            const long most = std::max({f[0], f[1], f[2]});
            if (margin[0] < 2 * start[0] && margin[1] < 2 * start[1] && margin[2] < 2 * start[2]) widen(0), widen(1), widen(2);
            else if (budget < mg.max_budget) budget *= 2;
            else
                for (int j = 0; j < 3; ++j)
                    if (4 * f[j] >= most) widen(j);
            continue;
        }
        const int j = p.fail_kind == 4 ? 2 : p.fail_kind - 1;
        const std::array<double, 4> x = fail_probe(k, ps, p, sign[j], rule);
        if (dir[j] * witness_cos(k, ps, x, sign[j], rule) > dir[j] * w[j].cos + 1e-12)
            w[j] = search_witness(k, ps, sign[j], &x, rule);
        else if (margin[j] < 64 * start[j]) widen(j);
        else break;  // nothing left to change
    }
    // Last resort: the caps themselves, no budget.
    p = prove_key(k, al, mg.cap, max_depth, 1L << 40, rule);
    p.claim = mg.cap, p.wmin = w[0], p.wmax = w[1], p.wface = w[2];
    return p;
}

}  // namespace warpmesh::bcc_prover
