// face_rule3.cpp — stage 5's Delaunay face rule (uniform3d.hpp:
// delaunay_choice): generic_bcc.hpp's delaunay_diagonals, evaluated with the
// exact signs of its forms at the window's cut points.
//
// Why exact.  A face quad's diagonal must be the same in the two tetrahedra
// sharing the face (conformity), and the certificate covers the rule with
// exact signs (a zero — cocircular points, equal inside diagonals — falls
// back to the parity rule's choice, resolve_delaunay).  Both tetrahedra see
// the same cut points, so exact signs agree; rounded ones need not (each
// tetrahedron names the face's vertices in its own local order and the
// local fraction is u or 1 − u, rounded differently).
//
// How.  The cut fractions are the stored doubles u (from the edge's lower
// endpoint); the local fraction is u or 1 − u.  The forms are polynomials in
// them (face_form linear, inside_form quadratic).  First a filter: the forms
// are evaluated in double together with a rigorous bound on their rounding
// error (`Filtered`: running error analysis, below); a comparison with zero
// is decided when |value| exceeds the bound, and is `maybe` otherwise (the
// three-valued comparison of warpmesh/numerics/scalar.hpp, as the provers'
// intervals answer it).  Where a sign is undecided the whole choice is
// evaluated again exactly: near a tie, which on a lattice aligned with the
// voxels is common (equal fractions, 1/2 above all), so exactly is made cheap.
//
// Exactly.  A double u in [2^-6, 1) is a multiple of 2^-58, so U = u 2^58 is
// an integer below 2^58 and 1 − u is 2^58 − U, exactly (`Fixed`: an integer
// n times 2^(-58 k), k the degree in the fractions).  The forms have degree
// at most 2 with small integer coefficients (doubled coordinates in [-1, 2]):
// a degree-1 value is below 2^61 in magnitude, a product of two below 2^122,
// the inside form's six squares summed below 2^126 — within __int128.  If a
// fraction lies below 2^-6 (never at the certified alphas, whose cut
// fractions are >= α; possible only for thresholds below 2^-6), exact
// rationals (boost::multiprecision::cpp_rational, from the stored doubles).
//
// The bound.  A Filtered x carries its double value x.v and a bound x.e >= |x
// − x.v| on the distance to the exact value of the same expression.  With ε =
// 2^-53 (round to nearest; a result's rounding error is at most ε |result|,
// plus η = the smallest subnormal for a product's underflow):
//     x ± y: v = fl(x.v ± y.v),   e = x.e + y.e + ε |v|
//     x · y: v = fl(x.v · y.v),   e = |x.v| y.e + |y.v| x.e + x.e y.e + ε |v| + η
// The bound itself is computed in rounded arithmetic, off by at most a
// relative (1 + ε)^k after k operations; a comparison with zero inflates it
// by 2^-40, which covers k < 2^12 (the forms take a few dozen).
#include <boost/multiprecision/cpp_int.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "uniform3d.hpp"

namespace warpmesh {
namespace {

struct Filtered {
    double v = 0, e = 0;
};
constexpr double eps = 0x1p-53;

Filtered operator+(const Filtered& a, const Filtered& b) {
    const double v = a.v + b.v;
    return {v, a.e + b.e + eps * std::fabs(v)};
}
Filtered operator-(const Filtered& a, const Filtered& b) {
    const double v = a.v - b.v;
    return {v, a.e + b.e + eps * std::fabs(v)};
}
Filtered operator*(const Filtered& a, const Filtered& b) {
    const double v = a.v * b.v;
    return {v, std::fabs(a.v) * b.e + std::fabs(b.v) * a.e + a.e * b.e + eps * std::fabs(v) + std::numeric_limits<double>::denorm_min()};
}

// An exact fixed-point value n · 2^(-58 k), k <= 2 (see "Exactly").
struct Fixed {
    __int128 n = 0;
    int k = 0;
};
constexpr int fixed_bits = 58;
Fixed lift(const Fixed& a, int k) { return {a.n * (static_cast<__int128>(1) << (fixed_bits * (k - a.k))), k}; }
Fixed operator+(const Fixed& a, const Fixed& b) {
    const int k = std::max(a.k, b.k);
    return {lift(a, k).n + lift(b, k).n, k};
}
Fixed operator-(const Fixed& a, const Fixed& b) {
    const int k = std::max(a.k, b.k);
    return {lift(a, k).n - lift(b, k).n, k};
}
Fixed operator*(const Fixed& a, const Fixed& b) { return {a.n * b.n, a.k + b.k}; }  // degrees add up to <= 2

// An exact rational.
struct Exact {
    boost::multiprecision::cpp_rational q;
};
Exact operator+(const Exact& a, const Exact& b) { return {a.q + b.q}; }
Exact operator-(const Exact& a, const Exact& b) { return {a.q - b.q}; }
Exact operator*(const Exact& a, const Exact& b) { return {a.q * b.q}; }

}  // namespace

// `positive` is three-valued for Filtered: decided where |a.v| exceeds the
// bound (inflated, see "The bound"), `maybe` otherwise; exact for the others.
template <>
struct ScalarOps<Filtered> {
    static Filtered from_int(int v) { return {static_cast<double>(v), 0}; }  // small integers: exact
    static Truth positive(const Filtered& a) {
        const double bound = a.e * (1 + 0x1p-40);
        if (a.v > bound) return Truth::yes;
        if (a.v < -bound) return Truth::no;
        return Truth::maybe;
    }
};
template <>
struct ScalarOps<Fixed> {
    static Fixed from_int(int v) { return {v, 0}; }
    static Truth positive(const Fixed& a) { return truth(a.n > 0); }
};
template <>
struct ScalarOps<Exact> {
    static Exact from_int(int v) { return {boost::multiprecision::cpp_rational(v)}; }
    static Truth positive(const Exact& a) { return truth(a.q > 0); }
};

namespace {

Filtered scalar(double u, Filtered) { return {u, 0}; }
Fixed scalar(double u, Fixed) { return {static_cast<__int128>(std::ldexp(u, fixed_bits)), 1}; }  // exact for u in [2^-6, 1)
Exact scalar(double u, Exact) { return {boost::multiprecision::cpp_rational(u)}; }  // exact: a double is a dyadic rational

// decided_delaunay_diagonals in scalar T on the local fractions of u (see
// delaunay_choice): std::nullopt where T leaves a sign undecided.
template <class T>
std::optional<bcc::Diagonals> diagonals_in(const std::array<int, 4>& sign, int parity, const std::array<double, 6>& u, unsigned from_upper) {
    std::array<T, 6> local{};
    for (std::size_t e = 0; e < 6; ++e) {
        const T x = scalar(u[e], T{});
        local[e] = (from_upper >> e & 1u) ? ScalarOps<T>::from_int(1) - x : x;
    }
    return bcc::decided_delaunay_diagonals<T>(sign, parity, local);
}

}  // namespace

bcc::Diagonals uniform3d::delaunay_choice(const std::array<int, 4>& sign, int parity, const std::array<double, 6>& u,
                                          unsigned from_upper) {
    if (const auto d = diagonals_in<Filtered>(sign, parity, u, from_upper)) return *d;
    bool fixed = true;  // every fraction the choice reads in [2^-6, 1) (unread ones are 0)
    for (double x : u) fixed = fixed && (x == 0 || (x >= 0x1p-6 && x < 1));
    return (fixed ? diagonals_in<Fixed>(sign, parity, u, from_upper) : diagonals_in<Exact>(sign, parity, u, from_upper)).value();
}

}  // namespace warpmesh
