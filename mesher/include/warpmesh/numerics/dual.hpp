// dual.hpp — forward-mode dual numbers over a scalar (the numerics layer,
// warpmesh/numerics/): a value with its partial derivatives in N variables
// (`Dual`), or with its second partials too (`Dual2`).  The provers run the
// generic models on Dual<Interval> (interval.hpp) to bound a form and its
// gradient on a box; the models' positions are affine and their forms
// polynomial in the variables, so + - * is all that is needed.
//
// Header-only and free of Boost itself; its users include interval.hpp.
#pragma once

#include <array>
#include <cstddef>

#include "warpmesh/numerics/scalar.hpp"

namespace warpmesh {

template <class S, std::size_t N = 4>
struct Dual {
    S v;
    std::array<S, N> d;
};
template <class S, std::size_t N>
Dual<S, N> operator+(const Dual<S, N>& a, const Dual<S, N>& b) {
    Dual<S, N> r{a.v + b.v, {}};
    for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] + b.d[i];
    return r;
}
template <class S, std::size_t N>
Dual<S, N> operator-(const Dual<S, N>& a, const Dual<S, N>& b) {
    Dual<S, N> r{a.v - b.v, {}};
    for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] - b.d[i];
    return r;
}
template <class S, std::size_t N>
Dual<S, N> operator*(const Dual<S, N>& a, const Dual<S, N>& b) {
    Dual<S, N> r{a.v * b.v, {}};
    for (std::size_t i = 0; i < N; ++i) r.d[i] = a.d[i] * b.v + a.v * b.d[i];
    return r;
}
// A constant: value v, every partial 0.
template <class S, std::size_t N>
struct ScalarOps<Dual<S, N>> {
    static Dual<S, N> from_int(int v) {
        Dual<S, N> r{ScalarOps<S>::from_int(v), {}};
        r.d.fill(ScalarOps<S>::from_int(0));
        return r;
    }
};

// Second order: value, partials and the second partials h[i][j], kept for
// i <= j only (the entries below the diagonal are not maintained).
template <class S, std::size_t N = 4>
struct Dual2 {
    S v;
    std::array<S, N> d;
    std::array<std::array<S, N>, N> h;
};
template <class S, std::size_t N>
Dual2<S, N> operator+(const Dual2<S, N>& a, const Dual2<S, N>& b) {
    Dual2<S, N> r = a;
    r.v = a.v + b.v;
    for (std::size_t i = 0; i < N; ++i) {
        r.d[i] = a.d[i] + b.d[i];
        for (std::size_t j = i; j < N; ++j) r.h[i][j] = a.h[i][j] + b.h[i][j];
    }
    return r;
}
template <class S, std::size_t N>
Dual2<S, N> operator-(const Dual2<S, N>& a, const Dual2<S, N>& b) {
    Dual2<S, N> r = a;
    r.v = a.v - b.v;
    for (std::size_t i = 0; i < N; ++i) {
        r.d[i] = a.d[i] - b.d[i];
        for (std::size_t j = i; j < N; ++j) r.h[i][j] = a.h[i][j] - b.h[i][j];
    }
    return r;
}
template <class S, std::size_t N>
Dual2<S, N> operator*(const Dual2<S, N>& a, const Dual2<S, N>& b) {
    Dual2<S, N> r = a;
    r.v = a.v * b.v;
    for (std::size_t i = 0; i < N; ++i) {
        r.d[i] = a.d[i] * b.v + a.v * b.d[i];
        for (std::size_t j = i; j < N; ++j)
            r.h[i][j] = a.h[i][j] * b.v + a.v * b.h[i][j] + a.d[i] * b.d[j] + a.d[j] * b.d[i];
    }
    return r;
}
template <class S, std::size_t N>
struct ScalarOps<Dual2<S, N>> {
    static Dual2<S, N> from_int(int v) {
        Dual2<S, N> r;
        r.v = ScalarOps<S>::from_int(v);
        r.d.fill(ScalarOps<S>::from_int(0));
        for (auto& row : r.h) row.fill(ScalarOps<S>::from_int(0));
        return r;
    }
};

}  // namespace warpmesh
