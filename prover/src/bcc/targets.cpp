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

// cos of the extreme angle over the tetrahedra of stencil st at the points
// pts: the largest cos of a dihedral angle (smallest angle, sign = +1) or the
// smallest (largest angle, sign = −1), as +cos resp. −cos so that larger is
// more extreme; sign = 2: the largest cos of a face angle.
template <std::size_t N>
double tets_extreme(const bcc::OutTet* tets, int count, const std::array<bcc::Vec<double>, N>& pts, int sign) {
    double best = -2;
    for (int j = 0; j < count; ++j) {
        std::array<bcc::Vec<double>, 4> p{};
        for (int v = 0; v < 4; ++v) p[static_cast<std::size_t>(v)] = pts[tets[j][static_cast<std::size_t>(v)]];
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
double stencil_extreme(const bcc::Stencil& st, const std::array<bcc::Vec<double>, 10>& pts, int sign) {
    return tets_extreme(st.tet.data(), st.count, pts, sign);
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

namespace {
// The cos of the extreme angle (stencil_extreme's) over the subject's output
// at x: a junction face's cone tetrahedra, or the key's stencil under its
// rule there.
double extreme_cos(const Subject& s, const std::array<double, 4>& x, int sign) {
    std::array<double, 4> t{};
    std::array<double, 6> u{};
    split_params(s.ps, x.data(), t, u);
    if (s.junction) return tets_extreme(s.tets.data(), static_cast<int>(s.tets.size()), subject_points(s, t, u), sign);
    if (s.a15_class >= 0) {
        const auto p15 = subject_points(s, t, u);
        std::array<bcc::Vec<double>, 10> p{};
        std::copy(p15.begin(), p15.begin() + 10, p.begin());
        return stencil_extreme(a15_stencil_at(s, x.data()), p, sign);
    }
    return stencil_extreme(stencil_at(s.key, s.ps, x.data(), s.rule), key_points(s.key, s.ps, x.data()), sign);
}
}  // namespace

double subject_witness_cos(const Subject& s, const std::array<double, 4>& x, int sign) {
    return (sign == -1 ? -1 : 1) * extreme_cos(s, x, sign);
}

double witness_cos(const Key& k, const std::vector<Param>& ps, const std::array<double, 4>& x, int sign, FaceRule rule) {
    Subject s;
    s.key = k, s.ps = ps, s.rule = rule;
    return subject_witness_cos(s, x, sign);
}

namespace {

// Pattern search from x (value fb of obj): steps of `from` down to `to` times
// each side's width, on the 2^-24 grid.
template <class F>
void pattern_search(const F& obj, const std::vector<Param>& ps, std::array<double, 4>& x, double& fb, double from, double to) {
    for (double step = from; step > to; step *= 0.5)
        for (bool improved = true; improved;) {
            improved = false;
            for (std::size_t i = 0; i < ps.size(); ++i)
                for (double d : {-1.0, 1.0}) {
                    std::array<double, 4> y = x;
                    y[i] = snap(y[i] + d * step * (ps[i].hi - ps[i].lo), ps[i]);
                    const double f = obj(y);
                    if (f > fb + 1e-15) fb = f, x = y, improved = true;
                }
        }
}

// A tie of the Delaunay rule as a function of the other parameters: `onto`
// moves parameter ib of x onto it (false if that leaves its box).
//   A face quad's: face_form = L_b (1 − u_b) − L_a (1 − u_a) (u_x the cut
//   fraction on xr from x, L_x = |xr|²) vanishes where
//   u_b = 1 − (L_a / L_b)(1 − u_a); ia, ib the parameters of the edges ar,
//   br, from_a, from_b whether they count from a (b).
//   The prism's inside quad's (n− = 2, n+ = 2): inside_form, quadratic in
//   each cut fraction, vanishes on it; ib is solved for by bisection on the
//   part of its box on either side of x[ib] whose ends the form's sign
//   separates (the root nearer x first).
struct Tie {
    std::size_t ia = 0, ib = 0;
    bool from_a = true, from_b = true;
    double la = 0, lb = 0;
    std::array<int, 4> prism{-1, -1, -1, -1};  // a, b, r0, r1: the inside quad's tie
    bool onto(const std::vector<Param>& ps, std::array<double, 4>& x) const {
        if (prism[0] < 0) {
            const double ua = from_a ? x[ia] : 1 - x[ia];
            const double ub = 1 - la / lb * (1 - ua);
            x[ib] = from_b ? ub : 1 - ub;
            return x[ib] >= ps[ib].lo && x[ib] <= ps[ib].hi;
        }
        const auto g = [&](double s) {
            std::array<double, 4> y = x, t{};
            std::array<double, 6> u{};
            y[ib] = s;
            split_params(ps, y.data(), t, u);
            return bcc::inside_form(prism[0], prism[1], prism[2], prism[3], u);
        };
        const double mid = x[ib];
        for (auto [lo, hi] : {std::pair{ps[ib].lo, mid}, std::pair{mid, ps[ib].hi}}) {
            const bool neg_lo = g(lo) < 0;
            if (neg_lo == (g(hi) < 0)) continue;
            for (int it = 0; it < 80 && lo < hi; ++it) {
                const double m = 0.5 * (lo + hi);
                if (m <= lo || m >= hi) break;
                ((g(m) < 0) == neg_lo ? lo : hi) = m;
            }
            x[ib] = 0.5 * (lo + hi);
            return true;
        }
        return false;
    }
};
std::vector<Tie> delaunay_ties(const Key& k, const std::vector<Param>& ps) {
    std::vector<Tie> out;
    for (int f = 0, a, b, r; f < 4; ++f) {
        if (!quad_face(k, f, a, b, r)) continue;
        Tie t;
        for (std::size_t i = 0; i < ps.size(); ++i)
            for (const int x : {a, b}) {
                const int e = bcc::edge_index(x, r);
                if (e < 0 || ps[i].index != 4 + e) continue;
                const bool from = bcc::tet_edges[static_cast<std::size_t>(e)][0] == x;
                const double len2 = bcc::edge_is_long(e) ? 4 : 3;
                (x == a ? t.ia : t.ib) = i, (x == a ? t.from_a : t.from_b) = from, (x == a ? t.la : t.lb) = len2;
            }
        out.push_back(t);
    }
    int a = -1, b = -1, r0 = -1, r1 = -1;
    if (inside_quad(k, a, b, r0, r1))  // the prism's inside quad: solved for each of its four cut fractions in turn
        for (std::size_t i = 0; i < ps.size(); ++i) {
            Tie t;
            t.ib = i, t.prism = {a, b, r0, r1};
            out.push_back(t);
        }
    return out;
}

// Delaunay: the extreme may lie on a tie (a face quad's or the prism's
// inside quad's, delaunay_ties), where the rule's stencil changes — approached from the side whose stencil is worse, while
// the tie itself may take the other (parity's) diagonal — and a
// coordinate-wise search stops at a tie instead of following it.  So, per
// tie, the search is repeated on its tie (one parameter solved for),
// with the extreme over both of its diagonals there (the stencils admitted
// on a box of half-width 2^-30 around the point): from the three best of
// the starts and w, moved onto the tie; the point found is then moved off the
// tie by 1, 2, 4 or 8 grid steps either way (parameter ib) to the most
// extreme of the rule's own values, on the worse side.  Returns the best of
// those and w (value fb).
Witness follow_ties(const Subject& sub, int sign, std::vector<std::array<double, 4>> starts, Witness w, double fb) {
    const Key& k = sub.key;
    const std::vector<Param>& ps = sub.ps;
    starts.push_back(w.x);
    for (const Tie& tie : delaunay_ties(k, ps)) {
        const auto on_tie = [&](std::array<double, 4> y) {
            if (!tie.onto(ps, y)) return -3.0;
            Box b;
            b.m = static_cast<int>(ps.size());
            for (std::size_t i = 0; i < ps.size(); ++i) b.lo[i] = y[i] - 0x1p-30, b.hi[i] = y[i] + 0x1p-30;
            double best = -2;
            const auto pts = key_points(k, ps, y.data());
            for (const bcc::Stencil& st : admissible_stencils(k, ps, b)) best = std::max(best, stencil_extreme(st, pts, sign));
            return best;
        };
        std::vector<std::pair<double, std::size_t>> order;
        for (std::size_t s = 0; s < starts.size(); ++s) order.emplace_back(on_tie(starts[s]), s);
        std::stable_sort(order.begin(), order.end(), [](const auto& x, const auto& y) { return x.first > y.first; });
        for (std::size_t s = 0; s < std::min<std::size_t>(3, order.size()) && order[s].first > -3; ++s) {
            std::array<double, 4> x = starts[order[s].second];
            double f = order[s].first;
            pattern_search(on_tie, ps, x, f, 0.25, 0x1p-24);
            tie.onto(ps, x);
            for (double d : {-8.0, -4.0, -2.0, -1.0, 1.0, 2.0, 4.0, 8.0}) {
                std::array<double, 4> y = x;
                y[tie.ib] = snap(x[tie.ib] + d * 0x1p-24, ps[tie.ib]);
                const double g = extreme_cos(sub, y, sign);
                if (g > fb + 1e-15) fb = g, w.x = y;
            }
        }
    }
    w.cos = (sign == -1 ? -1 : 1) * fb;
    return w;
}

// An A15 key's extreme may sit at an exact tie on the boundary of its box,
// realised there only (`1:+,-,-,+`'s largest angle: at the corner where its
// two face quads and its inside quad all tie, a15_stencil_at), which no
// point of the 2^-24 grid reaches: the 2^m corners of the exact box (every
// parameter at the nearest double of an exact end; a15_stencil_at decides
// the rule there in exact rationals) are tried too.  Corners only: a point
// mixing the grid's 2^-24 with the ends' denominator would need more digits
// than the checker's fixed 768 bits hold.
void try_exact_corners(const Subject& sub, int sign, Witness& w, double& fb) {
    const std::size_t m = sub.ps.size();
    for (std::size_t c = 0; c < (std::size_t{1} << m); ++c) {
        std::array<double, 4> y{};
        for (std::size_t i = 0; i < m; ++i) y[i] = (c >> i) & 1 ? sub.ps[i].hi : sub.ps[i].lo;
        const double f = extreme_cos(sub, y, sign);
        if (f > fb + 1e-15) fb = f, w.x = y;
    }
}

}  // namespace

// Random starts (corners and faces favoured) and a shrinking-step pattern
// search on the 2^-24 grid, from `start` if given (Delaunay: then the face
// quads' ties followed, follow_ties).
Witness search_witness(const Key& k, const std::vector<Param>& ps, int sign, const std::array<double, 4>* start, FaceRule rule) {
    Subject s;
    s.key = k, s.ps = ps, s.rule = rule, s.seed = code_of(k);
    return search_subject(s, sign, start);
}

Witness search_subject(const Subject& sub, int sign, const std::array<double, 4>* start) {
    const std::vector<Param>& ps = sub.ps;
    std::mt19937 rng(static_cast<unsigned>(std::hash<std::string>{}(sub.seed) & 0xffffffffu) + static_cast<unsigned>(sign + 1));
    const auto obj = [&](const std::array<double, 4>& x) { return extreme_cos(sub, x, sign); };
    Witness w;
    double fb = -3;
    const int n = start ? 0 : 48;
    std::vector<std::array<double, 4>> starts;
    if (start) w.x = *start, fb = obj(w.x), starts.push_back(*start);
    for (int s = 0; s < n; ++s) {
        std::array<double, 4> x{};
        for (std::size_t i = 0; i < ps.size(); ++i) {
            const int corner = std::uniform_int_distribution<int>(0, 3)(rng);
            const double r = corner == 0 ? 0 : corner == 1 ? 1 : std::uniform_real_distribution<double>(0, 1)(rng);
            x[i] = snap(ps[i].lo + r * (ps[i].hi - ps[i].lo), ps[i]);
        }
        starts.push_back(x);
        const double f = obj(x);
        if (f > fb) fb = f, w.x = x;
    }
    pattern_search(obj, ps, w.x, fb, 0.25, 0x1p-24);
    if (sub.a15_class >= 0) try_exact_corners(sub, sign, w, fb);
    w.cos = (sign == -1 ? -1 : 1) * fb;
    return !sub.junction && sub.a15_class < 0 && sub.rule == FaceRule::delaunay ? follow_ties(sub, sign, std::move(starts), w, fb) : w;
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
Claim cap_claim(double min_deg, double max_deg, double face_deg) {
    const auto c2 = [](double deg) {
        const double c = std::cos(deg * M_PI / 180);
        return std::round(std::ldexp(c * c, 40)) / 1099511627776.0;
    };
    return {c2(min_deg), c2(max_deg), c2(face_deg)};  // cos 0 = 1 exactly: no face cap
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
// follow; the box's corners (on the grid) are probed too, and each of these
// points moved by one grid step (2^-24) along every parameter, either way or
// not at all: a box outside the parameters' exact ranges (the root box is
// their dyadic enclosure) snaps onto a range's end, which may lie on the tie
// itself, where the rule takes the parity diagonal and the worse stencil is
// one step away.  The most extreme of these points is taken.
std::array<double, 4> fail_probe(const Subject& sub, const KeyProof& p, int sign) {
    const std::vector<Param>& ps = sub.ps;
    std::array<double, 4> x{};
    for (std::size_t i = 0; i < ps.size(); ++i) x[i] = snap(p.fail_point[i], ps[i]);
    if (sub.junction || sub.rule == FaceRule::parity) return x;
    std::vector<std::array<double, 4>> points{x};
    for (unsigned c = 0; c < 1u << ps.size(); ++c) {
        std::array<double, 4> y{};
        for (std::size_t i = 0; i < ps.size(); ++i) y[i] = snap((c >> i & 1u) ? p.fail_box.hi[i] : p.fail_box.lo[i], ps[i]);
        points.push_back(y);
    }
    double best = extreme_cos(sub, x, sign);
    unsigned steps = 1;
    for (std::size_t i = 0; i < ps.size(); ++i) steps *= 3;
    for (const auto& y0 : points)
        for (unsigned d = 0; d < steps; ++d) {
            std::array<double, 4> y = y0;
            for (unsigned i = 0, e = d; i < ps.size(); ++i, e /= 3) y[i] = snap(y[i] + (static_cast<double>(e % 3) - 1) * 0x1p-24, ps[i]);
            const double f = extreme_cos(sub, y, sign);
            if (f > best) best = f, x = y;
        }
    return x;
}

}  // namespace

KeyProof prove_key_tight(const Key& k, const bcc::Alphas& al, Margins mg, int max_depth, FaceRule rule) {
    return prove_subject_tight(region_subject(k, al, rule), mg, max_depth);
}

KeyProof prove_subject_tight(const Subject& sub, Margins mg, int max_depth) { return prove_tight({sub}, mg, max_depth)[0]; }

std::vector<KeyProof> prove_tight(const std::vector<Subject>& subs, Margins mg, int max_depth) {
    // Per kind j: 0 the smallest dihedral angle, 1 the largest, 2 the
    // smallest face angle; `sign` as in extreme_cos, `dir` +1 where a larger
    // cos is more extreme.  w[i][j]: subject i's witness; the claim is made
    // from the most extreme subject's (ext(j), the first on ties).
    const int sign[3] = {1, -1, 2}, dir[3] = {1, -1, 1};
    const std::size_t n = subs.size();
    std::vector<std::array<Witness, 3>> w(n);
    for (std::size_t i = 0; i < n; ++i)
        for (int j = 0; j < 3; ++j) w[i][static_cast<std::size_t>(j)] = search_subject(subs[i], sign[j]);
    const auto ext = [&](int j) {
        std::size_t e = 0;
        for (std::size_t i = 1; i < n; ++i)
            if (dir[j] * w[i][static_cast<std::size_t>(j)].cos > dir[j] * w[e][static_cast<std::size_t>(j)].cos) e = i;
        return w[e][static_cast<std::size_t>(j)];
    };
    const double start[3] = {mg.min_deg, mg.max_deg, mg.face_deg};
    double margin[3] = {mg.min_deg, mg.max_deg, mg.face_deg};
    long budget = mg.budget;
    const auto widen = [&](int j) { margin[j] = std::min(2 * margin[j], 64 * start[j]); };
    std::vector<KeyProof> p(n);
    const auto prove_all = [&](const Claim& c, long leaves) {  // the first subject that fails, or n
        for (std::size_t i = 0; i < n; ++i) {
            p[i] = prove_subject(subs[i], c, max_depth, leaves);
            p[i].claim = c, p[i].wmin = w[i][0], p[i].wmax = w[i][1], p[i].wface = w[i][2];
            if (!p[i].ok) return i;
        }
        return n;
    };
    for (int attempt = 0; attempt < 32; ++attempt) {
        // A largest angle below 90 deg (cos > 0) is claimed as 90 deg + the
        // margin; no claim is looser than the caps.
        const Claim c{key_claim(ext(0).cos, margin[0], mg.cap.cmin, mg.tight_min_deg),
                      key_claim(std::min(ext(1).cos, 0.0), margin[1], mg.cap.cmax, mg.tight_max_deg),
                      key_claim(ext(2).cos, margin[2], mg.cap.cface, mg.tight_min_deg)};
        // No budget once a margin reached 64 times its start: prove or fail.
        bool last = false;
        for (int j = 0; j < 3; ++j) last = last || margin[j] >= 64 * start[j];
        const std::size_t f = prove_all(c, last ? 1L << 40 : budget);
        if (f == n || p[f].fail_kind == 0) return p;
        if (p[f].fail_kind == 3) {
            // Over budget: first every margin to twice its start (still
            // within tight), then the budget doubles up to max_budget, then
            // the margin that caused most splits doubles (and any other that
            // caused at least a quarter as many).
            const long fk[3] = {p[f].split_fails[1], p[f].split_fails[2], p[f].split_fails[4]};
            const long most = std::max({fk[0], fk[1], fk[2]});
            if (margin[0] < 2 * start[0] && margin[1] < 2 * start[1] && margin[2] < 2 * start[2]) widen(0), widen(1), widen(2);
            else if (budget < mg.max_budget) budget *= 2;
            else
                for (int j = 0; j < 3; ++j)
                    if (4 * fk[j] >= most) widen(j);
            continue;
        }
        // A failure at a point more extreme than the failed subject's witness
        // moves that witness there; unless that makes it the most extreme, the
        // margin doubles.
        const int j = p[f].fail_kind == 4 ? 2 : p[f].fail_kind - 1;
        const auto J = static_cast<std::size_t>(j);
        const double before = ext(j).cos;
        const std::array<double, 4> x = fail_probe(subs[f], p[f], sign[j]);
        if (dir[j] * subject_witness_cos(subs[f], x, sign[j]) > dir[j] * w[f][J].cos + 1e-12) w[f][J] = search_subject(subs[f], sign[j], &x);
        if (dir[j] * ext(j).cos > dir[j] * before + 1e-12) continue;
        if (margin[j] < 64 * start[j]) widen(j);
        else break;  // nothing left to change
    }
    // Last resort: the caps themselves, no budget.
    prove_all(mg.cap, 1L << 40);
    return p;
}

}  // namespace warpmesh::bcc_prover
