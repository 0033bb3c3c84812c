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
// is decided when |value| exceeds the bound.  Otherwise the whole choice is
// evaluated again in exact rationals (boost::multiprecision::cpp_rational,
// built exactly from the stored doubles, so 1 − u is exact): only near a tie.
//
// The bound.  A Filtered x carries its double value x.v and a bound x.e >= |x
// − x.v| on the distance to the exact value of the same expression.  With ε =
// 2^-53 (round to nearest; a result's rounding error is at most ε |result|,
// plus η = the smallest subnormal for a product's underflow):
//     x ± y: v = fl(x.v ± y.v),   e = x.e + y.e + ε |v|
//     x · y: v = fl(x.v · y.v),   e = |x.v| y.e + |y.v| x.e + x.e y.e + ε |v| + η
// The bound itself is computed in rounded arithmetic, off by at most a
// relative (1 + ε)^k after k operations; a comparison inflates it by 2^-40,
// which covers k < 2^12 (the forms take a few dozen).
#include <boost/multiprecision/cpp_int.hpp>
#include <cmath>
#include <limits>

#include "uniform3d.hpp"

namespace warpmesh {
namespace {

// Set by a Filtered comparison that the bound cannot decide (per thread:
// stage 5 runs on OpenMP threads).
thread_local bool undecided = false;

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
// a < b if the bound decides it; otherwise false, and `undecided` is set.
bool operator<(const Filtered& a, const Filtered& b) {
    const Filtered d = a - b;
    const double bound = d.e * (1 + 0x1p-40);
    if (d.v < -bound) return true;
    if (!(d.v > bound)) undecided = true;
    return false;
}

// An exact rational.
struct Exact {
    boost::multiprecision::cpp_rational q;
};
Exact operator+(const Exact& a, const Exact& b) { return {a.q + b.q}; }
Exact operator-(const Exact& a, const Exact& b) { return {a.q - b.q}; }
Exact operator*(const Exact& a, const Exact& b) { return {a.q * b.q}; }
bool operator<(const Exact& a, const Exact& b) { return a.q < b.q; }

}  // namespace

template <>
struct ScalarOps<Filtered> {
    static Filtered from_int(int v) { return {static_cast<double>(v), 0}; }  // small integers: exact
};
template <>
struct ScalarOps<Exact> {
    static Exact from_int(int v) { return {boost::multiprecision::cpp_rational(v)}; }
};

namespace {

Filtered scalar(double u, Filtered) { return {u, 0}; }
Exact scalar(double u, Exact) { return {boost::multiprecision::cpp_rational(u)}; }  // exact: a double is a dyadic rational

// delaunay_diagonals in scalar T on the local fractions of u (see
// delaunay_choice).
template <class T>
bcc::Diagonals diagonals_in(const std::array<int, 4>& sign, int parity, const std::array<double, 6>& u, unsigned from_upper) {
    std::array<T, 6> local{};
    for (std::size_t e = 0; e < 6; ++e) {
        const T x = scalar(u[e], T{});
        local[e] = (from_upper >> e & 1u) ? ScalarOps<T>::from_int(1) - x : x;
    }
    return bcc::delaunay_diagonals<T>(sign, parity, local);
}

}  // namespace

bcc::Diagonals uniform3d::delaunay_choice(const std::array<int, 4>& sign, int parity, const std::array<double, 6>& u,
                                          unsigned from_upper) {
    undecided = false;
    const bcc::Diagonals d = diagonals_in<Filtered>(sign, parity, u, from_upper);
    if (!undecided) return d;
    return diagonals_in<Exact>(sign, parity, u, from_upper);
}

}  // namespace warpmesh
