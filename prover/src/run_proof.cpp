// run_proof.cpp — the 2D proof driver: the targets (sampled extremes, not
// part of the proof), the exact rational witnesses, rigorous degrees for the
// log, and the certificate text: run_proof drives key enumeration (keys.cpp)
// and branch and bound (bound.cpp) in passes — sample_keys, set_targets,
// prove_keys (first_pass, second_pass per key) — and writes what they proved
// (write_claim, write_key, write_leaf; format: proofs/README.md).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iomanip>
#include <sstream>

#include <boost/multiprecision/cpp_int.hpp>

#include "warpmesh/mesh2d/square_keys.hpp"
#include "warpmesh/key_progress.hpp"
#include "warpmesh/prove.hpp"

namespace warpmesh {

using Q = boost::multiprecision::cpp_rational;

// Exact rationals, for witnesses.
template <>
struct ScalarOps<Q> {
    static Q from_int(int v) { return Q(v); }
    static Truth positive(const Q& a) { return truth(a > 0); }
    static Truth less(const Q& a, const Q& b) { return truth(a < b); }
    static Q max(const Q& a, const Q& b) { return a < b ? b : a; }
};

namespace prover {
namespace {

// ---- double evaluation (targets and witnesses) ---------------------------------
struct PointEval {
    bool valid = true;
    double qmin = -1e300;  // largest cot among the chosen triangles' angles
    double qmax = 1e300;   // smallest cot
    int diag = 0;
};

PointEval eval_double(DiagonalRule rule, const Key& k, const std::array<double, 4>& t) {
    std::array<Warp, 4> w{};
    for (int c = 0; c < 4; ++c) w[c] = k.s[c].warp;
    const auto p = generic_positions<double>(w, t);
    const Choice ch = choose_key_diagonal<double>(rule, p, k);
    PointEval e;
    const Diagonal d = ch.ad ? Diagonal::AD : Diagonal::BC;
    e.diag = ch.fan ? 4 : ch.ad ? 1 : 2;
    const auto fp = fan_points(p);
    std::vector<std::array<Point<double>, 3>> tris;
    if (ch.fan)
        for (const auto& tri : fan_triangles) tris.push_back({fp[tri[0]], fp[tri[1]], fp[tri[2]]});
    else
        for (const auto& tri : diagonal_triangles(d)) tris.push_back({p[tri[0]], p[tri[1]], p[tri[2]]});
    for (const auto& tri : tris) {
        const auto f = triangle_forms(tri[0], tri[1], tri[2], k.metric);
        if (!(f.cross > 0)) {
            e.valid = false;
            continue;
        }
        for (double dot : f.dot) {
            e.qmin = std::max(e.qmin, dot / f.cross);
            e.qmax = std::min(e.qmax, dot / f.cross);
        }
    }
    return e;
}

struct Extreme {
    double value;
    std::array<double, 4> t;  // indexed by corner
};

// Pattern search (coordinate steps of h, halved when nothing improves) that
// maximises value(t) from e.  `ridges`: where no coordinate step improves,
// also steps of h in 16 directions of each plane of two coordinates (the
// rhombic metric: its max-min extremes lie on switching surfaces
// q(AD) = q(BC) that run obliquely to the axes, where coordinate steps stall
// below the maximum — key -L-R-R+D stalled at r 7.0 and 7.54, its maximum is
// 7.6056).  The square metric keeps the coordinate steps alone (its
// certificates unchanged).
template <class F>
Extreme climb(const F& value, const std::vector<int>& vars, Extreme e, double h, bool ridges = false) {
    const int m = static_cast<int>(vars.size());
    auto step = [&](int j, double dj, int l, double dl, bool& improved) {
        std::array<double, 4> t = e.t;
        t[vars[j]] = std::clamp(t[vars[j]] + dj * h, 0.0, 0.5);
        if (l >= 0) t[vars[l]] = std::clamp(t[vars[l]] + dl * h, 0.0, 0.5);
        const double v = value(t);
        if (v > e.value) e = {v, t}, improved = true;
    };
    while (h > 1e-13 && m > 0) {
        bool improved = false;
        for (int j = 0; j < m; ++j)
            for (int s : {-1, 1}) step(j, s, -1, 0, improved);
        for (int j = 0; ridges && !improved && j < m; ++j)
            for (int l = j + 1; l < m; ++l)
                for (int a = 1; a < 16; ++a)
                    if (a != 4 && a != 8 && a != 12) step(j, std::cos(a * 0.39269908169872414), l, std::sin(a * 0.39269908169872414), improved);
        if (!improved) h *= 0.5;
    }
    return e;
}

// Grid sampling, then pattern search from the best grid points.  `sense` = +1
// maximises qmin, -1 minimises qmax.  Not part of the proof: it only picks targets.
Extreme search(DiagonalRule rule, const Key& k, const std::vector<int>& vars, int sense, bool* invalid,
               std::array<double, 4>* invalid_at) {
    const int m = static_cast<int>(vars.size());
    auto value = [&](const std::array<double, 4>& t) {
        const PointEval e = eval_double(rule, k, t);
        if (!e.valid) {
            if (invalid && !*invalid) *invalid = true, *invalid_at = t;
            return 1e300;
        }
        return sense > 0 ? e.qmin : -e.qmax;
    };
    const int n = m <= 1 ? 65 : m == 2 ? 33 : m == 3 ? 13 : 7;
    std::vector<Extreme> best;
    std::array<int, 4> idx{};
    for (;;) {
        std::array<double, 4> t{};
        for (int j = 0; j < m; ++j) t[vars[j]] = 0.5 * idx[j] / (n - 1);
        best.push_back({value(t), t});
        int j = 0;
        while (j < m && ++idx[j] == n) idx[j++] = 0;
        if (j == m) break;
    }
    std::sort(best.begin(), best.end(), [](const Extreme& a, const Extreme& b) { return a.value > b.value; });
    best.resize(std::min<std::size_t>(best.size(), 4));
    Extreme top = best[0];
    for (Extreme e : best) {
        e = climb(value, vars, e, 0.5 / (n - 1), k.metric == LatticeMetric::rhombic);
        if (e.value > top.value) top = e;
    }
    if (sense < 0) top.value = -top.value;
    return top;
}

// Pattern search from the point t0 (used when a proof attempt finds a point
// more extreme than the sampled one).
Extreme search_from(DiagonalRule rule, const Key& k, const std::vector<int>& vars, int sense,
                    const std::array<double, 4>& t0) {
    auto value = [&](const std::array<double, 4>& t) {
        const PointEval e = eval_double(rule, k, t);
        if (!e.valid) return -1e300;
        return sense > 0 ? e.qmin : -e.qmax;
    };
    Extreme top = climb(value, vars, Extreme{value(t0), t0}, 1.0 / 64, k.metric == LatticeMetric::rhombic);
    if (sense < 0) top.value = -top.value;
    return top;
}

// ---- exact rationals for the log and the certificate --------------------------
std::string qstr(const Q& q) {
    std::ostringstream s;
    s << q;
    return s.str();
}
Q dyadic(double x) {  // exact value of a double
    int e = 0;
    const double f = std::frexp(x, &e);
    const auto n = static_cast<long long>(std::ldexp(f, 53));
    Q r(n);
    e -= 53;
    const Q two(2);
    if (e >= 0) {
        for (int i = 0; i < e; ++i) r *= 2;
    } else {
        boost::multiprecision::cpp_int den = 1;
        den <<= -e;
        r /= Q(den);
    }
    return r;
}
std::string dstr(double x) { return qstr(dyadic(x)); }

// Rigorous enclosure of atan(y), y >= 0, by the alternating Taylor series after
// reduction to |z| <= sqrt(2)-1; pi by Machin's formula.
std::pair<Q, Q> atan_series(const Q& z) {  // |z| < 1/2
    Q sum = 0, pw = z, z2 = z * z;
    for (int n = 0; n < 40; ++n) {
        sum += (n % 2 ? -pw : pw) / (2 * n + 1);
        pw *= z2;
    }
    Q err = abs(pw) / 81;
    return {sum - err, sum + err};
}
std::pair<Q, Q> pi_enc() {
    auto a = atan_series(Q(1, 5)), b = atan_series(Q(1, 239));
    return {16 * a.first - 4 * b.second, 16 * a.second - 4 * b.first};
}
// Angle in degrees whose cotangent is c, as an enclosure.
std::pair<Q, Q> angle_of_cot(const Q& c) {
    const auto pi = pi_enc();
    if (c == 0) return {Q(90), Q(90)};
    const Q y = 1 / abs(c);  // atan(y) in (0, pi/2)
    std::pair<Q, Q> a;       // enclosure of atan(y)/pi
    if (y <= Q(2, 5)) {
        auto s = atan_series(y);
        a = {s.first / pi.second, s.second / pi.first};
    } else if (y <= Q(5, 2)) {
        auto s = atan_series((y - 1) / (y + 1));  // atan(y) = pi/4 + atan((y-1)/(y+1))
        a = {Q(1, 4) + std::min(s.first / pi.second, s.first / pi.first),
             Q(1, 4) + std::max(s.second / pi.first, s.second / pi.second)};
    } else {
        auto s = atan_series(1 / y);  // atan(y) = pi/2 - atan(1/y)
        a = {Q(1, 2) - s.second / pi.first, Q(1, 2) - s.first / pi.second};
    }
    if (c > 0) return {180 * a.first, 180 * a.second};
    return {180 - 180 * a.second, 180 - 180 * a.first};
}
std::string dec(const Q& q, bool up, int digits = 10) {
    boost::multiprecision::cpp_int scale = 1;
    for (int i = 0; i < digits; ++i) scale *= 10;
    const Q s = q * Q(scale);
    boost::multiprecision::cpp_int n = numerator(s) / denominator(s);  // truncation toward 0
    if (Q(n) > s) n -= 1;
    if (up && Q(n) < s) n += 1;
    const bool neg = n < 0;
    if (neg) n = -n;
    std::string d = n.str();
    while (static_cast<int>(d.size()) <= digits) d = "0" + d;
    return (neg ? "-" : "") + d.substr(0, d.size() - digits) + "." + d.substr(d.size() - digits);
}
// The angle whose form ratio is c (square: c = cot; rhombic: c = sqrt(3) cot,
// with sqrt 3 in [97/56, 1351/780], the angle is between those of c / (1351/780)
// and c / (97/56)), as an enclosure in degrees.  Log only.
std::string deg_range(const Q& c, LatticeMetric metric = LatticeMetric::square) {
    auto e = angle_of_cot(c);
    if (metric == LatticeMetric::rhombic) {
        const auto a = angle_of_cot(c / Q(1351, 780)), b = angle_of_cot(c / Q(97, 56));
        e = {std::min(a.first, b.first), std::max(a.second, b.second)};
    }
    return "[" + dec(e.first, false) + ", " + dec(e.second, true) + "] deg";
}

struct ExactEval {
    Q qmin, qmax;
    bool valid = true;
    int diag = 0;
};
ExactEval eval_exact(DiagonalRule rule, const Key& k, const std::array<Q, 4>& t) {
    std::array<Warp, 4> w{};
    for (int c = 0; c < 4; ++c) w[c] = k.s[c].warp;
    const auto p = generic_positions<Q>(w, t);
    const Choice ch = choose_key_diagonal<Q>(rule, p, k);
    ExactEval e;
    e.diag = ch.fan ? 4 : ch.ad ? 1 : 2;
    bool first = true;
    const auto fp = fan_points(p);
    std::vector<std::array<Point<Q>, 3>> tris;
    if (ch.fan)
        for (const auto& tri : fan_triangles) tris.push_back({fp[tri[0]], fp[tri[1]], fp[tri[2]]});
    else
        for (const auto& tri : diagonal_triangles(ch.ad ? Diagonal::AD : Diagonal::BC))
            tris.push_back({p[tri[0]], p[tri[1]], p[tri[2]]});
    for (const auto& tri : tris) {
        const auto f = triangle_forms(tri[0], tri[1], tri[2], k.metric);
        if (f.cross <= 0) e.valid = false;
        for (const Q& dot : f.dot) {
            if (f.cross == 0) continue;
            const Q c = dot / f.cross;
            if (first || c > e.qmin) e.qmin = c;
            if (first || c < e.qmax) e.qmax = c;
            first = false;
        }
    }
    return e;
}

std::array<Q, 4> to_dyadic_t(const std::array<double, 4>& t);
// The 3^m points t0 + {-1, 0, 1} 2^-30 per variable (clamped to [0, 1/2]).
std::vector<std::array<double, 4>> neighbours(const std::array<double, 4>& t0, const std::vector<int>& vars) {
    int combos = 1;
    for (std::size_t j = 0; j < vars.size(); ++j) combos *= 3;
    std::vector<std::array<double, 4>> out;
    for (int cmb = 0; cmb < combos; ++cmb) {
        std::array<double, 4> t = t0;
        int r = cmb;
        for (int v : vars) {
            t[v] = std::clamp(t[v] + (r % 3 - 1) * std::ldexp(1.0, -30), 0.0, 0.5);
            r /= 3;
        }
        out.push_back(t);
    }
    return out;
}
// The rational witness: the dyadic point (2^-40 grid) nearest the sampled
// extreme, or a neighbour at distance 2^-30 per coordinate if the rule's exact
// choice there gives a more extreme value (the extreme may sit on a switch).
std::pair<std::array<Q, 4>, ExactEval> witness(DiagonalRule rule, const Key& k, const std::array<double, 4>& t0,
                                               int sense) {
    std::pair<std::array<Q, 4>, ExactEval> best{to_dyadic_t(t0), eval_exact(rule, k, to_dyadic_t(t0))};
    if (best.second.valid && best.second.diag == eval_double(rule, k, t0).diag) return best;
    for (const auto& t : neighbours(t0, key_vars(k))) {
        const auto tq = to_dyadic_t(t);
        const ExactEval e = eval_exact(rule, k, tq);
        if (!e.valid) continue;
        if ((sense > 0 && e.qmin > best.second.qmin) || (sense < 0 && e.qmax < best.second.qmax)) best = {tq, e};
    }
    return best;
}
// An exact witness of an inverted or degenerate chosen triangle (cross <= 0)
// near the double point t0 where sampling met one: the 2^-40 grid point
// nearest t0, or a neighbour at 2^-30 per coordinate.  False if none is
// exactly inverted (then the key is a failure, not a counter-example).
bool inverted_witness(DiagonalRule rule, const Key& k, const std::array<double, 4>& t0, std::array<Q, 4>& out) {
    std::vector<std::array<double, 4>> pts{t0};
    for (const auto& t : neighbours(t0, key_vars(k))) pts.push_back(t);
    for (const auto& t : pts)
        if (!eval_exact(rule, k, to_dyadic_t(t)).valid) {
            out = to_dyadic_t(t);
            return true;
        }
    return false;
}

std::array<Q, 4> to_dyadic_t(const std::array<double, 4>& t) {
    std::array<Q, 4> r;
    for (int c = 0; c < 4; ++c) r[c] = dyadic(std::ldexp(std::nearbyint(std::ldexp(t[c], 40)), -40));
    return r;
}

double round_down(double x, int bits) { return std::ldexp(std::floor(std::ldexp(x, bits)), -bits); }
double q_up(const Q& q, int bits) {  // smallest multiple of 2^-bits that is >= q
    const Q s = q * Q(boost::multiprecision::cpp_int(1) << bits);
    boost::multiprecision::cpp_int n = numerator(s) / denominator(s);
    if (Q(n) < s) n += 1;
    return std::ldexp(n.convert_to<double>(), -bits);
}
double q_down(const Q& q, int bits) { return -q_up(-q, bits); }
// Angle between the cotangents a <= b, in degrees (for the log only): the
// angles are arccot a >= arccot b, and arccot a - arccot b = atan((b - a)/(1 + a b))
// when 1 + a b > 0.
double gap_deg(double a, double b, LatticeMetric metric) {
    if (metric == LatticeMetric::rhombic) a /= 1.7320508075688772, b /= 1.7320508075688772;  // cot = r / sqrt 3
    return (1 + a * b > 0 ? std::atan((b - a) / (1 + a * b)) : 3.14159265358979 - std::atan((b - a) / -(1 + a * b))) *
           180 / 3.14159265358979;
}

// ---- the proof driver: its passes -------------------------------------------------
// One key's state through the passes.
struct Info {
    bool flat = false, invalid = false, relaxed = false;
    std::array<double, 4> invalid_at{};  // where sampling met an inverted triangle (double)
    bool inverted_exact = false;         // and an exact witness of it, at tinv
    std::array<Q, 4> tinv{};
    Extreme emin{}, emax{};
    // Exact witnesses of the key's extremes (rational t), and their values.
    std::array<Q, 4> tmin{}, tmax{};
    ExactEval wmin{}, wmax{};
    double qmin = 0, qmax = 0;  // the key's claim (targets until proved)
    KeyProof proof;
};
// Per category (0 = U any, 1 = F flat): the keys of the extreme witnesses and
// of the first inverted triangle, and the category's targets.
struct Cat {
    int wmin = -1, wmax = -1, winv = -1;
    double qmin = 0, qmax = 0, qmax_loose = 0;
};
// One proof: the rule over the keys all[ids[i]].  Junction keys with the same
// warps and the same forced diagonal (or none) have the same configurations and
// the same decisions — the rule sees the materials only through the forcing —
// hence the same targets and proof: each is computed once, for the first key of
// its class (rep), and copied; the output is the same as computing every key.
struct Proof {
    DiagonalRule rule;
    bool junctions;  // no flat category (proofs/README.md, "Junction keys")
    LatticeMetric metric;
    std::vector<Key> all;
    std::vector<int> ids, rep;
    std::vector<Info> info;
    Cat cat[2];
    int n() const { return static_cast<int>(ids.size()); }
    int ncat() const { return junctions ? 1 : 2; }
    const Key& key(int i) const { return all[static_cast<std::size_t>(ids[static_cast<std::size_t>(i)])]; }
    Info& at(int i) { return info[static_cast<std::size_t>(i)]; }
    const Info& at(int i) const { return info[static_cast<std::size_t>(i)]; }
    bool computed(int i) const { return !junctions || rep[static_cast<std::size_t>(i)] == i; }
    void copy_classes() {
        for (int i = 0; i < n(); ++i)
            if (!computed(i)) at(i) = at(rep[static_cast<std::size_t>(i)]);
    }
};

// Targets.  Per key: the exact value at its witness plus a margin worth `gap`
// degrees at that cot: d(angle)/d(cot) = -1/(1+cot^2), and the margin moves
// the cot away from 0, so the angle gap is at most margin/(1+cot^2) radians.
constexpr double gap_min = 0.004, gap_max = 0.08;  // min angle, max angle (deg)
// In the rhombic metric the claims are on r = s cot (s = sqrt 3): dr/d(angle) =
// -s (1 + cot^2), the same margin with cot = r / s, times s.
double margin(const Q& c, double gap, LatticeMetric metric) {
    const double s = metric == LatticeMetric::rhombic ? 1.7320508075688772 : 1.0;
    const double x = c.convert_to<double>() / s;
    return round_down(gap * (3.14159265358979 / 180) * (1 + x * x) * s, 40);
}

// The progress line's name for a pass over p's keys (key_progress.hpp).
std::string progress_name(const Proof& p, const char* pass) {
    return std::string("warpmesh prove: ") + rule_name(p.rule) + (p.junctions ? " (junctions)" : "") + ": " + pass;
}

// Pass 1 (not part of the proof): each key's sampled extremes and their exact
// witnesses; a key on which sampling meets an inverted triangle gets an exact
// witness of it instead, if there is one.
void sample_keys(Proof& p) {
    const int n = p.n();
    KeyProgress progress(progress_name(p, "sampling"), n);
#pragma omp parallel for schedule(dynamic, 1)
    for (int i = 0; i < n; ++i) {
        progress.tick();
        if (!p.computed(i)) continue;
        const Key& k = p.key(i);
        Info& f = p.at(i);
        f.flat = !p.junctions && flat_compatible(k);
        const auto vars = key_vars(k);
        f.emin = search(p.rule, k, vars, +1, &f.invalid, &f.invalid_at);
        f.emax = search(p.rule, k, vars, -1, nullptr, nullptr);
        if (f.invalid) {
            f.inverted_exact = inverted_witness(p.rule, k, f.invalid_at, f.tinv);
            continue;
        }
        std::tie(f.tmin, f.wmin) = witness(p.rule, k, f.emin.t, 1);
        std::tie(f.tmax, f.wmax) = witness(p.rule, k, f.emax.t, -1);
    }
    p.copy_classes();
}

// Pass 2: the category targets — the worst witness plus a tiny margin caps the
// keys close to it, so that the theorems U and F are tight — and each key's
// first targets.
void set_targets(Proof& p) {
    for (int c = 0; c < p.ncat(); ++c) {
        Cat& cat = p.cat[c];
        for (int i = 0; i < p.n(); ++i) {
            const Info& f = p.at(i);
            if (c == 1 && !f.flat) continue;
            if (f.invalid) {
                if (cat.winv < 0 && f.inverted_exact) cat.winv = i;
                continue;
            }
            if (cat.wmin < 0 || f.wmin.qmin > p.at(cat.wmin).wmin.qmin) cat.wmin = i;
            if (cat.wmax < 0 || f.wmax.qmax < p.at(cat.wmax).wmax.qmax) cat.wmax = i;
        }
        if (cat.wmin < 0) continue;
        // 2^-33 (F) resp. 2^-24 (U) above the worst min-angle witness: < 1e-9
        // resp. 1e-6 deg; 2^-33 resp. 2^-20 below the worst max-angle witness.
        const int bits = c == 1 ? 33 : 24, mbits = c == 1 ? 33 : 20;
        cat.qmin = q_up(p.at(cat.wmin).wmin.qmin, bits + 3) + std::ldexp(1.0, -bits);
        cat.qmax = q_down(p.at(cat.wmax).wmax.qmax, mbits + 3) - std::ldexp(1.0, -mbits);
        cat.qmax_loose = c == 1 ? cat.qmax : q_down(p.at(cat.wmax).wmax.qmax, 40) - 0.125;
        // The fan rule: where the rule may take either the fan or a diagonal
        // (leaf Y), a taken diagonal is only known to have q <= fan_taken_cot.
        if (p.rule == DiagonalRule::fan) cat.qmin = std::max(cat.qmin, fan_taken_cot);
    }
    for (int i = 0; i < p.n(); ++i) {
        Info& f = p.at(i);
        if (f.invalid) continue;
        const Cat& c = p.cat[f.flat ? 1 : 0];
        const LatticeMetric metric = p.key(i).metric;
        f.qmin = std::min(q_up(f.wmin.qmin, 40) + margin(f.wmin.qmin, gap_min, metric), c.qmin);
        // First-pass max-angle claims: the previous loose ones (sample minus
        // 0.25 (1 + |cot|), keys that are not flat-compatible at most cot -3/2).
        const double v = f.wmax.qmax.convert_to<double>();
        f.qmax = std::max(round_down(v - 0.25 * (1 + std::fabs(v)), 16), c.qmax_loose);
        if (!f.flat) f.qmax = std::min(f.qmax, metric == LatticeMetric::rhombic ? -2.5 : -1.5);  // r: about sqrt 3 times
    }
}

// A proof attempt failed on the max angle at `at`: if that point is more
// extreme than the key's witness, the witness moves to the extreme found by a
// pattern search from it.
void move_max_witness(DiagonalRule rule, const Key& key, Info& f, const std::array<double, 4>& at) {
    const PointEval e = eval_double(rule, key, at);
    if (!(e.valid && e.qmax < f.wmax.qmax.convert_to<double>())) return;
    const Extreme x = search_from(rule, key, key_vars(key), -1, at);
    const auto w = witness(rule, key, x.t, -1);
    if (w.second.valid && w.second.qmax < f.wmax.qmax) std::tie(f.tmax, f.wmax) = w;
}

// Pass 3a, one key: prove its targets.  A claim that cannot be certified
// within the leaf budget is relaxed (and reported as such): the certificate
// only ever states what was proved.  A failure at a point more extreme than
// the witness means the sampling missed the key's extreme: the witness moves
// there (pattern search from that point) and the target follows it.  Returns
// the number of attempts.
int first_pass(DiagonalRule rule, const Key& key, Info& f, std::size_t leaf_budget, double qmin_cap) {
    const auto vars = key_vars(key);
    double gmin = gap_min;
    int attempts = 0;
    for (int attempt = 0; attempt < 10; ++attempt) {
        ++attempts;
        f.proof = prove_key(rule, key, f.qmin, f.qmax, leaf_budget);
        if (f.proof.ok) break;
        // Fan rule, a square that may take the fan: undecided leaves (Y) need
        // qmin >= fan_taken_cot; try that before relaxing further.
        if (fan_key(rule, key) && f.qmin < fan_taken_cot) {
            f.qmin = fan_taken_cot;
            f.relaxed = true;
            continue;
        }
        const PointEval e = eval_double(rule, key, f.proof.fail_point);
        if (f.proof.fail_kind == 1) {
            bool moved = false;
            if (e.valid && e.qmin > f.wmin.qmin.convert_to<double>()) {
                const Extreme x = search_from(rule, key, vars, +1, f.proof.fail_point);
                const auto w = witness(rule, key, x.t, 1);
                if (w.second.valid && w.second.qmin > f.wmin.qmin) std::tie(f.tmin, f.wmin) = w, moved = true;
            }
            // The rhombic metric: a witness that moved resets the claim to it
            // plus the first margin (the failure was the witness's, not the
            // margin's: the proof bisects to the target's level set, where
            // e.qmin > f.qmin is a matter of rounding).
            // Below the category's cap (the worst witness + 2^-24 or 2^-33) the
            // target is capped there, as the first targets are.
            const bool reset = moved && key.metric == LatticeMetric::rhombic;
            if (!(e.valid && e.qmin > f.qmin) && !reset) gmin *= 4;
            double q = q_up(f.wmin.qmin, 40) + margin(f.wmin.qmin, gmin, key.metric);
            if (reset && q_up(f.wmin.qmin, 40) < qmin_cap) q = std::min(q, qmin_cap);
            f.qmin = std::max(f.qmin, q);
        } else if (f.proof.fail_kind == 2) {
            move_max_witness(rule, key, f, f.proof.fail_point);
            const double step = 1e-3 * std::pow(4.0, attempt);
            f.qmax = round_down(std::min({f.qmax, e.valid ? e.qmax : f.qmax, f.wmax.qmax.convert_to<double>()}) -
                                    step * (1 + std::fabs(f.qmax)),
                                24);
        } else {
            break;  // orientation cannot be certified: reported as a failure
        }
        f.relaxed = true;
    }
    return attempts;
}

// Pass 3b, one proved key: tighter max-angle claims, each tried within a leaf
// budget of 3x the first proof's leaves + 200, the first proved kept: the
// witness minus gap_max, then minus 1 deg (neither tighter than the category's
// tight cap `cap`, which keeps the theorem tight), the cap itself, and for
// keys whose witness is at the cap, the witness minus 0.25 deg and minus 1 deg.
// Along the max-min switching surfaces these need switching leaves (bound.cpp).
// Keys at the cap first try 0.02, 0.05 and 0.1 deg below their witness (with a
// larger budget: their maximum may lie on a curve, where the boxes must be
// about sqrt(margin) wide along it).
void second_pass(DiagonalRule rule, const Key& key, Info& f, double cap) {
    const std::size_t budget = static_cast<std::size_t>(3.0 * static_cast<double>(f.proof.leaves.size())) + 200;
    std::vector<double> tried;
    for (double g : {gap_max, 1.0, -1.0, -0.02, -0.05, -0.1, -0.25, -1.0 - 1e-9}) {
        const double w = q_down(f.wmax.qmax, 40);
        const double q = g == -1.0 ? cap
                         : g < 0   ? w - margin(f.wmax.qmax, -g, key.metric)
                                   : std::max(w - margin(f.wmax.qmax, g, key.metric), cap);
        if (q <= f.qmax) break;
        const bool near_cap = g < 0 && g > -0.25 && g != -1.0;
        if (near_cap && q >= cap) continue;
        if (std::find(tried.begin(), tried.end(), q) != tried.end()) continue;
        tried.push_back(q);
        KeyProof p = prove_key(rule, key, f.qmin, q, budget + (near_cap ? 2000 : 0));
        if (p.ok) {
            f.proof = std::move(p), f.qmax = q;
            return;
        }
        if (p.fail_kind == 2) move_max_witness(rule, key, f, p.fail_point);
    }
}

// Pass 3, every key (the branch and bound): first and second pass.
void prove_keys(Proof& p) {
    const double cap[2] = {p.cat[0].qmax, p.cat[1].qmax};
    const bool verbose = std::getenv("WARPMESH_PROVE_VERBOSE") != nullptr;
    const std::size_t leaf_budget = std::getenv("WARPMESH_LEAF_BUDGET") ? std::atol(std::getenv("WARPMESH_LEAF_BUDGET")) : 3000;
    const int n = p.n();
    KeyProgress progress(progress_name(p, "proving"), n);
#pragma omp parallel for schedule(dynamic, 1)
    for (int i = 0; i < n; ++i) {
        Info& f = p.at(i);
        if (f.invalid || !p.computed(i)) {
            progress.tick();
            continue;
        }
        const auto k0 = std::chrono::steady_clock::now();
        const Key& key = p.key(i);
        const int attempts = first_pass(p.rule, key, f, leaf_budget, p.cat[f.flat ? 1 : 0].qmin);
        if (f.proof.ok) second_pass(p.rule, key, f, cap[f.flat ? 1 : 0]);
        const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - k0).count();
        if (verbose && (dt > 0.05 || f.relaxed))
            std::fprintf(stderr, "key %d %s: %.2f s, %d attempts, %zu leaves, ok %d, targets %.12g %.12g (witnesses %.12g %.12g)\n",
                         p.ids[static_cast<std::size_t>(i)], code_of(key).c_str(), dt, attempts, f.proof.leaves.size(),
                         f.proof.ok, f.qmin, f.qmax, f.wmin.qmin.convert_to<double>(), f.wmax.qmax.convert_to<double>());
        progress.tick();
    }
    p.copy_classes();
    // The category witnesses, after any witness moved.
    for (int c = 0; c < p.ncat(); ++c)
        for (int i = 0; i < p.n(); ++i) {
            const Info& f = p.at(i);
            if (f.invalid || (c == 1 && !f.flat)) continue;
            if (f.wmin.qmin > p.at(p.cat[c].wmin).wmin.qmin) p.cat[c].wmin = i;
            if (f.wmax.qmax < p.at(p.cat[c].wmax).wmax.qmax) p.cat[c].wmax = i;
        }
}

// ---- the certificate text -------------------------------------------------------------
void write_t(std::ostream& o, const Key& k, const std::array<Q, 4>& t) {
    for (int v : key_vars(k)) o << ' ' << qstr(t[v]);
}
// Category c's claim — the extremes of its keys' claims, or `inverted` with an
// exact witness — and its witnesses; the log states it in degrees.
void write_claim(const Proof& p, int c, std::ostream& o, std::ostream& lg) {
    const char* rname = rule_name(p.rule);
    double cq = -1e300, cp = 1e300;
    bool any_inv = false;
    for (const Info& f : p.info) {
        if (c == 1 && !f.flat) continue;
        if (f.invalid) {
            any_inv = true;
            continue;
        }
        cq = std::max(cq, f.qmin), cp = std::min(cp, f.qmax);
    }
    const char* cn = c ? "F" : "U";
    const Cat& cat = p.cat[c];
    if (any_inv) {
        o << "claim " << cn << " inverted\n";
        if (cat.winv >= 0) {
            o << "witness " << cn << " inverted " << code_of(p.key(cat.winv));
            write_t(o, p.key(cat.winv), p.at(cat.winv).tinv);
            o << "\n";
        }
        lg << rname << " (" << cn << "): orientation FAILS"
           << (cat.winv >= 0 ? ", e.g. key " + code_of(p.key(cat.winv)) : std::string(" (no exact witness)")) << "\n";
        return;
    }
    if (cat.wmin < 0) return;  // a key subset without keys of this category
    o << "claim " << cn << " " << dstr(cq) << " " << dstr(cp) << "\n";
    const Key &kmin = p.key(cat.wmin), &kmax = p.key(cat.wmax);
    const Info &fmin = p.at(cat.wmin), &fmax = p.at(cat.wmax);
    o << "witness " << cn << " min " << code_of(kmin);
    write_t(o, kmin, fmin.tmin);
    o << " " << qstr(fmin.wmin.qmin) << "\n";
    o << "witness " << cn << " max " << code_of(kmax);
    write_t(o, kmax, fmax.tmax);
    o << " " << qstr(fmax.wmax.qmax) << "\n";
    const LatticeMetric mt = kmin.metric;
    const char* cot = mt == LatticeMetric::rhombic ? "r" : "cot";  // r = dot / cross = sqrt(3) cot
    lg << rname << " (" << cn << "): min angle >= " << deg_range(dyadic(cq), mt) << " (" << cot << " <= " << dstr(cq)
       << "), witness " << code_of(kmin) << " has " << cot << " " << std::setprecision(17)
       << fmin.wmin.qmin.convert_to<double>() << " = " << deg_range(fmin.wmin.qmin, mt) << "; gap in " << cot << " "
       << (dyadic(cq) - fmin.wmin.qmin).convert_to<double>() << "\n";
    lg << rname << " (" << cn << "): max angle <= " << deg_range(dyadic(cp), mt) << " (" << cot << " >= " << dstr(cp)
       << "), witness " << code_of(kmax) << " has " << cot << " " << fmax.wmax.qmax.convert_to<double>() << " = "
       << deg_range(fmax.wmax.qmax, mt) << "; gap in " << cot << " " << (fmax.wmax.qmax - dyadic(cp)).convert_to<double>()
       << "\n";
}
// One leaf line: tag, k, the box, a threshold's H, a switching certificate.
void write_leaf(std::ostream& o, const Leaf& l, const KeyProof& proof, int m) {
    o << (l.sw >= 0 ? 'S' : l.diag == 4 ? 'F' : l.diag == 5 ? 'Y' : l.threshold != 0 ? "ab"[l.diag - 1] : "ABX"[l.diag - 1]) << ' ' << l.k;
    for (int j = 0; j < 2 * m; ++j) o << ' ' << l.num[static_cast<std::size_t>(j)];
    if (l.threshold != 0) o << ' ' << dstr(l.threshold);
    if (l.sw >= 0) {  // the switching certificate, per diagonal: - or k:J:J2:mask and the multipliers
        const Switch& sw = proof.switches[static_cast<std::size_t>(l.sw)];
        for (int d = 0; d < 2; ++d) {
            if (sw.k[d] < 0) {
                o << " -";
                continue;
            }
            auto idx = [&](int v) { return v < 0 ? std::string("-") : std::to_string(v); };
            int mask = 0;
            for (int x = 0; x < 6; ++x)
                if (sw.lambda[static_cast<std::size_t>(12 * d + x)] >= 0 && sw.j[2 * d] >= 0) mask |= 1 << x;
            o << ' ' << int{sw.k[d]} << ':' << idx(sw.j[2 * d]) << ':' << idx(sw.j[2 * d + 1]) << ':' << mask;
            for (int n = 0; n < 2; ++n)
                for (int x = 0; x < 6; ++x)
                    if (sw.j[2 * d + n] >= 0 && (mask >> x & 1)) o << ' ' << dstr(sw.lambda[static_cast<std::size_t>(12 * d + 6 * n + x)]);
        }
    }
    o << "\n";
}
// Key i: its line, its witnesses and its leaves; or `inverted` and its exact
// witness `winv`.  A key without a proof (or an inverted one without an exact
// witness) is written as such and logged FAILED: the checker rejects it.
void write_key(const Proof& p, int i, std::ostream& o, std::ostream& lg) {
    const Info& f = p.at(i);
    const Key& k = p.key(i);
    const int m = static_cast<int>(key_vars(k).size());
    o << "key " << p.ids[static_cast<std::size_t>(i)] << ' ' << code_of(k) << ' ' << f.flat << ' ' << m;
    if (f.invalid) {
        o << " inverted\n";
        if (f.inverted_exact) {
            o << "winv";
            write_t(o, k, f.tinv);
            o << "\n";
        } else {
            lg << "FAILED key " << code_of(k) << ": an inverted triangle sampled in double, no exact witness\n";
        }
        return;
    }
    o << ' ' << dstr(f.qmin) << ' ' << dstr(f.qmax) << ' ' << (f.proof.ok ? f.proof.leaves.size() : 0) << "\n";
    // The key's witnesses: exact configurations close to its bounds.
    o << "wmin";
    write_t(o, k, f.tmin);
    o << ' ' << qstr(f.wmin.qmin) << "\nwmax";
    write_t(o, k, f.tmax);
    o << ' ' << qstr(f.wmax.qmax) << "\n";
    if (!f.proof.ok) {
        lg << "FAILED key " << code_of(k) << " qmin " << f.qmin << " qmax " << f.qmax << " at";
        for (double x : f.proof.fail_point) lg << ' ' << x;
        const auto e = eval_double(p.rule, k, f.proof.fail_point);
        lg << " (there: qmin " << e.qmin << " qmax " << e.qmax << ")\n";
        return;
    }
    for (const Leaf& l : f.proof.leaves) write_leaf(o, l, f.proof, m);
}
// Per-key tightness (for the log; the checker recomputes it exactly).
std::string tightness_log(const Proof& p) {
    std::vector<double> gmin, gmax;
    for (const Info& f : p.info) {
        if (f.invalid || !f.proof.ok) continue;
        const double a = f.wmin.qmin.convert_to<double>(), b = f.wmax.qmax.convert_to<double>();
        gmin.push_back(gap_deg(a, f.qmin, p.metric));
        gmax.push_back(gap_deg(f.qmax, b, p.metric));
    }
    auto summary = [](std::vector<double> g, double tol) {
        std::sort(g.begin(), g.end());
        std::ostringstream s;
        if (g.empty()) return std::string("none");
        s << "median " << g[g.size() / 2] << " deg, max " << g.back() << " deg, "
          << g.end() - std::upper_bound(g.begin(), g.end(), tol) << " keys above " << tol;
        return s.str();
    };
    return std::string(rule_name(p.rule)) + ": per-key gap to the witness, min angle: " + summary(gmin, 0.01) +
           "; max angle: " + summary(gmax, 0.1) + "\n";
}

}  // namespace

// ---------------------------------------------------------------------------
std::string run_proof(DiagonalRule rule, const std::vector<int>* key_subset, std::string* log, KeySpace space,
                      LatticeMetric metric) {
    const auto t0 = std::chrono::steady_clock::now();
    Proof p{rule, space == KeySpace::junctions, metric, {}, {}, {}, {}, {}};
    p.all = p.junctions ? junction_keys() : consistent_keys();
    for (Key& k : p.all) k.metric = metric;
    if (key_subset) p.ids = *key_subset;
    else
        for (int i = 0; i < static_cast<int>(p.all.size()); ++i) p.ids.push_back(i);
    p.info.resize(p.ids.size());
    if (p.junctions) p.rep = junction_classes(rule, p.all, p.ids);
    sample_keys(p);
    set_targets(p);
    const auto t1 = std::chrono::steady_clock::now();
    if (std::getenv("WARPMESH_PROVE_VERBOSE"))
        std::fprintf(stderr, "targets: U %.17g %.17g  F %.17g %.17g  (%.2f s)\n", p.cat[0].qmin, p.cat[0].qmax, p.cat[1].qmin,
                     p.cat[1].qmax, std::chrono::duration<double>(t1 - t0).count());
    prove_keys(p);
    const auto t2 = std::chrono::steady_clock::now();

    std::ostringstream o, lg;
    const char* rname = rule_name(rule);
    // Format 3: the square metric (no metric line, as before); format 4 adds
    // the metric line, so that a checker of format 3 refuses a rhombic
    // certificate instead of reading its bounds on r as cotangents.
    if (metric == LatticeMetric::square)
        o << "warpmesh-certificate 3\n"
          << "# Angle bounds for the generic square, diagonal rule " << rname << ".  Format: proofs/README.md.\n";
    else
        o << "warpmesh-certificate 4\n"
          << "# Angle bounds for the generic square in the rhombic lattice's metric, diagonal rule " << rname
          << "; claims on r = dot/cross = sqrt(3) cot(angle).  Format: proofs/README.md.\n"
          << "metric " << metric_name(metric) << "\n";
    o << "rule " << rname << "\n";
    if (p.junctions) o << "space junctions\n";
    for (int c = 0; c < p.ncat(); ++c) write_claim(p, c, o, lg);
    o << "keys " << p.n() << "\n";
    for (int i = 0; i < p.n(); ++i) write_key(p, i, o, lg);
    o << "end\n";
    lg << tightness_log(p);
    std::size_t leaves = 0, failed = 0, inverted = 0;
    for (const Info& f : p.info) leaves += f.proof.leaves.size(), failed += !f.invalid && !f.proof.ok, inverted += f.invalid;
    lg << rname << ": " << p.n() << " keys, " << leaves << " leaves, " << failed << " failed, " << inverted
       << " with inverted triangles; targets " << std::chrono::duration<double>(t1 - t0).count() << " s, branch and bound "
       << std::chrono::duration<double>(t2 - t1).count() << " s\n";
    if (log) *log += lg.str();
    return o.str();
}

}  // namespace prover
}  // namespace warpmesh
