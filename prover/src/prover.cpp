// prover.cpp — certifies angle bounds of the generic square, box by box, by
// running generic_square.hpp's own code with outward-rounded intervals.
// See proofs/README.md for the configuration space, the theorems and the
// certificate format.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include <boost/multiprecision/cpp_int.hpp>
#include <boost/numeric/interval.hpp>
#ifdef _OPENMP
#include <omp.h>
#endif

#include "warpmesh/prove.hpp"

namespace warpmesh {

namespace ia = boost::numeric::interval_lib;
using I = boost::numeric::interval<
    double, ia::policies<ia::save_state<ia::rounded_arith_std<double>>, ia::checking_base<double>>>;
using Q = boost::multiprecision::cpp_rational;

// Intervals: `less` and `positive` answer yes/no only when decided on the whole
// box.  `less` further demands a relative margin of 1e-9: where the prover says
// "decided", the exact values differ by more than 1e-9 relative, so the
// mesher's double evaluation (within a few ulps of the exact value) takes the
// same diagonal.  An empty interval (NaN ends, from a division by [0,0]) is
// never decided.
template <>
struct ScalarOps<I> {
    static I from_int(int v) { return I(static_cast<double>(v)); }
    static bool bad(const I& a) { return std::isnan(a.lower()) || std::isnan(a.upper()); }
    static Truth positive(const I& a) {
        if (bad(a)) return Truth::maybe;
        if (a.lower() > 0) return Truth::yes;
        if (a.upper() <= 0) return Truth::no;
        return Truth::maybe;
    }
    static Truth less(const I& a, const I& b) {
        if (bad(a) || bad(b)) return Truth::maybe;
        const double mag = std::max({std::fabs(a.lower()), std::fabs(a.upper()), std::fabs(b.lower()),
                                     std::fabs(b.upper())});
        const double m = 1e-9 * mag;  // >= 0; fl(x + m) >= x, so the tests below imply the exact ones
        if (a.upper() + m < b.lower()) return Truth::yes;
        if (a.lower() >= b.upper() + m) return Truth::no;
        return Truth::maybe;
    }
    static I max(const I& a, const I& b) {
        if (bad(a) || bad(b)) return I::whole();
        return boost::numeric::max(a, b);
    }
};

// Exact rationals, for witnesses.
template <>
struct ScalarOps<Q> {
    static Q from_int(int v) { return Q(v); }
    static Truth positive(const Q& a) { return truth(a > 0); }
    static Truth less(const Q& a, const Q& b) { return truth(a < b); }
    static Q max(const Q& a, const Q& b) { return a < b ? b : a; }
};

// Forward-mode dual numbers over intervals: value and the partial derivatives
// with respect to the (at most 4) t variables.  Positions are affine in t, the
// angle forms quadratic; only + - * are needed.
struct DI {
    I v;
    std::array<I, 4> d;
};
inline DI operator+(const DI& a, const DI& b) {
    DI r{a.v + b.v, {}};
    for (int i = 0; i < 4; ++i) r.d[i] = a.d[i] + b.d[i];
    return r;
}
inline DI operator-(const DI& a, const DI& b) {
    DI r{a.v - b.v, {}};
    for (int i = 0; i < 4; ++i) r.d[i] = a.d[i] - b.d[i];
    return r;
}
inline DI operator*(const DI& a, const DI& b) {
    DI r{a.v * b.v, {}};
    for (int i = 0; i < 4; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
    return r;
}
template <>
struct ScalarOps<DI> {
    static DI from_int(int v) { return DI{I(static_cast<double>(v)), {I(0.), I(0.), I(0.), I(0.)}}; }
};

namespace prover {
namespace {

constexpr char warp_char[5] = {'s', 'R', 'L', 'U', 'D'};

CornerState state_of(int st) {
    if (st == 0) return {0, Warp::stay};
    return {static_cast<std::int8_t>(st <= 5 ? -1 : 1), static_cast<Warp>((st - 1) % 5)};
}

// Corner reached from corner c by the slide w, or -1 when the slide is outward.
int inward_target(int c, Warp w) {
    const int x = (c & 1) + warp_dx(w), y = (c >> 1) + warp_dy(w);
    if (w == Warp::stay || x < 0 || x > 1 || y < 0 || y > 1) return -1;
    return x + 2 * y;
}

bool consistent(const Key& k) {
    for (int c = 0; c < 4; ++c) {
        const CornerState s = k.s[c];
        if (s.sign == 0 && s.warp != Warp::stay) return false;  // zero corners stay
        if (s.warp == Warp::stay) continue;
        const int n = inward_target(c, s.warp);
        if (n >= 0) {
            if (k.s[n].sign != -s.sign) return false;             // slides only along a cut edge
            if (inward_target(n, k.s[n].warp) == c) return false;  // never towards each other
        }
    }
    // Every cut edge of the square has a warped endpoint.
    constexpr int edges[4][2] = {{A, B}, {B, D}, {D, C}, {C, A}};
    for (const auto& e : edges) {
        const CornerState a = k.s[e[0]], b = k.s[e[1]];
        if (a.sign != 0 && b.sign == -a.sign && a.warp == Warp::stay && b.warp == Warp::stay) return false;
    }
    return true;
}

// ---- flat stencil patterns ---------------------------------------------------
// Stencil point 0..3 = corner c at (c&1, c>>1); 4 + 2c + a = the lattice
// neighbour of corner c outside the square along axis a (0 = x, 1 = y).
struct P2 {
    long x, y;
};
std::array<P2, 12> stencil() {
    std::array<P2, 12> p{};
    for (int c = 0; c < 4; ++c) {
        const long cx = c & 1, cy = c >> 1;
        p[c] = {cx, cy};
        p[4 + 2 * c] = {cx == 0 ? -1 : 2, cy};
        p[4 + 2 * c + 1] = {cx, cy == 0 ? -1 : 2};
    }
    return p;
}
int outward_index(int c, Warp w) { return 4 + 2 * c + (warp_dy(w) != 0 ? 1 : 0); }

using Pattern = std::array<std::int8_t, 12>;
int sgn(long v) { return (v > 0) - (v < 0); }

// Every sign vector of an affine function on the 12 points.  A non-constant
// affine function's zero line either passes through >= 2 stencil points (then
// it is +-L for the line L through a pair), or through exactly one point p_i
// (rotating it about p_i changes nothing until it meets another point, so it
// is a small rotation of a line through p_i and some p_j), or through none
// (translating it changes nothing until it meets a point, so its signs are
// those of a line of the first two kinds with every zero replaced by one
// common sign).  Constants give all +, all -, all 0.
const std::set<Pattern>& flat_patterns() {
    static const std::set<Pattern> pats = [] {
        std::set<Pattern> out;
        const auto p = stencil();
        auto add_with_shifts = [&](const Pattern& s) {
            out.insert(s);
            for (int z : {-1, 1}) {
                Pattern t = s;
                for (auto& v : t)
                    if (v == 0) v = static_cast<std::int8_t>(z);
                out.insert(t);
            }
        };
        for (int v : {-1, 0, 1}) {
            Pattern s;
            s.fill(static_cast<std::int8_t>(v));
            out.insert(s);
        }
        for (int i = 0; i < 12; ++i)
            for (int j = 0; j < 12; ++j) {
                if (i == j) continue;
                const long dx = p[j].x - p[i].x, dy = p[j].y - p[i].y;
                for (int o : {-1, 1}) {
                    Pattern base{};
                    for (int k = 0; k < 12; ++k)
                        base[k] = static_cast<std::int8_t>(o * sgn(dx * (p[k].y - p[i].y) - dy * (p[k].x - p[i].x)));
                    add_with_shifts(base);
                    for (int e : {-1, 1}) {  // rotate slightly about p_i
                        Pattern r = base;
                        for (int k = 0; k < 12; ++k)
                            if (r[k] == 0 && k != i)
                                r[k] = static_cast<std::int8_t>(e * sgn(dx * (p[k].x - p[i].x) + dy * (p[k].y - p[i].y)));
                        add_with_shifts(r);
                    }
                }
            }
        return out;
    }();
    return pats;
}

// ---- boxes -----------------------------------------------------------------
struct Box {
    int m = 0;
    std::array<double, 4> lo{}, hi{};
};

std::array<Point<I>, 4> positions_i(const Key& k, const std::vector<int>& vars, const Box& b) {
    std::array<Warp, 4> w{};
    std::array<I, 4> t{I(0.), I(0.), I(0.), I(0.)};
    for (int c = 0; c < 4; ++c) w[c] = k.s[c].warp;
    for (int j = 0; j < b.m; ++j) t[vars[j]] = I(b.lo[j], b.hi[j]);
    return generic_positions<I>(w, t);
}

std::array<Point<DI>, 4> positions_d(const Key& k, const std::vector<int>& vars, const Box& b) {
    std::array<Warp, 4> w{};
    std::array<DI, 4> t{};
    for (int c = 0; c < 4; ++c) {
        w[c] = k.s[c].warp;
        t[c] = ScalarOps<DI>::from_int(0);
    }
    for (int j = 0; j < b.m; ++j) {
        t[vars[j]].v = I(b.lo[j], b.hi[j]);
        t[vars[j]].d[j] = I(1.);
    }
    return generic_positions<DI>(w, t);
}

// Form f of a triangle: 0 = cross (> 0), 1..3 = qmin*cross - dot_i (>= 0),
// 4..6 = dot_i - qmax*cross (>= 0).
DI form(const TriangleForms<DI>& tf, int f, double qmin, double qmax) {
    if (f == 0) return tf.cross;
    const DI qc = ScalarOps<DI>::from_int(0);
    DI c = tf.cross;
    if (f <= 3) {
        DI q = qc;
        q.v = I(qmin);
        return q * c - tf.dot[f - 1];
    }
    DI q = qc;
    q.v = I(qmax);
    return tf.dot[f - 4] - q * c;
}

bool form_ok(const DI& g, int f) { return f == 0 ? g.v.lower() > 0 : g.v.lower() >= 0; }

// Monotonicity reduction: while the form is not proved on the box, every
// variable whose partial derivative has a decided sign on the box is fixed at
// the end where the form is smallest (all fixed at once: each segment stays in
// the box), and the form is re-evaluated on the smaller box.  The checker
// applies the identical procedure with exact rational intervals.
bool verify_form(const Key& k, const std::vector<int>& vars, Box b, const std::array<int, 3>& tri, int f,
                 double qmin, double qmax, DI g) {
    for (;;) {
        if (form_ok(g, f)) return true;
        bool fixed = false;
        for (int j = 0; j < b.m; ++j) {
            if (b.lo[j] == b.hi[j]) continue;
            if (g.d[j].lower() >= 0) b.hi[j] = b.lo[j], fixed = true;
            else if (g.d[j].upper() <= 0) b.lo[j] = b.hi[j], fixed = true;
        }
        if (!fixed) return false;
        const auto p = positions_d(k, vars, b);
        g = form(triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]]), f, qmin, qmax);
    }
}

// Forms f0 <= f < f1 of both triangles of diagonal d.
bool verify_diag(const Key& k, const std::vector<int>& vars, const Box& b, Diagonal d, double qmin, double qmax,
                 int* fail_kind, int f0 = 0, int f1 = 7) {
    const auto p = positions_d(k, vars, b);
    for (const auto& tri : diagonal_triangles(d)) {
        const TriangleForms<DI> tf = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]]);
        for (int f = f0; f < f1; ++f)
            if (!verify_form(k, vars, b, tri, f, qmin, qmax, form(tf, f, qmin, qmax))) {
                *fail_kind = f == 0 ? 0 : f <= 3 ? 1 : 2;
                return false;
            }
    }
    return true;
}

// A second, division-free decision of the max-min rule, used where the header's
// interval evaluation cannot decide because the losing diagonal degenerates
// (its cross product's enclosure contains 0).  `win` is taken on the whole box
// if `win` is valid there and, for some triangle T of the other diagonal and
// some vertex i, dot_i(T) - H cross(T) > 0 on the box (>= 0 when win = AD, the
// tie-break) with H >= q(win): where cross(T) > 0 this gives
// q(other) >= dot_i/cross > H >= q(win) (so the rule takes win), and where
// cross(T) <= 0 the other diagonal is invalid.  H is q(win)'s upper bound
// times (1 + 2^-28), a dyadic recorded in the certificate: the relative margin
// that lets the mesher's double evaluation agree.  Returns H in `thr`.
bool threshold_decides(const Key& k, const std::vector<int>& vars, const Box& b, Diagonal win, double& thr) {
    const auto p = positions_i(k, vars, b);
    double h = -1e300;
    for (const auto& tri : diagonal_triangles(win)) {
        const auto tf = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]]);
        if (!(tf.cross.lower() > 0)) return false;
        for (const I& dot : tf.dot) h = std::max(h, (dot / tf.cross).upper());
    }
    if (!(h > 0) || !std::isfinite(h)) return false;
    {
        int e = 0;
        std::frexp(h, &e);
        h = std::ldexp(std::ceil(std::ldexp(h, 24 - e) * (1 + std::ldexp(1.0, -28))) + 1, e - 24);
    }
    const Diagonal other = win == Diagonal::AD ? Diagonal::BC : Diagonal::AD;
    for (const auto& tri : diagonal_triangles(other)) {
        const auto tf = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]]);
        for (const I& dot : tf.dot) {
            const I g = dot - I(h) * tf.cross;
            if (g.lower() > 0) {
                thr = h;
                return true;
            }
        }
    }
    return false;
}

Leaf make_leaf(const Box& b, int diag) {
    Leaf l;
    l.diag = static_cast<std::uint8_t>(diag);
    int k = 0;
    for (int j = 0; j < b.m; ++j)
        for (double x : {b.lo[j], b.hi[j]}) {
            int e = 0;
            while (x * std::ldexp(1.0, e) != std::floor(x * std::ldexp(1.0, e))) ++e;
            k = std::max(k, e);
        }
    l.k = k;
    for (int j = 0; j < b.m; ++j) {
        l.num[2 * j] = static_cast<std::int64_t>(std::ldexp(b.lo[j], k));
        l.num[2 * j + 1] = static_cast<std::int64_t>(std::ldexp(b.hi[j], k));
    }
    return l;
}

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
    const Choice ch = choose_diagonal<double>(rule, p, k.s);
    PointEval e;
    const Diagonal d = ch.ad ? Diagonal::AD : Diagonal::BC;
    e.diag = ch.ad ? 1 : 2;
    for (const auto& tri : diagonal_triangles(d)) {
        const auto f = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]]);
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
        double h = 0.5 / (n - 1);
        while (h > 1e-13 && m > 0) {
            bool improved = false;
            for (int j = 0; j < m; ++j)
                for (int s : {-1, 1}) {
                    std::array<double, 4> t = e.t;
                    t[vars[j]] = std::clamp(t[vars[j]] + s * h, 0.0, 0.5);
                    const double v = value(t);
                    if (v > e.value) e = {v, t}, improved = true;
                }
            if (!improved) h *= 0.5;
        }
        if (e.value > top.value) top = e;
    }
    if (sense < 0) top.value = -top.value;
    return top;
}

// ---- exact rationals for the report -------------------------------------------
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
std::string deg_range(const Q& cot) {
    const auto e = angle_of_cot(cot);
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
    const Choice ch = choose_diagonal<Q>(rule, p, k.s);
    ExactEval e;
    e.diag = ch.ad ? 1 : 2;
    bool first = true;
    for (const auto& tri : diagonal_triangles(ch.ad ? Diagonal::AD : Diagonal::BC)) {
        const auto f = triangle_forms(p[tri[0]], p[tri[1]], p[tri[2]]);
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
ExactEval eval_exact(DiagonalRule rule, const Key& k, const std::array<Q, 4>& t);
// The rational witness: the dyadic point (2^-40 grid) nearest the sampled
// extreme, or a neighbour at distance 2^-30 per coordinate if the rule's exact
// choice there gives a more extreme value (the extreme may sit on a switch).
std::pair<std::array<Q, 4>, ExactEval> witness(DiagonalRule rule, const Key& k, const std::array<double, 4>& t0,
                                               int sense) {
    const auto vars = key_vars(k);
    std::pair<std::array<Q, 4>, ExactEval> best{to_dyadic_t(t0), eval_exact(rule, k, to_dyadic_t(t0))};
    int combos = 1;
    for (std::size_t j = 0; j < vars.size(); ++j) combos *= 3;
    for (int cmb = 0; cmb < combos; ++cmb) {
        std::array<double, 4> t = t0;
        int r = cmb;
        for (int v : vars) {
            t[v] = std::clamp(t[v] + (r % 3 - 1) * std::ldexp(1.0, -30), 0.0, 0.5);
            r /= 3;
        }
        const auto tq = to_dyadic_t(t);
        const ExactEval e = eval_exact(rule, k, tq);
        if (!e.valid) continue;
        if ((sense > 0 && e.qmin > best.second.qmin) || (sense < 0 && e.qmax < best.second.qmax)) best = {tq, e};
    }
    return best;
}

std::array<Q, 4> to_dyadic_t(const std::array<double, 4>& t) {
    std::array<Q, 4> r;
    for (int c = 0; c < 4; ++c) r[c] = dyadic(std::ldexp(std::nearbyint(std::ldexp(t[c], 40)), -40));
    return r;
}

double round_up(double x, int bits) { return std::ldexp(std::ceil(std::ldexp(x, bits)), -bits); }
double round_down(double x, int bits) { return std::ldexp(std::floor(std::ldexp(x, bits)), -bits); }
double q_up(const Q& q, int bits) {  // smallest multiple of 2^-bits that is >= q
    const Q s = q * Q(boost::multiprecision::cpp_int(1) << bits);
    boost::multiprecision::cpp_int n = numerator(s) / denominator(s);
    if (Q(n) < s) n += 1;
    return std::ldexp(n.convert_to<double>(), -bits);
}
double q_down(const Q& q, int bits) { return -q_up(-q, bits); }

}  // namespace

std::string key_code(const Key& k) {
    std::string s;
    for (int c = 0; c < 4; ++c) {
        s += k.s[c].sign < 0 ? '-' : k.s[c].sign > 0 ? '+' : '0';
        s += warp_char[static_cast<int>(k.s[c].warp)];
    }
    return s;
}

std::vector<Key> consistent_keys() {
    std::vector<Key> out;
    for (int a = 0; a < 11; ++a)
        for (int b = 0; b < 11; ++b)
            for (int c = 0; c < 11; ++c)
                for (int d = 0; d < 11; ++d) {
                    Key k{{state_of(a), state_of(b), state_of(c), state_of(d)}};
                    if (consistent(k)) out.push_back(k);
                }
    return out;
}

std::size_t flat_pattern_count() { return flat_patterns().size(); }

bool flat_compatible(const Key& k) {
    for (const Pattern& p : flat_patterns()) {
        bool ok = true;
        for (int c = 0; c < 4 && ok; ++c) {
            if (p[c] != k.s[c].sign) ok = false;
            const Warp w = k.s[c].warp;
            if (w != Warp::stay && inward_target(c, w) < 0 && p[outward_index(c, w)] != -k.s[c].sign) ok = false;
        }
        if (ok) return true;
    }
    return false;
}

std::vector<int> key_vars(const Key& k) {
    std::vector<int> v;
    for (int c = 0; c < 4; ++c)
        if (k.s[c].warp != Warp::stay) v.push_back(c);
    return v;
}

int interval_choice(DiagonalRule rule, const Key& key, const std::array<double, 4>& lo,
                    const std::array<double, 4>& hi) {
    const auto vars = key_vars(key);
    Box b;
    b.m = static_cast<int>(vars.size());
    b.lo = lo, b.hi = hi;
    const Choice ch = choose_diagonal<I>(rule, positions_i(key, vars, b), key.s);
    return (ch.ad ? 1 : 0) | (ch.bc ? 2 : 0);
}

KeyProof prove_key(DiagonalRule rule, const Key& key, double qmin, double qmax, std::size_t max_leaves) {
    KeyProof out;
    const auto vars = key_vars(key);
    Box root;
    root.m = static_cast<int>(vars.size());
    for (int j = 0; j < root.m; ++j) root.lo[j] = 0, root.hi[j] = 0.5;
    // Depth-first, left half first: the checker rebuilds the same bisection tree
    // (split the widest side, the first one on ties, at its midpoint).
    std::vector<Box> stack{root};
    while (!stack.empty()) {
        const Box b = stack.back();
        stack.pop_back();
        Choice ch = choose_diagonal<I>(rule, positions_i(key, vars, b), key.s);
        double thr = 0;
        if (ch.ad && ch.bc) {
            if (threshold_decides(key, vars, b, Diagonal::BC, thr)) ch.ad = false;
            else if (threshold_decides(key, vars, b, Diagonal::AD, thr)) ch.bc = false;
        }
        bool ok = true;
        int kind = 0;
        if (ch.ad && ch.bc) {
            // Undecided (max-min rule): if one diagonal X is valid with q(X) <= qmin
            // on the box, the rule takes a valid diagonal Y with q(Y) <= q(X) at
            // every point, so orientation and the min angle hold; the max angle is
            // needed on both diagonals (the one taken is valid there).
            ok = verify_diag(key, vars, b, Diagonal::AD, qmin, qmax, &kind, 0, 4) ||
                 verify_diag(key, vars, b, Diagonal::BC, qmin, qmax, &kind, 0, 4);
            ok = ok && verify_diag(key, vars, b, Diagonal::AD, qmin, qmax, &kind, 4, 7) &&
                 verify_diag(key, vars, b, Diagonal::BC, qmin, qmax, &kind, 4, 7);
        } else if (ch.ad) {
            ok = verify_diag(key, vars, b, Diagonal::AD, qmin, qmax, &kind);
        } else {
            ok = verify_diag(key, vars, b, Diagonal::BC, qmin, qmax, &kind);
        }
        if (ok) {
            out.leaves.push_back(make_leaf(b, (ch.ad ? 1 : 0) | (ch.bc ? 2 : 0)));
            out.leaves.back().threshold = (ch.ad && ch.bc) ? 0 : thr;
            continue;
        }
        int s = -1;
        for (int j = 0; j < b.m; ++j)
            if (s < 0 || b.hi[j] - b.lo[j] > b.hi[s] - b.lo[s]) s = j;
        if (s < 0 || b.hi[s] - b.lo[s] < std::ldexp(1.0, -44) || out.leaves.size() > max_leaves) {
            for (int j = 0; j < b.m; ++j) out.fail_point[vars[j]] = 0.5 * (b.lo[j] + b.hi[j]);
            out.fail_kind = kind;
            return out;
        }
        const double mid = 0.5 * (b.lo[s] + b.hi[s]);
        Box l = b, r = b;
        l.hi[s] = mid, r.lo[s] = mid;
        stack.push_back(r);
        stack.push_back(l);
    }
    out.ok = true;
    return out;
}

// ---------------------------------------------------------------------------
std::string run_proof(DiagonalRule rule, const std::vector<int>* key_subset, std::string* log) {
    const auto t0 = std::chrono::steady_clock::now();
    const auto all = consistent_keys();
    std::vector<int> ids;
    if (key_subset) ids = *key_subset;
    else
        for (int i = 0; i < static_cast<int>(all.size()); ++i) ids.push_back(i);
    const int n = static_cast<int>(ids.size());
    struct Info {
        bool flat = false, invalid = false, relaxed = false;
        std::array<double, 4> invalid_at{};
        Extreme emin{}, emax{};
        double qmin = 0, qmax = 0;
        KeyProof proof;
    };
    std::vector<Info> info(static_cast<std::size_t>(n));
    flat_patterns();
#pragma omp parallel for schedule(dynamic, 1)
    for (int i = 0; i < n; ++i) {
        const Key& k = all[static_cast<std::size_t>(ids[i])];
        Info& f = info[static_cast<std::size_t>(i)];
        f.flat = flat_compatible(k);
        const auto vars = key_vars(k);
        f.emin = search(rule, k, vars, +1, &f.invalid, &f.invalid_at);
        f.emax = search(rule, k, vars, -1, nullptr, nullptr);
    }
    // Targets: per category (0 = any, 1 = flat) the exact value at the rational
    // witness nearest the sampled extreme, plus a small margin.
    struct Cat {
        int wmin = -1, wmax = -1, winv = -1;
        ExactEval emin, emax;
        std::array<Q, 4> tmin, tmax;
        double qmin = 0, qmax = 0;
    } cat[2];
    for (int c = 0; c < 2; ++c) {
        for (int i = 0; i < n; ++i) {
            const Info& f = info[static_cast<std::size_t>(i)];
            if (c == 1 && !f.flat) continue;
            if (f.invalid) {
                if (cat[c].winv < 0) cat[c].winv = i;
                continue;
            }
            if (cat[c].wmin < 0 || f.emin.value > info[static_cast<std::size_t>(cat[c].wmin)].emin.value) cat[c].wmin = i;
            if (cat[c].wmax < 0 || f.emax.value < info[static_cast<std::size_t>(cat[c].wmax)].emax.value) cat[c].wmax = i;
        }
        const int bits = c == 1 ? 33 : 24;  // min-angle margins: 2^-33 (F, < 1e-9 deg), 2^-24 (U, < 1e-6 deg)
        // Max-angle margins: 2^-33 for F (flat keys: < 1e-8 deg at 135 and 143.13
        // deg; the extremes sit at box corners, where the monotonicity reduction
        // closes the boxes), 1/8 for U: tight max-angle bounds cost many leaves
        // along the max-min switching surfaces.
        const int mbits = c == 1 ? 33 : 3;
        const Key& kmin = all[static_cast<std::size_t>(ids[cat[c].wmin])];
        std::tie(cat[c].tmin, cat[c].emin) = witness(rule, kmin, info[static_cast<std::size_t>(cat[c].wmin)].emin.t, 1);
        cat[c].qmin = std::max(q_up(cat[c].emin.qmin, bits + 3), round_up(info[static_cast<std::size_t>(cat[c].wmin)].emin.value, bits + 3)) + std::ldexp(1.0, -bits);
        const Key& kmax = all[static_cast<std::size_t>(ids[cat[c].wmax])];
        std::tie(cat[c].tmax, cat[c].emax) = witness(rule, kmax, info[static_cast<std::size_t>(cat[c].wmax)].emax.t, -1);
        cat[c].qmax = std::min(q_down(cat[c].emax.qmax, bits + 3), round_down(info[static_cast<std::size_t>(cat[c].wmax)].emax.value, bits + 3)) - std::ldexp(1.0, -mbits);
    }
    for (int i = 0; i < n; ++i) {
        Info& f = info[static_cast<std::size_t>(i)];
        const Cat& c = cat[f.flat ? 1 : 0];
        const double rel = 0.25 * (1 + std::fabs(f.emin.value));
        f.qmin = std::min(round_up(f.emin.value + rel, 16), c.qmin);
        f.qmax = std::max(round_down(f.emax.value - 0.25 * (1 + std::fabs(f.emax.value)), 16), c.qmax);
        // Keys that are not flat-compatible: the max-angle claim is at least as
        // loose as cot -3/2 (146.31 deg) — tight max-angle claims need too many leaves
        // along the max-min switching surfaces (both diagonals must be bounded there).
        if (!f.flat) f.qmax = std::min(f.qmax, std::getenv("WARPMESH_U_MAX_COT") ? std::atof(std::getenv("WARPMESH_U_MAX_COT")) : -1.5);
    }
    const auto t1 = std::chrono::steady_clock::now();
    const bool verbose = std::getenv("WARPMESH_PROVE_VERBOSE") != nullptr;
    const std::size_t leaf_budget = std::getenv("WARPMESH_LEAF_BUDGET") ? std::atol(std::getenv("WARPMESH_LEAF_BUDGET")) : 3000;
    if (verbose)
        std::fprintf(stderr, "targets: U %.17g %.17g  F %.17g %.17g  (%.2f s)\n", cat[0].qmin, cat[0].qmax, cat[1].qmin,
                     cat[1].qmax, std::chrono::duration<double>(t1 - t0).count());
    std::atomic<std::size_t> done{0};
#pragma omp parallel for schedule(dynamic, 1)
    for (int i = 0; i < n; ++i) {
        Info& f = info[static_cast<std::size_t>(i)];
        if (f.invalid) continue;
        const auto k0 = std::chrono::steady_clock::now();
        const Key& key = all[static_cast<std::size_t>(ids[i])];
        // A claim that cannot be certified within the leaf budget is relaxed
        // (and reported as such): the certificate only ever states what was proved.
        for (int attempt = 0; attempt < 8; ++attempt) {
            f.proof = prove_key(rule, key, f.qmin, f.qmax, leaf_budget);
            if (f.proof.ok) break;
            const PointEval e = eval_double(rule, key, f.proof.fail_point);
            const double step = 1e-3 * std::pow(4.0, attempt);
            if (f.proof.fail_kind == 1)
                f.qmin = round_up(std::max(f.qmin, e.valid ? e.qmin : f.qmin) + step * (1 + std::fabs(f.qmin)), 24);
            else if (f.proof.fail_kind == 2)
                f.qmax = round_down(std::min(f.qmax, e.valid ? e.qmax : f.qmax) - step * (1 + std::fabs(f.qmax)), 24);
            else
                break;  // orientation cannot be certified: reported as a failure
            f.relaxed = true;
        }
        const double dt = std::chrono::duration<double>(std::chrono::steady_clock::now() - k0).count();
        if (verbose && (dt > 0.2 || f.relaxed))
            std::fprintf(stderr, "key %d %s: %.2f s, %zu leaves, ok %d, targets %.12g %.12g (sampled %.12g %.12g)\n",
                         ids[i], key_code(all[static_cast<std::size_t>(ids[i])]).c_str(), dt, f.proof.leaves.size(),
                         f.proof.ok, f.qmin, f.qmax, f.emin.value, f.emax.value);
        ++done;
    }
    const auto t2 = std::chrono::steady_clock::now();

    std::ostringstream o, lg;
    const char* rname = rule == DiagonalRule::maxmin ? "maxmin" : "separating";
    o << "warpmesh-certificate 1\n"
      << "# Angle bounds for the generic square, diagonal rule " << rname << ".  Format: proofs/README.md.\n"
      << "rule " << rname << "\n";
    std::size_t leaves = 0, failed = 0, inverted = 0;
    for (const Info& f : info) leaves += f.proof.leaves.size(), failed += !f.invalid && !f.proof.ok,
                                inverted += f.invalid;
    // Category claims: max/min of the key claims.
    for (int c = 0; c < 2; ++c) {
        double cq = -1e300, cp = 1e300;
        bool any_inv = false;
        for (const Info& f : info) {
            if (c == 1 && !f.flat) continue;
            if (f.invalid) {
                any_inv = true;
                continue;
            }
            cq = std::max(cq, f.qmin), cp = std::min(cp, f.qmax);
        }
        const char* cn = c ? "F" : "U";
        if (any_inv) {
            const Info& f = info[static_cast<std::size_t>(cat[c].winv)];
            const auto t = to_dyadic_t(f.invalid_at);
            o << "claim " << cn << " inverted\n";
            o << "witness " << cn << " inverted " << key_code(all[static_cast<std::size_t>(ids[cat[c].winv])]);
            for (int v : key_vars(all[static_cast<std::size_t>(ids[cat[c].winv])])) o << ' ' << qstr(t[v]);
            o << "\n";
            lg << rname << " (" << cn << "): orientation FAILS, e.g. key "
               << key_code(all[static_cast<std::size_t>(ids[cat[c].winv])]) << "\n";
            continue;
        }
        o << "claim " << cn << " " << dstr(cq) << " " << dstr(cp) << "\n";
        const Key& kmin = all[static_cast<std::size_t>(ids[cat[c].wmin])];
        const Key& kmax = all[static_cast<std::size_t>(ids[cat[c].wmax])];
        o << "witness " << cn << " min " << key_code(kmin);
        for (int v : key_vars(kmin)) o << ' ' << qstr(cat[c].tmin[v]);
        o << " " << qstr(cat[c].emin.qmin) << "\n";
        o << "witness " << cn << " max " << key_code(kmax);
        for (int v : key_vars(kmax)) o << ' ' << qstr(cat[c].tmax[v]);
        o << " " << qstr(cat[c].emax.qmax) << "\n";
        lg << rname << " (" << cn << "): min angle >= " << deg_range(dyadic(cq)) << " (cot <= " << dstr(cq)
           << "), witness " << key_code(kmin) << " has cot " << std::setprecision(17)
           << cat[c].emin.qmin.convert_to<double>() << " = " << deg_range(cat[c].emin.qmin) << "; gap in cot "
           << (dyadic(cq) - cat[c].emin.qmin).convert_to<double>() << "\n";
        lg << rname << " (" << cn << "): max angle <= " << deg_range(dyadic(cp)) << " (cot >= " << dstr(cp)
           << "), witness " << key_code(kmax) << " has cot " << cat[c].emax.qmax.convert_to<double>() << " = "
           << deg_range(cat[c].emax.qmax) << "; gap in cot "
           << (cat[c].emax.qmax - dyadic(cp)).convert_to<double>() << "\n";
    }
    o << "keys " << n << "\n";
    for (int i = 0; i < n; ++i) {
        const Info& f = info[static_cast<std::size_t>(i)];
        const Key& k = all[static_cast<std::size_t>(ids[i])];
        const int m = static_cast<int>(key_vars(k).size());
        if (f.invalid) {
            o << "key " << ids[i] << ' ' << key_code(k) << ' ' << f.flat << ' ' << m << " inverted\n";
            continue;
        }
        o << "key " << ids[i] << ' ' << key_code(k) << ' ' << f.flat << ' ' << m << ' ' << dstr(f.qmin) << ' '
          << dstr(f.qmax) << ' ' << (f.proof.ok ? f.proof.leaves.size() : 0) << "\n";
        if (!f.proof.ok) {
            lg << "FAILED key " << key_code(k) << " qmin " << f.qmin << " qmax " << f.qmax << " at";
            for (double x : f.proof.fail_point) lg << ' ' << x;
            const auto e = eval_double(rule, k, f.proof.fail_point);
            lg << " (there: qmin " << e.qmin << " qmax " << e.qmax << ")\n";
            continue;
        }
        for (const Leaf& l : f.proof.leaves) {
            o << (l.threshold != 0 ? "ab"[l.diag - 1] : "ABX"[l.diag - 1]) << ' ' << l.k;
            for (int j = 0; j < 2 * m; ++j) o << ' ' << l.num[static_cast<std::size_t>(j)];
            if (l.threshold != 0) o << ' ' << dstr(l.threshold);
            o << "\n";
        }
    }
    o << "end\n";
    lg << rname << ": " << n << " keys, " << leaves << " leaves, " << failed << " failed, " << inverted
       << " with inverted triangles; targets "
       << std::chrono::duration<double>(t1 - t0).count() << " s, branch and bound "
       << std::chrono::duration<double>(t2 - t1).count() << " s\n";
    if (log) *log += lg.str();
    return o.str();
}

}  // namespace prover

int prove_main(int argc, char** argv) {
    std::string out = "proofs";
    std::vector<int> subset;
    bool use_subset = false;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "prove") continue;
        if (a == "--out" && i + 1 < argc) out = argv[++i];
        else if (a == "--threads" && i + 1 < argc) {
#ifdef _OPENMP
            omp_set_num_threads(std::max(1, std::atoi(argv[++i])));
#else
            ++i;
#endif
        } else if (a == "--keys" && i + 1 < argc) {
            use_subset = true;
            std::stringstream ss(argv[++i]);
            std::string tok;
            while (std::getline(ss, tok, ',')) subset.push_back(std::atoi(tok.c_str()));
        } else {
            std::fprintf(stderr, "usage: warpmesh prove [--out DIR] [--threads N] [--keys I,J,...]\n");
            return 2;
        }
    }
    std::filesystem::create_directories(out);
    int status = 0;
    for (DiagonalRule r : {DiagonalRule::maxmin, DiagonalRule::separating}) {
        std::string log;
        const std::string cert = prover::run_proof(r, use_subset ? &subset : nullptr, &log);
        const std::string name = r == DiagonalRule::maxmin ? "maxmin" : "separating";
        const std::string path = out + "/" + name + ".cert";
        std::ofstream f(path + ".tmp", std::ios::binary);
        f << cert;
        f.close();
        std::filesystem::rename(path + ".tmp", path);
        // The key table: one line per key.
        std::ofstream tab(out + "/key_table.txt", r == DiagonalRule::maxmin ? std::ios::trunc : std::ios::app);
        if (r == DiagonalRule::maxmin)
            tab << "# rule key flat min_cot max_cot   (see proofs/README.md; every angle a of the chosen triangles\n"
                << "# of every configuration of the key has max_cot <= cot(a) <= min_cot)\n";
        std::istringstream cs(cert);
        for (std::string line; std::getline(cs, line);) {
            if (line.rfind("key ", 0) != 0) continue;
            std::istringstream ls(line);
            std::string w, id, code, flat, m, qmin, qmax;
            ls >> w >> id >> code >> flat >> m >> qmin >> qmax;
            tab << name << ' ' << code << ' ' << (flat == "1" ? "flat" : "any") << ' ' << qmin << ' '
                << (qmin == "inverted" ? "-" : qmax) << "\n";
        }
        std::fputs(log.c_str(), stdout);
        std::fflush(stdout);
        if (log.find("FAILED") != std::string::npos) status = 1;
    }
    return status;
}

}  // namespace warpmesh
